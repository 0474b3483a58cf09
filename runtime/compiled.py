"""Load the generated model: compile ``generated/`` into a cached shared library and call it.

Never loads stale code:

* ``generated/manifest.json`` records the sha256 of every generated source; a mismatch (a hand
  edit, a partial checkout) is an error that says to run ``python build.py``;
* every generated C file is compiled on its own into an object named by a key over its bytes,
  the compiler's identity and the flags (``<cache>/obj/``), in parallel on every core; the
  library is linked from those objects and the loop driver and named by a key over all of
  them, the manifest and the runtime ABI version, so a rebuilt library never reuses a path
  that a process may already have loaded, and an edit recompiles only the files it changed;
* objects and the library are written to temporary files in the cache and renamed into place
  (atomic); the link runs under a file lock, so concurrent builds are safe;
* every cached shared library (the model's, the lane library, the fast-call extension) has a side
  file ``.<name>.sha256`` with its name and the sha256 of its bytes, written before the library is
  renamed into place; a library whose bytes or name do not match (truncated, corrupt, another
  library copied under this name) is never loaded: it is rebuilt, or refused with one line if it
  cannot be (:func:`ensure_built`).  Each file is hashed once per process (~1 ms per MB);
* after loading, every function's input/output count and shapes are checked against the manifest.

Only numpy and ctypes are needed here: no SymPy, no CasADi (except for the explicit, warned
``backend="casadi"`` fallback used when no C compiler is available).
"""

from __future__ import annotations

import ctypes
import gzip
import hashlib
import json
import math
import os
import platform
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import ThreadPoolExecutor, as_completed
from contextlib import contextmanager
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from .errors import ModelError

#: Bump when the loop driver's calling convention or the library layout changes.
RUNTIME_ABI = 3
#: -O2 without -ffast-math: IEEE semantics are kept so that divergence (NaN/inf) is detected
#: and results match the symbolic model to round-off.  -ffp-contract=off and rpo's own math
#: functions (rpo_math_scalar.h, forced in before the generated code) make the scalar objects
#: compute exactly what the lane objects compute in every lane.
CFLAGS = ("-O2", "-fPIC", "-ffp-contract=off")
#: The lane objects (runtime/lanes.py): the same IEEE rules, for the machine's vector unit
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
#: The manifest format this runtime reads (``rpo.symbolic.codegen.codegen.FORMAT_VERSION``; a test checks they agree).
MANIFEST_FORMAT = 2

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)
_INT_P = ctypes.POINTER(ctypes.c_longlong)


def generated_dir() -> Path:
    """The folder holding the generated sources and manifest (``rpo.generated``)."""
    return Path(str(resources.files("rpo.generated")))


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


def _scalar_flags() -> list[str]:
    return [*CFLAGS, "-I", str(csrc_dir()), "-include", SCALAR_MATH]


def read_manifest(gen_dir: Path | None = None, verify: bool = True) -> dict:
    """Read ``manifest.json`` and check the generated files against the hashes it records."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    path = gen_dir / "manifest.json"
    if not path.exists():
        raise ModelError(f"{path} is missing: run `python build.py` in the rpo checkout")
    try:
        manifest = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"{path} cannot be read ({exc}): run `python build.py`") from exc
    if manifest.get("format_version") != MANIFEST_FORMAT:
        raise ModelError(f"{path} has format {manifest.get('format_version')}, this runtime reads format "
                         f"{MANIFEST_FORMAT}: run `python build.py`")
    if verify:
        if manifest.get("manifest_hash") != manifest_hash(manifest):
            raise ModelError(f"{path} does not match its recorded hash (edited by hand?): run `python build.py`")
        for name, digest in manifest["files"].items():
            f = gen_dir / name
            if not f.exists():
                raise ModelError(f"{f} is missing: run `python build.py`")
            if hashlib.sha256(f.read_bytes()).hexdigest() != digest:
                raise ModelError(f"{f} does not match manifest.json (edited by hand or half-written):"
                                 " run `python build.py`")
    return manifest


def manifest_hash(manifest: dict) -> str:
    """sha256 of the manifest's canonical JSON without its ``manifest_hash`` field.

    Same definition as ``rpo.symbolic.codegen.codegen.manifest_hash`` (the runtime must not import
    rpo.symbolic); ``tests/test_build.py`` checks that the two agree.
    """
    body = {k: v for k, v in manifest.items() if k != "manifest_hash"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


# --------------------------------------------------------------------------- compiler


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


def cache_dir() -> Path:
    """Per-user build cache: $RPO_CACHE_DIR, else $XDG_CACHE_HOME/rpo, else ~/.cache/rpo."""
    if os.environ.get("RPO_CACHE_DIR"):
        return Path(os.environ["RPO_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "rpo"


def object_key(source: bytes, cc_id: str, flags: Iterable[str] = CFLAGS) -> str:
    """Cache key of one object file: the C source's bytes, the headers it includes, the compiler
    identity and the flags."""
    h = hashlib.sha256(source)
    h.update(json.dumps({"cc": cc_id, "flags": list(flags), "abi": RUNTIME_ABI, "platform": sys.platform,
                         "machine": platform.machine(), "headers": headers_digest()}, sort_keys=True).encode())
    return h.hexdigest()


def selected_sources(manifest: dict, controllers: Iterable[str] | None = None) -> list[str]:
    """The generated C files a library needs: all of them, or (``controllers`` given) those of the
    families that belong to no controller (the plant) plus the families of the named controllers.

    A first ``rpo run`` compiles only what its scenario flies; the objects are cached and shared
    with any later, larger selection.
    """
    if controllers is None:
        return list(manifest["sources"])
    ctrls = manifest.get("controllers", {})
    unknown = sorted(set(controllers) - set(ctrls))
    if unknown:
        raise ModelError(f"unknown controller {', '.join(unknown)}; available: {', '.join(sorted(ctrls))}")
    funcs = manifest["functions"]
    owned = {name: {funcs[f]["family"] for f in entry.values() if f in funcs} for name, entry in ctrls.items()}
    all_ctrl = set().union(*owned.values()) if owned else set()
    keep = set().union(*(owned[c] for c in controllers)) if controllers else set()
    return [d["source"] for d in sorted(funcs.values(), key=lambda d: d["source"])
            if d["family"] not in all_ctrl or d["family"] in keep]


def _sources(gen_dir: Path, manifest: dict, controllers: Iterable[str] | None = None) -> list[tuple[str, bytes]]:
    """(name, bytes) of every C file the library is linked from: the generated ones, each read once
    and checked against the manifest's sha256, and the loop driver.

    The object key and the compiler see these same bytes (the compiler reads a private copy), so
    a build.py writing generated/ while a library is built cannot file new code under an old key.
    """
    out = []
    for name in selected_sources(manifest, controllers):
        try:
            data = (gen_dir / name).read_bytes()
        except OSError as exc:
            raise ModelError(f"{gen_dir / name} cannot be read ({exc.strerror}): run `python build.py`") from exc
        if hashlib.sha256(data).hexdigest() != manifest["files"].get(name):
            raise ModelError(f"{gen_dir / name} does not match manifest.json (edited by hand or being "
                             "rewritten): run `python build.py`")
        out.append((name, data))
    out.append((LOOP_SOURCE, loop_source().read_bytes()))
    return out


def _library_key(sources: list[tuple[str, bytes]], manifest: dict, cc_id: str) -> str:
    h = hashlib.sha256()
    for name, data in sources:
        h.update(name.encode() + b"\0" + object_key(data, cc_id).encode() + b"\0")
    h.update(json.dumps({"ldflags": LDFLAGS, "abi": RUNTIME_ABI, "tools": manifest["tools"],
                         "manifest": manifest["manifest_hash"]}, sort_keys=True).encode())
    return h.hexdigest()


def _compiler() -> tuple[list[str], str]:
    """The C compiler command and its identity, or the error that says what to install."""
    cc = find_compiler()
    if cc is None:
        raise ModelError(NO_COMPILER)
    return cc, compiler_identity(cc)


def _object_path(cache: Path, name: str, source: bytes, cc_id: str) -> Path:
    return cache / "obj" / f"{Path(name).stem}-{object_key(source, cc_id)[:24]}.o"


def _library_path(cache: Path, sources: list[tuple[str, bytes]], manifest: dict, cc_id: str) -> Path:
    return cache / f"rpo_model_{_library_key(sources, manifest, cc_id)[:24]}.so"


def library_key(gen_dir: Path, manifest: dict, cc_id: str, controllers: Iterable[str] | None = None) -> str:
    """Cache key of the library: every object key, the link flags, the manifest and the tool versions."""
    return _library_key(_sources(gen_dir, manifest, controllers), manifest, cc_id)


@contextmanager
def file_lock(path: Path) -> Iterator[None]:
    """An exclusive advisory lock on ``path`` (created if missing) for the duration of the block."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - non-POSIX: rely on the atomic renames alone
        yield
        return
    with open(path, "a+") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)



def _run_cc(cmd: list[str], what: str, cc: list[str]) -> None:
    res = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if res.returncode != 0:
        lines = res.stderr.strip().splitlines() or ["(no output)"]
        # the compiler's first "error:" line says what is wrong; the last is often a caret
        first = next((ln.strip() for ln in lines if "error" in ln.lower()), lines[-1].strip())
        raise ModelError(f"{what} failed ({' '.join(cc)}): {first}")


def _compile_object(cc: list[str], name: str, source: bytes, obj: Path, flags: list[str] | None = None) -> float:
    """Compile the C ``source`` (the bytes its key was computed from, written to a private copy) to
    ``obj`` through a temporary file in the same folder (atomic rename); return seconds."""
    t0 = time.perf_counter()
    fd, tmp = tempfile.mkstemp(prefix=f".{obj.stem}.", suffix=".tmp.o", dir=obj.parent)
    os.close(fd)
    fd, src = tempfile.mkstemp(prefix=f".{Path(name).stem}.", suffix=".c", dir=obj.parent)
    with os.fdopen(fd, "wb") as fh:
        fh.write(source)
    try:
        _run_cc([*cc, *(flags if flags is not None else _scalar_flags()), "-c", src, "-o", tmp],
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


def build_library(gen_dir: Path | None = None, cache: Path | None = None, log: Callable[[str], None] | None = None,
                  jobs: int | None = None, controllers: Iterable[str] | None = None,
                  manifest: dict | None = None) -> tuple[Path, bool]:
    """Compile the generated model into the cache if needed; return (library path, compiled?).

    Objects missing from ``<cache>/obj`` are compiled in parallel (``jobs``, default every core),
    with a progress line per file through ``log``; then the library is linked from them.
    ``controllers``: only the plant and these controllers' functions (default: everything).
    ``manifest``: the already verified manifest the caller will use with the library (default: read it).
    """
    controllers = None if controllers is None else sorted(set(controllers))
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    manifest = read_manifest(gen_dir) if manifest is None else manifest
    cc, cc_id = _compiler()
    cache = cache_dir() if cache is None else Path(cache)
    try:
        (cache / "obj").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"cannot create the build cache {cache} ({exc.strerror}): set RPO_CACHE_DIR "
                         "to a writable folder") from exc
    sources = _sources(gen_dir, manifest, controllers)
    objects = [(name, data, _object_path(cache, name, data, cc_id)) for name, data in sources]
    lib = _library_path(cache, sources, manifest, cc_id)
    return _compile_and_link(cc, objects, lib, cache, log, jobs, None, "the generated model")


def digest_path(lib: Path) -> Path:
    """The side file of a cached library: its name and the sha256 of its bytes (JSON)."""
    return lib.with_name(f".{lib.name}.sha256")


#: path -> (device, inode, size, mtime) of each library whose bytes matched its side file in this
#: process: a file is hashed once, and again only if it was replaced or touched since
_INTACT: dict[str, tuple[int, int, int, int]] = {}


def _sha256_file(path: Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def library_intact(lib: Path) -> bool:
    """True if ``lib`` exists and its bytes and name match its side file (:func:`digest_path`).

    False for a missing side file (a library of an older rpo, or one that was not sealed), a
    truncated or corrupt file, and a library copied from another name (the side file names the
    library it was written for).  Hashes a file once per process, unless its identity changes.
    """
    try:
        st = lib.stat()
        rec = json.loads(digest_path(lib).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    ident = (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)
    if _INTACT.get(str(lib)) == ident:
        return True
    if not isinstance(rec, dict) or rec.get("name") != lib.name or rec.get("size") != st.st_size:
        return False
    try:
        ok = rec.get("sha256") == _sha256_file(lib)
    except OSError:
        return False
    if ok:
        _INTACT[str(lib)] = ident
    return ok


def _seal(tmp: Path, lib: Path) -> None:
    """Write ``lib``'s side file for the finished ``tmp``, then rename ``tmp`` to ``lib`` (both atomic).

    The side file goes first: a library under its final name always has the record it is checked
    against (a crash in between leaves a side file without a library, which the next build rewrites).
    """
    rec = {"name": lib.name, "size": tmp.stat().st_size, "sha256": _sha256_file(tmp)}
    fd, side_tmp = tempfile.mkstemp(prefix=f".{lib.name}.", suffix=".sha256.part", dir=lib.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(rec, fh)
        os.replace(side_tmp, digest_path(lib))
    finally:
        if os.path.exists(side_tmp):
            os.unlink(side_tmp)
    os.replace(tmp, lib)
    st = lib.stat()
    _INTACT[str(lib)] = (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def ensure_built(lib: Path, build: Callable[[Path], None], what: str,
                 log: Callable[[str], None] | None = None) -> bool:
    """Make sure the cached library ``lib`` exists and is intact; return True if it was (re)built.

    ``build(tmp)`` writes the library into the temporary file ``tmp`` (in the cache folder).  An
    existing ``lib`` that fails :func:`library_intact` (truncated, corrupt, swapped, or unsealed) is
    removed and rebuilt under ``lib``'s lock; one that cannot be replaced is a :class:`ModelError`
    naming it (never loaded).
    """
    if library_intact(lib):
        return False
    with file_lock(lib.with_name(f".{lib.name}.lock")):
        if library_intact(lib):  # another process built it while we waited
            return False
        if lib.exists():
            if log:
                why = ("does not match its recorded name and sha256 (truncated, corrupt or replaced)"
                       if digest_path(lib).exists() else "has no recorded sha256 (an older rpo built it)")
                log(f"{lib} {why}: rebuilding {what}")
            try:
                lib.unlink()
            except OSError as exc:
                raise ModelError(f"cached {what} {lib} is corrupt and cannot be removed ({exc.strerror}): "
                                 "delete it or set RPO_CACHE_DIR to a writable folder") from None
        fd, tmp = tempfile.mkstemp(prefix=f".{lib.stem}.", suffix=f".tmp{lib.suffix}", dir=lib.parent)
        os.close(fd)
        try:
            build(Path(tmp))
            _seal(Path(tmp), lib)
        except OSError as exc:
            raise ModelError(f"cannot write {what} into the cache {lib.parent} ({exc.strerror or exc}): set "
                             "RPO_CACHE_DIR to a writable folder") from None
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return True


def _compile_and_link(cc: list[str], objects: list[tuple[str, bytes, Path]], lib: Path, cache: Path,
                      log: Callable[[str], None] | None, jobs: int | None, flags: list[str] | None,
                      what: str) -> tuple[Path, bool]:
    """Compile the missing ``objects`` (name, source bytes, object path) in parallel and link ``lib``
    from all of them, under the library's lock (:func:`ensure_built`); (lib, compiled?)."""
    def build(tmp: Path) -> None:
        todo = [(name, src, obj) for name, src, obj in objects if not obj.exists()]
        n_jobs = max(1, min(jobs or default_jobs(), len(todo) or 1))
        if log and todo:
            kind = "lane " if flags is not None else ""
            log(f"compiling {len(todo)} of {len(objects)} {kind}C files on {n_jobs} core{'s' * (n_jobs > 1)} "
                f"({len(objects) - len(todo)} cached) into {cache} ...")
        t0 = time.perf_counter()
        # largest first, so that the long step functions start at once and the short ones fill in
        todo.sort(key=lambda item: -len(item[1]))
        with ThreadPoolExecutor(max_workers=n_jobs) as pool:
            futures = {pool.submit(_compile_object, cc, name, src, obj, flags): name for name, src, obj in todo}
            try:
                for i, fut in enumerate(as_completed(futures), 1):
                    seconds = fut.result()
                    if log:
                        log(f"  [{i}/{len(todo)}] {futures[fut]} ({seconds:.1f} s, {len(todo) - i} left)")
            except BaseException:  # an error or an interrupt: start no further file (the running ones end)
                pool.shutdown(wait=True, cancel_futures=True)
                raise
        _run_cc([*cc, *LDFLAGS, "-o", str(tmp), *(str(obj) for _n, _s, obj in objects), "-lm"],
                f"linking {what}", cc)
        if log:
            log(f"linked {lib.name} from {len(objects)} objects ({time.perf_counter() - t0:.1f} s)")

    return lib, ensure_built(lib, build, what, log)


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


def _lane_flags(native: list[str]) -> list[str]:
    return [*LANE_CFLAGS, *native, "-I", str(csrc_dir())]


def lane_sources(gen_dir: Path, manifest: dict, controllers: Iterable[str] | None = None
                 ) -> tuple[list[tuple[str, bytes]], dict[str, str]]:
    """The lane forms (runtime/lanes.py) of the selected generated files whose every operation has
    one, and of the composed steps whose callees all have one; plus {file: why not} for the rest."""
    from .lanes import LaneError, lane_source

    done: dict[str, tuple[bytes, list[str]]] = {}
    skipped: dict[str, str] = {}
    for name, data in _sources(gen_dir, manifest, controllers)[:-1]:  # the last one is the loop driver
        try:
            text, callees = lane_source(name, data.decode())
        except LaneError as exc:
            skipped[name] = str(exc)
            continue
        done[name] = (text.encode(), callees)
    stem_to_file = {Path(n).stem: n for n in done}
    for name, (_text, callees) in list(done.items()):
        missing = [c for c in callees if c not in stem_to_file]
        if missing:
            skipped[name] = f"calls {', '.join(missing)}, which has no lane form"
            del done[name]
    out = [(f"{Path(n).stem}.lanes.c", text) for n, (text, _c) in sorted(done.items())]
    out.append((LANE_LOOP_SOURCE, (csrc_dir() / LANE_LOOP_SOURCE).read_bytes()))
    return out, skipped


def build_lane_library(gen_dir: Path | None = None, cache: Path | None = None,
                       log: Callable[[str], None] | None = None, jobs: int | None = None,
                       controllers: Iterable[str] | None = None, manifest: dict | None = None
                       ) -> tuple[Path, bool, dict[str, str]]:
    """Compile the lane forms of the generated model for this machine's vector width into the cache
    if needed; return (library path, compiled?, {file: why it has no lane form})."""
    controllers = None if controllers is None else sorted(set(controllers))
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    manifest = read_manifest(gen_dir) if manifest is None else manifest
    cc, cc_id = _compiler()
    cache = cache_dir() if cache is None else Path(cache)
    (cache / "obj").mkdir(parents=True, exist_ok=True)
    objects, lib, flags, skipped = _lane_plan(gen_dir, manifest, controllers, cache, cc, cc_id)
    path, compiled = _compile_and_link(cc, objects, lib, cache, log, jobs, flags, "the lane model")
    return path, compiled, skipped


def _lane_plan(gen_dir: Path, manifest: dict, controllers: list[str] | None, cache: Path, cc: list[str], cc_id: str):
    """(objects, library path, compile flags, skipped) of the lane library of a selection."""
    from .lanes import LANES_VERSION

    native, target_id = native_target(cc)
    flags = _lane_flags(native)
    lane_id = f"{cc_id}\ntarget {target_id}\nlanes {LANES_VERSION}"
    sources, skipped = lane_sources(gen_dir, manifest, controllers)
    keyflags = [*LANE_CFLAGS, *native]
    objects = [(n, d, cache / "obj" / f"{Path(n).stem}-{object_key(d, lane_id, keyflags)[:24]}.o") for n, d in sources]
    h = hashlib.sha256()
    for n, _d, obj in objects:
        h.update(n.encode() + b"\0" + obj.name.encode() + b"\0")
    h.update(json.dumps({"ldflags": LDFLAGS, "abi": RUNTIME_ABI, "manifest": manifest["manifest_hash"]},
                        sort_keys=True).encode())
    return objects, cache / f"rpo_lanes_{h.hexdigest()[:24]}.so", flags, skipped


def current_cache_files(gen_dir: Path | None = None, cache: Path | None = None) -> set[Path]:
    """The cache files the current generated/ uses: its objects, and its libraries for every
    selection a run makes (everything, or the plant and one controller)."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    cache = cache_dir() if cache is None else Path(cache)
    manifest = read_manifest(gen_dir)
    cc, cc_id = _compiler()
    keep = set()
    for ctrls in [None, *([c] for c in sorted(manifest.get("controllers", {})))]:
        sources = _sources(gen_dir, manifest, ctrls)
        keep |= {_object_path(cache, n, d, cc_id) for n, d in sources}
        keep.add(_library_path(cache, sources, manifest, cc_id))
        objects, lib, _flags, _skipped = _lane_plan(gen_dir, manifest, ctrls, cache, cc, cc_id)
        keep |= {obj for _n, _d, obj in objects}
        keep.add(lib)
    return keep


def prune_cache(gen_dir: Path | None = None, cache: Path | None = None, dry_run: bool = False) -> tuple[int, int]:
    """Delete the objects and libraries the current generated/ does not use; return (files, bytes).

    A library still loaded by a running process keeps working (the mapping outlives the name), and
    a library deleted here is rebuilt from cached or recompiled objects when it is needed again.
    Runs under a lock of its own, so two prunes do not race; a build running at the same time may
    have to recompile what was pruned, never loads anything stale.
    """
    cache = cache_dir() if cache is None else Path(cache)
    if not cache.is_dir():
        return 0, 0
    keep = current_cache_files(gen_dir, cache)
    n = size = 0
    with file_lock(cache / ".prune.lock"):
        for f in [*cache.glob("rpo_model_*.so"), *cache.glob("rpo_lanes_*.so"), *(cache / "obj").glob("*.o")]:
            if f in keep:
                continue
            n += 1
            size += f.stat().st_size
            if not dry_run:
                f.unlink(missing_ok=True)
                if f.suffix == ".so":  # its lock and its side file (the recorded sha256) go with it
                    (cache / f".{f.name}.lock").unlink(missing_ok=True)
                    digest_path(f).unlink(missing_ok=True)
    return n, size


# --------------------------------------------------------------------------- calling


#: (id of the library, function name) -> (the library, the manifest entry it was checked against,
#: its work sizes): a clone (one per simulation: a campaign makes one per run) is not checked again
_CHECKED: dict[tuple[int, str], tuple[ctypes.CDLL, dict, tuple[int, ...]]] = {}


class CompiledFunction:
    """A generated function called through ctypes with preallocated buffers.

    ``f(*inputs)`` returns fresh arrays shaped as in the manifest (a tuple, one per output);
    ``f(*inputs, out=arrays)`` writes into ``arrays`` (one array, or a tuple with one per output;
    float64, contiguous; a matrix output as a Fortran-ordered (rows, cols) array or flat) and
    returns them.  With the fast-call extension (:mod:`rpo.runtime.fastcall`) the inputs are read
    in place and the same arrays passed again cost nothing to check.  ``f.batch(...)`` evaluates
    many points in one C call.  Not thread-safe: use one instance per thread (``clone()``).
    """

    _model: Model | None = None

    def __init__(self, lib: ctypes.CDLL, name: str, desc: dict):
        self.name = name
        self.desc = desc
        self._lib = lib
        self.c_function = getattr(lib, name)
        checked = _CHECKED.get((id(lib), name))
        if checked is None or checked[0] is not lib or checked[1] is not desc:
            self.c_function.restype = ctypes.c_int
            self.c_function.argtypes = [ctypes.POINTER(_DOUBLE_P), ctypes.POINTER(_DOUBLE_P), _INT_P, _DOUBLE_P,
                                        ctypes.c_int]
            self._check_signature()
            sz = [ctypes.c_longlong() for _ in range(4)]
            getattr(lib, f"{name}_work")(*[ctypes.byref(s) for s in sz])
            checked = _CHECKED[(id(lib), name)] = (lib, desc, tuple(s.value for s in sz))
        # a clone (another instance of a function already checked against this manifest entry):
        # the same library, the same signature and work sizes
        self.sz_arg, self.sz_res, self.sz_iw, self.sz_w = checked[2]
        self.in_names = [i["name"] for i in desc["inputs"]]
        self.out_names = [o["name"] for o in desc["outputs"]]
        self.in_shapes = [tuple(i["shape"]) for i in desc["inputs"]]
        self.out_shapes = [tuple(o["shape"]) for o in desc["outputs"]]
        self.in_sizes = [math.prod(s) for s in self.in_shapes]
        self.out_sizes = [math.prod(s) for s in self.out_shapes]
        self.inputs = [np.zeros(n) for n in self.in_sizes]
        self.outputs = [np.zeros(n) for n in self.out_sizes]
        self.iw = np.zeros(max(self.sz_iw, 1), dtype=np.int64)
        self.work = np.zeros(max(self.sz_w, 1))
        self._arg = (_DOUBLE_P * max(self.sz_arg, 1))(*[b.ctypes.data_as(_DOUBLE_P) for b in self.inputs])
        self._res = (_DOUBLE_P * max(self.sz_res, 1))(*[b.ctypes.data_as(_DOUBLE_P) for b in self.outputs])
        self._iw_p = self.iw.ctypes.data_as(_INT_P)
        self._out_pairs = list(zip(self.outputs, self.out_shapes, strict=True))
        self._w_p = self.work.ctypes.data_as(_DOUBLE_P)

    def _check_signature(self):
        lib, name, desc = self._lib, self.name, self.desc
        for fn in ("n_in", "n_out"):
            getattr(lib, f"{name}_{fn}").restype = ctypes.c_longlong
        for fn in ("sparsity_in", "sparsity_out"):
            getattr(lib, f"{name}_{fn}").restype = _INT_P
            getattr(lib, f"{name}_{fn}").argtypes = [ctypes.c_longlong]
        if lib[f"{name}_n_in"]() != len(desc["inputs"]) or lib[f"{name}_n_out"]() != len(desc["outputs"]):
            raise ModelError(f"{name}: the compiled library does not match manifest.json (input/output count)")
        for kind, items in (("in", desc["inputs"]), ("out", desc["outputs"])):
            for i, item in enumerate(items):
                sp = getattr(lib, f"{name}_sparsity_{kind}")(i)
                nrow, ncol, dense = sp[0], sp[1], sp[2]
                if [nrow, ncol] != list(item["shape"]) or dense != 1:
                    raise ModelError(f"{name}: {kind}put {item['name']} is {nrow}x{ncol} (dense={dense}) in the "
                                     f"library but {item['shape']} in manifest.json: run `python build.py`")

    # -- one call ----------------------------------------------------------------------------

    def _wanted(self, i: int) -> str:
        r, c = self.in_shapes[i]
        return f"({r},)" if c == 1 else f"({r}, {c})"

    def _input(self, i: int, a) -> np.ndarray:
        """Input i as a flat float64 array in CasADi's (column-major) order, or a clear error."""
        r, c = self.in_shapes[i]
        try:
            arr = np.asarray(a, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"{self.name}: input {self.in_names[i]} must be numbers of shape {self._wanted(i)}, "
                            f"got {type(a).__name__}") from exc
        ok = arr.shape in {(r, c), (r * c,)} or (c == 1 and arr.shape == (r, 1)) or (r * c == 1 and arr.ndim == 0)
        if not ok:
            extra = " or a number" if r * c == 1 else (f" or ({r}, 1)" if c == 1 else "")
            raise ValueError(f"{self.name}: input {self.in_names[i]} must have shape {self._wanted(i)}{extra}, "
                             f"got {arr.shape}")
        return np.ravel(arr, order="F")

    def _out_views(self, out) -> list[np.ndarray]:
        """The out= arrays as flat views in CasADi's order, or a clear error."""
        outs = list(out) if isinstance(out, (tuple, list)) else [out]
        if len(outs) != len(self.out_shapes):
            raise ValueError(f"{self.name}: out= needs {len(self.out_shapes)} arrays "
                             f"({', '.join(self.out_names)}), got {len(outs)}")
        views = []
        for j, (o, (r, c)) in enumerate(zip(outs, self.out_shapes, strict=True)):
            want = (f"({r},)" if c == 1 else
                    f"({r}, {c}) in Fortran order (np.empty(({r}, {c}), order='F')) or ({r * c},)")
            if not isinstance(o, np.ndarray) or o.dtype != np.float64 or not o.flags.writeable:
                raise TypeError(f"{self.name}: out for {self.out_names[j]} must be a writable float64 array of "
                                f"shape {want}")
            if c == 1 and o.shape in {(r,), (r, 1)} and o.flags.c_contiguous:
                views.append(o.reshape(-1))
            elif c > 1 and o.shape == (r, c) and o.flags.f_contiguous:
                views.append(o.reshape(-1, order="F"))
            elif o.shape == (r * c,) and o.flags.c_contiguous:
                views.append(o)
            else:
                raise ValueError(f"{self.name}: out for {self.out_names[j]} must have shape {want} "
                                 f"(contiguous), got {o.shape}")
        return views

    def _py_call(self, args, out=None):
        """The ctypes path (also the fast path's fallback, which explains what is wrong)."""
        if len(args) != len(self.inputs):
            raise TypeError(f"{self.name} takes {len(self.inputs)} inputs ({', '.join(self.in_names)}), "
                            f"got {len(args)}")
        for i, (buf, a) in enumerate(zip(self.inputs, args, strict=True)):
            if isinstance(a, float | int) and buf.size == 1:
                buf[0] = a
                continue
            buf[:] = self._input(i, a)
        views = None if out is None else self._out_views(out)
        if self.c_function(self._arg, self._res, self._iw_p, self._w_p, 0) != 0:
            raise FloatingPointError(f"{self.name} reported an evaluation error")
        if views is not None:
            for v, o in zip(views, self.outputs, strict=True):
                v[:] = o
            return out
        return self._finish()

    def _finish(self):
        return tuple(o.reshape(s, order="F").copy() if s[1] > 1 else o.copy() for o, s in self._out_pairs)

    def __call__(self, *args, out=None):
        return self._py_call(args, out)

    # -- many points -------------------------------------------------------------------------

    def batch(self, *args, out=None):
        """Evaluate at N points in one C call (K at a time in SIMD lanes where the lane library
        has this function), bit-identical to N single calls.

        Each input is either per point, with the leading axis N (``(N, n)``, or ``(N,)`` for a
        size-1 input), or one value shared by every point (``(n,)``, or a number).  Returns one
        array per output, ``(N, n)`` (``(N, rows, cols)`` for a matrix); ``out=`` takes such arrays
        (C-contiguous; a matrix output ``o`` with ``o.transpose(0, 2, 1)`` C-contiguous).
        """
        if len(args) != len(self.in_sizes):
            raise TypeError(f"{self.name}.batch takes {len(self.in_sizes)} inputs ({', '.join(self.in_names)}), "
                            f"got {len(args)}")
        n_points = None
        ins, strides = [], []
        for i, (a, n) in enumerate(zip(args, self.in_sizes, strict=True)):
            arr = np.asarray(a, dtype=float)
            r, c = self.in_shapes[i]
            if c > 1:
                per_point, shared = arr.ndim == 3 and arr.shape[1:] == (r, c), arr.shape == (r, c)
                if per_point:
                    arr = arr.transpose(0, 2, 1)
            else:
                per_point = (arr.ndim == 2 and arr.shape[1] == n) or (n == 1 and arr.ndim == 1)
                shared = (arr.ndim == 1 and arr.shape[0] == n and n > 1) or (n == 1 and arr.ndim == 0)
            if per_point:
                if n_points is not None and arr.shape[0] != n_points:
                    raise ValueError(f"{self.name}.batch: input {self.in_names[i]} has {arr.shape[0]} points, an "
                                     f"earlier input {n_points}")
                n_points = arr.shape[0]
                ins.append(np.ascontiguousarray(arr).reshape(n_points, n))
                strides.append(n)
            elif shared:
                ins.append(np.ascontiguousarray(arr).reshape(n, order="F"))
                strides.append(0)
            else:
                one = f"({r}, {c})" if c > 1 else f"({n},)" if n > 1 else "a number"
                many = f"(N, {r}, {c})" if c > 1 else f"(N, {n})" if n > 1 else "(N,)"
                raise ValueError(f"{self.name}.batch: input {self.in_names[i]} must have shape {many} (one per "
                                 f"point) or {one} (shared), got {arr.shape}")
        if n_points is None:
            raise ValueError(f"{self.name}.batch: no input has the leading axis N (use the single call)")
        N = n_points
        shapes = [(N, r) if c == 1 else (N, c, r) for r, c in self.out_shapes]  # per point: CasADi's column order
        if out is None:
            bufs = [np.empty(s) for s in shapes]
        else:
            outs = list(out) if isinstance(out, (tuple, list)) else [out]
            if len(outs) != len(shapes):
                raise ValueError(f"{self.name}.batch: out= needs {len(shapes)} arrays, got {len(outs)}")
            bufs = []
            for j, (o, s) in enumerate(zip(outs, shapes, strict=True)):
                o2 = o.transpose(0, 2, 1) if isinstance(o, np.ndarray) and o.ndim == 3 else o
                if not (isinstance(o2, np.ndarray) and o2.dtype == np.float64 and o2.shape == s
                        and o2.flags.c_contiguous and o2.flags.writeable):
                    want = s if len(s) == 2 else (N, s[2], s[1])
                    raise ValueError(f"{self.name}.batch: out for {self.out_names[j]} must be a writable, contiguous "
                                     f"float64 array of shape {want}")
                bufs.append(o2)
        # an input sharing memory with an output (out=X) is read from a copy: the scalar loop
        # evaluates in place, and the generated code writes outputs before it has read all inputs
        ins = [a.copy() if any(np.may_share_memory(a, b) for b in bufs) else a for a in ins]
        in_p = (_DOUBLE_P * len(ins))(*[a.ctypes.data_as(_DOUBLE_P) for a in ins])
        in_n = (ctypes.c_longlong * len(ins))(*self.in_sizes)
        in_s = (ctypes.c_longlong * len(ins))(*strides)
        out_p = (_DOUBLE_P * len(bufs))(*[b.ctypes.data_as(_DOUBLE_P) for b in bufs])
        out_n = (ctypes.c_longlong * len(bufs))(*self.out_sizes)
        lanes = self._model.lanes() if self._model is not None else None
        if lanes is not None and lanes.has(self.name):
            rc = lanes.batch(ctypes.c_void_p(lanes.pointers[self.name]), ctypes.c_longlong(lanes.work[self.name]),
                             ctypes.c_int(len(ins)), in_p, in_n, in_s, ctypes.c_int(len(bufs)), out_p, out_n,
                             ctypes.c_longlong(N))
        else:
            f = self._lib.rpo_batch_scalar
            f.restype = ctypes.c_longlong
            rc = f(ctypes.cast(self.c_function, ctypes.c_void_p), self._iw_p, self._w_p, ctypes.c_int(len(ins)),
                   in_p, in_s, ctypes.c_int(len(bufs)), out_p, out_n, ctypes.c_longlong(N))
        if rc == -1:
            raise MemoryError(f"{self.name}.batch: no memory for the lane buffers")
        if rc != 0:
            raise FloatingPointError(f"{self.name} reported an evaluation error at point {rc - 1}")
        if out is not None:
            return out
        return tuple(b if b.ndim == 2 else b.transpose(0, 2, 1) for b in bufs)

    def clone(self) -> CompiledFunction:
        other = type(self)(self._lib, self.name, self.desc)
        other._model = self._model
        return other


_FAST_CLASS: dict[int, type] = {}


def _function_class(ext) -> type:
    """CompiledFunction with its single call done by the fast-call extension's ``Caller``."""
    if ext is None:
        return CompiledFunction
    if id(ext) not in _FAST_CLASS:
        class FastCompiledFunction(ext.Caller, CompiledFunction):  # type: ignore[misc, name-defined]
            __doc__ = CompiledFunction.__doc__

            def __init__(self, lib: ctypes.CDLL, name: str, desc: dict):
                CompiledFunction.__init__(self, lib, name, desc)
                ext.Caller.__init__(
                    self, ctypes.cast(self.c_function, ctypes.c_void_p).value, self.in_sizes, self.out_sizes,
                    [s[1] > 1 for s in self.out_shapes], self.iw.ctypes.data, self.work.ctypes.data,
                    tuple(self.outputs), self._py_call, self._finish)

        ext.enable_vectorcall(FastCompiledFunction)
        _FAST_CLASS[id(ext)] = FastCompiledFunction
    return _FAST_CLASS[id(ext)]


class CasadiFunction:
    """Fallback with the same call interface, evaluated by CasADi's virtual machine."""

    def __init__(self, fn, desc: dict):
        self.name = fn.name()
        self.desc = desc
        self.fn = fn
        self.out_shapes = [tuple(o["shape"]) for o in desc["outputs"]]

    def __call__(self, *args):
        res = self.fn(*[np.asarray(a, float).reshape(-1, 1, order="F") for a in args])
        res = res if isinstance(res, (list, tuple)) else [res]
        return tuple(np.asarray(r.full()).reshape(s, order="F") if s[1] > 1 else np.asarray(r.full()).ravel()
                     for r, s in zip(res, self.out_shapes, strict=True))

    def clone(self) -> CasadiFunction:
        return self


class Model:
    """The generated model: manifest, layouts and callable functions (compiled or CasADi)."""

    def __init__(self, manifest: dict, functions: dict, backend: str, library: Path | None = None,
                 lib: ctypes.CDLL | None = None, gen_dir: Path | None = None,
                 controllers: Iterable[str] | None = None, log: Callable[[str], None] | None = None):
        self.manifest = manifest
        self.functions = functions
        self.backend = backend
        self.library = library
        self._lib = lib
        self._gen_dir = gen_dir
        self._controllers = None if controllers is None else sorted(set(controllers))
        self._log = log
        self._lanes: LaneLibrary | None = None
        #: layout name -> (field -> (offset, size), packed defaults, fields without a default, size)
        self._packing: dict[str, tuple[dict[str, tuple[int, int]], np.ndarray, list[str], int]] = {}
        self._slices: dict[str, dict[str, slice]] = {}
        self._orders: dict[str, list[tuple[int, str, int]]] = {}
        self._columns: dict[tuple, Any] = {}
        self._bad_defaults: dict[str, list[str]] = {}
        for f in functions.values():
            if isinstance(f, CompiledFunction):
                f._model = self

    def lanes(self) -> LaneLibrary | None:
        """The lane library (K runs per call, K = this machine's vector width), built on first use
        (compiled backend only; None for the CasADi backend)."""
        if self._lanes is None and self.backend == "compiled":
            path, _compiled, skipped = build_lane_library(self._gen_dir, log=self._log,
                                                          controllers=self._controllers, manifest=self.manifest)
            self._lanes = LaneLibrary(path, skipped, self.manifest)
        return self._lanes

    def __getattr__(self, name):
        try:
            return self.__dict__["functions"][name]
        except KeyError:
            raise AttributeError(name) from None

    def linearize(self, controller: str, z: np.ndarray, t: float, p: np.ndarray, k: np.ndarray, **kw):
        """The closed-loop step's Jacobian in reduced coordinates (AD of ``step_<controller>``):
        :func:`rpo.runtime.linearize.linearize`."""
        from .linearize import linearize

        return linearize(self, controller, z, t, p, k, **kw)

    def plant_jacobians(self, x: np.ndarray, u: np.ndarray, t: float, p: np.ndarray, **kw):
        """The plant's continuous A = df/dx, B = df/du: :func:`rpo.runtime.linearize.plant_jacobians`."""
        from .linearize import plant_jacobians

        return plant_jacobians(self, x, u, t, p, **kw)

    def function(self, name: str):
        """The loaded function ``name``; a clear error if the manifest has it but it was not loaded."""
        if name in self.functions:
            return self.functions[name]
        if name in self.manifest["functions"]:
            raise ModelError(f"{name} is not loaded: this model was loaded for some controllers only "
                             "(load_model(controllers=[...]))")
        raise ModelError(f"no generated function {name!r}")

    @property
    def layouts(self) -> dict:
        return self.manifest["layouts"]

    def layout_size(self, name: str) -> int:
        return sum(f["size"] for f in self.layouts[name])

    def _pack(self, name: str) -> tuple[dict[str, tuple[int, int]], np.ndarray, list[str], int]:
        """The packing of a layout, made once (a campaign packs thousands of vectors)."""
        info = self._packing.get(name)
        if info is None:
            offs, i, missing = {}, 0, []
            for f in self.layouts[name]:
                offs[f["name"]] = (i, int(f["size"]))
                i += int(f["size"])
            base = np.zeros(i)
            for f in self.layouts[name]:
                a, n = offs[f["name"]]
                if "default" in f and len(f["default"]) == n:
                    base[a:a + n] = np.array(f["default"], float)
                elif "default" in f:
                    self._bad_defaults.setdefault(name, []).append(f["name"])
                else:
                    missing.append(f["name"])
            info = self._packing[name] = (offs, base, missing, i)
        return info

    def _order(self, name: str) -> list[tuple[int, str, int]]:
        """(offset, field, size) of a layout, sorted by offset then name (made once)."""
        order = self._orders.get(name)
        if order is None:
            order = self._orders[name] = sorted((a, k, n) for k, (a, n) in self._pack(name)[0].items())
        return order

    def _contiguous(self, name: str) -> bool:
        """Whether the fields of a layout, in :meth:`_order`, tile it without gaps or overlaps."""
        key = ("contiguous", name)
        hit = self._columns.get(key)
        if hit is None:
            at = 0
            hit = True
            for a, _k, n in self._order(name):
                hit = hit and a == at
                at = a + n
            hit = self._columns[key] = hit and at == self._pack(name)[3]
        return bool(hit)

    def offsets(self, name: str) -> dict[str, slice]:
        """{field: slice} of a layout (a new dict each call; the slices are made once per layout:
        a campaign asks for them a dozen times per run)."""
        sl = self._slices.get(name)
        if sl is None:
            sl = self._slices[name] = {k: slice(a, a + n) for k, (a, n) in self._pack(name)[0].items()}
        return dict(sl)

    def labels(self, name: str) -> list[str]:
        """Column labels of a layout (a new list; made once per layout)."""
        key = ("labels", name)
        if key not in self._columns:
            self._columns[key] = [lbl for f in self.layouts[name] for lbl in f["labels"]]
        return list(self._columns[key])

    def units(self, name: str) -> list[str]:
        """Column units of a layout (a new list; made once per layout)."""
        key = ("units", name)
        if key not in self._columns:
            self._columns[key] = [f["unit"] for f in self.layouts[name] for _ in range(f["size"])]
        return list(self._columns[key])

    def field_labels(self, *names: str) -> Mapping[str, tuple[str, ...]]:
        """Field -> its column labels over the layouts ``names`` (read-only, made once per selection:
        every run's result shares it)."""
        key = ("fields", *names)
        if key not in self._columns:
            self._columns[key] = MappingProxyType({f["name"]: tuple(f["labels"]) for n in names
                                                   for f in self.layouts[n]})
        return self._columns[key]

    def defaults(self, name: str) -> dict[str, np.ndarray]:
        return {f["name"]: np.array(f["default"], float) for f in self.layouts[name] if "default" in f}

    def vector(self, name: str, values: dict | None = None) -> np.ndarray:
        """Pack a layout from defaults overridden by ``values`` (by field name)."""
        offs, base, no_default, _size = self._pack(name)
        bad = self._bad_defaults.get(name, [])
        values = values or {}
        for f in no_default:
            if f not in values:
                raise ModelError(f"{name}.{f} has no default and was not given")
        order = self._order(name)
        if len(values) == len(order) and self._contiguous(name):
            # every field given (a run's parameters): one concatenation in the layout's order
            given_all = [values.get(k) for _a, k, _n in order]
            vals = [v for v in given_all if type(v) is np.ndarray and v.dtype == np.float64 and v.ndim == 1]
            if len(vals) == len(order) and [v.size for v in vals] == [n for _a, _k, n in order]:
                return np.concatenate(vals) if vals else base.copy()
        out = base.copy()
        if 4 * len(values) < len(offs):
            given = sorted((offs[k][0], k, offs[k][1]) for k in values if k in offs)
        else:  # most of the fields (a run's parameters): the layout's own order, the same sequence
            given = [f for f in self._order(name) if f[1] in values]
        for a, k, n in given:
            v = values[k]
            if type(v) is not np.ndarray or v.dtype != np.float64 or v.ndim != 1:  # else as it is: no copy
                v = np.atleast_1d(np.asarray(v, float)).ravel()
            if v.size != n:
                raise ModelError(f"{name}.{k} needs {n} values, got {v.size}")
            out[a:a + n] = v
        unknown = [k for k in values if k not in offs]
        if unknown:
            raise ModelError(f"unknown {name} fields: {', '.join(sorted(unknown))}")
        for f in bad:  # a default of the wrong size (a hand-edited manifest), used: refused as before
            if f not in values:
                got = len(next(e for e in self.layouts[name] if e["name"] == f)["default"])
                raise ModelError(f"{name}.{f} needs {offs[f][1]} values, got {got}")
        return out

    @property
    def run_function(self):
        """The C loop driver ``rpo_run`` (compiled backend only)."""
        if self._lib is None:
            return None
        f = self._lib.rpo_run
        f.restype = ctypes.c_int
        return f


class LaneLibrary:
    """The lane forms of the generated functions, loaded: ``width`` runs per call."""

    def __init__(self, path: Path, skipped: dict[str, str], manifest: dict):
        try:
            self.lib = ctypes.CDLL(str(path))
        except OSError as exc:
            raise ModelError(f"cannot load {path} ({exc}): delete it and run again to rebuild") from exc
        self.path = path
        self.skipped = skipped
        self.width = int(self.lib.rpo_lanes_width())
        self.pointers: dict[str, int] = {}
        self.work: dict[str, int] = {}
        for name, desc in manifest["functions"].items():
            if desc["source"] in skipped or not hasattr(self.lib, f"{name}_lanes"):
                continue
            self.pointers[name] = ctypes.cast(getattr(self.lib, f"{name}_lanes"), ctypes.c_void_p).value or 0
            work = getattr(self.lib, f"{name}_lanes_work")
            work.restype = ctypes.c_longlong
            self.work[name] = int(work())
        self.batch = self.lib.rpo_batch_lanes
        self.batch.restype = ctypes.c_longlong
        self.run = self.lib.rpo_run_lanes
        self.run.restype = ctypes.c_int

    def has(self, name: str) -> bool:
        return name in self.pointers


def _load_compiled(gen_dir: Path, manifest: dict, log=None, controllers: Iterable[str] | None = None) -> Model:
    lib_path, _ = build_library(gen_dir, log=log, controllers=controllers, manifest=manifest)
    sources = set(selected_sources(manifest, controllers))
    try:
        lib = ctypes.CDLL(str(lib_path))
    except OSError as exc:
        raise ModelError(f"cannot load {lib_path} ({exc}): delete it and run again to rebuild") from exc
    selftest = lib.rpo_selftest_nan
    selftest.restype = ctypes.c_int
    selftest.argtypes = [ctypes.c_double]
    if selftest(float("nan")) != 0 or selftest(float("inf")) != 0 or selftest(1.0) != 1:
        raise ModelError(f"{lib_path} does not detect NaN/inf (built with -ffast-math or similar via $CC?): "
                         "divergence would go unnoticed; use a plain C compiler command")
    for source in sorted(sources):
        int_size = getattr(lib, f"{Path(source).stem}_casadi_int_size")
        int_size.restype = ctypes.c_int
        if int_size() != 8:
            raise ModelError(f"generated/{source} uses a casadi_int that is not 64-bit: run `python build.py`")
    from . import fastcall

    cls = _function_class(fastcall.load())
    funcs = {name: cls(lib, name, desc) for name, desc in manifest["functions"].items()
             if desc["source"] in sources}
    return Model(manifest, funcs, "compiled", lib_path, lib, gen_dir=gen_dir, controllers=controllers, log=log)


def _load_casadi(gen_dir: Path, manifest: dict) -> Model:
    try:
        import casadi as ca
    except ImportError as exc:  # pragma: no cover
        raise ModelError("backend 'casadi' needs the casadi package (pip install casadi)") from exc
    funcs = {}
    for name, desc in manifest["functions"].items():
        with gzip.open(gen_dir / f"{name}.casadi.gz", "rt") as fh:
            funcs[name] = CasadiFunction(ca.Function.deserialize(fh.read()), desc)
    return Model(manifest, funcs, "casadi")


def load_model(backend: str = "auto", gen_dir: Path | None = None, log: Callable[[str], None] | None = None,
               controllers: Iterable[str] | None = None) -> Model:
    """Load the model: ``"compiled"`` (C), ``"casadi"`` (VM fallback, warned) or ``"auto"``.

    ``auto`` means compiled; without a C compiler it raises a :class:`ModelError` that says
    what to install or how to choose the CasADi fallback explicitly (never a silent slowdown).
    ``controllers``: load only the plant and these controllers (what a run needs; the first run
    after an install then compiles a fraction of the model); default: every controller.
    ``log`` receives the compile progress (which file, how many left).
    """
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    manifest = read_manifest(gen_dir)
    if backend in ("auto", "compiled"):
        return _load_compiled(gen_dir, manifest, log, controllers)
    if backend == "casadi":
        warnings.warn("backend 'casadi': evaluating the model in CasADi's virtual machine, about 100x slower "
                      "than the compiled backend", RuntimeWarning, stacklevel=2)
        return _load_casadi(gen_dir, manifest)
    raise ModelError(f"backend must be one of auto, compiled, casadi; got {backend!r}")
