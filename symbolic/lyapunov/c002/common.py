"""Shared by the 002 claims: the paper's data (eq. 46, Section IV) and the symbols of the closed loop."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...physics.rotations import dot
from ..core import (
    lie_derivative,
    symbols_vec,
)
from ..scenarios import controller_gains, scenario
from ..units import declare, layout_units

DELTA = sp.Rational(2785, 10000)     # Lemma 1's delta (mu = 1)

# Module-level symbols that mutations name (symbols are equal by name and assumptions).
AHAT = sp.symbols("alphahat_1:10", real=True)
U_R = tuple(symbols_vec("u_r"))

# The paper's Section IV data (eq. 46, "The control parameters are selected as follows").
PAPER_GAINS = {k: v for k, v in controller_gains("002_scenario", "c002").items()
               if k in ("k1", "k2", "kappa1", "k3", "k4", "k5", "k6", "kappa2", "k7", "k8", "eps")}
# Theta(0) 3-2-1 as a quaternion, scalar last: the pursuer's initial attitude (the target's is the identity)
Q0_PAPER = tuple(scenario("002_scenario")["chaser"]["quaternion"])
R0_PAPER = (10.0, 10.0, -10.0)                                  # r~(0) [m]; v~(0) = w~(0) = 0


# =========================================================================== helpers

def _vec_lie(vec, states, rates) -> sp.Matrix:
    """Component-wise time derivative of a vector function of the states."""
    return sp.Matrix([lie_derivative(e, states, rates) for e in vec])


def _tanh_form(expr):
    """cosh(x) -> (1 - tanh(x)^2)^(-1/2) (real x): phi^-1 = cosh^2 becomes 1/(1 - tanh^2)."""
    return expr.replace(lambda e: isinstance(e, sp.cosh),
                        lambda e: (1 - sp.tanh(e.args[0]) ** 2) ** sp.Rational(-1, 2))


def _nrm(x):
    return sp.sqrt(dot(x, x))


def _sym_matrix(name: str) -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"{name}_{min(i, j) + 1}{max(i, j) + 1}", real=True))


class _S:
    """Symbols of 002's closed loop (all real; gains positive)."""

    def __init__(self):
        self.w, self.v, self.r = symbols_vec("omega"), symbols_vec("v"), symbols_vec("r")
        self.q = sp.Matrix(sp.symbols("q_1 q_2 q_3 q_0", real=True))      # scalar last
        self.qv, self.q0 = self.q[:3, :], self.q[3]
        self.chi1, self.chi2 = symbols_vec("chi1"), symbols_vec("chi2")
        self.ahat = sp.Matrix(AHAT)
        self.alpha = sp.Matrix(sp.symbols("alpha_1:10", positive=True))
        self.beta = sp.Matrix(sp.symbols("beta_1:10", positive=True))
        self.gamma = sp.Matrix(sp.symbols("gamma_1:10", positive=True))
        self.l = sp.Matrix(sp.symbols("l_1:10", positive=True))
        (self.k1, self.k2, self.k3, self.k4, self.k5, self.k6, self.k7, self.k8,
         self.kappa1, self.kappa2, self.eps, self.m) = sp.symbols(
            "k_1:9 kappa_1 kappa_2 varepsilon m", positive=True)
        self.J = _sym_matrix("J")
        self.Jd = sp.diag(*sp.symbols("J_1:4", positive=True))
        self.eps_r, self.eps_t = symbols_vec("epsilon_r"), symbols_vec("epsilon_t")
        self.u_r, self.u_t = sp.Matrix(U_R), symbols_vec("u_t")
        self.C_r = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Cr_{i + 1}{j + 1}", real=True))
        self.C_t = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Ct_{i + 1}{j + 1}", real=True))
        self.n_r, self.n_t = symbols_vec("n_r"), symbols_vec("n_t")
        self.d_r, self.d_t = symbols_vec("d_r"), symbols_vec("d_t")
        self.s1, self.s2 = symbols_vec("s_1"), symbols_vec("s_2")

    @property
    def atilde(self):
        return self.alpha - self.ahat

    def gains(self):
        return [self.k1, self.k2, self.k3, self.k4, self.k5, self.k6, self.k7, self.k8,
                self.kappa1, self.kappa2, self.eps, self.m]


# =========================================================================== claims



# =========================================================================== units of the domain symbols
# (the report prints them with each search domain; ..units)

#: alpha_1..9 of eqs. 21-22: ||Phi1|| <= alpha1 |w|^2 + alpha2 |w| + alpha3 [N m], ||Phi2|| <= alpha4 |w||v| +
#: alpha5 |w||r| + alpha6 |w| + alpha7 |v| + alpha8 |r| + alpha9 [N]
_ALPHA = ("N m s^2", "N m s", "N m", "kg", "kg/s", "N s", "kg/s", "kg/s^2", "N")
#: d/dt alpha^_i
_ALPHA_RATE = ("N m s", "N m", "N m/s", "kg/s", "kg/s^2", "N", "kg/s^2", "kg/s^3", "N/s")
#: eq. 25's rates and leakages (the layout's "-"): alpha~_i^2 / (2 beta_i) is an energy (V1, eq. 26) and
#: gamma_i alpha~_i alpha^_i a power (eq. 29), so beta_i = [alpha_i]^2 / J and gamma_i = W / [alpha_i]^2
_BETA = ("N m s^4", "N m s^2", "N m", "kg s^2/m^2", "kg/m^2", "kg", "kg/m^2", "kg/(m^2 s^2)", "N/m")
_GAMMA = ("1/(N m s^5)", "1/(N m s^3)", "1/(N m s)", "m^2/(kg s^3)", "m^2/(kg s)", "1/(kg s)", "m^2/(kg s)",
          "m^2 s/kg", "s/kg")
#: eqs. 23-24's epsilon (the layout's "-": "mixed units, as in the paper")
_EPS = "SI numbers (as in the paper: W in the adaptive terms of eqs. 23-24, rad/s or m/s in the k3, k7 terms)"


def _indexed() -> dict:
    out = {}
    for i in range(9):
        n = i + 1
        out |= {f"alpha_{n}": _ALPHA[i], f"alphahat_{n}": _ALPHA[i], f"alpha_hat_{n}": _ALPHA[i],
                f"alphatilde_{n}": _ALPHA[i], f"alphahatdot_{n}": _ALPHA_RATE[i], f"beta_{n}": _BETA[i],
                f"gamma_{n}": _GAMMA[i]}
    return out


_DESIGN = c.C002()
_GAINS = layout_units(_DESIGN.k)

UNITS = declare(layout_units(_DESIGN.k, _DESIGN.xc), {
    **_indexed(),
    # the gains of _S (eqs. 15-18, 23-24), as the layout states them for k1..k8, kappa1, kappa2
    **{f"k_{i}": _GAINS[f"k{i}"] for i in range(1, 9)}, "kappa_1": _GAINS["kappa1"], "kappa_2": _GAINS["kappa2"],
    "varepsilon": {"": _EPS, "V1.lemma2_unit_terms": "rad/s or m/s (as ||s||)"}, "eps": _EPS,
    # Lemma 2 for the k3 term (attitude) or the k7 term (position)
    "snorm": "rad/s or m/s (the k3 or the k7 term)", "k": "N m or N (k3 or k7)",
    # eq. 30 (Young) for any one i
    "alphatilde": "the unit of alpha_i (any i)", "alpha": "the unit of alpha_i (any i)",
    "gamma": "W / (the unit of alpha_i)^2", "l": "1",
    # ---- states, surfaces, auxiliary systems (eqs. 1-18)
    "q": "1", "q0": "1", "Q": "1", "Q_p": "1", "Q_t": "1", "q_c": "1", "q_t": "1", "q_cL": "1", "R": "1",
    "e_0": "1", "chi1": "1", "chi2": "1", "c_1": "1", "c_2": "1",
    "omega": "rad/s", "omega_p": "rad/s", "omega_t": "rad/s", "w_c": "rad/s", "w_t": "rad/s", "W": "rad/s",
    "n": "rad/s", "omegadot_t": "rad/s^2",
    "r": "m", "r_p": "m", "r_t": "m", "r0": "m", "sigma_t": "m", "sigmanorm": "m",
    "v": "m/s", "v_p": "m/s", "v_t": "m/s", "vdot_t": "m/s^2", "g_p": "m/s^2", "Deltag": "m/s^2",
    "s_1": "rad/s", "s_2": "m/s", "s1dot": "rad/s^2", "s2dot": "m/s^2",
    "o_1": "rad/s", "o_2": "m/s", "o_3": "1", "o_4": "m",        # bounds on s1, s2, q~_v, r~ (eqs. 40-43)
    "x": "any unit (the transport theorem for any vector)", "xdot": "the unit of x per s",
    # ---- the model (eqs. 4, 7-12) and its lumped bounds (eqs. 21-22, Assumption 1, Remarks 4-5)
    "J": "kg m^2", "J0": "kg m^2", "Jdot": "kg m^2/s", "m": "kg", "m_0": "kg", "mdot": "kg/s",
    "Cr": "kg m^2/s", "Ct": "1/s", "n_r": "N m", "n_t": "m/s^2",
    "a_1": "rad/s", "a_2": "rad/s^2", "a_3": "m/s", "a_4": "m/s^2", "b_1": "kg m^2", "b_3": "kg",
    "D_1": "N m", "D_2": "N", "Phi1": "N m", "Phi2": "N", "B_1": "J", "B_2": "J",
    "tau": "N m", "tau_d": "N m", "d_r": "N m", "epsilon_r": "N m", "u_r": "N m", "e_1": "N m", "varpi_1": "N m",
    "f": "N", "f_d": "N", "d_t": "N", "epsilon_t": "N", "u_t": "N", "e_2": "N", "varpi_2": "N",
    "u_M": {"gains.kappa1_varpi1": "N m", "gains.kappa2_varpi2": "N"},     # the torque or the force limit
})
