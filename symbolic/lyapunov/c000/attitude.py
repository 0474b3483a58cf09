"""000, attitude: the per-axis abstract argument (eqs. 48, 52-72) and the spacecraft layer (eqs. 15-29, 49-50,
53-56)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c000 as c
from ...physics.layout import XYZ
from ...physics.relative_attitude import rate_error, rate_error_dynamics
from ...physics.rotations import quat_rate
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
)
from ..domains import (
    ball,
    box,
    derived,
    fixed,
    unit_quaternion,
)
from .common import I_C_PAPER, I_T_PAPER, MU, _law, _paper_layer, _pos, _real, _s_then_edot, _sign_of

claim = claim_factory(__name__)

# =====================================================================================================
# Attitude, abstract per-axis form (eqs. 48, 52-72)
# =====================================================================================================

def attitude_V(S, a_tilde, b_tilde, b, gamma_a=1, gamma_b=1):
    """V = S^2/2 + b/2 [sum a_tilde_i^2 / gamma_a + b_tilde^2 / gamma_b] (eq. 57; a_tilde = a_hat - a/b,
    b_tilde = b_hat - 1/b; printed: i = 2..6, unit gains; implemented: i = 1..6, gains)."""
    return S**2 / 2 + b / 2 * (sum(t**2 for t in a_tilde) / gamma_a + b_tilde**2 / gamma_b)


class _AttitudeAxis:
    """One axis of eq. 48 in closed loop with eqs. 52-56, 66-67.

    ``printed``: the law of eq. 55 as printed (a_x1 f_x1 with a_x1 = 1 added to the torque, a_hat_1 not
    adapted), V of eq. 57 (i = 2..6), unit adaptation gains.  ``layer``: the boundary-layer function.
    """

    def __init__(self, printed: bool = False, layer=None):
        self.e, self.edot, self.acc_d, self.dist = _real("e edot acc_d dist")
        self.lam, self.D, self.eps, self.b = _pos("lambda_0 D epsilon b")
        self.d = sp.Symbol("d", positive=True)
        self.ga, self.gb = _pos("gamma_a gamma_b")
        self.a = list(_real("a_1:7"))
        self.ah = list(_real("ahat_1:7"))
        self.f = list(_real("f_1:7"))
        self.bh = sp.Symbol("bhat", real=True)
        self.Ss = sp.Symbol("S_aug", real=True)          # S_aug as a coordinate (rate s_dot)
        layer = layer or c.boundary_layer_surface
        if printed:
            self.a[0] = sp.Integer(1)                     # Table 1: a_x1 = 1, "known"
        ga, gb = (1, 1) if printed else (self.ga, self.gb)
        self.s = c.sliding_surface(self.edot, self.e, self.lam)                          # eq. 53
        self.S = layer(self.s, self.d)                                                   # eq. 52
        self.u1 = c.u1_term(self.acc_d, self.lam, self.edot)                             # eq. 56
        a_law = [self.a[0]] + self.ah[1:] if printed else self.ah                        # eq. 55
        self.u = c.attitude_control_axis(self.bh, self.u1, self.D, self.eps, self.s, a_law, self.f)
        eddot = c.attitude_model_axis(self.a, self.f, self.b, self.u, self.dist) - self.acc_d   # eq. 48
        self.sdot = lie_derivative(self.s, [self.e, self.edot], [self.edot, eddot])
        idx = range(1, 6) if printed else range(6)
        est = [self.ah[i] for i in idx]
        rates = [c.attitude_param_rate(self.f[i], self.S, ga) for i in idx]             # eq. 66
        bh_rate = c.gain_estimate_rate(self.u1, self.D, self.eps, self.s, self.S, gb)   # eq. 67
        a_tilde = [self.ah[i] - self.a[i] / self.b for i in idx]
        self.V = attitude_V(self.Ss, a_tilde, self.bh - 1 / self.b, self.b, ga, gb)
        Vdot = lie_derivative(self.V, [self.Ss, *est, self.bh], [self.sdot, *rates, bh_rate])
        self.Vdot = Vdot.xreplace({self.Ss: self.S})
        self.K = self.D + self.eps

    def domain(self, s_scale=0.3, params=True):
        """``params``: draw a and b in boxes (False: the caller derives them, e.g. from inertias)."""
        dom = [box(self.lam, 0.05, 1.0), box(self.d, 0.001, 0.1), box(self.e, -1, 1),
               _s_then_edot(s_scale, self.e, self.lam, self.d, self.edot),
               box([self.D, self.eps], 0.001, 0.05), box(self.acc_d, -0.01, 0.01), box(self.ah, -40, 40),
               box(self.f, -0.2, 0.2), box(self.bh, 0, 40), box([self.ga, self.gb], 0.1, 10),
               ball([self.dist], self.D)]
        if params:
            dom[6:6] = [box(self.b, 1 / 30, 1 / 5), box([a for a in self.a if isinstance(a, sp.Symbol)], -2, 2)]
        return dom


def _att_V_definite(printed: bool):
    def build():
        S = sp.Symbol("S_aug", real=True)
        b, ga, gb = _pos("b gamma_a gamma_b")
        n = 5 if printed else 6
        at = list(sp.symbols(f"atilde_{7 - n}:7", real=True))
        bt = sp.Symbol("btilde", real=True)
        V = attitude_V(S, at, bt, b, *((1, 1) if printed else (ga, gb)))
        return Statement(V, ">", 0, [box(S, -1, 1), box(at, -40, 40), box(bt, -40, 40), box(b, 1 / 30, 1 / 5),
                                     box([ga, gb], 0.1, 10)],
                         positive=[b, ga, gb], zero_at=[S, *at, bt], assumptions=["b = 1/I_cj > 0", "gamma > 0"])
    return build


def _att_Vdot_identity(printed: bool):
    """Eqs. 58-68: V-dot = -(D + eps) sign(s) S_aug + d S_aug (printed: eq. 55, V of eq. 57, the paper's
    piecewise layer)."""
    def build():
        A = _AttitudeAxis(printed=printed, layer=_paper_layer if printed else None)
        rhs = -A.K * sp.sign(A.s) * A.S + A.dist * A.S
        return Statement(A.Vdot, "==", rhs, A.domain(),
                         assumptions=["eq. 48 with e_ddot = X_ddot - acc_d", "eqs. 55, 66, 67 substituted"])
    return build


def _att_Vdot_bound():
    """Eqs. 68-72 for the implementation: V-dot <= -eps |S_aug| under |d| <= D (eq. 51)."""
    A = _AttitudeAxis()
    return Statement(A.Vdot, "<=", -A.eps * sp.Abs(A.S), A.domain(), symbolic=False,
                     assumptions=["|d| <= D (eq. 51)"])


def _att_Vdot_negative_definite():
    """After eq. 72: "its time-derivative is negative definite": there is a kappa > 0 with
    -V-dot >= kappa (S^2 + |a_tilde|^2 + b_tilde^2); tested with kappa fixed at 1e-9 (any smaller kappa
    fails at the same points: V-dot = 0 with nonzero parameter errors)."""
    A = _AttitudeAxis()
    kappa = sp.Symbol("kappa", positive=True)
    at = [A.ah[i] - A.a[i] / A.b for i in range(6)]
    size = A.S**2 + sum(t**2 for t in at) + (A.bh - 1 / A.b) ** 2
    return Statement(-A.Vdot, ">=", kappa * size, [fixed(kappa, [1e-9]), *A.domain()], symbolic=False,
                     residual_seconds=1.0, assumptions=["|d| <= D (eq. 51)", "kappa = 1e-9"])


def _att_time_varying():
    """Eq. 72 with the chaser's time-varying inertia (Fig. 10): V-dot gains the terms of d/dt(a_i/b),
    d/dt(1/b) (in V) and -I_cx_dot omega_cx / I_cx (in omega_e_dot, from d/dt(I omega)); the printed claim is
    still V-dot <= -eps |S_aug|.  Axis x with Table 1's a, b of I_c, I_t (implemented law and V)."""
    A = _AttitudeAxis()
    Ic, It = _inertia_symbols()
    Icdot = list(_real("Idot_c1:4"))
    wcx = sp.Symbol("omega_c1", real=True)
    z3 = sp.zeros(3, 1)
    a_t, _, b_t = c.table1_attitude_axis(0, Ic, It, z3, z3, z3, sp.eye(3), z3)
    p = [a_t[i] / b_t for i in range(6)]                       # the estimated a_i / b = p_i(I_c)
    pdot = [sum(sp.diff(pi, I) * Id for I, Id in zip(Ic, Icdot, strict=True)) for pi in p]
    binv_dot = Icdot[0]                                         # d/dt(1/b) = I_cx_dot
    # V of the implementation in terms of p and 1/b
    at = [A.ah[i] - A.a[i] / A.b for i in range(6)]
    V = attitude_V(A.S, at, A.bh - 1 / A.b, A.b, A.ga, A.gb)
    extra_V = (sum(sp.diff(V, A.a[i]) * (pdot[i] * A.b - A.a[i] * A.b * binv_dot) for i in range(6))
               + sp.diff(V, A.b) * (-A.b**2 * binv_dot))    # a_i = p_i b, b = 1/I_cx: a_i_dot = p_i_dot b - a_i b Idot
    extra_plant = A.S * (-A.b * Icdot[0] * wcx)                 # S_aug * (-I_cx_dot omega_cx / I_cx)
    lhs = A.Vdot + extra_V + extra_plant
    dom = [box(Ic, 11, 27), box(It, 2000, 4000), box(Icdot, -0.3, 0.3), box(wcx, -0.13, 0.13),
           derived([A.b, *A.a], [b_t, *a_t], [*Ic, *It]), *A.domain(params=False)]
    return Statement(lhs, "<=", -A.eps * sp.Abs(A.S), dom, symbolic=False, residual_seconds=1.0,
                     assumptions=["|d| <= D (eq. 51)", "I_c in [11, 27] kg m^2, |I_c_dot| <= 0.3 kg m^2/s "
                                  "(Fig. 10's ramps: 14 kg m^2 in ~40 s); the steps (11 -> 22 at t = 20 s) are jumps "
                                  "of a/b, i.e. of V, not covered by any derivative bound"])


# =====================================================================================================
# Attitude, spacecraft layer (eqs. 15-29, 49-50, 53-56)
# =====================================================================================================

def _att_symbols():
    q = sp.Matrix(_real("q_1:5"))
    w = sp.Matrix(_real("omega_e1:4"))
    wdot = sp.Matrix(_real("omegadot_e1:4"))
    sig = sp.Symbol("sigma", real=True)
    lam = sp.Symbol("lambda_0", positive=True)
    return q, w, wdot, sig, lam


def _att_kin_domain(q, w, wdot, sig, lam):
    return [unit_quaternion(q), box(w, -0.15, 0.15), box(wdot, -0.05, 0.05),
            derived([sig], [_sign_of(q[3])], [q[3]]), box(lam, 0.05, 1.0)]


def _eq24(q, w):
    """Eq. 24 hand-typed: q_ev_dot = (q_e4 omega_e + q_ev x omega_e)/2, q_e4_dot = -q_ev . omega_e / 2."""
    qv = sp.Matrix(q[:3])
    return sp.Matrix([*((q[3] * w + qv.cross(w)) / 2), -qv.dot(w) / 2])


def _e_ddot_printed():
    """Eqs. 53-54, 59-60 as printed: e = q_ev (q_d = identity) and e_ddot = omega_e_dot."""
    q, w, wdot, sig, lam = _att_symbols()
    e_dot = _eq24(q, w)[:3, 0]
    e_ddot = sp.Matrix([lie_derivative(e_dot[j], [q, w], [_eq24(q, w), wdot]) for j in range(3)])
    return Statement(e_ddot, "==", wdot, _att_kin_domain(q, w, wdot, sig, lam),
                     constraints=[sum(x**2 for x in q) - 1], assumptions=["|q_e| = 1", "eq. 24 kinematics"])


def _e_ddot_implemented():
    """The law's surface (diag s_att of C000.law: omega_e + lambda_0 sgn(q_e4) q_ev) along eq. 24 (hand-typed):
    s_dot = omega_e_dot + lambda_0 e_dot with e_dot = sgn(q_e4) d/dt q_ev, the abstract s dynamics."""
    ctrl, M, tau, F, rates, dg, sig, mu = _law()
    q, w, lam = M["q_e"], M["w_e"], ctrl.k["lam_att"]
    wdot = sp.Matrix(_real("omegadot_e1:4"))
    s = dg["s_att"]
    sdot = sp.Matrix([lie_derivative(s[j], [q, w], [_eq24(q, w), wdot]) for j in range(3)])
    rhs = wdot + lam * sig * _eq24(q, w)[:3, 0]
    dom = _att_kin_domain(q, w, wdot, sig, lam)
    return Statement(sdot, "==", rhs, dom, constraints=[sum(x**2 for x in q) - 1, sig**2 - 1],
                     assumptions=["|q_e| = 1", "sigma = sgn(q_e4) (constant between crossings of q_e4 = 0)"])


def _sliding_decay():
    """On s = 0 (omega_e = -lambda_0 e) the quaternion error decays: d/dt |e|^2 = -lambda_0 sgn(q_e4) q_e4 |e|^2
    = -lambda_0 |q_e4| |e|^2."""
    q, w, wdot, sig, lam = _att_symbols()
    e = c.tracking_error(sig * c.quat_vec(q), sp.zeros(3, 1))
    w0 = sp.Symbol("w_0", real=True)
    # omega_e on the surface: s_j(omega_e) = 0 solved with the code's sliding_surface (linear in omega_e)
    w_s = sp.Matrix([sp.solve(c.sliding_surface(w0, e[j], lam), w0)[0] for j in range(3)])
    e2 = sum(x**2 for x in e)
    rate = lie_derivative(e2, list(q), list(quat_rate(q, w_s)))
    return Statement(rate, "==", -lam * sig * q[3] * e2, _att_kin_domain(q, w, wdot, sig, lam),
                     constraints=[sum(x**2 for x in q) - 1, sig**2 - 1],
                     assumptions=["|q_e| = 1", "sigma = sgn(q_e4), so sigma q_e4 = |q_e4|", "s = 0"])


def _inertia_symbols():
    Ic = list(_pos("I_c1:4"))
    It = list(_pos("I_t1:4"))
    return Ic, It


def _eq49_printed_row(j, Ic, It, wc, we, h, T, Mc, Mt, C, dl):
    """omega_e_dot_j solved from eq. 49-b (j = 1) or 49-c (j = 2) exactly as printed (hand-typed), with c_jm the
    entries of C_t^c (the reading under which eq. 49 is the rigid-body equation; the sentence "entries of
    (C_t^c)^-1" follows eq. 50, for delta)."""
    x, y, z = 0, 1, 2
    d1, d2, d3 = dl
    tgt = lambda r: (C[r, 0] / It[x] * (It[z] - It[y]) * d2 * d3 + C[r, 1] / It[y] * (It[x] - It[z]) * d1 * d3  # noqa: E731
                     + C[r, 2] / It[z] * (It[y] - It[x]) * d1 * d2)
    Mtt = lambda r: C[r, 0] * Mt[x] + C[r, 1] * Mt[y] + C[r, 2] * Mt[z]  # noqa: E731
    if j == 1:      # 49-b (and 49-a, its printed duplicate): note I_ty^-1 T_cy and (...) I_ty^-1
        lhs_terms = ((Ic[x] - Ic[z]) * wc[x] * wc[z] / Ic[y] + (h[x] * wc[z] - h[z] * wc[x]) / Ic[y]
                     + (wc[z] * we[x] - wc[x] * we[z]) - tgt(1))
        rhs = T[y] / It[y] + Mc[y] / Ic[y] - Mtt(1) / It[y]
    else:           # 49-c
        lhs_terms = ((Ic[y] - Ic[x]) * wc[x] * wc[y] / Ic[z] + (h[y] * wc[x] - h[x] * wc[y]) / Ic[z]
                     + (wc[x] * we[y] - wc[y] * we[x]) - tgt(2))
        rhs = T[z] / Ic[z] + Mc[z] / Ic[z] - Mtt(2) / It[z]
    return rhs - lhs_terms


def _table1_vs_rigid(printed: bool):
    """Eq. 48 with Table 1 (eq. 49) == omega_e_dot of the two rigid bodies (eqs. 26-29), principal axes.
    Printed: eq. 49 as printed (49-a is a copy of 49-b, so the x row is the y equation)."""
    def build():
        q, w, _, _, _ = _att_symbols()
        wc, h, T, Mc, Mt = (sp.Matrix(_real(f"{n}1:4")) for n in ("omega_c", "h_rw", "T_c", "M_c", "M_t"))
        Ic, It = _inertia_symbols()
        ref = rate_error_dynamics(q, w, wc, h, sp.diag(*Ic), sp.diag(*It), T, Mc, Mt)
        C_tc = c.dcm_target_to_chaser(q)
        delta = c.target_rate_in_target_axes(C_tc, wc, w)
        rows = []
        for j in range(3):
            if printed:
                rows.append(_eq49_printed_row(max(j, 1), Ic, It, wc, w, h, T, Mc, Mt, C_tc, delta))
                continue
            a, f, b = c.table1_attitude_axis(j, Ic, It, wc, w, h, C_tc, delta)
            dj = c.attitude_disturbance_axis(j, Ic, It, C_tc, Mc, Mt)
            rows.append(c.attitude_model_axis(a, f, b, T[j], dj))
        dom = [unit_quaternion(q), box(w, -0.15, 0.15), box(wc, -0.15, 0.15), box(h, -2, 2), box(T, -0.2, 0.2),
               box(Mc, -0.3, 0.3), box(Mt, -1, 1), box(Ic, 5, 30), box(It, 2000, 4000)]
        return Statement(sp.Matrix(rows), "==", ref, dom, constraints=[sum(x**2 for x in q) - 1],
                         residual_seconds=1.0, symbolic=not printed,
                         assumptions=["principal-axis inertias (the paper's model)"])
    return build


def _d_total(Mc, Mt):
    """(model, ref, symbols): eq. 49 with the diagonals of the paper's inertias and no disturbance (what the law
    models) and the rigid bodies with the paper's full inertias and torques M_c, M_t; ref - model is the d of
    eq. 48 that eq. 51 bounds."""
    q, w, _, _, _ = _att_symbols()
    wc, h, T = (sp.Matrix(_real(f"{n}1:4")) for n in ("omega_c", "h_rw", "T_c"))
    z = sp.zeros(3, 1)
    model = c.attitude_model(q, w, wc, h, tuple(np.diag(I_C_PAPER)), tuple(np.diag(I_T_PAPER)), T, z, z)
    ref = rate_error_dynamics(q, w, wc, h, sp.Matrix(I_C_PAPER), sp.Matrix(I_T_PAPER), T, Mc, Mt)
    wt = sp.Matrix(_real("omega_t1:4"))
    dom = [unit_quaternion(q), ball(wc, 0.13), ball(wt, 0.13),
           derived(list(w), list(rate_error(q, wc, wt)), [*q, *wc, *wt]), ball(h, 2.0), box(T, -0.17, 0.17)]
    return model, ref, dom


_KIN_ASSUMPTIONS = ["the paper's I_c, I_t (with products of inertia)",
                    "|omega_c|, |omega_t| <= 0.13 rad/s (scenarios II/III: 0.122-0.124)",
                    "|h_rw| <= 2 N m s (the wheels' capacity)", "|T_c,j| <= 0.17 N m"]


def _principal_axes_paper():
    """Eq. 49 (principal axes, diag of the paper's inertias) == the rigid bodies with the paper's full inertias."""
    z = sp.zeros(3, 1)
    model, ref, dom = _d_total(z, z)
    return Statement(model, "==", ref, dom, symbolic=False, residual_seconds=1.0,
                     assumptions=[*_KIN_ASSUMPTIONS, "no external torque"])


#: the implementation's budget for the external torques inside D_att (joint with the products of inertia)
M_C_BUDGET, M_T_BUDGET = 0.04, 1.0


def _principal_axes_bound():
    """Joint budget: |products-of-inertia residual + external torques| <= D_att = 0.0075 rad/s^2 (eq. 51) for
    |M_c| <= 0.04 N m, |M_t| <= 1 N m."""
    Mc, Mt = sp.Matrix(_real("M_c1:4")), sp.Matrix(_real("M_t1:4"))
    model, ref, dom = _d_total(Mc, Mt)
    D = c.C000().k._symbols["D_att"]
    lhs = sp.Matrix([sp.Abs(r) for r in ref - model])
    return Statement(lhs, "<=", sp.Matrix(D), dom + [ball(Mc, M_C_BUDGET), ball(Mt, M_T_BUDGET),
                                                     fixed(list(D), [0.0075] * 3)], symbolic=False,
                     residual_seconds=1.0,
                     assumptions=[*_KIN_ASSUMPTIONS, f"|M_c| <= {M_C_BUDGET} N m, |M_t| <= {M_T_BUDGET} N m",
                                  "D_att = 0.0075 rad/s^2 (the default)"])


def _gg_eq4(I, phi, theta, r0, mu):
    """Eq. 4 (gravity-gradient torque, principal inertias I) hand-typed [N m]."""
    k = 3 * mu / (2 * r0**3)
    return sp.Matrix([k * (I[2] - I[1]) * sp.sin(2 * phi) * sp.cos(theta) ** 2,
                      k * (I[2] - I[0]) * sp.sin(2 * theta) * sp.cos(phi),
                      k * (I[0] - I[1]) * sp.sin(2 * theta) * sp.cos(phi) ** 2])


def _disturbance_paper():
    """Eq. 51 |d_j| <= D_j against the paper's own disturbance model: eq. 4 (GG) + eq. 5 (M_r = 0.3 randn, here
    at 3 sigma: |M_r,j| <= 0.9 N m) on both bodies, plus the products-of-inertia residual, with D_att = 0.0075."""
    Mrc, Mrt = sp.Matrix(_real("M_rc1:4")), sp.Matrix(_real("M_rt1:4"))
    phc, thc, pht, tht = _real("phi_c theta_c phi_t theta_t")
    r0 = sp.Symbol("r_0", positive=True)
    Mc = _gg_eq4(np.diag(I_C_PAPER), phc, thc, r0, MU) + Mrc
    Mt = _gg_eq4(np.diag(I_T_PAPER), pht, tht, r0, MU) + Mrt
    model, ref, dom = _d_total(Mc, Mt)
    D = c.C000().k._symbols["D_att"]
    lhs = sp.Matrix([sp.Abs(r) for r in ref - model])
    dom += [box(Mrc, -0.9, 0.9), box(Mrt, -0.9, 0.9), box([phc, thc, pht, tht], -np.pi, np.pi),
            box(r0, 6.778e6, 4.2164e7), fixed(list(D), [0.0075] * 3)]
    return Statement(lhs, "<=", sp.Matrix(D), dom, symbolic=False, residual_seconds=1.0,
                     assumptions=[*_KIN_ASSUMPTIONS, "eq. 4 GG on both bodies, r_0 from LEO to GEO",
                                  "eq. 5 random torque at 3 sigma (0.9 N m per axis); eq. 5 itself is unbounded",
                                  "D_att = 0.0075 rad/s^2"])


def _att_spacecraft_common(ctrl, M, sig):
    k, xc = ctrl.k, ctrl.xc
    Ic, It = _inertia_symbols()
    Mc, Mt = sp.Matrix(_real("M_c1:4")), sp.Matrix(_real("M_t1:4"))
    dom = [unit_quaternion(M["q_e"]), derived([sig], [_sign_of(M["q_e"][3])], [M["q_e"][3]]),
           box(M["w_e"], -0.15, 0.15), box(M["w_c"], -0.15, 0.15), box(M["h_rw"], -2, 2),
           box(Mc, -0.3, 0.3), box(Mt, -1, 1), box(Ic, 5, 30), box(It, 2000, 4000),
           box(k["lam_att"], 0.05, 1.0), box(list(k["D_att"]) + list(k["eps_att"]), 0.001, 0.05),
           box(k["d_att"], 0.0, 0.01), box(k["wdot_d"], -0.01, 0.01), box([k["gamma_a"], k["gamma_b"]], 0.1, 10)]
    for ax in XYZ:
        dom += [box(xc[f"a_hat_{ax}"], -40, 40), box(xc[f"b_hat_{ax}"], 0, 40)]
    return Ic, It, Mc, Mt, dom


def _att_spacecraft_parts():
    """(statement pieces) V_j-dot (eq. 57 with gains, i = 1..6) of C000.law along eq. 24 and the rigid-body
    omega_e_dot (principal axes): lhs, the identity's rhs, S, eps, D, disturbance d_j, domain, symbols."""
    ctrl, M, tau, F, rates, dg, sig, mu = _law()
    k, xc = ctrl.k, ctrl.xc
    q, w, wc, h = M["q_e"], M["w_e"], M["w_c"], M["h_rw"]
    Ic, It, Mc, Mt, dom = _att_spacecraft_common(ctrl, M, sig)
    C_tc = c.dcm_target_to_chaser(q)
    delta = c.target_rate_in_target_axes(C_tc, wc, w)
    s_list, S_list = list(dg["s_att"]), list(dg["S_aug_att"])
    wdot = rate_error_dynamics(q, w, wc, h, sp.diag(*Ic), sp.diag(*It), tau, Mc, Mt)
    qdot = quat_rate(q, w)
    lhs, rhs, dist = [], [], []
    for j, ax in enumerate(XYZ):
        a, _, b = c.table1_attitude_axis(j, Ic, It, wc, w, h, C_tc, delta)
        Ss = sp.Symbol(f"S_aug_{ax}", real=True)
        ah, bh = list(xc[f"a_hat_{ax}"]), xc[f"b_hat_{ax}"]
        V = attitude_V(Ss, [ah[i] - a[i] / b for i in range(6)], bh - 1 / b, b, k["gamma_a"], k["gamma_b"])
        sdot = lie_derivative(s_list[j], [q, w], [qdot, wdot])
        Vdot = lie_derivative(V, [Ss, *ah, bh], [sdot, *rates[f"a_hat_{ax}"], rates[f"b_hat_{ax}"][0]])
        lhs.append(Vdot.xreplace({Ss: S_list[j]}))
        dj = c.attitude_disturbance_axis(j, Ic, It, C_tc, Mc, Mt)
        dist.append(dj)
        K = k["D_att"][j] + k["eps_att"][j]
        rhs.append((-K * sp.sign(s_list[j]) + dj + k["wdot_d"][j]) * S_list[j])
    return dict(ctrl=ctrl, M=M, lhs=sp.Matrix(lhs), rhs=sp.Matrix(rhs), S=sp.Matrix(S_list), dist=dist,
                dom=dom, Ic=Ic, It=It, Mc=Mc, Mt=Mt, C_tc=C_tc, q=q)


def _att_spacecraft_Vdot():
    """V_j-dot of the law along the spacecraft equations = -(D_j + eps_j) sign(s_j) S_j + d_j S_j
    + omega_e_dot_d,j S_j (fixed goal: the desired acceleration is a bias, choice C2)."""
    P = _att_spacecraft_parts()
    return Statement(P["lhs"], "==", P["rhs"], P["dom"], constraints=[sum(x**2 for x in P["q"]) - 1],
                     residual_seconds=1.0,
                     assumptions=["principal-axis inertias", "eq. 24 kinematics, eqs. 26-29 dynamics",
                                  "sigma = sgn(q_e4)"])


def _att_spacecraft_Vdot_bound():
    """V_j-dot of the law along the spacecraft equations <= -eps_j |S_j| whenever |d_j + omega_e_dot_d,j| <= D_j
    (the implementation's condition: the desired acceleration spends the disturbance budget)."""
    P = _att_spacecraft_parts()
    k = P["ctrl"].k
    Ic, It, C_tc, Mc, Mt = P["Ic"], P["It"], P["C_tc"], P["Mc"], P["Mt"]
    # M_c drawn so that d_j = D_j z_j - wdot_d,j (|z_j| <= 1): M_c,j = I_cj (d_j + (C_t^c I_t^-1 M_t)_j)
    tgt = [sum(C_tc[j, m] * Mt[m] / It[m] for m in range(3)) for j in range(3)]
    zz = sp.Matrix(_real("z_d1:4"))
    mc_expr = [Ic[j] * (k["D_att"][j] * zz[j] - k["wdot_d"][j] + tgt[j]) for j in range(3)]
    deps = sorted(set().union(*[e.free_symbols for e in mc_expr]), key=str)
    dom = [v for v in P["dom"] if not set(v.symbols) & set(Mc)]
    dom += [box(zz, -1, 1), derived(list(Mc), mc_expr, deps)]
    eps = k["eps_att"]
    rhs = sp.Matrix([-eps[j] * sp.Abs(P["S"][j]) for j in range(3)])
    return Statement(P["lhs"], "<=", rhs, dom, symbolic=False, residual_seconds=1.0,
                     assumptions=["|d_j + omega_e_dot_d,j| <= D_j", "principal-axis inertias"])


CLAIMS = [
        claim("attitude.V_definite", "attitude", "abstract", "57",
              "V_x positive definite in (S_aug, a_tilde, b_tilde)", _att_V_definite(True), _att_V_definite(False),
              correction="V = S^2/2 + b/2 [sum_{i=1..6} a_tilde_i^2/gamma_a + b_tilde^2/gamma_b]",
              note="b = 1/I_cx > 0. Definite in S_aug, not in (e, e_dot): V vanishes on the whole layer |s| <= d."),
        claim("attitude.Vdot_identity", "attitude", "abstract", "55, 58-68",
              "V_x-dot = -(D + eps) sign(s) S_aug + d S_aug under eqs. 55, 66, 67",
              _att_Vdot_identity(True), _att_Vdot_identity(False),
              correction="eq. 55: a_hat_x1 f_x1 (a_hat_x1 -> a_x1/b_x = I_cx adapted by eq. 66 with i = 1) instead "
                         "of a_x1 f_x1; V with i = 1..6 and gains gamma_a, gamma_b",
              note="Printed eq. 55 adds a_x1 f_x1 (rad/s^2) to the torque; the proof (eqs. 62-64) needs "
                   "a_x1 f_x1 / b_x: residual (b_x - 1) f_x1 S_aug (paper's piecewise layer)."),
        claim("attitude.Vdot_bound", "attitude", "abstract", "51, 68-72",
              "V_x-dot <= -eps |S_aug| under |d| <= D (implemented law, V, layer)", None, _att_Vdot_bound,
              note="Implementation only. The printed law fails one step earlier (Vdot_identity); the printed "
                   "layer read alone is the erratum boundary_layer.zero_inside."),
        claim("attitude.Vdot_negative_definite", "attitude", "abstract", "72 (text after it)",
              "V_x-dot is negative definite in (S_aug, a_tilde, b_tilde) (there is kappa > 0; kappa = 1e-9)",
              _att_Vdot_negative_definite, about="paper",
              note="V-dot = (-(D + eps) sign(s) + d) S_aug does not depend on the parameter errors (and is 0 inside "
                   "the layer): negative semidefinite only. S_aug -> 0 follows (Barbalat); the estimates need not "
                   "converge, contrary to the conclusion's 'adaptive parameters converge'."),
        claim("attitude.time_varying_inertia", "attitude", "abstract", "48 ('slowly time-varying'), 57-72, "
              "Fig. 10", "V_x-dot <= -eps |S_aug| with the time-varying I_c of Fig. 10", _att_time_varying,
              about="paper",
              note="The proof takes a/b and 1/b constant and omits -I_c_dot omega_c / I_c: with I_c_dot != 0 V-dot "
                   "has sign-indefinite parameter-drift terms (nonzero at S_aug = 0); the steps of Fig. 10 "
                   "(I_cx 11 -> 22) are jumps of V. The implementation inherits this (no projection/leakage)."),
        # ---- attitude, spacecraft
        claim("attitude.e_ddot", "attitude", "spacecraft", "24, 53-54, 59-60",
              "The surface's derivative is omega_e_dot + lambda_0 e_dot (the proof's e_ddot = omega_e_dot)",
              _e_ddot_printed, _e_ddot_implemented,
              correction="s = omega_e + lambda_0 sgn(q_e4) q_ev and u_1 = -omega_e_dot_d + lambda_0 e_dot with "
                         "e_dot = sgn(q_e4) d/dt q_ev from eq. 24",
              note="For e = q_ev (eq. 54), d^2/dt^2 q_ev = (q_e4 w_dot + q_ev x w_dot)/2 - |w|^2 q_ev/4 != w_dot. "
                   "Corrected: the law's diag s_att along eq. 24 typed by hand."),
        claim("attitude.sliding_decay", "attitude", "spacecraft", "53 (s = 0)",
              "On s = 0 the quaternion error decays: d/dt |e|^2 <= -lambda_0 |q_e4| |e|^2", None, _sliding_decay,
              note="Needs e = sgn(q_e4) q_ev (choice C1); with e = q_ev the error grows while q_e4 < 0 (unwinding)."),
        claim("attitude.table1", "attitude", "spacecraft", "26-29, 48-50, Table 1",
              "Eq. 49 (as printed) / Table 1 is omega_e_dot of the two rigid bodies (principal axes)",
              _table1_vs_rigid(True), _table1_vs_rigid(False),
              correction="x row from eq. 61 (49-a is a copy of 49-b); I_cy^-1 T_cy for 49-b's I_ty^-1 T_cy; target "
                         "torque sum_m c_jm M_tm / I_tm for (sum_m c_jm M_tm) I_tj^-1",
              note="Eq. 49 typed as printed with c_jm the entries of C_t^c (the sentence 'entries of (C_t^c)^-1' "
                   "follows eq. 50, for delta). Fails on the printed slips: duplicated 49-a, I_ty^-1 T_cy in 49-b, "
                   "I_tj^-1 on the target torque."),
        claim("attitude.principal_axes", "attitude", "spacecraft", "49, 51 vs 6, 10, 26-29",
              "Eq. 49 (principal axes) + eq. 51: the products of inertia and external torques fit in D_att",
              _principal_axes_paper, _principal_axes_bound,
              correction=f"joint budget: products-of-inertia residual (<= ~0.0023 rad/s^2) + external torques "
                         f"|M_c| <= {M_C_BUDGET} N m, |M_t| <= {M_T_BUDGET} N m within D_att = 0.0075 rad/s^2",
              note="Eq. 49 drops the products of inertia of I_c and I_t (-0.09..-0.4, -135..-154 kg m^2); the "
                   "implementation counts them in d, sharing D_att with the external torques."),
        claim("attitude.disturbance_paper", "attitude", "spacecraft", "4, 5, 49, 51",
              "|d_j| <= D_j with the paper's disturbances (eq. 4 GG, eq. 5 at 3 sigma) and inertia residual",
              _disturbance_paper, about="paper",
              note="Eq. 5's M_r = 0.3 randn is unbounded (contradicts eq. 51's bounded d); at 1 sigma |M_r/I_cx| "
                   "~ 0.027 rad/s^2 >> D_att = 0.0075 (at 3 sigma ~0.08). Not satisfiable by any D within the "
                   "wheels' 0.1 N m."),
        claim("attitude.spacecraft_Vdot", "attitude", "spacecraft", "24, 26-29, 53-68",
              "V_j-dot of the full law along the spacecraft equations = -(D+eps) sign(s) S + d S + wdot_d S",
              None, _att_spacecraft_Vdot,
              note="Implementation only (with the printed e = q_ev the step fails already at attitude.e_ddot). "
                   "The wdot_d S term: the goal is fixed (choice C2), so wdot_d is a bias the bound must absorb."),
        claim("attitude.spacecraft_Vdot_bound", "attitude", "spacecraft", "51, 56, 68-72",
              "V_j-dot of the full law <= -eps_j |S_j| when |d_j + wdot_d,j| <= D_j", None,
              _att_spacecraft_Vdot_bound,
              note="The desired angular acceleration enters V-dot like a disturbance (fixed goal): it spends D. "
                   "Scenarios set wdot_d = 0."),
]
