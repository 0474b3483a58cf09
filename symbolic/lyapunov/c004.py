"""Claims of 004 (Sun & Huo): the position (eqs. 21-28) and attitude (eqs. 29-37) Lyapunov arguments,
Theorem 1 (eqs. 38-39) and the relative model they rest on (eqs. 9-20).

Every statement is built from the functions of :mod:`rpo.symbolic.controllers.c004` that generate the C
code (looked up on the module at check time, so mutations are seen): the closed loop is the paper's model
(eqs. 13, 19 / 14, 20) driven by the law (eq. 25 / 34) and the adaptation (eq. 27 / 36), and V-dot is
V differentiated along it (:func:`~rpo.symbolic.lyapunov.core.lie_derivative`).  Where the paper prints
a different form (y of eq. 22, Y under eq. 31, row 1 of L, eq. 9) that form is hand-typed below
(``_printed_*``) as the claim's ``paper`` statement, and the code's form is the ``corrected`` one.

Layers: ``abstract`` is the Lyapunov argument on the relative model (13), (14), (19), (20) as the paper
states it (Theorem 1 takes that model as given); ``spacecraft`` is whether rigid-body motion (eqs. 1-8)
really has that form through eqs. 9-18, and the bounds that use ||R|| = 1 and the target's inertia.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..controllers import c004 as c
from ..rotations import mrp_shadow, quat_from_mrp
from .core import (
    Claim,
    Mutation,
    Statement,
    ball,
    box,
    custom,
    drop_terms,
    fixed,
    lie_derivative,
    negate_output,
    replace_output,
    scale_argument,
    symbols_vec,
)

# The paper's data (section 5): chaser inertia J, target inertia J_t (the search domains cover them).
J_PAPER = np.array([[598.3, -22.5, -51.5], [-22.5, 424.4, -27.0], [-51.5, -27.0, 263.6]])
J_T = np.array([[3336.3, -135.4, -154.2], [-135.4, 3184.5, -148.5], [-154.2, -148.5, 2423.7]])
SIGMA_E0 = (0.5, -0.6, 0.7)          # Table 1
_IJ = [(i, j) for i in range(3) for j in range(i, 3)]   # upper triangle: 11, 12, 13, 22, 23, 33


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


def _upper(M) -> list:
    return [M[i, j] for i, j in _IJ]


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
        return np.column_stack([A[:, i, j] for i, j in _IJ])

    return _dep(custom(_upper(Mi), 0, draw, "the inverse of " + str(M[0, 0]).rsplit("_", 1)[0]), *_upper(M))


def _spd(M, diag: tuple[float, float], off: float):
    """A symmetric matrix with diagonal in [lo, hi] and |off-diagonal| <= off < lo/2: diagonally
    dominant, so every point is positive definite (Hypothesis 1)."""
    lo, hi = diag
    assert 2 * off < lo

    def draw(z, env):
        out = np.empty_like(z)
        for k, (i, j) in enumerate(_IJ):
            out[:, k] = lo + (z[:, k] + 1) * 0.5 * (hi - lo) if i == j else off * z[:, k]
        return out

    return custom(_upper(M), 6, draw, f"symmetric, diagonal in [{lo:g}, {hi:g}], |off-diagonal| <= {off:g} "
                                      "(diagonally dominant: positive definite)")


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


def _rotation_from_mrp_box(z, env):
    """9 entries (row-major) of R(sigma) for sigma in the unit ball (independent of eq. 9: scipy)."""
    from scipy.spatial.transform import Rotation

    sig = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1.0)
    return Rotation.from_mrp(sig).as_matrix().reshape(len(z), 9)


def _rotation_symbols() -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))


def _unit_vector(z, env):
    n = np.linalg.norm(z, axis=1, keepdims=True)
    return np.where(n > 1e-9, z / np.maximum(n, 1e-12), np.array([0.0, 0.0, 1.0]))


def _code_rotation(R, sig):
    """Domain entry: the symbols R_ij drawn as the code's R(sigma_e) (eq. 9 as rpo implements it,
    evaluated numerically at the drawn sigma_e; looked up at build time, so a mutated eq. 9 is seen).
    The statements stay small: R enters them as 9 symbols."""
    f = sp.lambdify(list(sig), list(c.rotation_matrix(sp.Matrix(sig))), "numpy")

    def draw(z, env):
        vals = f(*[np.asarray(env[x], dtype=float) for x in sig])
        return np.column_stack([np.broadcast_to(np.asarray(v, dtype=float), (len(z),)) for v in vals])

    return _dep(custom(list(R), 0, draw, "R = R(sigma_e), eq. 9 as in the code"), *sig)


class _Dep(tuple):
    """(Var, symbols its draw reads from earlier entries): lets :func:`_finish` keep what a kept entry needs."""


def _dep(var, *symbols):
    return _Dep((var, frozenset(symbols)))


def _finish(entries, *exprs) -> list:
    """The domain of a statement: the entries (Var or :func:`_dep`) that draw a symbol of ``exprs`` or
    that a kept entry reads; duplicates (an entry whose symbols are all drawn earlier) dropped.
    Fewer coordinates make the adversarial search cheaper without changing what it covers."""
    seen, flat = set(), []
    for e in entries:
        var, deps = e if isinstance(e, _Dep) else (e, frozenset())
        if set(var.symbols) <= seen:
            continue
        seen |= set(var.symbols)
        flat.append((var, deps))
    used = set()
    for x in exprs:
        used |= getattr(x, "free_symbols", set())
    keep = []
    for var, deps in reversed(flat):
        if set(var.symbols) & used:
            keep.append(var)
            used |= deps
    return keep[::-1]


def _st(lhs, relation, rhs, entries, **kw) -> Statement:
    """A statement whose domain is ``entries`` trimmed to what lhs and rhs use (:func:`_finish`)."""
    return Statement(lhs, relation, rhs, _finish(entries, lhs, rhs), **kw)


def _s_dot(s, states, rates):
    """Time derivative of each entry of a vector along the given vector field."""
    return sp.Matrix([lie_derivative(si, states, rates) for si in s])


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
            rot = [custom(list(self.R), 3, _rotation_from_mrp_box, "R = R(sigma), |sigma| <= 1"),
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
                _dep(ball(self.d_f, self.rho_f), self.rho_f), _spd(Jt, (2000, 3500), 200), _inverse_var(Jt),
                _dep(custom([self.rho_m], 0, lambda z, env: (env[m] * _cond(Jts, env))[:, None],
                            "rho_m = m ||J_t^-1|| ||J_t||"), m, *_upper(Jt)),
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
        return _st(lhs, "==", rhs, P.domain(), assumptions=["any f (before eq. 25)"])
    return build


def _eq24(y: str):
    def build() -> Statement:
        """Eq. 24: V1-dot along eqs. 13, 19, for any f and estimate rates."""
        P = _Position(opaque=True, y=y, law=False, adapt=False)
        rhs = (-P.k0 * c.dot(P.r_e, P.L1 * P.r_e)
               + c.dot(P.s1, P.k0 * P.r_e - P.m * P.y - P.m * P.n1 + P.f + P.d_f) + P.adapt_terms)
        return _st(P.V1dot, "==", rhs, P.domain(), assumptions=["any f, any estimate rates"])
    return build


def _eq26() -> Statement:
    """Eq. 26: eq. 24 with the law (25) substituted (estimate rates still free)."""
    P = _Position(opaque=True, adapt=False)
    s1, sg = P.s1, c.sgn(P.s1)
    rhs = (P.nominal + c.dot(s1, P.m_tilde * P.y) - c.dot(s1, P.m * P.n1) + c.dot(s1, P.d_f)
           - c.dot(s1, P.rf_hat * sg) - c.dot(s1, P.rm_hat * c.norm2(P.p_t) * P.wt2 * sg) + P.adapt_terms)
    return _st(P.V1dot, "==", rhs, P.domain(), assumptions=["eq. 25 substituted, estimate rates free"])


def _v1dot_identity() -> Statement:
    """Eqs. 24-27: with eq. 27 the estimation errors cancel; what remains is the paper's eq. 28 before
    its bound: -k0 r^T L1 r - s^T K1 s + s^T(d_f - m n1) - (rho_f + rho_m |p_t| |w_t|^2) |s|_1."""
    P = _Position(opaque=True)
    rhs = P.nominal + c.dot(P.s1, P.d_f - P.m * P.n1) - P.robust
    return _st(P.V1dot, "==", rhs, P.domain(), assumptions=["eqs. 25, 27 substituted"])


def _closed_loop_28() -> Statement:
    """Eq. 28: m s1-dot = -k0 r_e - K1 s1 + m~ y - m n1 + d_f - (rho^_f + rho^_m |p_t| |w_t|^2) sgn(s1)."""
    P = _Position(opaque=True)
    lhs = P.m * _s_dot(P.s1, P.states[:2], P.rates[:2])
    rhs = (-P.k0 * P.r_e - P.K1 * P.s1 + P.m_tilde * P.y - P.m * P.n1 + P.d_f
           - (P.rf_hat + P.rm_hat * c.norm2(P.p_t) * P.wt2) * c.sgn(P.s1))
    return _st(lhs, "==", rhs, P.domain(), assumptions=["eq. 25 substituted"])


def _n1_bound() -> Statement:
    """The step under eq. 27: ||m n1|| <= rho_m ||p_t|| ||w - w_e||^2 with rho_m = |m| ||J_t^-1|| ||J_t||."""
    P = _Position()
    lhs = c.norm2(P.m * P.n1)
    rhs = P.rho_m * c.norm2(P.p_t) * P.wt2
    return _st(lhs, "<=", rhs, P.domain(), symbolic=False,
                     assumptions=["R = R(sigma_e) (eq. 9, corrected): ||R|| = 1", "||S(a)|| = ||a||",
                                  "rho_m = m ||J_t^-1|| ||J_t||, J_t > 0"])


def _v1dot_bound() -> Statement:
    """Eq. 27's chain: V1-dot <= -k0 r^T L1 r - s^T K1 s <= -s^T K1 s under ||d_f|| <= rho_f and
    rho_m = m ||J_t^-1|| ||J_t||."""
    P = _Position()
    lhs = sp.Matrix([P.V1dot, P.nominal])
    rhs = sp.Matrix([P.nominal, -c.dot(P.s1, P.K1 * P.s1)])
    return _st(lhs, "<=", rhs, P.domain(), symbolic=False,
                     assumptions=["||d_f|| <= rho_f (Hypothesis 2)", "rho_m = m ||J_t^-1|| ||J_t|| (above eq. 23)",
                                  "||S(a)|| = ||a||, ||R|| = 1, ||s||_2 <= ||s||_1 (the paper's steps)"])


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
            rot = [custom(list(self.R), 3, _rotation_from_mrp_box, "R = R(sigma), |sigma| <= 1"),
                   box(self.n2, -0.01, 0.01)]
        else:
            rot = [_code_rotation(self.R, self.sig)]
        J, Jt = self.J, self.Jt
        Js, Jts = list(J), list(Jt)
        return [box(self.omega, -0.1, 0.1), box(self.omega_e, -0.1, 0.1), ball(self.sig, 1.0), *rot,
                _spd(J, (200, 700), 60), _spd(Jt, (2000, 3500), 200), _inverse_var(Jt),
                *([_inverse_var(J)] if isinstance(J, _WithInverse) else []),
                box(self.l2, 0.01, 1), box(self.k2, 1, 200), box([self.g4, self.g5, self.g6], 0.01, 1),
                box(self.theta0[:3], 200, 700), fixed(self.theta0[3:], [0, 0, 0]),
                box(self.th_hat, -100, 100), box(self.rt_hat, -20, 20), box(self.rJ_hat, -3000, 3000),
                box(self.rho_tau, 0, 1), _dep(ball(self.d_tau, self.rho_tau), self.rho_tau),
                _dep(custom([self.rho_J], 0,
                            lambda z, env: (_eig(Js, env)[:, 2] * _cond(Jts, env))[:, None],
                            "rho_J = ||J|| ||J_t^-1|| ||J_t||"), *_upper(J), *_upper(Jt)),
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
                         [box(a, -1, 1), _spd(J, (200, 700), 60)])
    return build


def _eq30() -> Statement:
    """Eq. 30: J s2-dot along eqs. 14, 20 (any tau)."""
    A = _Attitude(opaque=True, law=False, adapt=False)
    rhs = c.attitude_surface_dynamics(A.J, A.omega, A.omega_e, A.sig, A.L2, A.n2, A.tau, A.d_tau)
    return _st(A.Js2dot(), "==", rhs, A.domain(), assumptions=["any tau (before eq. 34)"])


def _eq31(Y: str):
    def build() -> Statement:
        """Eq. 31: J s2-dot = Y (theta0 + theta_Delta) + J n2 + tau + d_tau, theta0 + theta_Delta = theta(J)."""
        A = _Attitude(opaque=True, Y=Y, law=False, adapt=False)
        rhs = A.Y * A.theta + A.J * A.n2 + A.tau + A.d_tau
        return _st(A.Js2dot(), "==", rhs, A.domain(), assumptions=["any tau (before eq. 34)"])
    return build


def _eq33(Y: str):
    def build() -> Statement:
        """Eq. 33: V2-dot along eqs. 14, 20, any tau and estimate rates."""
        A = _Attitude(opaque=True, Y=Y, law=False, adapt=False)
        rhs = c.dot(A.s2, A.Y * A.theta + A.J * A.n2 + A.tau + A.d_tau) + A.adapt_terms
        return _st(A.V2dot, "==", rhs, A.domain(), assumptions=["any tau, any estimate rates"])
    return build


def _eq35() -> Statement:
    """Eq. 35: eq. 33 with the law (34) substituted (estimate rates still free)."""
    A = _Attitude(opaque=True, adapt=False)
    s2, sg = A.s2, c.sgn(A.s2)
    rhs = (-c.dot(s2, A.K2 * s2) + c.dot(s2, A.J * A.n2) + c.dot(s2, A.d_tau) - c.dot(s2, A.Y * A.th_tilde)
           - c.dot(s2, A.rt_hat * sg) - c.dot(s2, A.rJ_hat * A.wt2 * sg) + A.adapt_terms)
    return _st(A.V2dot, "==", rhs, A.domain(), assumptions=["eq. 34 substituted, estimate rates free"])


def _v2dot_identity() -> Statement:
    """Eqs. 35-36: with eq. 36 the estimation errors cancel:
    V2-dot = -s2^T K2 s2 + s2^T (J n2 + d_tau) - (rho_tau + rho_J |w_t|^2) |s2|_1."""
    A = _Attitude(opaque=True)
    rhs = (-c.dot(A.s2, A.K2 * A.s2) + c.dot(A.s2, A.J * A.n2 + A.d_tau)
           - (A.rho_tau + A.rho_J * A.wt2) * c.norm1(A.s2))
    return _st(A.V2dot, "==", rhs, A.domain(), assumptions=["eqs. 34, 36 substituted"])


def _closed_loop_37() -> Statement:
    """Eq. 37: J s2-dot = -K2 s2 - Y theta~ + J n2 + d_tau - (rho^_tau + rho^_J |w_t|^2) sgn(s2)."""
    A = _Attitude(opaque=True)
    rhs = (-A.K2 * A.s2 - A.Y * A.th_tilde + A.J * A.n2 + A.d_tau
           - (A.rt_hat + A.rJ_hat * A.wt2) * c.sgn(A.s2))
    return _st(A.Js2dot(), "==", rhs, A.domain(), assumptions=["eq. 34 substituted"])


def _n2_bound() -> Statement:
    """The step under eq. 36: ||J n2|| <= rho_J ||w - w_e||^2 with rho_J = ||J|| ||J_t^-1|| ||J_t||."""
    A = _Attitude(exact_inverse=False)
    return _st(c.norm2(A.J * A.n2), "<=", A.rho_J * A.wt2, A.domain(), symbolic=False,
                     assumptions=["R = R(sigma_e) (eq. 9, corrected): ||R|| = 1", "||S(a)|| = ||a||",
                                  "rho_J = ||J|| ||J_t^-1|| ||J_t||, J, J_t > 0"])


def _v2dot_bound() -> Statement:
    """Eq. 36's chain: V2-dot <= -s2^T K2 s2 under ||d_tau|| <= rho_tau, rho_J = ||J|| ||J_t^-1|| ||J_t||."""
    A = _Attitude(exact_inverse=False)
    return _st(A.V2dot, "<=", -c.dot(A.s2, A.K2 * A.s2), A.domain(), symbolic=False,
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

    dom = [custom(list(sig), 3, _unit_vector, "|sigma_e| = 1"),
           custom(list(we), 3, outward, "|omega_e| <= 0.1 sqrt(3) (reflected), sigma_e^T omega_e >= 0"),
           fixed(_upper(A.J), [J_PAPER[i, j] for i, j in _IJ]), fixed(A.l2, [0.2, 0.2, 0.2])]
    return Statement(V2(mrp_shadow(sig)), "<=", V2(sig), dom, symbolic=False,
                     assumptions=["|sigma_e| = 1, sigma_e^T omega_e >= 0 (leaving the unit ball)",
                                  "the paper's J and Lambda2 = 0.2 I"])


# --------------------------------------------------------------------------- Theorem 1 (section 4)

def _v_lower_bound() -> Statement:
    """The proof's bound: V >= k0/2 |r_e|^2 + m/2 |s1|^2 + lambda_J/2 |s2|^2 + |zeta|^2/(2 gamma),
    zeta = [m~, theta~, rho~_tau, rho~_m, rho~_J] as printed (rho~_f is not in it)."""
    P, A = _Position(opaque=True), _Attitude(opaque=True, exact_inverse=False)
    mt, rft, rmt = sp.symbols("mtilde_Delta rhotilde_f rhotilde_m", real=True)
    tt = symbols_vec("thetatilde_Delta", 6)
    rtt, rJt = sp.symbols("rhotilde_tau rhotilde_J", real=True)
    s1, s2 = symbols_vec("s_1"), symbols_vec("s_2")
    lam_J = sp.Symbol("lambda_J", positive=True)
    V1 = c.position_lyapunov(P.k0, P.r_e, P.m, s1, mt, rft, rmt, P.g1, P.g2, P.g3)
    V2 = c.attitude_lyapunov(A.J, s2, tt, rtt, rJt, A.g4, A.g5, A.g6)
    zeta = sp.Matrix([mt, *tt, rtt, rmt, rJt])
    gam = sp.Max(P.g1, P.g2, P.g3, A.g4, A.g5, A.g6)
    rhs = (P.k0 * c.dot(P.r_e, P.r_e) + P.m * c.dot(s1, s1) + lam_J * c.dot(s2, s2)
           + c.dot(zeta, zeta) / gam) / 2
    J = A.J
    Js = list(J)
    dom = [box(P.r_e, -40, 40), box([*s1, *s2], -2, 2), box([mt, rft, rmt, rtt, rJt], -20, 20), box(tt, -100, 100),
           box([P.k0], 0.01, 1), box(P.m, 20, 100), box([P.g1, P.g2, P.g3, A.g4, A.g5, A.g6], 0.01, 1),
           _spd(J, (200, 700), 60),
           custom([lam_J], 0, lambda z, env: _eig(Js, env)[:, :1], "min eigenvalue of J")]
    return Statement(V1 + V2, ">=", rhs, dom, symbolic=False,
                     assumptions=["lambda_J = min eig J", "gamma = max gamma_i"])


def _theorem_vdot() -> Statement:
    """Eq. 38 along the coupled closed loop (13, 14, 19, 20 under 25, 27, 34, 36), R = R(sigma_e):
    V-dot <= -l_k1 |s1|^2 - l_k2 |s2|^2 <= -mu |s|^2 <= 0."""
    P, A = _Position(), _Attitude(exact_inverse=False)
    V = P.V1 + A.V2
    Vdot = lie_derivative(V, P.states + A.states, P.rates + A.rates)
    lk1, lk2 = sp.Min(*P.k1), sp.Min(*A.k2)
    n1, n2 = c.dot(P.s1, P.s1), c.dot(A.s2, A.s2)
    mu = sp.Min(lk1, lk2)
    a = -lk1 * n1 - lk2 * n2
    lhs = sp.Matrix([Vdot, a, -mu * (n1 + n2)])
    rhs = sp.Matrix([a, -mu * (n1 + n2), 0])
    return _st(lhs, "<=", rhs, P.domain() + A.domain(), symbolic=False,
                     assumptions=["Hypotheses 1-2", "rho_m = m ||J_t^-1|| ||J_t||, rho_J = ||J|| ||J_t^-1|| ||J_t||",
                                  "lambda_k1 = min eig K1, lambda_k2 = min eig K2"])


def _vs_manifold():
    """(r_e, sigma_e) dynamics on s1 = s2 = 0 (v_e = -L1 r_e, w_e = -L2 sigma_e) from eqs. 13, 14."""
    P, A = _Position(opaque=True), _Attitude(opaque=True, exact_inverse=False)
    zero = sp.zeros(3, 1)
    v_e = -c.position_surface(zero, P.r_e, P.L1)        # s1 = 0
    w_e = -c.attitude_surface(zero, A.sig, A.L2)        # s2 = 0
    Vs = (c.dot(P.r_e, P.r_e) + c.dot(A.sig, A.sig)) / 2
    Vsdot = lie_derivative(Vs, [P.r_e, A.sig], [c.position_kinematics(P.r_e, v_e, P.omega),
                                                c.mrp_kinematics(A.sig, w_e)])
    dom = [box(P.r_e, -40, 40), ball(A.sig, 1.0), box(P.omega, -0.1, 0.1), box(P.l1, 0.01, 1),
           box(A.l2, 0.01, 1)]
    return P, A, Vsdot, dom


def _vs_identity() -> Statement:
    """Eq. 39: Vs-dot = -r_e^T L1 r_e - (1 + |sigma_e|^2)/4 sigma_e^T L2 sigma_e
    (uses r^T S(w) r = 0 and sigma^T G(sigma) = (1 + |sigma|^2)/4 sigma^T)."""
    P, A, Vsdot, dom = _vs_manifold()
    rhs = -c.dot(P.r_e, P.L1 * P.r_e) - (1 + c.dot(A.sig, A.sig)) / 4 * c.dot(A.sig, A.L2 * A.sig)
    return Statement(Vsdot, "==", rhs, dom)


def _vs_bound() -> Statement:
    """Eq. 39, last line: Vs-dot <= -l_m1 |r_e|^2 - l_m2/4 |sigma_e|^2 <= 0."""
    P, A, Vsdot, dom = _vs_manifold()
    b = -sp.Min(*P.l1) * c.dot(P.r_e, P.r_e) - sp.Min(*A.l2) / 4 * c.dot(A.sig, A.sig)
    return Statement(sp.Matrix([Vsdot, b]), "<=", sp.Matrix([b, 0]), dom, symbolic=False,
                     assumptions=["lambda_m1 = min eig L1, lambda_m2 = min eig L2"])


def _G_invertible() -> Statement:
    """End of the proof: G(sigma_e) is invertible; det G = (1 + |sigma|^2)^3 / 64 > 0."""
    sig = symbols_vec("sigma_e")
    return Statement(c.mrp_kinematics_matrix(sig).det(), "==", (1 + c.dot(sig, sig)) ** 3 / 64, [ball(sig, 1.0)])


def _claim1_energy() -> Statement:
    """Claim 1: E-dot = 0 along the torque-free target (eqs. 7, 8), so v_t, w_t stay bounded.  Stated as
    E + E-dot = E so that the numeric tolerance is relative to E (E-dot alone is 0 +- rounding)."""
    v_t, w_t = symbols_vec("v_t"), symbols_vec("omega_t")
    m_t = sp.Symbol("m_t", positive=True)
    Jt = _sym3("Jt")
    zero = sp.zeros(3, 1)
    E = c.target_kinetic_energy(m_t, v_t, Jt, w_t)
    Edot = lie_derivative(E, [v_t, w_t], [c.translational_dynamics(m_t, v_t, w_t, zero, zero),
                                          c.rotational_dynamics(Jt, w_t, zero, zero)])
    return Statement(E + Edot, "==", E, [box(v_t, -1, 1), box(w_t, -0.1, 0.1), box(m_t, 100, 5000),
                                     _spd(Jt, (2000, 3500), 200)])


def _hypothesis1_paper_data() -> Statement:
    """Hypothesis 1 for section 5's data: m = 58.2 > 0, J > 0, J_t > 0, J0 = diag(theta0[:3]) > 0
    (leading principal minors; exact rationals)."""
    def minors(A):
        M = sp.Matrix(A).applyfunc(sp.nsimplify)
        return [M[:k, :k].det() for k in (1, 2, 3)]
    vals = [sp.nsimplify(58.2), *minors(J_PAPER), *minors(J_T), *minors(np.diag([580.0, 400.0, 300.0]))]
    return Statement(sp.Matrix(vals), ">", 0, [])


def _sigma_e0(corrected: bool):
    def build() -> Statement:
        """|sigma_e(0)| <= 1 (the constraint stated under eq. 4 and used in the proof)."""
        s = sp.Matrix([sp.nsimplify(x) for x in SIGMA_E0])
        if corrected:      # the same attitude as rpo's law forms it: principal_mrp of its quaternion
            s = c.principal_mrp(quat_from_mrp(s))
        return Statement(c.dot(s, s), "<=", 1, [])
    return build


# --------------------------------------------------------------------------- relative model (section 2.2)

def _orthogonal(printed: bool):
    def build() -> Statement:
        """Eq. 9 is a rotation matrix: R^T R a = a for every a, and det R = 1 (the proof uses R^-1 = R^T,
        ||R|| = 1).  (R^T R a = a on a box of a is R^T R = I without zero entries, which a relative
        tolerance cannot judge.)"""
        sig, a = symbols_vec("sigma_e"), symbols_vec("a")
        R = _printed_R(sig) if printed else c.rotation_matrix(sig)
        lhs = sp.Matrix([*(R.T * (R * a)), R.det()])
        rhs = sp.Matrix([*a, 1])
        return Statement(lhs, "==", rhs, [box(sig, -1.5, 1.5), box(a, 1, 2)])
    return build


def _R_dot(printed: bool):
    def build() -> Statement:
        """Eq. 9 along eq. 14 (sigma_e-dot = G(sigma_e) w_e): R-dot = -S(w_e) R, used to derive eqs. 13-16."""
        sig, we = symbols_vec("sigma_e"), symbols_vec("omega_e")
        R = _printed_R(sig) if printed else c.rotation_matrix(sig)
        sd = c.mrp_kinematics(sig, we)
        Rdot = sum((sp.diff(R, s) * d for s, d in zip(sig, sd, strict=True)), sp.zeros(3, 3))
        return Statement(Rdot, "==", -c.S(we) * R, [box(sig, -1.5, 1.5), box(we, -0.1, 0.1)])
    return build


def _rotation(sig):
    """R(sigma_e) of the code (eq. 9, corrected) over its common denominator (the same matrix; the
    symbolic proofs of eqs. 13, 17 are 10x faster in this form)."""
    return c.rotation_matrix(sig).applyfunc(sp.together)


def _eq13() -> Statement:
    """Eq. 13 from eqs. 1, 5, 11, 12, R(sigma_e) of eq. 9 and eq. 14: d/dt (r - R r_pt) = v_e - S(w) r_e."""
    r, v, r_t, v_t = symbols_vec("r"), symbols_vec("v"), symbols_vec("r_t"), symbols_vec("v_t")
    w_t, we, p_t, sig = symbols_vec("omega_t"), symbols_vec("omega_e"), symbols_vec("p_t"), symbols_vec("sigma_e")
    R = _rotation(sig)
    w = we + R * w_t                                       # eq. 12: w_e = w - R w_t
    r_pt, v_pt = c.docking_point(r_t, v_t, w_t, p_t)       # eq. 11
    r_e, v_e, _ = c.relative_state(r, v, w, R, r_pt, v_pt, w_t)
    r_e_dot = _s_dot(r_e, [r, r_t, sig], [c.position_kinematics(r, v, w),          # eq. 1
                                           c.position_kinematics(r_t, v_t, w_t),    # eq. 5
                                           c.mrp_kinematics(sig, we)])              # eq. 14
    dom = [box(r, -40, 40), box(r_t, -40, 40), box(v, -2, 2), box(v_t, -2, 2), box(w_t, -0.1, 0.1),
           box(we, -0.1, 0.1), box(p_t, -6, 6), ball(sig, 1.0)]
    return Statement(r_e_dot.applyfunc(sp.together), "==", c.position_kinematics(r_e, v_e, w), dom,
                     assumptions=["R = R(sigma_e) as corrected in eq. 9"])


def _eq17() -> Statement:
    """Eq. 17: R v_pt-dot (eqs. 7, 11) = -S(w - w_e)[v - v_e - S(w - w_e) R p_t] - R S(p_t) w_t-dot,
    with v = v_e + R v_pt, w = w_e + R w_t (eq. 12); uses R S(a) = S(R a) R."""
    v_t, w_t, p_t, v_e = symbols_vec("v_t"), symbols_vec("omega_t"), symbols_vec("p_t"), symbols_vec("v_e")
    we, wtd, sig = symbols_vec("omega_e"), symbols_vec("omegadot_t"), symbols_vec("sigma_e")
    m_t = sp.Symbol("m_t", positive=True)
    R = _rotation(sig)
    zero = sp.zeros(3, 1)
    _, v_pt = c.docking_point(zero, v_t, w_t, p_t)
    v_pt_dot = _s_dot(v_pt, [v_t, w_t], [c.translational_dynamics(m_t, v_t, w_t, zero, zero), wtd])  # eq. 7
    v, w = v_e + R * v_pt, we + R * w_t
    rhs = c.docking_point_acceleration(R, v, v_e, w, we, p_t, wtd)
    dom = [box(v_t, -2, 2), box(w_t, -0.1, 0.1), box(p_t, -6, 6), box(v_e, -2, 2), box(we, -0.1, 0.1),
           box(wtd, -0.01, 0.01), ball(sig, 1.0), box(m_t, 100, 5000)]
    return Statement(R * v_pt_dot, "==", rhs, dom, assumptions=["R = R(sigma_e) as corrected in eq. 9"])


def _eq19() -> Statement:
    """Eq. 19 from eqs. 15, 17, 18, in two rows: eq. 15 with eq. 17 (w_t-dot = u, any) is eq. 19 with
    n1 = -R S(p_t) u (the v terms cancel, g appears), and -R S(p_t) w_t-dot of eq. 18 is the printed n1.
    (Split so that the symbolic proof does not expand the J_t chain of eq. 18 into eq. 15.)"""
    P = _Position(opaque=True, law=False)
    v, f, u = symbols_vec("v"), P.f, symbols_vec("omegadot_t")
    Rvpt = c.docking_point_acceleration(P.R, v, P.v_e, P.omega, P.omega_e, P.p_t, u)        # eq. 17
    eq15 = c.relative_velocity_rate_coupled(P.m, v, P.v_e, P.omega, P.omega_e, Rvpt, f, P.d_f)
    eq19 = c.relative_velocity_rate(P.m, P.g, -P.R * c.S(P.p_t) * u, f, P.d_f)
    wtd = c.target_angular_acceleration(P.Jt, P.R, P.omega, P.omega_e)                      # eq. 18
    n1 = c.coupling_n1(P.R, P.p_t, P.Jt, P.omega, P.omega_e)
    dom = P.domain() + [box(v, -2, 2), box(u, -0.01, 0.01)]
    return _st(sp.Matrix([eq15, -P.R * c.S(P.p_t) * wtd]), "==", sp.Matrix([eq19, n1]), dom,
                     assumptions=["any R, any J_t^-1 (no orthogonality needed)"])


def _eq20() -> Statement:
    """Eq. 20 from eqs. 16, 18, in two rows as for eq. 19: eq. 16 with w_t-dot = u is eq. 20 with
    n2 = -R u, and -R w_t-dot of eq. 18 is the printed n2."""
    A = _Attitude(opaque=True, law=False, adapt=False, exact_inverse=False)
    u = symbols_vec("omegadot_t")
    eq16 = c.relative_rate_rate_coupled(A.J, A.omega, A.omega_e, A.R, u, A.tau, A.d_tau)
    eq20 = c.relative_rate_rate(A.J, A.omega, A.omega_e, -A.R * u, A.tau, A.d_tau)
    wtd = c.target_angular_acceleration(A.Jt, A.R, A.omega, A.omega_e)                      # eq. 18
    n2 = c.coupling_n2(A.R, A.Jt, A.omega, A.omega_e)
    dom = A.domain() + [box(u, -0.01, 0.01)]
    return _st(sp.Matrix([eq16, -A.R * wtd]), "==", sp.Matrix([eq20, n2]), dom,
                     assumptions=["any R, any J^-1, J_t^-1 (no orthogonality needed)"])


# --------------------------------------------------------------------------- claims

_C = "c004"
_Y_NOTE = ("Printed y = g + L1 v_e + L1 S(w) r_e; the middle line of eq. 22 (+m L1 v_e - m L1 S(w) r_e = "
           "m L1 r_e-dot by eq. 13) needs -L1 v_e: the residual is 2 m L1 v_e.")
_YY_NOTE = ("Printed Y ends with - L(L2 G(sigma_e) w_e); eq. 30 has + J L2 G(sigma_e) w_e, so the printed Y "
            "misses J s2-dot by 2 L(L2 G w_e) theta (L as corrected, to isolate the sign).")
_R_NOTE = ("Printed eq. 9 has + 8/(1+s^2)^2 S^T S; S^T S = -S^2 is positive semidefinite, so R^T R != I "
           "(||R|| up to 3 at |sigma| = 1).")

CLAIMS = [
    # ---- position (3.1)
    Claim(f"{_C}.position.V1_definite", _C, "position", "abstract", "23",
          "V1 is positive definite in (r_e, s1, m~, rho~_f, rho~_m)", _v1_positive),
    Claim(f"{_C}.position.surface_dynamics", _C, "position", "abstract", "21-22",
          "m s1-dot = -m y - m n1 + f + d_f along eqs. 13, 19", _surface_dynamics("printed"),
          _surface_dynamics("code"), correction="y = g - L1 v_e + L1 S(w) r_e (= g - L1 r_e-dot)",
          note=_Y_NOTE),
    Claim(f"{_C}.position.eq24_identity", _C, "position", "abstract", "24",
          "V1-dot = -k0 r^T L1 r + s1^T(k0 r - m y - m n1 + f + d_f) + estimate terms (any f)",
          _eq24("printed"), _eq24("code"), correction="y = g - L1 v_e + L1 S(w) r_e",
          note="Inherits eq. 22's printed y: the residual is 2 m s1^T L1 v_e."),
    Claim(f"{_C}.position.eq26_identity", _C, "position", "abstract", "25-26",
          "V1-dot under the law (25) equals eq. 26 (estimate rates free)", _eq26,
          note="With y as corrected in eq. 22; the law and the printed line use the same y, so this step holds "
               "for either y given eq. 22."),
    Claim(f"{_C}.position.V1dot_identity", _C, "position", "abstract", "24-27",
          "V1-dot along eqs. 13, 19 under eqs. 25, 27: the estimation errors cancel", _v1dot_identity,
          note="With y as corrected in eq. 22 (with the printed y in the law this step fails too, by eq. 22)."),
    Claim(f"{_C}.position.closed_loop", _C, "position", "abstract", "28",
          "closed loop m s1-dot = -k0 r - K1 s1 + m~ y - m n1 + d_f - (rho^_f + rho^_m ‖p_t‖ ‖w_t‖^2) sgn(s1)",
          _closed_loop_28),
    Claim(f"{_C}.position.n1_bound", _C, "position", "spacecraft", "19, 27",
          "‖m n1‖ <= rho_m ‖p_t‖ ‖w - w_e‖^2, rho_m = m ‖J_t^-1‖ ‖J_t‖", _n1_bound,
          note="Uses ||R|| = ||R^T|| = 1, true for the corrected eq. 9 only (see c004.model.eq9_rotation)."),
    Claim(f"{_C}.position.V1dot_bound", _C, "position", "abstract", "27-28",
          "V1-dot <= -k0 r_e^T L1 r_e - s1^T K1 s1 <= -s1^T K1 s1", _v1dot_bound),
    # ---- attitude (3.2)
    Claim(f"{_C}.attitude.V2_definite", _C, "attitude", "abstract", "32",
          "V2 is positive definite in (s2, theta~, rho~_tau, rho~_J) for J > 0", _v2_positive),
    Claim(f"{_C}.attitude.L_operator", _C, "attitude", "abstract", "31 (L)",
          "J a = L(a) theta, theta = [J11, J22, J33, J23, J13, J12]", _L_operator(True), _L_operator(False),
          correction="row 1 of L = [a1, 0, 0, 0, a3, a2]",
          note="Row 1 is printed with five entries [a1 0 0 a3 a2]; read as the first five columns it gives "
               "J11 a1 + J23 a3 + J13 a2 instead of J11 a1 + J12 a2 + J13 a3."),
    Claim(f"{_C}.attitude.surface_dynamics", _C, "attitude", "abstract", "29-30",
          "J s2-dot along eqs. 14, 20 equals eq. 30", _eq30),
    Claim(f"{_C}.attitude.regressor_form", _C, "attitude", "abstract", "31",
          "J s2-dot = Y (theta0 + theta_Delta) + J n2 + tau + d_tau", _eq31("printed"), _eq31("code"),
          correction="Y = L(S(w_e)(w - w_e)) - S(w) L(w) + L(L2 G(sigma_e) w_e)", note=_YY_NOTE),
    Claim(f"{_C}.attitude.eq33_identity", _C, "attitude", "abstract", "33",
          "V2-dot = s2^T[Y theta + J n2 + tau + d_tau] + estimate terms (any tau)", _eq33("printed"),
          _eq33("code"), correction="Y = L(S(w_e)(w - w_e)) - S(w) L(w) + L(L2 G(sigma_e) w_e)",
          note="Inherits the printed Y of eq. 31: residual 2 s2^T L(L2 G w_e) theta."),
    Claim(f"{_C}.attitude.eq35_identity", _C, "attitude", "abstract", "34-35",
          "V2-dot under the law (34) equals eq. 35 (estimate rates free)", _eq35,
          note="With Y as corrected; the law and the printed line use the same Y, so the step itself holds for "
               "either Y given eq. 31."),
    Claim(f"{_C}.attitude.V2dot_identity", _C, "attitude", "abstract", "33-36",
          "V2-dot along eqs. 14, 20 under eqs. 34, 36: the estimation errors cancel", _v2dot_identity,
          note="With Y as corrected under eq. 31 (with the printed Y in the law this step fails too, by eq. 31)."),
    Claim(f"{_C}.attitude.closed_loop", _C, "attitude", "abstract", "37",
          "closed loop J s2-dot = -K2 s2 - Y theta~ + J n2 + d_tau - (rho^_tau + rho^_J ‖w_t‖^2) sgn(s2)",
          _closed_loop_37, note="Printed with Y theta-double-dot (an extraction artefact for theta~)."),
    Claim(f"{_C}.attitude.n2_bound", _C, "attitude", "spacecraft", "20, 36",
          "‖J n2‖ <= rho_J ‖w - w_e‖^2, rho_J = ‖J‖ ‖J_t^-1‖ ‖J_t‖", _n2_bound,
          note="Uses ||R|| = ||R^T|| = 1, true for the corrected eq. 9 only (see c004.model.eq9_rotation)."),
    Claim(f"{_C}.attitude.V2dot_bound", _C, "attitude", "abstract", "36-37",
          "V2-dot <= -s2^T K2 s2", _v2dot_bound),
    Claim(f"{_C}.attitude.V2_shadow_switch", _C, "attitude", "spacecraft", "14, 32",
          "‖sigma_e‖ <= 1 via the shadow-set switch: V2 does not jump up at the switch", _v2_shadow_switch,
          about="paper",
          note="Eq. 14 leaves the unit ball; keeping ‖sigma_e‖ <= 1 (assumed in the proof) needs the switch "
               "sigma -> -sigma at ‖sigma‖ = 1, which changes V2 by -2 w_e^T J L2 sigma: positive for some "
               "outward crossings when J L2 is not a multiple of I. V2 is then only piecewise continuous; rpo "
               "switches too (principal_mrp), so the proof's monotone V does not cover the switch."),
    # ---- Theorem 1 (section 4)
    Claim(f"{_C}.theorem.claim1_energy", _C, "theorem", "spacecraft", "7-8 (Claim 1)",
          "target kinetic energy is constant along eqs. 7, 8 (bounded target motion)", _claim1_energy),
    Claim(f"{_C}.theorem.hypothesis1_paper_data", _C, "theorem", "abstract", "Hyp. 1, sec. 5",
          "section 5's m, J, J_t, J0 satisfy Hypothesis 1 (positive, positive definite)",
          _hypothesis1_paper_data, about="paper"),
    Claim(f"{_C}.theorem.sigma_e0_constraint", _C, "theorem", "spacecraft", "Table 1",
          "Table 1's sigma_e(0) satisfies ‖sigma_e‖ <= 1", _sigma_e0(False), _sigma_e0(True), about="paper",
          correction="the shadow set -sigma/‖sigma‖^2 = [-0.4545, 0.5455, -0.6364] (same attitude)",
          note="sigma_e(0) = [0.5, -0.6, 0.7] has norm 1.049 > 1, against the constraint the proof uses."),
    Claim(f"{_C}.theorem.V_lower_bound", _C, "theorem", "abstract", "38 (proof)",
          "V = V1 + V2 >= k0/2‖r‖^2 + m/2‖s1‖^2 + l_J/2‖s2‖^2 + ‖zeta‖^2/(2 gamma)", _v_lower_bound,
          note="Holds, but the printed zeta omits rho~_f, so the proof's 'zeta bounded' does not name "
               "rho^_f (it is bounded anyway since V is)."),
    Claim(f"{_C}.theorem.Vdot_bound", _C, "theorem", "abstract", "38",
          "V-dot <= -l_k1‖s1‖^2 - l_k2‖s2‖^2 <= -mu‖s‖^2 <= 0 on the coupled closed loop", _theorem_vdot),
    Claim(f"{_C}.theorem.Vs_identity", _C, "theorem", "abstract", "39",
          "on s1 = s2 = 0: Vs-dot = -r^T L1 r - (1+‖sigma‖^2)/4 sigma^T L2 sigma", _vs_identity),
    Claim(f"{_C}.theorem.Vs_bound", _C, "theorem", "abstract", "39",
          "on s1 = s2 = 0: Vs-dot <= -l_m1‖r‖^2 - l_m2/4‖sigma‖^2 <= 0", _vs_bound),
    Claim(f"{_C}.theorem.G_invertible", _C, "theorem", "abstract", "14, 39",
          "G(sigma_e) is invertible: det G = (1 + ‖sigma‖^2)^3/64", _G_invertible),
    # ---- relative model (2.2): do the rigid bodies have the form the proof uses?
    Claim(f"{_C}.model.eq9_rotation", _C, "relative model", "spacecraft", "9",
          "R(sigma_e) is a rotation: R^T R = I, det R = 1", _orthogonal(True), _orthogonal(False),
          correction="R = I - 4(1-s^2)/(1+s^2)^2 S(s) + 8/(1+s^2)^2 S(s)^2", note=_R_NOTE),
    Claim(f"{_C}.model.R_dot", _C, "relative model", "spacecraft", "9, 14",
          "R-dot = -S(w_e) R along sigma_e-dot = G(sigma_e) w_e", _R_dot(True), _R_dot(False),
          correction="R = I - 4(1-s^2)/(1+s^2)^2 S(s) + 8/(1+s^2)^2 S(s)^2", note="Inherits eq. 9's print."),
    Claim(f"{_C}.model.eq13", _C, "relative model", "spacecraft", "1, 5, 11-13",
          "d/dt (r - R r_pt) = v_e - S(w) r_e (R from eq. 9, sigma_e from eq. 14)", _eq13,
          note="Holds with R as corrected; with the printed eq. 9 it fails (R-dot != -S(w_e) R, "
               "see c004.model.R_dot)."),
    Claim(f"{_C}.model.eq17", _C, "relative model", "spacecraft", "7, 11, 12, 17",
          "R v_pt-dot = -S(w - w_e)[v - v_e - S(w - w_e) R p_t] - R S(p_t) w_t-dot", _eq17,
          note="Holds with R as corrected; its middle line uses R S(a) = S(Ra) R, false for the printed eq. 9."),
    Claim(f"{_C}.model.eq19", _C, "relative model", "spacecraft", "15, 17-19",
          "eq. 15 with eqs. 17, 18 is eq. 19 (g, n1 as printed)", _eq19),
    Claim(f"{_C}.model.eq20", _C, "relative model", "spacecraft", "16, 18, 20",
          "eq. 16 with eq. 18 is eq. 20 (n2 as printed)", _eq20),
]


# --------------------------------------------------------------------------- mutations

_RF_HAT, _RJ_HAT = sp.Symbol("rhohat_f", real=True), sp.Symbol("rhohat_J", real=True)
_TH_HAT = list(symbols_vec("thetahat_Delta", 6))


def _id(name: str) -> str:
    return f"{_C}.{name}"


MUTATIONS = [
    # position law (25)
    Mutation("c004: +K1 s1 in eq. 25", c, "position_control", scale_argument("K1", -1),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"),
              _id("position.V1dot_bound"))),
    Mutation("c004: +k0 r_e in eq. 25", c, "position_control", scale_argument("k0", -1),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"))),
    Mutation("c004: drop rho^_f sgn(s1) from eq. 25", c, "position_control", drop_terms(_RF_HAT),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"),
              _id("position.V1dot_bound"))),
    Mutation("c004: printed y (+L1 v_e) in eq. 22", c, "position_regressor",
             replace_output(lambda out, g, v_e, r_e, omega, Lambda1: _printed_y(g, v_e, r_e, omega, Lambda1)),
             (_id("position.surface_dynamics"), _id("position.eq24_identity"), _id("position.V1dot_identity"))),
    # position adaptation (27)
    Mutation("c004: sign of the m_hat adaptation (eq. 27)", c, "position_adaptation", negate_output(0),
             (_id("position.V1dot_identity"),)),
    Mutation("c004: -gamma3 in the rho^_m adaptation (eq. 27)", c, "position_adaptation",
             scale_argument("gamma3", -1), (_id("position.V1dot_identity"),)),
    # attitude law (34)
    Mutation("c004: +K2 s2 in eq. 34", c, "attitude_control", scale_argument("K2", -1),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"),
              _id("attitude.V2dot_bound"))),
    Mutation("c004: drop Y theta^_Delta from eq. 34", c, "attitude_control", drop_terms(_TH_HAT),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"))),
    Mutation("c004: drop rho^_J ‖w_t‖^2 sgn(s2) from eq. 34", c, "attitude_control", drop_terms(_RJ_HAT),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"),
              _id("attitude.V2dot_bound"))),
    Mutation("c004: printed Y sign (under eq. 31)", c, "attitude_regressor",
             replace_output(lambda out, omega, omega_e, sigma_e, Lambda2: _printed_Y(omega, omega_e, sigma_e,
                                                                                     Lambda2)),
             (_id("attitude.regressor_form"), _id("attitude.eq33_identity"), _id("attitude.V2dot_identity"))),
    Mutation("c004: printed row 1 of L", c, "inertia_operator", replace_output(lambda out, a: _printed_L(a)),
             (_id("attitude.L_operator"), _id("attitude.regressor_form"), _id("attitude.V2dot_identity"))),
    # attitude adaptation (36)
    Mutation("c004: sign of the theta^ adaptation (eq. 36)", c, "attitude_adaptation", negate_output(0),
             (_id("attitude.V2dot_identity"),)),
    Mutation("c004: -gamma6 in the rho^_J adaptation (eq. 36)", c, "attitude_adaptation",
             scale_argument("gamma6", -1), (_id("attitude.V2dot_identity"),)),
    Mutation("c004: -gamma5 in the rho^_tau adaptation (eq. 36)", c, "attitude_adaptation",
             scale_argument("gamma5", -1), (_id("attitude.V2dot_identity"),)),
    # relative model (eq. 9)
    Mutation("c004: printed eq. 9 (S^T S)", c, "rotation_matrix", replace_output(lambda out, s: _printed_R(s)),
             (_id("model.eq9_rotation"), _id("model.R_dot"), _id("model.eq13"), _id("model.eq17"),
              _id("position.n1_bound"))),
]
