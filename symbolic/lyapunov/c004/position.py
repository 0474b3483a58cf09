"""004, position subsystem (section 3.1, eqs. 21-28)."""

from __future__ import annotations

import sympy as sp

from ...controllers import c004 as c
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
    needing,
    rotation_matrix,
    spd_dominant,
    upper,
)
from .common import _code_rotation, _cond, _inverse_var, _opaque_inverse, _printed_y, _rotation_symbols, _s_dot

claim = claim_factory(__name__)

# --------------------------------------------------------------------------- position subsystem

class _Position:
    """Symbols and closed loop of the position subsystem (eqs. 13, 19, 21-27)."""

    def __init__(self, opaque: bool = False, y: str = "code", law: bool = True, adapt: bool = True):
        """R is always 9 symbols.  ``opaque``: n1 a free symbol too and R drawn as any rotation
        (exogenous signals the identity must hold for whatever their values; keeps the symbolic proof
        small); otherwise R is drawn as the code's R(sigma_e) (eq. 9) and n1 is the printed coupling.
        ``y``: "code" (corrected) or "printed" (eq. 22 as printed, also used in the law and adaptation).
        ``law`` / ``adapt``: False leaves f / the estimate rates free (the steps before eqs. 25 / 27)."""
        self.opaque = opaque
        self.r_e, self.v_e = symbols_vec("r_e"), symbols_vec("v_e")
        self.omega, self.omega_e = symbols_vec("omega"), symbols_vec("omega_e")
        self.sig = symbols_vec("sigma_e")
        self.d_f = symbols_vec("d_f")
        self.m, self.m0, self.k0 = sp.symbols("m m_0 k_0", positive=True)
        self.m_hat, self.rf_hat, self.rm_hat = sp.symbols("mhat_Delta rhohat_f rhohat_m", real=True)
        self.rho_f, self.rho_m = sp.symbols("rho_f rho_m", positive=True)
        self.g1, self.g2, self.g3 = sp.symbols("gamma_1:4", positive=True)
        self.l1 = sp.symbols("lambda1_1:4", positive=True)
        self.k1 = sp.symbols("k1_1:4", positive=True)
        self.Jt = _opaque_inverse("Jt")
        self.p_t = symbols_vec("p_t")
        L1, K1 = sp.diag(*self.l1), sp.diag(*self.k1)
        self.L1, self.K1 = L1, K1
        self.R = R = _rotation_symbols()
        if opaque:
            self.n1 = symbols_vec("n_1")
        else:
            self.n1 = c.coupling_n1(R, self.p_t, self.Jt, self.omega, self.omega_e)
        self.g = g = c.coupling_g(self.omega, self.omega_e, self.v_e, R, self.p_t)
        self.s1 = c.position_surface(self.v_e, self.r_e, L1)                                  # eq. 21
        y_fn = c.position_regressor if y == "code" else _printed_y
        self.y = y_fn(g, self.v_e, self.r_e, self.omega, L1)                                  # eq. 22
        self.free = []
        if law:
            self.f = c.position_control(self.k0, K1, self.r_e, self.s1, self.m0, self.m_hat,  # eq. 25
                                        self.y, self.rf_hat, self.rm_hat, self.p_t, self.omega, self.omega_e)
        else:
            self.f = symbols_vec("f")
            self.free.append(box(self.f, -100, 100))
        if adapt:
            dm, drf, drm = c.position_adaptation(self.g1, self.g2, self.g3, self.y, self.s1,  # eq. 27
                                                 self.p_t, self.omega, self.omega_e)
        else:
            dm, drf, drm = sp.symbols("mhatdot_Delta rhohatdot_f rhohatdot_m", real=True)
            self.free.append(box([dm, drf, drm], -10, 10))
        self.states = [self.r_e, self.v_e, self.m_hat, self.rf_hat, self.rm_hat]
        self.rates = [c.position_kinematics(self.r_e, self.v_e, self.omega),                  # eq. 13
                      c.relative_velocity_rate(self.m, g, self.n1, self.f, self.d_f),         # eq. 19
                      dm, drf, drm]
        self.m_tilde = self.m0 + self.m_hat - self.m
        self.rf_tilde, self.rm_tilde = self.rf_hat - self.rho_f, self.rm_hat - self.rho_m
        self.V1 = c.position_lyapunov(self.k0, self.r_e, self.m, self.s1, self.m_tilde,       # eq. 23
                                      self.rf_tilde, self.rm_tilde, self.g1, self.g2, self.g3)
        self.V1dot = lie_derivative(self.V1, self.states, self.rates)
        self.wt2 = c.dot(self.omega - self.omega_e, self.omega - self.omega_e)
        s1 = self.s1
        self.nominal = -self.k0 * c.dot(self.r_e, L1 * self.r_e) - c.dot(s1, K1 * s1)
        self.robust = (self.rho_f + self.rho_m * c.norm2(self.p_t) * self.wt2) * c.norm1(s1)
        self.adapt_terms = (self.m_tilde * dm / self.g1 + self.rf_tilde * drf / self.g2
                            + self.rm_tilde * drm / self.g3)

    def domain(self):
        """Gains, mass, states and disturbances in ranges that cover the paper's scenario (section 5);
        J_t any positive definite inertia, rho_m = m ||J_t^-1|| ||J_t|| exactly (the paper's definition)."""
        if self.opaque:
            rot = [rotation_matrix(list(self.R), "R = R(sigma), |sigma| <= 1"),
                   box(self.n1, -0.01, 0.01)]
        else:
            rot = [ball(self.sig, 1.0), _code_rotation(self.R, self.sig)]
        m, Jt = self.m, self.Jt
        Jts = list(Jt)
        return [box(self.r_e, -40, 40), box(self.v_e, -2, 2), box(self.omega, -0.1, 0.1),
                box(self.omega_e, -0.1, 0.1), *rot,
                box([self.m, self.m0], 20, 100), box(self.k0, 0.01, 1), box(self.l1, 0.01, 1),
                box(self.k1, 1, 50), box([self.g1, self.g2, self.g3], 0.01, 1),
                box([self.m_hat, self.rf_hat], -20, 20), box(self.rm_hat, -300, 300), box(self.rho_f, 0, 1),
                needing(ball(self.d_f, self.rho_f), self.rho_f), spd_dominant(Jt, (2000, 3500), 200), _inverse_var(Jt),
                needing(custom([self.rho_m], 0, lambda z, env: (env[m] * _cond(Jts, env))[:, None],
                            "rho_m = m ||J_t^-1|| ||J_t||"), m, *upper(Jt)),
                box(self.p_t, -6, 6), *self.free]


def _v1_positive() -> Statement:
    P = _Position(opaque=True)
    r_t = sp.symbols("mtilde_Delta rhotilde_f rhotilde_m", real=True)
    V = c.position_lyapunov(P.k0, P.r_e, P.m, P.s1, *r_t, P.g1, P.g2, P.g3)
    s = symbols_vec("s_1")
    V = V.subs(dict(zip(P.v_e, list(s - P.L1 * P.r_e), strict=True)))
    return Statement(V, ">", 0, [box(P.r_e, -30, 30), box(s, -2, 2), box(r_t, -20, 20), box(P.m, 20, 100),
                                 box(P.k0, 0.01, 1), box(P.l1, 0.01, 1), box([P.g1, P.g2, P.g3], 0.01, 1)],
                     positive=[P.k0, P.m, P.g1, P.g2, P.g3], zero_at=list(P.r_e) + list(s) + list(r_t),
                     assumptions=["k0, m, gamma_1..3 > 0 (Hypothesis 1, eq. 23)"])


def _surface_dynamics(y: str):
    def build() -> Statement:
        """Eq. 22: m s1-dot along eqs. 13, 19 (any f) = -m y - m n1 + f + d_f."""
        P = _Position(opaque=True, y=y, law=False, adapt=False)
        lhs = P.m * _s_dot(P.s1, P.states[:2], P.rates[:2])
        rhs = c.position_surface_dynamics(P.m, P.y, P.n1, P.f, P.d_f)
        return statement(lhs, "==", rhs, P.domain(), assumptions=["any f (before eq. 25)"])
    return build


def _eq24(y: str):
    def build() -> Statement:
        """Eq. 24: V1-dot along eqs. 13, 19, for any f and estimate rates."""
        P = _Position(opaque=True, y=y, law=False, adapt=False)
        rhs = (-P.k0 * c.dot(P.r_e, P.L1 * P.r_e)
               + c.dot(P.s1, P.k0 * P.r_e - P.m * P.y - P.m * P.n1 + P.f + P.d_f) + P.adapt_terms)
        return statement(P.V1dot, "==", rhs, P.domain(), assumptions=["any f, any estimate rates"])
    return build


def _eq26() -> Statement:
    """Eq. 26: eq. 24 with the law (25) substituted (estimate rates still free)."""
    P = _Position(opaque=True, adapt=False)
    s1, sg = P.s1, c.sgn(P.s1)
    rhs = (P.nominal + c.dot(s1, P.m_tilde * P.y) - c.dot(s1, P.m * P.n1) + c.dot(s1, P.d_f)
           - c.dot(s1, P.rf_hat * sg) - c.dot(s1, P.rm_hat * c.norm2(P.p_t) * P.wt2 * sg) + P.adapt_terms)
    return statement(P.V1dot, "==", rhs, P.domain(), assumptions=["eq. 25 substituted, estimate rates free"])


def _v1dot_identity() -> Statement:
    """Eqs. 24-27: with eq. 27 the estimation errors cancel; what remains is the paper's eq. 28 before
    its bound: -k0 r^T L1 r - s^T K1 s + s^T(d_f - m n1) - (rho_f + rho_m |p_t| |w_t|^2) |s|_1."""
    P = _Position(opaque=True)
    rhs = P.nominal + c.dot(P.s1, P.d_f - P.m * P.n1) - P.robust
    return statement(P.V1dot, "==", rhs, P.domain(), assumptions=["eqs. 25, 27 substituted"])


def _closed_loop_28() -> Statement:
    """Eq. 28: m s1-dot = -k0 r_e - K1 s1 + m~ y - m n1 + d_f - (rho^_f + rho^_m |p_t| |w_t|^2) sgn(s1)."""
    P = _Position(opaque=True)
    lhs = P.m * _s_dot(P.s1, P.states[:2], P.rates[:2])
    rhs = (-P.k0 * P.r_e - P.K1 * P.s1 + P.m_tilde * P.y - P.m * P.n1 + P.d_f
           - (P.rf_hat + P.rm_hat * c.norm2(P.p_t) * P.wt2) * c.sgn(P.s1))
    return statement(lhs, "==", rhs, P.domain(), assumptions=["eq. 25 substituted"])


def _n1_bound() -> Statement:
    """The step under eq. 27: ||m n1|| <= rho_m ||p_t|| ||w - w_e||^2 with rho_m = |m| ||J_t^-1|| ||J_t||."""
    P = _Position()
    lhs = c.norm2(P.m * P.n1)
    rhs = P.rho_m * c.norm2(P.p_t) * P.wt2
    return statement(lhs, "<=", rhs, P.domain(), symbolic=False,
                     assumptions=["R = R(sigma_e) (eq. 9, corrected): ||R|| = 1", "||S(a)|| = ||a||",
                                  "rho_m = m ||J_t^-1|| ||J_t||, J_t > 0"])


def _v1dot_bound() -> Statement:
    """Eq. 27's chain: V1-dot <= -k0 r^T L1 r - s^T K1 s <= -s^T K1 s under ||d_f|| <= rho_f and
    rho_m = m ||J_t^-1|| ||J_t||."""
    P = _Position()
    lhs = sp.Matrix([P.V1dot, P.nominal])
    rhs = sp.Matrix([P.nominal, -c.dot(P.s1, P.K1 * P.s1)])
    return statement(lhs, "<=", rhs, P.domain(), symbolic=False,
                     assumptions=["||d_f|| <= rho_f (Hypothesis 2)", "rho_m = m ||J_t^-1|| ||J_t|| (above eq. 23)",
                                  "||S(a)|| = ||a||, ||R|| = 1, ||s||_2 <= ||s||_1 (the paper's steps)"])
_Y_NOTE = ("Printed y = g + L1 v_e + L1 S(w) r_e; the middle line of eq. 22 (+m L1 v_e - m L1 S(w) r_e = "
           "m L1 r_e-dot by eq. 13) needs -L1 v_e: the residual is 2 m L1 v_e.")


CLAIMS = [
    claim("position.V1_definite", "position", "abstract", "23",
          "V1 is positive definite in (r_e, s1, m~, rho~_f, rho~_m)", _v1_positive),
    claim("position.surface_dynamics", "position", "abstract", "21-22",
          "m s1-dot = -m y - m n1 + f + d_f along eqs. 13, 19", _surface_dynamics("printed"),
          _surface_dynamics("code"), correction="y = g - L1 v_e + L1 S(w) r_e (= g - L1 r_e-dot)",
          note=_Y_NOTE),
    claim("position.eq24_identity", "position", "abstract", "24",
          "V1-dot = -k0 r^T L1 r + s1^T(k0 r - m y - m n1 + f + d_f) + estimate terms (any f)",
          _eq24("printed"), _eq24("code"), correction="y = g - L1 v_e + L1 S(w) r_e",
          note="Inherits eq. 22's printed y: the residual is 2 m s1^T L1 v_e."),
    claim("position.eq26_identity", "position", "abstract", "25-26",
          "V1-dot under the law (25) equals eq. 26 (estimate rates free)", _eq26,
          note="With y as corrected in eq. 22; the law and the printed line use the same y, so this step holds "
               "for either y given eq. 22."),
    claim("position.V1dot_identity", "position", "abstract", "24-27",
          "V1-dot along eqs. 13, 19 under eqs. 25, 27: the estimation errors cancel", _v1dot_identity,
          note="With y as corrected in eq. 22 (with the printed y in the law this step fails too, by eq. 22)."),
    claim("position.closed_loop", "position", "abstract", "28",
          "closed loop m s1-dot = -k0 r - K1 s1 + m~ y - m n1 + d_f - (rho^_f + rho^_m ‖p_t‖ ‖w_t‖^2) sgn(s1)",
          _closed_loop_28),
    claim("position.n1_bound", "position", "spacecraft", "19, 27",
          "‖m n1‖ <= rho_m ‖p_t‖ ‖w - w_e‖^2, rho_m = m ‖J_t^-1‖ ‖J_t‖", _n1_bound,
          note="Uses ||R|| = ||R^T|| = 1, true for the corrected eq. 9 only (see c004.model.eq9_rotation)."),
    claim("position.V1dot_bound", "position", "abstract", "27-28",
          "V1-dot <= -k0 r_e^T L1 r_e - s1^T K1 s1 <= -s1^T K1 s1", _v1dot_bound),
]
