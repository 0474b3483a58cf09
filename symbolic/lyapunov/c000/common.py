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
from ..units import declare, layout_units

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


# ----- units of the domain symbols (the report prints them with each search domain; ..units)

#: the translation parameters theta (abstract axes: x, y, z) and their regressors phi (eqs. 81-83, 105, 121);
#: the estimates theta_hat = m_c theta have the controller's units (c.TRANSLATION_UNITS)
_THETA_UNITS = (("1/s", "1/s^2", "1/s^2", "1/s^2", "m^3/s^2"), ("1/s", "1/s^2", "1/s^2"), ("1/s^2",))
_PHI_UNITS = (("m/s", "m", "m", "m", "1/m^2"), ("m/s", "m", "m"), ("m",))
#: Table 1's a_ji, f_ji (i = 1..6) and the estimates a_hat_ji = a_ji / b_j (c.table1_attitude_axis)
_A_UNITS = ("1", "1", "1/(kg m^2)", "1", "1", "1")
_F_UNITS = ("rad/s^2", "rad^2/s^2", "N m", "rad^2/s^2", "rad^2/s^2", "rad^2/s^2")
_AHAT_UNITS = ("kg m^2", "kg m^2", "1", "kg m^2", "kg m^2", "kg m^2")


def _per_axis() -> dict:
    out = {}
    for j, ax in enumerate(AXES):
        names, est = c.TRANSLATION_PARAMS[j], c.TRANSLATION_UNITS[j]
        for i, (th, ph, e) in enumerate(zip(_THETA_UNITS[j], _PHI_UNITS[j], est, strict=True)):
            out |= {f"theta_{ax}{i + 1}": th, f"phi_{ax}{i + 1}": ph, f"thetahat_{ax}{i + 1}": e,
                    f"thetatilde_{ax}{i + 1}": e}
            out[f"theta_{ax}{ax}" if len(names) == 1 else f"theta_{ax}{ax}_{names[i]}"] = e
        for i in range(6):
            out[f"a_hat_{ax}_{i + 1}"] = _AHAT_UNITS[i]
    for i in range(6):
        out |= {f"a_{i + 1}": _A_UNITS[i], f"f_{i + 1}": _F_UNITS[i], f"ahat_{i + 1}": _AHAT_UNITS[i],
                f"atilde_{i + 1}": _AHAT_UNITS[i]}
    return out


_ATT, _TR, _BL = "attitude", "translation", "boundary layer"
_DESIGN = c.C000()

UNITS = declare(layout_units(_DESIGN.k, _DESIGN.xc), {
    **_per_axis(),
    # ---- the abstract per-axis forms (eq. 48: rad/s^2; eqs. 81, 105, 30-z: m/s^2); the boundary-layer lemma
    # and the convergence conclusion hold for either surface
    "e": {_ATT: "rad", _TR: "m", _BL: "rad (attitude) or m (translation)"},
    "edot": {_ATT: "rad/s", _TR: "m/s"},
    "s": "rad/s (attitude) or m/s (translation)",
    "S_aug": {_ATT: "rad/s", _TR: "m/s"},
    "d": {_ATT: "rad/s", _TR: "m/s", _BL: "rad/s (attitude) or m/s (translation)"},
    "D": {_ATT: "rad/s^2", _TR: "m/s^2"},
    "epsilon": {_ATT: "rad/s^2", _TR: "m/s^2"},
    "acc_d": {_ATT: "rad/s^2", _TR: "m/s^2"},
    "dist": "rad/s^2", "a_d": "m/s^2", "A_dx": "m/s^2", "D_margin": "m/s^2", "g_c": "m/s^2",
    "lambda_0": "1/s",
    "b": {_ATT: "1/(kg m^2)", _TR: "1/kg"},
    "bhat": "kg m^2", "btilde": "kg m^2", "hhat": "kg", "htilde": "kg",
    # adaptation gains: the units that make b/gamma (estimate error)^2 an S_aug^2 (the layout says "-": one gain
    # scales estimates of different units, erratum 9 of docs/controllers/c000.md)
    "gamma_a": "kg m^2 s^2 (a_hat_3: s^2/(kg m^2))",
    "gamma_b": "kg m^2 s^2",
    "gamma_theta": "kg/(m^2 s^2) (the 2n estimates: kg/m^2; mu's: kg m^4/s^2)",
    "gamma_h": "kg s^2/m^2",
    "kappa": "SI numbers (eq. 72's sum adds S_aug^2 in rad^2/s^2 and parameter errors in (kg m^2)^2)",
    # ---- attitude, spacecraft layer
    "q": "1", "q_e": "1", "q_cL": "1", "sigma": "1",
    "z_d": "1", "z_ad": "1",                    # the draws' normalised coordinates (d_j = D_j z_j - ...)
    "omega_c": "rad/s", "omega_e": "rad/s", "omega_t": "rad/s", "w_c": "rad/s", "w_e": "rad/s",
    "omegadot_e": "rad/s^2",
    "I_c": "kg m^2", "I_t": "kg m^2", "Idot_c": "kg m^2/s",
    "h_rw": "N m s", "T_c": "N m", "M_c": "N m", "M_t": "N m", "M_rc": "N m", "M_rt": "N m",
    "phi_c": "rad", "theta_c": "rad", "phi_t": "rad", "theta_t": "rad", "r_0": "m",
    # ---- translation, spacecraft layer (LVLH)
    "x": "m", "y": "m", "z": "m", "xdot": "m/s", "ydot": "m/s", "zdot": "m/s", "r": "m", "v": "m/s",
    "a_c": "m/s^2", "r_t": "m", "r_t_dot": "m/s", "n": "rad/s", "n_dot": "rad/s^2", "n_ddot": "rad/s^3",
    "mu": "m^3/s^2", "m_c": "kg", "m_c_dot": "kg/s",
})
