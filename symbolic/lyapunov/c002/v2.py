"""002, V2 (eqs. 35-38, Theorem 1 ii): the auxiliary anti-saturation system."""

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
)
from .common import _S, DELTA, _nrm, _tanh_form
from .model import _loop_domain

claim = claim_factory(__name__)

# =========================================================================== V2 (eqs. 35-38)

def _V2(S: _S):
    return S.k2 * dot(S.chi1, S.chi1) / 2 + S.k6 * dot(S.chi2, S.chi2) / 2


def _phi_inv_typed(chi):
    """phi^-1 as printed under eq. 18: diag(1 - tanh^2(chi_i))^-1."""
    return sp.diag(*[1 / (1 - sp.tanh(x) ** 2) for x in chi])


def _v2_definite() -> Statement:
    S = _S()
    return statement(_V2(S), ">", 0, [box(S.chi1, -3, 3), box(S.chi2, -3, 3), box([S.k2, S.k6], 0.001, 5)],
                     positive=[S.k2, S.k6], zero_at=list(S.chi1) + list(S.chi2), assumptions=["k2, k6 > 0"])


def _v2_dot_identity() -> Statement:
    """Eq. 36: V2_dot = chi1^T phi1^-1 J^-1 [-kappa1 tanh chi1 + sat - eps] + chi2^T phi2^-1 m^-1 [...]."""
    S = _S()
    rates = [c.aux_attitude_rate(S.chi1, S.J, S.k2, S.kappa1, S.eps_r, S.u_r),
             c.aux_position_rate(S.chi2, S.m, S.k6, S.kappa2, S.eps_t, S.u_t)]
    lhs = _tanh_form(lie_derivative(_V2(S), [S.chi1, S.chi2], rates))
    rhs = (dot(S.chi1, _phi_inv_typed(S.chi1) * S.J.inv() * (-S.kappa1 * c.tanh_vec(S.chi1) + S.u_r - S.eps_r))
           + dot(S.chi2, _phi_inv_typed(S.chi2) / S.m * (-S.kappa2 * c.tanh_vec(S.chi2) + S.u_t - S.eps_t)))
    return statement(lhs, "==", rhs, _loop_domain(S), assumptions=["cosh^2 = 1/(1 - tanh^2)"])


def _lemma1() -> Statement:
    """Eq. 37 (Lemma 1 for vectors): -kappa chi^T tanh(chi) <= -kappa ||chi|| + kappa delta."""
    S = _S()
    return statement(-S.kappa1 * dot(S.chi1, c.tanh_vec(S.chi1)), "<=",
                     -S.kappa1 * _nrm(S.chi1) + S.kappa1 * DELTA,
                     [box(S.chi1, -4, 4), box(S.kappa1, 0.01, 5)], symbolic=False, residual_seconds=1,
                     assumptions=["delta = 0.2785 (Lemma 1, mu = 1)"])


class _Aux:
    """The auxiliary systems of the code with sat(eps) - eps = e, ||e|| <= varpi, J diagonal."""

    def __init__(self):
        S = self.S = _S()
        self.e1, self.e2 = symbols_vec("e_1"), symbols_vec("e_2")
        self.w1, self.w2 = sp.symbols("varpi_1 varpi_2", nonnegative=True)
        self.chi1_dot = c.aux_attitude_rate(S.chi1, S.Jd, S.k2, S.kappa1, S.eps_r, S.eps_r + self.e1)
        self.chi2_dot = c.aux_position_rate(S.chi2, S.m, S.k6, S.kappa2, S.eps_t, S.eps_t + self.e2)

    def domain(self, chi=None):
        S = self.S
        chi = chi or [box(S.chi1, -3, 3), box(S.chi2, -3, 3)]
        return [box([S.kappa1, S.kappa2], 0.1, 5), box([self.w1, self.w2], 0, 5), *chi,
                ball(self.e1, self.w1), ball(self.e2, self.w2), box(S.eps_r, -10, 10), box(S.eps_t, -100, 100),
                box([S.k2, S.k6], 0.001, 1), box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200)]


def _v2_bound(corrected: bool):
    """Eq. 38: V2_dot <= ||phi1^-1 J^-1|| [kappa1 delta - (kappa1 - varpi1)||chi1||] + m^-1 ||phi2^-1|| [...]."""
    def build() -> Statement:
        X = _Aux()
        S = X.S
        lhs = lie_derivative(_V2(S), [S.chi1, S.chi2], [X.chi1_dot, X.chi2_dot])
        M1 = [1 / ((1 - sp.tanh(S.chi1[i]) ** 2) * S.Jd[i, i]) for i in range(3)]
        M2 = [1 / ((1 - sp.tanh(S.chi2[i]) ** 2) * S.m) for i in range(3)]
        if corrected:       # axis by axis (J diagonal): sum_i M_i [kappa delta - (kappa - varpi)|chi_i|]
            rhs = (sum(M1[i] * (S.kappa1 * DELTA - (S.kappa1 - X.w1) * sp.Abs(S.chi1[i])) for i in range(3))
                   + sum(M2[i] * (S.kappa2 * DELTA - (S.kappa2 - X.w2) * sp.Abs(S.chi2[i])) for i in range(3)))
        else:
            rhs = (sp.Max(*M1) * (S.kappa1 * DELTA - (S.kappa1 - X.w1) * _nrm(S.chi1))
                   + sp.Max(*M2) * (S.kappa2 * DELTA - (S.kappa2 - X.w2) * _nrm(S.chi2)))
        return statement(lhs, "<=", rhs, X.domain(), symbolic=False, residual_seconds=1,
                         assumptions=["||sat(eps) - eps|| <= varpi_j", "J = diag(J1, J2, J3) (Table 1)"])
    return build


def _invariant_set() -> Statement:
    """Theorem 1 ii, axis by axis: |chi_ji| >= kappa_j delta/(kappa_j - varpi_j) => chi_ji chi_ji_dot <= 0
    (kappa_j > varpi_j), so chi_j(0) = 0 stays in ||chi_j||_inf <= kappa_j delta/(kappa_j - varpi_j)."""
    X = _Aux()
    S = X.S

    def outside(chi, kap, vp):
        def draw(z, env):
            c0 = env[kap] * float(DELTA) / (env[kap] - env[vp])
            return np.sign(z[:, :3] + 1e-12) * (c0[:, None] + 3 * np.abs(z[:, :3]))
        return custom(chi, 3, draw, "|chi_i| >= kappa delta/(kappa - varpi)")

    dom = [box([S.kappa1, S.kappa2], 0.1, 5),
           custom([X.w1, X.w2], 2, lambda z, env: np.column_stack(
               [(z[:, 0] + 1) * 0.475 * env[S.kappa1], (z[:, 1] + 1) * 0.475 * env[S.kappa2]]),
               "varpi_j in [0, 0.95 kappa_j]"),
           outside(S.chi1, S.kappa1, X.w1), outside(S.chi2, S.kappa2, X.w2),
           ball(X.e1, X.w1), ball(X.e2, X.w2), box(S.eps_r, -10, 10), box(S.eps_t, -100, 100),
           box([S.k2, S.k6], 0.001, 1), box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200)]
    lhs = sp.Matrix([S.chi1[i] * X.chi1_dot[i] for i in range(3)] + [S.chi2[i] * X.chi2_dot[i] for i in range(3)])
    return statement(lhs, "<=", 0, dom, symbolic=False, residual_seconds=1,
                     assumptions=["kappa_j > varpi_j >= ||sat(eps) - eps||", "J diagonal (Table 1)"])


def _invariant_set_printed() -> Statement:
    """Theorem 1 ii as printed: Omega_2 = {||chi_j|| <= kappa_j delta/(kappa_j - varpi_j)} (2-norm) is forward
    invariant, i.e. chi_j^T chi_j_dot <= 0 on (and outside) its boundary sphere."""
    X = _Aux()
    S = X.S

    def outside(chi, kap, vp):
        def draw(z, env):
            c0 = env[kap] * float(DELTA) / (env[kap] - env[vp])
            u = z[:, :3] / np.maximum(np.linalg.norm(z[:, :3], axis=1, keepdims=True), 1e-12)
            return u * (c0 * (1.0 + 0.5 * (z[:, 3] + 1.0) ** 2))[:, None]
        return custom(chi, 4, draw, "||chi|| >= kappa delta/(kappa - varpi)")

    dom = [box([S.kappa1, S.kappa2], 0.1, 5),
           custom([X.w1, X.w2], 2, lambda z, env: np.column_stack(
               [(z[:, 0] + 1) * 0.475 * env[S.kappa1], (z[:, 1] + 1) * 0.475 * env[S.kappa2]]),
               "varpi_j in [0, 0.95 kappa_j]"),
           outside(S.chi1, S.kappa1, X.w1), outside(S.chi2, S.kappa2, X.w2),
           ball(X.e1, X.w1), ball(X.e2, X.w2), box(S.eps_r, -10, 10), box(S.eps_t, -100, 100),
           box([S.k2, S.k6], 0.001, 1), box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200)]
    lhs = sp.Matrix([dot(S.chi1, X.chi1_dot), dot(S.chi2, X.chi2_dot)])
    return statement(lhs, "<=", 0, dom, symbolic=False, residual_seconds=0,
                      assumptions=["kappa_j > varpi_j >= ||sat(eps) - eps||", "J diagonal (Table 1)"])


CLAIMS = [
    claim("V2.definite", "auxiliary system", "abstract", "35",
          "V2 = k2/2 chi1^T chi1 + k6/2 chi2^T chi2 is positive definite", _v2_definite),
    claim("V2.derivative_identity", "auxiliary system", "abstract", "17-18, 36",
          "V2_dot along eqs. 17-18 equals eq. 36", _v2_dot_identity),
    claim("V2.lemma1", "auxiliary system", "abstract", "Lemma 1, 37",
          "-kappa chi^T tanh(chi) <= -kappa ||chi|| + kappa delta (vector form, delta = 0.2785)", _lemma1),
    claim("V2.bound", "auxiliary system", "abstract", "36-38",
          "V2_dot <= ||phi1^-1 J^-1|| [kappa1 delta - (kappa1 - varpi1)||chi1||] + m^-1 ||phi2^-1|| [...]",
          _v2_bound(False), _v2_bound(True),
          correction="sum over axes of (phi^-1 J^-1)_ii [kappa delta - (kappa - varpi)|chi_i|] (J diagonal)",
          note="-kappa chi^T M tanh(chi) <= -kappa ||M|| (||chi|| - delta) takes the largest weight M_ii = "
               "cosh^2(chi_i)/J_i for the negative term; with unequal chi_i it fails (also for Table 1's J)."),
    claim("V2.invariant_set", "auxiliary system", "abstract", "17-18, 38, Theorem 1 ii",
          "kappa_j > varpi_j: Omega_2 = {||chi_j|| <= kappa_j delta/(kappa_j - varpi_j)} is forward invariant",
          _invariant_set_printed, _invariant_set,
          correction="Omega_2 per axis: ||chi_j||_inf <= kappa_j delta/(kappa_j - varpi_j) (printed with ||chi_j||, "
                     "and Theorem 1 ii prints omega_j for varpi_j)",
          note="As printed (2-norm) chi^T chi_dot > 0 on the sphere when the weights cosh^2(chi_i)/J_i differ: "
               "eq. 38's max-weight slip (c002.V2.bound).  With J diagonal each axis of eqs. 17-18 is scalar; the "
               "per-axis bound gives ||chi_j|| <= sqrt(3) kappa_j delta/(kappa_j - varpi_j)."),
]
