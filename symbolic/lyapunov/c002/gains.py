"""002, the paper's gains against the conditions of Theorem 1."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ..core import (
    Statement,
    claim_factory,
    statement,
    symbols_vec,
)
from ..domains import (
    box,
    fixed,
)
from .common import _S, PAPER_GAINS, Q0_PAPER, R0_PAPER, _nrm

claim = claim_factory(__name__)

# =========================================================================== gain conditions (paper data)

def _varpi0(S: _S, which: str, u_max):
    """||sat(eps) - eps|| at t = 0 of the paper's scenario (w~ = v~ = 0, chi = 0, alpha^ = 0)."""
    z3 = sp.zeros(3, 1)
    if which == "att":
        q = sp.Matrix(sp.symbols("q0_1:5", real=True))
        s1 = c.sliding_surface_attitude(z3, q[:3, :], z3, S.k1, S.k2)
        e = c.attitude_control(s1, z3, 0, 0, 0, S.k3, S.k4, S.eps)
        sym, vals = list(q), Q0_PAPER
    else:
        r = symbols_vec("r0")
        s2 = c.sliding_surface_position(z3, r, z3, S.k5, S.k6)
        e = c.position_control(s2, z3, z3, r, 0, 0, 0, 0, 0, 0, S.k7, S.k8, S.eps)
        sym, vals = list(r), R0_PAPER
    d = c.saturation(e, u_max) - e
    return _nrm(d), fixed(sym, vals)


def _k_condition(printed: bool) -> Statement:
    """Eq. 41's rates at the paper's gains: printed k1 > 1/2 and k5 > 1/2 - ||C_t|| (||C_t|| ~ nu_dot of the
    target orbit, up to 1.5e-3 rad/s); corrected k1 > 1/2, k5 > 1/2 (r~^T C_t r~ = 0), written
    k - 1/2 >= 1e-6 so that the strict inequality is tested numerically."""
    S = _S()
    W = symbols_vec("W")
    g = PAPER_GAINS
    dom = [fixed([S.k1, S.k5], [g["k1"], g["k5"]]), box(W, -0.0015, 0.0015)]
    if printed:
        return statement(sp.Matrix([S.k1, S.k5]), ">", sp.Matrix([sp.S.Half, sp.S.Half - _nrm(W)]), dom,
                          symbolic=False, residual_seconds=0, assumptions=["||C_t|| = ||W|| <= 2.6e-3 rad/s"])
    eta = sp.Rational(1, 10**6)
    return statement(sp.Matrix([S.k1 - sp.S.Half, S.k5 - sp.S.Half]), ">=", sp.Matrix([eta, eta]), dom[:1],
                      symbolic=False, residual_seconds=0, assumptions=["strict: margin 1e-6"])


def _kappa_condition(which: str, kappa: float, u_max_value: float, note: str):
    def build() -> Statement:
        S = _S()
        u_max = sp.Symbol("u_M", positive=True)
        varpi, qdom = _varpi0(S, which, u_max)
        kap = S.kappa1 if which == "att" else S.kappa2
        g = dict(PAPER_GAINS)
        g["kappa1" if which == "att" else "kappa2"] = kappa
        names = ["k1", "k2", "k3", "k4", "k5", "k6", "k7", "k8", "kappa1", "kappa2", "eps"]
        syms = [S.k1, S.k2, S.k3, S.k4, S.k5, S.k6, S.k7, S.k8, S.kappa1, S.kappa2, S.eps]
        dom = [fixed(syms, [g[n] for n in names]), fixed(u_max, [u_max_value]), qdom]
        return statement(kap, ">", varpi, dom, symbolic=False, residual_seconds=1, trials=4,
                         assumptions=["varpi >= ||sat(eps) - eps|| at t = 0 (a lower bound of varpi)", note])
    return build


CLAIMS = [
    claim("gains.k5", "tracking errors", "abstract", "41, 46, Theorem 1 iii",
          "the paper's k1 = 2, k5 = 0.5 give eq. 41 positive rates (printed: k1 > 1/2, k5 > 1/2 - ||C_t||)",
          lambda: _k_condition(True), lambda: _k_condition(False), about="paper",
          correction="k5 > 1/2 (C_t is skew, r~^T C_t r~ = 0)",
          note="The printed k5 > 1/2 - ||C_t|| holds at k5 = 0.5 only through ||C_t|| > 0, a term that does not exist; "
               "k5 = 0.5 makes the position rate 2(k5 - 1/2) of V3 zero.  k1 = 2 > 1/2 passes."),
    claim("gains.kappa1_varpi1", "auxiliary system", "abstract", "13, 15, 23, 46, Theorem 1 ii",
          "necessary: kappa1 > varpi1(0) with the paper's gains, torque limit 1 N m (rpo's reading)",
          _kappa_condition("att", 2.0, 1.0, "kappa1 = 2 (paper)"), about="paper",
          correction="none checkable at design time: varpi1 = sup_t ||sat(eps_r) - eps_r|| has no a-priori bound",
          note="varpi1 >= ||sat(eps_r(0)) - eps_r(0)|| = 2.67 N m > kappa1 = 2, so condition ii fails (chi1 escapes at "
               "t = 1.705 s in the paper plant).  rpo's kappa1 = 3 (scenarios/002_scenario_kappa3.toml) passes this "
               "t = 0 test, which is necessary only (varpi1 peaks at ~2.9 N m along that run)."),
    claim("gains.kappa2_varpi2", "auxiliary system", "abstract", "13, 16, 24, 46, Theorem 1 ii",
          "necessary: kappa2 > varpi2(0) with the paper's gains and the printed force limit (1)",
          _kappa_condition("pos", 2.0, 1.0, "force limit 1 N as printed ('position subsystem +-1')"), about="paper",
          correction="none checkable at design time: varpi2 = sup_t ||sat(eps_t) - eps_t|| has no a-priori bound",
          note="With the printed labels varpi2(0) = 172 N >> kappa2 = 2.  With rpo's reading (labels swapped, force "
               "limit 100 N, docs/controllers/c002.md) varpi2(0) = 0.5 N < 2 passes this necessary test, but kappa1 "
               "then fails (c002.gains.kappa1_varpi1): no reading satisfies condition ii."),
]
