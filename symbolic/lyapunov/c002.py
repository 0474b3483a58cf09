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

from ..controllers import c002 as c
from ..rotations import dot, skew
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

def _s1dot_printed() -> Statement:
    """Eq. 19 as printed: 'J_dot s1' = ... (J_dot: any symmetric matrix, Assumption 2 lets J vary)."""
    S = _S()
    Jdot = _sym_matrix("Jdot")
    return _statement(Jdot * c.sliding_surface_attitude(S.w, S.qv, S.chi1, S.k1, S.k2), "==", _eq19_rhs(S),
                     [*_loop_domain(S), _spd(Jdot, -1, 1)], assumptions=["J_dot any (Assumption 2)"],
                     residual_seconds=3)


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
        self.a = sp.symbols("a_1:6", positive=True)       # Assumption 1 bounds (+ a5 >= |g_p|)
        self.b1, self.b3, self.D1, self.D2 = sp.symbols("b_1 b_3 D_1 D_2", positive=True)
        self.sig_n = sp.Symbol("sigmanorm", positive=True)
        R = c.dcm_pursuer_from_target(S.q)
        self.C_r = c.attitude_coriolis_matrix(S.J, R, self.w_t, S.w)
        n_r = c.attitude_nonlinear_term(S.J, R, self.w_t, self.wd_t)
        qv_dot = c.relative_quaternion_rate(S.q, S.w)[:3, :]
        self.Phi1 = (-self.C_r * S.w - n_r + S.d_r + S.k1 * S.J * qv_dot + S.kappa1 * c.tanh_vec(S.chi1))
        C_t = c.translation_rate_matrix(S.w, R, self.w_t)
        self.n_t = c.translation_nonlinear_term(R, self.w_t, self.wd_t, self.v_t, self.vd_t, self.sig, self.g_p)
        r_dot = c.relative_position_rate(S.v, C_t, S.r)
        self.Phi2 = (-S.m * C_t * S.v - S.m * self.n_t + S.d_t + S.k5 * S.m * r_dot
                     + S.kappa2 * c.tanh_vec(S.chi2))

    def domain(self, near: bool, gravity: bool = False):
        """``near``: close to docking (small w~, v~, r~, kappa, D, a2) with a tumbling target in free
        space, seen from an inertial frame moving with the target's centre (v_t = v_t_dot = 0): where
        the printed bounds are tightest.  Otherwise ranges covering the paper's run and beyond."""
        S, (a1, a2, a3, a4, a5) = self.S, self.a
        if near:
            dom = [box(S.w, -0.01, 0.01), box(S.v, -0.05, 0.05), box(S.r, -0.5, 0.5),
                   box([S.kappa1, S.kappa2, self.D1, self.D2], 0.0001, 0.01), box(a1, 0.05, 0.5),
                   box(a2, 0.0001, 0.01), fixed([a3, a4], [0.0, 0.0])]
        else:
            dom = [box(S.w, -1, 1), box(S.v, -2, 2), box(S.r, -20, 20), box([S.kappa1, S.kappa2], 0.01, 2),
                   box([self.D1, self.D2], 0, 0.01), box([a1, a2], 0.001, 0.5), box([a3, a4], 0.01, 10)]
        dom += [unit_quaternion(S.q), box(S.chi1, -3, 3), box(S.chi2, -3, 3), box([S.k1, S.k5], 0.5, 3),
                ball(self.w_t, a1), ball(self.wd_t, a2), ball(self.v_t, a3), ball(self.vd_t, a4),
                ball(S.d_r, self.D1), ball(S.d_t, self.D2), _spd(S.J, 5, 40, self.b1), box(S.m, 20, 200),
                custom([self.b3], 0, lambda z, env: env[S.m][:, None], "b3 = m"),
                box(self.sig_n, 0.1, 10), ball(self.sig, self.sig_n)]
        if gravity:
            dom += [box(a5, 0, 10), ball(self.g_p, a5)]
        else:       # the printed model holds only in free space: no pursuer gravity
            dom += [fixed(a5, [0.0]), fixed(self.g_p, [0.0, 0.0, 0.0])]
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
        S, (a1, a2, a3, a4, a5) = self.S, self.a
        b3, sn = self.b3, self.sig_n
        rhs = b3 * a1 * a3 + b3 * a4 + b3 * sn * a1 * _nrm(S.w) + b3 * sn * a2
        if corrected:
            rhs += b3 * a1**2 * sn + b3 * a5
        return _statement(_nrm(S.m * self.n_t), "<=", rhs, self.domain(near=not corrected, gravity=corrected),
                         symbolic=False, residual_seconds=1,
                         assumptions=["Assumption 1 (a1..a4)", "m <= b3", "||sigma_t|| = sigmanorm",
                                      "||g_p|| <= a5" if corrected else "free space (g_p = 0), v_t = 0"])

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
        S, (a1, a2, a3, a4, a5) = self.S, self.a
        b3, sn = self.b3, self.sig_n
        w, v, r = _nrm(S.w), _nrm(S.v), _nrm(S.r)
        al = [b3, S.k5 * b3, b3 * sn * a1, S.k5 * b3 + b3 * a1, S.k5 * b3 * a1,
              b3 * sn * a2 + b3 * a1 * a3 + b3 * a4 + self.D2 + sp.sqrt(3) * S.kappa2]
        if corrected:
            al[5] += b3 * a1**2 * sn + b3 * a5        # centripetal term of sigma_t; pursuer gravity
        rhs = al[0] * w * v + al[1] * w * r + al[2] * w + al[3] * v + al[4] * r + al[5]
        return _statement(_nrm(self.Phi2), "<=", rhs, self.domain(near=not corrected, gravity=corrected),
                         symbolic=False, residual_seconds=1,
                         assumptions=["Assumption 1 (a1..a4)", "m <= b3", "||d_t|| <= D2",
                                      "||sigma_t|| = sigmanorm", "||g_p|| <= a5" if corrected else "g_p = 0"])


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
                         [box(e, 0.001, 0.1), custom([x], 1, lambda z, env: (z + 1) * env[e][:, None], "0..2 eps"),
                          box(k, 0.01, 10)], symbolic=False, residual_seconds=1,
                         assumptions=["k > 0, eps > 0, ||s|| >= 0"])
    return build


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
        rates = [S.Jd.inv() * (self.eps_r + self.Phi1), (self.eps_t + self.Phi2) / S.m, self.ahat_dot]
        self.V1 = _V1(S, S.s1, S.s2, S.Jd, True)
        self.V1att = _V1(S, S.s1, S.s2, S.Jd, True, "att")
        self.V1pos = _V1(S, S.s1, S.s2, S.Jd, True, "pos")
        self.V1_printed = _V1(S, S.s1, S.s2, S.Jd, False)
        self.V1dot = lie_derivative(self.V1, [S.s1, S.s2, S.ahat], rates)
        n1, n2 = _nrm(S.s1), _nrm(S.s2)
        self.nominal = -S.k3 * n1 - S.k4 * n1**2 - S.k7 * n2 - S.k8 * n2**2
        self.young = sum(S.gamma[i] * S.atilde[i] * S.ahat[i] for i in range(9))

    def domain(self, l_: bool = False):
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

        dom = [box(S.s1, -1, 1), box(S.s2, -5, 5), box(S.w, -1, 1), box(S.v, -2, 2), box(S.r, -20, 20),
               box(S.ahat, -1, 5), box(al, 0, 5), box(S.beta, 0.001, 10), box(S.gamma, 0.1, 2),
               box([S.k3, S.k4, S.k7], 0.01, 10), box(S.k8, 0.1, 50), box(S.eps, 0.0001, 0.1),
               box(list(S.Jd.diagonal()), 5, 40), box(S.m, 20, 200), ball(self.Phi1, r1), ball(self.Phi2, r2)]
        if l_:
            dom.append(box(S.l, 0.5, 5))
        return dom

    assumptions = ["||Phi1|| <= alpha1 |w|^2 + alpha2 |w| + alpha3 (eq. 21)", "||Phi2|| <= eq. 22's bound",
                   "J = diag(J1, J2, J3) > 0, m > 0", "alpha^ of any sign"]


def _v1_bound(printed: bool):
    """Eq. 29: V1_dot <= -k3|s1| - k4|s1|^2 - k7|s2| - k8|s2|^2 + sum gamma_i alpha~_i alpha^_i + c eps."""
    def build() -> Statement:
        A = _Abstract()
        S = A.S
        if printed:     # as printed: gamma_i alpha~_i alpha~_i_dot (alpha~_dot = -alpha^_dot) and 11 eps
            rhs = A.nominal - sum(S.gamma[i] * S.atilde[i] * A.ahat_dot[i] for i in range(9)) + 11 * S.eps
        else:
            rhs = A.nominal + A.young + (9 + S.k3 + S.k7) * S.eps
        return _statement(A.V1dot, "<=", rhs, A.domain(), symbolic=False, residual_seconds=1, assumptions=A.assumptions)
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
        S = T.S
        rate, const = _v3_constants(T, corrected)
        V = T.V3 if corrected else _V2(S)
        return _statement(T.V3dot, "<=", -rate * V + const, T.domain(), symbolic=False, residual_seconds=1,
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


# =========================================================================== claims

C, P = "c002", "paper"
CLAIMS = [
    # ---- spacecraft layer: the model has the form the proof uses
    Claim("c002.model.s1dot_identity", C, "attitude", "spacecraft", "2-4, 11, 15, 17, 19",
          "J s1_dot along the code's model, eq. 15 and eq. 17 equals eq. 19's right-hand side",
          _s1dot_printed, _s1dot_corrected,
          correction="left side J s1_dot (printed 'J_dot s1', an extraction slip)",
          note="As printed the left side is J_dot s1; every term of the right side is J times a term of s1_dot."),
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
          correction="+ b3 a1^2 ||sigma_t|| + b3 a5 (||g_p|| <= a5)",
          note="Remark 5 bounds the printed n_t (eq. 9 erratum); the physical one has the centripetal "
               "acceleration (R w_t)^x (R w_t)^x R sigma_t of the rendezvous point, present even in free space "
               "at rest relative to a tumbling target."),
    Claim("c002.model.lumped_bound_position", C, "position", "spacecraft", "7, 9, 22, Remark 5",
          "||-m C_t v~ - m n_t + d_t + k5 m r~_dot + kappa2 tanh chi2|| <= eq. 22's bound",
          lambda: _Bounds().position(False), lambda: _Bounds().position(True),
          correction="alpha9 + b3 a1^2 ||sigma_t|| + b3 a5 (the physical n_t's centripetal term; pursuer gravity)",
          note="Paper statement near docking in free space (v_t = 0): the centripetal term, constant in w~, "
               "exceeds the printed alphas; the corrected alpha9 is checked on the wide domain with gravity."),
    Claim("c002.model.Ct_skew", C, "position", "spacecraft", "7, 41",
          "r~^T C_t r~ = 0: C_t = (w~ + R w_t)^x of the code is skew-symmetric", _ct_skew),
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
    Claim("c002.V1.closed_loop_identity", C, "sliding surfaces", "spacecraft", "15-20, 25-27",
          "V1_dot along the full closed loop equals eq. 27's second line",
          _v1_closed_loop("k2"), _v1_closed_loop("k5"),
          correction="m k5 r~_dot in the position bracket (printed m k2 r~_dot)",
          note="Both statements use V1 with 1/(2 beta_i) (the eq. 26 slip is c002.V1.derivative_chain); the "
               "printed k2 in place of k5 leaves m (k5 - k2) s2^T r~_dot."),
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
          note="The gap -k||s||^2/sqrt(.) + k||s|| reaches 0.30 k eps, > eps when k > 3.33: the paper's k3 = 4."),
    Claim("c002.V1.bound", C, "sliding surfaces", "abstract", "21-25, 27-29",
          "V1_dot <= -k3||s1|| - k4||s1||^2 - k7||s2|| - k8||s2||^2 + sum gamma_i alpha~_i alpha^_i + c eps",
          _v1_bound(True), _v1_bound(False),
          correction="sum gamma_i alpha~_i alpha^_i (printed alpha~_i alpha~_i_dot) and c = 9 + k3 + k7 (printed 11)",
          note="As printed the last sum is gamma_i alpha~_i alpha~_i_dot (eq. 30 then uses alpha^_i) and the "
               "constant 11 eps misses the k3, k7 factors of Lemma 2."),
    Claim("c002.V1.young", C, "sliding surfaces", "abstract", "30",
          "gamma alpha~ alpha^ <= -gamma (2l - 1)/(2l) alpha~^2 + gamma l alpha^2 / 2", _young),
    Claim("c002.V1.exponential", C, "sliding surfaces", "abstract", "29-33",
          "V1_dot <= -rho1 V1 - rho2 V1 + Delta1 + Delta2",
          _v1_exponential(False), _v1_exponential(True),
          correction="-rho1 V1_att - rho2 V1_pos + Delta1 + Delta2 (each rho on its own subsystem; or -min(rho1, "
                     "rho2) V1), Delta1 = ... + (3 + k3) eps, Delta2 = ... + (6 + k7) eps",
          note="-rho1 V1 - rho2 V1 claims the sum of the two rates on all of V1; each rho only bounds its own "
               "subsystem's part."),
    Claim("c002.V1.residual_set", C, "sliding surfaces", "abstract", "34",
          "V1's parts <= Delta_j/rho_j imply ||s_j|| <= o_j = sqrt(2 Delta_j/rho_j)",
          _residual_set(False), _residual_set(True),
          correction="o1 = sqrt(2 Delta1 / (rho1 lambda_min(J))), o2 = sqrt(2 Delta2 / (rho2 m))",
          note="The printed o_j forgets J and m; it holds only when lambda_min(J) >= 1 and m >= 1 in the chosen "
               "units (true for Table 1's J and m in SI)."),
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
          "kappa_j > varpi_j: each |chi_ji| decreases outside kappa_j delta/(kappa_j - varpi_j)",
          None, _invariant_set,
          correction="Omega_2 per axis: ||chi_j||_inf <= kappa_j delta/(kappa_j - varpi_j) (printed with ||chi_j||, "
                     "and Theorem 1 ii prints omega_j for varpi_j)",
          note="With J diagonal each axis of eqs. 17-18 is scalar; the per-axis bound also gives "
               "||chi_j|| <= sqrt(3) kappa_j delta/(kappa_j - varpi_j)."),
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
          "V3_dot <= -(k1 + 2 k5 + 2||C_t|| - 3/2) V2 + o1^2 + k2^2 + 2(k1 - 1/2) + o2^2 + k6^2",
          _v3_exponential(False), _v3_exponential(True),
          correction="V3_dot <= -min(k1 - 1/2, 2(k5 - 1/2)) V3 + 4(k1 - 1/2) + o1^2 + 3 k2^2 + o2^2 + 3 k6^2",
          note="Printed with V2 (V3 meant) and the sum of the two rates; at the paper's k5 = 0.5 the corrected rate "
               "is 0."),
    Claim("c002.V3.informative", C, "tracking errors", "abstract", "40-41, Theorem 1 iii",
          "eq. 41's ultimate bound on V3 (>= ||q~_v||^2) is below 1, so it bounds q~_v",
          _informative(False), _informative(True), about=P,
          correction="none within this argument: needs e.g. V3_att = 2(1 - q~0) and ||q~_v||^2 >= 1 - q~0 (q~0 >= 0)",
          note="Bounding (1 - q~0)^2 by 4 (eq. 40) puts 4(k1 - 1/2)/(k1 - 1/2) = 4 into the ultimate bound: the "
               "argument cannot show q~_v small (printed constants: ~2 at the paper's gains)."),
    Claim("c002.V3.rate_bounds", C, "tracking errors", "abstract", "15-16, 42-43",
          "|w~_i| <= o1 + k1 o3 + k2 tanh(c1), |v~_i| <= o2 + k5 o4 + k6 tanh(c2)", _rate_bounds),
    # ---- the paper's gains against condition ii
    Claim("c002.gains.kappa1_varpi1", C, "auxiliary system", "abstract", "13, 15, 23, 46, Theorem 1 ii",
          "kappa1 > varpi1 at t = 0 with the paper's gains, torque limit 1 N m (rpo's reading)",
          _kappa_condition("att", 2.0, 1.0, "kappa1 = 2 (paper)"),
          _kappa_condition("att", 3.0, 1.0, "kappa1 = 3 (scenarios/002_scenario_kappa3.toml)"), about=P,
          correction="kappa1 = 3 (scenarios/002_scenario_kappa3.toml; varpi1 peaks at ~2.9 N m along that run)",
          note="||sat(eps_r(0)) - eps_r(0)|| = 2.67 N m > kappa1 = 2: chi1 escapes at t = 1.705 s in the paper plant."),
    Claim("c002.gains.kappa2_varpi2", C, "auxiliary system", "abstract", "13, 16, 24, 46, Theorem 1 ii",
          "kappa2 > varpi2 at t = 0 with the paper's gains and the printed force limit (1)",
          _kappa_condition("pos", 2.0, 1.0, "force limit 1 N as printed ('position subsystem +-1')"),
          _kappa_condition("pos", 2.0, 100.0, "force limit 100 N (rpo's reading: labels swapped)"), about=P,
          correction="force limit 100 N (labels swapped, docs/controllers/c002.md): varpi2(0) = 0.5 N < 2",
          note="With the printed labels ||sat(eps_t(0)) - eps_t(0)|| = 172 N >> kappa2 = 2; with the swapped "
               "labels kappa1 fails instead (c002.gains.kappa1_varpi1): no reading satisfies condition ii."),
]


def _drop_alpha7(out, *a, **kw):
    out = sp.Matrix(out)
    out[6] = 0
    return out


MUTATIONS = [
    Mutation("c002: k4 -> -k4 in eq. 23", c, "attitude_control", scale_argument("k4", -1),
             ("c002.V1.bound", "c002.V1.exponential")),
    Mutation("c002: sign of eps_r (eq. 23)", c, "attitude_control", negate_output(),
             ("c002.V1.bound", "c002.V1.exponential")),
    Mutation("c002: alpha^_3 term dropped from eq. 23", c, "attitude_control", drop_terms(AHAT[2]),
             ("c002.V1.bound",)),
    Mutation("c002: k3 -> -k3 in eq. 23", c, "attitude_control", scale_argument("k3", -1),
             ("c002.V1.bound",)),
    Mutation("c002: k8 -> -k8 in eq. 24", c, "position_control", scale_argument("k8", -1),
             ("c002.V1.bound", "c002.V1.exponential")),
    Mutation("c002: k7 -> -k7 in eq. 24", c, "position_control", scale_argument("k7", -1),
             ("c002.V1.bound",)),
    Mutation("c002: alpha^_9 term dropped from eq. 24", c, "position_control", drop_terms(AHAT[8]),
             ("c002.V1.bound",)),
    Mutation("c002: sign of eq. 25", c, "adaptive_rates", negate_output(),
             ("c002.V1.adaptation_cancels", "c002.V1.bound")),
    Mutation("c002: gamma -> -gamma in eq. 25", c, "adaptive_rates", scale_argument("gamma", -1),
             ("c002.V1.adaptation_cancels", "c002.V1.bound")),
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
             ("c002.model.s2dot_identity", "c002.V2.derivative_identity", "c002.V2.invariant_set")),
]
