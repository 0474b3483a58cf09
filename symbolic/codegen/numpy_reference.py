"""NumPy evaluation of the same SymPy model: the independent reference for tests and benchmarks.

The pieces are the SymPy expressions of :func:`rpo.symbolic.codegen.functions.sources` evaluated through
``sympy.lambdify`` (NumPy), and the step is the same :func:`rpo.symbolic.physics.closed_loop.step`
composition the C code is generated from.  Nothing here is retyped.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..physics import closed_loop as cl
from .to_casadi import numpy_function


def _vcat(*parts):
    return np.concatenate([np.atleast_1d(np.asarray(a, float)).ravel() for a in parts])


NUMPY_OPS = SimpleNamespace(
    vcat=_vcat,
    floor=np.floor,
    fmax=np.maximum,
    sqrt=np.sqrt,
    if_else=lambda c, a, b: a if c else b,
    zeros=lambda n: np.zeros(n),
)


def lambdified(piece: cl.Piece):
    """A NumPy callable taking flat arrays per input and returning a tuple of flat arrays."""
    syms = []
    for _name, a in piece.inputs:
        syms.append(list(a) if hasattr(a, "shape") else a)
    fn = numpy_function(syms, [e for _n, e in piece.outputs])

    def call(*args):
        flat = [list(np.ravel(np.asarray(a, float))) if hasattr(s, "__len__") else float(np.ravel(a)[0])
                for a, s in zip(args, syms, strict=True)]
        return tuple(np.ravel(np.asarray(o, float)) if np.ndim(o) else np.array([float(o)])
                     for o in fn(*flat))

    return call


def _pieces(pieces, make, names):
    make = make or (lambda name: lambdified(pieces[name]))
    return {name: make(name) for name in names}


def numpy_plant_advance(pieces: dict[str, cl.Piece], plant, make=None):
    """``plant_advance(zp, t, p, w, cmd) -> (zp_next, y_plant)`` evaluated with NumPy."""
    fn = _pieces(pieces, make, cl.PLANT_PIECES)
    idx = cl.step_indices(plant)

    def advance(zp, t, p, w, cmd):
        return cl.plant_advance(NUMPY_OPS, fn, idx, np.asarray(zp, float), float(t), np.asarray(p, float),
                                np.asarray(w, float), np.asarray(cmd, float))

    return advance


def numpy_control(pieces: dict[str, cl.Piece], plant, ctrl, make=None):
    """``control_<name>(meas, xc, t, p, k) -> (cmd, xc_next, diag)`` evaluated with NumPy."""
    law = _pieces(pieces, make, [f"law_{ctrl.name}"])[f"law_{ctrl.name}"]
    i_dt = plant.p.offsets()["dt"][0]

    def control(meas, xc, t, p, k):
        p = np.asarray(p, float)
        return cl.controller_update(NUMPY_OPS, law, np.asarray(meas, float), np.asarray(xc, float), float(t), p,
                                    np.asarray(k, float), p[i_dt], ctrl.xc.size)

    return control


def numpy_step(pieces: dict[str, cl.Piece], plant, ctrl, make=None):
    """``step(z, t, p, k, w) -> (z_next, y)`` evaluated with NumPy.

    ``make(name)`` may supply already-lambdified pieces (lambdify takes ~10 s per large piece).
    """
    fn = _pieces(pieces, make, (*cl.PLANT_PIECES, f"law_{ctrl.name}"))
    fn["law"] = fn.pop(f"law_{ctrl.name}")
    idx = cl.step_indices(plant, ctrl)

    def step(z, t, p, k, w):
        return cl.step(NUMPY_OPS, fn, idx, np.asarray(z, float), float(t), np.asarray(p, float),
                       np.asarray(k, float), np.asarray(w, float))

    return step
