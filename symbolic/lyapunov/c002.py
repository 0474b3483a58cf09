"""Claims of 002 (Li et al.): Theorem 1 and its three Lyapunov arguments (eqs. 19-43).

The paper's proof has three candidates:

* V1 (eq. 26) for the sliding surfaces s1, s2 and the estimation errors alpha~ = alpha - alpha^
  (Theorem 1 i), along eqs. 19-20 (the surfaces' dynamics, where the auxiliary systems eqs. 17-18
  cancel the saturation), under the laws eqs. 23-24 and the adaptation eq. 25, with the lumped
  bounds eqs. 21-22;
* V2 (eq. 35) for the auxiliary states chi1, chi2 (Theorem 1 ii, the condition kappa > varpi);
* V3 (eq. 39) for the tracking errors q~_v, r~ (Theorem 1 iii).

Two layers.  *Spacecraft*: the relative model of :mod:`rpo.symbolic.controllers.c002` (eqs. 2-4, 7,
9, 11-12, with the corrected n_r and n_t) really gives eqs. 19-20, and its C_r, n_r, C_t, n_t obey the
lumped bounds eqs. 21-22.  *Abstract*: J s1_dot = eps_r + Phi1, m s2_dot = eps_t + Phi2 with
||Phi1||, ||Phi2|| inside the bounds of eqs. 21-22 (drawn in those balls), the rest of the proof.

Everything the controller computes comes from the module (looked up at check time, so mutations are
seen): the surfaces (eqs. 15-16), the auxiliary rates (eqs. 17-18), the laws (eqs. 23-24), the
adaptation (eq. 25), the model.  V1, V2, V3 and the paper's right-hand sides are typed from the paper
(the code has no Lyapunov functions).  The identity ``cosh^2 = 1/(1 - tanh^2)`` (phi^-1 of eqs. 17-18
is computed as cosh^2 in the code) is applied before the symbolic proof: :func:`_tanh_form`.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.utilities.lambdify import implemented_function

from ..controllers import c002 as c
from ..layout import XYZ, XYZW, Layout
from ..rotations import dot, quat_conj, quat_mul, quat_to_dcm, skew
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
    unit_quaternion,
)

DELTA = sp.Rational(2785, 10000)     # Lemma 1's delta (mu = 1)

# Module-level symbols that mutations name (symbols are equal by name and assumptions).
AHAT = sp.symbols("alphahat_1:10", real=True)
U_R = tuple(symbols_vec("u_r"))

# The paper's Section IV data (eq. 46, "The control parameters are selected as follows").
PAPER_GAINS = {"k1": 2.0, "k2": 0.1, "kappa1": 2.0, "k3": 4.0, "k4": 0.5, "k5": 0.5, "k6": 0.001,
               "kappa2": 2.0, "k7": 0.5, "k8": 20.0, "eps": 0.001}
Q0_PAPER = (0.16878105, -0.05986357, 0.13299289, 0.97480367)   # Theta(0) 3-2-1, scalar last
R0_PAPER = (10.0, 10.0, -10.0)                                  # r~(0) [m]; v~(0) = w~(0) = 0


# =========================================================================== helpers

def _prune(dom, *exprs):
    """The domain's variables that the expressions use, with the ones their draws depend on (found by a
    trial draw: a missing dependency raises KeyError).  Unused variables would only slow the search."""
    need = set().union(*[getattr(e, "free_symbols", set()) for e in exprs])
    owner = {s: v for v in dom for s in v.symbols}
    keep = {id(v) for v in dom if set(v.symbols) & need}
    while True:
        ordered = [v for v in dom if id(v) in keep]
        env, z = {}, np.zeros((1, sum(v.dim for v in ordered)))
        try:
            k = 0
            for v in ordered:
                cols = v.draw(z[:, k:k + v.dim], env)
                k += v.dim
                env.update({s: cols[:, j] for j, s in enumerate(v.symbols)})
            return ordered
        except KeyError as exc:
            keep.add(id(owner[exc.args[0]]))


def _statement(lhs, relation, rhs, domain, **kw) -> Statement:
    """A Statement over the part of ``domain`` it uses."""
    return Statement(lhs, relation, rhs, _prune(domain, lhs, rhs), **kw)


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


def _upper(M: sp.Matrix) -> list:
    return [M[i, j] for i in range(3) for j in range(i, 3)]


def _rot(z):
    """Rotation matrices (n, 3, 3) from MRPs in the unit ball (scipy, independent of rpo)."""
    from scipy.spatial.transform import Rotation

    sig = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1.0)
    return Rotation.from_mrp(sig).as_matrix()


def _spd(M: sp.Matrix, lo: float, hi: float, norm_symbol: sp.Symbol | None = None):
    """A symmetric positive definite J = C diag(d) C^T, d in [lo, hi]; optionally its 2-norm too."""
    syms = _upper(M) + ([norm_symbol] if norm_symbol is not None else [])

    def draw(z, env):
        d = lo + (z[:, :3] + 1.0) * 0.5 * (hi - lo)
        C = _rot(z[:, 3:6])
        J = np.einsum("nij,nj,nkj->nik", C, d, C)
        cols = [J[:, i, j] for i in range(3) for j in range(i, 3)]
        if norm_symbol is not None:
            cols.append(d.max(axis=1))
        return np.column_stack(cols)

    return custom(syms, 6, draw, f"J = C diag(d) C^T, d in [{lo:g}, {hi:g}]")


def _rotation_of(R: sp.Matrix):
    """The 9 entries of R (row-major) drawn as a rotation matrix."""
    return custom(list(R), 3, lambda z, env: _rot(z).reshape(len(z), 9), "rotation matrix")


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


# =========================================================================== the closed loop (spacecraft)

class _Loop:
    """The relative model (eqs. 2-4, 7, 9, 11-12) with the surfaces (15-16), the auxiliary systems
    (17-18) and the adaptation (25), all from the controller module.  The commands eps_r, eps_t and
    their saturated values u_r, u_t are free (eqs. 19-20, 27 hold for any); C_r, n_r, C_t, n_t and the
    disturbances are free symbols (the identities hold whatever they are; their bounds are eqs. 21-22).

    ``J_aux``, ``m_aux``: the inertia and mass used by eqs. 17-18 (the code's nominal J_nom, m_nom);
    the proof assumes they are the plant's J and m."""

    def __init__(self, S: _S, J_aux=None, m_aux=None, adaptation: bool = True):
        self.S = S
        J, m = S.J, S.m
        J_aux = J if J_aux is None else J_aux
        m_aux = m if m_aux is None else m_aux
        self.s1 = c.sliding_surface_attitude(S.w, S.qv, S.chi1, S.k1, S.k2)                 # eq. 15
        self.s2 = c.sliding_surface_position(S.v, S.r, S.chi2, S.k5, S.k6)                  # eq. 16
        self.states = [S.w, S.q, S.chi1, S.v, S.r, S.chi2]
        self.rates = [c.relative_angular_acceleration(J, S.C_r, S.n_r, S.w, S.u_r, S.d_r),   # eqs. 4, 11
                      c.relative_quaternion_rate(S.q, S.w),                                  # eqs. 2-3
                      c.aux_attitude_rate(S.chi1, J_aux, S.k2, S.kappa1, S.eps_r, S.u_r),     # eq. 17
                      c.relative_acceleration(m, S.C_t, S.v, S.n_t, S.u_t, S.d_t),            # eqs. 9, 12
                      c.relative_position_rate(S.v, S.C_t, S.r),                              # eq. 7
                      c.aux_position_rate(S.chi2, m_aux, S.k6, S.kappa2, S.eps_t, S.u_t)]     # eq. 18
        if adaptation:
            self.ahat_dot = c.adaptive_rates(self.s1, self.s2, S.w, S.v, S.r, S.ahat, S.beta, S.gamma)
            self.states.append(S.ahat)
            self.rates.append(self.ahat_dot)

    def J_s1_dot(self):
        return self.S.J * _tanh_form(_vec_lie(self.s1, self.states, self.rates))

    def m_s2_dot(self):
        return self.S.m * _tanh_form(_vec_lie(self.s2, self.states, self.rates))


def _eq19_rhs(S: _S):
    """Eq. 19's right-hand side as printed: eps_r - C_r w - n_r + d_r + k1/2 J (q^x + q0 I) w + kappa1 tanh chi1."""
    return (S.eps_r - S.C_r * S.w - S.n_r + S.d_r + S.k1 / 2 * S.J * (skew(S.qv) + S.q0 * sp.eye(3)) * S.w
            + S.kappa1 * c.tanh_vec(S.chi1))


def _eq20_rhs(S: _S, k_rdot):
    """Eq. 20 / 27's bracket: eps_t - m C_t v - m n_t + d_t + m k r~_dot + kappa2 tanh chi2,
    r~_dot = v - C_t r (eq. 7)."""
    return (S.eps_t - S.m * S.C_t * S.v - S.m * S.n_t + S.d_t + S.m * k_rdot * (S.v - S.C_t * S.r)
            + S.kappa2 * c.tanh_vec(S.chi2))


def _loop_domain(S: _S, J_aux=None, m_aux=None):
    out = [box(S.w, -1, 1), unit_quaternion(S.q), box(S.chi1, -2, 2), box(S.v, -2, 2), box(S.r, -20, 20),
           box(S.chi2, -2, 2), box(S.ahat, -1, 5), box(S.alpha, 0, 5), box(S.beta, 0.001, 10),
           box(S.gamma, 0.1, 2), box([S.k1, S.k2, S.k5, S.k6, S.kappa1, S.kappa2], 0.001, 5),
           box(S.m, 20, 200), _spd(S.J, 5, 40), box(S.eps_r, -10, 10), box(S.u_r, -1, 1),
           box(S.eps_t, -100, 100), box(S.u_t, -100, 100), box(S.C_r, -1, 1), box(S.C_t, -1, 1),
           box(S.n_r, -1, 1), box(S.n_t, -1, 1), box(S.d_r, -0.01, 0.01), box(S.d_t, -0.01, 0.01)]
    if J_aux is not None:
        out += [_spd(J_aux, 5, 40), box(m_aux, 20, 200)]
    return out


# --------------------------------------------------------------------------- eqs. 19-20 (spacecraft)

def _s1dot_corrected() -> Statement:
    S = _S()
    L = _Loop(S, adaptation=False)
    return _statement(L.J_s1_dot(), "==", _eq19_rhs(S), _loop_domain(S),
                     assumptions=["eq. 17 uses the plant's J", "cosh^2 = 1/(1 - tanh^2)"])


def _s2dot() -> Statement:
    S = _S()
    L = _Loop(S, adaptation=False)
    return _statement(L.m_s2_dot(), "==", _eq20_rhs(S, S.k5), _loop_domain(S),
                     assumptions=["eq. 18 uses the plant's m", "cosh^2 = 1/(1 - tanh^2)"])


def _nominal_inertia() -> Statement:
    """Eqs. 19-20 when eqs. 17-18 use a nominal J0, m0 (J and m are unknown: Assumption 2, Remark 2)."""
    S = _S()
    J0, m0 = _sym_matrix("J0"), sp.Symbol("m_0", positive=True)
    L = _Loop(S, J_aux=J0, m_aux=m0, adaptation=False)
    lhs = sp.Matrix.vstack(L.J_s1_dot(), L.m_s2_dot())
    rhs = sp.Matrix.vstack(_eq19_rhs(S), _eq20_rhs(S, S.k5))
    return _statement(lhs, "==", rhs, _loop_domain(S, J0, m0), symbolic=False, residual_seconds=1,
                     assumptions=["eqs. 17-18 with J0 != J, m0 != m (the code: J_nom, m_nom)"])


# --------------------------------------------------------------------------- eqs. 21-22 (spacecraft)

class _Bounds:
    """The lumped terms of eqs. 21-22 built from the code's C_r, n_r (eq. 4), C_t, n_t (eqs. 7, 9)."""

    def __init__(self):
        S = self.S = _S()
        self.w_t, self.wd_t = symbols_vec("omega_t"), symbols_vec("omegadot_t")
        self.v_t, self.vd_t = symbols_vec("v_t"), symbols_vec("vdot_t")
        self.sig, self.g_p = symbols_vec("sigma_t"), symbols_vec("g_p")
        self.a = sp.symbols("a_1:6", positive=True)       # Assumption 1 bounds (a5 unused)
        self.dg = symbols_vec("Deltag")                   # R v_t_dot - g_p: differential gravity, ||.|| <= a4
        self.b1, self.b3, self.D1, self.D2 = sp.symbols("b_1 b_3 D_1 D_2", positive=True)
        self.sig_n = sp.Symbol("sigmanorm", positive=True)
        R = self.R = c.dcm_pursuer_from_target(S.q)
        self.C_r = c.attitude_coriolis_matrix(S.J, R, self.w_t, S.w)
        n_r = c.attitude_nonlinear_term(S.J, R, self.w_t, self.wd_t)
        qv_dot = c.relative_quaternion_rate(S.q, S.w)[:3, :]
        self.Phi1 = (-self.C_r * S.w - n_r + S.d_r + S.k1 * S.J * qv_dot + S.kappa1 * c.tanh_vec(S.chi1))
        C_t = c.translation_rate_matrix(S.w, R, self.w_t)
        self.n_t = c.translation_nonlinear_term(R, self.w_t, self.wd_t, self.v_t, self.vd_t, self.sig, self.g_p)
        r_dot = c.relative_position_rate(S.v, C_t, S.r)
        self.Phi2 = (-S.m * C_t * S.v - S.m * self.n_t + S.d_t + S.k5 * S.m * r_dot
                     + S.kappa2 * c.tanh_vec(S.chi2))

    def gravity(self, expr):
        """g_p = R v_t_dot - Deltag: with gravity, Assumption 1's a4 bounds ||R v_t_dot - g_p|| (differential
        gravity ~ 3 n^2 ||r||, plus the target's non-gravitational acceleration), not ||v_t_dot||."""
        return expr.xreplace(dict(zip(self.g_p, self.R * self.vd_t - self.dg, strict=True)))

    def domain(self, near: bool, gravity: bool = False):
        """``near``: close to docking (small w~, v~, r~, kappa, D, a2) with a tumbling target in free
        space, seen from an inertial frame moving with the target's centre (v_t = v_t_dot = 0): where
        the printed bounds are tightest.  Otherwise ranges covering the paper's run and beyond."""
        S, (a1, a2, a3, a4, _) = self.S, self.a
        if near:
            dom = [box(S.w, -0.01, 0.01), box(S.v, -0.05, 0.05), box(S.r, -0.5, 0.5),
                   box([S.kappa1, S.kappa2, self.D1, self.D2], 0.0001, 0.01), box(a1, 0.05, 0.5),
                   box(a2, 0.0001, 0.01), fixed([a3, a4], [0.0, 0.0])]
        else:
            dom = [box(S.w, -1, 1), box(S.v, -2, 2), box(S.r, -20, 20), box([S.kappa1, S.kappa2], 0.01, 2),
                   box([self.D1, self.D2], 0, 0.01), box([a1, a2], 0.001, 0.5), box([a3, a4], 0.01, 10)]
        dom += [unit_quaternion(S.q), box(S.chi1, -3, 3), box(S.chi2, -3, 3), box([S.k1, S.k5], 0.5, 3),
                ball(self.w_t, a1), ball(self.wd_t, a2), ball(self.v_t, a3),
                ball(S.d_r, self.D1), ball(S.d_t, self.D2), _spd(S.J, 5, 40, self.b1), box(S.m, 20, 200),
                custom([self.b3], 0, lambda z, env: env[S.m][:, None], "b3 = m"),
                box(self.sig_n, 0.1, 10), ball(self.sig, self.sig_n)]
        if gravity:     # v_t_dot up to LEO gravity; a4 bounds R v_t_dot - g_p = Deltag
            dom += [ball(self.vd_t, 10.0), ball(self.dg, a4)]
        else:       # the printed model holds only in free space: no pursuer gravity
            dom += [ball(self.vd_t, a4), fixed(self.g_p, [0.0, 0.0, 0.0])]
        return dom

    def remark4_Cr(self, factor) -> Statement:
        """Remark 4: ||C_r w~|| <= a1 b1 ||w~|| + b1 ||w~||^2 (printed factor 1)."""
        S, a1 = self.S, self.a[0]
        w = _nrm(S.w)
        return _statement(_nrm(self.C_r * S.w), "<=", factor * a1 * self.b1 * w + self.b1 * w**2,
                         self.domain(near=True), symbolic=False, residual_seconds=1,
                         assumptions=["||omega_t|| <= a1", "||J|| = b1"])

    def remark5_nt(self, corrected: bool) -> Statement:
        """Remark 5: ||m n_t|| <= b3 a1 a3 + b3 a4 + b3 ||sigma_t|| a1 ||w~|| + b3 ||sigma_t|| a2."""
        S, (a1, a2, a3, a4, _) = self.S, self.a
        b3, sn = self.b3, self.sig_n
        rhs = b3 * a1 * a3 + b3 * a4 + b3 * sn * a1 * _nrm(S.w) + b3 * sn * a2
        lhs = _nrm(S.m * self.n_t)
        if corrected:
            rhs += b3 * a1**2 * sn
            lhs = self.gravity(lhs)
        return _statement(lhs, "<=", rhs, self.domain(near=not corrected, gravity=corrected),
                         symbolic=False, residual_seconds=1,
                         assumptions=["Assumption 1 (a1..a3)", "m <= b3", "||sigma_t|| = sigmanorm",
                                      "||R v_t_dot - g_p|| <= a4 (differential gravity)" if corrected
                                      else "free space (g_p = 0), ||v_t_dot|| <= a4"])

    def attitude(self) -> Statement:
        """Eq. 21 with the paper's alpha1..3 (Remark 4) and the code's C_r, n_r (corrected n_r)."""
        S, (a1, a2, *_) = self.S, self.a
        alpha1 = self.b1
        alpha2 = S.k1 * self.b1 / 2 + a1 * self.b1
        alpha3 = a1**2 * self.b1 + self.b1 * a2 + self.D1 + sp.sqrt(3) * S.kappa1
        w = _nrm(S.w)
        return _statement(_nrm(self.Phi1), "<=", alpha1 * w**2 + alpha2 * w + alpha3, self.domain(near=False),
                         symbolic=False, residual_seconds=1,
                         assumptions=["||omega_t|| <= a1, ||omega_t_dot|| <= a2 (Assumption 1)",
                                      "||J|| <= b1 (Assumption 2)", "||d_r|| <= D1 (Assumption 3)"])

    def position(self, corrected: bool) -> Statement:
        """Eq. 22 with the paper's alpha4..9 (Remark 5) or alpha9 corrected, the code's C_t, n_t."""
        S, (a1, a2, a3, a4, _) = self.S, self.a
        b3, sn = self.b3, self.sig_n
        w, v, r = _nrm(S.w), _nrm(S.v), _nrm(S.r)
        al = [b3, S.k5 * b3, b3 * sn * a1, S.k5 * b3 + b3 * a1, S.k5 * b3 * a1,
              b3 * sn * a2 + b3 * a1 * a3 + b3 * a4 + self.D2 + sp.sqrt(3) * S.kappa2]
        lhs = _nrm(self.Phi2)
        if corrected:
            al[5] += b3 * a1**2 * sn        # centripetal term of sigma_t
            lhs = self.gravity(lhs)
        rhs = al[0] * w * v + al[1] * w * r + al[2] * w + al[3] * v + al[4] * r + al[5]
        return _statement(lhs, "<=", rhs, self.domain(near=not corrected, gravity=corrected),
                         symbolic=False, residual_seconds=1,
                         assumptions=["Assumption 1 (a1..a3)", "m <= b3", "||d_t|| <= D2", "||sigma_t|| = sigmanorm",
                                      "||R v_t_dot - g_p|| <= a4" if corrected else "g_p = 0, ||v_t_dot|| <= a4"])


def _ct_skew() -> Statement:
    """C_t + C_t^T = 0 (hence r~^T C_t r~ = 0) for the code's C_t (eq. 7)."""
    S = _S()
    R = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))
    w_t = symbols_vec("omega_t")
    C_t = c.translation_rate_matrix(S.w, R, w_t)
    return _statement(C_t + C_t.T, "==", sp.zeros(3, 3),
                     [box(S.w, -1, 1), _rotation_of(R), box(w_t, -0.1, 0.1)])


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
        return _statement(V, ">", 0, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(at, -5, 5), box(S.ahat, -1, 5),
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
        return _statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.ahat, -1, 5),
                                          box(S.alpha, 0, 5), box(S.beta, 0.001, 10), box(S.m, 20, 200),
                                          _spd(S.J, 5, 40), box(s1d, -1, 1), box(s2d, -1, 1), box(ad, -1, 1)],
                         residual_seconds=3)
    return build


def _v1_time_varying() -> Statement:
    """Eq. 27 (first line) when J and m vary (Assumption 2: 'unknown time-varying'): V1_dot gains
    1/2 s1^T J_dot s1 + 1/2 m_dot ||s2||^2 that eq. 27 (and the proof) drop."""
    S = _S()
    s1d, s2d, ad = symbols_vec("s1dot"), symbols_vec("s2dot"), symbols_vec("alphahatdot", 9)
    Jdot, mdot = _sym_matrix("Jdot"), sp.Symbol("mdot", real=True)
    V = _V1(S, S.s1, S.s2, S.J, True)
    lhs = lie_derivative(V, [S.s1, S.s2, S.ahat, _upper(S.J), S.m], [s1d, s2d, ad, _upper(Jdot), mdot])
    rhs = (dot(S.s1, S.J * s1d) + S.m * dot(S.s2, s2d) - sum(S.atilde[i] * ad[i] / S.beta[i] for i in range(9)))
    return _statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.ahat, -1, 5), box(S.alpha, 0, 5),
                                      box(S.beta, 0.001, 10), box(S.m, 20, 200), _spd(S.J, 5, 40),
                                      _spd(Jdot, -0.01, 0.01), box(mdot, -0.05, 0), box(s1d, -1, 1), box(s2d, -1, 1),
                                      box(ad, -1, 1)],
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
        return _statement(lhs, "==", rhs, _loop_domain(S),
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
        return _statement(lhs, "==", rhs, [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.w, -1, 1), box(S.v, -2, 2),
                                          box(S.r, -20, 20), box(S.ahat, -1, 5), box(S.alpha, 0, 5),
                                          box(S.beta, 0.001, 10), box(S.gamma, 0.1, 2)])
    return build


def _lemma2_unit(corrected: bool):
    """Eq. 29's step for the k3 (k7) term: -k ||s||^2 / sqrt(||s||^2 + eps^2) <= -k ||s|| + eps (printed)."""
    def build() -> Statement:
        x, k, e = sp.symbols("snorm k varepsilon", positive=True)
        rhs = -k * x + (k * e if corrected else e)
        return _statement(-k * x**2 / sp.sqrt(x**2 + e**2), "<=", rhs,
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
            ww = w(env)
            return env[al[0]] * ww**2 + env[al[1]] * ww + env[al[2]]

        def r2(env):
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
        return _statement(A.V1dot, "<=", rhs, A.domain(gains=gains), symbolic=False, residual_seconds=1,
                          assumptions=[*A.assumptions, *(["the paper's gains, Table 1's J, m"] if gains else [])])
    return build


def _young() -> Statement:
    """Eq. 30: gamma alpha~ alpha^ = gamma(-alpha~^2 + alpha alpha~)
    <= -gamma(2l-1)/(2l) alpha~^2 + gamma l alpha^2/2."""
    at, al = sp.symbols("alphatilde alpha", real=True)
    g, l_ = sp.symbols("gamma l", positive=True)
    return _statement(g * at * (al - at), "<=", -g * (2 * l_ - 1) / (2 * l_) * at**2 + g * l_ * al**2 / 2,
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
        return _statement(A.V1dot, "<=", rhs, A.domain(l_=True), symbolic=False, residual_seconds=1,
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
        return _statement(Vdot, "<=", -rho * V + d, A.domain(l_=True), symbolic=False, residual_seconds=1,
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
    return _statement(o2 / S.k5, "<=", sp.Rational(3, 10), dom, symbolic=False, residual_seconds=0,
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
        return _statement(lhs, "<=", rhs, dom, symbolic=False, residual_seconds=1,
                         assumptions=["1/2 s1^T J s1 <= B1, 1/2 m |s2|^2 <= B2 (B_j = Delta_j/rho_j)",
                                      "J = diag(J1, J2, J3), any positive units"])
    return build


# =========================================================================== V2 (eqs. 35-38)

def _V2(S: _S):
    return S.k2 * dot(S.chi1, S.chi1) / 2 + S.k6 * dot(S.chi2, S.chi2) / 2


def _phi_inv_typed(chi):
    """phi^-1 as printed under eq. 18: diag(1 - tanh^2(chi_i))^-1."""
    return sp.diag(*[1 / (1 - sp.tanh(x) ** 2) for x in chi])


def _v2_definite() -> Statement:
    S = _S()
    return _statement(_V2(S), ">", 0, [box(S.chi1, -3, 3), box(S.chi2, -3, 3), box([S.k2, S.k6], 0.001, 5)],
                     positive=[S.k2, S.k6], zero_at=list(S.chi1) + list(S.chi2), assumptions=["k2, k6 > 0"])


def _v2_dot_identity() -> Statement:
    """Eq. 36: V2_dot = chi1^T phi1^-1 J^-1 [-kappa1 tanh chi1 + sat - eps] + chi2^T phi2^-1 m^-1 [...]."""
    S = _S()
    rates = [c.aux_attitude_rate(S.chi1, S.J, S.k2, S.kappa1, S.eps_r, S.u_r),
             c.aux_position_rate(S.chi2, S.m, S.k6, S.kappa2, S.eps_t, S.u_t)]
    lhs = _tanh_form(lie_derivative(_V2(S), [S.chi1, S.chi2], rates))
    rhs = (dot(S.chi1, _phi_inv_typed(S.chi1) * S.J.inv() * (-S.kappa1 * c.tanh_vec(S.chi1) + S.u_r - S.eps_r))
           + dot(S.chi2, _phi_inv_typed(S.chi2) / S.m * (-S.kappa2 * c.tanh_vec(S.chi2) + S.u_t - S.eps_t)))
    return _statement(lhs, "==", rhs, _loop_domain(S), assumptions=["cosh^2 = 1/(1 - tanh^2)"])


def _lemma1() -> Statement:
    """Eq. 37 (Lemma 1 for vectors): -kappa chi^T tanh(chi) <= -kappa ||chi|| + kappa delta."""
    S = _S()
    return _statement(-S.kappa1 * dot(S.chi1, c.tanh_vec(S.chi1)), "<=",
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
        return _statement(lhs, "<=", rhs, X.domain(), symbolic=False, residual_seconds=1,
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
    return _statement(lhs, "<=", 0, dom, symbolic=False, residual_seconds=1,
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
    return _statement(lhs, "<=", 0, dom, symbolic=False, residual_seconds=0,
                      assumptions=["kappa_j > varpi_j >= ||sat(eps) - eps||", "J diagonal (Table 1)"])


# =========================================================================== V3 (eqs. 39-43)

def _V3(S: _S):
    return dot(S.qv, S.qv) + (1 - S.q0) ** 2 + dot(S.r, S.r) / 2


def _v3_definite() -> Statement:
    S = _S()
    e0 = sp.Symbol("e_0", real=True)            # e0 = 1 - q0
    return _statement(_V3(S).subs(S.q0, 1 - e0), ">", 0, [box(S.qv, -1, 1), box(e0, 0, 2), box(S.r, -20, 20)],
                     zero_at=[*S.qv, e0, *S.r], assumptions=["e0 = 1 - q0"])


def _v3_upper() -> Statement:
    S = _S()
    return _statement(_V3(S), "<=", dot(S.qv, S.qv) + 4 + dot(S.r, S.r) / 2,
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
    return _statement(lhs, "==", rhs, _loop_domain(S))


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
        return _statement(T.V3dot, "<=", rhs, T.domain(), symbolic=False, residual_seconds=1, assumptions=T.assumptions)
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
        return _statement(T.V3dot, "<=", -rate * T.V3 + const, T.domain(), symbolic=False, residual_seconds=1,
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
        return _statement(sp.S.One, ">", const / rate, dom, symbolic=False, residual_seconds=1,
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
    return _statement(lhs, "<=", rhs, dom, symbolic=False, residual_seconds=1,
                     assumptions=["||s_j|| <= o_j, ||q~_v|| <= o3, ||r~|| <= o4, ||chi_j|| <= c_j (Omega_2)"])


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
        return _statement(sp.Matrix([S.k1, S.k5]), ">", sp.Matrix([sp.S.Half, sp.S.Half - _nrm(W)]), dom,
                          symbolic=False, residual_seconds=0, assumptions=["||C_t|| = ||W|| <= 2.6e-3 rad/s"])
    eta = sp.Rational(1, 10**6)
    return _statement(sp.Matrix([S.k1 - sp.S.Half, S.k5 - sp.S.Half]), ">=", sp.Matrix([eta, eta]), dom[:1],
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
        return _statement(kap, ">", varpi, dom, symbolic=False, residual_seconds=1, trials=4,
                         assumptions=["varpi >= ||sat(eps) - eps|| at t = 0 (a lower bound of varpi)", note])
    return build


# =========================================================================== the law itself (provenance)

_SAT = implemented_function(sp.Function("sat", real=True), lambda e, u: np.clip(e, -u, u))


def _opaque_sat(expr):
    """Max(-u, Min(u, e)) -> sat(e, u), a function NumPy evaluates as clip: SymPy's Abs (the checker's round-off
    scale) otherwise spends minutes asking the sign of the unevaluated Max/Min."""
    def is_sat(x):
        return isinstance(x, sp.Max) and len(x.args) == 2 and any(isinstance(a, sp.Min) for a in x.args)

    def to_sat(x):
        mn = next(a for a in x.args if isinstance(a, sp.Min))
        u = -next(a for a in x.args if a is not mn)
        e = next(a for a in mn.args if a != u)
        return _SAT(e, u)

    return expr.replace(is_sat, to_sat)


def _law_identity(part: str) -> Statement:
    """C002.law (what generates the C code) against eqs. 1, 5-6, 13, 15-18, 23-25 typed here from the paper.

    ``part="kinematics"``: diag q_err, rate_err, pos_err, vel_err against eqs. 1, 5-6 of the measurements.
    ``part="law"``: the surfaces (diag s1, s2), the commands (diag eps_r, eps_t), the saturated outputs (cmd),
    the auxiliary and adaptive rates (xc_dot) against eqs. 13, 15-18, 23-25; to keep the expressions small the
    target frame is the inertial/LVLH one here (q_t = q_cL = identity, w_t = 0, n = 0, sigma_t = 0), so the
    relative signals are q_c, w_c, r, v themselves (the general frame chain is the kinematics part)."""
    ctrl = c.C002()
    k, xc = ctrl.k, ctrl.xc
    M = Layout("meas")
    for n, size in (("q_t", 4), ("q_c", 4), ("q_cL", 4), ("w_c", 3), ("w_t", 3), ("r", 3), ("v", 3), ("n", 1)):
        M.add(n, size, "-", n, XYZW if size == 4 else (XYZ if size == 3 else ()))
    cmd, xc_dot, diag = ctrl.law(M, sp.Symbol("t", real=True), {})

    def block(layout, vec, name):
        a, b = layout.offsets()[name]
        return vec[a:b, 0]

    # ---- typed from the paper (rotations only from rpo.symbolic.rotations)
    q = quat_mul(quat_conj(M["q_t"]), M["q_c"])                                   # eq. 1
    R = quat_to_dcm(q).T
    C_pL = quat_to_dcm(M["q_cL"]).T
    sig = k["sigma_t"]
    w = M["w_c"] - R * M["w_t"]
    r = C_pL * M["r"] - R * sig                                                    # eq. 5
    v = C_pL * (M["v"] + skew(sp.Matrix([0, 0, M["n"]])) * M["r"]) - R * skew(M["w_t"]) * sig     # eq. 6
    chi1, chi2, a = xc["chi1"], xc["chi2"], xc["alpha_hat"]
    th1, th2 = chi1.applyfunc(sp.tanh), chi2.applyfunc(sp.tanh)
    s1 = w + k["k1"] * q[:3, :] - k["k2"] * th1                                   # eq. 15
    s2 = v + k["k5"] * r - k["k6"] * th2                                           # eq. 16
    eps = k["eps"]
    w2, v2, r2 = dot(w, w), dot(v, v), dot(r, r)

    def lemma2(s_, ai, y2):
        return -s_ * ai**2 * y2 / sp.sqrt(dot(s_, s_) * ai**2 * y2 + eps**2)

    eps_r = (lemma2(s1, a[0], w2**2) + lemma2(s1, a[1], w2) + lemma2(s1, a[2], 1)
             - k["k3"] * s1 / sp.sqrt(dot(s1, s1) + eps**2) - k["k4"] * s1)                   # eq. 23
    eps_t = sum((lemma2(s2, a[3 + i], y) for i, y in enumerate([w2 * v2, w2 * r2, w2, v2, r2, 1])), sp.zeros(3, 1))
    eps_t += -k["k7"] * s2 / sp.sqrt(dot(s2, s2) + eps**2) - k["k8"] * s2                    # eq. 24
    def sat(e, u):      # unevaluated, as in the code: SymPy would try to order u against e
        return sp.Max(-u, sp.Min(u, e, evaluate=False), evaluate=False)

    u_r = eps_r.applyfunc(lambda e: sat(e, k["tau_max"]))                                   # eq. 13
    u_t = eps_t.applyfunc(lambda e: sat(e, k["f_max"]))
    Jn = k["J_nom"]
    chi1_dot = sp.Matrix([(-k["kappa1"] * th1[i] + u_r[i] - eps_r[i]) / ((1 - th1[i] ** 2) * Jn[i] * k["k2"])
                          for i in range(3)])                                                   # eq. 17
    chi2_dot = sp.Matrix([(-k["kappa2"] * th2[i] + u_t[i] - eps_t[i]) / ((1 - th2[i] ** 2) * k["m_nom"] * k["k6"])
                          for i in range(3)])                                                   # eq. 18
    n1, n2, nw, nv, nr = (sp.sqrt(dot(x, x)) for x in (s1, s2, w, v, r))
    y = [n1 * nw**2, n1 * nw, n1, n2 * nw * nv, n2 * nw * nr, n2 * nw, n2 * nv, n2 * nr, n2]
    a_dot = sp.Matrix([k["beta"][i] * (y[i] - k["gamma"][i] * a[i]) for i in range(9)])       # eq. 25

    cl = c.command_layout()
    if part == "kinematics":
        lhs = sp.Matrix.vstack(*[block(ctrl.diag, diag, n) for n in ("q_err", "rate_err", "pos_err", "vel_err")])
        rhs = sp.Matrix.vstack(q, w, r, v)
        dom = [unit_quaternion(M["q_t"]), unit_quaternion(M["q_c"]), unit_quaternion(M["q_cL"]),
               box(M["w_c"], -0.5, 0.5), box(M["w_t"], -0.1, 0.1), box(M["r"], -20, 20), box(M["v"], -2, 2),
               box(M["n"], 0.0005, 0.002), box(sig, -5, 5)]
        return _statement(lhs, "==", rhs, dom, assumptions=["C002.law as generated"])
    lhs = sp.Matrix.vstack(block(ctrl.diag, diag, "s1"), block(ctrl.diag, diag, "s2"),
                           block(ctrl.diag, diag, "eps_r"), block(ctrl.diag, diag, "eps_t"),
                           block(cl, cmd, "tau_w"), block(cl, cmd, "F"),
                           block(xc, xc_dot, "chi1"), block(xc, xc_dot, "chi2"), block(xc, xc_dot, "alpha_hat"))
    rhs = sp.Matrix.vstack(s1, s2, eps_r, eps_t, u_r, u_t, chi1_dot, chi2_dot, a_dot)
    frame = {**dict(zip(M["q_t"], (0, 0, 0, 1), strict=True)), **dict(zip(M["q_cL"], (0, 0, 0, 1), strict=True)),
             **dict.fromkeys([*M["w_t"], M["n"], *sig], 0)}
    lhs, rhs = (_opaque_sat(_tanh_form(x.xreplace(frame))) for x in (lhs, rhs))
    dom = [unit_quaternion(M["q_c"]), box(M["w_c"], -0.5, 0.5), box(M["r"], -20, 20), box(M["v"], -2, 2),
           box([k[n] for n in ("k1", "k2", "kappa1", "k3", "k4", "k5", "k6", "kappa2",
                                                          "k7")], 0.001, 5),
           box(k["k8"], 0.1, 50), box(eps, 0.0001, 0.1), box(k["beta"], 0.001, 10), box(k["gamma"], 0.1, 2),
           box(Jn, 5, 40), box(k["m_nom"], 20, 200), box(k["tau_max"], 0.2, 2),
           box(k["f_max"], 1, 200), box(chi1, -2, 2), box(chi2, -2, 2), box(a, -1, 5)]
    return _statement(lhs, "==", rhs, dom, symbolic=False, residual_seconds=0,
                      assumptions=["C002.law as generated (J_nom diagonal)", "cosh^2 = 1/(1 - tanh^2)"])


# =========================================================================== claims

C, P = "c002", "paper"
CLAIMS = [
    # ---- spacecraft layer: the model has the form the proof uses
    Claim("c002.model.s1dot_identity", C, "attitude", "spacecraft", "2-4, 11, 15, 17, 19",
          "J s1_dot along the code's model, eq. 15 and eq. 17 equals eq. 19's right-hand side",
          None, _s1dot_corrected,
          note="Eq. 19 prints the left side 'J_dot s1', a typesetting slip (the same line's right side is J times "
               "s1_dot term by term); checked as J s1_dot."),
    Claim("c002.model.s2dot_identity", C, "position", "spacecraft", "7, 9, 12, 16, 18, 20",
          "m s2_dot along the code's model, eq. 16 and eq. 18 equals eq. 20's right-hand side", _s2dot),
    Claim("c002.model.known_inertia_needed", C, "attitude + position", "spacecraft", "17-20, Assumption 2",
          "eqs. 19-20 hold when eqs. 17-18 use a nominal J0, m0 instead of the unknown J, m", _nominal_inertia,
          about=P,
          note="The saturation terms cancel only if eqs. 17-18 use the plant's J and m, which the paper calls "
               "unknown (Assumption 2, Remark 2); a mismatch leaves (I - J J0^-1)(sat - eps - kappa1 tanh chi1) in "
               "eq. 19.  rpo uses J_nom, m_nom: the truth in the paper plant, nominal values in the full plant "
               "(000's chaser and mass profile)."),
    Claim("c002.model.remark4_Cr", C, "attitude", "spacecraft", "4, Remark 4",
          "||C_r w~|| <= a1 b1 ||w~|| + b1 ||w~||^2 for the code's C_r",
          lambda: _Bounds().remark4_Cr(1), lambda: _Bounds().remark4_Cr(3),
          correction="3 a1 b1 ||w~|| + b1 ||w~||^2: C_r w~ has three terms linear in R w_t (J(Rw_t)^x w~, "
                     "(Rw_t)^x J w~, -(J R w_t)^x w~)",
          note="The part of C_r w~ bilinear in (R w_t, w~) was sampled up to 1.9 a1 b1 ||w~|| for a general "
               "inertia (1.4 for a physical one); Remark 4 bounds it by a1 b1 ||w~||, wrong when ||w~|| << a1."),
    Claim("c002.model.lumped_bound_attitude", C, "attitude", "spacecraft", "4, 21, Remark 4",
          "||-C_r w~ - n_r + d_r + k1/2 J(q^x + q0 I) w~ + kappa1 tanh chi1|| <= alpha1|w~|^2 + alpha2|w~| + alpha3",
          lambda: _Bounds().attitude(),
          note="Holds with the paper's alpha1..3 despite the Remark 4 slip: the quadratic and n_r terms are "
               "over-bounded (|(J w) x w| <= (lambda_max - lambda_min)/2 |w|^2) by more than the slip."),
    Claim("c002.model.remark5_nt", C, "position", "spacecraft", "9, Remark 5",
          "||m n_t|| <= b3 a1 a3 + b3 a4 + b3 ||sigma_t|| a1 ||w~|| + b3 ||sigma_t|| a2 for the code's n_t",
          lambda: _Bounds().remark5_nt(False), lambda: _Bounds().remark5_nt(True),
          correction="+ b3 a1^2 ||sigma_t||, with a4 >= ||R v_t_dot - g_p|| (differential gravity ~ 3 n^2 ||r||)",
          note="Remark 5 bounds the printed n_t (eq. 9 erratum); the physical one has the centripetal "
               "acceleration (R w_t)^x (R w_t)^x R sigma_t of the rendezvous point, present even in free space "
               "at rest relative to a tumbling target."),
    Claim("c002.model.lumped_bound_position", C, "position", "spacecraft", "7, 9, 22, Remark 5",
          "||-m C_t v~ - m n_t + d_t + k5 m r~_dot + kappa2 tanh chi2|| <= eq. 22's bound",
          lambda: _Bounds().position(False), lambda: _Bounds().position(True),
          correction="alpha9 + b3 a1^2 ||sigma_t|| (centripetal term), a4 >= ||R v_t_dot - g_p||",
          note="Paper statement near docking in free space (v_t = 0): the centripetal term, constant in w~, "
               "exceeds the printed alphas; the corrected alpha9 is checked on the wide domain with gravity, where a4 "
               "bounds the differential gravity R v_t_dot - g_p (not each gravity: b3 ||g_p|| ~ 830 N >> f_max)."),
    Claim("c002.model.Ct_skew", C, "position", "spacecraft", "7, 41",
          "r~^T C_t r~ = 0: C_t = (w~ + R w_t)^x of the code is skew-symmetric", _ct_skew),
    Claim("c002.model.law_composition", C, "attitude + position", "spacecraft", "1, 5-6, 13, 15-18, 23-25",
          "C002.law's s1, s2, eps_r, eps_t, sat outputs and xc_dot equal eqs. 1, 5-6, 13, 15-18, 23-25 of its "
          "own inputs",
          None, lambda: _law_identity("law"),
          note="Provenance: the other claims call the equation functions; this one checks that the law that generates "
               "the C code composes them as the paper's equations (typed here) with its own signals."),
    Claim("c002.model.law_kinematics", C, "attitude + position", "spacecraft", "1, 3, 5-6",
          "C002.law's diag q_err, rate_err, pos_err, vel_err equal eqs. 1, 5-6 (and omega~ under eq. 3) of its inputs",
          None, lambda: _law_identity("kinematics")),
    # ---- V1 (Theorem 1 i)
    Claim("c002.V1.definite", C, "sliding surfaces", "abstract", "26",
          "V1 is positive definite in (s1, s2, alpha~) (printed 1/beta_i and corrected 1/(2 beta_i))",
          _v1_definite(False), _v1_definite(True)),
    Claim("c002.V1.derivative_chain", C, "sliding surfaces", "abstract", "26, 27",
          "V1_dot = s1^T J s1_dot + s2^T m s2_dot - sum alpha~_i alpha^_i_dot / beta_i",
          _v1_chain(False), _v1_chain(True),
          correction="V1 = 1/2 s1^T J s1 + 1/2 m s2^T s2 + sum alpha~_i^2 / (2 beta_i)",
          note="With the printed sum alpha~_i^2/beta_i the derivative is -2 sum alpha~_i alpha^_i_dot/beta_i; eqs. "
               "31-32's rho (beta_i gamma_i (2l_i - 1)/l_i) also match the 1/(2 beta_i) form."),
    Claim("c002.V1.time_varying_inertia", C, "sliding surfaces", "abstract", "26, 27, Assumption 2",
          "eq. 27's V1_dot = s1^T J s1_dot + s2^T m s2_dot - ... when J(t), m(t) vary (Assumption 2)",
          _v1_time_varying, about=P,
          correction="V1_dot gains 1/2 s1^T J_dot s1 + 1/2 m_dot ||s2||^2; eq. 19 gains -J_dot (w~ + R w_t) "
                     "(Euler with varying J), neither bounded in eqs. 21-22",
          note="The paper's contribution ii (time-varying J, m) is not covered by its proof: its derivatives treat J, "
               "m as constants.  rpo's model and law take J, m constant (J_nom, m_nom)."),
    Claim("c002.V1.closed_loop_identity", C, "sliding surfaces", "spacecraft", "15-20, 25-27",
          "V1_dot along the full closed loop equals eq. 27's second line",
          _v1_closed_loop("k2"), _v1_closed_loop("k5"),
          correction="m k5 r~_dot in the position bracket (printed m k2 r~_dot)",
          note="Both statements use V1 with 1/(2 beta_i) (the eq. 26 slip is c002.V1.derivative_chain); the "
               "printed k2 in place of k5 leaves m (k5 - k2) s2^T r~_dot.  The adaptation part is the same on both "
               "sides (c002.V1.adaptation_cancels checks it): only the s-part is tested here."),
    Claim("c002.V1.adaptation_cancels", C, "sliding surfaces", "abstract", "25, 29",
          "eq. 25 turns -sum alpha~_i alpha^_i_dot/beta_i into -sum alpha~_i ||s|| y_i + sum gamma_i alpha~_i alpha^_i",
          _adaptation(True), _adaptation(False),
          correction="alpha^_7_dot = beta_7 (||s2|| ||v~|| - gamma_7 alpha^_7) (missing in print)",
          note="Eq. 25 as printed has eight laws; without alpha^_7's, the term alpha~_7 ||s2|| ||v~|| of eq. 22 "
               "stays in V1_dot."),
    Claim("c002.V1.lemma2_unit_terms", C, "sliding surfaces", "abstract", "14, 29",
          "-k ||s||^2/sqrt(||s||^2 + eps^2) <= -k ||s|| + eps (the k3, k7 terms of eqs. 23-24)",
          _lemma2_unit(False), _lemma2_unit(True),
          correction="<= -k ||s|| + k eps (Lemma 2 times k); eq. 29's 11 eps becomes (9 + k3 + k7) eps",
          note="The gap -k||s||^2/sqrt(.) + k||s|| reaches 0.30 k eps, > eps when k > 3.33 (the paper's k3 = 4).  "
               "Corrected form: gap = k x eps^2/(sqrt(x^2+eps^2)(sqrt(x^2+eps^2)+x)) <= k eps/2 for all x; searched "
               "over ||s|| in [0, 1e6 eps]."),
    Claim("c002.V1.bound", C, "sliding surfaces", "abstract", "21-25, 27-29",
          "V1_dot <= -k3||s1|| - k4||s1||^2 - k7||s2|| - k8||s2||^2 + sum gamma_i alpha~_i alpha^_i + c eps",
          _v1_bound(True), _v1_bound(False),
          correction="c = 9 + k3 + k7 (printed 11; the exact worst case is 0.3003 (9 + k3 + k7))",
          note="Typed with alpha^_i (eq. 29 prints alpha~_i alpha~_i_dot, a hat/dot slip: eq. 30 uses alpha^_i).  "
               "11 eps misses the k3, k7 factors of Lemma 2; it fails only for k3 + k7 > 27.6 at ||s_j|| ~ 0.79 eps "
               "(k3, k7 searched in [0.01, 40]); the paper's k3 + k7 = 4.5 passes (c002.gains.eq29_constant)."),
    Claim("c002.gains.eq29_constant", C, "sliding surfaces", "abstract", "29, 46",
          "eq. 29 with the printed 11 eps at the paper's gains (k3 = 4, k4 = 0.5, k7 = 0.5, k8 = 20, eps = 1e-3)",
          _v1_bound(True, PAPER_GAINS), about=P,
          note="At k3 + k7 = 4.5 the true constant 0.3003 (9 + k3 + k7) eps = 4.1 eps is below 11 eps."),
    Claim("c002.V1.young", C, "sliding surfaces", "abstract", "30",
          "gamma alpha~ alpha^ <= -gamma (2l - 1)/(2l) alpha~^2 + gamma l alpha^2 / 2", _young),
    Claim("c002.V1.exponential", C, "sliding surfaces", "abstract", "29-33",
          "V1_dot <= -rho1 V1 - rho2 V1 + Delta1 + Delta2",
          _v1_exponential(False), _v1_exponential(True),
          correction="-rho1 V1_att - rho2 V1_pos + Delta1 + Delta2 (each rho on its own subsystem; or -min(rho1, "
                     "rho2) V1), Delta1 = ... + (3 + k3) eps, Delta2 = ... + (6 + k7) eps",
          note="-rho1 V1 - rho2 V1 claims the sum of the two rates on all of V1; each rho only bounds its own "
               "subsystem's part (checked separately: c002.V1.exponential_att, c002.V1.exponential_pos)."),
    Claim("c002.V1.exponential_att", C, "attitude", "abstract", "29-34",
          "V1att_dot <= -rho1 V1att + Delta1 (V1att = 1/2 s1^T J s1 + sum_{i<=3} alpha~_i^2/(2 beta_i))",
          None, _v1_split("att"),
          note="The attitude and position parts of V1 decouple (s1 and alpha^_1..3 only in V1att); eq. 34 per "
               "subsystem rests on this and c002.V1.exponential_pos.  Delta1 = ... + (3 + k3) eps."),
    Claim("c002.V1.exponential_pos", C, "position", "abstract", "29-34",
          "V1pos_dot <= -rho2 V1pos + Delta2 (V1pos = 1/2 m ||s2||^2 + sum_{i>=4} alpha~_i^2/(2 beta_i))",
          None, _v1_split("pos"), note="Delta2 = ... + (6 + k7) eps."),
    Claim("c002.V1.residual_set", C, "sliding surfaces", "abstract", "34",
          "V1's parts <= Delta_j/rho_j imply ||s_j|| <= o_j = sqrt(2 Delta_j/rho_j)",
          _residual_set(False), _residual_set(True),
          correction="o1 = sqrt(2 Delta1 / (rho1 lambda_min(J))), o2 = sqrt(2 Delta2 / (rho2 m))",
          note="Dimensional: the printed o_j forgets J and m, so it fails only when lambda_min(J) < 1 or m < 1 in "
               "the chosen units (the search draws J, m from 0.1).  For Table 1's J, m in SI the printed o_j is a "
               "valid, looser bound."),
    Claim("c002.V1.informative", C, "position", "abstract", "22, 31-34, 46, Theorem 1 i",
          "at the paper's data, Theorem 1 i's residual set allows ||r~|| ~ o2/k5 below the published 0.3 m",
          _informative_pos, about=P,
          note="Even with alpha4..8 = 0 and alpha9 only sqrt(3) kappa2 + D2, rho2 <= beta9 gamma9 (2 l9 - 1)/l9 <= "
               "0.002 gives Delta2/rho2 >= 6000, ||s2|| <= 11 m/s, ||r~|| ~ 22 m: the bound says nothing at the 0.3 m "
               "scale (beta7..9 = 0.001 make rho2 tiny)."),
    # ---- V2 (Theorem 1 ii)
    Claim("c002.V2.definite", C, "auxiliary system", "abstract", "35",
          "V2 = k2/2 chi1^T chi1 + k6/2 chi2^T chi2 is positive definite", _v2_definite),
    Claim("c002.V2.derivative_identity", C, "auxiliary system", "abstract", "17-18, 36",
          "V2_dot along eqs. 17-18 equals eq. 36", _v2_dot_identity),
    Claim("c002.V2.lemma1", C, "auxiliary system", "abstract", "Lemma 1, 37",
          "-kappa chi^T tanh(chi) <= -kappa ||chi|| + kappa delta (vector form, delta = 0.2785)", _lemma1),
    Claim("c002.V2.bound", C, "auxiliary system", "abstract", "36-38",
          "V2_dot <= ||phi1^-1 J^-1|| [kappa1 delta - (kappa1 - varpi1)||chi1||] + m^-1 ||phi2^-1|| [...]",
          _v2_bound(False), _v2_bound(True),
          correction="sum over axes of (phi^-1 J^-1)_ii [kappa delta - (kappa - varpi)|chi_i|] (J diagonal)",
          note="-kappa chi^T M tanh(chi) <= -kappa ||M|| (||chi|| - delta) takes the largest weight M_ii = "
               "cosh^2(chi_i)/J_i for the negative term; with unequal chi_i it fails (also for Table 1's J)."),
    Claim("c002.V2.invariant_set", C, "auxiliary system", "abstract", "17-18, 38, Theorem 1 ii",
          "kappa_j > varpi_j: Omega_2 = {||chi_j|| <= kappa_j delta/(kappa_j - varpi_j)} is forward invariant",
          _invariant_set_printed, _invariant_set,
          correction="Omega_2 per axis: ||chi_j||_inf <= kappa_j delta/(kappa_j - varpi_j) (printed with ||chi_j||, "
                     "and Theorem 1 ii prints omega_j for varpi_j)",
          note="As printed (2-norm) chi^T chi_dot > 0 on the sphere when the weights cosh^2(chi_i)/J_i differ: "
               "eq. 38's max-weight slip (c002.V2.bound).  With J diagonal each axis of eqs. 17-18 is scalar; the "
               "per-axis bound gives ||chi_j|| <= sqrt(3) kappa_j delta/(kappa_j - varpi_j)."),
    # ---- V3 (Theorem 1 iii)
    Claim("c002.V3.definite", C, "tracking errors", "abstract", "39",
          "V3 = q~_v^T q~_v + (1 - q~0)^2 + 1/2 r~^T r~ is positive definite", _v3_definite),
    Claim("c002.V3.upper_bound", C, "tracking errors", "abstract", "40",
          "V3 <= q~_v^T q~_v + 4 + 1/2 r~^T r~", _v3_upper),
    Claim("c002.V3.derivative_identity", C, "tracking errors", "spacecraft", "2-3, 7, 15-16, 41",
          "V3_dot along eqs. 2-3, 7 = q~_v^T(s1 - k1 q~_v + k2 tanh chi1) + r~^T(s2 - k5 r~ + k6 tanh chi2 - C_t r~)",
          _v3_dot_identity),
    Claim("c002.V3.bound", C, "tracking errors", "abstract", "41",
          "V3_dot <= -(k1 - 1/2)(q~_v^T q~_v + 4) + o1^2 + k2^2 + 2(k1 - 1/2) - (k5 + ||C_t|| - 1/2)||r~||^2 "
          "+ o2^2 + k6^2",
          _v3_bound(False), _v3_bound(True),
          correction="... + 4(k1 - 1/2) + o1^2 + 3 k2^2 - (k5 - 1/2)||r~||^2 + o2^2 + 3 k6^2",
          note="r~^T C_t r~ = 0, so no -||C_t|| ||r~||^2 decay exists (the printed condition k5 > 1/2 - ||C_t|| "
               "becomes k5 > 1/2); adding and removing (k1 - 1/2)(.. + 4) needs 4(k1 - 1/2), not 2; "
               "||tanh chi||^2 <= 3 gives 3 k2^2."),
    Claim("c002.V3.exponential", C, "tracking errors", "abstract", "41",
          "V3_dot <= -(k1 + 2 k5 + 2||C_t|| - 3/2) V3 + o1^2 + k2^2 + 2(k1 - 1/2) + o2^2 + k6^2",
          _v3_exponential(False), _v3_exponential(True),
          correction="V3_dot <= -min(k1 - 1/2, 2(k5 - 1/2)) V3 + 4(k1 - 1/2) + o1^2 + 3 k2^2 + o2^2 + 3 k6^2",
          note="Printed with V2, typed with V3 (meant); it still fails: the sum of the two rates, the constant "
               "2(k1 - 1/2) and the -||C_t|| term.  At the paper's k5 = 0.5 the corrected rate is 0 (c002.gains.k5)."),
    Claim("c002.V3.informative", C, "tracking errors", "abstract", "40-41, Theorem 1 iii",
          "eq. 41's ultimate bound on V3 (>= ||q~_v||^2) is below 1, so it bounds q~_v",
          _informative(False), _informative(True), about=P,
          correction="none within this argument: needs e.g. V3_att = 2(1 - q~0) and ||q~_v||^2 >= 1 - q~0 (q~0 >= 0)",
          note="Bounding (1 - q~0)^2 by 4 (eq. 40) puts 4(k1 - 1/2)/(k1 - 1/2) = 4 into the ultimate bound: the "
               "argument cannot show q~_v small (printed constants: ~2 at the paper's gains)."),
    Claim("c002.V3.rate_bounds", C, "tracking errors", "abstract", "15-16, 42-43",
          "|w~_i| <= o1 + k1 o3 + k2 tanh(c1), |v~_i| <= o2 + k5 o4 + k6 tanh(c2)", _rate_bounds),
    # ---- the paper's gains against condition ii
    Claim("c002.gains.k5", C, "tracking errors", "abstract", "41, 46, Theorem 1 iii",
          "the paper's k1 = 2, k5 = 0.5 give eq. 41 positive rates (printed: k1 > 1/2, k5 > 1/2 - ||C_t||)",
          lambda: _k_condition(True), lambda: _k_condition(False), about=P,
          correction="k5 > 1/2 (C_t is skew, r~^T C_t r~ = 0)",
          note="The printed k5 > 1/2 - ||C_t|| holds at k5 = 0.5 only through ||C_t|| > 0, a term that does not exist; "
               "k5 = 0.5 makes the position rate 2(k5 - 1/2) of V3 zero.  k1 = 2 > 1/2 passes."),
    Claim("c002.gains.kappa1_varpi1", C, "auxiliary system", "abstract", "13, 15, 23, 46, Theorem 1 ii",
          "necessary: kappa1 > varpi1(0) with the paper's gains, torque limit 1 N m (rpo's reading)",
          _kappa_condition("att", 2.0, 1.0, "kappa1 = 2 (paper)"), about=P,
          correction="none checkable at design time: varpi1 = sup_t ||sat(eps_r) - eps_r|| has no a-priori bound",
          note="varpi1 >= ||sat(eps_r(0)) - eps_r(0)|| = 2.67 N m > kappa1 = 2, so condition ii fails (chi1 escapes at "
               "t = 1.705 s in the paper plant).  rpo's kappa1 = 3 (scenarios/002_scenario_kappa3.toml) passes this "
               "t = 0 test, which is necessary only (varpi1 peaks at ~2.9 N m along that run)."),
    Claim("c002.gains.kappa2_varpi2", C, "auxiliary system", "abstract", "13, 16, 24, 46, Theorem 1 ii",
          "necessary: kappa2 > varpi2(0) with the paper's gains and the printed force limit (1)",
          _kappa_condition("pos", 2.0, 1.0, "force limit 1 N as printed ('position subsystem +-1')"), about=P,
          correction="none checkable at design time: varpi2 = sup_t ||sat(eps_t) - eps_t|| has no a-priori bound",
          note="With the printed labels varpi2(0) = 172 N >> kappa2 = 2.  With rpo's reading (labels swapped, force "
               "limit 100 N, docs/controllers/c002.md) varpi2(0) = 0.5 N < 2 passes this necessary test, but kappa1 "
               "then fails (c002.gains.kappa1_varpi1): no reading satisfies condition ii."),
]


def _drop_alpha7(out, *a, **kw):
    out = sp.Matrix(out)
    out[6] = 0
    return out


MUTATIONS = [
    Mutation("c002: k4 -> -k4 in eq. 23", c, "attitude_control", scale_argument("k4", -1),
             ("c002.V1.bound", "c002.V1.exponential_att", "c002.model.law_composition")),
    Mutation("c002: sign of eps_r (eq. 23)", c, "attitude_control", negate_output(),
             ("c002.V1.bound", "c002.V1.exponential", "c002.V1.exponential_att", "c002.model.law_composition")),
    Mutation("c002: alpha^_3 term dropped from eq. 23", c, "attitude_control", drop_terms(AHAT[2]),
             ("c002.V1.bound",)),
    Mutation("c002: k3 -> -k3 in eq. 23", c, "attitude_control", scale_argument("k3", -1),
             ("c002.V1.bound",)),
    Mutation("c002: k8 -> -k8 in eq. 24", c, "position_control", scale_argument("k8", -1),
             ("c002.V1.bound", "c002.V1.exponential", "c002.V1.exponential_pos", "c002.model.law_composition")),
    Mutation("c002: k7 -> -k7 in eq. 24", c, "position_control", scale_argument("k7", -1),
             ("c002.V1.bound",)),
    Mutation("c002: alpha^_9 term dropped from eq. 24", c, "position_control", drop_terms(AHAT[8]),
             ("c002.V1.bound",)),
    Mutation("c002: sign of eq. 25", c, "adaptive_rates", negate_output(),
             ("c002.V1.adaptation_cancels", "c002.V1.bound")),
    Mutation("c002: gamma -> -gamma in eq. 25", c, "adaptive_rates", scale_argument("gamma", -1),
             ("c002.V1.adaptation_cancels", "c002.V1.bound", "c002.model.law_composition")),
    Mutation("c002: beta -> -beta in eq. 25", c, "adaptive_rates", scale_argument("beta", -1),
             ("c002.V1.adaptation_cancels",)),
    Mutation("c002: alpha^_7 law dropped (as printed, eq. 25)", c, "adaptive_rates", replace_output(_drop_alpha7),
             ("c002.V1.adaptation_cancels",)),
    Mutation("c002: sign of eq. 17", c, "aux_attitude_rate", negate_output(),
             ("c002.model.s1dot_identity", "c002.V1.closed_loop_identity", "c002.V2.derivative_identity",
              "c002.V2.invariant_set")),
    Mutation("c002: sat(eps_r) dropped from eq. 17", c, "aux_attitude_rate", drop_terms(U_R),
             ("c002.model.s1dot_identity", "c002.V2.derivative_identity")),
    Mutation("c002: kappa2 -> -kappa2 in eq. 18", c, "aux_position_rate", scale_argument("kappa2", -1),
             ("c002.model.s2dot_identity", "c002.V2.derivative_identity", "c002.V2.invariant_set",
              "c002.model.law_composition")),
    Mutation("c002: k1 -> -k1 in the attitude surface (eq. 15)", c, "sliding_surface_attitude",
             scale_argument("k1", -1), ("c002.model.s1dot_identity", "c002.model.law_composition")),
    Mutation("c002: k6 -> -k6 in the position surface (eq. 16)", c, "sliding_surface_position",
             scale_argument("k6", -1), ("c002.model.s2dot_identity", "c002.model.law_composition")),
    Mutation("c002: saturation sign flipped (eq. 13)", c, "saturation", negate_output(),
             ("c002.model.law_composition",)),
    Mutation("c002: sigma_t term of v~ sign flipped (eq. 6)", c, "relative_velocity", scale_argument("sigma_t", -1),
             ("c002.model.law_kinematics",)),
    Mutation("c002: omega~ = omega_p + R omega_t (under eq. 3)", c, "relative_angular_velocity",
             scale_argument("w_t", -1), ("c002.model.law_kinematics",)),
    Mutation("c002: sign of r~_dot (eq. 7)", c, "relative_position_rate", negate_output(),
             ("c002.model.s2dot_identity", "c002.V3.derivative_identity")),
]
