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

The paper's S_aug is typed piecewise (eq. 52 completed by the text after eq. 57: 0 inside the layer); eq. 52's
formula read alone is reported once, as the notation erratum ``c000.boundary_layer.zero_inside``.  Claims marked
"implementation only" (paper=None) are the ones whose printed counterpart would be a hybrid of printed and
implemented pieces; their printed failures are the claims named in their notes.

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
from ..rotations import quat_rate, quat_to_dcm
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
    """S_aug = s - d sign(s) as printed (eqs. 52, 84, 106, 119), read alone."""
    return s - d * sp.sign(s)


def _paper_layer(s, d):
    """The paper's S_aug: eq. 52 completed by the text after eq. 57 ("inside the boundary layer S_aug = 0"):
    0 for |s| <= d, s - d sign(s) outside (Slotine's s_Delta, typed piecewise as the paper states it)."""
    return sp.Piecewise((0, sp.Abs(s) <= d), (s - d * sp.sign(s), True))


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
    """sign(s) S_aug = |S_aug|: the step from eq. 68 to eqs. 69-72 (and 102-104, 117, 129); printed: the
    paper's piecewise S_aug (eq. 52 with the text after eq. 57)."""
    def build():
        s, d = _layer_symbols()
        S = (_paper_layer if printed else c.boundary_layer_surface)(s, d)
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
    """(ctrl, meas, tau, F_body, xc_dot, diag, sigma, mu) from C000.law with the default switches
    (shortest = adapt_a1 = acc_d_on = 1) and sgn(q_e4) -> sigma; q_cL stays a symbol (F is the body force)."""
    ctrl = c.C000()
    M = _Meas().m
    mu = sp.Symbol("mu", positive=True)
    cmd, xc_dot, diag = ctrl.law(M, sp.Symbol("t", real=True), {"mu": mu, "gravity_on": sp.Integer(1)})
    k = ctrl.k
    sig = sp.Symbol("sigma", real=True)
    rep = {k["shortest"]: 1, k["adapt_a1"]: 1, k["acc_d_on"]: 1}

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
        xddot = c.translation_model_axis(self.th, self.phi, self.b, self.F, self.ad) + known
        self.sdot = lie_derivative(self.s, [self.e, self.edot], [self.edot, xddot - self.acc_d])
        gt, gh = (1, 1) if (laws_printed or V_printed) else (self.gt, self.gh)
        if laws_printed:
            rates = [sg * p * self.S for sg, p in zip(PRINTED_RATE_SIGNS[axis], self.phi, strict=True)]
        else:
            rates = [c.translation_param_rate(p, self.S, gt) for p in self.phi]
        h_rate = c.gain_estimate_rate(self.u1, self.D, self.eps, self.s, self.S, gh)
        self.h_rate = h_rate
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
    """Printed: V of eqs. 89/109/123 with the printed laws and the paper's piecewise layer -> eqs. 102/117/129;
    implemented: positive-definite V with the code's laws -> -(D + eps) sign(s) S + a_d S."""
    def build():
        T = _TranslationAxis(axis, V_printed=printed, laws_printed=printed, layer=_paper_layer if printed else None)
        known = -T.kg * T.S if (printed and axis == 0) else 0
        rhs = known + T.ad * T.S - T.K * sp.sign(T.s) * T.S
        return Statement(T.Vdot, "==", rhs, T.domain(), assumptions=["model, law and adaptation substituted"])
    return build


def _tr_adaptation_sign(axis: int):
    """With a positive-definite V, the implemented adaptation laws cancel the parameter errors in V-dot."""
    def build():
        T = _TranslationAxis(axis, V_printed=False, laws_printed=False)
        rhs = T.ad * T.S - T.K * sp.sign(T.s) * T.S
        return Statement(T.Vdot, "==", rhs, T.domain(), assumptions=["positive-definite V"])
    return build


def _tr_Vdot_bound(axis: int, printed: bool):
    """V-dot <= -eps |S_aug| under the paper's bound (eqs. 103-104, 117-118, 129).  Printed: V, laws and the
    piecewise layer as printed; for x, eq. 104 with A_dx the upper bound of |a_dx|: D_xx = |-mu/r_c^2 + A_dx|
    + margin (the smallest D the printed condition allows is g - A)."""
    def build():
        T = _TranslationAxis(axis, V_printed=printed, laws_printed=printed, layer=_paper_layer if printed else None)
        D_var = None
        if printed and axis == 0:
            A, marg = sp.Symbol("A_dx", positive=True), sp.Symbol("D_margin", nonnegative=True)
            D_var = [box(A, 0.0, 0.05), ball([T.ad], A), box(marg, 0.0, 0.01),
                     derived([T.D], [sp.Abs(-T.kg + A) + marg], [T.kg, A, marg])]
        return Statement(T.Vdot, "<=", -T.eps * sp.Abs(T.S), T.domain(D_var=D_var), symbolic=False,
                         assumptions=["|a_d| <= D" if not (printed and axis == 0) else
                                      "|a_dx| <= A_dx, D_xx = |-mu/r_c^2 + A_dx| + margin (eq. 104)"])
    return build


def _shared_h_hat():
    """Eqs. 101, 116, 128 give one h_hat three laws.  With one h_hat (one b/2 (h_hat - h)^2 term in the summed V)
    updated by eq. 101, the summed V-dot is not the sum of eqs. 102, 117, 129 (printed V, laws, layer)."""
    Ts = [_TranslationAxis(i, V_printed=True, laws_printed=True, layer=_paper_layer) for i in range(3)]
    hh = Ts[0].hh
    rep = {T.hh: hh for T in Ts}
    total = sum(T.Vdot for T in Ts)
    # remove each axis' own h term, add the single one driven by eq. 101 (the x law)
    total += -sum(sp.diff(T.V, T.hh) * T.h_rate for T in Ts) + sp.diff(Ts[0].V, Ts[0].hh) * Ts[0].h_rate
    total = total.xreplace(rep)
    rhs = sum(T.ad * T.S - T.K * sp.sign(T.s) * T.S for T in Ts) - Ts[0].kg * Ts[0].S
    dom, seen = [], set()
    for T in Ts:
        for v in T.domain():
            if set(v.symbols) & seen or set(v.symbols) & (set(rep) - {hh}):
                continue
            dom.append(v)
            seen |= set(v.symbols)
    return Statement(total, "==", rhs.xreplace(rep), dom, symbolic=False, residual_seconds=1.0,
                     assumptions=["one h_hat = 1/b shared by the three axes (eq. 89: h = m_c)"])


def _convergence(printed: bool):
    """The conclusion "tracking errors converge to zero asymptotically": where V-dot = 0 (inside the layer,
    |s| <= d, S_aug = 0), d/dt(e^2/2) = e (s - lambda e).  Printed: <= 0 everywhere there (e -> 0);
    corrected: <= 0 for |e| >= d/lambda (ultimate bound |e| <= d/lambda, |s| <= d)."""
    e, edot = _real("e edot")
    lam, d = _pos("lambda_0 d")
    s = c.sliding_surface(edot, e, lam)     # the layer |s| <= d is drawn below: e_dot = s - lambda e

    def draw_e(z, env):
        if printed:
            return (z[:, 0] * 3 * env[d] / env[lam])[:, None]
        bound = env[d] / env[lam]
        return (np.sign(z[:, 0] + 1e-300) * bound * (1 + 2 * np.abs(z[:, 0])))[:, None]

    def draw_edot(z, env):      # s uniform in [-d, d] (S_aug = 0)
        return (z[:, 0] * env[d] - env[lam] * env[e])[:, None]

    dom = [box(lam, 0.005, 1.0), box(d, 0.001, 1.0),
           custom([e], 1, draw_e, "|e| <= 3 d/lambda" if printed else "|e| >= d/lambda"),
           custom([edot], 1, draw_edot, "|s| <= d")]
    assert s.has(edot)
    return Statement(e * edot, "<=", 0, dom,
                     symbolic=False, assumptions=["inside the boundary layer |s| <= d (V-dot = 0 there)"])


# =====================================================================================================
# Translation, spacecraft layer (eq. 30 vs eqs. 81-83, 105; the law on eq. 30)
# =====================================================================================================

def _tr_symbols():
    r, v = sp.Matrix(_real("x y z")), sp.Matrix(_real("xdot ydot zdot"))
    n, n_dot = _real("n n_dot")
    r_t, mu, m = _pos("r_t mu m_c")
    a_c, a_d = sp.Matrix(_real("a_c1:4")), sp.Matrix(_real("a_d1:4"))
    return r, v, n, n_dot, r_t, mu, m, a_c, a_d


def _kepler(rp, e, f):
    """(r, r_dot, n, n_dot, n_ddot) of a Kepler orbit (perigee radius rp, eccentricity e, true anomaly f);
    n = h/r^2 is the LVLH rate."""
    p = rp * (1 + e)
    h = np.sqrt(MU * p)
    r = p / (1 + e * np.cos(f))
    rdot = np.sqrt(MU / p) * e * np.sin(f)
    n = h / r**2
    rddot = h**2 / r**3 - MU / r**2
    return r, rdot, n, -2 * h * rdot / r**3, -2 * h * rddot / r**3 + 6 * h * rdot**2 / r**4


def _orbit(r_t, n, n_dot, extra=()):
    """(r_t, n, n_dot[, r_t_dot, n_ddot]) of one target orbit: perigee 6700 km .. 43000 km (LEO to GEO),
    e in [0, 0.15] (scenario III: 6778 km, 0.138), any true anomaly."""
    def draw(z, env):
        rp = 6.7e6 + (z[:, 0] + 1) / 2 * (4.3e7 - 6.7e6)
        e = (z[:, 1] + 1) / 2 * 0.15
        r, rdot, nn, nd, ndd = _kepler(rp, e, np.pi * z[:, 2])
        cols = [r, nn, nd] + ([rdot, ndd] if extra else [])
        return np.column_stack(cols)
    return custom([r_t, n, n_dot, *extra], 3, draw, "Kepler orbit: r_p 6700-43000 km, e <= 0.15")


def _tr_domain(r, v, n, n_dot, r_t, mu, extra=()):
    return [box(r, -100, 100), box(v, -6, 6), _orbit(r_t, n, n_dot), fixed(mu, [MU]), *extra]


def _eq81_printed(r, v, n, n_dot, r_c, mu, a_c, a_d):
    """Eq. 81 with eqs. 82-83, hand-typed."""
    x, y, z = r
    _, yd, _ = v
    f1 = sp.sqrt(x**2 + y**2 + z**2)
    f2 = 1 / (r_c - sp.sqrt(x**2 + y**2 + z**2)) ** 2
    return (2 * n * yd + n**2 * x - mu / r_c**3 * x + n_dot * y - mu / r_c**2 + mu * f2 + mu / r_c**3 * f1
            + a_c + a_d)


def _form(axis: int, printed: bool):
    """Eq. 30's row == the per-axis form (printed: eq. 81 / 105 / 30-z as printed, hand-typed; implemented: the
    code's regressors of translation_regressors)."""
    def build():
        r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
        ref = relative_acceleration(r, v, r_t, n, n_dot, mu, a_c, a_d)[axis]
        r_c = c.chaser_orbit_radius(r_t, r)
        x, y, z = r
        xd, _, _ = v
        if printed:
            if axis == 0:     # eq. 81 (with f_xx1, f_xx2 of eqs. 82-83)
                form = _eq81_printed(r, v, n, n_dot, r_c, mu, a_c[0], a_d[0])
            elif axis == 1:   # eq. 105: alpha_yy1 x_dot + alpha_yy2 y - alpha_yy3 x
                form = -2 * n * xd + (n**2 - mu / r_c**3) * y - n_dot * x + a_c[1] + a_d[1]
            else:             # eq. 30's z row with a_zz1 = -mu/r_c^3 (eq. 121)
                form = -mu / r_c**3 * z + a_c[2] + a_d[2]
        else:
            theta, phi = c.translation_regressors(r, v, n, n_dot, r_c, mu)
            form = c.translation_model_axis(theta[axis], phi[axis], 1, a_c[axis], a_d[axis])
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
    """The code's regressor form (-mu/r_c^2 grouped into phi_xx5) == eq. 81 as printed (hand-typed)."""
    r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
    r_c = c.chaser_orbit_radius(r_t, r)
    theta, phi = c.translation_regressors(r, v, n, n_dot, r_c, mu)
    form = c.translation_model_axis(theta[0], phi[0], 1, a_c[0], a_d[0])
    model = _eq81_printed(r, v, n, n_dot, r_c, mu, a_c[0], a_d[0])
    dom = _tr_domain(r, v, n, n_dot, r_t, mu, [box(a_c, -0.05, 0.05), box(a_d, -1e-4, 1e-4)])
    return Statement(form, "==", model, dom)


def _theta_constant():
    """The proof differentiates V with d/dt (theta / b) = 0.  Along eq. 30 on a Kepler target orbit (scenario
    III: e = 0.138; r_t, n, n_dot move) and with the chaser mass profile of Fig. 9 (m_c_dot), theta/b =
    m_c (2n, n^2 - mu/r_c^3, n_dot, mu/r_c^3, mu | ... | -mu/r_c^3) is not constant; with gamma_theta = 1e-8 the
    neglected V-dot term -(b/gamma_theta) sum theta_tilde d/dt(theta/b) is multiplied by 1e8."""
    r, v, n, n_dot, r_t, mu, m, a_c, a_d = _tr_symbols()
    rtd, ndd, mdot = _real("r_t_dot n_ddot m_c_dot")
    theta, _ = c.translation_regressors(r, v, n, n_dot, c.chaser_orbit_radius(r_t, r), mu)
    th = sp.Matrix([t * m for row in theta for t in row])       # theta / b = m_c theta
    rate = sp.Matrix([lie_derivative(t, [*r, r_t, n, n_dot, m], [*v, rtd, n_dot, ndd, mdot]) for t in th])
    dom = [box(r, -100, 100), box(v, -6, 6), _orbit(r_t, n, n_dot, extra=(rtd, ndd)), fixed(mu, [MU]),
           box(m, 80, 120), box(mdot, -0.3, 0.3)]
    return Statement(rate, "==", 0, dom, symbolic=False,
                     assumptions=["Kepler target orbit, e <= 0.15", "|m_c_dot| <= 0.3 kg/s (Fig. 9: 36 kg in 120 s)"])


def _mean_motion():
    """Eqs. 9 and 35 (n = sqrt(mu/r^3), n_dot = -3/2 sqrt(mu) r^-5/2 r_dot) against the LVLH rate of the target
    orbit (n = h/r^2, n_dot = -2 n r_dot / r) that eq. 30 needs."""
    r_t, rtd, n, n_dot = _real("r_t r_t_dot n n_dot")
    ndd = sp.Symbol("n_ddot", real=True)
    lhs = sp.Matrix([sp.sqrt(MU / r_t**3), -sp.Rational(3, 2) * sp.sqrt(MU) * r_t ** sp.Rational(-5, 2) * rtd])
    rhs = sp.Matrix([n, n_dot])
    return Statement(lhs, "==", rhs, [_orbit(r_t, n, n_dot, extra=(rtd, ndd))], symbolic=False,
                     assumptions=["Kepler target orbit, e <= 0.15 (scenario III: 0.138)"])


def _tr_spacecraft_parts(axis: int, with_residual: bool, law=None):
    """V_j-dot (positive-definite V, frozen theta: d/dt(theta/b) = 0 as in the proof) of C000.law along eq. 30
    with the plant's a_control = C_{L<-c}(q_cL) F_body / m_c (eq. 87; F_body is the law's output)."""
    ctrl, M, tau, F, rates, dg, sig, mu = law or _law()
    k, xc = ctrl.k, ctrl.xc
    ax = AXES[axis]
    r, v, n, n_dot, r_t = M["r"], M["v"], M["n"], M["n_dot"], M["r_t"]
    m = sp.Symbol("m_c", positive=True)
    a_d = sp.Matrix(_real("a_d1:4"))
    # the plant's C_{L<-c}(q_cL), written quat_to_dcm(q)/|q|^4: equal on the unit sphere (where the domain draws
    # q_cL), and quat_to_dcm(q) quat_to_dcm(q)^T = |q|^4 I holds as polynomials, so no Groebner step is needed
    q_cL = M["q_cL"]
    C_Lc = quat_to_dcm(q_cL) / q_cL.dot(q_cL) ** 2
    acc = relative_acceleration(r, v, r_t, n, n_dot, mu, C_Lc * F / m, a_d)
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
    rho = 0
    if with_residual:
        z3 = sp.zeros(3, 1)
        rho = (relative_acceleration(r, v, r_t, n, n_dot, mu, z3, z3)[0]
               - c.translation_model(r, v, n, n_dot, r_c, mu, z3, z3)[0])
    rhs = (-K * sp.sign(s) + a_d[axis] + k["acc_d"][axis] + rho) * S
    dom = [box(r, -100, 100), box(v, -6, 6), _orbit(r_t, n, n_dot), fixed(mu, [MU]), unit_quaternion(M["q_cL"]),
           box(m, 80, 120), box(a_d, -1e-3, 1e-3),
           box(k["lam_pos"], 0.005, 0.1), box(list(k["D_pos"]) + list(k["eps_pos"]), 0.001, 0.1),
           box(k["d_pos"], 0.0, 0.05), box(k["acc_d"], -0.05, 0.05), box(k["r_goal"], -20, 20),
           box(k["gamma_theta"], 1e-9, 1.0), box(k["gamma_h"], 0.1, 10)]
    # every axis' estimates: the body force (and so each LVLH row through the plant's rotation) depends on all
    scales = ((1, 1e-3, 1e-3, 1e-3, 1e17), (1, 1e-3, 1e-3), (1e-3,))
    for j, aj in enumerate(AXES):
        tj = xc[f"theta_{aj}{aj}"]
        tj = [tj] if not isinstance(tj, sp.MatrixBase) else list(tj)
        dom += [box(xc[f"h_hat_{aj}{aj}"], 50, 200)] + [box([t], -sc, sc) for t, sc in zip(tj, scales[j], strict=True)]
    return dict(ctrl=ctrl, M=M, Vdot=Vdot, rhs=rhs, S=S, dom=dom, a_d=a_d, rho=rho, m=m, ax=ax, hh=hh)


def _tr_spacecraft_Vdot(axis: int):
    """= -(D + eps) sign(s) S + a_d S + acc_d S (fixed goal: the desired acceleration is a bias, choice C2)
    [+ rho S for x, rho = eq. 30 - eq. 81 the substitution residual, part of a_dx]."""
    def build():
        P = _tr_spacecraft_parts(axis, axis == 0)
        return Statement(P["Vdot"], "==", P["rhs"], P["dom"], residual_seconds=1.0,
                         assumptions=["eq. 30 with a_control = C_{L<-c}(q_cL) F_body / m_c, |q_cL| = 1",
                                      "theta frozen (d/dt(theta/b) = 0, the proof's premise)"])
    return build


#: scenario III's translation gains (scenarios/000_scenario_III.toml, [controller.c000])
SCENARIO_III = {"lam_pos": 0.03, "D_pos": (0.02,) * 3, "eps_pos": (0.02,) * 3, "d_pos": (0.01,) * 3,
                "acc_d": (-0.02, 0.00333, -0.0333)}
#: bound on the unmodelled LVLH acceleration a_d for the scenario check (differential J2/drag, well below this)
A_D_SCENARIO = 1e-4


def _tr_spacecraft_bound(scenario: bool):
    """V_j-dot of the law along eq. 30 <= -eps_j |S_j| (j = x, y, z).  Implementation: whenever
    |a_dj + rho_j + acc_d,j| <= D_j (the desired acceleration spends the disturbance budget; rho the x
    substitution residual).  Scenario III: its gains and acc_d with |a_dj| <= 1e-4 m/s^2."""
    def build():
        law = _law()
        parts = [_tr_spacecraft_parts(i, i == 0, law) for i in range(3)]
        P = parts[0]
        k = P["ctrl"].k
        a_d = P["a_d"]
        dom = [v for v in P["dom"] if not set(v.symbols) & set(a_d)]
        if scenario:
            g = SCENARIO_III
            dom = [v for v in dom if not set(v.symbols) & {k["lam_pos"], *k["D_pos"], *k["eps_pos"], *k["d_pos"],
                                                             *k["acc_d"]}]
            dom += [fixed(k["lam_pos"], [g["lam_pos"]]), fixed(list(k["D_pos"]), g["D_pos"]),
                    fixed(list(k["eps_pos"]), g["eps_pos"]), fixed(list(k["d_pos"]), g["d_pos"]),
                    fixed(list(k["acc_d"]), g["acc_d"]), box(a_d, -A_D_SCENARIO, A_D_SCENARIO)]
            assumptions = ["scenario III gains and acc_d", f"|a_d,j| <= {A_D_SCENARIO} m/s^2"]
        else:
            zz = sp.Matrix(_real("z_ad1:4"))
            exprs = [k["D_pos"][j] * zz[j] - k["acc_d"][j] - parts[j]["rho"] for j in range(3)]
            deps = sorted(set().union(*[e.free_symbols for e in exprs]) - set(zz), key=str)
            dom += [box(zz, -1, 1), derived(list(a_d), exprs, [*deps, *zz])]
            assumptions = ["|a_d + rho + acc_d| <= D per axis (the desired acceleration spends the budget)"]
        lhs = sp.Matrix([Q["Vdot"] for Q in parts])
        rhs = sp.Matrix([-k["eps_pos"][j] * sp.Abs(parts[j]["S"]) for j in range(3)])
        return Statement(lhs, "<=", rhs, dom, symbolic=False, residual_seconds=1.0, assumptions=assumptions)
    return build


# =====================================================================================================
# Claims
# =====================================================================================================

def _claims() -> list[Claim]:
    C = "c000"
    out = [
        # ---- boundary layer
        Claim("c000.boundary_layer.zero_inside", C, "boundary layer", "abstract", "52 and the text after 57",
              "Notation erratum: eq. 52's formula gives S_aug = 0 inside the layer |s| <= d",
              _bl_zero_inside(True), _bl_zero_inside(False),
              correction="S_aug = s - d sat(s/d) (eq. 52 completed by the text: 0 inside, s - d sign(s) outside)",
              note="Reported once: the formula s - d sign(s) alone is nonzero inside the layer; the text after "
                   "eq. 57 completes it into Slotine's s_Delta. The other claims type the paper's S_aug piecewise."),
        Claim("c000.boundary_layer.sign", C, "boundary layer", "abstract", "52, 84, 106, 119; 68-72",
              "sign(s) S_aug = |S_aug| (used from eq. 68 to eq. 72)", _bl_sign(True), _bl_sign(False),
              note="Holds for the paper's piecewise S_aug and for the implemented sat form."),
        Claim("c000.boundary_layer.derivative", C, "boundary layer", "abstract", "57-59",
              "S_aug dS_aug/ds = S_aug (so S_aug S_aug_dot = S_aug s_dot, the step in eq. 58)", None,
              _bl_derivative,
              note="Holds for the implemented layer (dS/ds = 1 outside, S = 0 inside); the V-dot claims use it."),
        Claim("c000.convergence", C, "boundary layer", "abstract", "72 and the conclusion",
              "Where V-dot = 0 (inside the layer) the tracking error still decreases (e -> 0)",
              lambda: _convergence(True), lambda: _convergence(False),
              correction="ultimate bound: |s| <= d and |e| <= d/lambda_0 (e e_dot <= 0 only for |e| >= d/lambda_0)",
              note="Inside the layer V-dot = 0 and e_dot = s - lambda_0 e: e -> s/lambda_0, not 0. The conclusion's "
                   "'converge to zero asymptotically' holds for S_aug only."),
        # ---- attitude, abstract
        Claim("c000.attitude.V_definite", C, "attitude", "abstract", "57",
              "V_x positive definite in (S_aug, a_tilde, b_tilde)", _att_V_definite(True), _att_V_definite(False),
              correction="V = S^2/2 + b/2 [sum_{i=1..6} a_tilde_i^2/gamma_a + b_tilde^2/gamma_b]",
              note="b = 1/I_cx > 0. Definite in S_aug, not in (e, e_dot): V vanishes on the whole layer |s| <= d."),
        Claim("c000.attitude.Vdot_identity", C, "attitude", "abstract", "55, 58-68",
              "V_x-dot = -(D + eps) sign(s) S_aug + d S_aug under eqs. 55, 66, 67",
              _att_Vdot_identity(True), _att_Vdot_identity(False),
              correction="eq. 55: a_hat_x1 f_x1 (a_hat_x1 -> a_x1/b_x = I_cx adapted by eq. 66 with i = 1) instead "
                         "of a_x1 f_x1; V with i = 1..6 and gains gamma_a, gamma_b",
              note="Printed eq. 55 adds a_x1 f_x1 (rad/s^2) to the torque; the proof (eqs. 62-64) needs "
                   "a_x1 f_x1 / b_x: residual (b_x - 1) f_x1 S_aug (paper's piecewise layer)."),
        Claim("c000.attitude.Vdot_bound", C, "attitude", "abstract", "51, 68-72",
              "V_x-dot <= -eps |S_aug| under |d| <= D (implemented law, V, layer)", None, _att_Vdot_bound,
              note="Implementation only. The printed law fails one step earlier (Vdot_identity); the printed "
                   "layer read alone is the erratum boundary_layer.zero_inside."),
        Claim("c000.attitude.Vdot_negative_definite", C, "attitude", "abstract", "72 (text after it)",
              "V_x-dot is negative definite in (S_aug, a_tilde, b_tilde) (there is kappa > 0; kappa = 1e-9)",
              _att_Vdot_negative_definite, about="paper",
              note="V-dot = (-(D + eps) sign(s) + d) S_aug does not depend on the parameter errors (and is 0 inside "
                   "the layer): negative semidefinite only. S_aug -> 0 follows (Barbalat); the estimates need not "
                   "converge, contrary to the conclusion's 'adaptive parameters converge'."),
        Claim("c000.attitude.time_varying_inertia", C, "attitude", "abstract", "48 ('slowly time-varying'), 57-72, "
              "Fig. 10", "V_x-dot <= -eps |S_aug| with the time-varying I_c of Fig. 10", _att_time_varying,
              about="paper",
              note="The proof takes a/b and 1/b constant and omits -I_c_dot omega_c / I_c: with I_c_dot != 0 V-dot "
                   "has sign-indefinite parameter-drift terms (nonzero at S_aug = 0); the steps of Fig. 10 "
                   "(I_cx 11 -> 22) are jumps of V. The implementation inherits this (no projection/leakage)."),
        # ---- attitude, spacecraft
        Claim("c000.attitude.e_ddot", C, "attitude", "spacecraft", "24, 53-54, 59-60",
              "The surface's derivative is omega_e_dot + lambda_0 e_dot (the proof's e_ddot = omega_e_dot)",
              _e_ddot_printed, _e_ddot_implemented,
              correction="s = omega_e + lambda_0 sgn(q_e4) q_ev and u_1 = -omega_e_dot_d + lambda_0 e_dot with "
                         "e_dot = sgn(q_e4) d/dt q_ev from eq. 24",
              note="For e = q_ev (eq. 54), d^2/dt^2 q_ev = (q_e4 w_dot + q_ev x w_dot)/2 - |w|^2 q_ev/4 != w_dot. "
                   "Corrected: the law's diag s_att along eq. 24 typed by hand."),
        Claim("c000.attitude.sliding_decay", C, "attitude", "spacecraft", "53 (s = 0)",
              "On s = 0 the quaternion error decays: d/dt |e|^2 <= -lambda_0 |q_e4| |e|^2", None, _sliding_decay,
              note="Needs e = sgn(q_e4) q_ev (choice C1); with e = q_ev the error grows while q_e4 < 0 (unwinding)."),
        Claim("c000.attitude.table1", C, "attitude", "spacecraft", "26-29, 48-50, Table 1",
              "Eq. 49 (as printed) / Table 1 is omega_e_dot of the two rigid bodies (principal axes)",
              _table1_vs_rigid(True), _table1_vs_rigid(False),
              correction="x row from eq. 61 (49-a is a copy of 49-b); I_cy^-1 T_cy for 49-b's I_ty^-1 T_cy; target "
                         "torque sum_m c_jm M_tm / I_tm for (sum_m c_jm M_tm) I_tj^-1",
              note="Eq. 49 typed as printed with c_jm the entries of C_t^c (the sentence 'entries of (C_t^c)^-1' "
                   "follows eq. 50, for delta). Fails on the printed slips: duplicated 49-a, I_ty^-1 T_cy in 49-b, "
                   "I_tj^-1 on the target torque."),
        Claim("c000.attitude.principal_axes", C, "attitude", "spacecraft", "49, 51 vs 6, 10, 26-29",
              "Eq. 49 (principal axes) + eq. 51: the products of inertia and external torques fit in D_att",
              _principal_axes_paper, _principal_axes_bound,
              correction=f"joint budget: products-of-inertia residual (<= ~0.0023 rad/s^2) + external torques "
                         f"|M_c| <= {M_C_BUDGET} N m, |M_t| <= {M_T_BUDGET} N m within D_att = 0.0075 rad/s^2",
              note="Eq. 49 drops the products of inertia of I_c and I_t (-0.09..-0.4, -135..-154 kg m^2); the "
                   "implementation counts them in d, sharing D_att with the external torques."),
        Claim("c000.attitude.disturbance_paper", C, "attitude", "spacecraft", "4, 5, 49, 51",
              "|d_j| <= D_j with the paper's disturbances (eq. 4 GG, eq. 5 at 3 sigma) and inertia residual",
              _disturbance_paper, about="paper",
              note="Eq. 5's M_r = 0.3 randn is unbounded (contradicts eq. 51's bounded d); at 1 sigma |M_r/I_cx| "
                   "~ 0.027 rad/s^2 >> D_att = 0.0075 (at 3 sigma ~0.08). Not satisfiable by any D within the "
                   "wheels' 0.1 N m."),
        Claim("c000.attitude.spacecraft_Vdot", C, "attitude", "spacecraft", "24, 26-29, 53-68",
              "V_j-dot of the full law along the spacecraft equations = -(D+eps) sign(s) S + d S + wdot_d S",
              None, _att_spacecraft_Vdot,
              note="Implementation only (with the printed e = q_ev the step fails already at attitude.e_ddot). "
                   "The wdot_d S term: the goal is fixed (choice C2), so wdot_d is a bias the bound must absorb."),
        Claim("c000.attitude.spacecraft_Vdot_bound", C, "attitude", "spacecraft", "51, 56, 68-72",
              "V_j-dot of the full law <= -eps_j |S_j| when |d_j + wdot_d,j| <= D_j", None,
              _att_spacecraft_Vdot_bound,
              note="The desired angular acceleration enters V-dot like a disturbance (fixed goal): it spends D. "
                   "Scenarios set wdot_d = 0."),
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
                  "With a positive-definite V the implemented adaptation laws cancel the parameter errors",
                  None, _tr_adaptation_sign(i),
                  note="Implementation only: theta_hat_dot = +gamma_theta phi S_aug" +
                       (" (eq. 115 unchanged)" if i == 1 else "") + ". The printed -phi S_aug (from the "
                       "indefinite V, see V_definite) would double the parameter-error terms of a positive-definite "
                       "V instead of cancelling them."),
            Claim(f"{pre}.Vdot_bound", C, part, "abstract", eB,
                  "V-dot <= -eps |S_aug| under the disturbance bound", _tr_Vdot_bound(i, True),
                  _tr_Vdot_bound(i, False),
                  correction=("bound |a_dx| <= D_xx (the implementation groups -mu/r_c^2 into the regressor) instead "
                              "of eq. 104's |-mu/r_c^2 + A_dx| <= D_xx" if i == 0 else ""),
                  note=("Eq. 104 with A_dx the upper bound of |a_dx| allows D_xx = mu/r_c^2 - A_dx; at a_dx = -A_dx "
                        "V-dot exceeds -eps|S| by (2 A_dx - margin)|S| even outside the layer (needs "
                        "D >= mu/r_c^2 + A_dx)." if i == 0 else
                        "With the paper's piecewise S_aug the printed argument holds.")),
        ]
        if i == 0:
            out += [
                Claim(f"{pre}.form_eq30", C, part, "spacecraft", "30, 81-83",
                      "Eq. 81 (r_t = r_c - |r_e|) is eq. 30's x row", _form(0, True), _x_substitution_bound,
                      correction="the substitution residual is treated as part of a_dx: |eq. 81 - eq. 30| "
                                 "<= 1.05 * 3 mu (|r_e| - x)/r_t^3 (< 3e-4 m/s^2 within 100 m in LEO)",
                      note="r_t = r_c - |r_e| is exact only for a radial offset (r_e along +X_L)."),
                Claim(f"{pre}.regressors", C, part, "spacecraft", "81-83, 86",
                      "The implemented regressors reproduce eq. 81 as printed (-mu/r_c^2 grouped into phi_xx5)", None,
                      _x_regressors),
                Claim(f"{pre}.spacecraft_Vdot", C, part, "spacecraft", "30, 84-101",
                      "V-dot of the full law along eq. 30 = -(D+eps) sign(s) S + (a_d + rho + acc_d) S",
                      None, _tr_spacecraft_Vdot(0),
                      note="Implementation only; rho = eq. 30 - eq. 81 (the substitution residual, part of a_dx). "
                           "Frozen theta (the proof's premise, see translation.theta_constant); the plant rotates "
                           "the law's body force back with C_{L<-c}(q_cL) (eq. 87)."),
            ]
        else:
            out += [
                Claim(f"{pre}.form_eq30", C, part, "spacecraft", "30, " + eF,
                      f"The printed / implemented per-axis form is eq. 30's {ax} row", _form(i, True), _form(i, False)),
                Claim(f"{pre}.spacecraft_Vdot", C, part, "spacecraft", "30, " + eId,
                      "V-dot of the full law along eq. 30 = -(D+eps) sign(s) S + a_d S + acc_d S", None,
                      _tr_spacecraft_Vdot(i),
                      note="Frozen theta (the proof's premise); the acc_d S term: fixed goal (choice C2)."),
            ]
    out += [
        Claim("c000.translation.spacecraft_Vdot_bound", C, "translation", "spacecraft", "30, 86-88, 102-104, 118, 129",
              "V_j-dot of the full law <= -eps_j |S_j| when |a_dj + rho_j + acc_d,j| <= D_j", None,
              _tr_spacecraft_bound(False),
              note="The desired acceleration is a bias of the fixed-goal loop: it spends the disturbance budget D."),
        Claim("c000.translation.spacecraft_Vdot_bound_scenario_III", C, "translation", "spacecraft",
              "86-88, 104, 118, 129; scenario III",
              "Scenario III's gains and acc_d keep V_j-dot <= -eps_j |S_j| (|a_d| <= 1e-4 m/s^2)", None,
              _tr_spacecraft_bound(True), about="paper",
              note="acc_d = [-0.02, 0.00333, -0.0333] m/s^2 with D = eps = 0.02: |acc_d_z| > D, so on one side of "
                   "the layer V-dot = -(D + eps - |acc_d| -/+ a_d)|S| only (z: -0.0067|S|); x (|acc_d_x| = D) fails "
                   "by |a_dx|. Reaching still holds for z (D + eps > |acc_d|), not with margin eps."),
        Claim("c000.translation.shared_h_hat", C, "translation", "abstract", "89, 101, 109, 116, 123, 128",
              "One h_hat with three laws (eqs. 101, 116, 128): the summed V-dot is the sum of eqs. 102, 117, 129",
              _shared_h_hat, about="paper",
              note="With one h_hat (h = m_c for all axes) the summed V has one (h_hat - h)^2 term and h_hat one law; "
                   "the other two axes' b (h_hat - h) h_hat_dot terms stay. The implementation keeps one h_hat "
                   "per axis."),
        Claim("c000.translation.theta_constant", C, "translation", "spacecraft", "81, 89-90, 105, 121, Fig. 9",
              "The estimated parameters theta/b are constant along the motion (V-dot has no d/dt(theta/b))",
              _theta_constant, about="paper",
              note="On scenario III's elliptic orbit n, n_dot, mu/r_c^3 move, and m_c varies (Fig. 9): "
                   "d/dt(theta/b) != 0. The neglected V-dot term is multiplied by 1/gamma_theta = 1e8 in the "
                   "implementation (slow drift, not in V-dot)."),
        Claim("c000.translation.mean_motion", C, "translation", "spacecraft", "9, 35 vs 30",
              "n = sqrt(mu/r^3) (eq. 9) and eq. 35's n_dot are the LVLH rate eq. 30 needs", _mean_motion,
              about="paper",
              note="On an elliptic orbit the LVLH rate is h/r^2 (at perigee sqrt(mu (1 + e)/r_p^3)): at scenario "
                   "III's perigee sqrt(mu/r^3) = 1.131e-3 vs 1.207e-3 rad/s (-6.3 %). The implementation takes "
                   "n, n_dot from the plant's LVLH frame (meas)."),
    ]
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


def _transpose_rotation(out, q_cL, F_L):
    return quat_to_dcm(q_cL) * F_L


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
    Mutation("c000: LVLH->body force rotation transposed (eq. 87)", c, "lvlh_to_body_force",
             replace_output(_transpose_rotation), tuple(_t(ax, "spacecraft_Vdot") for ax in AXES)),
]
