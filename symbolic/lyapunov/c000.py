"""Claims of 000 (adaptive sliding mode with adjustable acceleration): attitude (eqs. 48-80) and the
three translational axes (eqs. 81-129), each on two layers.

* **abstract**: the paper's per-axis argument for the form of eq. 48 (attitude) and eqs. 81, 105, 30-z
  (translation): X_ddot = -sum a_i f_i + b u + d.  The closed loop is that form driven by the per-axis
  law and adaptation functions of :mod:`rpo.symbolic.controllers.c000` (looked up on the module at check
  time, so mutations are seen); the regressors f, phi and the parameters a, theta are free symbols (the
  identity must hold whatever they are).  V-dot is V differentiated along it with S_aug as a coordinate
  whose rate is s_dot: the paper's step "outside the boundary layer S_aug_dot = s_dot, inside S_aug = 0"
  (eq. 57), which makes S_aug S_aug_dot = S_aug s_dot everywhere; that step is its own claim
  (``c000.boundary_layer.derivative``).
* **spacecraft**: whether the spacecraft equations have that form: the quaternion error (eqs. 53-60),
  Table 1 against the two rigid bodies (eqs. 26-29, 49-50), the products of inertia, eq. 81's scalar
  substitution r_t = r_c - |r_e| against eq. 30, and V-dot of the full law :meth:`C000.law` (the function
  that generates the C code) along the rigid-body / LVLH equations of the plant.

V is not in the controller module (000 only adapts); the candidates are written here, as printed (eqs. 57,
89, 109, 123) and as the implementation's proof uses them (positive definite, with the adaptation gains).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..controllers import c000 as c
from ..layout import XYZ, XYZW, Layout
from ..relative_attitude import rate_error, rate_error_dynamics
from ..relative_translation import relative_acceleration
from ..rotations import quat_rate, quat_vec
from .core import (
    Claim,
    Mutation,
    Statement,
    ball,
    box,
    custom,
    derived,
    fixed,
    lie_derivative,
    negate_output,
    replace_output,
    scale_argument,
    unit_quaternion,
)

MU = 3.986004418e14
#: the paper's inertia matrices ("Simulation", all three scenarios) [kg m^2]
I_C_PAPER = np.array([[11.0, -0.09, -0.4], [-0.09, 14.0, -0.08], [-0.4, -0.08, 13.0]])
I_T_PAPER = np.array([[3336.0, -135.0, -154.0], [-135.0, 3184.0, -135.0], [-154.0, -135.0, 2423.0]])
AXES = ("x", "y", "z")
NPHI = (5, 3, 1)


def _printed_layer(s, d):
    """S_aug = s - d sign(s) as printed (eqs. 52, 84, 106, 119)."""
    return s - d * sp.sign(s)


def _real(names):
    return sp.symbols(names, real=True)


def _pos(names):
    return sp.symbols(names, positive=True)


def _s_then_edot(s_scale, e, lam, d, edot):
    """Draw e_dot so that s = e_dot + lambda e is uniform in +-(3 d + s_scale): inside and outside the layer."""
    def draw(z, env):
        s = z[:, 0] * (3.0 * env[d] + s_scale)
        return (s - env[lam] * env[e])[:, None]
    return custom([edot], 1, draw, f"e_dot = s - lambda e, |s| <= 3 d + {s_scale:g}")


def _sign_of(x):
    """sgn with sgn(0) = +1 (the code's Piecewise((-1, x < 0), (1, True)))."""
    return sp.Piecewise((-1, x < 0), (1, True))


# =====================================================================================================
# Boundary layer (eqs. 52, 84, 106, 119 and the text after eq. 57)
# =====================================================================================================

def _layer_symbols():
    s = sp.Symbol("s", real=True)
    d = sp.Symbol("d", positive=True)
    return s, d


def _bl_sign(printed: bool):
    """sign(s) S_aug = |S_aug|: the step from eq. 68 to eqs. 69-72 (and 102-104, 117, 129)."""
    def build():
        s, d = _layer_symbols()
        S = (_printed_layer if printed else c.boundary_layer_surface)(s, d)
        return Statement(sp.sign(s) * S, "==", sp.Abs(S), [box(d, 0.001, 0.5), box(s, -1.5, 1.5)],
                         symbolic=False, assumptions=["d > 0"])
    return build


def _bl_zero_inside(printed: bool):
    """S_aug = 0 for |s| <= d (the text after eq. 57)."""
    def build():
        s, d = _layer_symbols()
        S = (_printed_layer if printed else c.boundary_layer_surface)(s, d)
        inside = custom([s], 1, lambda z, env: z * env[d][:, None], "|s| <= d")
        return Statement(S, "==", 0, [box(d, 0.001, 0.5), inside], symbolic=False,
                         assumptions=["|s| <= d (inside the layer)"])
    return build


def _bl_derivative():
    """S_aug dS_aug/ds = S_aug: S_aug S_aug_dot = S_aug s_dot everywhere (eqs. 57-59)."""
    s, d = _layer_symbols()
    S = c.boundary_layer_surface(s, d)
    return Statement(S * sp.diff(S, s), "==", S, [box(d, 0.001, 0.5), box(s, -1.5, 1.5)], symbolic=False)


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

    def domain(self, s_scale=0.3):
        return [box(self.lam, 0.05, 1.0), box(self.d, 0.001, 0.1), box(self.e, -1, 1),
                _s_then_edot(s_scale, self.e, self.lam, self.d, self.edot),
                box([self.D, self.eps], 0.001, 0.05), box(self.acc_d, -0.01, 0.01), box(self.b, 1 / 30, 1 / 5),
                box([a for a in self.a if isinstance(a, sp.Symbol)], -2, 2), box(self.ah, -40, 40),
                box(self.f, -0.2, 0.2), box(self.bh, 0, 40), box([self.ga, self.gb], 0.1, 10),
                ball([self.dist], self.D)]


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
    """Eqs. 58-68: V-dot = -(D + eps) sign(s) S_aug + d S_aug."""
    def build():
        A = _AttitudeAxis(printed=printed, layer=_printed_layer if printed else None)
        rhs = -A.K * sp.sign(A.s) * A.S + A.dist * A.S
        return Statement(A.Vdot, "==", rhs, A.domain(),
                         assumptions=["eq. 48 with e_ddot = X_ddot - acc_d", "eqs. 55, 66, 67 substituted"])
    return build


def _att_Vdot_bound(printed_layer: bool):
    """Eqs. 68-72: V-dot <= -eps |S_aug| under |d| <= D (eq. 51)."""
    def build():
        A = _AttitudeAxis(layer=_printed_layer if printed_layer else None)
        return Statement(A.Vdot, "<=", -A.eps * sp.Abs(A.S), A.domain(), symbolic=False,
                         assumptions=["|d| <= D (eq. 51)"])
    return build


def _att_Vdot_negative_definite():
    """After eq. 72: "its time-derivative is negative definite": -V-dot >= kappa (S^2 + |a_tilde|^2 + b_tilde^2)
    for some kappa > 0 (here any kappa in [1e-9, 1e-3])."""
    A = _AttitudeAxis()
    kappa = sp.Symbol("kappa", positive=True)
    at = [A.ah[i] - A.a[i] / A.b for i in range(6)]
    size = A.S**2 + sum(t**2 for t in at) + (A.bh - 1 / A.b) ** 2
    return Statement(-A.Vdot, ">=", kappa * size, [box(kappa, 1e-9, 1e-3), *A.domain()], symbolic=False,
                     residual_seconds=1.0, assumptions=["|d| <= D (eq. 51)"])


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


def _e_ddot_printed():
    """Eqs. 53-54, 59-60 as printed: e = q_ev (q_d = identity) and e_ddot = omega_e_dot."""
    q, w, wdot, sig, lam = _att_symbols()
    e_dot = quat_vec(quat_rate(q, w))                                   # eq. 24
    e_ddot = sp.Matrix([lie_derivative(e_dot[j], [q, w], [quat_rate(q, w), wdot]) for j in range(3)])
    return Statement(e_ddot, "==", wdot, _att_kin_domain(q, w, wdot, sig, lam),
                     constraints=[sum(x**2 for x in q) - 1], assumptions=["|q_e| = 1", "eq. 24 kinematics"])


def _e_ddot_implemented():
    """The implementation's surface s = omega_e + lambda_0 sgn(q_e4) q_ev: s_dot = omega_e_dot + lambda_0 e_dot
    with e_dot the u_1 term's (sgn(q_e4) d/dt q_ev from eq. 24), so s has the abstract dynamics."""
    q, w, wdot, sig, lam = _att_symbols()
    e = c.tracking_error(sig * c.quat_vec(q), sp.zeros(3, 1))
    e_dot_u1 = sig * c.quat_vec(c.attitude_error_rate(q, w))
    s = sp.Matrix([c.sliding_surface(w[j], e[j], lam) for j in range(3)])
    sdot = sp.Matrix([lie_derivative(s[j], [q, w], [quat_rate(q, w), wdot]) for j in range(3)])
    return Statement(sdot, "==", wdot + lam * e_dot_u1, _att_kin_domain(q, w, wdot, sig, lam),
                     constraints=[sum(x**2 for x in q) - 1, sig**2 - 1],
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


def _table1_vs_rigid(printed_reading: bool):
    """Eq. 48 with Table 1 (eq. 49) == omega_e_dot of the two rigid bodies (eqs. 26-29), principal axes."""
    def build():
        q, w, _, _, _ = _att_symbols()
        wc, h, T, Mc, Mt = (sp.Matrix(_real(f"{n}1:4")) for n in ("omega_c", "h_rw", "T_c", "M_c", "M_t"))
        Ic, It = _inertia_symbols()
        ref = rate_error_dynamics(q, w, wc, h, sp.diag(*Ic), sp.diag(*It), T, Mc, Mt)
        C_tc = c.dcm_target_to_chaser(q)
        delta = c.target_rate_in_target_axes(C_tc, wc, w)
        rows = []
        for j in range(3):
            a, f, b = c.table1_attitude_axis(j, Ic, It, wc, w, h, C_tc.T if printed_reading else C_tc, delta)
            dj = c.attitude_disturbance_axis(j, Ic, It, C_tc, Mc, Mt)
            rows.append(c.attitude_model_axis(a, f, b, T[j], dj))
        dom = [unit_quaternion(q), box(w, -0.15, 0.15), box(wc, -0.15, 0.15), box(h, -2, 2), box(T, -0.2, 0.2),
               box(Mc, -0.3, 0.3), box(Mt, -1, 1), box(Ic, 5, 30), box(It, 2000, 4000)]
        return Statement(sp.Matrix(rows), "==", ref, dom, constraints=[sum(x**2 for x in q) - 1],
                         residual_seconds=1.0, assumptions=["principal-axis inertias (the paper's model)"])
    return build


def _principal_axes_paper():
    """Eq. 49 (principal axes, diag of the paper's inertias) == the rigid bodies with the paper's full inertias."""
    q, w, _, _, _ = _att_symbols()
    wc, h, T = (sp.Matrix(_real(f"{n}1:4")) for n in ("omega_c", "h_rw", "T_c"))
    z = sp.zeros(3, 1)
    model = c.attitude_model(q, w, wc, h, tuple(np.diag(I_C_PAPER)), tuple(np.diag(I_T_PAPER)), T, z, z)
    ref = rate_error_dynamics(q, w, wc, h, sp.Matrix(I_C_PAPER), sp.Matrix(I_T_PAPER), T, z, z)
    wt = sp.Matrix(_real("omega_t1:4"))
    dom = [unit_quaternion(q), ball(wc, 0.13), ball(wt, 0.13),
           derived(list(w), list(rate_error(q, wc, wt)), [*q, *wc, *wt]), ball(h, 2.0), box(T, -0.17, 0.17)]
    return Statement(model, "==", ref, dom, symbolic=False, residual_seconds=1.0,
                     assumptions=["the paper's I_c, I_t (with products of inertia)", "no external torque",
                                  "|omega_c|, |omega_t| <= 0.13 rad/s (scenarios II/III: 0.122-0.124)",
                                  "|h_rw| <= 2 N m s (the wheels' capacity)", "|T_c,j| <= 0.17 N m"])


def _principal_axes_bound():
    """The products-of-inertia residual stays inside D_att (the implementation's bound, eq. 51)."""
    st = _principal_axes_paper()
    res = st.lhs - st.rhs
    D = c.C000().k._symbols["D_att"]
    lhs = sp.Matrix([sp.Abs(r) for r in res])
    return Statement(lhs, "<=", sp.Matrix(D), st.domain + [fixed(list(D), [0.0075] * 3)], symbolic=False,
                     residual_seconds=1.0, assumptions=st.assumptions + ["D_att = 0.0075 rad/s^2 (the default)"])


# ----- the implementation's law on the spacecraft equations

class _Meas:
    """Measurement symbols of C000.law (the fields it reads)."""

    def __init__(self):
        m = Layout("meas")
        for n, size in (("q_e", 4), ("w_e", 3), ("w_c", 3), ("h_rw", 3), ("r", 3), ("v", 3), ("n", 1),
                        ("n_dot", 1), ("r_t", 1), ("q_cL", 4)):
            m.add(n, size, "-", n, XYZW if size == 4 else (XYZ if size == 3 else ()))
        self.m = m


def _law():
    """(ctrl, meas, tau, F_lvlh, xc_dot, diag, sigma, mu) from C000.law with the default switches
    (shortest = adapt_a1 = acc_d_on = 1), q_cL = identity (so F_body = F_LVLH) and sgn(q_e4) -> sigma."""
    ctrl = c.C000()
    M = _Meas().m
    mu = sp.Symbol("mu", positive=True)
    cmd, xc_dot, diag = ctrl.law(M, sp.Symbol("t", real=True), {"mu": mu, "gravity_on": sp.Integer(1)})
    k = ctrl.k
    sig = sp.Symbol("sigma", real=True)
    rep = {k["shortest"]: 1, k["adapt_a1"]: 1, k["acc_d_on"]: 1}
    rep.update(dict(zip(M["q_cL"], [0, 0, 0, 1], strict=True)))

    def fix(e):
        e = e.xreplace(rep)
        return e.replace(lambda x: isinstance(x, sp.Piecewise), lambda x: sig)

    off = c.command_layout().offsets()
    cmd = fix(cmd)
    tau = cmd[off["tau_w"][0]:off["tau_w"][1], 0]
    F = cmd[off["F"][0]:off["F"][1], 0]
    xo = ctrl.xc.offsets()
    xc_dot = fix(xc_dot)
    rates = {name: xc_dot[a:b, 0] for name, (a, b) in xo.items()}
    do = ctrl.diag.offsets()
    diag = fix(diag)
    dg = {name: diag[a:b, 0] for name, (a, b) in do.items() if name in ("s_att", "S_aug_att", "s_pos", "S_aug_pos")}
    return ctrl, M, tau, F, rates, dg, sig, mu


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


def _att_spacecraft_Vdot(printed_e: bool):
    """V_j-dot (eq. 57 with gains, i = 1..6) along eq. 24 and the rigid-body omega_e_dot (principal axes)
    under the law: = -(D_j + eps_j) sign(s_j) S_j + d_j S_j + omega_e_dot_d,j S_j (fixed goal: the desired
    acceleration is a bias, choice C2).  ``printed_e``: e = q_ev with e_dot = d/dt q_ev in s and u_1
    (eqs. 53, 54, 56 as printed), everything else as implemented."""
    def build():
        ctrl, M, tau, F, rates, dg, sig, mu = _law()
        k, xc = ctrl.k, ctrl.xc
        q, w, wc, h = M["q_e"], M["w_e"], M["w_c"], M["h_rw"]
        Ic, It, Mc, Mt, dom = _att_spacecraft_common(ctrl, M, sig)
        C_tc = c.dcm_target_to_chaser(q)
        delta = c.target_rate_in_target_axes(C_tc, wc, w)
        s_list, S_list = list(dg["s_att"]), list(dg["S_aug_att"])
        if printed_e:
            e, e_dot = c.quat_vec(q), quat_vec(quat_rate(q, w))
            tau, rates = sp.zeros(3, 1), dict(rates)
            for j, ax in enumerate(XYZ):
                _, f, _ = c.table1_attitude_axis(j, c.I_C_NOM, c.I_T_NOM, wc, w, h, C_tc, delta)
                s = c.sliding_surface(e_dot[j], e[j], k["lam_att"])
                S = c.boundary_layer_surface(s, k["d_att"][j])
                u1 = c.u1_term(k["wdot_d"][j], k["lam_att"], e_dot[j])
                tau[j] = c.attitude_control_axis(xc[f"b_hat_{ax}"], u1, k["D_att"][j], k["eps_att"][j], s,
                                                 list(xc[f"a_hat_{ax}"]), f)
                rates[f"a_hat_{ax}"] = sp.Matrix([c.attitude_param_rate(fi, S, k["gamma_a"]) for fi in f])
                rates[f"b_hat_{ax}"] = sp.Matrix([c.gain_estimate_rate(u1, k["D_att"][j], k["eps_att"][j], s, S,
                                                                       k["gamma_b"])])
                s_list[j], S_list[j] = s, S
        wdot = rate_error_dynamics(q, w, wc, h, sp.diag(*Ic), sp.diag(*It), tau, Mc, Mt)
        qdot = quat_rate(q, w)
        lhs, rhs = [], []
        for j, ax in enumerate(XYZ):
            a, _, b = c.table1_attitude_axis(j, Ic, It, wc, w, h, C_tc, delta)
            Ss = sp.Symbol(f"S_aug_{ax}", real=True)
            ah, bh = list(xc[f"a_hat_{ax}"]), xc[f"b_hat_{ax}"]
            V = attitude_V(Ss, [ah[i] - a[i] / b for i in range(6)], bh - 1 / b, b, k["gamma_a"], k["gamma_b"])
            sdot = lie_derivative(s_list[j], [q, w], [qdot, wdot])
            Vdot = lie_derivative(V, [Ss, *ah, bh], [sdot, *rates[f"a_hat_{ax}"], rates[f"b_hat_{ax}"][0]])
            lhs.append(Vdot.xreplace({Ss: S_list[j]}))
            dj = c.attitude_disturbance_axis(j, Ic, It, C_tc, Mc, Mt)
            K = k["D_att"][j] + k["eps_att"][j]
            rhs.append((-K * sp.sign(s_list[j]) + dj + k["wdot_d"][j]) * S_list[j])
        return Statement(sp.Matrix(lhs), "==", sp.Matrix(rhs), dom, constraints=[sum(x**2 for x in q) - 1],
                         residual_seconds=1.0,
                         assumptions=["principal-axis inertias", "eq. 24 kinematics, eqs. 26-29 dynamics",
                                      "sigma = sgn(q_e4)"])
    return build


# =====================================================================================================
# Translation, abstract per-axis form (eqs. 81-129)
# =====================================================================================================

def translation_V(S, th_tilde, h_tilde, b, gamma_t=1, gamma_h=1, signs=None, h_sign=1):
    """V = S^2/2 + b/2 [sum sign_i th_tilde_i^2 / gamma_t + h_sign h_tilde^2 / gamma_h].

    Printed (eqs. 89, 109, 123): signs -1 for the alpha / a estimates (+1 for alpha_yy3), h_sign +1;
    implemented: all +1 (positive definite)."""
    signs = signs or [1] * len(th_tilde)
    return S**2 / 2 + b / 2 * (sum(sg * t**2 for sg, t in zip(signs, th_tilde, strict=True)) / gamma_t
                               + h_sign * h_tilde**2 / gamma_h)


#: the printed signs of the parameter-error terms in V (eqs. 89, 109, 123)
PRINTED_V_SIGNS = ([-1] * 5, [-1, -1, 1], [-1])
#: the printed adaptation laws, as factors of phi_i S_aug in the code's regressor convention
#: (eqs. 96-100: -phi S; 113, 114: -phi S; 115: -x S = +phi_3 S with phi_3 = -x; 127: -z S)
PRINTED_RATE_SIGNS = ([-1] * 5, [-1, -1, 1], [-1])


class _TranslationAxis:
    """One LVLH axis: r_ddot_j = sum theta_i phi_i (- mu/r_c^2 printed x) + b F + a_d (eqs. 81, 105, 30-z)
    in closed loop with eqs. 84-88, 106-108, 119-122 and the adaptation laws."""

    def __init__(self, axis: int, V_printed: bool = False, laws_printed: bool = False, layer=None):
        n = NPHI[axis]
        ax = AXES[axis]
        self.axis = axis
        self.e, self.edot, self.acc_d, self.ad = _real(f"e_{ax} edot_{ax} acc_d{ax} a_d{ax}")
        self.lam, self.D, self.eps, self.b = _pos(f"lambda_0 D_{ax} epsilon_{ax} b")
        self.d = sp.Symbol(f"d_{ax}", positive=True)
        self.gt, self.gh = _pos("gamma_theta gamma_h")
        self.th = list(sp.symbols(f"theta_{ax}1:{n + 1}", real=True))
        self.thh = list(sp.symbols(f"thetahat_{ax}1:{n + 1}", real=True))
        self.phi = list(sp.symbols(f"phi_{ax}1:{n + 1}", real=True))
        self.hh = sp.Symbol(f"hhat_{ax}", real=True)
        self.kg = sp.Symbol("g_c", positive=True)     # mu / r_c^2, the known term of eq. 81
        self.Ss = sp.Symbol(f"S_aug_{ax}", real=True)
        layer = layer or c.boundary_layer_surface
        self.s = c.sliding_surface(self.edot, self.e, self.lam)
        self.S = layer(self.s, self.d)
        self.u1 = c.u1_term(self.acc_d, self.lam, self.edot)
        self.F = c.translation_control_axis(self.hh, self.u1, self.D, self.eps, self.s, self.thh, self.phi)
        known = -self.kg if (laws_printed and axis == 0) else 0
        xddot = sum(t * p for t, p in zip(self.th, self.phi, strict=True)) + known + self.b * self.F + self.ad
        self.sdot = lie_derivative(self.s, [self.e, self.edot], [self.edot, xddot - self.acc_d])
        gt, gh = (1, 1) if (laws_printed or V_printed) else (self.gt, self.gh)
        if laws_printed:
            rates = [sg * p * self.S for sg, p in zip(PRINTED_RATE_SIGNS[axis], self.phi, strict=True)]
        else:
            rates = [c.translation_param_rate(p, self.S, gt) for p in self.phi]
        h_rate = c.gain_estimate_rate(self.u1, self.D, self.eps, self.s, self.S, gh)
        th_tilde = [t - th / self.b for t, th in zip(self.thh, self.th, strict=True)]
        signs = PRINTED_V_SIGNS[axis] if V_printed else None
        self.V = translation_V(self.Ss, th_tilde, self.hh - 1 / self.b, self.b, gt, gh, signs)
        Vdot = lie_derivative(self.V, [self.Ss, *self.thh, self.hh], [self.sdot, *rates, h_rate])
        self.Vdot = Vdot.xreplace({self.Ss: self.S})
        self.K = self.D + self.eps

    def domain(self, s_scale=5.0, D_var=None):
        dom = [box(self.lam, 0.005, 0.1), box(self.d, 0.001, 1.0), box(self.e, -500, 500),
               _s_then_edot(s_scale, self.e, self.lam, self.d, self.edot), box(self.eps, 0.001, 0.1),
               box(self.acc_d, -0.05, 0.05), box(self.b, 1 / 150, 1 / 50), box(self.th, -2, 2),
               box(self.thh, -200, 200), box(self.phi, -10, 10), box(self.hh, 0, 200),
               box([self.gt, self.gh], 1e-3, 10)]
        if D_var is None:
            dom += [box(self.D, 0.001, 0.1), ball([self.ad], self.D)]
        else:
            dom += D_var
        if self.kg in self.Vdot.free_symbols:
            dom.insert(0, box(self.kg, 0.2, 9.0))
        return dom


def _tr_V_definite(axis: int, printed: bool):
    def build():
        ax = AXES[axis]
        S = sp.Symbol(f"S_aug_{ax}", real=True)
        b, gt, gh = _pos("b gamma_theta gamma_h")
        tt = list(sp.symbols(f"thetatilde_{ax}1:{NPHI[axis] + 1}", real=True))
        ht = sp.Symbol(f"htilde_{ax}", real=True)
        if printed:
            V = translation_V(S, tt, ht, b, 1, 1, PRINTED_V_SIGNS[axis])
        else:
            V = translation_V(S, tt, ht, b, gt, gh)
        return Statement(V, ">", 0, [box(S, -1, 1), box(tt, -100, 100), box(ht, -100, 100), box(b, 1 / 150, 1 / 50),
                                     box([gt, gh], 1e-3, 10)],
                         positive=[b, gt, gh], zero_at=[S, *tt, ht], assumptions=["b = 1/m_c > 0", "gamma > 0"])
    return build


def _tr_Vdot_identity(axis: int, printed: bool):
    """Printed: V of eqs. 89/109/123 with the printed laws -> eqs. 102/117/129; implemented: positive-definite
    V with the code's laws -> -(D + eps) sign(s) S + a_d S."""
    def build():
        T = _TranslationAxis(axis, V_printed=printed, laws_printed=printed, layer=_printed_layer if printed else None)
        known = -T.kg * T.S if (printed and axis == 0) else 0
        rhs = known + T.ad * T.S - T.K * sp.sign(T.s) * T.S
        return Statement(T.Vdot, "==", rhs, T.domain(), assumptions=["model, law and adaptation substituted"])
    return build


def _tr_adaptation_sign(axis: int, printed: bool):
    """With a positive-definite V, the adaptation laws cancel the parameter errors in V-dot."""
    def build():
        T = _TranslationAxis(axis, V_printed=False, laws_printed=printed)
        rhs = T.ad * T.S - T.K * sp.sign(T.s) * T.S
        if printed and axis == 0:
            rhs += -T.kg * T.S
        return Statement(T.Vdot, "==", rhs, T.domain(), assumptions=["positive-definite V"])
    return build


def _tr_Vdot_bound(axis: int, printed: bool):
    """V-dot <= -eps |S_aug| under the paper's bound (eqs. 103-104, 117-118, 129)."""
    def build():
        T = _TranslationAxis(axis, V_printed=printed, laws_printed=printed, layer=_printed_layer if printed else None)
        D_var = None
        if printed and axis == 0:
            # eq. 104: D_xx >= |-mu/r_c^2 + A_dx|, here D = |-g_c + a_d| + margin
            A, marg = sp.Symbol("A_dx", positive=True), sp.Symbol("D_margin", nonnegative=True)
            D_var = [box(A, 0.0, 0.05), ball([T.ad], A), box(marg, 0.0, 0.1),
                     derived([T.D], [sp.Abs(-T.kg + T.ad) + marg], [T.kg, T.ad, marg])]
        return Statement(T.Vdot, "<=", -T.eps * sp.Abs(T.S), T.domain(D_var=D_var), symbolic=False,
                         assumptions=["|a_d| <= D" if not (printed and axis == 0) else
                                      "D_xx >= |-mu/r_c^2 + a_dx| (eq. 104)"])
    return build


# =====================================================================================================
# Translation, spacecraft layer (eq. 30 vs eqs. 81-83, 105; the law on eq. 30)
# =====================================================================================================

def _tr_symbols():
    r, v = sp.Matrix(_real("x y z")), sp.Matrix(_real("xdot ydot zdot"))
    n, n_dot = _real("n n_dot")
    r_t, mu, m = _pos("r_t mu m_c")
    a_c, a_d = sp.Matrix(_real("a_c1:4")), sp.Matrix(_real("a_d1:4"))
    return r, v, n, n_dot, r_t, mu, m, a_c, a_d


def _tr_domain(r, v, n, n_dot, r_t, mu, extra=()):
    return [box(r, -100, 100), box(v, -6, 6), box(r_t, 6.7e6, 4.3e7),
            box(n, 7e-5, 1.2e-3),
            box(n_dot, -2e-7, 2e-7), fixed(mu, [MU]), *extra]


def _form(axis: int, printed: bool):
    """Eq. 30's row == the per-axis form (printed: eq. 81 / 105 / 30-z as printed; implemented: the code's
    regressors of translation_regressors)."""
    def build():
        r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
        ref = relative_acceleration(r, v, r_t, n, n_dot, mu, a_c, a_d)[axis]
        r_c = c.chaser_orbit_radius(r_t, r)
        x, y, z = r
        xd, _, _ = v
        if printed:
            if axis == 0:     # eq. 81 (with f_xx1, f_xx2 of eqs. 82-83)
                form = c.translation_model(r, v, n, n_dot, r_c, mu, a_c, a_d)[0]
            elif axis == 1:   # eq. 105: alpha_yy1 x_dot + alpha_yy2 y - alpha_yy3 x
                form = -2 * n * xd + (n**2 - mu / r_c**3) * y - n_dot * x + a_c[1] + a_d[1]
            else:             # eq. 30's z row with a_zz1 = -mu/r_c^3 (eq. 121)
                form = -mu / r_c**3 * z + a_c[2] + a_d[2]
        else:
            theta, phi = c.translation_regressors(r, v, n, n_dot, r_c, mu)
            form = sum(t * p for t, p in zip(theta[axis], phi[axis], strict=True)) + a_c[axis] + a_d[axis]
        dom = _tr_domain(r, v, n, n_dot, r_t, mu, [box(a_c, -0.05, 0.05), box(a_d, -1e-4, 1e-4)])
        return Statement(form, "==", ref, dom, residual_seconds=2.0, assumptions=["r_c = |r_t X_L + r_e|"])
    return build


def _x_substitution_bound():
    """|eq. 81 - eq. 30| (x row) <= 1.05 * 3 mu (|r_e| - x) / r_t^3: the substitution error is a small extra a_dx."""
    r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
    ref = relative_acceleration(r, v, r_t, n, n_dot, mu, a_c, a_d)[0]
    model = c.translation_model(r, v, n, n_dot, c.chaser_orbit_radius(r_t, r), mu, a_c, a_d)[0]
    bound = sp.Rational(105, 100) * 3 * mu * (sp.sqrt(r.dot(r)) - r[0]) / r_t**3
    dom = _tr_domain(r, v, n, n_dot, r_t, mu, [box(a_c, -0.05, 0.05), box(a_d, -1e-4, 1e-4)])
    return Statement(sp.Abs(model - ref), "<=", bound, dom, symbolic=False,
                     assumptions=["|r_e| <= 100 m per axis", "r_t from LEO (6700 km) to GEO"])


def _x_regressors():
    """The code's regressor form (-mu/r_c^2 grouped into phi_xx5) == eq. 81 (translation_model)."""
    r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
    r_c = c.chaser_orbit_radius(r_t, r)
    theta, phi = c.translation_regressors(r, v, n, n_dot, r_c, mu)
    form = sum(t * p for t, p in zip(theta[0], phi[0], strict=True)) + a_c[0] + a_d[0]
    model = c.translation_model(r, v, n, n_dot, r_c, mu, a_c, a_d)[0]
    dom = _tr_domain(r, v, n, n_dot, r_t, mu, [box(a_c, -0.05, 0.05), box(a_d, -1e-4, 1e-4)])
    return Statement(form, "==", model, dom)


def _theta_constant():
    """The proof differentiates V with d/dt (theta / b) = 0: along eq. 30 (circular target orbit: n, r_t
    constant, n_dot = 0) theta = (2n, n^2 - mu/r_c^3, n_dot, mu/r_c^3, mu | ... | -mu/r_c^3) moves with r_c."""
    r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
    theta, _ = c.translation_regressors(r, v, n, 0, c.chaser_orbit_radius(r_t, r), mu)
    th = sp.Matrix([t * m for row in theta for t in row])       # theta / b = m_c theta
    rate = sp.Matrix([lie_derivative(t, list(r), list(v)) for t in th])
    dom = [box(r, -100, 100), box(v, -6, 6), box(r_t, 6.7e6, 4.3e7), box(n, 7e-5, 1.2e-3), fixed(mu, [MU]),
           box(m, 80, 120)]
    return Statement(rate, "==", 0, dom, symbolic=False, assumptions=["circular target orbit"])


def _tr_spacecraft_Vdot(axis: int, with_residual: bool):
    """V_j-dot (positive-definite V, frozen theta: d/dt(theta/b) = 0 as in the proof) of C000.law along eq. 30
    (a_control = F_LVLH / m_c): = -(D + eps) sign(s) S + a_d S + acc_d S (fixed goal: the desired acceleration is
    a bias, choice C2) [+ rho S for x, rho = eq. 30 - eq. 81 the substitution residual]."""
    def build():
        ctrl, M, tau, F, rates, dg, sig, mu = _law()
        k, xc = ctrl.k, ctrl.xc
        ax = AXES[axis]
        r, v, n, n_dot, r_t = M["r"], M["v"], M["n"], M["n_dot"], M["r_t"]
        m = sp.Symbol("m_c", positive=True)
        a_d = sp.Matrix(_real("a_d1:4"))
        acc = relative_acceleration(r, v, r_t, n, n_dot, mu, F / m, a_d)
        b = 1 / m
        r_c = c.chaser_orbit_radius(r_t, r)
        theta, _ = c.translation_regressors(r, v, n, n_dot, r_c, mu)
        Th = list(sp.symbols(f"Theta_{ax}1:{NPHI[axis] + 1}", real=True))     # frozen parameters
        thh = xc[f"theta_{ax}{ax}"]
        thh = [thh] if not isinstance(thh, sp.MatrixBase) else list(thh)
        hh = xc[f"h_hat_{ax}{ax}"]
        Ss = sp.Symbol(f"S_aug_{ax}", real=True)
        s, S = dg["s_pos"][axis], dg["S_aug_pos"][axis]
        V = translation_V(Ss, [t - T / b for t, T in zip(thh, Th, strict=True)], hh - 1 / b, b,
                          k["gamma_theta"], k["gamma_h"])
        sdot = lie_derivative(s, [r, v], [v, acc])
        Vdot = lie_derivative(V, [Ss, *thh, hh], [sdot, *rates[f"theta_{ax}{ax}"], rates[f"h_hat_{ax}{ax}"][0]])
        Vdot = Vdot.xreplace({Ss: S, **dict(zip(Th, theta[axis], strict=True))})
        K = k["D_pos"][axis] + k["eps_pos"][axis]
        rhs = (-K * sp.sign(s) + a_d[axis] + k["acc_d"][axis]) * S
        if with_residual:
            z3 = sp.zeros(3, 1)
            rho = (relative_acceleration(r, v, r_t, n, n_dot, mu, z3, z3)[0]
                   - c.translation_model(r, v, n, n_dot, r_c, mu, z3, z3)[0])
            rhs += rho * S
        dom = [box(r, -100, 100), box(v, -6, 6), box(r_t, 6.7e6, 4.3e7), box(n, 7e-5, 1.2e-3),
               box(n_dot, -2e-7, 2e-7), fixed(mu, [MU]), box(m, 80, 120), box(a_d, -1e-3, 1e-3),
               box(k["lam_pos"], 0.005, 0.1), box(list(k["D_pos"]) + list(k["eps_pos"]), 0.001, 0.1),
               box(k["d_pos"], 0.0, 0.05), box(k["acc_d"], -0.05, 0.05), box(k["r_goal"], -20, 20),
               box(k["gamma_theta"], 1e-9, 1.0), box(k["gamma_h"], 0.1, 10), box(hh, 50, 200)]
        scales = ((1, 1e-3, 1e-3, 1e-3, 1e17), (1, 1e-3, 1e-3), (1e-3,))[axis]
        dom += [box([t], -sc, sc) for t, sc in zip(thh, scales, strict=True)]
        return Statement(Vdot, "==", rhs, dom, residual_seconds=1.0,
                         assumptions=["eq. 30 with a_control = F_LVLH / m_c",
                                      "theta frozen (d/dt(theta/b) = 0, the proof's premise)"])
    return build


# =====================================================================================================
# Claims
# =====================================================================================================

def _claims() -> list[Claim]:
    C = "c000"
    out = [
        # ---- boundary layer
        Claim("c000.boundary_layer.sign", C, "boundary layer", "abstract", "52, 84, 106, 119; 68-72",
              "sign(s) S_aug = |S_aug| (used from eq. 68 to eq. 72)", _bl_sign(True), _bl_sign(False),
              correction="S_aug = s - d sat(s/d) = max(s - d, 0) + min(s + d, 0)",
              note="Printed S_aug = s - d sign(s) has the opposite sign of s inside |s| < d, so "
                   "-(D + eps) sign(s) S_aug = +(D + eps)|S_aug| there."),
        Claim("c000.boundary_layer.zero_inside", C, "boundary layer", "abstract", "52 and the text after 57",
              "S_aug = 0 inside the boundary layer |s| <= d", _bl_zero_inside(True), _bl_zero_inside(False),
              correction="S_aug = s - d sat(s/d)",
              note="The text says S_aug = 0 inside the layer; the printed formula is s - d sign(s) != 0 there."),
        Claim("c000.boundary_layer.derivative", C, "boundary layer", "abstract", "57-59",
              "S_aug dS_aug/ds = S_aug (so S_aug S_aug_dot = S_aug s_dot, the step in eq. 58)", None,
              _bl_derivative,
              note="Holds for the implemented layer (dS/ds = 1 outside, S = 0 inside); the V-dot claims use it."),
        # ---- attitude, abstract
        Claim("c000.attitude.V_definite", C, "attitude", "abstract", "57",
              "V_x positive definite in (S_aug, a_tilde, b_tilde)", _att_V_definite(True), _att_V_definite(False),
              correction="V = S^2/2 + b/2 [sum_{i=1..6} a_tilde_i^2/gamma_a + b_tilde^2/gamma_b]",
              note="b = 1/I_cx > 0. Definite in S_aug, not in (e, e_dot): V vanishes on the whole layer |s| <= d "
                   "(printed S_aug: on |s| = d)."),
        Claim("c000.attitude.Vdot_identity", C, "attitude", "abstract", "55, 58-68",
              "V_x-dot = -(D + eps) sign(s) S_aug + d S_aug under eqs. 55, 66, 67",
              _att_Vdot_identity(True), _att_Vdot_identity(False),
              correction="eq. 55: a_hat_x1 f_x1 (a_hat_x1 -> a_x1/b_x = I_cx adapted by eq. 66 with i = 1) instead "
                         "of a_x1 f_x1; V with i = 1..6 and gains gamma_a, gamma_b",
              note="Printed eq. 55 adds a_x1 f_x1 (rad/s^2) to the torque; the proof (eqs. 62-64) needs "
                   "a_x1 f_x1 / b_x: residual (b_x - 1) f_x1 S_aug."),
        Claim("c000.attitude.Vdot_bound", C, "attitude", "abstract", "51, 68-72",
              "V_x-dot <= -eps |S_aug| under |d| <= D", _att_Vdot_bound(True), _att_Vdot_bound(False),
              correction="S_aug = s - d sat(s/d)",
              note="With the printed S_aug = s - d sign(s), inside |s| < d V-dot = (D + eps - d sign(s))|S_aug| > 0."),
        Claim("c000.attitude.Vdot_negative_definite", C, "attitude", "abstract", "72 (text after it)",
              "V_x-dot is negative definite in (S_aug, a_tilde, b_tilde)", _att_Vdot_negative_definite,
              about="paper",
              note="V-dot = (-(D + eps) sign(s) + d) S_aug does not depend on the parameter errors (and is 0 inside "
                   "the layer): negative semidefinite only. S_aug -> 0 follows (Barbalat); the estimates need not "
                   "converge, contrary to the conclusion's 'adaptive parameters converge'."),
        # ---- attitude, spacecraft
        Claim("c000.attitude.e_ddot", C, "attitude", "spacecraft", "24, 53-54, 59-60",
              "The surface's derivative is omega_e_dot + lambda_0 e_dot (the proof's e_ddot = omega_e_dot)",
              _e_ddot_printed, _e_ddot_implemented,
              correction="s = omega_e + lambda_0 sgn(q_e4) q_ev and u_1 = -omega_e_dot_d + lambda_0 e_dot with "
                         "e_dot = sgn(q_e4) d/dt q_ev from eq. 24",
              note="For e = q_ev (eq. 54), d^2/dt^2 q_ev = (q_e4 w_dot + q_ev x w_dot)/2 - |w|^2 q_ev/4 != w_dot."),
        Claim("c000.attitude.sliding_decay", C, "attitude", "spacecraft", "53 (s = 0)",
              "On s = 0 the quaternion error decays: d/dt |e|^2 <= -lambda_0 |q_e4| |e|^2", None, _sliding_decay,
              note="Needs e = sgn(q_e4) q_ev (choice C1); with e = q_ev the error grows while q_e4 < 0 (unwinding)."),
        Claim("c000.attitude.table1", C, "attitude", "spacecraft", "26-29, 48-50, Table 1",
              "Eq. 48 with Table 1 is omega_e_dot of the two rigid bodies (principal axes)",
              _table1_vs_rigid(True), _table1_vs_rigid(False),
              correction="c_jm in eq. 49 are the entries of row j of C_t^c (eq. 50: of its transpose)",
              note="Read as eq. 50 says ('entries of (C_t^c)^-1'), the target terms of eq. 49 are wrong."),
        Claim("c000.attitude.principal_axes", C, "attitude", "spacecraft", "49 vs 6, 10, 26-29",
              "Eq. 49 (principal axes) is the rigid-body dynamics with the paper's inertias (products of inertia)",
              _principal_axes_paper, _principal_axes_bound,
              correction="products of inertia treated as part of d: residual <= D_att = 0.0075 rad/s^2 "
                         "for |omega| <= 0.13 rad/s, |T_c| <= 0.17 N m",
              note="Eq. 49 drops the products of inertia of I_c and I_t (-0.09..-0.4, -135..-154 kg m^2)."),
        Claim("c000.attitude.spacecraft_Vdot", C, "attitude", "spacecraft", "24, 26-29, 53-68",
              "V_j-dot of the full law along the spacecraft equations = -(D+eps) sign(s) S + d S + wdot_d S",
              _att_spacecraft_Vdot(True), _att_spacecraft_Vdot(False),
              correction="e = sgn(q_e4) q_ev, s = omega_e + lambda_0 e, u_1 with the true e_dot",
              note="With e = q_ev and s = d/dt q_ev + lambda_0 q_ev (eqs. 53-54), s_dot contains q_ev_ddot, not the "
                   "omega_e_dot the law cancels. The wdot_d S term: the goal is fixed (choice C2)."),
    ]
    # ---- translation, per axis
    eqs = {0: ("89", "90-102", "96-100", "102-104", "81-83"),
           1: ("109", "110-117", "113-114", "117-118", "105"),
           2: ("123", "124-129", "127", "129", "30 (z row), 121")}
    for i, ax in enumerate(AXES):
        part = f"translation {ax}"
        eV, eId, eAd, eB, eF = eqs[i]
        pre = f"c000.translation_{ax}"
        out += [
            Claim(f"{pre}.V_definite", C, part, "abstract", eV,
                  f"V_{ax}{ax} positive definite in (S_aug, theta_tilde, h_tilde)",
                  _tr_V_definite(i, True), _tr_V_definite(i, False),
                  correction="V = S^2/2 + b/2 [sum theta_tilde^2/gamma_theta + h_tilde^2/gamma_h]",
                  note=f"Eq. {eV} enters parameter errors with a minus sign: V < 0 at S_aug = 0, theta_tilde != 0."
                       + (" Eq. 123 also writes S_aug_yy for S_aug_zz." if i == 2 else "")),
            Claim(f"{pre}.Vdot_identity", C, part, "abstract", eId,
                  "V-dot along the closed loop equals the paper's result", _tr_Vdot_identity(i, True),
                  _tr_Vdot_identity(i, False),
                  note="The printed derivation is consistent with its own (indefinite) V and laws"
                       + (" and keeps -mu/r_c^2 S_aug (eq. 102); the implementation groups -mu/r_c^2 into "
                          "phi_xx5 = f_xx2 - 1/r_c^2" if i == 0 else "") + "."),
            Claim(f"{pre}.adaptation_sign", C, part, "abstract", eAd,
                  "With a positive-definite V the adaptation laws cancel the parameter errors",
                  _tr_adaptation_sign(i, True), _tr_adaptation_sign(i, False),
                  correction="theta_hat_dot = +gamma_theta phi S_aug" + (" (eq. 115 unchanged)" if i == 1 else ""),
                  note="The printed -phi S_aug signs follow from the indefinite V; with V > 0 they double the "
                       "parameter-error terms instead of cancelling them."),
            Claim(f"{pre}.Vdot_bound", C, part, "abstract", eB,
                  "V-dot <= -eps |S_aug| under the disturbance bound", _tr_Vdot_bound(i, True),
                  _tr_Vdot_bound(i, False),
                  correction="S_aug = s - d sat(s/d)" + ("; bound |a_dx| <= D_xx instead of eq. 104's "
                                                         "D_xx >= |-mu/r_c^2 + A_dx| (~8.7 m/s^2 in LEO)"
                                                         if i == 0 else ""),
                  note="Fails with the printed S_aug = s - d sign(s) inside the layer (V-dot > 0 there)."),
        ]
        if i == 0:
            out += [
                Claim(f"{pre}.form_eq30", C, part, "spacecraft", "30, 81-83",
                      "Eq. 81 (r_t = r_c - |r_e|) is eq. 30's x row", _form(0, True), _x_substitution_bound,
                      correction="the substitution residual is treated as part of a_dx: |eq. 81 - eq. 30| "
                                 "<= 1.05 * 3 mu (|r_e| - x)/r_t^3 (< 3e-4 m/s^2 within 100 m in LEO)",
                      note="r_t = r_c - |r_e| is exact only for a radial offset (r_e along +X_L)."),
                Claim(f"{pre}.regressors", C, part, "spacecraft", "81-83, 86",
                      "The implemented regressors reproduce eq. 81 (-mu/r_c^2 grouped into phi_xx5)", None,
                      _x_regressors),
                Claim(f"{pre}.spacecraft_Vdot", C, part, "spacecraft", "30, 84-101",
                      "V-dot of the full law along eq. 30 = -(D+eps) sign(s) S + a_d S + acc_d S",
                      _tr_spacecraft_Vdot(0, False), _tr_spacecraft_Vdot(0, True),
                      correction="+ rho S_aug with rho = eq. 30 - eq. 81 (the substitution residual, part of a_dx)",
                      note="Frozen theta (the proof's premise). The x row of eq. 30 differs from eq. 81 off the "
                           "radial direction."),
            ]
        else:
            out += [
                Claim(f"{pre}.form_eq30", C, part, "spacecraft", "30, " + eF,
                      f"The printed / implemented per-axis form is eq. 30's {ax} row", _form(i, True), _form(i, False)),
                Claim(f"{pre}.spacecraft_Vdot", C, part, "spacecraft", "30, " + eId,
                      "V-dot of the full law along eq. 30 = -(D+eps) sign(s) S + a_d S + acc_d S", None,
                      _tr_spacecraft_Vdot(i, False),
                      note="Frozen theta (the proof's premise); the acc_d S term: fixed goal (choice C2)."),
            ]
    out.append(Claim("c000.translation.theta_constant", C, "translation", "spacecraft", "81, 89-90, 105, 121",
                     "The estimated parameters theta/b are constant along the motion (V-dot has no d/dt(theta/b))",
                     _theta_constant, about="paper",
                     note="mu/r_c^3 (and n^2 - mu/r_c^3) change with r_c: d/dt = -3 mu r_c_dot/r_c^4 != 0; the "
                          "implementation inherits this (slow drift, not in V-dot)."))
    return out


CLAIMS = _claims()


# =====================================================================================================
# Mutations
# =====================================================================================================

def _flip_switching(out, b_hat, u1, D, eps, s, a_hat, f):
    return out + 2 * b_hat * (D + eps) * sp.sign(s)


def _drop_regression_att(out, b_hat, u1, D, eps, s, a_hat, f):
    return out - sum(a * fi for a, fi in zip(a_hat, f, strict=True))


def _flip_regression_tr(out, h_hat, u1, D, eps, s, theta_hat, phi):
    return out + 2 * sum(t * p for t, p in zip(theta_hat, phi, strict=True))


def _drop_lambda_edot(out, acc_d, lam, e_dot):
    return -acc_d


def _ungroup_mu(out, r_e, v_e, n, n_dot, r_c, mu):
    theta, phi = out
    phi = [list(p) for p in phi]
    phi[0][4] = c.f_xx2(r_c, r_e)
    return theta, phi


def _drop_wheel_regressor(out, *a, **kw):
    a_, f, b = out
    f = list(f)
    f[2] = sp.Integer(0)
    return a_, f, b


_AI, _AS = "c000.attitude.Vdot_identity", "c000.attitude.spacecraft_Vdot"


def _t(ax, name):
    return f"c000.translation_{ax}.{name}"


MUTATIONS = [
    Mutation("c000: switching term sign flipped (eq. 55)", c, "attitude_control_axis",
             replace_output(_flip_switching), (_AI, _AS, "c000.attitude.Vdot_bound")),
    Mutation("c000: sum a_hat f dropped from eq. 55", c, "attitude_control_axis",
             replace_output(_drop_regression_att), (_AI, _AS)),
    Mutation("c000: b_hat x -1 in eq. 55", c, "attitude_control_axis", scale_argument("b_hat", -1), (_AI,)),
    Mutation("c000: sign of the a_hat adaptation (eq. 66)", c, "attitude_param_rate", negate_output(), (_AI, _AS)),
    Mutation("c000: gamma_a x -1 in eq. 66", c, "attitude_param_rate", scale_argument("gamma", -1), (_AI,)),
    Mutation("c000: sign of the b_hat / h_hat adaptation (eqs. 67, 101, 116, 128)", c, "gain_estimate_rate",
             negate_output(), (_AI, _t("y", "Vdot_identity"), _t("x", "spacecraft_Vdot"))),
    Mutation("c000: lambda_0 e_dot dropped from u_1 (eqs. 56, 88, 122)", c, "u1_term",
             replace_output(_drop_lambda_edot), (_AI, _AS, _t("z", "Vdot_identity"), _t("y", "spacecraft_Vdot"))),
    Mutation("c000: sum theta_hat phi sign flipped (eqs. 86, 108, 121)", c, "translation_control_axis",
             replace_output(_flip_regression_tr), tuple(_t(ax, "Vdot_identity") for ax in AXES)),
    Mutation("c000: h_hat x -1 in eqs. 86, 108, 121", c, "translation_control_axis", scale_argument("h_hat", -1),
             (_t("x", "Vdot_identity"), _t("z", "spacecraft_Vdot"))),
    Mutation("c000: printed sign of the theta adaptation (eqs. 96-100, 113-114, 127)", c, "translation_param_rate",
             negate_output(), (*(_t(ax, "adaptation_sign") for ax in AXES), _t("y", "spacecraft_Vdot"))),
    Mutation("c000: -mu/r_c^2 not grouped into phi_xx5 (eq. 81)", c, "translation_regressors",
             replace_output(_ungroup_mu), (_t("x", "regressors"), _t("x", "spacecraft_Vdot"))),
    Mutation("c000: printed boundary layer s - d sign(s)", c, "boundary_layer_surface",
             replace_output(lambda out, s, d: _printed_layer(s, d)),
             ("c000.boundary_layer.sign", "c000.boundary_layer.zero_inside", "c000.attitude.Vdot_bound",
              _t("x", "Vdot_bound"))),
    Mutation("c000: lambda_0 -> -lambda_0 in the sliding surface (eqs. 53, 85, 107, 120)", c, "sliding_surface",
             scale_argument("lam", -1), ("c000.attitude.sliding_decay", "c000.attitude.e_ddot",
                                         _t("y", "Vdot_identity"))),
    Mutation("c000: wheel-momentum regressor f_j3 dropped (Table 1)", c, "table1_attitude_axis",
             replace_output(_drop_wheel_regressor), ("c000.attitude.table1", _AS)),
]
