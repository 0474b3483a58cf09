"""004, the relative model (section 2.2, eqs. 9-20): do the rigid bodies have the form the proof uses?"""

from __future__ import annotations

import sympy as sp

from ...controllers import c004 as c
from ..core import (
    Statement,
    claim_factory,
    statement,
    symbols_vec,
)
from ..domains import (
    ball,
    box,
)
from .attitude import _Attitude
from .common import _printed_R, _s_dot
from .position import _Position

claim = claim_factory(__name__)

# --------------------------------------------------------------------------- relative model (section 2.2)

def _orthogonal(printed: bool):
    def build() -> Statement:
        """Eq. 9 is a rotation matrix: R^T R a = a for every a, and det R = 1 (the proof uses R^-1 = R^T,
        ||R|| = 1).  (R^T R a = a on a box of a is R^T R = I without zero entries, which a relative
        tolerance cannot judge.)"""
        sig, a = symbols_vec("sigma_e"), symbols_vec("a")
        R = _printed_R(sig) if printed else c.rotation_matrix(sig)
        lhs = sp.Matrix([*(R.T * (R * a)), R.det()])
        rhs = sp.Matrix([*a, 1])
        return Statement(lhs, "==", rhs, [box(sig, -1.5, 1.5), box(a, 1, 2)])
    return build


def _R_dot(printed: bool):
    def build() -> Statement:
        """Eq. 9 along eq. 14 (sigma_e-dot = G(sigma_e) w_e): R-dot = -S(w_e) R, used to derive eqs. 13-16."""
        sig, we = symbols_vec("sigma_e"), symbols_vec("omega_e")
        R = _printed_R(sig) if printed else c.rotation_matrix(sig)
        sd = c.mrp_kinematics(sig, we)
        Rdot = sum((sp.diff(R, s) * d for s, d in zip(sig, sd, strict=True)), sp.zeros(3, 3))
        return Statement(Rdot, "==", -c.S(we) * R, [box(sig, -1.5, 1.5), box(we, -0.1, 0.1)])
    return build


def _rotation(sig):
    """R(sigma_e) of the code (eq. 9, corrected) over its common denominator (the same matrix; the
    symbolic proofs of eqs. 13, 17 are 10x faster in this form)."""
    return c.rotation_matrix(sig).applyfunc(sp.together)


def _eq13() -> Statement:
    """Eq. 13 from eqs. 1, 5, 11, 12, R(sigma_e) of eq. 9 and eq. 14: d/dt (r - R r_pt) = v_e - S(w) r_e."""
    r, v, r_t, v_t = symbols_vec("r"), symbols_vec("v"), symbols_vec("r_t"), symbols_vec("v_t")
    w_t, we, p_t, sig = symbols_vec("omega_t"), symbols_vec("omega_e"), symbols_vec("p_t"), symbols_vec("sigma_e")
    R = _rotation(sig)
    w = we + R * w_t                                       # eq. 12: w_e = w - R w_t
    r_pt, v_pt = c.docking_point(r_t, v_t, w_t, p_t)       # eq. 11
    r_e, v_e, _ = c.relative_state(r, v, w, R, r_pt, v_pt, w_t)
    r_e_dot = _s_dot(r_e, [r, r_t, sig], [c.position_kinematics(r, v, w),          # eq. 1
                                           c.position_kinematics(r_t, v_t, w_t),    # eq. 5
                                           c.mrp_kinematics(sig, we)])              # eq. 14
    dom = [box(r, -40, 40), box(r_t, -40, 40), box(v, -2, 2), box(v_t, -2, 2), box(w_t, -0.1, 0.1),
           box(we, -0.1, 0.1), box(p_t, -6, 6), ball(sig, 1.0)]
    return Statement(r_e_dot.applyfunc(sp.together), "==", c.position_kinematics(r_e, v_e, w), dom,
                     assumptions=["R = R(sigma_e) as corrected in eq. 9"])


def _eq17() -> Statement:
    """Eq. 17: R v_pt-dot (eqs. 7, 11) = -S(w - w_e)[v - v_e - S(w - w_e) R p_t] - R S(p_t) w_t-dot,
    with v = v_e + R v_pt, w = w_e + R w_t (eq. 12); uses R S(a) = S(R a) R."""
    v_t, w_t, p_t, v_e = symbols_vec("v_t"), symbols_vec("omega_t"), symbols_vec("p_t"), symbols_vec("v_e")
    we, wtd, sig = symbols_vec("omega_e"), symbols_vec("omegadot_t"), symbols_vec("sigma_e")
    m_t = sp.Symbol("m_t", positive=True)
    R = _rotation(sig)
    zero = sp.zeros(3, 1)
    _, v_pt = c.docking_point(zero, v_t, w_t, p_t)
    v_pt_dot = _s_dot(v_pt, [v_t, w_t], [c.translational_dynamics(m_t, v_t, w_t, zero, zero), wtd])  # eq. 7
    v, w = v_e + R * v_pt, we + R * w_t
    rhs = c.docking_point_acceleration(R, v, v_e, w, we, p_t, wtd)
    dom = [box(v_t, -2, 2), box(w_t, -0.1, 0.1), box(p_t, -6, 6), box(v_e, -2, 2), box(we, -0.1, 0.1),
           box(wtd, -0.01, 0.01), ball(sig, 1.0), box(m_t, 100, 5000)]
    return Statement(R * v_pt_dot, "==", rhs, dom, assumptions=["R = R(sigma_e) as corrected in eq. 9"])


def _eq19() -> Statement:
    """Eq. 19 from eqs. 15, 17, 18, in two rows: eq. 15 with eq. 17 (w_t-dot = u, any) is eq. 19 with
    n1 = -R S(p_t) u (the v terms cancel, g appears), and -R S(p_t) w_t-dot of eq. 18 is the printed n1.
    (Split so that the symbolic proof does not expand the J_t chain of eq. 18 into eq. 15.)"""
    P = _Position(opaque=True, law=False)
    v, f, u = symbols_vec("v"), P.f, symbols_vec("omegadot_t")
    Rvpt = c.docking_point_acceleration(P.R, v, P.v_e, P.omega, P.omega_e, P.p_t, u)        # eq. 17
    eq15 = c.relative_velocity_rate_coupled(P.m, v, P.v_e, P.omega, P.omega_e, Rvpt, f, P.d_f)
    eq19 = c.relative_velocity_rate(P.m, P.g, -P.R * c.S(P.p_t) * u, f, P.d_f)
    wtd = c.target_angular_acceleration(P.Jt, P.R, P.omega, P.omega_e)                      # eq. 18
    n1 = c.coupling_n1(P.R, P.p_t, P.Jt, P.omega, P.omega_e)
    dom = P.domain() + [box(v, -2, 2), box(u, -0.01, 0.01)]
    return statement(sp.Matrix([eq15, -P.R * c.S(P.p_t) * wtd]), "==", sp.Matrix([eq19, n1]), dom,
                     assumptions=["any R, any J_t^-1 (no orthogonality needed)"])


def _eq20() -> Statement:
    """Eq. 20 from eqs. 16, 18, in two rows as for eq. 19: eq. 16 with w_t-dot = u is eq. 20 with
    n2 = -R u, and -R w_t-dot of eq. 18 is the printed n2."""
    A = _Attitude(opaque=True, law=False, adapt=False, exact_inverse=False)
    u = symbols_vec("omegadot_t")
    eq16 = c.relative_rate_rate_coupled(A.J, A.omega, A.omega_e, A.R, u, A.tau, A.d_tau)
    eq20 = c.relative_rate_rate(A.J, A.omega, A.omega_e, -A.R * u, A.tau, A.d_tau)
    wtd = c.target_angular_acceleration(A.Jt, A.R, A.omega, A.omega_e)                      # eq. 18
    n2 = c.coupling_n2(A.R, A.Jt, A.omega, A.omega_e)
    dom = A.domain() + [box(u, -0.01, 0.01)]
    return statement(sp.Matrix([eq16, -A.R * wtd]), "==", sp.Matrix([eq20, n2]), dom,
                     assumptions=["any R, any J^-1, J_t^-1 (no orthogonality needed)"])
_R_NOTE = ("Printed eq. 9 has + 8/(1+s^2)^2 S^T S; S^T S = -S^2 is positive semidefinite, so R^T R != I "
           "(||R|| up to 3 at |sigma| = 1).")


CLAIMS = [
    claim("model.eq9_rotation", "relative model", "spacecraft", "9",
          "R(sigma_e) is a rotation: R^T R = I, det R = 1", _orthogonal(True), _orthogonal(False),
          correction="R = I - 4(1-s^2)/(1+s^2)^2 S(s) + 8/(1+s^2)^2 S(s)^2", note=_R_NOTE),
    claim("model.R_dot", "relative model", "spacecraft", "9, 14",
          "R-dot = -S(w_e) R along sigma_e-dot = G(sigma_e) w_e", _R_dot(True), _R_dot(False),
          correction="R = I - 4(1-s^2)/(1+s^2)^2 S(s) + 8/(1+s^2)^2 S(s)^2", note="Inherits eq. 9's print."),
    claim("model.eq13", "relative model", "spacecraft", "1, 5, 11-13",
          "d/dt (r - R r_pt) = v_e - S(w) r_e (R from eq. 9, sigma_e from eq. 14)", _eq13,
          note="Holds with R as corrected; with the printed eq. 9 it fails (R-dot != -S(w_e) R, "
               "see c004.model.R_dot)."),
    claim("model.eq17", "relative model", "spacecraft", "7, 11, 12, 17",
          "R v_pt-dot = -S(w - w_e)[v - v_e - S(w - w_e) R p_t] - R S(p_t) w_t-dot", _eq17,
          note="Holds with R as corrected; its middle line uses R S(a) = S(Ra) R, false for the printed eq. 9."),
    claim("model.eq19", "relative model", "spacecraft", "15, 17-19",
          "eq. 15 with eqs. 17, 18 is eq. 19 (g, n1 as printed)", _eq19),
    claim("model.eq20", "relative model", "spacecraft", "16, 18, 20",
          "eq. 16 with eq. 18 is eq. 20 (n2 as printed)", _eq20),
]
