"""Claims of 004 (Sun & Huo): the position (eqs. 21-28) and attitude (eqs. 29-37) Lyapunov arguments.

Every statement is built from the functions of :mod:`rpo.symbolic.controllers.c004` that generate the C
code (looked up on the module at check time, so mutations are seen): the closed loop is the paper's model
(eqs. 13, 19 / 14, 20) driven by the law (eq. 25 / 34) and the adaptation (eq. 27 / 36), and V-dot is
V differentiated along it (:func:`~rpo.symbolic.lyapunov.core.lie_derivative`).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..controllers import c004 as c
from .core import (
    Claim,
    Mutation,
    Statement,
    ball,
    box,
    custom,
    fixed,
    lie_derivative,
    negate_output,
    scale_argument,
    symbols_vec,
)

# A representative target (the paper's J_t and docking offset) for the numeric search; the symbolic
# steps keep every quantity a symbol.
J_T = np.array([[3336.3, -135.4, -154.2], [-135.4, 3184.5, -148.5], [-154.2, -148.5, 2423.7]])
P_T = np.array([0.0, 5.0, 0.0])


class _Position:
    """Symbols and closed loop of the position subsystem (eqs. 13, 19, 21-27)."""

    def __init__(self, opaque: bool = False):
        """``opaque``: R and n1 as free symbols (exogenous signals the identity must hold for whatever
        their values; keeps the symbolic proof small); otherwise R = R(sigma_e) (eq. 9) and n1 as printed."""
        self.opaque = opaque
        self.r_e, self.v_e = symbols_vec("r_e"), symbols_vec("v_e")
        self.omega, self.omega_e = symbols_vec("omega"), symbols_vec("omega_e")
        self.sig = symbols_vec("sigma_e")
        self.d_f = symbols_vec("d_f")
        self.m, self.m0, self.k0 = sp.symbols("m m_0 k_0", positive=True)
        self.m_hat, self.rf_hat, self.rm_hat = sp.symbols("mhat_Delta rhohat_f rhohat_m", real=True)
        self.rho_f, self.rho_m = sp.symbols("rho_f rho_m", positive=True)
        self.g1, self.g2, self.g3 = sp.symbols("gamma_1:4", positive=True)
        self.l1 = sp.symbols("lambda_1:4", positive=True)
        self.k1 = sp.symbols("k_1:4", positive=True)
        self.Jt = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Jt_{min(i, j) + 1}{max(i, j) + 1}", real=True))
        self.p_t = symbols_vec("p_t")
        L1, K1 = sp.diag(*self.l1), sp.diag(*self.k1)
        self.L1, self.K1 = L1, K1
        if opaque:
            R = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))
            self.n1 = symbols_vec("n_1")
        else:
            R = c.rotation_matrix(self.sig)
            self.n1 = c.coupling_n1(R, self.p_t, self.Jt, self.omega, self.omega_e)
        self.R = R
        g = c.coupling_g(self.omega, self.omega_e, self.v_e, R, self.p_t)
        self.s1 = c.position_surface(self.v_e, self.r_e, L1)                                  # eq. 21
        y = c.position_regressor(g, self.v_e, self.r_e, self.omega, L1)                       # eq. 22
        self.f = c.position_control(self.k0, K1, self.r_e, self.s1, self.m0, self.m_hat, y,   # eq. 25
                                    self.rf_hat, self.rm_hat, self.p_t, self.omega, self.omega_e)
        dm, drf, drm = c.position_adaptation(self.g1, self.g2, self.g3, y, self.s1, self.p_t,  # eq. 27
                                             self.omega, self.omega_e)
        self.states = [self.r_e, self.v_e, self.m_hat, self.rf_hat, self.rm_hat]
        self.rates = [c.position_kinematics(self.r_e, self.v_e, self.omega),                  # eq. 13
                      c.relative_velocity_rate(self.m, g, self.n1, self.f, self.d_f),         # eq. 19
                      dm, drf, drm]
        self.m_tilde = self.m0 + self.m_hat - self.m
        self.V1 = c.position_lyapunov(self.k0, self.r_e, self.m, self.s1, self.m_tilde,       # eq. 23
                                      self.rf_hat - self.rho_f, self.rm_hat - self.rho_m,
                                      self.g1, self.g2, self.g3)
        self.V1dot = lie_derivative(self.V1, self.states, self.rates)
        wt2 = c.dot(self.omega - self.omega_e, self.omega - self.omega_e)
        s1 = self.s1
        self.nominal = -self.k0 * c.dot(self.r_e, L1 * self.r_e) - c.dot(s1, K1 * s1)
        self.robust = (self.rho_f + self.rho_m * c.norm2(self.p_t) * wt2) * c.norm1(s1)

    def domain(self, rho_m_value=None):
        """Gains, mass, states and disturbances in ranges that cover the paper's scenario (section 5)."""
        rho_m = (self.m_value_bound() if rho_m_value is None else rho_m_value)
        if self.opaque:
            rot = [custom(list(self.R), 3, _rotation_from_mrp_box, "R = R(sigma), |sigma| <= 1"),
                   box(self.n1, -0.01, 0.01)]
        else:
            rot = [ball(self.sig, 1.0)]
        return [box(self.r_e, -30, 30), box(self.v_e, -2, 2), box(self.omega, -0.1, 0.1),
                box(self.omega_e, -0.1, 0.1), *rot,
                box([self.m, self.m0], 20, 100), box(self.k0, 0.01, 1), box(self.l1, 0.01, 1),
                box(self.k1, 1, 50), box([self.g1, self.g2, self.g3], 0.01, 1),
                box([self.m_hat, self.rf_hat, self.rm_hat], -20, 20), box(self.rho_f, 0, 1),
                ball(self.d_f, self.rho_f), fixed(self.rho_m, [rho_m]),
                fixed(list(self.Jt.upper_triangular()[i, j] for i in range(3) for j in range(i, 3)),
                      [J_T[i, j] for i in range(3) for j in range(i, 3)]),
                fixed(self.p_t, P_T)]

    def m_value_bound(self):
        # rho_m >= m ||J_t^-1|| ||J_t|| for the largest m of the domain (the paper's bound, above eq. 28)
        return 100.0 * np.linalg.norm(np.linalg.inv(J_T), 2) * np.linalg.norm(J_T, 2)


def _rotation_from_mrp_box(z, env):
    """9 entries (row-major) of R(sigma) for sigma in the unit ball (independent of eq. 9: scipy)."""
    from scipy.spatial.transform import Rotation

    sig = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1.0)
    return Rotation.from_mrp(sig).as_matrix().reshape(len(z), 9)


def _v1_positive() -> Statement:
    P = _Position()
    r_t = sp.symbols("mtilde_Delta rhotilde_f rhotilde_m", real=True)
    V = c.position_lyapunov(P.k0, P.r_e, P.m, P.s1, *r_t, P.g1, P.g2, P.g3)
    s = symbols_vec("s_1")
    V = V.subs(dict(zip(P.v_e, list(s - P.L1 * P.r_e), strict=True)))
    return Statement(V, ">", 0, [box(P.r_e, -30, 30), box(s, -2, 2), box(r_t, -20, 20), box(P.m, 20, 100),
                                 box(P.k0, 0.01, 1), box(P.l1, 0.01, 1), box([P.g1, P.g2, P.g3], 0.01, 1)],
                     positive=[P.k0, P.m, P.g1, P.g2, P.g3], zero_at=list(P.r_e) + list(s) + list(r_t),
                     assumptions=["k0, m, gamma_1..3 > 0"])


def _v1dot_identity() -> Statement:
    """Eqs. 24-27: with eq. 27 the estimation errors cancel; what remains is the paper's eq. 28 before
    its bound: -k0 r^T L1 r - s^T K1 s + s^T(d_f - m n1) - (rho_f + rho_m |p_t| |w_t|^2) |s|_1."""
    P = _Position(opaque=True)
    rhs = P.nominal + c.dot(P.s1, P.d_f - P.m * P.n1) - P.robust
    return Statement(P.V1dot, "==", rhs, P.domain(), assumptions=["eq. 27 substituted"])


def _v1dot_bound() -> Statement:
    """Eq. 28: V1-dot <= -k0 r^T L1 r - s^T K1 s under ||d_f|| <= rho_f and rho_m >= m ||J_t^-1|| ||J_t||."""
    P = _Position()
    return Statement(P.V1dot, "<=", P.nominal, P.domain(), symbolic=False,
                     assumptions=["||d_f|| <= rho_f", "rho_m = 100 kg ||J_t^-1|| ||J_t|| >= m ||J_t^-1|| ||J_t||",
                                  "||S(a)|| = ||a||, ||R|| = 1, ||s||_2 <= ||s||_1 (the paper's steps)"])


CLAIMS = [
    Claim("c004.position.V1_definite", "c004", "position", "spacecraft", "23",
          "V1 is positive definite in (r_e, s1, m~, rho~_f, rho~_m)", _v1_positive),
    Claim("c004.position.V1dot_identity", "c004", "position", "spacecraft", "24-27",
          "V1-dot along eqs. 13, 19 under eqs. 25, 27: the estimation errors cancel", _v1dot_identity),
    Claim("c004.position.V1dot_bound", "c004", "position", "spacecraft", "28",
          "V1-dot <= -k0 r_e^T L1 r_e - s1^T K1 s1", _v1dot_bound),
]

MUTATIONS = [
    Mutation("c004: +K1 s1 in eq. 25", c, "position_control", scale_argument("K1", -1),
             ("c004.position.V1dot_identity", "c004.position.V1dot_bound")),
    Mutation("c004: sign of the m_hat adaptation (eq. 27)", c, "position_adaptation", negate_output(0),
             ("c004.position.V1dot_identity",)),
]
