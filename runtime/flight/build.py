"""Building the processor-in-the-loop firmware: one exported controller package (``rpo export``)
cross-compiled with the harness of ``runtime/flight/firmware/`` for an emulated Cortex-M.

:func:`build_firmware` writes the ELF into rpo's compile cache (``<cache>/pil/``), keyed by a
sha256 of every input: the package's files, the harness's files, the adapter header written for
the package, the compiler's identity (its executable, version, and the newlib and libgcc archives
linked for the core) and every flag.  The build goes through :func:`rpo.runtime.model.cache.ensure_built`
(a temporary file sealed with its sha256, then renamed, under a lock), so two processes building
at once are safe and an ELF whose inputs changed is never reused: its key is another file.

The compiler reads private copies of the bytes the key was computed from, so a package edited
during a build cannot be filed under the old key.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.tools import CORE_FLAGS, NUMERIC_FLAGS
from rpo.runtime.model.cache import cache_dir, ensure_built

#: the cross compiler and the emulator, looked up on PATH; each missing one is named with its Debian package
ARM_GCC = "arm-none-eabi-gcc"
QEMU_ARM = "qemu-system-arm"
DEBIAN_PACKAGE = {ARM_GCC: "gcc-arm-none-eabi", "newlib": "libnewlib-arm-none-eabi", QEMU_ARM: "qemu-system-arm"}

#: Bump when the harness's protocol changes (the host checks the READY line's version).
PROTOCOL_VERSION = 1

#: QEMU runs with -icount shift=ICOUNT_SHIFT: 2^10 ns of virtual time per guest instruction, 25.6 ticks
#: of the 25 MHz timer, so the harness's instruction counts are exact (pil_harness.c).
ICOUNT_SHIFT = 10

#: the stack region below the harness (bytes): painted and scanned around every step, so its size
#: costs host time (measured, toy package: 0.15 ms per step round trip with 4 KiB, 0.18 with 64 KiB,
#: 0.30 with 256 KiB); a step that writes into its lowest 1 KiB is an error
DEFAULT_STACK_SIZE = 64 * 1024


@dataclass(frozen=True)
class Core:
    """One emulated core: the QEMU machine and the compiler flags that select its FPU."""

    name: str
    machine: str
    flags: tuple[str, ...]


#: m7: Cortex-M7 with the double-precision FPU (fpv5-d16), for double packages; m4f: Cortex-M4 with
#: the single-precision FPU (fpv4-sp-d16), for float packages (a double there is software IEEE).
CORES: dict[str, Core] = {
    "m7": Core("m7", "mps2-an500", ("-mthumb", *CORE_FLAGS["cortex-m7"])),
    "m4f": Core("m4f", "mps2-an386", ("-mthumb", *CORE_FLAGS["cortex-m4"])),
}
DEFAULT_CORE = {"double": "m7", "float": "m4f"}

#: The package's compile flags (after the core's).  IEEE semantics, as on the host: -ffp-contract=off
#: (no fused multiply-add, which the M7 and M4F have), no -ffast-math; C99.
TARGET_CFLAGS = ("-std=c99", *NUMERIC_FLAGS, "-fno-common", "-ffunction-sections", "-fdata-sections",
                 "-Wall", "-Wextra")
#: The harness's own flags: the same, and the icount shift its conversion of ticks assumes.
HARNESS_DEFINES = (f"-DPIL_ICOUNT_SHIFT={ICOUNT_SHIFT}",)
#: own startup (no crt0), newlib-nano's libc and libm, no heap and no system calls.
LDFLAGS = ("-nostartfiles", "-specs=nano.specs", "-Wl,--gc-sections")
LDLIBS = ("-lm",)
LINKER_SCRIPT = "pil_mps2.ld"


def firmware_dir() -> Path:
    """The harness's C sources, headers and linker script (package data of ``rpo.runtime.flight.firmware``)."""
    return Path(str(resources.files("rpo.runtime.flight"))) / "firmware"


def pil_cache() -> Path:
    return cache_dir() / "pil"


@dataclass(frozen=True)
class Package:
    """An exported controller package, read once: its prefix name, real type, and the bytes of each
    file the firmware is built from (``test_*.c`` excluded: host test programs)."""

    folder: Path
    name: str
    real: str
    files: tuple[tuple[str, bytes], ...]

    @property
    def real_bytes(self) -> int:
        return 8 if self.real == "double" else 4

    @property
    def sources(self) -> list[str]:
        return [n for n, _ in self.files if n.endswith(".c")]


def read_package(folder: Path | str, name: str | None = None) -> Package:
    """The package in ``folder``: its name from ``rpo_<name>_io.h`` (unless given), its real type
    from the ``typedef`` in ``rpo_<name>.h``, the bytes of its ``*.c`` and ``*.h`` files."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ModelError(f"the controller package {folder} is not a folder")
    if name is None:
        found = sorted(p.name[4:-5] for p in folder.glob("rpo_*_io.h"))
        if len(found) != 1:
            raise ModelError(f"the controller package {folder} must hold exactly one rpo_<name>_io.h, found "
                             f"{len(found)}" + (f" ({', '.join(found)}): pass the name" if found else ""))
        name = found[0]
    for f in (f"rpo_{name}.h", f"rpo_{name}.c", f"rpo_{name}_io.h", f"rpo_{name}_io.c"):
        if not (folder / f).is_file():
            raise ModelError(f"the controller package {folder} has no {f}")
    files = []
    for p in sorted(folder.iterdir()):
        if p.suffix in (".c", ".h") and p.is_file() and not (p.suffix == ".c" and p.name.startswith("test_")):
            files.append((p.name, p.read_bytes()))
    header = dict(files)[f"rpo_{name}.h"].decode("utf-8", "replace")
    m = re.search(rf"typedef\s+(double|float)\s+rpo_{re.escape(name)}_real_t\s*;", header)
    if m is None:
        raise ModelError(f"{folder / f'rpo_{name}.h'} has no `typedef double|float rpo_{name}_real_t;`")
    return Package(folder, name, m.group(1), tuple(files))


def adapter_header(pkg: Package) -> str:
    """``pil_adapter.h``: the package's prefixed names mapped onto the harness's generic ones."""
    n, up = pkg.name, pkg.name.upper()
    lines = [
        f"/* pil_adapter.h -- written by rpo.runtime.flight.build for the package rpo_{n}: maps its names",
        " * onto the generic ones of pil_harness.c.  Do not edit. */",
        "#ifndef PIL_ADAPTER_H", "#define PIL_ADAPTER_H", "",
        f'#include "rpo_{n}.h"', f'#include "rpo_{n}_io.h"', "",
        f'#define PIL_PACKAGE "rpo_{n}"', f"#define PIL_REAL_BYTES {pkg.real_bytes}",
        f"typedef rpo_{n}_real_t pil_real_t;",
    ]
    lines += [f"typedef rpo_{n}_{t}_t pil_{t}_t;" for t in ("params", "inputs", "outputs", "state")]
    lines += [f"#define PIL_N_{c} RPO_{up}_N_{c}" for c in ("PARAMS", "INPUTS", "OUTPUTS", "STATE")]
    lines += [f"#define pil_{f} rpo_{n}_{f}" for f in ("initialize", "step", "terminate", "params_from_array",
                                                       "inputs_from_array", "outputs_to_array", "state_to_array")]
    header = (pkg.folder / f"rpo_{n}.h").read_text(encoding="utf-8", errors="replace")
    if f"void rpo_{n}_start(" in header:  # a design that starts its states from a measurement
        lines += ["#define PIL_HAS_START 1", f"#define pil_start rpo_{n}_start"]
    return "\n".join([*lines, "", "#endif", ""])


def harness_files() -> tuple[tuple[str, bytes], ...]:
    d = firmware_dir()
    return tuple((p.name, p.read_bytes()) for p in sorted(d.iterdir())
                 if p.suffix in (".c", ".h", ".ld") and p.is_file())


# --------------------------------------------------------------------------- tools


def _which(tool: str) -> str:
    path = shutil.which(tool)
    if path is None:
        raise ModelError(f"{tool} not found on PATH: install the Debian package {DEBIAN_PACKAGE[tool]} "
                         f"(apt-get install {DEBIAN_PACKAGE[tool]})")
    return path


def qemu_path() -> str:
    """The emulator's path, or the ModelError naming the Debian package to install."""
    return _which(QEMU_ARM)


def _run(cmd: list[str], what: str, timeout: float = 120.0) -> subprocess.CompletedProcess[str]:
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise ModelError(f"{what} failed ({cmd[0]}): {exc}") from None
    if res.returncode != 0:
        lines = (res.stderr or res.stdout).strip().splitlines() or ["(no output)"]
        first = next((ln.strip() for ln in lines if "error" in ln.lower()), lines[-1].strip())
        raise ModelError(f"{what} failed ({Path(cmd[0]).name}): {first}")
    return res


def _sha256(path: str) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


@functools.cache
def _identity(gcc: str, stamp: tuple[int, int], core: str) -> str:
    parts = [gcc, _sha256(gcc)]
    for flag in ("--version", "-dumpmachine"):
        parts.append(_run([gcc, flag], f"{ARM_GCC} {flag}").stdout.strip())
    # the archives the link takes for this core's multilib: newlib-nano's libc and libm, libgcc
    for lib in ("libc_nano.a", "libm.a", "libgcc.a"):
        path = _run([gcc, *CORES[core].flags, f"-print-file-name={lib}"], f"{ARM_GCC} -print-file-name").stdout.strip()
        if not os.path.isabs(path) or not os.path.isfile(path):
            what = "libgcc" if lib == "libgcc.a" else "newlib"
            pkg = DEBIAN_PACKAGE[ARM_GCC] if lib == "libgcc.a" else DEBIAN_PACKAGE["newlib"]
            raise ModelError(f"{ARM_GCC} finds no {lib} ({what} for the {core} core): install the Debian "
                             f"package {pkg} (apt-get install {pkg})")
        parts += [path, _sha256(path)]
    return "\n".join(parts)


def toolchain(core: str) -> tuple[str, str]:
    """The cross compiler's path and its identity for ``core`` (executable, version, the archives
    linked), or the ModelError naming the Debian package that is missing."""
    gcc = _which(ARM_GCC)
    st = os.stat(gcc)
    return gcc, _identity(gcc, (st.st_mtime_ns, st.st_size), core)


def check_tools(core: str = "m7") -> None:
    """Raise the one-line ModelError for the first missing tool: the cross compiler, newlib, QEMU."""
    toolchain(core)
    qemu_path()


# --------------------------------------------------------------------------- the build


@dataclass(frozen=True)
class Firmware:
    """A built PIL firmware: the ELF in the cache and what the host needs to run it."""

    elf: Path
    package: str
    real: str
    core: str
    machine: str
    stack_size: int
    key: str

    @property
    def real_bytes(self) -> int:
        return 8 if self.real == "double" else 4


def firmware_key(pkg: Package, core: str, identity: str, stack_size: int, adapter: str,
                 harness: tuple[tuple[str, bytes], ...]) -> str:
    """sha256 over every input of the ELF (see the module docstring)."""
    rec = {
        "protocol": PROTOCOL_VERSION, "core": core, "machine": CORES[core].machine, "compiler": identity,
        "core_flags": list(CORES[core].flags), "cflags": list(TARGET_CFLAGS), "harness_defines": list(HARNESS_DEFINES),
        "ldflags": list(LDFLAGS), "ldlibs": list(LDLIBS), "stack_size": stack_size, "icount_shift": ICOUNT_SHIFT,
        "adapter": hashlib.sha256(adapter.encode()).hexdigest(),
        "package": [[n, hashlib.sha256(b).hexdigest()] for n, b in pkg.files],
        "harness": [[n, hashlib.sha256(b).hexdigest()] for n, b in harness],
    }
    return hashlib.sha256(json.dumps(rec, sort_keys=True).encode()).hexdigest()


def build_firmware(package: Path | str | Package, core: str | None = None, *, stack_size: int = DEFAULT_STACK_SIZE,
                   cache: Path | None = None, log: Callable[[str], None] | None = None) -> Firmware:
    """The PIL firmware of the controller package (a folder written by ``rpo export``, or a
    :class:`Package`) for ``core`` ("m7": mps2-an500, Cortex-M7, double FPU; "m4f": mps2-an386,
    Cortex-M4F, single FPU; default: m7 for a double package, m4f for a float one), built into the
    cache unless an intact ELF with the same key is there.  ``stack_size`` (bytes, a multiple of 8):
    the stack region the harness paints and scans around each step.  ``cache``: the folder of the
    ELFs (default ``<rpo cache>/pil``); ``log`` gets a line when an ELF is (re)built."""
    pkg = package if isinstance(package, Package) else read_package(package)
    core = core or DEFAULT_CORE[pkg.real]
    if core not in CORES:
        raise ModelError(f"unknown PIL core {core!r}: choose one of {', '.join(CORES)}")
    if stack_size < 4096 or stack_size % 8 or stack_size > 2 * 1024 * 1024:
        raise ModelError(f"stack_size must be a multiple of 8 from 4096 to 2097152 bytes, got {stack_size}")
    gcc, identity = toolchain(core)
    adapter = adapter_header(pkg)
    harness = harness_files()
    key = firmware_key(pkg, core, identity, stack_size, adapter, harness)
    folder = cache if cache is not None else pil_cache()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"cannot create the cache folder {folder} ({exc.strerror}): set RPO_CACHE_DIR "
                         "to a writable folder") from None
    elf = folder / f"rpo_{pkg.name}-{core}-{key[:24]}.elf"

    def build(tmp: Path) -> None:
        _compile_and_link(gcc, pkg, core, stack_size, adapter, harness, tmp)

    if ensure_built(elf, build, f"PIL firmware of rpo_{pkg.name}", log) and log:
        log(f"built the PIL firmware {elf.name}")
    return Firmware(elf, pkg.name, pkg.real, core, CORES[core].machine, stack_size, key)


def _compile_and_link(gcc: str, pkg: Package, core: str, stack_size: int, adapter: str,
                      harness: tuple[tuple[str, bytes], ...], out: Path) -> None:
    flags = [*CORES[core].flags, *TARGET_CFLAGS]
    with tempfile.TemporaryDirectory(prefix=".pil-build-", dir=out.parent) as tmp:
        work = Path(tmp)
        dirs = {"pkg": work / "pkg", "fw": work / "fw", "gen": work / "gen"}
        for d in dirs.values():
            d.mkdir()
        for n, b in pkg.files:
            (dirs["pkg"] / n).write_bytes(b)
        for n, b in harness:
            (dirs["fw"] / n).write_bytes(b)
        (dirs["gen"] / "pil_adapter.h").write_text(adapter, encoding="utf-8")
        include = ["-I", str(dirs["gen"]), "-I", str(dirs["pkg"]), "-I", str(dirs["fw"])]
        objs = []
        units: list[tuple[str, str, list[str]]] = [("pkg", n, []) for n in pkg.sources]
        units += [("fw", n, list(HARNESS_DEFINES)) for n, _ in harness if n.endswith(".c")]
        for i, (where, n, extra) in enumerate(units):
            obj = work / f"{i:03d}_{Path(n).stem}.o"
            _run([gcc, *flags, *extra, *include, "-c", str(dirs[where] / n), "-o", str(obj)],
                 f"compiling {n} for the PIL firmware ({core})")
            objs.append(str(obj))
        _run([gcc, *CORES[core].flags, *LDFLAGS, "-T", str(dirs["fw"] / LINKER_SCRIPT),
              f"-Wl,--defsym=__pil_stack_size={stack_size}", *objs, *LDLIBS, "-o", str(out)],
             f"linking the PIL firmware of rpo_{pkg.name} ({core})")
