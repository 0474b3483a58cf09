"""002, V1 (eqs. 26-34, Theorem 1 i): the sliding surfaces and the adaptation."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c002 as c
from ...physics.rotations import dot
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
    fixed,
    spd_rotated,
    upper,
)
from .common import _S, PAPER_GAINS, _nrm, _sym_matrix, _tanh_form
from .model import _eq19_rhs, _eq20_rhs, _Loop, _loop_domain

claim = claim_factory(__name__)

# =========================================================================== V1 (eqs. 26-34)

def _V1(S: _S, s1, s2, J, half_beta: bool, part: str = "all"):
    """Eq. 26: 1/2 s1^T J s1 + 1/2 m s2^T s2 + sum alpha~_i^2 / beta_i (printed) or / (2 beta_i)."""
    at, k = S.atilde, (2 if half_beta else 1)
    att = dot(s1, J * s1) / 2 + sum(at[i] ** 2 / (k * S.beta[i]) for i in range(3))
    pos = S.m * dot(s2, s2) / 2 + sum(at[i] ** 2 / (k * S.beta[i]) for i in range(3, 9))
    return {"att": att, "pos": pos, "all": att + pos}[part]


def _v1_definite(half_beta: bool):
    def build() -> Statement:
        S = _S()
        at = sp.Matrix(sp.symbols("alphatilde_1:10", real=True))
        V = _V1(S, S.s1, S.s2, S.Jd, half_beta).subs(dict(zip(S.alpha, at + S.ahat, strict=True)))
        return statement(V, ">", 0, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(at, -5, 5), box(S.ahat, -1, 5),
                                     box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200),
                                     box(S.beta, 0.001, 10)],
                         positive=[*S.Jd.diagonal(), S.m, *S.beta], zero_at=list(S.s1) + list(S.s2) + list(at),
                         assumptions=["J = diag(J_1, J_2, J_3) > 0 (Table 1)", "m > 0", "beta_i > 0"])
    return build


def _v1_chain(half_beta: bool):
    """Eqs. 26-27 (first line): V1_dot = s1^T J s1_dot + s2^T m s2_dot - sum alpha~_i alpha^_i_dot / beta_i."""
    def build() -> Statement:
        S = _S()
        s1d, s2d, ad = symbols_vec("s1dot"), symbols_vec("s2dot"), symbols_vec("alphahatdot", 9)
        V = _V1(S, S.s1, S.s2, S.J, half_beta)
        lhs = lie_derivative(V, [S.s1, S.s2, S.ahat], [s1d, s2d, ad])
        rhs = (dot(S.s1, S.J * s1d) + S.m * dot(S.s2, s2d)
               - sum(S.atilde[i] * ad[i] / S.beta[i] for i in range(9)))
        return statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.ahat, -1, 5),
                                          box(S.alpha, 0, 5), box(S.beta, 0.001, 10), box(S.m, 20, 200),
                                          spd_rotated(S.J, 5, 40), box(s1d, -1, 1), box(s2d, -1, 1), box(ad, -1, 1)],
                         residual_seconds=3)
    return build


def _v1_time_varying() -> Statement:
    """Eq. 27 (first line) when J and m vary (Assumption 2: 'unknown time-varying'): V1_dot gains
    1/2 s1^T J_dot s1 + 1/2 m_dot ||s2||^2 that eq. 27 (and the proof) drop."""
    S = _S()
    s1d, s2d, ad = symbols_vec("s1dot"), symbols_vec("s2dot"), symbols_vec("alphahatdot", 9)
    Jdot, mdot = _sym_matrix("Jdot"), sp.Symbol("mdot", real=True)
    V = _V1(S, S.s1, S.s2, S.J, True)
    lhs = lie_derivative(V, [S.s1, S.s2, S.ahat, upper(S.J), S.m], [s1d, s2d, ad, upper(Jdot), mdot])
    rhs = (dot(S.s1, S.J * s1d) + S.m * dot(S.s2, s2d) - sum(S.atilde[i] * ad[i] / S.beta[i] for i in range(9)))
    return statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.ahat, -1, 5), box(S.alpha, 0, 5),
                                      box(S.beta, 0.001, 10), box(S.m, 20, 200), spd_rotated(S.J, 5, 40),
                                      spd_rotated(Jdot, -0.01, 0.01), box(mdot, -0.05, 0), box(s1d, -1, 1),
                                      box(s2d, -1, 1), box(ad, -1, 1)],
                      assumptions=["J(t), m(t) (Assumption 2)", "J_dot symmetric, m_dot <= 0 (fuel use)"],
                      residual_seconds=3)


def _v1_closed_loop(k_rdot: str):
    """Eq. 27 (second line) along the full closed loop, V1 with 1/(2 beta_i)."""
    def build() -> Statement:
        S = _S()
        L = _Loop(S)
        V = _V1(S, L.s1, L.s2, S.J, True)
        lhs = _tanh_form(lie_derivative(V, L.states, L.rates))
        k = {"k2": S.k2, "k5": S.k5}[k_rdot]
        rhs = (dot(L.s1, _eq19_rhs(S)) + dot(L.s2, _eq20_rhs(S, k))
               - sum(S.atilde[i] * L.ahat_dot[i] / S.beta[i] for i in range(9)))
        return statement(lhs, "==", rhs, _loop_domain(S),
                         assumptions=["eqs. 17-18 use the plant's J, m", "alpha constant",
                                      "cosh^2 = 1/(1 - tanh^2)"], residual_seconds=3)
    return build


def _regressors(S: _S, s1, s2):
    """||s_j|| times the bounds' regressors of eqs. 21-22, typed from eq. 25 (i = 1..9)."""
    n1, n2, w, v, r = _nrm(s1), _nrm(s2), _nrm(S.w), _nrm(S.v), _nrm(S.r)
    return [n1 * w**2, n1 * w, n1, n2 * w * v, n2 * w * r, n2 * w, n2 * v, n2 * r, n2]


def _adaptation(printed: bool):
    """Eq. 25 into eq. 29: -sum alpha~_i alpha^_i_dot / beta_i = -sum alpha~_i ||s|| y_i
    + sum gamma_i alpha~_i alpha^_i."""
    def build() -> Statement:
        S = _S()
        Y = _regressors(S, S.s1, S.s2)
        if printed:     # eq. 25 as printed: eight laws, none for alpha^_7
            rates = sp.Matrix([0 if i == 6 else S.beta[i] * (Y[i] - S.gamma[i] * S.ahat[i]) for i in range(9)])
        else:
            rates = c.adaptive_rates(S.s1, S.s2, S.w, S.v, S.r, S.ahat, S.beta, S.gamma)
        Va = sum(S.atilde[i] ** 2 / (2 * S.beta[i]) for i in range(9))
        lhs = lie_derivative(Va, [S.ahat], [rates])
        rhs = sum(-S.atilde[i] * Y[i] + S.gamma[i] * S.atilde[i] * S.ahat[i] for i in range(9))
        return statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.w, -1, 1), box(S.v, -2, 2),
                                          box(S.r, -20, 20), box(S.ahat, -1, 5), box(S.alpha, 0, 5),
                                          box(S.beta, 0.001, 10), box(S.gamma, 0.1, 2)])
    return build


def _lemma2_unit(corrected: bool):
    """Eq. 29's step for the k3 (k7) term: -k ||s||^2 / sqrt(||s||^2 + eps^2) <= -k ||s|| + eps (printed)."""
    def build() -> Statement:
        x, k, e = sp.symbols("snorm k varepsilon", positive=True)
        rhs = -k * x + (k * e if corrected else e)
        return statement(-k * x**2 / sp.sqrt(x**2 + e**2), "<=", rhs,
                         [box(e, 0.001, 0.1),
                          custom([x], 1, lambda z, env: (10.0 ** (3 * (z + 1)) - 1) * env[e][:, None],
                                 "0..1e6 eps, log-spaced"),
                          box(k, 0.01, 10)], symbolic=False, residual_seconds=1,
                         assumptions=["k > 0, eps > 0, ||s|| >= 0"])
    return build


def _near_eps(s, eps, hi: float):
    """A vector s = direction x magnitude, ||s|| log-uniform in [eps/20, hi] (eps drawn before)."""
    def draw(z, env):
        u = z[:, :3]
        d = u / np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-12)
        lo = 0.05 * env[eps]
        mag = lo * (hi / lo) ** ((z[:, 3] + 1.0) * 0.5)
        return d * mag[:, None]
    return custom(s, 4, draw, f"||.|| log-uniform in [eps/20, {hi:g}]")


class _Abstract:
    """Eqs. 19-22 in their abstract form: J s1_dot = eps_r + Phi1, m s2_dot = eps_t + Phi2 with
    ||Phi1|| <= alpha1 |w|^2 + alpha2 |w| + alpha3 and ||Phi2|| <= the bound of eq. 22 (Phi drawn in
    those balls), eps_r, eps_t the laws eqs. 23-24, alpha^ the adaptation eq. 25 (all from the module).
    J = diag(J1, J2, J3) (Table 1) so that ||J||_max is explicit."""

    def __init__(self):
        S = self.S = _S()
        self.Phi1, self.Phi2 = symbols_vec("Phi1"), symbols_vec("Phi2")
        a = S.ahat
        self.eps_r = c.attitude_control(S.s1, S.w, a[0], a[1], a[2], S.k3, S.k4, S.eps)        # eq. 23
        self.eps_t = c.position_control(S.s2, S.w, S.v, S.r, a[3], a[4], a[5], a[6], a[7], a[8],
                                        S.k7, S.k8, S.eps)                                    # eq. 24
        self.ahat_dot = c.adaptive_rates(S.s1, S.s2, S.w, S.v, S.r, S.ahat, S.beta, S.gamma)  # eq. 25
        rates = self.rates = [S.Jd.inv() * (self.eps_r + self.Phi1), (self.eps_t + self.Phi2) / S.m, self.ahat_dot]
        self.V1 = _V1(S, S.s1, S.s2, S.Jd, True)
        self.V1att = _V1(S, S.s1, S.s2, S.Jd, True, "att")
        self.V1pos = _V1(S, S.s1, S.s2, S.Jd, True, "pos")
        self.V1_printed = _V1(S, S.s1, S.s2, S.Jd, False)
        self.V1dot = lie_derivative(self.V1, [S.s1, S.s2, S.ahat], rates)
        n1, n2 = _nrm(S.s1), _nrm(S.s2)
        self.nominal = -S.k3 * n1 - S.k4 * n1**2 - S.k7 * n2 - S.k8 * n2**2
        self.young = sum(S.gamma[i] * S.atilde[i] * S.ahat[i] for i in range(9))

    def domain(self, l_: bool = False, gains: dict | None = None):
        S = self.S
        al = S.alpha
        w, v, r = (lambda env, x=x: np.sqrt(sum(env[s] ** 2 for s in x)) for x in (S.w, S.v, S.r))

        def r1(env):
            """alpha1 |w|^2 + alpha2 |w| + alpha3 (eq. 21)"""
            ww = w(env)
            return env[al[0]] * ww**2 + env[al[1]] * ww + env[al[2]]

        def r2(env):
            """alpha4 |w||v| + alpha5 |w||r| + alpha6 |w| + alpha7 |v| + alpha8 |r| + alpha9 (eq. 22)"""
            ww, vv, rr = w(env), v(env), r(env)
            return (env[al[3]] * ww * vv + env[al[4]] * ww * rr + env[al[5]] * ww + env[al[6]] * vv
                    + env[al[7]] * rr + env[al[8]])

        if gains is None:
            dom = [box([S.k3, S.k7], 0.01, 40), box(S.k4, 0.01, 10), box(S.k8, 0.1, 50), box(S.eps, 0.0001, 0.1),
                   box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200)]
        else:       # the paper's data: its gains, Table 1's J and m
            dom = [fixed([S.k3, S.k4, S.k7, S.k8, S.eps], [gains[n] for n in ("k3", "k4", "k7", "k8", "eps")]),
                   fixed([*S.Jd.diagonal(), S.m], [21.0, 18.0, 16.0, 95.0])]
        # ||s_j|| log-uniform from eps/20 up: Lemma 2's gap peaks at ||s|| ~ 0.79 eps, which a uniform box
        # over [-1, 1] practically never draws
        dom += [_near_eps(S.s1, S.eps, 2.0), _near_eps(S.s2, S.eps, 5.0), box(S.w, -1, 1), box(S.v, -2, 2),
                box(S.r, -20, 20), box(S.ahat, -1, 5), box(al, 0, 5), box(S.beta, 0.001, 10), box(S.gamma, 0.1, 2),
                ball(self.Phi1, r1), ball(self.Phi2, r2)]
        if l_:
            dom.append(box(S.l, 0.5, 5))
        return dom

    assumptions = ["||Phi1|| <= alpha1 |w|^2 + alpha2 |w| + alpha3 (eq. 21)", "||Phi2|| <= eq. 22's bound",
                   "J = diag(J1, J2, J3) > 0, m > 0", "alpha^ of any sign"]


def _v1_bound(printed: bool, gains: dict | None = None):
    """Eq. 29: V1_dot <= -k3|s1| - k4|s1|^2 - k7|s2| - k8|s2|^2 + sum gamma_i alpha~_i alpha^_i + c eps.

    Printed: c = 11, and the sum read with alpha^_i (eq. 29 prints alpha~_i alpha~_i_dot, but eq. 30's
    identity gamma(-alpha~^2 + alpha alpha~) = gamma alpha~ alpha^ shows alpha^ is meant: a hat/dot slip).
    ``gains``: hold the paper's gains and Table 1's J, m."""
    def build() -> Statement:
        A = _Abstract()
        S = A.S
        c_eps = 11 if printed else 9 + S.k3 + S.k7
        rhs = A.nominal + A.young + c_eps * S.eps
        return statement(A.V1dot, "<=", rhs, A.domain(gains=gains), symbolic=False, residual_seconds=1,
                          assumptions=[*A.assumptions, *(["the paper's gains, Table 1's J, m"] if gains else [])])
    return build


def _young() -> Statement:
    """Eq. 30: gamma alpha~ alpha^ = gamma(-alpha~^2 + alpha alpha~)
    <= -gamma(2l-1)/(2l) alpha~^2 + gamma l alpha^2/2."""
    at, al = sp.symbols("alphatilde alpha", real=True)
    g, l_ = sp.symbols("gamma l", positive=True)
    return statement(g * at * (al - at), "<=", -g * (2 * l_ - 1) / (2 * l_) * at**2 + g * l_ * al**2 / 2,
                     [box(at, -5, 5), box(al, 0, 5), box(g, 0.1, 2), box(l_, 0.5, 5)], positive=[g, l_],
                     assumptions=["gamma > 0, l > 0 (l > 1/2 for a negative coefficient)"])


def _rho_delta(A: _Abstract, corrected: bool):
    S = A.S
    idx1, idx2 = range(3), range(3, 9)

    def rate(i):
        return S.beta[i] * S.gamma[i] * (2 * S.l[i] - 1) / S.l[i]

    rho1 = sp.Min(2 * S.k4 / sp.Max(*S.Jd.diagonal()), *[rate(i) for i in idx1])
    rho2 = sp.Min(2 * S.k8 / S.m, *[rate(i) for i in idx2])
    d1 = sum(S.gamma[i] * S.l[i] * S.alpha[i] ** 2 / 2 for i in idx1)
    d2 = sum(S.gamma[i] * S.l[i] * S.alpha[i] ** 2 / 2 for i in idx2)
    if corrected:
        return rho1, rho2, d1 + (3 + S.k3) * S.eps, d2 + (6 + S.k7) * S.eps
    return rho1, rho2, d1 + 4 * S.eps, d2 + 7 * S.eps


def _v1_exponential(corrected: bool):
    """Eqs. 31-33: V1_dot <= -rho1 V1 - rho2 V1 + Delta1 + Delta2 (printed)."""
    def build() -> Statement:
        A = _Abstract()
        rho1, rho2, d1, d2 = _rho_delta(A, corrected)
        if corrected:
            rhs = -rho1 * A.V1att - rho2 * A.V1pos + d1 + d2
        else:
            rhs = -rho1 * A.V1 - rho2 * A.V1 + d1 + d2
        return statement(A.V1dot, "<=", rhs, A.domain(l_=True), symbolic=False, residual_seconds=1,
                         assumptions=[*A.assumptions, "l_i > 1/2", "||J||_max = max(J1, J2, J3)"])
    return build


def _v1_split(part: str):
    """Eqs. 31-33 per subsystem (they decouple): V1att_dot <= -rho1 V1att + Delta1, V1pos_dot <= -rho2 V1pos
    + Delta2 (V1att = 1/2 s1^T J s1 + sum_{i<=3} alpha~_i^2/(2 beta_i), V1pos the rest)."""
    def build() -> Statement:
        A = _Abstract()
        S = A.S
        rho1, rho2, d1, d2 = _rho_delta(A, True)
        V, rho, d = (A.V1att, rho1, d1) if part == "att" else (A.V1pos, rho2, d2)
        Vdot = lie_derivative(V, [S.s1, S.s2, S.ahat], A.rates)
        return statement(Vdot, "<=", -rho * V + d, A.domain(l_=True), symbolic=False, residual_seconds=1,
                          assumptions=[*A.assumptions, "l_i > 1/2", "||J||_max = max(J1, J2, J3)"])
    return build


def _informative_pos() -> Statement:
    """Theorem 1 i at the paper's data: the residual set's ||s2|| <= o2 = sqrt(2 Delta2/(rho2 m)) allows
    ||r~|| up to about o2/k5 once v~ ~ 0; the paper reports 0.3 m.  Most favourable alphas: alpha4..8 = 0,
    alpha9 = sqrt(3) kappa2 + D2 (its tanh and disturbance parts, eq. 22 / Remark 5); l_i free."""
    A = _Abstract()
    S = A.S
    rho1, rho2, d1, d2 = _rho_delta(A, True)
    o2 = sp.sqrt(2 * d2 / (rho2 * S.m))
    g = PAPER_GAINS
    beta = (10, 5, 0.1, 0.01, 0.01, 0.01, 0.001, 0.001, 0.001)
    D2 = 0.002 * (0.5 + np.sqrt(2)) * np.sqrt(3)
    dom = [fixed([S.k5, S.k7, S.k8, S.eps, S.m], [g["k5"], g["k7"], g["k8"], g["eps"], 95.0]),
           fixed(S.beta, beta), fixed(S.gamma, [1.0] * 9),
           fixed(S.alpha, [0.0] * 8 + [np.sqrt(3) * g["kappa2"] + D2]), box(S.l, 0.5001, 10)]
    return statement(o2 / S.k5, "<=", sp.Rational(3, 10), dom, symbolic=False, residual_seconds=0,
                      assumptions=["paper gains, beta, gamma = 1 (scenario)",
                                   "alpha4..8 = 0, alpha9 = sqrt(3) kappa2 + D2", "l_i in (1/2, 10]"])


def _residual_set(corrected: bool):
    """Eq. 34 -> Omega_1: V1's attitude (position) part <= B_j implies ||s_j||^2 <= 2 B_j
    (o_j = sqrt(2 Delta_j/rho_j))."""
    def build() -> Statement:
        S = _S()
        B1, B2 = sp.symbols("B_1 B_2", positive=True)
        Jd = list(S.Jd.diagonal())

        def ell(z, env, which):
            u = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1e-9)
            if which == 1:
                quad = np.maximum(sum(env[Jd[i]] * u[:, i] ** 2 for i in range(3)), 1e-300)
                scale = np.sqrt(2 * env[B1] / quad)
            else:
                scale = np.sqrt(2 * env[B2] / env[S.m])
            return u * (scale * np.minimum(np.linalg.norm(z, axis=1), 1.0))[:, None]

        lhs = sp.Matrix([dot(S.s1, S.s1), dot(S.s2, S.s2)])
        if corrected:
            rhs = sp.Matrix([2 * B1 / sp.Min(*Jd), 2 * B2 / S.m])
        else:
            rhs = sp.Matrix([2 * B1, 2 * B2])
        dom = [box(Jd, 0.1, 40), box(S.m, 0.1, 200), box([B1, B2], 0.001, 10),
               custom(S.s1, 3, lambda z, env: ell(z, env, 1), "1/2 s1^T J s1 <= B1"),
               custom(S.s2, 3, lambda z, env: ell(z, env, 2), "1/2 m s2^T s2 <= B2")]
        return statement(lhs, "<=", rhs, dom, symbolic=False, residual_seconds=1,
                         assumptions=["1/2 s1^T J s1 <= B1, 1/2 m |s2|^2 <= B2 (B_j = Delta_j/rho_j)",
                                      "J = diag(J1, J2, J3), any positive units"])
    return build


CLAIMS = [
    claim("V1.definite", "sliding surfaces", "abstract", "26",
          "V1 is positive definite in (s1, s2, alpha~) (printed 1/beta_i and corrected 1/(2 beta_i))",
          _v1_definite(False), _v1_definite(True)),
    claim("V1.derivative_chain", "sliding surfaces", "abstract", "26, 27",
          "V1_dot = s1^T J s1_dot + s2^T m s2_dot - sum alpha~_i alpha^_i_dot / beta_i",
          _v1_chain(False), _v1_chain(True),
          correction="V1 = 1/2 s1^T J s1 + 1/2 m s2^T s2 + sum alpha~_i^2 / (2 beta_i)",
          note="With the printed sum alpha~_i^2/beta_i the derivative is -2 sum alpha~_i alpha^_i_dot/beta_i; eqs. "
               "31-32's rho (beta_i gamma_i (2l_i - 1)/l_i) also match the 1/(2 beta_i) form."),
    claim("V1.time_varying_inertia", "sliding surfaces", "abstract", "26, 27, Assumption 2",
          "eq. 27's V1_dot = s1^T J s1_dot + s2^T m s2_dot - ... when J(t), m(t) vary (Assumption 2)",
          _v1_time_varying, about="paper",
          correction="V1_dot gains 1/2 s1^T J_dot s1 + 1/2 m_dot ||s2||^2; eq. 19 gains -J_dot (w~ + R w_t) "
                     "(Euler with varying J), neither bounded in eqs. 21-22",
          note="The paper's contribution ii (time-varying J, m) is not covered by its proof: its derivatives treat J, "
               "m as constants.  rpo's model and law take J, m constant (J_nom, m_nom)."),
    claim("V1.closed_loop_identity", "sliding surfaces", "spacecraft", "15-20, 25-27",
          "V1_dot along the full closed loop equals eq. 27's second line",
          _v1_closed_loop("k2"), _v1_closed_loop("k5"),
          correction="m k5 r~_dot in the position bracket (printed m k2 r~_dot)",
          note="Both statements use V1 with 1/(2 beta_i) (the eq. 26 slip is c002.V1.derivative_chain); the "
               "printed k2 in place of k5 leaves m (k5 - k2) s2^T r~_dot.  The adaptation part is the same on both "
               "sides (c002.V1.adaptation_cancels checks it): only the s-part is tested here."),
    claim("V1.adaptation_cancels", "sliding surfaces", "abstract", "25, 29",
          "eq. 25 turns -sum alpha~_i alpha^_i_dot/beta_i into -sum alpha~_i ||s|| y_i + sum gamma_i alpha~_i alpha^_i",
          _adaptation(True), _adaptation(False),
          correction="alpha^_7_dot = beta_7 (||s2|| ||v~|| - gamma_7 alpha^_7) (missing in print)",
          note="Eq. 25 as printed has eight laws; without alpha^_7's, the term alpha~_7 ||s2|| ||v~|| of eq. 22 "
               "stays in V1_dot."),
    claim("V1.lemma2_unit_terms", "sliding surfaces", "abstract", "14, 29",
          "-k ||s||^2/sqrt(||s||^2 + eps^2) <= -k ||s|| + eps (the k3, k7 terms of eqs. 23-24)",
          _lemma2_unit(False), _lemma2_unit(True),
          correction="<= -k ||s|| + k eps (Lemma 2 times k); eq. 29's 11 eps becomes (9 + k3 + k7) eps",
          note="The gap -k||s||^2/sqrt(.) + k||s|| reaches 0.30 k eps, > eps when k > 3.33 (the paper's k3 = 4).  "
               "Corrected form: gap = k x eps^2/(sqrt(x^2+eps^2)(sqrt(x^2+eps^2)+x)) <= k eps/2 for all x; searched "
               "over ||s|| in [0, 1e6 eps]."),
    claim("V1.bound", "sliding surfaces", "abstract", "21-25, 27-29",
          "V1_dot <= -k3||s1|| - k4||s1||^2 - k7||s2|| - k8||s2||^2 + sum gamma_i alpha~_i alpha^_i + c eps",
          _v1_bound(True), _v1_bound(False),
          correction="c = 9 + k3 + k7 (printed 11; the exact worst case is 0.3003 (9 + k3 + k7))",
          note="Typed with alpha^_i (eq. 29 prints alpha~_i alpha~_i_dot, a hat/dot slip: eq. 30 uses alpha^_i).  "
               "11 eps misses the k3, k7 factors of Lemma 2; it fails only for k3 + k7 > 27.6 at ||s_j|| ~ 0.79 eps "
               "(k3, k7 searched in [0.01, 40]); the paper's k3 + k7 = 4.5 passes (c002.gains.eq29_constant)."),
    claim("gains.eq29_constant", "sliding surfaces", "abstract", "29, 46",
          "eq. 29 with the printed 11 eps at the paper's gains (k3 = 4, k4 = 0.5, k7 = 0.5, k8 = 20, eps = 1e-3)",
          _v1_bound(True, PAPER_GAINS), about="paper",
          note="At k3 + k7 = 4.5 the true constant 0.3003 (9 + k3 + k7) eps = 4.1 eps is below 11 eps."),
    claim("V1.young", "sliding surfaces", "abstract", "30",
          "gamma alpha~ alpha^ <= -gamma (2l - 1)/(2l) alpha~^2 + gamma l alpha^2 / 2", _young),
    claim("V1.exponential", "sliding surfaces", "abstract", "29-33",
          "V1_dot <= -rho1 V1 - rho2 V1 + Delta1 + Delta2",
          _v1_exponential(False), _v1_exponential(True),
          correction="-rho1 V1_att - rho2 V1_pos + Delta1 + Delta2 (each rho on its own subsystem; or -min(rho1, "
                     "rho2) V1), Delta1 = ... + (3 + k3) eps, Delta2 = ... + (6 + k7) eps",
          note="-rho1 V1 - rho2 V1 claims the sum of the two rates on all of V1; each rho only bounds its own "
               "subsystem's part (checked separately: c002.V1.exponential_att, c002.V1.exponential_pos)."),
    claim("V1.exponential_att", "attitude", "abstract", "29-34",
          "V1att_dot <= -rho1 V1att + Delta1 (V1att = 1/2 s1^T J s1 + sum_{i<=3} alpha~_i^2/(2 beta_i))",
          None, _v1_split("att"),
          note="The attitude and position parts of V1 decouple (s1 and alpha^_1..3 only in V1att); eq. 34 per "
               "subsystem rests on this and c002.V1.exponential_pos.  Delta1 = ... + (3 + k3) eps."),
    claim("V1.exponential_pos", "position", "abstract", "29-34",
          "V1pos_dot <= -rho2 V1pos + Delta2 (V1pos = 1/2 m ||s2||^2 + sum_{i>=4} alpha~_i^2/(2 beta_i))",
          None, _v1_split("pos"), note="Delta2 = ... + (6 + k7) eps."),
    claim("V1.residual_set", "sliding surfaces", "abstract", "34",
          "V1's parts <= Delta_j/rho_j imply ||s_j|| <= o_j = sqrt(2 Delta_j/rho_j)",
          _residual_set(False), _residual_set(True),
          correction="o1 = sqrt(2 Delta1 / (rho1 lambda_min(J))), o2 = sqrt(2 Delta2 / (rho2 m))",
          note="Dimensional: the printed o_j forgets J and m, so it fails only when lambda_min(J) < 1 or m < 1 in "
               "the chosen units (the search draws J, m from 0.1).  For Table 1's J, m in SI the printed o_j is a "
               "valid, looser bound."),
    claim("V1.informative", "position", "abstract", "22, 31-34, 46, Theorem 1 i",
          "at the paper's data, Theorem 1 i's residual set allows ||r~|| ~ o2/k5 below the published 0.3 m",
          _informative_pos, about="paper",
          note="Even with alpha4..8 = 0 and alpha9 only sqrt(3) kappa2 + D2, rho2 <= beta9 gamma9 (2 l9 - 1)/l9 <= "
               "0.002 gives Delta2/rho2 >= 6000, ||s2|| <= 11 m/s, ||r~|| ~ 22 m: the bound says nothing at the 0.3 m "
               "scale (beta7..9 = 0.001 make rho2 tiny)."),
]
