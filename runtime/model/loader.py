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
import sys
import warnings
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.cache import cache_dir, library_intact
from rpo.runtime.model.functions import CasadiFunction, function_class
from rpo.runtime.model.library import LaneLibrary, build_lane_library, lane_plan, link_library, open_library
from rpo.runtime.model.manifest import Layout, Manifest, generated_dir, read_manifest, selected_sources
from rpo.runtime.model.selection import needed_functions
from rpo.runtime.model.toolchain import compiler_command


class Model:
    """The generated model: its typed manifest (:class:`~rpo.runtime.model.manifest.Manifest`), layouts and
    callable functions (compiled or CasADi).

    The compiled backend compiles on first use, and only what is called: ``model.plant_rhs`` (or
    ``model.function("plant_rhs")``) links a library of that function's file; a closed-loop step
    asked for with its parameters (``model.function("step_c001", p=...)``, as a
    :class:`~rpo.runtime.run.simulate.Simulation` does) links only the specialised copies of the
    plant those parameters select (the others are stubs that return an error).  A later call that
    needs more links a larger library from the same cached objects; functions taken before stay
    valid (their library stays loaded).
    """

    def __init__(self, manifest: Manifest, functions: dict | None, backend: str, gen_dir: Path | None = None,
                 controllers: Iterable[str] | None = None, log: Callable[[str], None] | None = None):
        self.manifest = manifest
        self.backend = backend
        self._gen_dir = gen_dir
        self._controllers = None if controllers is None else sorted(set(controllers))
        self._log = log
        self._lanes: LaneLibrary | None = None
        self._lane_set: frozenset[str] = frozenset()
        #: the scalar library linked last, the functions it holds, its CDLL
        self.library: Path | None = None
        self._lib: ctypes.CDLL | None = None
        self._lib_set: frozenset[str] = frozenset()
        #: name -> (function, the functions of the library it was taken from)
        self._made: dict[str, tuple[Any, frozenset[str]]] = {}
        self._texts: dict[str, str] = {}
        self._selectable = ({d.name for d in manifest.functions.values()
                             if d.source in set(selected_sources(manifest, controllers))}
                            if functions is None else set(functions))
        self.functions: Mapping[str, Any] = _Functions(self)
        if functions is not None:  # the CasADi backend: every function made at once
            for name, f in functions.items():
                self._made[name] = (f, frozenset(functions))
        #: layout name -> (field -> (offset, size), packed defaults, fields without a default, size)
        self._packing: dict[str, tuple[dict[str, tuple[int, int]], np.ndarray, list[str], int]] = {}
        self._slices: dict[str, dict[str, slice]] = {}
        self._orders: dict[str, list[tuple[int, str, int]]] = {}
        self._columns: dict[tuple, Any] = {}
        self._bad_defaults: dict[str, list[str]] = {}
        #: (names, parameter rows) -> what they need: the callee graph is fixed, and parsing it costs a
        #: millisecond, a thousand times a compiled call (``model.plant_rhs(...)`` asks on every access)
        self._need_cache: dict[tuple, frozenset[str]] = {}

    # -- what a call needs, compiled on first use ----------------------------------------------

    def needs(self, names: Iterable[str], P: np.ndarray | None = None) -> frozenset[str]:
        """The functions a call of ``names`` may reach with the parameter rows ``P`` (None: any)."""
        names = list(names)
        for n in names:
            if n not in self._selectable:
                self.function(n)  # the error that says why
        P = None if P is None else np.atleast_2d(np.asarray(P, float))
        key = (tuple(names), None if P is None else (P.shape, P.tobytes()))
        need = self._need_cache.get(key)
        if need is None:
            texts = _SourceTexts(self)
            offsets = {} if P is None else self.offsets("p")
            need = self._need_cache[key] = frozenset(needed_functions(self.manifest, texts, names, P, offsets))
        return need

    def _ensure(self, need: frozenset[str]) -> None:
        """Link (or find in the cache) a library holding ``need`` and what is loaded already."""
        if need <= self._lib_set:
            return
        assert self._gen_dir is not None
        want = self._lib_set | need
        path, _ = link_library(self._gen_dir, self.manifest, log=self._log, controllers=self._controllers,
                               functions=want)
        self._lib = open_library(path, {self.manifest.functions[f].source for f in want - self._lib_set})
        self.library, self._lib_set = path, want

    def prepare(self, names: Iterable[str], p: np.ndarray | None = None) -> None:
        """Compile now, in one go, what calls of ``names`` with parameters ``p`` need (names this model
        does not hold are left out): a run asks for everything it will call before its first call."""
        if self.backend == "compiled":
            self._ensure(self.needs([n for n in names if n in self._selectable], p))

    def function(self, name: str, p: np.ndarray | None = None):
        """The function ``name``, compiled on first use; a clear error if it cannot be loaded.

        ``p``: the parameter vector (or rows of vectors) it will be called with: a closed-loop step
        then needs only the plant's copies those parameters select (see the class)."""
        if name not in self._selectable:
            if name in self.manifest.functions:
                raise ModelError(f"{name} is not loaded: this model was loaded for some controllers only "
                                 "(load_model(controllers=[...]))")
            raise ModelError(f"no generated function {name!r}")
        need = self.needs([name], p)
        made = self._made.get(name)
        if made is not None and need <= made[1]:
            return made[0]
        self._ensure(need)
        from rpo.runtime.model import fastcall

        f = function_class(fastcall.load())(self._lib, name, self.manifest.functions[name])
        f._model = self
        self._made[name] = (f, self._lib_set)
        return f

    def lanes(self, names: Iterable[str] | None = None, P: np.ndarray | None = None) -> LaneLibrary | None:
        """The lane library (K runs per call, K = this machine's vector width) holding the lane forms of
        ``names`` as called with the parameter rows ``P`` (default: every function of the model), built
        on first use (compiled backend only; None for the CasADi backend)."""
        if self.backend != "compiled":
            return None
        need = frozenset(self._selectable) if names is None else self.needs(names, P)
        if self._lanes is None or not need <= self._lane_set:
            assert self._gen_dir is not None
            want = need | self._lane_set
            fns = None if want == frozenset(self._selectable) else want
            path, _compiled, skipped = build_lane_library(self._gen_dir, self.manifest, log=self._log,
                                                          controllers=self._controllers, functions=fns)
            self._lanes = LaneLibrary(path, skipped, self.manifest)
            self._lane_set = want
        return self._lanes

    def lanes_ready(self, names: Iterable[str], P: np.ndarray | None = None) -> bool:
        """Whether :meth:`lanes` of ``names`` with ``P`` would load without compiling (loaded or cached)."""
        if self.backend != "compiled":
            return False
        need = self.needs(names, P)
        if self._lanes is not None and need <= self._lane_set:
            return True
        assert self._gen_dir is not None
        cc, cc_id = compiler_command()
        want = need | self._lane_set
        fns = None if want == frozenset(self._selectable) else want
        _objs, path, _flags, _skipped = lane_plan(self._gen_dir, self.manifest, self._controllers, cache_dir(), cc,
                                                  cc_id, fns)
        return library_intact(path)

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            return self.function(name)
        except ModelError:
            raise AttributeError(name) from None

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
        """The C loop driver ``rpo_run`` (compiled backend only; None before any library is linked)."""
        if self._lib is None:
            return None
        f = self._lib.rpo_run
        f.restype = ctypes.c_int
        return f


    def loop_noise(self, key: int, g0: int, n: int) -> np.ndarray | None:
        """The noise w of steps ``g0 .. g0 + n - 1`` exactly as the C loop draws it (``rpo_noise_fill``
        in the linked library, ``key`` = :func:`rpo.runtime.run.noise.key` of the seed), shape (n, nw);
        None for the CasADi backend (it draws NumPy's, equal only to rounding)."""
        if self.backend != "compiled":
            return None
        if self._lib is None:  # every library holds the loop (sim_loop.c): link the smallest function's
            self._ensure(self.needs([min(self._selectable, key=lambda f: self.manifest.functions[f].ops)]))
        assert self._lib is not None
        nw = self.layout_size("w")
        W = np.empty((n, nw))
        self._lib.rpo_noise_fill(ctypes.c_ulonglong(key), ctypes.c_longlong(g0), ctypes.c_longlong(n),
                                 ctypes.c_int(nw), W.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
        return W


class _Functions(Mapping):
    """``model.functions``: name -> function, each compiled on first access (:meth:`Model.function`)."""

    def __init__(self, model: Model):
        self._model = model

    def __getitem__(self, name: str):
        if name not in self._model._selectable:
            raise KeyError(name)
        return self._model.function(name)

    def __iter__(self):
        return iter(sorted(self._model._selectable))

    def __len__(self) -> int:
        return len(self._model._selectable)

    def __contains__(self, name: object) -> bool:
        return name in self._model._selectable


class _SourceTexts(dict):
    """source file -> its C text, read on first use (only composed steps are parsed for callees)."""

    def __init__(self, model: Model):
        super().__init__()
        self._model = model

    def __missing__(self, source: str) -> str:
        texts = self._model._texts
        if source not in texts:
            assert self._model._gen_dir is not None
            texts[source] = (self._model._gen_dir / source).read_text(encoding="utf-8")
        return texts[source]


def _load_compiled(gen_dir: Path, manifest: Manifest, log=None, controllers: Iterable[str] | None = None) -> Model:
    compiler_command()  # no compiler: the error that says what to install, now rather than at the first call
    return Model(manifest, None, "compiled", gen_dir=gen_dir, controllers=controllers, log=log)


def _load_casadi(gen_dir: Path, manifest: Manifest) -> Model:
    try:
        import casadi as ca
    except ImportError as exc:  # pragma: no cover
        raise ModelError("backend 'casadi' needs the casadi package (pip install casadi)") from exc
    funcs = {}
    for name, desc in manifest.functions.items():
        with gzip.open(gen_dir / f"{name}.casadi.gz", "rt") as fh:
            funcs[name] = CasadiFunction(ca.Function.deserialize(fh.read()), desc)
    return Model(manifest, funcs, "casadi", gen_dir=gen_dir)


def stderr_log(line: str) -> None:
    """The default progress log of a compile: one line to stderr, flushed at once."""
    print(line, file=sys.stderr, flush=True)


def load_model(backend: str = "auto", gen_dir: Path | None = None,
               log: Callable[[str], None] | None | bool = True,
               controllers: Iterable[str] | None = None) -> Model:
    """Load the model: ``"compiled"`` (C), ``"casadi"`` (VM fallback, warned) or ``"auto"``.

    ``auto`` means compiled; without a C compiler it raises a :class:`ModelError` that says
    what to install or how to choose the CasADi fallback explicitly (never a silent slowdown).
    ``controllers``: load only the plant and these controllers (what a run needs; the first run
    after an install then compiles a fraction of the model); default: every controller.
    Nothing is compiled here: each function is compiled on its first call (see :class:`Model`).
    ``log`` receives the compile progress (which file, how many left; a line at least every 4 s):
    True (default) prints it to stderr, False or None is silent.
    """
    log = stderr_log if log is True else (log or None)
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    manifest = read_manifest(gen_dir)
    if backend in ("auto", "compiled"):
        return _load_compiled(gen_dir, manifest, log, controllers)
    if backend == "casadi":
        warnings.warn("backend 'casadi': evaluating the model in CasADi's virtual machine, about 100x slower "
                      "than the compiled backend", RuntimeWarning, stacklevel=2)
        return _load_casadi(gen_dir, manifest)
    raise ModelError(f"backend must be one of auto, compiled, casadi; got {backend!r}")
