"""Building the model's shared libraries from generated/: the scalar library and the lane library, each
linked from cached objects, and pruning the cache."""

from __future__ import annotations

import ctypes
import hashlib
import json
import time
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.model.cache import (
    RUNTIME_ABI,
    cache_dir,
    digest_path,
    ensure_built,
    file_lock,
    object_key,
    object_path,
)
from rpo.runtime.model.lanes import LANES_VERSION, LaneError, lane_source
from rpo.runtime.model.manifest import Manifest, generated_dir, read_manifest, selected_sources
from rpo.runtime.model.selection import callees, stub_source
from rpo.runtime.model.toolchain import (
    LANE_CFLAGS,
    LANE_LOOP_SOURCE,
    LDFLAGS,
    LOOP_SOURCE,
    compile_object,
    compiler_command,
    csrc_dir,
    default_jobs,
    lane_flags,
    loop_source,
    native_target,
    run_cc,
    scalar_cflags,
)

#: the file of the stubs of a partial library (never a generated file's name: generated/ has no "rpo_")
STUB_SOURCE = "rpo_stubs.c"

#: the longest a compile goes without a progress line (s)
HEARTBEAT_S = 4.0

def generated_sources(gen_dir: Path, manifest: Manifest, controllers: Iterable[str] | None = None,
                      functions: Iterable[str] | None = None) -> list[tuple[str, bytes]]:
    """(name, bytes) of every C file the library is linked from: the generated ones, each read once
    and checked against the manifest's sha256, and the loop driver.  ``functions`` (names): only
    their files, and the stub file (:func:`~rpo.runtime.model.selection.stub_source`) for the
    callees they leave out.

    The object key and the compiler see these same bytes (the compiler reads a private copy), so
    a build.py writing generated/ while a library is built cannot file new code under an old key.
    """
    out = []
    names = selected_sources(manifest, controllers)
    if functions is not None:
        functions = set(functions)
        files = {manifest.functions[f].source for f in functions}
        names = [n for n in names if n in files]
    for name in names:
        try:
            data = (gen_dir / name).read_bytes()
        except OSError as exc:
            raise ModelError(f"{gen_dir / name} cannot be read ({exc.strerror}): run `python build.py`") from exc
        if hashlib.sha256(data).hexdigest() != manifest.files.get(name):
            raise ModelError(f"{gen_dir / name} does not match manifest.json (edited by hand or being "
                             "rewritten): run `python build.py`")
        out.append((name, data))
    if functions is not None:
        missing = {c for _n, d in out for c in callees(d.decode())} - functions
        if missing:
            out.append((STUB_SOURCE, stub_source(missing, lanes=False)))
    out.append((LOOP_SOURCE, loop_source().read_bytes()))
    return out


def _library_key(sources: list[tuple[str, bytes]], manifest: Manifest, cc_id: str) -> str:
    h = hashlib.sha256()
    for name, data in sources:
        h.update(name.encode() + b"\0" + object_key(data, cc_id, scalar_cflags(name)).encode() + b"\0")
    h.update(json.dumps({"ldflags": LDFLAGS, "abi": RUNTIME_ABI, "tools": dict(manifest.tools),
                         "manifest": manifest.manifest_hash}, sort_keys=True).encode())
    return h.hexdigest()


def _library_path(cache: Path, sources: list[tuple[str, bytes]], manifest: Manifest, cc_id: str) -> Path:
    return cache / f"rpo_model_{_library_key(sources, manifest, cc_id)[:24]}.so"


def library_key(gen_dir: Path, manifest: Manifest, cc_id: str, controllers: Iterable[str] | None = None,
                functions: Iterable[str] | None = None) -> str:
    """Cache key of the library: every object key, the link flags, the manifest and the tool versions."""
    return _library_key(generated_sources(gen_dir, manifest, controllers, functions), manifest, cc_id)


def build_library(gen_dir: Path | None = None, cache: Path | None = None, log: Callable[[str], None] | None = None,
                  jobs: int | None = None, controllers: Iterable[str] | None = None) -> tuple[Path, bool]:
    """Compile the generated model of ``gen_dir`` (default: ``rpo.generated``) into the cache if needed;
    return (library path, compiled?): :func:`link_library` with the folder's manifest."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    return link_library(gen_dir, read_manifest(gen_dir), cache, log=log, jobs=jobs, controllers=controllers)


def link_library(gen_dir: Path, manifest: Manifest, cache: Path | None = None,
                 log: Callable[[str], None] | None = None, jobs: int | None = None,
                 controllers: Iterable[str] | None = None,
                 functions: Iterable[str] | None = None) -> tuple[Path, bool]:
    """Compile the generated model into the cache if needed; return (library path, compiled?).

    ``manifest``: the verified manifest of ``gen_dir`` the caller will use with the library.
    Objects missing from ``<cache>/obj`` are compiled in parallel (``jobs``, default every core),
    with a progress line per file through ``log``; then the library is linked from them.
    ``controllers``: only the plant and these controllers' functions (default: everything);
    ``functions``: only these functions' files (:func:`generated_sources`).
    """
    controllers = None if controllers is None else sorted(set(controllers))
    cc, cc_id = compiler_command()
    cache = cache_dir() if cache is None else Path(cache)
    try:
        (cache / "obj").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(f"cannot create the build cache {cache} ({exc.strerror}): set RPO_CACHE_DIR "
                         "to a writable folder") from exc
    sources = generated_sources(gen_dir, manifest, controllers, functions)
    objects = [(name, data, object_path(cache, name, data, cc_id)) for name, data in sources]
    lib = _library_path(cache, sources, manifest, cc_id)
    return _compile_and_link(cc, objects, lib, cache, log, jobs, None, "the generated model")


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
            futures = {pool.submit(compile_object, cc, name, src, obj, flags): name for name, src, obj in todo}
            order = list(futures)  # a pool's threads take the files in this order
            pending = set(futures)
            i = 0
            try:
                while pending:
                    # a line at least every HEARTBEAT_S: one large file takes longer than that on a slow core
                    finished, pending = wait(pending, timeout=HEARTBEAT_S, return_when=FIRST_COMPLETED)
                    for fut in finished:
                        i += 1
                        seconds = fut.result()
                        if log:
                            log(f"  [{i}/{len(todo)}] {futures[fut]} ({seconds:.1f} s, {len(todo) - i} left)")
                    if log and not finished and pending:
                        running = [futures[f] for f in order if f in pending][:n_jobs]
                        log(f"  ... compiling {', '.join(running)} ({len(pending)} left, "
                            f"{time.perf_counter() - t0:.0f} s so far)")
            except BaseException:  # an error or an interrupt: start no further file (the running ones end)
                pool.shutdown(wait=True, cancel_futures=True)
                raise
        run_cc([*cc, *LDFLAGS, "-o", str(tmp), *(str(obj) for _n, _s, obj in objects), "-lm"],
                f"linking {what}", cc)
        if log:
            log(f"linked {lib.name} from {len(objects)} objects ({time.perf_counter() - t0:.1f} s)")

    return lib, ensure_built(lib, build, what, log)


def lane_sources(gen_dir: Path, manifest: Manifest, controllers: Iterable[str] | None = None,
                 functions: Iterable[str] | None = None) -> tuple[list[tuple[str, bytes]], dict[str, str]]:
    """The lane forms (runtime/model/lanes.py) of the selected generated files whose every operation has
    one, and of the composed steps whose callees all have one; plus {file: why not} for the rest.
    ``functions``: only these functions' files, and lane stubs for the callees they leave out."""

    done: dict[str, tuple[bytes, list[str]]] = {}
    skipped: dict[str, str] = {}
    left_out: set[str] = set()
    for name, data in generated_sources(gen_dir, manifest, controllers, functions)[:-1]:  # the last: the driver
        if name == STUB_SOURCE:  # the scalar stubs: the lane stubs are made below
            continue
        try:
            text, called = lane_source(name, data.decode())
        except LaneError as exc:
            skipped[name] = str(exc)
            continue
        done[name] = (text.encode(), called)
    stem_to_file = {Path(n).stem: n for n in done}
    chosen = None if functions is None else set(functions)
    for name, (_text, called) in list(done.items()):
        missing = [c for c in called if c not in stem_to_file and (chosen is None or c in chosen)]
        if missing:
            skipped[name] = f"calls {', '.join(missing)}, which has no lane form"
            del done[name]
        elif chosen is not None:
            left_out.update(c for c in called if c not in chosen)
    out = [(f"{Path(n).stem}.lanes.c", text) for n, (text, _c) in sorted(done.items())]
    if left_out:
        out.append((f"{Path(STUB_SOURCE).stem}.lanes.c", stub_source(left_out, lanes=True)))
    out.append((LANE_LOOP_SOURCE, (csrc_dir() / LANE_LOOP_SOURCE).read_bytes()))
    return out, skipped


def build_lane_library(gen_dir: Path, manifest: Manifest, cache: Path | None = None,
                       log: Callable[[str], None] | None = None, jobs: int | None = None,
                       controllers: Iterable[str] | None = None,
                       functions: Iterable[str] | None = None) -> tuple[Path, bool, dict[str, str]]:
    """Compile the lane forms of the generated model (``manifest``: the verified manifest of ``gen_dir``)
    for this machine's vector width into the cache if needed; return (library path, compiled?,
    {file: why it has no lane form})."""
    controllers = None if controllers is None else sorted(set(controllers))
    cc, cc_id = compiler_command()
    cache = cache_dir() if cache is None else Path(cache)
    (cache / "obj").mkdir(parents=True, exist_ok=True)
    objects, lib, flags, skipped = lane_plan(gen_dir, manifest, controllers, cache, cc, cc_id, functions)
    path, compiled = _compile_and_link(cc, objects, lib, cache, log, jobs, flags, "the lane model")
    return path, compiled, skipped


def lane_plan(gen_dir: Path, manifest: Manifest, controllers: list[str] | None, cache: Path, cc: list[str], cc_id: str,
              functions: Iterable[str] | None = None):
    """(objects, library path, compile flags, skipped) of the lane library of a selection."""

    native, target_id = native_target(cc)
    flags = lane_flags(native)
    lane_id = f"{cc_id}\ntarget {target_id}\nlanes {LANES_VERSION}"
    sources, skipped = lane_sources(gen_dir, manifest, controllers, functions)
    keyflags = [*LANE_CFLAGS, *native]
    objects = [(n, d, cache / "obj" / f"{Path(n).stem}-{object_key(d, lane_id, keyflags)[:24]}.o") for n, d in sources]
    h = hashlib.sha256()
    for n, _d, obj in objects:
        h.update(n.encode() + b"\0" + obj.name.encode() + b"\0")
    h.update(json.dumps({"ldflags": LDFLAGS, "abi": RUNTIME_ABI, "manifest": manifest.manifest_hash},
                        sort_keys=True).encode())
    return objects, cache / f"rpo_lanes_{h.hexdigest()[:24]}.so", flags, skipped


def current_cache_files(gen_dir: Path | None = None, cache: Path | None = None) -> set[Path]:
    """The cache files the current generated/ uses: its objects, and its libraries for every
    selection a run makes (everything, or the plant and one controller)."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    cache = cache_dir() if cache is None else Path(cache)
    manifest = read_manifest(gen_dir)
    cc, cc_id = compiler_command()
    keep = set()
    for ctrls in [None, *([c] for c in sorted(manifest.controllers))]:
        sources = generated_sources(gen_dir, manifest, ctrls)
        keep |= {object_path(cache, n, d, cc_id) for n, d in sources}
        keep.add(_library_path(cache, sources, manifest, cc_id))
        objects, lib, _flags, _skipped = lane_plan(gen_dir, manifest, ctrls, cache, cc, cc_id)
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


def open_library(lib_path: Path, sources: Iterable[str]) -> ctypes.CDLL:
    """Load a linked library and check it: NaN detection, and 64-bit ``casadi_int`` in ``sources``."""
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
    return lib


class LaneLibrary:
    """The lane forms of the generated functions, loaded: ``width`` runs per call."""

    def __init__(self, path: Path, skipped: dict[str, str], manifest: Manifest):
        try:
            self.lib = ctypes.CDLL(str(path))
        except OSError as exc:
            raise ModelError(f"cannot load {path} ({exc}): delete it and run again to rebuild") from exc
        self.path = path
        self.skipped = skipped
        self.width = int(self.lib.rpo_lanes_width())
        self.pointers: dict[str, int] = {}
        self.work: dict[str, int] = {}
        for name, desc in manifest.functions.items():
            # (a stub of a left-out callee defines <name>_lanes but no <name>_lanes_work)
            if desc.source in skipped or not hasattr(self.lib, f"{name}_lanes_work"):
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
