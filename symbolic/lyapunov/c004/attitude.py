"""004, attitude subsystem (section 3.2, eqs. 29-37)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c004 as c
from ...physics.rotations import mrp_shadow
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
    statement,
    symbols_vec,
)
from ..domains import (
    UPPER,
    ball,
    box,
    custom,
    fixed,
    needing,
    rotation_matrix,
    spd_dominant,
    unit_vector,
    upper,
)
from .common import (
    J_PAPER,
    _code_rotation,
    _cond,
    _eig,
    _inverse_var,
    _opaque_inverse,
    _printed_L,
    _printed_Y,
    _rotation_symbols,
    _s_dot,
    _sym3,
    _WithInverse,
)

claim = claim_factory(__name__)

# --------------------------------------------------------------------------- attitude subsystem

class _Attitude:
    """Symbols and closed loop of the attitude subsystem (eqs. 14, 20, 29-36)."""

    def __init__(self, opaque: bool = False, Y: str = "code", law: bool = True, adapt: bool = True,
                 exact_inverse: bool = True):
        """As :class:`_Position`: ``opaque`` R and n2 free symbols; ``Y`` "code" or "printed" (the sign
        under eq. 31); ``law`` / ``adapt`` False leave tau / the estimate rates free.  ``exact_inverse``:
        J^-1 as SymPy's inverse of the symbols (needed where J J^-1 must cancel: J s2-dot, V2-dot);
        otherwise its own symbols (smaller numeric statements)."""
        self.opaque = opaque
        self.omega, self.omega_e = symbols_vec("omega"), symbols_vec("omega_e")
        self.sig = symbols_vec("sigma_e")
        self.d_tau = symbols_vec("d_tau")
        self.J = _sym3("J") if exact_inverse else _opaque_inverse("J")
        self.Jt = _opaque_inverse("Jt")
        self.l2 = sp.symbols("lambda2_1:4", positive=True)
        self.k2 = sp.symbols("k2_1:4", positive=True)
        self.L2, self.K2 = sp.diag(*self.l2), sp.diag(*self.k2)
        self.g4, self.g5, self.g6 = sp.symbols("gamma_4:7", positive=True)
        self.theta0 = symbols_vec("theta_0", 6)
        self.th_hat = symbols_vec("thetahat_Delta", 6)
        self.rt_hat, self.rJ_hat = sp.symbols("rhohat_tau rhohat_J", real=True)
        self.rho_tau, self.rho_J = sp.symbols("rho_tau rho_J", positive=True)
        self.R = _rotation_symbols()
        if opaque:
            self.n2 = symbols_vec("n_2")
        else:
            self.n2 = c.coupling_n2(self.R, self.Jt, self.omega, self.omega_e)
        self.s2 = c.attitude_surface(self.omega_e, self.sig, self.L2)                          # eq. 29
        Y_fn = c.attitude_regressor if Y == "code" else _printed_Y
        self.Y = Y_fn(self.omega, self.omega_e, self.sig, self.L2)                            # eq. 31
        self.free = []
        if law:
            self.tau = c.attitude_control(self.K2, self.s2, self.Y, self.theta0, self.th_hat,  # eq. 34
                                          self.rt_hat, self.rJ_hat, self.omega, self.omega_e)
        else:
            self.tau = symbols_vec("tau")
            self.free.append(box(self.tau, -50, 50))
        if adapt:
            dth, drt, drJ = c.attitude_adaptation(self.g4, self.g5, self.g6, self.Y, self.s2,  # eq. 36
                                                  self.omega, self.omega_e)
        else:
            dth = symbols_vec("thetahatdot_Delta", 6)
            drt, drJ = sp.symbols("rhohatdot_tau rhohatdot_J", real=True)
            self.free.append(box(list(dth) + [drt, drJ], -10, 10))
        self.theta = c.inertia_parameters(self.J)
        self.th_tilde = self.theta0 + self.th_hat - self.theta
        self.rt_tilde, self.rJ_tilde = self.rt_hat - self.rho_tau, self.rJ_hat - self.rho_J
        self.states = [self.omega_e, self.sig, self.th_hat, self.rt_hat, self.rJ_hat]
        self.rates = [c.relative_rate_rate(self.J, self.omega, self.omega_e, self.n2, self.tau,  # eq. 20
                                           self.d_tau),
                      c.mrp_kinematics(self.sig, self.omega_e),                               # eq. 14
                      dth, drt, drJ]
        self.V2 = c.attitude_lyapunov(self.J, self.s2, self.th_tilde, self.rt_tilde,          # eq. 32
                                      self.rJ_tilde, self.g4, self.g5, self.g6)
        self.V2dot = lie_derivative(self.V2, self.states, self.rates)
        self.wt2 = c.dot(self.omega - self.omega_e, self.omega - self.omega_e)
        self.adapt_terms = (c.dot(self.th_tilde, dth) / self.g4 + self.rt_tilde * drt / self.g5
                            + self.rJ_tilde * drJ / self.g6)

    def Js2dot(self):
        """J s2-dot along eqs. 14, 20."""
        return self.J * _s_dot(self.s2, self.states[:2], self.rates[:2])

    def domain(self):
        """The paper's scenario ranges: J, J_t any positive definite inertia around the paper's;
        |sigma_e| <= 1 (the paper's constraint); rho_J = ||J|| ||J_t^-1|| ||J_t|| exactly."""
        if self.opaque:
            rot = [rotation_matrix(list(self.R), "R = R(sigma), |sigma| <= 1"),
                   box(self.n2, -0.01, 0.01)]
        else:
            rot = [_code_rotation(self.R, self.sig)]
        J, Jt = self.J, self.Jt
        Js, Jts = list(J), list(Jt)
        return [box(self.omega, -0.1, 0.1), box(self.omega_e, -0.1, 0.1), ball(self.sig, 1.0), *rot,
                spd_dominant(J, (200, 700), 60), spd_dominant(Jt, (2000, 3500), 200), _inverse_var(Jt),
                *([_inverse_var(J)] if isinstance(J, _WithInverse) else []),
                box(self.l2, 0.01, 1), box(self.k2, 1, 200), box([self.g4, self.g5, self.g6], 0.01, 1),
                box(self.theta0[:3], 200, 700), fixed(self.theta0[3:], [0, 0, 0]),
                box(self.th_hat, -100, 100), box(self.rt_hat, -20, 20), box(self.rJ_hat, -3000, 3000),
                box(self.rho_tau, 0, 1), needing(ball(self.d_tau, self.rho_tau), self.rho_tau),
                needing(custom([self.rho_J], 0,
                            lambda z, env: (_eig(Js, env)[:, 2] * _cond(Jts, env))[:, None],
                            "rho_J = ||J|| ||J_t^-1|| ||J_t||"), *upper(J), *upper(Jt)),
                *self.free]


def _v2_positive() -> Statement:
    """Eq. 32 with J > 0: J = C C^T (Cholesky, C lower triangular with positive diagonal, which covers
    every J > 0) and z = C^T s2, so V2 is a sum of squares in (z, theta~, rho~_tau, rho~_J)."""
    A = _Attitude(opaque=True, exact_inverse=False)
    cd = sp.symbols("c_11 c_22 c_33", positive=True)
    co = sp.symbols("c_21 c_31 c_32", real=True)
    C = sp.Matrix([[cd[0], 0, 0], [co[0], cd[1], 0], [co[1], co[2], cd[2]]])
    z = symbols_vec("z")
    tt = symbols_vec("thetatilde_Delta", 6)
    rt = sp.symbols("rhotilde_tau rhotilde_J", real=True)
    s2 = C.T.inv() * z
    V = c.attitude_lyapunov(C * C.T, s2, tt, *rt, A.g4, A.g5, A.g6)
    return Statement(V, ">", 0, [box(z, -20, 20), box(tt, -100, 100), box(rt, -20, 20), box(cd, 10, 30),
                                 box(co, -10, 10), box([A.g4, A.g5, A.g6], 0.01, 1)],
                     positive=[*cd, A.g4, A.g5, A.g6], zero_at=list(z) + list(tt) + list(rt),
                     assumptions=["J = J^T > 0 (Hypothesis 1), written J = C C^T", "gamma_4..6 > 0"])


def _L_operator(printed: bool):
    def build() -> Statement:
        """J a = L(a) theta with theta = [J11, J22, J33, J23, J13, J12] (above eq. 31)."""
        J, a = _sym3("J"), symbols_vec("a")
        L = _printed_L(a) if printed else c.inertia_operator(a)
        return Statement(L * c.inertia_parameters(J), "==", J * a,
                         [box(a, -1, 1), spd_dominant(J, (200, 700), 60)])
    return build


def _eq30() -> Statement:
    """Eq. 30: J s2-dot along eqs. 14, 20 (any tau)."""
    A = _Attitude(opaque=True, law=False, adapt=False)
    rhs = c.attitude_surface_dynamics(A.J, A.omega, A.omega_e, A.sig, A.L2, A.n2, A.tau, A.d_tau)
    return statement(A.Js2dot(), "==", rhs, A.domain(), assumptions=["any tau (before eq. 34)"])


def _eq31(Y: str):
    def build() -> Statement:
        """Eq. 31: J s2-dot = Y (theta0 + theta_Delta) + J n2 + tau + d_tau, theta0 + theta_Delta = theta(J)."""
        A = _Attitude(opaque=True, Y=Y, law=False, adapt=False)
        rhs = A.Y * A.theta + A.J * A.n2 + A.tau + A.d_tau
        return statement(A.Js2dot(), "==", rhs, A.domain(), assumptions=["any tau (before eq. 34)"])
    return build


def _eq33(Y: str):
    def build() -> Statement:
        """Eq. 33: V2-dot along eqs. 14, 20, any tau and estimate rates."""
        A = _Attitude(opaque=True, Y=Y, law=False, adapt=False)
        rhs = c.dot(A.s2, A.Y * A.theta + A.J * A.n2 + A.tau + A.d_tau) + A.adapt_terms
        return statement(A.V2dot, "==", rhs, A.domain(), assumptions=["any tau, any estimate rates"])
    return build


def _eq35() -> Statement:
    """Eq. 35: eq. 33 with the law (34) substituted (estimate rates still free)."""
    A = _Attitude(opaque=True, adapt=False)
    s2, sg = A.s2, c.sgn(A.s2)
    rhs = (-c.dot(s2, A.K2 * s2) + c.dot(s2, A.J * A.n2) + c.dot(s2, A.d_tau) - c.dot(s2, A.Y * A.th_tilde)
           - c.dot(s2, A.rt_hat * sg) - c.dot(s2, A.rJ_hat * A.wt2 * sg) + A.adapt_terms)
    return statement(A.V2dot, "==", rhs, A.domain(), assumptions=["eq. 34 substituted, estimate rates free"])


def _v2dot_identity() -> Statement:
    """Eqs. 35-36: with eq. 36 the estimation errors cancel:
    V2-dot = -s2^T K2 s2 + s2^T (J n2 + d_tau) - (rho_tau + rho_J |w_t|^2) |s2|_1."""
    A = _Attitude(opaque=True)
    rhs = (-c.dot(A.s2, A.K2 * A.s2) + c.dot(A.s2, A.J * A.n2 + A.d_tau)
           - (A.rho_tau + A.rho_J * A.wt2) * c.norm1(A.s2))
    return statement(A.V2dot, "==", rhs, A.domain(), assumptions=["eqs. 34, 36 substituted"])


def _closed_loop_37() -> Statement:
    """Eq. 37: J s2-dot = -K2 s2 - Y theta~ + J n2 + d_tau - (rho^_tau + rho^_J |w_t|^2) sgn(s2)."""
    A = _Attitude(opaque=True)
    rhs = (-A.K2 * A.s2 - A.Y * A.th_tilde + A.J * A.n2 + A.d_tau
           - (A.rt_hat + A.rJ_hat * A.wt2) * c.sgn(A.s2))
    return statement(A.Js2dot(), "==", rhs, A.domain(), assumptions=["eq. 34 substituted"])


def _n2_bound() -> Statement:
    """The step under eq. 36: ||J n2|| <= rho_J ||w - w_e||^2 with rho_J = ||J|| ||J_t^-1|| ||J_t||."""
    A = _Attitude(exact_inverse=False)
    return statement(c.norm2(A.J * A.n2), "<=", A.rho_J * A.wt2, A.domain(), symbolic=False,
                     assumptions=["R = R(sigma_e) (eq. 9, corrected): ||R|| = 1", "||S(a)|| = ||a||",
                                  "rho_J = ||J|| ||J_t^-1|| ||J_t||, J, J_t > 0"])


def _v2dot_bound() -> Statement:
    """Eq. 36's chain: V2-dot <= -s2^T K2 s2 under ||d_tau|| <= rho_tau, rho_J = ||J|| ||J_t^-1|| ||J_t||."""
    A = _Attitude(exact_inverse=False)
    return statement(A.V2dot, "<=", -c.dot(A.s2, A.K2 * A.s2), A.domain(), symbolic=False,
                     assumptions=["||d_tau|| <= rho_tau (Hypothesis 2)", "rho_J = ||J|| ||J_t^-1|| ||J_t||",
                                  "||S(a)|| = ||a||, ||R|| = 1, ||s||_2 <= ||s||_1 (the paper's steps)"])


def _v2_shadow_switch() -> Statement:
    """|sigma_e| <= 1 (the paper's constraint, used in the proof) needs the shadow-set switch
    sigma -> -sigma/|sigma|^2 when |sigma_e| reaches 1 moving outwards (sigma^T omega_e > 0); V2 must
    then not jump up: V2(shadow) <= V2(sigma).  The estimate errors do not change at the switch, so they
    are set to 0 here (the jump is all in s2).  The paper's J and Lambda2 = 0.2 I."""
    A = _Attitude(opaque=True, exact_inverse=False)
    sig, we = A.sig, A.omega_e
    zero6 = sp.zeros(6, 1)

    def V2(sigma):
        return c.attitude_lyapunov(A.J, c.attitude_surface(we, sigma, A.L2), zero6, 0, 0, A.g4, A.g5, A.g6)

    def outward(z, env):
        s = np.column_stack([env[x] for x in sig])
        w = 0.1 * z
        dotp = np.sum(s * w, axis=1, keepdims=True)
        return np.where(dotp < 0, w - 2 * dotp * s, w)          # reflect into sigma^T omega_e >= 0

    dom = [unit_vector(list(sig), "|sigma_e| = 1"),
           custom(list(we), 3, outward, "|omega_e| <= 0.1 sqrt(3) (reflected), sigma_e^T omega_e >= 0"),
           fixed(upper(A.J), [J_PAPER[i, j] for i, j in UPPER]), fixed(A.l2, [0.2, 0.2, 0.2])]
    return Statement(V2(mrp_shadow(sig)), "<=", V2(sig), dom, symbolic=False,
                     assumptions=["|sigma_e| = 1, sigma_e^T omega_e >= 0 (leaving the unit ball)",
                                  "the paper's J and Lambda2 = 0.2 I"])
_YY_NOTE = ("Printed Y ends with - L(L2 G(sigma_e) w_e); eq. 30 has + J L2 G(sigma_e) w_e, so the printed Y "
            "misses J s2-dot by 2 L(L2 G w_e) theta (L as corrected, to isolate the sign).")


CLAIMS = [
    claim("attitude.V2_definite", "attitude", "abstract", "32",
          "V2 is positive definite in (s2, theta~, rho~_tau, rho~_J) for J > 0", _v2_positive),
    claim("attitude.L_operator", "attitude", "abstract", "31 (L)",
          "J a = L(a) theta, theta = [J11, J22, J33, J23, J13, J12]", _L_operator(True), _L_operator(False),
          correction="row 1 of L = [a1, 0, 0, 0, a3, a2]",
          note="Row 1 is printed with five entries [a1 0 0 a3 a2]; read as the first five columns it gives "
               "J11 a1 + J23 a3 + J13 a2 instead of J11 a1 + J12 a2 + J13 a3."),
    claim("attitude.surface_dynamics", "attitude", "abstract", "29-30",
          "J s2-dot along eqs. 14, 20 equals eq. 30", _eq30),
    claim("attitude.regressor_form", "attitude", "abstract", "31",
          "J s2-dot = Y (theta0 + theta_Delta) + J n2 + tau + d_tau", _eq31("printed"), _eq31("code"),
          correction="Y = L(S(w_e)(w - w_e)) - S(w) L(w) + L(L2 G(sigma_e) w_e)", note=_YY_NOTE),
    claim("attitude.eq33_identity", "attitude", "abstract", "33",
          "V2-dot = s2^T[Y theta + J n2 + tau + d_tau] + estimate terms (any tau)", _eq33("printed"),
          _eq33("code"), correction="Y = L(S(w_e)(w - w_e)) - S(w) L(w) + L(L2 G(sigma_e) w_e)",
          note="Inherits the printed Y of eq. 31: residual 2 s2^T L(L2 G w_e) theta."),
    claim("attitude.eq35_identity", "attitude", "abstract", "34-35",
          "V2-dot under the law (34) equals eq. 35 (estimate rates free)", _eq35,
          note="With Y as corrected; the law and the printed line use the same Y, so the step itself holds for "
               "either Y given eq. 31."),
    claim("attitude.V2dot_identity", "attitude", "abstract", "33-36",
          "V2-dot along eqs. 14, 20 under eqs. 34, 36: the estimation errors cancel", _v2dot_identity,
          note="With Y as corrected under eq. 31 (with the printed Y in the law this step fails too, by eq. 31)."),
    claim("attitude.closed_loop", "attitude", "abstract", "37",
          "closed loop J s2-dot = -K2 s2 - Y theta~ + J n2 + d_tau - (rho^_tau + rho^_J ‖w_t‖^2) sgn(s2)",
          _closed_loop_37, note="Printed with Y theta-double-dot (an extraction artefact for theta~)."),
    claim("attitude.n2_bound", "attitude", "spacecraft", "20, 36",
          "‖J n2‖ <= rho_J ‖w - w_e‖^2, rho_J = ‖J‖ ‖J_t^-1‖ ‖J_t‖", _n2_bound,
          note="Uses ||R|| = ||R^T|| = 1, true for the corrected eq. 9 only (see c004.model.eq9_rotation)."),
    claim("attitude.V2dot_bound", "attitude", "abstract", "36-37",
          "V2-dot <= -s2^T K2 s2", _v2dot_bound),
    claim("attitude.V2_shadow_switch", "attitude", "spacecraft", "14, 32",
          "‖sigma_e‖ <= 1 via the shadow-set switch: V2 does not jump up at the switch", _v2_shadow_switch,
          about="paper",
          note="Eq. 14 leaves the unit ball; keeping ‖sigma_e‖ <= 1 (assumed in the proof) needs the switch "
               "sigma -> -sigma at ‖sigma‖ = 1, which changes V2 by -2 w_e^T J L2 sigma: positive for some "
               "outward crossings when J L2 is not a multiple of I. V2 is then only piecewise continuous; rpo "
               "switches too (principal_mrp), so the proof's monotone V does not cover the switch."),
]
