"""Shared by the 001 claims: the paper's data (sec. 7, read from C001's defaults) and the pose samplers (unit
dual quaternions, admissible poses)."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ...controllers import c001 as c
from ...physics.special import Step
from ..domains import (
    custom,
    qmul,
    rotate,
    unit_rows,
)
from ..units import declare, layout_units

# --------------------------------------------------------------------------- the paper's data (sec. 7)
# read from C001's gain defaults (the values rpo flies), not typed again
_KDEF = {f.name: (f.default if f.size > 1 else f.default[0]) for f in c.C001().k.fields}
K_P, K_D, K_A, K_R = (_KDEF[n] for n in ("k_p", "k_d", "k_a", "k_r"))
MASS, INERTIA = _KDEF["m"], _KDEF["M"]
R_S, R_T, THETA, Z_N = (_KDEF[n] for n in ("R_S", "R_T", "theta", "z_N"))
Z_NP = Z_N + R_T / math.sin(THETA)               # eq. 40
Q_D = _KDEF["q_D"]                                # q_D/T, scalar last (sign reconstructed, doc c001)
R_D = _KDEF["r_D"]
KAPPA1, KAPPA2, DELTA = _KDEF["kappa1"], _KDEF["kappa2"], _KDEF["delta"]
ESO_GAINS = {   # (k1, k2) of the angular channels; the printed exponents lost their minus (doc c001)
    "reconstructed": (_KDEF["K1"][0], _KDEF["K2"][0]),     # rpo's defaults
    "printed": (1.0e4, 1.6e9),                             # the paper's print, as printed
}
FOV_EPS = _KDEF["fov_eps"]                        # rpo's regularisation of eq. 55
F_MAX, TAU_MAX = _KDEF["F_max"], _KDEF["tau_max"]  # sec. 7 actuator limits
MU, SEMI_MAJOR, ECC = 3.986004418e14, 6878136.6, 0.01454   # Table 1 (scenarios/001_scenario.toml)
TAU_SIN, TAU_COS = (7.2e-4, 0.0, 9.5e-4), (7.2e-4, 8.1e-4, 0.0)  # eq. 67, N m
RHO_MIN, RHO_MAX = 3.7, 300.0    # range of the admissible poses drawn (> R_S + R_T; initial 275 m)

VEC = (0, 1, 2, 4, 5, 6)         # vector slots of a pure dual quaternion (rpo storage)
ZERO8 = sp.zeros(8, 1)


def _pv(name: str) -> tuple[sp.Matrix, sp.Matrix]:
    """Pure dual vector ``(0, a) + eps (0, b)`` from six real symbols ``name_1..6`` (a = 1..3)."""
    s = sp.Matrix(sp.symbols(f"{name}_1:7", real=True))
    return c.pure_dq(s[0:3, :], s[3:6, :]), s


def _six(d: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([d[i] for i in VEC])


def _nostep(e):
    """``Step -> 1``: valid where its argument is positive (``max(s, 0) = s`` off the camera axis)."""
    return e.replace(Step, lambda a: sp.S.One)


# --------------------------------------------------------------------------- numeric helpers (domains)

def _dq_rows(qr: np.ndarray, r_T: np.ndarray) -> np.ndarray:
    """Unit dual quaternion ``q + eps r^T q / 2`` (eq. 13) as rows of 8."""
    return np.hstack([qr, qmul(np.hstack([r_T, np.zeros((len(r_T), 1))]), qr) / 2])


def _unit_dq_var(q: sp.Matrix, r_max: float = RHO_MAX):
    """Any pose: unit quaternion q_S/T and |r^T_i| <= r_max."""
    def draw(z, env):
        return _dq_rows(unit_rows(z[:, :4]), r_max * z[:, 4:7])
    return custom(list(q), 7, draw, f"unit dual quaternion, |r_i| <= {r_max:g} m")


def _admissible_draw(frac_min: float = 1e-3, frac_max: float = 1.0 - 1e-9, rho_min: float | None = None,
                     rho_max: float | None = None):
    """Admissible poses: any attitude; the target centre (at -r^S) inside the FOV cone (beta_FOV > 0,
    eq. 41) at a distance in [RHO_MIN, RHO_MAX] (beta_CA > 0, eq. 47).  The off-axis angle is the fraction
    [frac_min, frac_max] of the largest admissible one (frac -> 1: the FOV boundary)."""
    def draw(z, env):
        qr = unit_rows(z[:, :4])
        lo, hi = (RHO_MIN if rho_min is None else rho_min), (RHO_MAX if rho_max is None else rho_max)
        rho = lo + (z[:, 4] + 1.0) * 0.5 * (hi - lo)
        # rho (cos a - cot sin a) > z_N'  <=>  a < arccos(z_N' sin(theta) / rho) - (pi/2 - theta)
        a_max = np.arccos(np.minimum(Z_NP * math.sin(THETA) / rho, 1.0)) - (math.pi / 2 - THETA)
        a = a_max * (frac_min + (frac_max - frac_min) * (z[:, 5] + 1.0) * 0.5)
        ph = math.pi * z[:, 6]
        p = rho[:, None] * np.stack([np.sin(a) * np.cos(ph), np.sin(a) * np.sin(ph), np.cos(a)], 1)
        return _dq_rows(qr, rotate(qr, -p))
    return draw


def _admissible_var(q: sp.Matrix, frac_min: float = 1e-3, frac_max: float = 1.0 - 1e-9,
                    rho_min: float = RHO_MIN, rho_max: float = RHO_MAX):
    return custom(list(q), 7, _admissible_draw(frac_min, frac_max, rho_min, rho_max),
                  f"admissible pose: beta_FOV > 0, beta_CA > 0, {rho_min:g} <= |r| <= {rho_max:g} m, "
                  f"off the camera axis by {frac_min:g}..{frac_max:g} of the cone")


def _desired_dq() -> np.ndarray:
    return _dq_rows(np.array([Q_D]), rotate(np.array([Q_D]), np.zeros((1, 3))) + np.array([R_D]))[0]


P1, P2, APF = "ESO (Prop. 1)", "pose law (Prop. 2)", "APF (Prop. 2)"

MODEL, CONS = "model (eqs. 12-20)", "constraints (eqs. 42-48)"


def _paper_apf(q: sp.Matrix, on_axis: bool = False):
    """V_p of eq. 53 with rpo's gradient, built by ``c.apf_terms`` (as ``C001.law``) with the paper's k_a, k_r,
    geometry and desired pose.

    ``on_axis``: keep eq. 46's ``max(s, 0)`` (as a Heaviside, for numbers on the camera axis); otherwise
    ``Step -> 1`` (differentiable off the axis)."""
    unstep = (lambda e: e.replace(Step, lambda a: sp.Heaviside(a, 1))) if on_axis else _nostep
    a = c.apf_terms(q, sp.Matrix(Q_D), sp.Matrix(R_D), K_A, K_R, sp.Float(THETA), sp.Float(Z_N), sp.Float(R_S),
                    sp.Float(R_T), FOV_EPS)
    return unstep(a["V_p"]), a["dq_err"], unstep(a["grad"])


# --------------------------------------------------------------------------- units of the domain symbols
# (the report prints them with each search domain; ..units).  Channel convention of the dual vectors (rpo storage,
# ``_pv``): components 1-3 are the real part, 4-6 the dual part: angular then linear for a velocity or an
# acceleration (omega + eps v), force then torque for a dual force (F + eps tau).  A dual quaternion's entries 1-4
# are the real (rotation) part, 5-8 the dual part r q / 2 (m).  The ESO's channels follow the same numbering (a
# statement over fewer channels, e.g. eso.V1dot_bound's two, takes the first ones: angular).


def _channels(name: str, first: str, second: str) -> dict:
    return {f"{name}_{i}": first if i <= 3 else second for i in range(1, 7)}


def _dual_quaternion(name: str, real: str = "1", dual: str = "m") -> dict:
    return {f"{name}_{i}": real if i <= 4 else dual for i in range(1, 9)}


def _either(angular: str, linear: str) -> str:
    """A scalar of the ESO or of V that serves both kinds of channel."""
    return f"{angular} or {linear} (angular or linear channels)"


_ACC = ("rad/s^2", "m/s^2")
_DESIGN = c.C001()

UNITS = declare(layout_units(_DESIGN.k, _DESIGN.xc), {
    # ---- poses (eqs. 6-7, 13, 49-51) and their constraints (eqs. 40-48)
    **_dual_quaternion("q"), **_dual_quaternion("qS"), **_dual_quaternion("qT"), **_dual_quaternion("qD"),
    **_dual_quaternion("Deltaq"),
    "Q": "1", "v": "1",          # a unit quaternion; a unit 8-vector (a direction of q, eq. 53's convexity)
    "beta_FOV": "m", "beta_CA": "m^2",
    **_dual_quaternion("gFOV", "m", "1"), **_dual_quaternion("gCA", "m^2", "m"),   # gradients in q (eq. 55)
    "epsilon": "m",                                                                # rpo's fov_eps
    # V_p (eq. 53) is a number: k_a and k_r weigh Delta q o Delta q, which adds the rotation part (1) and the
    # position part (m^2), and eq. 52 divides it by beta_FOV (m) and beta_CA (m^2): SI numbers, as the layout's
    # note on k_r says
    "k_a": "SI numbers (eq. 51 adds 1 and m^2 parts of Delta q o Delta q)",
    "k_r": "SI numbers (eq. 52: Delta q o Delta q over beta_FOV in m and beta_CA in m^2)",
    **_dual_quaternion("g", "1", "1/m"),                                           # grad V_p in q
    # ---- the pose law (eqs. 57-64): V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V_d in J
    **_channels("omega", "rad/s", "m/s"), **_channels("omegaSI", "rad/s", "m/s"),
    **_channels("omegaTI", "rad/s", "m/s"), **_channels("omegahat", "rad/s", "m/s"),
    **_channels("omegadotTI", *_ACC), **_channels("dhat", *_ACC), **_channels("Deltad", *_ACC),
    **_channels("fG", "N", "N m"), **_channels("fC", "N", "N m"), **_channels("fD", "N", "N m"),
    "M": "kg m^2",
    "k_p": "N m",                                       # k_p V_p is an energy, the torque k_p [V_p]
    "k_d": "N s/m or N m s (force or torque channels)",   # the layout's doc: N s/m and N m s
    # V_d := V1 of Prop. 1 (the corrected chain), in (rad/s^2)^2 or (m/s^2)^2 per channel; k_v V_d in J
    "V_d": _either("rad^2/s^4", "m^2/s^4"), "Vdot_d": _either("rad^2/s^5", "m^2/s^5"),
    "k_v": _either("kg m^2 s^2", "kg s^2"),
    # D of the printed V_d = Dd^T D Dd: the rate of eq. 64's V_d-dot <= -D |Delta d|^2 (corrected D =
    # 2 chi kappa2 lambda_min(P)/delta)
    **{f"D_{i}": "1/s" for i in range(1, 7)},
    # ---- the ESO (eqs. 21-39): channel i of the dual velocity; the scaled time t/delta of eq. 27
    **_channels("a", *_ACC), **_channels("d", *_ACC), **_channels("alpha", "rad/s^3", "m/s^3"),
    **_channels("eta1", *_ACC), **_channels("eta2", *_ACC), **_channels("Theta", *_ACC),
    **_channels("y", "(rad/s^2)^(1/2)", "(m/s^2)^(1/2)"),           # y = |eta1|^(1/2)
    "eta1": _either(*_ACC), "eta2": _either(*_ACC), "y": _either("(rad/s^2)^(1/2)", "(m/s^2)^(1/2)"),
    "k1": "1", "k2": "1", "k1_v": "1", "k2_v": "1",     # K1, K2 (eq. 23): k1_1..6, k1_w, k1_v (the layout's "-")
    "kappa_1": _either("(rad/s^2)^(1/2)", "(m/s^2)^(1/2)"),   # Theta = kappa1 sig^(1/2)(eta1) + kappa2 eta1
    "kappa_2": "1",
    "Q11": "1", "Q12": "1", "Q22": "1",                 # Q_i, P_i (eq. 32): V1 in the channel's (unit/s^2)^2
    "C": _either("rad/s^3", "m/s^3"),                    # the bound on |alpha|
    "Y": _either(*_ACC), "y_0": _either(*_ACC),           # V1^(1/2) (eqs. 37-39)
    "a": _either(*_ACC),                                 # gamma kappa1^2 - delta sigma (eq. 37)
    "b": "1",                                            # chi kappa2 (scaled time)
    "t": "1",                                            # the scaled time of eq. 27
    "nu": "rad",
    # ---- the model (eqs. 12-20) and rpo's plant
    "F": "N", "tau": "N m", "V": "m/s", "VS": "m/s", "VT": "m/s", "r": "m", "rS": "m", "rT": "m",
    "omegaS": "rad/s", "omegaT": "rad/s",
})
