"""004, Theorem 1 (section 4, eqs. 38-39)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c004 as c
from ...physics.rotations import quat_from_mrp
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
    statement,
    symbols_vec,
)
from ..domains import (
    ball,
    box,
    custom,
    spd_dominant,
)
from .attitude import _Attitude
from .common import J_PAPER, J_T, SIGMA_E0, _eig, _sym3
from .position import _Position

claim = claim_factory(__name__)

# --------------------------------------------------------------------------- Theorem 1 (section 4)

def _v_lower_bound() -> Statement:
    """The proof's bound: V >= k0/2 |r_e|^2 + m/2 |s1|^2 + lambda_J/2 |s2|^2 + |zeta|^2/(2 gamma),
    zeta = [m~, theta~, rho~_tau, rho~_m, rho~_J] as printed (rho~_f is not in it)."""
    P, A = _Position(opaque=True), _Attitude(opaque=True, exact_inverse=False)
    mt, rft, rmt = sp.symbols("mtilde_Delta rhotilde_f rhotilde_m", real=True)
    tt = symbols_vec("thetatilde_Delta", 6)
    rtt, rJt = sp.symbols("rhotilde_tau rhotilde_J", real=True)
    s1, s2 = symbols_vec("s_1"), symbols_vec("s_2")
    lam_J = sp.Symbol("lambda_J", positive=True)
    V1 = c.position_lyapunov(P.k0, P.r_e, P.m, s1, mt, rft, rmt, P.g1, P.g2, P.g3)
    V2 = c.attitude_lyapunov(A.J, s2, tt, rtt, rJt, A.g4, A.g5, A.g6)
    zeta = sp.Matrix([mt, *tt, rtt, rmt, rJt])
    gam = sp.Max(P.g1, P.g2, P.g3, A.g4, A.g5, A.g6)
    rhs = (P.k0 * c.dot(P.r_e, P.r_e) + P.m * c.dot(s1, s1) + lam_J * c.dot(s2, s2)
           + c.dot(zeta, zeta) / gam) / 2
    J = A.J
    Js = list(J)
    dom = [box(P.r_e, -40, 40), box([*s1, *s2], -2, 2), box([mt, rft, rmt, rtt, rJt], -20, 20), box(tt, -100, 100),
           box([P.k0], 0.01, 1), box(P.m, 20, 100), box([P.g1, P.g2, P.g3, A.g4, A.g5, A.g6], 0.01, 1),
           spd_dominant(J, (200, 700), 60),
           custom([lam_J], 0, lambda z, env: _eig(Js, env)[:, :1], "min eigenvalue of J")]
    return Statement(V1 + V2, ">=", rhs, dom, symbolic=False,
                     assumptions=["lambda_J = min eig J", "gamma = max gamma_i"])


def _theorem_vdot() -> Statement:
    """Eq. 38 along the coupled closed loop (13, 14, 19, 20 under 25, 27, 34, 36), R = R(sigma_e):
    V-dot <= -l_k1 |s1|^2 - l_k2 |s2|^2 <= -mu |s|^2 <= 0."""
    P, A = _Position(), _Attitude(exact_inverse=False)
    V = P.V1 + A.V2
    Vdot = lie_derivative(V, P.states + A.states, P.rates + A.rates)
    lk1, lk2 = sp.Min(*P.k1), sp.Min(*A.k2)
    n1, n2 = c.dot(P.s1, P.s1), c.dot(A.s2, A.s2)
    mu = sp.Min(lk1, lk2)
    a = -lk1 * n1 - lk2 * n2
    lhs = sp.Matrix([Vdot, a, -mu * (n1 + n2)])
    rhs = sp.Matrix([a, -mu * (n1 + n2), 0])
    return statement(lhs, "<=", rhs, P.domain() + A.domain(), symbolic=False,
                     assumptions=["Hypotheses 1-2", "rho_m = m ||J_t^-1|| ||J_t||, rho_J = ||J|| ||J_t^-1|| ||J_t||",
                                  "lambda_k1 = min eig K1, lambda_k2 = min eig K2"])


def _vs_manifold():
    """(r_e, sigma_e) dynamics on s1 = s2 = 0 (v_e = -L1 r_e, w_e = -L2 sigma_e) from eqs. 13, 14."""
    P, A = _Position(opaque=True), _Attitude(opaque=True, exact_inverse=False)
    zero = sp.zeros(3, 1)
    v_e = -c.position_surface(zero, P.r_e, P.L1)        # s1 = 0
    w_e = -c.attitude_surface(zero, A.sig, A.L2)        # s2 = 0
    Vs = (c.dot(P.r_e, P.r_e) + c.dot(A.sig, A.sig)) / 2
    Vsdot = lie_derivative(Vs, [P.r_e, A.sig], [c.position_kinematics(P.r_e, v_e, P.omega),
                                                c.mrp_kinematics(A.sig, w_e)])
    dom = [box(P.r_e, -40, 40), ball(A.sig, 1.0), box(P.omega, -0.1, 0.1), box(P.l1, 0.01, 1),
           box(A.l2, 0.01, 1)]
    return P, A, Vsdot, dom


def _vs_identity() -> Statement:
    """Eq. 39: Vs-dot = -r_e^T L1 r_e - (1 + |sigma_e|^2)/4 sigma_e^T L2 sigma_e
    (uses r^T S(w) r = 0 and sigma^T G(sigma) = (1 + |sigma|^2)/4 sigma^T)."""
    P, A, Vsdot, dom = _vs_manifold()
    rhs = -c.dot(P.r_e, P.L1 * P.r_e) - (1 + c.dot(A.sig, A.sig)) / 4 * c.dot(A.sig, A.L2 * A.sig)
    return Statement(Vsdot, "==", rhs, dom)


def _vs_bound() -> Statement:
    """Eq. 39, last line: Vs-dot <= -l_m1 |r_e|^2 - l_m2/4 |sigma_e|^2 <= 0."""
    P, A, Vsdot, dom = _vs_manifold()
    b = -sp.Min(*P.l1) * c.dot(P.r_e, P.r_e) - sp.Min(*A.l2) / 4 * c.dot(A.sig, A.sig)
    return Statement(sp.Matrix([Vsdot, b]), "<=", sp.Matrix([b, 0]), dom, symbolic=False,
                     assumptions=["lambda_m1 = min eig L1, lambda_m2 = min eig L2"])


def _G_invertible() -> Statement:
    """End of the proof: G(sigma_e) is invertible; det G = (1 + |sigma|^2)^3 / 64 > 0."""
    sig = symbols_vec("sigma_e")
    return Statement(c.mrp_kinematics_matrix(sig).det(), "==", (1 + c.dot(sig, sig)) ** 3 / 64, [ball(sig, 1.0)])


def _claim1_energy() -> Statement:
    """Claim 1: E-dot = 0 along the torque-free target (eqs. 7, 8), so v_t, w_t stay bounded.  Stated as
    E + E-dot = E so that the numeric tolerance is relative to E (E-dot alone is 0 +- rounding)."""
    v_t, w_t = symbols_vec("v_t"), symbols_vec("omega_t")
    m_t = sp.Symbol("m_t", positive=True)
    Jt = _sym3("Jt")
    zero = sp.zeros(3, 1)
    E = c.target_kinetic_energy(m_t, v_t, Jt, w_t)
    Edot = lie_derivative(E, [v_t, w_t], [c.translational_dynamics(m_t, v_t, w_t, zero, zero),
                                          c.rotational_dynamics(Jt, w_t, zero, zero)])
    return Statement(E + Edot, "==", E, [box(v_t, -1, 1), box(w_t, -0.1, 0.1), box(m_t, 100, 5000),
                                     spd_dominant(Jt, (2000, 3500), 200)])


def _hypothesis1_paper_data() -> Statement:
    """Hypothesis 1 for section 5's data: m = 58.2 > 0, J > 0, J_t > 0, J0 = diag(theta0[:3]) > 0
    (leading principal minors; exact rationals)."""
    def minors(A):
        M = sp.Matrix(A).applyfunc(sp.nsimplify)
        return [M[:k, :k].det() for k in (1, 2, 3)]
    vals = [sp.nsimplify(58.2), *minors(J_PAPER), *minors(J_T), *minors(np.diag([580.0, 400.0, 300.0]))]
    return Statement(sp.Matrix(vals), ">", 0, [])


def _sigma_e0(corrected: bool):
    def build() -> Statement:
        """|sigma_e(0)| <= 1 (the constraint stated under eq. 4 and used in the proof)."""
        s = sp.Matrix([sp.nsimplify(x) for x in SIGMA_E0])
        if corrected:      # the same attitude as rpo's law forms it: principal_mrp of its quaternion
            s = c.principal_mrp(quat_from_mrp(s))
        return Statement(c.dot(s, s), "<=", 1, [])
    return build


CLAIMS = [
    claim("theorem.claim1_energy", "theorem", "spacecraft", "7-8 (Claim 1)",
          "target kinetic energy is constant along eqs. 7, 8 (bounded target motion)", _claim1_energy),
    claim("theorem.hypothesis1_paper_data", "theorem", "abstract", "Hyp. 1, sec. 5",
          "section 5's m, J, J_t, J0 satisfy Hypothesis 1 (positive, positive definite)",
          _hypothesis1_paper_data, about="paper"),
    claim("theorem.sigma_e0_constraint", "theorem", "spacecraft", "Table 1",
          "Table 1's sigma_e(0) satisfies ‖sigma_e‖ <= 1", _sigma_e0(False), _sigma_e0(True), about="paper",
          correction="the shadow set -sigma/‖sigma‖^2 = [-0.4545, 0.5455, -0.6364] (same attitude)",
          note="sigma_e(0) = [0.5, -0.6, 0.7] has norm 1.049 > 1, against the constraint the proof uses."),
    claim("theorem.V_lower_bound", "theorem", "abstract", "38 (proof)",
          "V = V1 + V2 >= k0/2‖r‖^2 + m/2‖s1‖^2 + l_J/2‖s2‖^2 + ‖zeta‖^2/(2 gamma)", _v_lower_bound,
          note="Holds, but the printed zeta omits rho~_f, so the proof's 'zeta bounded' does not name "
               "rho^_f (it is bounded anyway since V is)."),
    claim("theorem.Vdot_bound", "theorem", "abstract", "38",
          "V-dot <= -l_k1‖s1‖^2 - l_k2‖s2‖^2 <= -mu‖s‖^2 <= 0 on the coupled closed loop", _theorem_vdot),
    claim("theorem.Vs_identity", "theorem", "abstract", "39",
          "on s1 = s2 = 0: Vs-dot = -r^T L1 r - (1+‖sigma‖^2)/4 sigma^T L2 sigma", _vs_identity),
    claim("theorem.Vs_bound", "theorem", "abstract", "39",
          "on s1 = s2 = 0: Vs-dot <= -l_m1‖r‖^2 - l_m2/4‖sigma‖^2 <= 0", _vs_bound),
    claim("theorem.G_invertible", "theorem", "abstract", "14, 39",
          "G(sigma_e) is invertible: det G = (1 + ‖sigma‖^2)^3/64", _G_invertible),
]
