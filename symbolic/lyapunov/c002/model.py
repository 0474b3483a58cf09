"""002, spacecraft layer: the relative model has the form the proof uses (eqs. 19-22) and the law composes the
paper's equations (provenance)."""

from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.utilities.lambdify import implemented_function

from ...controllers import c002 as c
from ...physics.layout import XYZ, XYZW, Layout
from ...physics.rotations import dot, quat_conj, quat_mul, quat_to_dcm, skew
from ..core import (
    Statement,
    claim_factory,
    statement,
    symbols_vec,
)
from ..domains import (
    ball,
    box,
    custom,
    fixed,
    rotation_matrix,
    spd_rotated,
    unit_quaternion,
)
from .common import _S, _nrm, _sym_matrix, _tanh_form, _vec_lie

claim = claim_factory(__name__)

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
           box(S.m, 20, 200), spd_rotated(S.J, 5, 40), box(S.eps_r, -10, 10), box(S.u_r, -1, 1),
           box(S.eps_t, -100, 100), box(S.u_t, -100, 100), box(S.C_r, -1, 1), box(S.C_t, -1, 1),
           box(S.n_r, -1, 1), box(S.n_t, -1, 1), box(S.d_r, -0.01, 0.01), box(S.d_t, -0.01, 0.01)]
    if J_aux is not None:
        out += [spd_rotated(J_aux, 5, 40), box(m_aux, 20, 200)]
    return out


# --------------------------------------------------------------------------- eqs. 19-20 (spacecraft)

def _s1dot_corrected() -> Statement:
    S = _S()
    L = _Loop(S, adaptation=False)
    return statement(L.J_s1_dot(), "==", _eq19_rhs(S), _loop_domain(S),
                     assumptions=["eq. 17 uses the plant's J", "cosh^2 = 1/(1 - tanh^2)"])


def _s2dot() -> Statement:
    S = _S()
    L = _Loop(S, adaptation=False)
    return statement(L.m_s2_dot(), "==", _eq20_rhs(S, S.k5), _loop_domain(S),
                     assumptions=["eq. 18 uses the plant's m", "cosh^2 = 1/(1 - tanh^2)"])


def _nominal_inertia() -> Statement:
    """Eqs. 19-20 when eqs. 17-18 use a nominal J0, m0 (J and m are unknown: Assumption 2, Remark 2)."""
    S = _S()
    J0, m0 = _sym_matrix("J0"), sp.Symbol("m_0", positive=True)
    L = _Loop(S, J_aux=J0, m_aux=m0, adaptation=False)
    lhs = sp.Matrix.vstack(L.J_s1_dot(), L.m_s2_dot())
    rhs = sp.Matrix.vstack(_eq19_rhs(S), _eq20_rhs(S, S.k5))
    return statement(lhs, "==", rhs, _loop_domain(S, J0, m0), symbolic=False, residual_seconds=1,
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
                ball(S.d_r, self.D1), ball(S.d_t, self.D2), spd_rotated(S.J, 5, 40, self.b1), box(S.m, 20, 200),
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
        return statement(_nrm(self.C_r * S.w), "<=", factor * a1 * self.b1 * w + self.b1 * w**2,
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
        return statement(lhs, "<=", rhs, self.domain(near=not corrected, gravity=corrected),
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
        return statement(_nrm(self.Phi1), "<=", alpha1 * w**2 + alpha2 * w + alpha3, self.domain(near=False),
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
        return statement(lhs, "<=", rhs, self.domain(near=not corrected, gravity=corrected),
                         symbolic=False, residual_seconds=1,
                         assumptions=["Assumption 1 (a1..a3)", "m <= b3", "||d_t|| <= D2", "||sigma_t|| = sigmanorm",
                                      "||R v_t_dot - g_p|| <= a4" if corrected else "g_p = 0, ||v_t_dot|| <= a4"])


def _ct_skew() -> Statement:
    """C_t + C_t^T = 0 (hence r~^T C_t r~ = 0) for the code's C_t (eq. 7)."""
    S = _S()
    R = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))
    w_t = symbols_vec("omega_t")
    C_t = c.translation_rate_matrix(S.w, R, w_t)
    return statement(C_t + C_t.T, "==", sp.zeros(3, 3),
                     [box(S.w, -1, 1), rotation_matrix(R), box(w_t, -0.1, 0.1)])


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

    # ---- typed from the paper (rotations only from rpo.symbolic.physics.rotations)
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
        return statement(lhs, "==", rhs, dom, assumptions=["C002.law as generated"])
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
    return statement(lhs, "==", rhs, dom, residual_seconds=0,
                      assumptions=["C002.law as generated (J_nom diagonal)", "cosh^2 = 1/(1 - tanh^2)"])


CLAIMS = [
    claim("model.s1dot_identity", "attitude", "spacecraft", "2-4, 11, 15, 17, 19",
          "J s1_dot along the code's model, eq. 15 and eq. 17 equals eq. 19's right-hand side",
          None, _s1dot_corrected,
          note="Eq. 19 prints the left side 'J_dot s1', a typesetting slip (the same line's right side is J times "
               "s1_dot term by term); checked as J s1_dot."),
    claim("model.s2dot_identity", "position", "spacecraft", "7, 9, 12, 16, 18, 20",
          "m s2_dot along the code's model, eq. 16 and eq. 18 equals eq. 20's right-hand side", _s2dot),
    claim("model.known_inertia_needed", "attitude + position", "spacecraft", "17-20, Assumption 2",
          "eqs. 19-20 hold when eqs. 17-18 use a nominal J0, m0 instead of the unknown J, m", _nominal_inertia,
          about="paper",
          note="The saturation terms cancel only if eqs. 17-18 use the plant's J and m, which the paper calls "
               "unknown (Assumption 2, Remark 2); a mismatch leaves (I - J J0^-1)(sat - eps - kappa1 tanh chi1) in "
               "eq. 19.  rpo uses J_nom, m_nom: the truth in the paper plant, nominal values in the full plant "
               "(000's chaser and mass profile)."),
    claim("model.remark4_Cr", "attitude", "spacecraft", "4, Remark 4",
          "||C_r w~|| <= a1 b1 ||w~|| + b1 ||w~||^2 for the code's C_r",
          lambda: _Bounds().remark4_Cr(1), lambda: _Bounds().remark4_Cr(3),
          correction="3 a1 b1 ||w~|| + b1 ||w~||^2: C_r w~ has three terms linear in R w_t (J(Rw_t)^x w~, "
                     "(Rw_t)^x J w~, -(J R w_t)^x w~)",
          note="The part of C_r w~ bilinear in (R w_t, w~) was sampled up to 1.9 a1 b1 ||w~|| for a general "
               "inertia (1.4 for a physical one); Remark 4 bounds it by a1 b1 ||w~||, wrong when ||w~|| << a1."),
    claim("model.lumped_bound_attitude", "attitude", "spacecraft", "4, 21, Remark 4",
          "||-C_r w~ - n_r + d_r + k1/2 J(q^x + q0 I) w~ + kappa1 tanh chi1|| <= alpha1|w~|^2 + alpha2|w~| + alpha3",
          lambda: _Bounds().attitude(),
          note="Holds with the paper's alpha1..3 despite the Remark 4 slip: the quadratic and n_r terms are "
               "over-bounded (|(J w) x w| <= (lambda_max - lambda_min)/2 |w|^2) by more than the slip."),
    claim("model.remark5_nt", "position", "spacecraft", "9, Remark 5",
          "||m n_t|| <= b3 a1 a3 + b3 a4 + b3 ||sigma_t|| a1 ||w~|| + b3 ||sigma_t|| a2 for the code's n_t",
          lambda: _Bounds().remark5_nt(False), lambda: _Bounds().remark5_nt(True),
          correction="+ b3 a1^2 ||sigma_t||, with a4 >= ||R v_t_dot - g_p|| (differential gravity ~ 3 n^2 ||r||)",
          note="Remark 5 bounds the printed n_t (eq. 9 erratum); the physical one has the centripetal "
               "acceleration (R w_t)^x (R w_t)^x R sigma_t of the rendezvous point, present even in free space "
               "at rest relative to a tumbling target."),
    claim("model.lumped_bound_position", "position", "spacecraft", "7, 9, 22, Remark 5",
          "||-m C_t v~ - m n_t + d_t + k5 m r~_dot + kappa2 tanh chi2|| <= eq. 22's bound",
          lambda: _Bounds().position(False), lambda: _Bounds().position(True),
          correction="alpha9 + b3 a1^2 ||sigma_t|| (centripetal term), a4 >= ||R v_t_dot - g_p||",
          note="Paper statement near docking in free space (v_t = 0): the centripetal term, constant in w~, "
               "exceeds the printed alphas; the corrected alpha9 is checked on the wide domain with gravity, where a4 "
               "bounds the differential gravity R v_t_dot - g_p (not each gravity: b3 ||g_p|| ~ 830 N >> f_max)."),
    claim("model.Ct_skew", "position", "spacecraft", "7, 41",
          "r~^T C_t r~ = 0: C_t = (w~ + R w_t)^x of the code is skew-symmetric", _ct_skew),
    claim("model.law_composition", "attitude + position", "spacecraft", "1, 5-6, 13, 15-18, 23-25",
          "C002.law's s1, s2, eps_r, eps_t, sat outputs and xc_dot equal eqs. 1, 5-6, 13, 15-18, 23-25 of its "
          "own inputs",
          None, lambda: _law_identity("law"),
          note="Provenance: the other claims call the equation functions; this one checks that the law that generates "
               "the C code composes them as the paper's equations (typed here) with its own signals."),
    claim("model.law_kinematics", "attitude + position", "spacecraft", "1, 3, 5-6",
          "C002.law's diag q_err, rate_err, pos_err, vel_err equal eqs. 1, 5-6 (and omega~ under eq. 3) of its inputs",
          None, lambda: _law_identity("kinematics")),
]
