"""001, Proposition 2: the pose law's closed loop on the abstract layer (any potential V_p with gradient g, eqs.
53-64) and the composed chain with the ESO."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c001 as c
from ...physics.rotations import cross, dq_conj, dq_mul
from ...physics.special import Step
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
)
from ..domains import (
    ball,
    box,
    custom,
    derived,
    fixed,
    qmul,
    rotate,
    unit_rows,
)
from .common import (
    APF,
    DELTA,
    ECC,
    ESO_GAINS,
    F_MAX,
    INERTIA,
    K_D,
    K_P,
    KAPPA1,
    KAPPA2,
    MASS,
    MU,
    P2,
    R_S,
    R_T,
    RHO_MAX,
    SEMI_MAJOR,
    TAU_MAX,
    THETA,
    VEC,
    Z_N,
    ZERO8,
    _admissible_draw,
    _admissible_var,
    _desired_dq,
    _nostep,
    _paper_apf,
    _pv,
    _six,
    _unit_dq_var,
)
from .eso import N_BOUND, _eig2, _Eso, _eta_symbols, _lyap_P, _real_v1dot

claim = claim_factory(__name__)

# --------------------------------------------------------------------------- Proposition 2: the closed loop

class _Loop:
    """Closed loop of Proposition 2: eq. 15 and eq. 21 driven by eq. 57, V of eq. 58.

    ``apf=False`` (abstract layer): ``V_p`` is an undefined function of q_S/T whose gradient is the free
    8-vector ``g`` -- the law is built with ``g``, V-dot's ``dV_p/dq`` is replaced by ``g``.
    ``apf=True`` (spacecraft layer): ``V_p`` is eq. 53 (``c.apf``) of ``Delta q(q)`` (eq. 50-51),
    ``beta_FOV(q)`` (eq. 46), ``beta_CA(q)`` (eq. 48), differentiated by the chain rule with the code's
    functions; the law's gradient is the coded eqs. 54-55 with ``fov_eps = eps`` (0: exact gradient;
    None: the symbol ``epsilon``).  ``applied``: a map from eq. 57's output to the applied dual force.
    """

    def __init__(self, apf: bool = False, eps=0, applied=None):
        self.apf = apf
        self.q = sp.Matrix(sp.symbols("q_1:9", real=True))
        self.W, self.w6 = _pv("omega")            # omega_S/T^S (real: rad/s, dual: m/s)
        self.WSI, self.wsi6 = _pv("omegaSI")      # omega_S/I^S (measured; inertial velocity in S)
        self.FG, self.fg6 = _pv("fG")             # f_G^S (eq. 18), any value
        self.DH, self.dh6 = _pv("dhat")           # ESO estimate d_hat^S
        self.DD, self.dd6 = _pv("Deltad")         # Delta d = d^S - d_hat^S
        self.m = sp.Symbol("m", positive=True)
        self.Mi = sp.Matrix(sp.symbols("M_1:4", positive=True))
        self.k_p, self.k_d, self.k_v = sp.symbols("k_p k_d k_v", positive=True)
        self.V_d, self.Vd_dot = sp.symbols("V_d Vdot_d", real=True)
        self.J = c.dual_inertia(self.m, self.Mi)
        q = self.q
        if apf:
            self.qD = sp.Matrix(sp.symbols("qD_1:9", real=True))
            self.e = sp.Matrix(sp.symbols("Deltaq_1:9", real=True))
            self.k_a, self.k_r = sp.symbols("k_a k_r", positive=True)
            self.theta, self.z_N, self.R_S, self.R_T = sp.symbols("theta z_N R_S R_T", positive=True)
            self.eps = sp.Symbol("epsilon", positive=True)
            self.bF, self.bC = sp.symbols("beta_FOV beta_CA", positive=True)
            self.K_u = c.camera_axis_matrix(sp.Matrix([0, 0, 1]))
            self.z_Np = c.fov_vertex_offset(self.z_N, self.R_T, self.theta)
            self.dq_err = c.pose_error_offset(c.pose_error(self.qD, q))                   # eqs. 50-51
            self.bF_q = _nostep(c.beta_fov_dq(q, self.K_u, self.theta, self.z_Np))     # eq. 46
            self.bC_q = c.beta_ca_dq(q, self.R_S, self.R_T)                                # eq. 48
            E = [sp.Function(f"DQ_{i + 1}")(*q) for i in range(8)]
            BF, BC = sp.Function("B_FOV")(*q), sp.Function("B_CA")(*q)
            Vp = c.apf(sp.Matrix(E), self.k_a, self.k_r, BF, BC)                          # eq. 53
            self._chain = {BF: self.bF, BC: self.bC, **dict(zip(E, self.e, strict=True))}
            self._dchain = {}
            bF_full = c.beta_fov_dq(q, self.K_u, self.theta, self.z_Np)
            for qi in q:
                self._dchain[sp.Derivative(BF, qi)] = _nostep(sp.diff(bF_full, qi))
                self._dchain[sp.Derivative(BC, qi)] = sp.diff(self.bC_q, qi)
                for Ei, di in zip(E, self.dq_err, strict=True):
                    self._dchain[sp.Derivative(Ei, qi)] = sp.diff(di, qi)
            eps = self.eps if eps is None else eps
            g = c.apf_gradient(self.e, self.qD, self.k_a, self.k_r, self.bF, self.bC,
                               _nostep(c.grad_beta_fov(q, self.K_u, self.theta, eps)), c.grad_beta_ca(q))
        else:
            self.g = sp.Matrix(sp.symbols("g_1:9", real=True))
            Vp = sp.Function("V_p")(*q)
            self._chain = {}
            self._dchain = {sp.Derivative(Vp, qi): gi for qi, gi in zip(q, self.g, strict=True)}
            g = self.g
        self.grad = g
        self.WTI = c.target_inertial_dual_velocity(self.WSI, self.W)                     # omega_T/I^S
        self.fC = c.control_dual_force(q, g, self.W, self.WTI, self.J, self.FG, self.DH,  # eq. 57
                                       self.k_p, self.k_d)
        f_applied = self.fC if applied is None else applied(self.fC)
        self.f_applied = f_applied
        self.wdot = c.relative_dual_acceleration_lumped(self.J, self.FG, f_applied, self.WSI,  # eq. 21
                                                        self.W, self.DH + self.DD)
        self.qdot = c.pose_rate(q, self.W)                                              # eq. 15
        self.kin = c.circle(self.W, c.dq_swap(c.J_E_times(self.J, self.W)))            # omega o (EJE omega)
        self.V = 2 * self.k_p * Vp + self.kin / 2 + self.k_v * self.V_d                # eq. 58
        states = list(q) + list(self.w6) + [self.V_d]
        rates = list(self.qdot) + list(_six(self.wdot)) + [self.Vd_dot]
        Vdot = lie_derivative(self.V, states, rates)
        self.Vdot = Vdot.xreplace(self._dchain).xreplace(self._chain)
        w, v = self.w6[0:3, :], self.w6[3:6, :]
        dw, dv = self.dd6[0:3, :], self.dd6[3:6, :]
        self.ww = (w.T * w)[0] + (v.T * v)[0]                                           # omega o omega
        self.wJd = (w.T * sp.diag(*self.Mi) * dw)[0] + self.m * (v.T * dv)[0]            # omega o (EJE Dd)
        # eq. 63, second line (as printed, signs restored)
        self.eq63 = -self.k_d * self.ww + self.wJd + self.k_v * self.Vd_dot

    # ---- domains
    def domain(self):
        """Ranges covering 001's scenario (sec. 7): 7.6 km/s inertial velocity, rates ~0.1 deg/s,
        gravity force ~520 N, ESO estimates and errors of the size of d^S (~10 m/s^2 each part)."""
        out = [box(self.w6[0:3, :], -0.01, 0.01), box(self.w6[3:6, :], -1, 1),
               box(self.wsi6[0:3, :], -0.01, 0.01), box(self.wsi6[3:6, :], -8000, 8000),
               box(self.fg6[0:3, :], -600, 600), box(self.fg6[3:6, :], -1e-3, 1e-3),
               box(self.dh6, -10, 10), box(self.dd6, -10, 10),
               box(self.m, 30, 100), box(self.Mi, 5, 30),
               box(self.k_p, 1e-3, 1), box(self.k_d, 0.1, 10), box(self.k_v, 0.1, 10),
               box(self.V_d, 0, 10), box(self.Vd_dot, -10, 10)]
        if self.apf:
            qD = _desired_dq()
            out = [_admissible_var(self.q), fixed(self.qD, qD),
                   derived(self.e, self.dq_err, list(self.q) + list(self.qD)),
                   fixed([self.theta, self.z_N, self.R_S, self.R_T], [THETA, Z_N, R_S, R_T]),
                   derived(self.bF, self.bF_q, list(self.q) + [self.theta, self.z_N, self.R_T]),
                   derived(self.bC, self.bC_q, list(self.q) + [self.R_S, self.R_T]),
                   box(self.k_a, 0.1, 1), box(self.k_r, 1e-6, 1e-3), box(self.eps, 1e-4, 1e-2)] + out
        else:
            out = [_unit_dq_var(self.q), box(self.g, -100, 100)] + out
        return out


def _hand_E(a):
    """E a: swap real and dual parts (hand-typed, eq. 16 text)."""
    return sp.Matrix(list(a[4:8]) + list(a[0:4]))


def _hand_vec(a):
    return sp.Matrix([a[0], a[1], a[2], 0, a[4], a[5], a[6], 0])


def _hand_J_E(L: _Loop, a):
    """J_E a = J E a with J = diag(m I3, 1, M, 1) (eq. 16), typed out."""
    Ea = _hand_E(a)
    Mi = L.Mi
    return sp.Matrix([L.m * Ea[0], L.m * Ea[1], L.m * Ea[2], Ea[3],
                      Mi[0] * Ea[4], Mi[1] * Ea[5], Mi[2] * Ea[6], Ea[7]])


def _hand_cross(a, b):
    """Dual cross product of pure dual vectors: a_r x b_r + eps (a_r x b_d + a_d x b_r), in full."""
    ar, ad = sp.Matrix(a[0:3]), sp.Matrix(a[4:7])
    br, bd = sp.Matrix(b[0:3]), sp.Matrix(b[4:7])
    x, y = cross(ar, br), cross(ar, bd) + cross(ad, br)
    return sp.Matrix([x[0], x[1], x[2], 0, y[0], y[1], y[2], 0])


def _o(a, b):
    """Circle product a o b (8-vector dot product), typed out."""
    return sum((ai * bi for ai, bi in zip(a, b, strict=True)), sp.S.Zero)


# ---- Proposition 2 statements

def _v_definite() -> Statement:
    """Eq. 58 with eq. 53: V = 2 k_p V_p + omega o (EJE omega)/2 + k_v Dd^T D Dd, D = diag(D_i) > 0."""
    L = _Loop()
    e = sp.Matrix(sp.symbols("Deltaq_1:9", real=True))
    k_a, k_r = sp.symbols("k_a k_r", positive=True)
    bF, bC = sp.symbols("beta_FOV beta_CA", positive=True)
    D = sp.symbols("D_1:7", positive=True)
    Vp = c.apf(e, k_a, k_r, bF, bC)
    Vd = sum((Di * x**2 for Di, x in zip(D, L.dd6, strict=True)), sp.S.Zero)
    V = 2 * L.k_p * Vp + L.kin / 2 + L.k_v * Vd
    dom = [box(e[0:4, :], -2, 2), box(e[4:8, :], -150, 150), box([k_a, k_r], 1e-6, 1),
           box([bF, bC], 1e-3, 1e4), box(D, 0.01, 100), box(L.w6, -1, 1), box(L.dd6, -10, 10),
           box(L.m, 30, 100), box(L.Mi, 5, 30), box([L.k_p, L.k_v], 1e-3, 10)]
    return Statement(V, ">", 0, dom, positive=[k_a, k_r, bF, bC, *D, L.m, *L.Mi, L.k_p, L.k_v],
                     zero_at=list(e) + list(L.w6) + list(L.dd6),
                     assumptions=["beta_FOV > 0, beta_CA > 0 (admissible pose)", "k_p, k_a, k_r, k_v > 0",
                                  "D symmetric positive definite (diagonal here)"])


def _eq61() -> Statement:
    """Eq. 61: k_p grad V_p o (q omega) + (E omega) o (-k_p vec(q* (E grad V_p))) = 0: the proportional
    term of eq. 57 (the law with k_d, omega_T/I, f_G, d_hat set to zero) does no work."""
    L = _Loop()
    f_prop = c.control_dual_force(L.q, L.g, L.W, ZERO8, L.J, ZERO8, ZERO8, L.k_p, 0)
    lhs = 2 * L.k_p * c.circle(L.g, c.pose_rate(L.q, L.W)) + c.circle(_hand_E(L.W), f_prop)
    return Statement(lhs, "==", 0, L.domain(), assumptions=["omega pure (zero scalar parts)"])


def _eq62() -> Statement:
    """Eq. 62: (E omega) o (omega_T/I x (J_E omega_T/I) - omega_S/I x (J_E omega_S/I)
    + J_E (omega x omega_S/I)) = 0, the first term from eq. 57, the others from eq. 21."""
    L = _Loop()
    f_gyro = c.control_dual_force(L.q, ZERO8, L.W, L.WTI, L.J, ZERO8, ZERO8, 0, 0)
    acc = c.relative_dual_acceleration_lumped(L.J, ZERO8, f_gyro, L.WSI, L.W, ZERO8)
    lhs = c.circle(L.W, c.dq_swap(c.J_E_times(L.J, acc)))      # omega o (EJE omega_dot) = (E omega) o (J_E ..)
    return Statement(lhs, "==", 0, L.domain(), assumptions=["omega_T/I = omega_S/I - omega_S/T (eq. 14)"])


def _vdot_eq60() -> Statement:
    """Eqs. 59-60: V-dot along eqs. 15, 21 under eq. 57 equals the printed eq. 60 (typed out)."""
    L = _Loop()
    W, WSI, WTI, q, g = L.W, L.WSI, L.WTI, L.q, L.g
    EW = _hand_E(W)
    inner = (-L.k_p * _hand_vec(dq_mul(dq_conj(q), _hand_E(g))) - L.k_d * EW
             + _hand_cross(WTI, _hand_J_E(L, WTI)) - _hand_cross(WSI, _hand_J_E(L, WSI))
             + _hand_J_E(L, _hand_cross(W, WSI)) + _hand_J_E(L, L.DD))
    rhs = L.k_p * _o(g, dq_mul(q, W)) + _o(EW, inner) + L.k_v * L.Vd_dot
    return Statement(L.Vdot, "==", rhs, L.domain(), assumptions=["g = grad V_p", "Delta d = d^S - d_hat^S"])


def _vdot_identity() -> Statement:
    """Eqs. 59-63: V-dot = -k_d omega o omega + omega o (EJE Delta d) + k_v V_d-dot (eq. 63, 2nd line)."""
    L = _Loop()
    return Statement(L.Vdot, "==", L.eq63, L.domain(), assumptions=["g = grad V_p", "Delta d = d^S - d_hat^S"])


def _eq63_printed() -> Statement:
    """Eq. 63, first line as printed: (E omega) o (-k_v (E omega) + J_E Delta d) + k_p V_d-dot."""
    L = _Loop()
    EW = _hand_E(L.W)
    rhs = _o(EW, -L.k_v * EW + _hand_J_E(L, L.DD)) + L.k_p * L.Vd_dot
    return Statement(L.Vdot, "==", rhs, L.domain())


def _eq63_first_line_corrected() -> Statement:
    L = _Loop()
    EW = _hand_E(L.W)
    rhs = _o(EW, -L.k_d * EW + _hand_J_E(L, L.DD)) + L.k_v * L.Vd_dot
    return Statement(L.Vdot, "==", rhs, L.domain())


def _h_definite() -> Statement:
    """Eq. 64: -(-k_d omega o omega + omega o (EJE Dd) - k_v Dd o (D Dd)) = X^T H X > 0 for the paper's
    k_d = 2 and J, with k_v above the threshold max_i J_i^2 / (4 k_d D_i) (D diagonal)."""
    L = _Loop()
    D = sp.symbols("D_1:7", positive=True)
    DDd = c.pure_dq(sp.Matrix([D[i] * L.dd6[i] for i in range(3)]),
                    sp.Matrix([D[i] * L.dd6[i] for i in range(3, 6)]))
    wJd = c.circle(L.W, c.dq_swap(c.J_E_times(L.J, L.DD)))
    expr = L.k_d * c.circle(L.W, L.W) - wJd + L.k_v * c.circle(L.DD, DDd)
    J_diag = np.array([INERTIA[0], INERTIA[1], INERTIA[2], MASS, MASS, MASS])   # EJE = diag(M, m I)

    def draw_kv(z, env):
        thr = np.max(J_diag[None, :] ** 2 / (4 * K_D * np.column_stack([env[d] for d in D])), axis=1)
        return (thr * (1.0 + 1e-6 + 9.0 * (z[:, 0] + 1.0) / 2))[:, None]

    dom = [box(D, 0.01, 100), fixed(L.k_d, [K_D]), fixed(L.m, [MASS]), fixed(L.Mi, INERTIA),
           custom([L.k_v], 1, draw_kv, "k_v > max_i J_i^2 / (4 k_d D_i)"),
           box(L.w6, -1, 1), box(L.dd6, -1, 1)]
    return Statement(expr, ">", 0, dom, symbolic=False, zero_at=list(L.w6) + list(L.dd6),
                     assumptions=["k_d = 2, m = 60 kg, M = diag(15.6, 10.8, 11.5) (sec. 7)",
                                  "k_v D_i > J_i^2 / (4 k_d) for every i (the choice of eq. 64)"])


def _saturated_impl() -> Statement:
    """rpo's clipped law: V-dot = eq. 63 + (E omega) o (sat(f_C) - f_C), sat = ``c.applied_dual_force``."""
    L = _Loop(applied=lambda f: c.applied_dual_force(f, F_MAX, TAU_MAX))
    def hv(e):
        return e.replace(Step, lambda a: sp.Heaviside(a, 1))
    F, tau = c.dq_parts3(L.fC)
    clipped = c.dual_force(c.saturate(F, F_MAX), c.saturate(tau, TAU_MAX))       # per-axis clip, sec. 7
    rhs = L.eq63 + c.circle(_hand_E(L.W), clipped - L.fC)
    return Statement(hv(L.Vdot), "==", hv(rhs), L.domain(),
                     assumptions=["applied dual force = eq. 57 clipped per axis (sec. 7 limits)",
                                  "Delta d = d^S - d_hat^S"])


def _orbit_var(L: _Loop):
    """omega_S/I^S, f_G^S and d_hat^S from one consistent orbit state: the target on a Table 1 orbit (any
    point, any attitude, |omega_T/I| <= 0.01 rad/s, torque-free), the chaser at the drawn pose q_S/T with the
    drawn omega_S/T; omega_S/I = omega_S/T + q* omega_T/I^T q (eq. 14), f_G = eq. 18 at the chaser's
    position, d_hat = d^S - Delta d with d^S = -q* omega_T/I-dot^T q (eq. 21 text, f_D = 0: the target's
    orbital acceleration, which f_G's chaser gravity nearly cancels)."""
    WT = sp.Matrix(sp.symbols("_wt1:9", real=True))
    f_body = sp.lambdify([*L.q, *WT], list(c.dq_to_body(L.q, WT)), "numpy")
    rS = sp.Matrix(sp.symbols("_r1:4", real=True))
    m_, M_ = sp.Symbol("_m"), sp.Matrix(sp.symbols("_M1:4"))
    f_grav = sp.lambdify([m_, *M_, *rS], list(c.gravity_dual_force(MU, m_, sp.diag(*M_), rS)), "numpy")
    syms = list(L.wsi6) + list(L.fg6) + list(L.dh6)

    def cols(out, n):
        return np.array([np.broadcast_to(np.asarray(o, dtype=float), (n,)) for o in out]).T

    def pure8(a, b):
        z = np.zeros((len(a), 1))
        return np.hstack([a, z, b, z])

    def draw(zz, env):
        n = len(zz)
        Q = np.column_stack([env[s] for s in L.q])
        qr, qd = Q[:, :4], Q[:, 4:]
        r_T = 2 * qmul(qd, qr * np.array([-1.0, -1.0, -1.0, 1.0]))[:, :3]        # eq. 7, r^T
        q_TI = unit_rows(zz[:, 0:4])
        u = unit_rows(zz[:, 4:7])
        h = unit_rows(np.cross(u, unit_rows(zz[:, 7:10])))                     # along-track direction
        rad = SEMI_MAJOR * (1 + ECC * zz[:, 10])
        R_t = rad[:, None] * u
        V_t = np.sqrt(MU * (2 / rad - 1 / SEMI_MAJOR))[:, None] * h
        w_t = 0.01 * zz[:, 11:14]
        conj = np.array([-1.0, -1.0, -1.0, 1.0])
        V_tT = rotate(q_TI * conj, V_t)
        A_tT = rotate(q_TI * conj, -MU * R_t / np.linalg.norm(R_t, axis=1, keepdims=True) ** 3)
        wT = pure8(w_t, V_tT)
        wdT = pure8(np.zeros((n, 3)), A_tT - np.cross(w_t, V_tT))
        W = np.column_stack([env[s] for s in L.w6])
        body = cols(f_body(*Q.T, *wT.T), n)
        wsi = pure8(W[:, :3], W[:, 3:]) + body
        R_S = R_t + rotate(q_TI, r_T)
        q_SI = qmul(q_TI, qr)
        r_SI_S = rotate(q_SI * conj, R_S)
        fg = cols(f_grav(env[L.m], *[env[s] for s in L.Mi], *r_SI_S.T), n)
        dS = -cols(f_body(*Q.T, *wdT.T), n)
        DD = np.column_stack([env[s] for s in L.dd6])
        dh = dS[:, VEC] - DD
        return np.hstack([wsi[:, VEC], fg[:, VEC], dh])
    return custom(syms, 14, draw, "consistent orbit state (Table 1 orbit, |omega_T/I| <= 0.01 rad/s)")


def _saturated_identity() -> Statement:
    """Eq. 63 when the applied dual force is eq. 57 clipped to the sec. 7 limits (as rpo applies it), on
    consistent orbit states with the paper's gains."""
    L = _Loop(applied=lambda f: c.applied_dual_force(f, F_MAX, TAU_MAX))
    lhs = L.Vdot.replace(Step, lambda a: sp.Heaviside(a, 1))
    _, _, grad = _paper_apf(L.q)                                   # rpo's gradient, sec. 7 APF data
    dom = [_admissible_var(L.q), derived(L.g, grad, list(L.q)), box(L.w6[0:3, :], -0.01, 0.01),
           box(L.w6[3:6, :], -1, 1),
           box(L.dd6[0:3, :], -1e-4, 1e-4), box(L.dd6[3:6, :], -1e-2, 1e-2),
           fixed(L.m, [MASS]), fixed(L.Mi, INERTIA), fixed([L.k_p, L.k_d], [K_P, K_D]), box(L.k_v, 0.1, 10),
           box(L.V_d, 0, 10), box(L.Vd_dot, -10, 10), _orbit_var(L)]
    return Statement(lhs, "==", L.eq63, dom, symbolic=False,
                     assumptions=["|F_i| <= 0.75 N, |tau_i| <= 2 mN m (sec. 7), applied to eq. 57's output",
                                  "k_p, k_d, m, M of sec. 7; |Delta d| <= 1e-4 rad/s^2, 1e-2 m/s^2",
                                  "admissible poses, g = rpo's APF gradient (eqs. 54-55, sec. 7 data)"])


def _equilibrium_acc() -> Statement:
    """End of the proof of Prop. 2: at omega = 0, Delta d = 0 the closed loop (eq. 21 under eq. 57) gives
    omega-dot = -k_p J_E^-1 vec(q* (E grad V_p)), so omega stays 0 only where that vanishes."""
    L = _Loop()
    at = {**{s: 0 for s in L.w6}, **{s: 0 for s in L.dd6}}
    lhs = L.wdot.xreplace(at)
    f = -L.k_p * _hand_vec(dq_mul(dq_conj(L.q), _hand_E(L.g)))
    Jd = [L.m, L.m, L.m, 1, L.Mi[0], L.Mi[1], L.Mi[2], 1]
    rhs = _hand_E(sp.Matrix([f[i] / Jd[i] for i in range(8)]))                # J_E^-1 f = E J^-1 f
    return Statement(lhs, "==", rhs, L.domain(), assumptions=["omega_S/T = 0, Delta d = 0"])


def _boundary_draw(z, env):
    """Poses on the constraint boundary: beta_FOV = 0 (off-axis fraction 1, |r| in [R_S + R_T, 300 m]) or
    beta_CA = 0 (|r| = R_S + R_T, inside the cone)."""
    fov = _admissible_draw(1.0 - 1e-12, 1.0 - 1e-12, R_S + R_T, RHO_MAX)(z[:, :7], env)
    ca = _admissible_draw(1e-3, 1.0 - 1e-9, R_S + R_T, R_S + R_T)(z[:, :7], env)
    return np.where(z[:, 7:8] < 0.0, fov, ca)


BARRIER_MIN = 0.1   # lower bound claimed for Delta q o Delta q on the constraint boundary


def _barrier() -> Statement:
    """After eq. 64: V_p bounded => beta > 0 needs Delta q o Delta q >= c > 0 where beta_FOV = 0 or beta_CA = 0
    (the repulsive term k_r Dq o Dq / beta then blows up at the boundary)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    _, dq_err, _ = _paper_apf(q)
    return Statement(c.circle(dq_err, dq_err), ">=", BARRIER_MIN,
                     [custom(list(q), 8, _boundary_draw, "poses on beta_FOV = 0 or beta_CA = 0")], symbolic=False,
                     trials=2000,
                     assumptions=["q_D/T, r_D/T of sec. 7", "V non-increasing along the loop (eq. 64) -- broken "
                                  "by rpo's fov_eps term (c001.pose.Vdot_apf) and by saturation "
                                  "(c001.pose.saturation_impl)"])


def _vd_decay(corrected: bool) -> Statement:
    """Text before eq. 58 (used in eq. 63): a V_d of Delta d with V_d-dot <= -V_d along the ESO."""
    E = _Eso(N_BOUND)
    C = sp.Symbol("C", nonnegative=True)
    if not corrected:
        eta1, eta2 = _eta_symbols(E.n)
        base = [box(eta1, -10, 10), box(eta2, -10, 10), *E.signal_domain(), *E.gains_domain()]
        D = sp.symbols(f"D_1:{E.n + 1}", positive=True)
        Vd = sum((Di * e**2 for Di, e in zip(D, eta2, strict=True)), sp.S.Zero)
        _, r2 = E.scaled_rates(eta1, eta2)
        Vd_dot = sum((sp.diff(Vd, e) * r / E.delta for e, r in zip(eta2, r2, strict=True)), sp.S.Zero)
        return Statement(Vd_dot, "<=", -Vd, base + [box(D, 0.01, 100), box(C, 0, 10), ball(E.alpha, C)],
                         symbolic=False, assumptions=["V_d = Dd^T D Dd, D > 0 (diagonal here)", "|alpha| <= C"])
    eta1, eta2, V1, V1dot = _real_v1dot(E)
    base = [box(eta1, -10, 10), box(eta2, -10, 10), *E.signal_domain(), *E.gains_domain()]
    gam, chi, sigma, Pn, Pmin = E.constants(C)
    cmax = sp.lambdify([*E.K1, *E.K2, *[s for t in E.Q for s in t], E.delta, E.kappa1],
                       gam * E.kappa1**2 * sp.sqrt(Pmin) / (E.delta * Pn), "numpy")

    def draw_C(z, env):
        args = [env[s] for s in [*E.K1, *E.K2, *[s for t in E.Q for s in t], E.delta, E.kappa1]]
        return (cmax(*args) * (z[:, 0] + 1.0) / 2)[:, None]

    dom = base + [E.q_domain(),
                  custom([C], 1, draw_C, "0 <= C <= gamma kappa1^2 / (delta ||P|| / lambda_min(P)^(1/2))"),
                  ball(E.alpha, C)]
    rate = -2 * chi * E.kappa2 * Pmin / E.delta * sum((e**2 for e in eta2), sp.S.Zero)
    return Statement(V1dot / E.delta, "<=", rate, dom, symbolic=False,
                     assumptions=["V_d := V1 (eq. 32) of eta = (Theta(Delta omega/delta), Delta d)",
                                  "|alpha| <= C with delta sigma <= gamma kappa1^2 (eq. 37's condition)",
                                  "real time: d/dt = (1/delta) d/dtau"])


ALPHA_67 = 1.17e-7   # max over the orbit of |M^-1 d(tau_D)/dt| of eq. 67, rad/s^3 (c001.eso.gain_condition)


def _vd_decay_fixed(gains: str) -> Statement:
    """The corrected V_d-dot bound (V_d := V1) with the gains rpo flies / the printed gains (one angular
    channel, Q = I, delta, kappa of sec. 7) and |alpha| up to eq. 67's torque rate."""
    E = _Eso(1)
    C = sp.Symbol("C", nonnegative=True)
    eta1, eta2, V1, V1dot = _real_v1dot(E)
    gam, chi, sigma, Pn, Pmin = E.constants(C)
    k1, k2 = ESO_GAINS[gains]
    rate = -2 * chi * E.kappa2 * Pmin / E.delta * sum((e**2 for e in eta2), sp.S.Zero)
    dom = [box(eta1, -1e-3, 1e-3), box(eta2, -1e-6, 1e-6), *E.signal_domain(),
           fixed([*E.K1, *E.K2], [k1, k2]), fixed([E.delta, E.kappa1, E.kappa2], [DELTA, KAPPA1, KAPPA2]),
           fixed(list(E.Q[0]), [1.0, 0.0, 1.0]), fixed([C], [ALPHA_67]), ball(E.alpha, C)]
    return Statement(V1dot / E.delta, "<=", rate, dom, symbolic=False,
                     assumptions=[f"k1 = {k1:g}, k2 = {k2:g} (angular channel), Q = I, delta = {DELTA:g}, kappa1 = "
                                  f"{KAPPA1:g}, kappa2 = {KAPPA2:g}", f"|alpha| <= {ALPHA_67:g} rad/s^3 (eq. 67)"])


def _composed() -> Statement:
    """The corrected chain: V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V1 (V1 of eq. 32, Q_i = I) differentiated
    along the joint state (q, omega, omega_hat, d_hat, d) under eq. 57 and eq. 23 (the ESO fed the unsaturated
    f_C through ``eso_model_acceleration``), bounded by -X^T H X (eq. 64) with D = 2 chi kappa2 lambda_min(P)/delta."""
    L = _Loop()
    n = 6
    wh6 = sp.Matrix(sp.symbols("omegahat_1:7", real=True))
    e1 = sp.Matrix(sp.symbols("eta1_1:7", real=True))
    d6 = sp.Matrix(sp.symbols("dtrue_1:7", real=True))
    alpha = sp.Matrix(sp.symbols("alpha_1:7", real=True))
    ka, la = sp.symbols("k1_w k1_v", positive=True)           # one gain pair per angular / linear channels
    kb, lb = sp.symbols("k2_w k2_v", positive=True)
    K1, K2 = sp.Matrix([ka] * 3 + [la] * 3), sp.Matrix([kb] * 3 + [lb] * 3)
    delta, ka1, ka2 = sp.symbols("delta kappa_1 kappa_2", positive=True)
    model = c.eso_model_acceleration(L.J, L.FG, L.fC, L.WSI, L.W)
    D8 = c.pure_dq(d6[0:3, :], d6[3:6, :])
    wdot = c.relative_dual_acceleration_lumped(L.J, L.FG, L.fC, L.WSI, L.W, D8)
    wh_dot, dh_dot = c.eso_rates(_six(model), L.w6, wh6, L.dh6, K1, K2, delta, ka1, ka2)
    x1 = (L.w6 - wh6) / delta
    x2 = d6 - L.dh6
    Pw, Pv = _lyap_P(ka, kb, sp.eye(2)), _lyap_P(la, lb, sp.eye(2))
    Ps = [Pw] * 3 + [Pv] * 3
    V1 = sp.S.Zero
    for i in range(n):
        v = sp.Matrix([c.sta_theta(x1[i], ka1, ka2), x2[i]])
        V1 += (v.T * Ps[i] * v)[0]
    Vrest = L.kin / 2 + L.k_v * V1
    states = list(L.w6) + list(wh6) + list(L.dh6) + list(d6)
    rates = list(_six(wdot)) + list(wh_dot) + list(dh_dot) + list(alpha)
    Vdot = 2 * L.k_p * c.circle(L.g, L.qdot) + lie_derivative(Vrest, states, rates)
    Vdot = Vdot.replace(sp.DiracDelta, lambda *a: sp.S.Zero)
    sub = {**{d6[i]: L.dh6[i] + L.dd6[i] for i in range(n)}, **{wh6[i]: L.w6[i] - delta * e1[i] for i in range(n)}}
    Vdot = Vdot.xreplace(sub)
    eig = [_eig2(Pw), _eig2(Pv)]
    Pn, Pmin = sp.Max(*[e[1] for e in eig]), sp.Min(*[e[0] for e in eig])
    chi, gam = 1 / (2 * Pn), 1 / (4 * sp.sqrt(Pn))
    Dc = 2 * chi * ka2 * Pmin / delta
    dd2 = sum((x**2 for x in L.dd6), sp.S.Zero)
    rhs = -L.k_d * L.ww + L.wJd - L.k_v * Dc * dd2                                    # -X^T H X
    cmax = sp.lambdify([ka, la, kb, lb, delta, ka1], gam * ka1**2 * sp.sqrt(Pmin) / (delta * Pn), "numpy")
    C = sp.Symbol("C", nonnegative=True)

    def draw_C(z, env):
        return (cmax(*[env[s] for s in [ka, la, kb, lb, delta, ka1]]) * (z[:, 0] + 1.0) / 2)[:, None]

    dom = [d for d in L.domain() if not set(d.symbols) & {L.V_d, L.Vd_dot}] + [
        box(e1, -10, 10), box([ka, la, kb, lb], 0.1, 10), box(delta, 1e-3, 1), box([ka1, ka2], 0.1, 2),
        custom([C], 1, draw_C, "0 <= C <= gamma kappa1^2 / (delta ||P|| / lambda_min(P)^(1/2)) (eq. 37)"),
        ball(alpha, C)]
    return Statement(Vdot, "<=", rhs, dom, symbolic=False,
                     assumptions=["|alpha| <= C with delta sigma <= gamma kappa1^2 (eq. 37's condition; fails for "
                                  "the sec. 7 gains, c001.eso.gain_condition)", "Q_i = I; one (k1, k2) for the "
                                  "angular and one for the linear channels (as sec. 7)", "f_C unsaturated",
                                  "g = grad V_p (any potential)", "eta1_i != 0 a.e. (DiracDelta terms dropped)"])


CLAIMS = [
    claim("pose.V_definite", P2, "abstract", "53, 58",
        "V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V_d is positive definite in (Delta q, omega, Delta d)",
        _v_definite),
claim("pose.eq61", P2, "abstract", "61", "the proportional term of eq. 57 does no work (with eq. 15)", _eq61),
    claim("pose.eq62", P2, "abstract", "62",
        "the gyroscopic and transport terms of eqs. 21 and 57 do no work", _eq62),
    claim("pose.Vdot_eq60", P2, "abstract", "59-60",
        "V-dot along eqs. 15, 21 under eq. 57 equals the printed eq. 60", _vdot_eq60, about="paper",
        note="Eq. 60 as printed with its lost signs reconstructed (the reconstruction is the one that makes eq. 63 "
             "follow); the statement about rpo's law is c001.pose.Vdot_identity."),
    claim("pose.Vdot_identity", P2, "abstract", "59-63",
        "V-dot = -k_d omega o omega + omega o (EJE Delta d) + k_v V_d-dot (eq. 63)", _vdot_identity),
    claim("pose.eq63_first_line", P2, "abstract", "63",
        "printed first line of eq. 63: (E omega) o (-k_v (E omega) + J_E Dd) + k_p V_d-dot",
        _eq63_printed, corrected=_eq63_first_line_corrected,
        correction="(E omega) o (-k_d (E omega) + J_E Delta d) + k_v V_d-dot (the second line of eq. 63 is right)",
        note="Typo in the paper (not the extraction): k_v for k_d in the damping term and k_p for k_v in front of "
             "V_d-dot; the next line of eq. 63 has the right coefficients."),
    claim("pose.Vd_decay", P2, "abstract", "text before 58, 63",
        "there is V_d = Dd^T D Dd with V_d-dot <= -V_d along the ESO", lambda: _vd_decay(False),
        corrected=lambda: _vd_decay(True),
        correction="take V_d := V1 of Prop. 1 (eq. 32, a function of Theta(Delta omega/delta) and Delta d): under "
                   "eq. 37's condition dV1/dt <= -(2 chi kappa2 lambda_min(P)/delta) |Delta d|^2, so eqs. 63-64 hold "
                   "with D = (2 chi kappa2 lambda_min(P)/delta) I",
        note="Delta d-dot = -K2 Phi(Delta omega/delta)/delta + alpha does not depend on Delta d: at Delta omega = 0, "
             "alpha = 0 it is 0, so V_d-dot = 0 > -V_d for any D.  Proposition 1's V1 is a function of "
             "(Theta, Delta d), not of Delta d alone.  The corrected bound needs eq. 37's condition, which the sec. 7 "
             "gains violate (c001.eso.gain_condition; see c001.pose.Vd_decay_rpo_gains).  The gain domain here "
             "([0.1, 10]) excludes the paper's 1e-4 / 1.6e-9."),
    claim("pose.Vd_decay_rpo_gains", P2, "spacecraft", "text before 58, 37, sec. 7",
        "the corrected V_d-dot bound with the gains rpo flies (k1 = 1e-4, k2 = 1.6e-9) and eq. 67's |alpha|",
        lambda: _vd_decay_fixed("reconstructed"), about="paper",
        note="Fails: eq. 37's condition is violated by ~1e8 (c001.eso.gain_condition), and the bound itself "
             "fails at small errors (|eta| ~ 1e-6)."),
    claim("pose.Vd_decay_printed_gains", P2, "spacecraft", "text before 58, 37, sec. 7",
        "the corrected V_d-dot bound with the printed gains (1e4, 1.6e9) and eq. 67's |alpha|",
        lambda: _vd_decay_fixed("printed"), about="paper",
        note="Eq. 37's condition fails by 2.2-3x for these gains, but the bound it is used for was not disproved "
             "numerically (the condition is sufficient only): the search over |eta1| <= 1e-3, |eta2| <= 1e-6 and "
             "smaller scales found no violation."),
    claim("pose.composed", P2, "abstract", "32-37, 57-64",
        "V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V1 along (q, omega, omega_hat, d_hat, d) under eqs. 57 and 23: "
        "V-dot <= -X^T H X", _composed,
        note="The corrected chain composed: V_d := V1 of Prop. 1 differentiated along the code's ESO on the joint "
             "state, D = 2 chi kappa2 lambda_min(P)/delta; needs eq. 37's condition (not met by the sec. 7 gains)."),
    claim("pose.equilibrium", P2, "abstract", "57, 21, end of the proof of Prop. 2",
        "at omega = 0, Delta d = 0: omega-dot = -k_p J_E^-1 vec(q* (E grad V_p))", _equilibrium_acc),
    claim("pose.barrier", APF, "spacecraft", "52-53, after 64",
        f"Delta q o Delta q >= {BARRIER_MIN:g} on beta_FOV = 0 and beta_CA = 0 (so V_p bounded => beta > 0)",
        _barrier, about="paper",
        note="Holds with the paper's q_D/T, r_D/T; the step also needs V non-increasing, which rpo's fov_eps term "
             "(c001.pose.Vdot_apf) and the saturation (c001.pose.saturation_impl) do not guarantee."),
    claim("pose.H_definite", P2, "spacecraft", "63-64",
        "eq. 64: -V-dot bound = X^T H X > 0 for k_d = 2 and k_v above max J_i^2/(4 k_d D_i)", _h_definite),
    claim("pose.saturation", P2, "spacecraft", "57, 63, sec. 7",
        "eq. 63 with the force and torque limits of sec. 7 (rpo clips eq. 57 per axis)", _saturated_identity,
        about="paper",
        note="Drawn on consistent states (f_G, omega_S/I, d_hat from one Table 1 orbit state; g the APF gradient "
             "at an admissible pose; sec. 7 gains).  "
             "The proof assumes the unsaturated eq. 57; with the sec. 7 limits (0.75 N, 2 mN m per axis) "
             "V-dot differs by (E omega) o (sat(f_C) - f_C) (c001.pose.saturation_impl), e.g. when k_d |v| > 0.75 N.  "
             "In rpo's scenario saturation is active in the first minutes only (0.14 % / 0.23 % of the steps, "
             "docs/controllers/c001.md)."),
    claim("pose.saturation_impl", P2, "spacecraft", "57, 63, sec. 7",
        "rpo's clipped law: V-dot = eq. 63 + (E omega) o (sat(f_C) - f_C)", None, corrected=_saturated_impl,
        correction="the saturation term (E omega) o (sat(f_C) - f_C) is not sign-definite; the proof does not "
                   "cover it"),
]
