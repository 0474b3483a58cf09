"""002, V3 (eqs. 39-43, Theorem 1 iii): the tracking errors."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...physics.rotations import dot, skew
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
    fixed,
    unit_quaternion,
)
from .common import _S, PAPER_GAINS, _nrm
from .model import _loop_domain

claim = claim_factory(__name__)

# =========================================================================== V3 (eqs. 39-43)

def _V3(S: _S):
    return dot(S.qv, S.qv) + (1 - S.q0) ** 2 + dot(S.r, S.r) / 2


def _v3_definite() -> Statement:
    S = _S()
    e0 = sp.Symbol("e_0", real=True)            # e0 = 1 - q0
    return statement(_V3(S).subs(S.q0, 1 - e0), ">", 0, [box(S.qv, -1, 1), box(e0, 0, 2), box(S.r, -20, 20)],
                     zero_at=[*S.qv, e0, *S.r], assumptions=["e0 = 1 - q0"])


def _v3_upper() -> Statement:
    S = _S()
    return statement(_V3(S), "<=", dot(S.qv, S.qv) + 4 + dot(S.r, S.r) / 2,
                     [unit_quaternion(S.q), box(S.r, -20, 20)], symbolic=False,
                     assumptions=["unit quaternion"])


def _v3_dot_identity() -> Statement:
    """Eq. 41 (equalities): V3_dot = -2 q0_dot + r^T r_dot
    = q^T(s1 - k1 q + k2 tanh chi1) + r^T(s2 - k5 r + k6 tanh chi2 - C_t r)."""
    S = _S()
    s1 = c.sliding_surface_attitude(S.w, S.qv, S.chi1, S.k1, S.k2)
    s2 = c.sliding_surface_position(S.v, S.r, S.chi2, S.k5, S.k6)
    lhs = lie_derivative(_V3(S), [S.q, S.r], [c.relative_quaternion_rate(S.q, S.w),
                                              c.relative_position_rate(S.v, S.C_t, S.r)])
    rhs = (dot(S.qv, s1 - S.k1 * S.qv + S.k2 * c.tanh_vec(S.chi1))
           + dot(S.r, s2 - S.k5 * S.r + S.k6 * c.tanh_vec(S.chi2) - S.C_t * S.r))
    return statement(lhs, "==", rhs, _loop_domain(S))


class _Tracking:
    """V3 along the kinematics (eqs. 2-3, 7) with w~, v~ solved from the surfaces eqs. 15-16 for given
    s1, s2 (||s_j|| <= o_j, Theorem 1 i), C_t = (w~ + R w_t)^x = W^x (skew)."""

    def __init__(self):
        S = self.S = _S()
        self.W = symbols_vec("W")
        self.o1, self.o2 = sp.symbols("o_1 o_2", positive=True)
        z = sp.zeros(3, 1)
        w = S.s1 - c.sliding_surface_attitude(z, S.qv, S.chi1, S.k1, S.k2)
        v = S.s2 - c.sliding_surface_position(z, S.r, S.chi2, S.k5, S.k6)
        C_t = skew(self.W)
        self.V3 = _V3(S)
        self.V3dot = lie_derivative(self.V3, [S.q, S.r], [c.relative_quaternion_rate(S.q, w),
                                                          c.relative_position_rate(v, C_t, S.r)])
        self.Ct_norm = _nrm(self.W)

    def domain(self):
        S = self.S
        return [unit_quaternion(S.q), box(S.r, -20, 20), box(S.chi1, -3, 3), box(S.chi2, -3, 3),
                box([self.o1, self.o2], 0.001, 1), ball(S.s1, self.o1), ball(S.s2, self.o2),
                box([S.k1, S.k5], 0.5, 5), box([S.k2, S.k6], 0.001, 1), box(self.W, -0.5, 0.5)]

    assumptions = ["||s1|| <= o1, ||s2|| <= o2 (Theorem 1 i)", "unit quaternion", "k1, k5 >= 1/2"]


def _v3_bound(corrected: bool):
    def build() -> Statement:
        T = _Tracking()
        S = T.S
        qq, rr = dot(S.qv, S.qv), dot(S.r, S.r)
        if corrected:
            rhs = (-(S.k1 - sp.S.Half) * (qq + 4) + 4 * (S.k1 - sp.S.Half) + T.o1**2 + 3 * S.k2**2
                   - (S.k5 - sp.S.Half) * rr + T.o2**2 + 3 * S.k6**2)
        else:
            rhs = (-(S.k1 - sp.S.Half) * (qq + 4) + T.o1**2 + S.k2**2 + 2 * (S.k1 - sp.S.Half)
                   - (S.k5 + T.Ct_norm - sp.S.Half) * rr + T.o2**2 + S.k6**2)
        return statement(T.V3dot, "<=", rhs, T.domain(), symbolic=False, residual_seconds=1, assumptions=T.assumptions)
    return build


def _v3_constants(T: _Tracking, corrected: bool):
    S = T.S
    if corrected:
        rate = sp.Min(S.k1 - sp.S.Half, 2 * (S.k5 - sp.S.Half))
        const = 4 * (S.k1 - sp.S.Half) + T.o1**2 + 3 * S.k2**2 + T.o2**2 + 3 * S.k6**2
    else:
        rate = S.k1 + 2 * S.k5 + 2 * T.Ct_norm - sp.Rational(3, 2)
        const = T.o1**2 + S.k2**2 + 2 * (S.k1 - sp.S.Half) + T.o2**2 + S.k6**2
    return rate, const


def _v3_exponential(corrected: bool):
    """Eq. 41 (last line): V3_dot <= -(k1 + 2 k5 + 2||C_t|| - 3/2) V2 + o1^2 + k2^2 + 2(k1 - 1/2) + o2^2 + k6^2."""
    def build() -> Statement:
        T = _Tracking()
        rate, const = _v3_constants(T, corrected)
        return statement(T.V3dot, "<=", -rate * T.V3 + const, T.domain(), symbolic=False, residual_seconds=1,
                         assumptions=T.assumptions)
    return build


def _informative(corrected: bool):
    """Theorem 1 iii from eq. 41: the ultimate bound Delta3/rho3 of V3 >= ||q~_v||^2 must be < 1 to say
    anything about q~_v (||q~_v|| <= 1 always).  At the paper's gains (k1 = 2, k2 = 0.1, k5 = 0.5,
    k6 = 0.001, ||C_t|| ~ nu_dot = 1.3e-3 rad/s) and any small o1, o2."""
    def build() -> Statement:
        T = _Tracking()
        S = T.S
        rate, const = _v3_constants(T, corrected)
        g = PAPER_GAINS
        dom = [fixed([S.k1, S.k2, S.k5, S.k6], [g["k1"], g["k2"], g["k5"] + 1e-3 * corrected, g["k6"]]),
               box([T.o1, T.o2], 0.0, 0.1), box(T.W, -0.001, 0.001)]
        return statement(sp.S.One, ">", const / rate, dom, symbolic=False, residual_seconds=1,
                         assumptions=["paper gains", "o1, o2 <= 0.1",
                                      "k5 = 0.501 (rate > 0)" if corrected else "k5 = 0.5"])
    return build


def _rate_bounds() -> Statement:
    """Eqs. 42-43: |w~_i| <= o1 + k1 o3 + k2 tanh(c1), |v~_i| <= o2 + k5 o4 + k6 tanh(c2)."""
    S = _S()
    o = sp.symbols("o_1:5", positive=True)
    c1, c2 = sp.symbols("c_1 c_2", positive=True)
    z = sp.zeros(3, 1)
    w = S.s1 - c.sliding_surface_attitude(z, S.qv, S.chi1, S.k1, S.k2)
    v = S.s2 - c.sliding_surface_position(z, S.r, S.chi2, S.k5, S.k6)
    lhs = sp.Matrix([sp.Abs(x) for x in list(w) + list(v)])
    rhs = sp.Matrix([o[0] + S.k1 * o[2] + S.k2 * sp.tanh(c1)] * 3 + [o[1] + S.k5 * o[3] + S.k6 * sp.tanh(c2)] * 3)
    dom = [box(list(o), 0.001, 1), box([c1, c2], 0.01, 3), ball(S.s1, o[0]), ball(S.s2, o[1]),
           ball(S.qv, o[2]), ball(S.r, o[3]), ball(S.chi1, c1), ball(S.chi2, c2),
           box([S.k1, S.k5], 0.5, 5), box([S.k2, S.k6], 0.001, 1)]
    return statement(lhs, "<=", rhs, dom, symbolic=False, residual_seconds=1,
                     assumptions=["||s_j|| <= o_j, ||q~_v|| <= o3, ||r~|| <= o4, ||chi_j|| <= c_j (Omega_2)"])


CLAIMS = [
    claim("V3.definite", "tracking errors", "abstract", "39",
          "V3 = q~_v^T q~_v + (1 - q~0)^2 + 1/2 r~^T r~ is positive definite", _v3_definite),
    claim("V3.upper_bound", "tracking errors", "abstract", "40",
          "V3 <= q~_v^T q~_v + 4 + 1/2 r~^T r~", _v3_upper),
    claim("V3.derivative_identity", "tracking errors", "spacecraft", "2-3, 7, 15-16, 41",
          "V3_dot along eqs. 2-3, 7 = q~_v^T(s1 - k1 q~_v + k2 tanh chi1) + r~^T(s2 - k5 r~ + k6 tanh chi2 - C_t r~)",
          _v3_dot_identity),
    claim("V3.bound", "tracking errors", "abstract", "41",
          "V3_dot <= -(k1 - 1/2)(q~_v^T q~_v + 4) + o1^2 + k2^2 + 2(k1 - 1/2) - (k5 + ||C_t|| - 1/2)||r~||^2 "
          "+ o2^2 + k6^2",
          _v3_bound(False), _v3_bound(True),
          correction="... + 4(k1 - 1/2) + o1^2 + 3 k2^2 - (k5 - 1/2)||r~||^2 + o2^2 + 3 k6^2",
          note="r~^T C_t r~ = 0, so no -||C_t|| ||r~||^2 decay exists (the printed condition k5 > 1/2 - ||C_t|| "
               "becomes k5 > 1/2); adding and removing (k1 - 1/2)(.. + 4) needs 4(k1 - 1/2), not 2; "
               "||tanh chi||^2 <= 3 gives 3 k2^2."),
    claim("V3.exponential", "tracking errors", "abstract", "41",
          "V3_dot <= -(k1 + 2 k5 + 2||C_t|| - 3/2) V3 + o1^2 + k2^2 + 2(k1 - 1/2) + o2^2 + k6^2",
          _v3_exponential(False), _v3_exponential(True),
          correction="V3_dot <= -min(k1 - 1/2, 2(k5 - 1/2)) V3 + 4(k1 - 1/2) + o1^2 + 3 k2^2 + o2^2 + 3 k6^2",
          note="Printed with V2, typed with V3 (meant); it still fails: the sum of the two rates, the constant "
               "2(k1 - 1/2) and the -||C_t|| term.  At the paper's k5 = 0.5 the corrected rate is 0 (c002.gains.k5)."),
    claim("V3.informative", "tracking errors", "abstract", "40-41, Theorem 1 iii",
          "eq. 41's ultimate bound on V3 (>= ||q~_v||^2) is below 1, so it bounds q~_v",
          _informative(False), _informative(True), about="paper",
          correction="none within this argument: needs e.g. V3_att = 2(1 - q~0) and ||q~_v||^2 >= 1 - q~0 (q~0 >= 0)",
          note="Bounding (1 - q~0)^2 by 4 (eq. 40) puts 4(k1 - 1/2)/(k1 - 1/2) = 4 into the ultimate bound: the "
               "argument cannot show q~_v small (printed constants: ~2 at the paper's gains)."),
    claim("V3.rate_bounds", "tracking errors", "abstract", "15-16, 42-43",
          "|w~_i| <= o1 + k1 o3 + k2 tanh(c1), |v~_i| <= o2 + k5 o4 + k6 tanh(c2)", _rate_bounds),
]
