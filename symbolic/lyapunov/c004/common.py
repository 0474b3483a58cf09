"""Shared by the 004 claims: the paper's data and printed forms, symmetric matrices and the code's rotation as
domain entries."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c004 as c
from ..core import (
    lie_derivative,
)
from ..domains import (
    UPPER,
    custom,
    needing,
    upper,
)
from ..scenarios import scenario
from ..units import declare, layout_units

# The paper's data (section 5): chaser inertia J, target inertia J_t (the search domains cover them).
_SCENARIO = scenario("004_scenario")                   # paper Table 1
J_PAPER = np.array(_SCENARIO["chaser"]["inertia"])        # chaser inertia [kg m^2]
J_T = np.array(_SCENARIO["target"]["inertia"])            # target inertia [kg m^2]
SIGMA_E0 = (0.5, -0.6, 0.7)          # Table 1


# --------------------------------------------------------------------------- the paper's printed forms

def _printed_y(g, v_e, r_e, omega, Lambda1):
    """y as printed under eq. 22: ``g + Lambda1 v_e + Lambda1 S(omega) r_e`` (the code has -Lambda1 v_e)."""
    return g + Lambda1 * v_e + Lambda1 * c.S(omega) * r_e


def _printed_Y(omega, omega_e, sigma_e, Lambda2):
    """Y as printed under eq. 31 (last sign -; the code has +), with the corrected L to isolate the sign."""
    L = c.inertia_operator
    return (L(c.S(omega_e) * (omega - omega_e)) - c.S(omega) * L(omega)
            - L(Lambda2 * c.mrp_kinematics(sigma_e, omega_e)))


def _printed_L(a):
    """L(a) as printed: row 1 has five entries ``[a1 0 0 a3 a2]``, read as the first five columns."""
    a1, a2, a3 = a[0], a[1], a[2]
    return sp.Matrix([[a1, 0, 0, a3, a2, 0], [0, a2, 0, a3, 0, a1], [0, 0, a3, a2, a1, 0]])


def _printed_R(sigma):
    """Eq. 9 as printed: ``I - 4(1 - s^2)/(1 + s^2)^2 S + 8/(1 + s^2)^2 S^T S`` (the code has S^2)."""
    s2 = c.dot(sigma, sigma)
    Se = c.S(sigma)
    return sp.eye(3) - 4 * (1 - s2) / (1 + s2) ** 2 * Se + 8 / (1 + s2) ** 2 * Se.T * Se


# --------------------------------------------------------------------------- local helpers

def _sym3(name: str) -> sp.Matrix:
    """Symmetric 3x3 matrix of real symbols name_ij (i <= j)."""
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"{name}_{min(i, j) + 1}{max(i, j) + 1}", real=True))


class _WithInverse(sp.MutableDenseMatrix):
    """A symmetric symbol matrix whose ``inv()`` is a matrix of its own symbols (drawn as the true inverse
    by :func:`_inverse_var`).  Where an identity holds for *any* matrix in the place of the inverse (eqs.
    19, 20) the symbolic proof is then structural, and numeric statements stay small; the code's functions
    are called unchanged (they only ever call ``.inv()`` on the inertia they are given)."""

    def inv(self, *args, **kwargs):
        return self._inverse


def _opaque_inverse(name: str) -> sp.Matrix:
    M = _WithInverse(_sym3(name))
    M._inverse = _sym3(name + "inv")
    return M


def _inverse_var(M):
    """Domain entry: the symbols of ``M.inv()`` = the numeric inverse of the drawn M."""
    Mi, Ms = M.inv(), list(M)

    def draw(z, env):
        A = np.linalg.inv(_stack(Ms, env))
        return np.column_stack([A[:, i, j] for i, j in UPPER])

    return needing(custom(upper(Mi), 0, draw, "the inverse of " + str(M[0, 0]).rsplit("_", 1)[0]), *upper(M))


def _stack(M, env) -> np.ndarray:
    """(n, 3, 3) values of a symbol matrix (or its 9 symbols, row-major) from the drawn values."""
    syms = M if isinstance(M, list) else list(M)
    return np.stack([np.asarray(env[x], dtype=float) for x in syms], axis=-1).reshape(-1, 3, 3)


def _eig(M, env) -> np.ndarray:
    """(n, 3) ascending eigenvalues of a symmetric symbol matrix (or its 9 symbols) per point."""
    return np.linalg.eigvalsh(_stack(M, env))


def _cond(M, env) -> np.ndarray:
    """||M^-1|| ||M|| = lambda_max / lambda_min per point (M symmetric positive definite)."""
    ev = _eig(M, env)
    return ev[:, 2] / ev[:, 0]


def _rotation_symbols() -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))


def _code_rotation(R, sig):
    """Domain entry: the symbols R_ij drawn as the code's R(sigma_e) (eq. 9 as rpo implements it,
    evaluated numerically at the drawn sigma_e; looked up at build time, so a mutated eq. 9 is seen).
    The statements stay small: R enters them as 9 symbols."""
    f = sp.lambdify(list(sig), list(c.rotation_matrix(sp.Matrix(sig))), "numpy")

    def draw(z, env):
        vals = f(*[np.asarray(env[x], dtype=float) for x in sig])
        return np.column_stack([np.broadcast_to(np.asarray(v, dtype=float), (len(z),)) for v in vals])

    return needing(custom(list(R), 0, draw, "R = R(sigma_e), eq. 9 as in the code"), *sig)


def _s_dot(s, states, rates):
    """Time derivative of each entry of a vector along the given vector field."""
    return sp.Matrix([lie_derivative(si, states, rates) for si in s])


# --------------------------------------------------------------------------- claims

_C = "c004"


# --------------------------------------------------------------------------- units of the domain symbols
# (the report prints them with each search domain; ..units).  The claims name the controller's gains and
# estimates their own way (k_0 for k0, gamma_1 for gamma1, lambda1_i for Lambda1_x, ...): their units are the
# layout's, looked up under the layout's name.

_DESIGN = c.C004()
_L = layout_units(_DESIGN.k, _DESIGN.xc)
_LAYOUT_NAMES = {"k_0": "k0", "k1": "K1_x", "k2": "K2_x", "lambda1": "Lambda1_x", "lambda2": "Lambda2_x",
                 **{f"gamma_{i}": f"gamma{i}" for i in range(1, 7)}, "m_0": "m0", "theta_0": "theta0_11",
                 "p_t": "p_t_x", "mhat_Delta": "m_hat_delta", "rhohat_f": "rho_f_hat", "rhohat_m": "rho_m_hat",
                 "thetahat_Delta": "theta_hat_delta_11", "rhohat_tau": "rho_tau_hat", "rhohat_J": "rho_J_hat"}
_ESTIMATES = ("mhat_Delta", "rhohat_f", "rhohat_m", "thetahat_Delta", "rhohat_tau", "rhohat_J")


def _estimates() -> dict:
    """Each estimate's error (tilde) and rate (hatdot) from its unit."""
    out = {}
    for name in _ESTIMATES:
        u = _L[_LAYOUT_NAMES[name]]
        out |= {name.replace("hat", "tilde", 1): u, name.replace("hat", "hatdot", 1): f"{u}/s"}
    return out


UNITS = declare(_L, {
    **{name: _L[label] for name, label in _LAYOUT_NAMES.items()}, **_estimates(),
    # ---- model (eqs. 1-20): chaser body frame, R = C_{c<-t}
    "r": "m", "rI": "m", "r_t": "m", "r_e": "m", "v": "m/s", "vI": "m/s", "v_t": "m/s", "v_e": "m/s",
    "omega": "rad/s", "omega_t": "rad/s", "omega_e": "rad/s", "omegadot_t": "rad/s^2",
    "q": "1", "Q": "1", "q_c": "1", "q_t": "1", "sigma_e": "1", "R": "1",
    "m": "kg", "m_t": "kg", "J": "kg m^2", "Jt": "kg m^2", "Jinv": "1/(kg m^2)", "Jtinv": "1/(kg m^2)",
    "lambda_J": "kg m^2",
    "f": "N", "d_f": "N", "tau": "N m", "d_tau": "N m", "n_1": "m/s^2", "n_2": "rad/s^2",
    "a": "any unit (a test vector: eq. 9's R^T R a = a, J a = L(a) theta)",
    # ---- the laws and their Lyapunov functions (eqs. 21-39)
    "s_1": "m/s", "s_2": "rad/s",
    "rho_f": "N", "rho_tau": "N m", "rho_m": "kg", "rho_J": "kg m^2",
    "c": "kg^(1/2) m", "z": "kg^(1/2) m rad/s",          # J = C C^T, z = C^T s2 (eq. 32 as a sum of squares)
})
