"""The tools and targets of the flight-code checks: which programs, which flags, the package's files, one
compile call, and the finding every check reports.

A flight package is a folder of C99: its flight sources are every ``*.c`` except the host test program
(``test_*.c``, which uses stdio and is not flight code).  Every check works on a scratch copy of the
package's ``*.c``/``*.h`` (:func:`scratch_copy`), so that nothing is written into the package itself
(cppcheck's addons leave ``.dump`` files beside the sources, the compiler ``.su``/``.ci`` files beside
the objects) and the file names in the findings are the package's own, relative ones.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.emit import PRECISIONS as _REAL_TYPES

#: program -> the Debian package that installs it (named by the error when the program is missing)
DEBIAN_PACKAGES = {
    "gcc": "gcc",
    "clang": "clang",
    "nm": "binutils",
    "arm-none-eabi-gcc": "gcc-arm-none-eabi",
    "arm-none-eabi-nm": "binutils-arm-none-eabi",
    "cppcheck": "cppcheck",
}

PRECISIONS = tuple(_REAL_TYPES)

#: IEEE semantics, every operation rounded on its own (no fused multiply-add): the simulation's objects
#: are compiled so (runtime/model/toolchain.py), and so is every flight build here, the package's
#: Makefile, its host build (host.py) and its firmware (build.py)
NUMERIC_FLAGS: tuple[str, ...] = ("-O2", "-ffp-contract=off")

#: the Cortex-M parts' flags: hardware FPU, double precision on the M7, single only on the M4
CORE_FLAGS: dict[str, tuple[str, ...]] = {
    "cortex-m7": ("-mcpu=cortex-m7", "-mfpu=fpv5-d16", "-mfloat-abi=hard"),
    "cortex-m4": ("-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"),
}

#: The warnings every flight source and the host test program must compile without (-Werror): C99 and
#: pedantic, no VLA (-Wvla: the VLA check counts these), no shadowing, full prototypes, no cast dropping
#: a qualifier or raising the alignment, no #if on an undefined macro.
WARNING_FLAGS: tuple[str, ...] = (
    "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
    "-Wvla", "-Wshadow", "-Wstrict-prototypes", "-Wmissing-prototypes", "-Wold-style-definition",
    "-Wcast-qual", "-Wcast-align", "-Wundef", "-Wredundant-decls", "-Wwrite-strings", "-Wpointer-arith",
    "-Wnested-externs",
)

#: added for single precision: a float silently widened to double, or any narrowing conversion
SINGLE_WARNING_FLAGS: tuple[str, ...] = ("-Wconversion", "-Wdouble-promotion")

#: the optimisation the warnings are compiled at: -O2 runs the passes behind -Wmaybe-uninitialized,
#: -Warray-bounds and the like, which -O0 never reports
WARNING_OPT: tuple[str, ...] = NUMERIC_FLAGS


def warning_flags(precision: str) -> tuple[str, ...]:
    check_precision(precision)
    return WARNING_FLAGS + (SINGLE_WARNING_FLAGS if precision == "single" else ()) + WARNING_OPT


def check_precision(precision: str) -> None:
    if precision not in PRECISIONS:
        raise ModelError(f"precision must be one of {', '.join(PRECISIONS)}, not {precision!r}")


@dataclass(frozen=True)
class Target:
    """A compiler and the flags of the flight build for one processor (the stack and symbol checks)."""

    name: str
    cc: str
    nm: str
    flags: tuple[str, ...]


#: the flight builds: the host (gcc) and the Cortex-M parts with a hardware FPU (double-precision FPU
#: on the M7, single-precision only on the M4: double arithmetic there is a software library call)
TARGETS: dict[str, Target] = {
    "host-gcc": Target("host-gcc", "gcc", "nm", ("-std=c99", *NUMERIC_FLAGS)),
    "cortex-m7": Target("cortex-m7", "arm-none-eabi-gcc", "arm-none-eabi-nm",
                        ("-std=c99", *CORE_FLAGS["cortex-m7"], *NUMERIC_FLAGS)),
    "cortex-m4": Target("cortex-m4", "arm-none-eabi-gcc", "arm-none-eabi-nm",
                        ("-std=c99", *CORE_FLAGS["cortex-m4"], *NUMERIC_FLAGS)),
}


def targets(precision: str) -> tuple[Target, ...]:
    """The targets a package of this precision is checked on (single precision: the M4 as well)."""
    check_precision(precision)
    names = ("host-gcc", "cortex-m7") if precision == "double" else ("host-gcc", "cortex-m7", "cortex-m4")
    return tuple(TARGETS[n] for n in names)


def resolve_target(which: str | Target) -> Target:
    if isinstance(which, Target):
        return which
    if which not in TARGETS:
        raise ModelError(f"unknown flight target {which!r}: one of {', '.join(TARGETS)}")
    return TARGETS[which]


@dataclass
class Finding:
    """One thing a check found.  ``rule``: the warning option, MISRA rule, cppcheck id or symbol;
    ``justified``: a deviation covers it (its ``reason``); ``where``: the compiler or target."""

    check: str
    message: str
    file: str = ""
    line: int = 0
    rule: str = ""
    where: str = ""
    justified: bool = False
    reason: str = ""

    def json(self) -> dict[str, object]:
        return {k: v for k, v in asdict(self).items() if v not in ("", 0) or k in ("check", "message", "justified")}

    def text(self) -> str:
        loc = f"{self.file}:{self.line}: " if self.file and self.line else (f"{self.file}: " if self.file else "")
        tag = f" [{self.rule}]" if self.rule else ""
        at = f" ({self.where})" if self.where else ""
        why = f" -- justified: {self.reason}" if self.justified else ""
        return f"{self.check}{at}: {loc}{self.message}{tag}{why}"


def require(program: str) -> str:
    """The path of ``program``, or ModelError naming the Debian package that installs it."""
    found = shutil.which(program)
    if found is None:
        deb = DEBIAN_PACKAGES.get(program, program)
        raise ModelError(f"{program} not found: the flight checks need it (Debian: apt-get install {deb})")
    return found


def require_callgraph_gcc(cc: str) -> str:
    """``cc`` (a gcc), checked to write call graphs (-fcallgraph-info: gcc 10 and later)."""
    path = require(cc)
    out = subprocess.run([path, "-dumpversion"], capture_output=True, text=True, check=False).stdout.strip()
    major = re.match(r"\d+", out)
    if major is None or int(major.group()) < 10:
        deb = DEBIAN_PACKAGES.get(cc, cc)
        raise ModelError(f"{cc} {out or '(unknown version)'} cannot write call graphs (-fcallgraph-info needs "
                         f"gcc >= 10; Debian: apt-get install {deb})")
    return path


def is_test_source(name: str) -> bool:
    return name.startswith("test_")


def flight_sources(folder: Path) -> list[str]:
    """The flight ``*.c`` of a package folder (names, sorted): every C file but the test program."""
    return sorted(p.name for p in folder.glob("*.c") if not is_test_source(p.name))


def host_test_sources(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.glob("*.c") if is_test_source(p.name))


@contextmanager
def scratch_copy(pkg: Path | str) -> Iterator[Path]:
    """A temporary copy of the package's C sources and headers; removed afterwards."""
    src = Path(pkg)
    if not src.is_dir():
        raise ModelError(f"no flight package folder at {src}")
    if not flight_sources(src):
        raise ModelError(f"{src} holds no flight C source (*.c other than test_*.c)")
    with tempfile.TemporaryDirectory(prefix="rpo-flight-") as tmp:
        work = Path(tmp) / "pkg"
        work.mkdir()
        for f in sorted(src.iterdir()):
            if f.is_file() and f.suffix in (".c", ".h"):
                shutil.copy2(f, work / f.name)
        yield work


def run(cmd: Sequence[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    """One tool call; its output is the caller's to read (a nonzero exit is not an exception)."""
    return subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True, check=False)


@dataclass
class Objects:
    """The flight objects of one target, compiled in ``folder`` with stack and call-graph files beside."""

    target: Target
    folder: Path
    objects: list[Path] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)   # compile failures


def compile_flight(work: Path, tgt: Target, out: Path) -> Objects:
    """Compile every flight source of the scratch copy ``work`` for ``tgt`` into ``out`` with
    -fstack-usage and -fcallgraph-info=su (one .o, .su and .ci per source)."""
    cc = require_callgraph_gcc(tgt.cc)
    out.mkdir(parents=True, exist_ok=True)
    res = Objects(tgt, out)
    for name in flight_sources(work):
        obj = out / (Path(name).stem + ".o")
        proc = run([cc, *tgt.flags, "-fstack-usage", "-fcallgraph-info=su", "-c", name, "-o", str(obj)], work)
        if proc.returncode != 0 or not obj.exists():
            first = next((ln for ln in proc.stderr.splitlines() if "error" in ln), proc.stderr.strip()[:200])
            res.findings.append(Finding("compile", f"does not compile for {tgt.name}: {first}", file=name,
                                        where=tgt.name))
            continue
        res.objects.append(obj)
    return res
