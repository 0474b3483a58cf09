"""The C toolchain: compiler discovery and identity, the flags of the scalar and lane objects, one compile
call, the runtime's own C sources (runtime/csrc)."""

from __future__ import annotations

import hashlib
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

from rpo.runtime.errors import ModelError

#: -O2 without -ffast-math: IEEE semantics are kept so that divergence (NaN/inf) is detected
#: and results match the symbolic model to round-off.  -ffp-contract=off and rpo's own math
#: functions (rpo_math_scalar.h, forced in before the generated code) make the scalar objects
#: compute exactly what the lane objects compute in every lane.
CFLAGS = ("-O2", "-fPIC", "-ffp-contract=off")


#: The lane objects (runtime/model/lanes.py): the same IEEE rules, for the machine's vector unit
#: (``-march=native`` where the compiler has it: the lane width follows the target).  The
#: pressure-aware scheduling before register allocation spills fewer 64-byte vectors from the
#: long straight-line bodies: measured 1.7 against 2.05 us per run-step with -O3 alone and 2.7
#: with -O2 (benchmarks/bench_step.py, AVX-512, K = 8); K = 4 on the same machine was slower.
LANE_CFLAGS = ("-O3", "-fPIC", "-ffp-contract=off", "-fno-strict-aliasing", "-fschedule-insns", "-fsched-pressure")


SCALAR_MATH = "rpo_math_scalar.h"


LANE_LOOP_SOURCE = "lanes_loop.c"


#: -z defs (GNU ld): a callee missing from the link is an error now, not a library that fails to load
LDFLAGS = ("-shared", "-Wl,-z,defs") if sys.platform.startswith("linux") else ("-shared",)


LOOP_SOURCE = "sim_loop.c"


def csrc_dir() -> Path:
    """The hand-written C of the runtime: the loop drivers and the math headers."""
    return Path(str(resources.files("rpo.runtime"))) / "csrc"


def loop_source() -> Path:
    return csrc_dir() / LOOP_SOURCE


def headers_digest() -> str:
    """sha256 over the runtime's C headers (rpo_math.h and friends), which every object includes:
    a header edit must change every object key."""
    h = hashlib.sha256()
    for f in sorted(csrc_dir().glob("*.h")):
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


#: Scalar files compiled at another level than CFLAGS' -O2 (file -> level), chosen by measurement
#: (``benchmarks/bench_first_use.py --opt``): the plant's RK4 steps are 0.45-0.75 MB of straight-line
#: code whose -O2 compile takes about twice the -O1 one and the most of a first run's wait, for
#: a step that is a few percent slower at -O1.  IEEE semantics hold at every level (no
#: -ffast-math, -ffp-contract=off): the results are bit-identical whatever the level.
SCALAR_OPT: dict[str, str] = {
    "plant_advance.c": "-O1",
    "plant_advance_kepler.c": "-O1",
    "plant_advance_kepler_nodist.c": "-O1",
    "plant_jac.c": "-O1",
}


def scalar_cflags(name: str) -> tuple[str, ...]:
    """The flags of the scalar object of the C file ``name`` (its optimisation level from SCALAR_OPT)."""
    level = SCALAR_OPT.get(name)
    return CFLAGS if level is None else (level, *CFLAGS[1:])


def scalar_flags(name: str = "") -> list[str]:
    return [*scalar_cflags(name), "-I", str(csrc_dir()), "-include", SCALAR_MATH]


def find_compiler() -> list[str] | None:
    """The C compiler command: $CC (may carry arguments, e.g. ``ccache gcc``), else cc, gcc, clang."""
    if os.environ.get("CC"):  # explicit: used as given or not at all (no silent substitute)
        cmd = shlex.split(os.environ["CC"])
        path = shutil.which(cmd[0]) if cmd else None
        return [path, *cmd[1:]] if path else None
    for c in ("cc", "gcc", "clang"):
        path = shutil.which(c)
        if path:
            return [path]
    return None


def compiler_identity(cc: list[str]) -> str:
    """What the cache key needs to know about the compiler: the full command, a hash of the
    executable it starts (a wrapper script counts), ``--version`` and ``-dumpmachine``."""
    parts = [" ".join(cc), hashlib.sha256(Path(cc[0]).read_bytes()).hexdigest()]
    for flag in ("--version", "-dumpmachine"):
        try:
            out = subprocess.run([*cc, flag], capture_output=True, text=True, timeout=30, check=False)
        except OSError as exc:
            raise ModelError(f"cannot run the C compiler {' '.join(cc)}: {exc}") from exc
        parts.append((out.stdout or out.stderr).strip())
    return "\n".join(parts)


NO_COMPILER = (
    "no C compiler found (looked for $CC if set, else cc, gcc, clang). Install one "
    "(Debian/Ubuntu: `apt-get install gcc`; Fedora: `dnf install gcc`; macOS: `xcode-select --install`), "
    "or run with backend 'casadi' (`--backend casadi`), which evaluates the model in CasADi's "
    "virtual machine, about 100x slower."
)


def compiler_command() -> tuple[list[str], str]:
    """The C compiler command and its identity, or the error that says what to install."""
    cc = find_compiler()
    if cc is None:
        raise ModelError(NO_COMPILER)
    return cc, compiler_identity(cc)


def run_cc(cmd: list[str], what: str, cc: list[str]) -> None:
    res = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if res.returncode != 0:
        lines = res.stderr.strip().splitlines() or ["(no output)"]
        # the compiler's first "error:" line says what is wrong; the last is often a caret
        first = next((ln.strip() for ln in lines if "error" in ln.lower()), lines[-1].strip())
        raise ModelError(f"{what} failed ({' '.join(cc)}): {first}")


def compile_object(cc: list[str], name: str, source: bytes, obj: Path, flags: list[str] | None = None) -> float:
    """Compile the C ``source`` (the bytes its key was computed from, written to a private copy) to
    ``obj`` through a temporary file in the same folder (atomic rename); return seconds."""
    t0 = time.perf_counter()
    fd, tmp = tempfile.mkstemp(prefix=f".{obj.stem}.", suffix=".tmp.o", dir=obj.parent)
    os.close(fd)
    fd, src = tempfile.mkstemp(prefix=f".{Path(name).stem}.", suffix=".c", dir=obj.parent)
    with os.fdopen(fd, "wb") as fh:
        fh.write(source)
    try:
        run_cc([*cc, *(flags if flags is not None else scalar_flags(name)), "-c", src, "-o", tmp],
                f"compiling {name}", cc)
        os.replace(tmp, obj)
    finally:
        for f in (tmp, src):
            if os.path.exists(f):
                os.unlink(f)
    return time.perf_counter() - t0


def default_jobs() -> int:
    """Compiler processes to run at once: every core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


_NATIVE: dict[tuple[str, ...], tuple[list[str], str]] = {}


def native_target(cc: list[str]) -> tuple[list[str], str]:
    """The flags that select the vector unit of the lane objects and an identity of that target
    (the compiler's predefined macros under those flags) for their keys.

    ``-march=native`` (this machine's unit) when the compiler takes it, else the compiler's
    default target; ``RPO_LANES_TARGET=baseline`` asks for the default target (e.g. to test the
    SSE2 width on an AVX-512 machine).
    """
    want = os.environ.get("RPO_LANES_TARGET", "native")
    if want not in ("native", "baseline"):
        raise ModelError(f"RPO_LANES_TARGET must be native or baseline, got {want!r}")
    key = (*cc, want)
    if key not in _NATIVE:
        candidates = [["-march=native"], []] if want == "native" else [[]]
        for cand in candidates:
            res = subprocess.run([*cc, *cand, "-dM", "-E", "-x", "c", os.devnull], capture_output=True,
                                 text=True, check=False)
            if res.returncode == 0:
                _NATIVE[key] = (cand, hashlib.sha256(res.stdout.encode()).hexdigest())
                break
        else:
            raise ModelError(f"the C compiler {' '.join(cc)} cannot preprocess an empty file")
    return _NATIVE[key]


def lane_flags(native: list[str]) -> list[str]:
    return [*LANE_CFLAGS, *native, "-I", str(csrc_dir())]
