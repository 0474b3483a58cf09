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
import warnings
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.functions import CasadiFunction, CompiledFunction, function_class
from rpo.runtime.model.library import build_lane_library, link_library
from rpo.runtime.model.manifest import Layout, Manifest, generated_dir, read_manifest, selected_sources


class Model:
    """The generated model: its typed manifest (:class:`~rpo.runtime.model.manifest.Manifest`), layouts and
    callable functions (compiled or CasADi)."""

    def __init__(self, manifest: Manifest, functions: dict, backend: str, library: Path | None = None,
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
            assert self._gen_dir is not None
            path, _compiled, skipped = build_lane_library(self._gen_dir, self.manifest, log=self._log,
                                                          controllers=self._controllers)
            self._lanes = LaneLibrary(path, skipped, self.manifest)
        return self._lanes

    def __getattr__(self, name):
        try:
            return self.__dict__["functions"][name]
        except KeyError:
            raise AttributeError(name) from None

    def function(self, name: str):
        """The loaded function ``name``; a clear error if the manifest has it but it was not loaded."""
        if name in self.functions:
            return self.functions[name]
        if name in self.manifest.functions:
            raise ModelError(f"{name} is not loaded: this model was loaded for some controllers only "
                             "(load_model(controllers=[...]))")
        raise ModelError(f"no generated function {name!r}")

    @property
    def layouts(self) -> Mapping[str, Layout]:
        return self.manifest.layouts

    def layout_size(self, name: str) -> int:
        return self.layouts[name].size

    def _pack(self, name: str) -> tuple[dict[str, tuple[int, int]], np.ndarray, list[str], int]:
        """The packing of a layout, made once (a campaign packs thousands of vectors)."""
        info = self._packing.get(name)
        if info is None:
            offs, i, missing = {}, 0, []
            for f in self.layouts[name]:
                offs[f.name] = (i, f.size)
                i += f.size
            base = np.zeros(i)
            for f in self.layouts[name]:
                a, n = offs[f.name]
                if f.default is not None and len(f.default) == n:
                    base[a:a + n] = np.array(f.default, float)
                elif f.default is not None:
                    self._bad_defaults.setdefault(name, []).append(f.name)
                else:
                    missing.append(f.name)
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
        """Column labels of a layout (a new list)."""
        return list(self.layouts[name].labels)

    def units(self, name: str) -> list[str]:
        """Column units of a layout (a new list)."""
        return list(self.layouts[name].units)

    def field_labels(self, *names: str) -> Mapping[str, tuple[str, ...]]:
        """Field -> its column labels over the layouts ``names`` (read-only, made once per selection:
        every run's result shares it)."""
        key = ("fields", *names)
        if key not in self._columns:
            self._columns[key] = MappingProxyType({f.name: f.labels for n in names for f in self.layouts[n]})
        return self._columns[key]

    def defaults(self, name: str) -> dict[str, np.ndarray]:
        """Default values of a layout by field name (new arrays, the caller may change them)."""
        return {f.name: np.array(f.default, float) for f in self.layouts[name] if f.default is not None}

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
                got = len(self.layouts[name].field(f).default or ())
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
            if desc.source in skipped or not hasattr(self.lib, f"{name}_lanes"):
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


def _load_compiled(gen_dir: Path, manifest: Manifest, log=None, controllers: Iterable[str] | None = None) -> Model:
    lib_path, _ = link_library(gen_dir, manifest, log=log, controllers=controllers)
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
    from rpo.runtime.model import fastcall

    cls = function_class(fastcall.load())
    funcs = {name: cls(lib, name, desc) for name, desc in manifest.functions.items() if desc.source in sources}
    return Model(manifest, funcs, "compiled", lib_path, lib, gen_dir=gen_dir, controllers=controllers, log=log)


def _load_casadi(gen_dir: Path, manifest: Manifest) -> Model:
    try:
        import casadi as ca
    except ImportError as exc:  # pragma: no cover
        raise ModelError("backend 'casadi' needs the casadi package (pip install casadi)") from exc
    funcs = {}
    for name, desc in manifest.functions.items():
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
