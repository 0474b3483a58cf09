"""Shared by the 000 claims: constants, the boundary layer as the paper types it, and C000.law with the default
switches."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c000 as c
from ...physics.layout import XYZ, XYZW, Layout
from ..domains import (
    MU_EARTH,
    custom,
)

MU = MU_EARTH
#: the paper's inertia matrices ("Simulation", all three scenarios) [kg m^2]
I_C_PAPER = np.array([[11.0, -0.09, -0.4], [-0.09, 14.0, -0.08], [-0.4, -0.08, 13.0]])
I_T_PAPER = np.array([[3336.0, -135.0, -154.0], [-135.0, 3184.0, -135.0], [-154.0, -135.0, 2423.0]])
AXES = ("x", "y", "z")
NPHI = (5, 3, 1)


def _printed_layer(s, d):
    """S_aug = s - d sign(s) as printed (eqs. 52, 84, 106, 119), read alone."""
    return s - d * sp.sign(s)


def _paper_layer(s, d):
    """The paper's S_aug: eq. 52 completed by the text after eq. 57 ("inside the boundary layer S_aug = 0"):
    0 for |s| <= d, s - d sign(s) outside (Slotine's s_Delta, typed piecewise as the paper states it)."""
    return sp.Piecewise((0, sp.Abs(s) <= d), (s - d * sp.sign(s), True))


def _real(names):
    return sp.symbols(names, real=True)


def _pos(names):
    return sp.symbols(names, positive=True)


def _s_then_edot(s_scale, e, lam, d, edot):
    """Draw e_dot so that s = e_dot + lambda e is uniform in +-(3 d + s_scale): inside and outside the layer."""
    def draw(z, env):
        s = z[:, 0] * (3.0 * env[d] + s_scale)
        return (s - env[lam] * env[e])[:, None]
    return custom([edot], 1, draw, f"e_dot = s - lambda e, |s| <= 3 d + {s_scale:g}")


def _sign_of(x):
    """sgn with sgn(0) = +1 (the code's Piecewise((-1, x < 0), (1, True)))."""
    return sp.Piecewise((-1, x < 0), (1, True))


# ----- the implementation's law on the spacecraft equations

class _Meas:
    """Measurement symbols of C000.law (the fields it reads)."""

    def __init__(self):
        m = Layout("meas")
        for n, size in (("q_e", 4), ("w_e", 3), ("w_c", 3), ("h_rw", 3), ("r", 3), ("v", 3), ("n", 1),
                        ("n_dot", 1), ("r_t", 1), ("q_cL", 4)):
            m.add(n, size, "-", n, XYZW if size == 4 else (XYZ if size == 3 else ()))
        self.m = m


def _law():
    """(ctrl, meas, tau, F_body, xc_dot, diag, sigma, mu) from C000.law with the default switches
    (shortest = adapt_a1 = acc_d_on = 1) and sgn(q_e4) -> sigma; q_cL stays a symbol (F is the body force)."""
    ctrl = c.C000()
    M = _Meas().m
    mu = sp.Symbol("mu", positive=True)
    cmd, xc_dot, diag = ctrl.law(M, sp.Symbol("t", real=True), {"mu": mu, "gravity_on": sp.Integer(1)})
    k = ctrl.k
    sig = sp.Symbol("sigma", real=True)
    rep = {k["shortest"]: 1, k["adapt_a1"]: 1, k["acc_d_on"]: 1}

    def fix(e):
        e = e.xreplace(rep)
        return e.replace(lambda x: isinstance(x, sp.Piecewise), lambda x: sig)

    off = c.command_layout().offsets()
    cmd = fix(cmd)
    tau = cmd[off["tau_w"][0]:off["tau_w"][1], 0]
    F = cmd[off["F"][0]:off["F"][1], 0]
    xo = ctrl.xc.offsets()
    xc_dot = fix(xc_dot)
    rates = {name: xc_dot[a:b, 0] for name, (a, b) in xo.items()}
    do = ctrl.diag.offsets()
    diag = fix(diag)
    dg = {name: diag[a:b, 0] for name, (a, b) in do.items() if name in ("s_att", "S_aug_att", "s_pos", "S_aug_pos")}
    return ctrl, M, tau, F, rates, dg, sig, mu
