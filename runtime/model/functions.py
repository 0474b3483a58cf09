"""Calling a compiled (or CasADi) function: argument checks against the manifest, the ctypes and fast-call
paths, batches."""

from __future__ import annotations

import ctypes
import math
from typing import Any, Protocol

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.manifest import FunctionSpec


class _LaneOwner(Protocol):
    """What a function needs of its model: the lane library (``Model.lanes``), without importing the loader."""

    def lanes(self, names: Any = None, P: Any = None) -> Any: ...

    def lanes_ready(self, names: Any, P: Any = None) -> bool: ...

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


_INT_P = ctypes.POINTER(ctypes.c_longlong)


#: (the library, function name) -> (the manifest entry it was checked against, its work sizes): a clone
#: (one per simulation: a campaign makes one per run) is not checked again
_CHECKED: dict[tuple[ctypes.CDLL, str], tuple[FunctionSpec, tuple[int, ...]]] = {}


class CompiledFunction:
    """A generated function called through ctypes with preallocated buffers.

    ``f(*inputs)`` returns fresh arrays shaped as in the manifest (a tuple, one per output);
    ``f(*inputs, out=arrays)`` writes into ``arrays`` (one array, or a tuple with one per output;
    float64, contiguous; a matrix output as a Fortran-ordered (rows, cols) array or flat) and
    returns them.  With the fast-call extension (:mod:`rpo.runtime.model.fastcall`) the inputs are read
    in place and the same arrays passed again cost nothing to check.  ``f.batch(...)`` evaluates
    many points in one C call.  Not thread-safe: use one instance per thread (``clone()``).
    """

    _model: _LaneOwner | None = None     # the Model that owns this function (its lane library)

    def __init__(self, lib: ctypes.CDLL, name: str, desc: FunctionSpec):
        self.name = name
        self.desc = desc
        self._lib = lib
        self.c_function = getattr(lib, name)
        checked = _CHECKED.get((lib, name))
        if checked is None or (checked[0] is not desc and checked[0] != desc):
            self.c_function.restype = ctypes.c_int
            self.c_function.argtypes = [ctypes.POINTER(_DOUBLE_P), ctypes.POINTER(_DOUBLE_P), _INT_P, _DOUBLE_P,
                                        ctypes.c_int]
            self._check_signature()
            sz = [ctypes.c_longlong() for _ in range(4)]
            getattr(lib, f"{name}_work")(*[ctypes.byref(s) for s in sz])
            checked = _CHECKED[(lib, name)] = (desc, tuple(s.value for s in sz))
        # a clone (another instance of a function already checked against this manifest entry):
        # the same library, the same signature and work sizes
        self.sz_arg, self.sz_res, self.sz_iw, self.sz_w = checked[1]
        self.in_names = [i.name for i in desc.inputs]
        self.out_names = [o.name for o in desc.outputs]
        self.in_shapes = [i.shape for i in desc.inputs]
        self.out_shapes = [o.shape for o in desc.outputs]
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
        if lib[f"{name}_n_in"]() != len(desc.inputs) or lib[f"{name}_n_out"]() != len(desc.outputs):
            raise ModelError(f"{name}: the compiled library does not match manifest.json (input/output count)")
        for kind, items in (("in", desc.inputs), ("out", desc.outputs)):
            for i, item in enumerate(items):
                sp = getattr(lib, f"{name}_sparsity_{kind}")(i)
                nrow, ncol, dense = sp[0], sp[1], sp[2]
                if (nrow, ncol) != item.shape or dense != 1:
                    raise ModelError(f"{name}: {kind}put {item.name} is {nrow}x{ncol} (dense={dense}) in the "
                                     f"library but {list(item.shape)} in manifest.json: run `python build.py`")

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
        owner, P = self._model, _rows(ins, self.in_names, self.in_sizes)
        # the lane form when it is built, or worth building: compiling it takes seconds, which a small
        # batch would not win back (the scalar loop gives the same bits)
        want = owner is not None and (N >= BATCH_LANES_MIN_POINTS or owner.lanes_ready([self.name], P))
        lanes = owner.lanes([self.name], P) if want and owner is not None else None
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


#: Points from which a batch compiles the lane form of its function when it is not built yet (the
#: lane form of a large function compiles in seconds; at about 1 us per point, 2e5 points win that
#: back); ``rpo build --lanes`` builds every lane form ahead.
BATCH_LANES_MIN_POINTS = 200_000


def _rows(ins: list[np.ndarray], names: list[str], sizes: list[int]) -> np.ndarray | None:
    """The parameter vectors (input ``p``) of a batch's points, one row each; None without a ``p``."""
    if "p" not in names:
        return None
    i = names.index("p")
    return np.asarray(ins[i]).reshape(-1, sizes[i])


#: the fast-call extension module -> its CompiledFunction class
_FAST_CLASS: dict[Any, type] = {}


def function_class(ext) -> type:
    """CompiledFunction with its single call done by the fast-call extension's ``Caller``."""
    if ext is None:
        return CompiledFunction
    if ext not in _FAST_CLASS:
        class FastCompiledFunction(ext.Caller, CompiledFunction):  # type: ignore[misc, name-defined]
            __doc__ = CompiledFunction.__doc__

            def __init__(self, lib: ctypes.CDLL, name: str, desc: FunctionSpec):
                CompiledFunction.__init__(self, lib, name, desc)
                ext.Caller.__init__(
                    self, ctypes.cast(self.c_function, ctypes.c_void_p).value, self.in_sizes, self.out_sizes,
                    [s[1] > 1 for s in self.out_shapes], self.iw.ctypes.data, self.work.ctypes.data,
                    tuple(self.outputs), self._py_call, self._finish)

        ext.enable_vectorcall(FastCompiledFunction)
        _FAST_CLASS[ext] = FastCompiledFunction
    return _FAST_CLASS[ext]


class CasadiFunction:
    """Fallback with the same call interface, evaluated by CasADi's virtual machine."""

    def __init__(self, fn, desc: FunctionSpec):
        self.name = fn.name()
        self.desc = desc
        self.fn = fn
        self.out_shapes = [o.shape for o in desc.outputs]

    def __call__(self, *args):
        res = self.fn(*[np.asarray(a, float).reshape(-1, 1, order="F") for a in args])
        res = res if isinstance(res, (list, tuple)) else [res]
        return tuple(np.asarray(r.full()).reshape(s, order="F") if s[1] > 1 else np.asarray(r.full()).ravel()
                     for r, s in zip(res, self.out_shapes, strict=True))

    def clone(self) -> CasadiFunction:
        return self
