"""Shared by the 002 claims: the paper's data (eq. 46, Section IV) and the symbols of the closed loop."""

from __future__ import annotations

import sympy as sp

from ...physics.rotations import dot
from ..core import (
    lie_derivative,
    symbols_vec,
)
from ..scenarios import controller_gains, scenario

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

