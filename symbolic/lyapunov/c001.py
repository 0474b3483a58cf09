"""Claims of 001 (Zheng et al.): the ESO (Proposition 1, eqs. 21-39) and the pose law (Proposition 2,
eqs. 53-64).

Every statement is built from the functions of :mod:`rpo.symbolic.controllers.c001` that generate the C
code, looked up on the module at check time (mutations are seen):

* Proposition 1 (finite-time ESO): the estimation-error dynamics are the spacecraft model (eq. 20, its
  lumped form eq. 21 with ``d^S``) minus the observer (``eso_rates``, eq. 23, with ``sta_theta`` /
  ``sta_phi``, eq. 24); the abstract steps (time scaling eq. 27, ``Phi = W Theta`` eq. 30, the eta
  system eq. 31, ``V1 = eta^T P eta`` eqs. 32-37, the settling time eqs. 25, 38-39) are checked on the
  error system built from ``eso_rates``.
* Proposition 2 (PD-like law): V-dot is ``lie_derivative`` of eq. 58 along the pose kinematics
  (``pose_rate``, eq. 15) and the lumped dynamics (``relative_dual_acceleration_lumped``, eq. 21) driven
  by the law (``control_dual_force``, eq. 57).  Abstract layer: ``V_p`` any function of ``q_S/T`` with
  gradient ``g`` (eqs. 59-63 hold for every potential).  Spacecraft layer: ``V_p`` is the APF of eq. 53
  (``apf``, ``beta_fov_dq``, ``beta_ca_dq``) and ``g`` the coded gradient (``apf_gradient``,
  ``grad_beta_fov``, ``grad_beta_ca``, eqs. 54-55), including rpo's regularisation ``fov_eps``.

The full measurement -> law chain of ``C001.law`` takes minutes to build; the claims use the
equation-level functions on symbolic intermediate variables instead: exogenous quantities
(``omega_S/I``, ``f_G``, ``d_hat``, the model acceleration of the ESO) are free symbols, and inside the
spacecraft V-dot ``Delta q``, ``beta_FOV`` and ``beta_CA`` are symbols whose derivatives are the code's
(chain rule through undefined functions), which keeps each symbolic proof to seconds.  The numeric
search draws those symbols consistently (``derived``) from admissible poses.

``C001.law`` calls the same module functions for what it composes: ``target_inertial_dual_velocity``
(omega_T/I = omega_S/I - omega_S/T), ``eso_model_acceleration`` (the ESO's model acceleration),
``applied_dual_force`` (the clipped force and torque) and ``apf_terms`` (constraints, APF and gradient
wiring); the gains and limits are read from ``C001().k``'s defaults.
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..controllers import c001 as c
from ..rotations import cross, dq_conj, dq_mul
from ..special import Step
from .core import (
    Claim,
    Mutation,
    Statement,
    ball,
    box,
    custom,
    derived,
    drop_terms,
    fixed,
    lie_derivative,
    negate_output,
    replace_output,
    scale_argument,
)

# --------------------------------------------------------------------------- the paper's data (sec. 7)
# read from C001's gain defaults (the values rpo flies), not typed again
_KDEF = {f.name: (f.default if f.size > 1 else f.default[0]) for f in c.C001().k.fields}
K_P, K_D, K_A, K_R = (_KDEF[n] for n in ("k_p", "k_d", "k_a", "k_r"))
MASS, INERTIA = _KDEF["m"], _KDEF["M"]
R_S, R_T, THETA, Z_N = (_KDEF[n] for n in ("R_S", "R_T", "theta", "z_N"))
Z_NP = Z_N + R_T / math.sin(THETA)               # eq. 40
Q_D = _KDEF["q_D"]                                # q_D/T, scalar last (sign reconstructed, doc c001)
R_D = _KDEF["r_D"]
KAPPA1, KAPPA2, DELTA = _KDEF["kappa1"], _KDEF["kappa2"], _KDEF["delta"]
ESO_GAINS = {   # (k1, k2) of the angular channels; the printed exponents lost their minus (doc c001)
    "reconstructed": (_KDEF["K1"][0], _KDEF["K2"][0]),     # rpo's defaults
    "printed": (1.0e4, 1.6e9),                             # the paper's print, as printed
}
FOV_EPS = _KDEF["fov_eps"]                        # rpo's regularisation of eq. 55
F_MAX, TAU_MAX = _KDEF["F_max"], _KDEF["tau_max"]  # sec. 7 actuator limits
MU, SEMI_MAJOR, ECC = 3.986004418e14, 6878136.6, 0.01454   # Table 1 (scenarios/001_scenario.toml)
TAU_SIN, TAU_COS = (7.2e-4, 0.0, 9.5e-4), (7.2e-4, 8.1e-4, 0.0)  # eq. 67, N m
RHO_MIN, RHO_MAX = 3.7, 300.0    # range of the admissible poses drawn (> R_S + R_T; initial 275 m)

VEC = (0, 1, 2, 4, 5, 6)         # vector slots of a pure dual quaternion (rpo storage)
ZERO8 = sp.zeros(8, 1)


def _pv(name: str) -> tuple[sp.Matrix, sp.Matrix]:
    """Pure dual vector ``(0, a) + eps (0, b)`` from six real symbols ``name_1..6`` (a = 1..3)."""
    s = sp.Matrix(sp.symbols(f"{name}_1:7", real=True))
    return c.pure_dq(s[0:3, :], s[3:6, :]), s


def _six(d: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([d[i] for i in VEC])


def _nostep(e):
    """``Step -> 1``: valid where its argument is positive (``max(s, 0) = s`` off the camera axis)."""
    return e.replace(Step, lambda a: sp.S.One)


# --------------------------------------------------------------------------- numeric helpers (domains)

def _qmul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product, scalar last, row-wise (independent of the symbolic code)."""
    pv, pw, qv, qw = p[:, :3], p[:, 3:], q[:, :3], q[:, 3:]
    return np.hstack([pw * qv + qw * pv + np.cross(pv, qv), pw * qw - np.sum(pv * qv, 1, keepdims=True)])


def _unit_rows(z: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(z, axis=1, keepdims=True)
    fallback = np.zeros_like(z)
    fallback[:, -1] = 1.0
    return np.where(n > 1e-9, z / np.maximum(n, 1e-12), fallback)


def _rotate(qr: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``q v q*`` for scalar-last unit quaternions (rows)."""
    vq = np.hstack([v, np.zeros((len(v), 1))])
    conj = qr * np.array([-1.0, -1.0, -1.0, 1.0])
    return _qmul(_qmul(qr, vq), conj)[:, :3]


def _dq_rows(qr: np.ndarray, r_T: np.ndarray) -> np.ndarray:
    """Unit dual quaternion ``q + eps r^T q / 2`` (eq. 13) as rows of 8."""
    return np.hstack([qr, _qmul(np.hstack([r_T, np.zeros((len(r_T), 1))]), qr) / 2])


def _unit_dq_var(q: sp.Matrix, r_max: float = RHO_MAX):
    """Any pose: unit quaternion q_S/T and |r^T_i| <= r_max."""
    def draw(z, env):
        return _dq_rows(_unit_rows(z[:, :4]), r_max * z[:, 4:7])
    return custom(list(q), 7, draw, f"unit dual quaternion, |r_i| <= {r_max:g} m")


def _admissible_draw(frac_min: float = 1e-3, frac_max: float = 1.0 - 1e-9, rho_min: float | None = None,
                     rho_max: float | None = None):
    """Admissible poses: any attitude; the target centre (at -r^S) inside the FOV cone (beta_FOV > 0,
    eq. 41) at a distance in [RHO_MIN, RHO_MAX] (beta_CA > 0, eq. 47).  The off-axis angle is the fraction
    [frac_min, frac_max] of the largest admissible one (frac -> 1: the FOV boundary)."""
    def draw(z, env):
        qr = _unit_rows(z[:, :4])
        lo, hi = (RHO_MIN if rho_min is None else rho_min), (RHO_MAX if rho_max is None else rho_max)
        rho = lo + (z[:, 4] + 1.0) * 0.5 * (hi - lo)
        # rho (cos a - cot sin a) > z_N'  <=>  a < arccos(z_N' sin(theta) / rho) - (pi/2 - theta)
        a_max = np.arccos(np.minimum(Z_NP * math.sin(THETA) / rho, 1.0)) - (math.pi / 2 - THETA)
        a = a_max * (frac_min + (frac_max - frac_min) * (z[:, 5] + 1.0) * 0.5)
        ph = math.pi * z[:, 6]
        p = rho[:, None] * np.stack([np.sin(a) * np.cos(ph), np.sin(a) * np.sin(ph), np.cos(a)], 1)
        return _dq_rows(qr, _rotate(qr, -p))
    return draw


def _admissible_var(q: sp.Matrix, frac_min: float = 1e-3, frac_max: float = 1.0 - 1e-9,
                    rho_min: float = RHO_MIN, rho_max: float = RHO_MAX):
    return custom(list(q), 7, _admissible_draw(frac_min, frac_max, rho_min, rho_max),
                  f"admissible pose: beta_FOV > 0, beta_CA > 0, {rho_min:g} <= |r| <= {rho_max:g} m, "
                  f"off the camera axis by {frac_min:g}..{frac_max:g} of the cone")


def _desired_dq() -> np.ndarray:
    return _dq_rows(np.array([Q_D]), _rotate(np.array([Q_D]), np.zeros((1, 3))) + np.array([R_D]))[0]


def _unit_vector_var(v: sp.Matrix):
    return custom(list(v), len(v), lambda z, env: _unit_rows(z), f"unit {len(v)}-vector")


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


def _saturated_identity() -> Statement:
    """Eq. 63 when the applied dual force is eq. 57 clipped to the sec. 7 limits (as rpo applies it)."""
    L = _Loop(applied=lambda f: c.applied_dual_force(f, F_MAX, TAU_MAX))
    lhs = L.Vdot.replace(Step, lambda a: sp.Heaviside(a, 1))
    return Statement(lhs, "==", L.eq63, L.domain(), symbolic=False,
                     assumptions=["|F_i| <= 0.75 N, |tau_i| <= 2 mN m (sec. 7), applied to eq. 57's output"])


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
        r_T = 2 * _qmul(qd, qr * np.array([-1.0, -1.0, -1.0, 1.0]))[:, :3]        # eq. 7, r^T
        q_TI = _unit_rows(zz[:, 0:4])
        u = _unit_rows(zz[:, 4:7])
        h = _unit_rows(np.cross(u, _unit_rows(zz[:, 7:10])))                     # along-track direction
        rad = SEMI_MAJOR * (1 + ECC * zz[:, 10])
        R_t = rad[:, None] * u
        V_t = np.sqrt(MU * (2 / rad - 1 / SEMI_MAJOR))[:, None] * h
        w_t = 0.01 * zz[:, 11:14]
        conj = np.array([-1.0, -1.0, -1.0, 1.0])
        V_tT = _rotate(q_TI * conj, V_t)
        A_tT = _rotate(q_TI * conj, -MU * R_t / np.linalg.norm(R_t, axis=1, keepdims=True) ** 3)
        wT = pure8(w_t, V_tT)
        wdT = pure8(np.zeros((n, 3)), A_tT - np.cross(w_t, V_tT))
        W = np.column_stack([env[s] for s in L.w6])
        body = cols(f_body(*Q.T, *wT.T), n)
        wsi = pure8(W[:, :3], W[:, 3:]) + body
        R_S = R_t + _rotate(q_TI, r_T)
        q_SI = _qmul(q_TI, qr)
        r_SI_S = _rotate(q_SI * conj, R_S)
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


def _relative_velocity_rate() -> Statement:
    """Eqs. 17, 19-20: d/dt omega_S/T^S (eq. 14) along the pose kinematics (eq. 15) and the inertial dynamics of
    S (eq. 17) and T (any omega_T/I-dot^T) is eq. 20 (signs reconstructed)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    WSI, wsi6 = _pv("omegaSI")
    WT, wt6 = _pv("omegaTI")
    WDT, wdt6 = _pv("omegadotTI")
    FG, fg6 = _pv("fG")
    FD, fd6 = _pv("fD")
    FC, fc6 = _pv("fC")
    m = sp.Symbol("m", positive=True)
    Mi = sp.Matrix(sp.symbols("M_1:4", positive=True))
    J = c.dual_inertia(m, Mi)
    W = c.relative_dual_velocity(WSI, WT, q)                                               # eq. 14
    states = list(q) + list(wsi6) + list(wt6)
    rates = list(c.pose_rate(q, W)) + list(_six(c.inertial_dual_acceleration(J, WSI, FG + FD + FC))) + list(wdt6)
    lhs = sp.Matrix([lie_derivative(Wi, states, rates) for Wi in W])
    rhs = c.relative_dual_acceleration(J, FG, FD, FC, WSI, W, q, WDT)                      # eq. 20
    dom = [_unit_dq_var(q), box(wsi6[0:3, :], -0.01, 0.01), box(wsi6[3:6, :], -8000, 8000),
           box(wt6[0:3, :], -0.01, 0.01), box(wt6[3:6, :], -8000, 8000), box(wdt6, -10, 10),
           box(fg6, -600, 600), box(fd6, -1, 1), box(fc6, -1, 1), box(m, 30, 100), box(Mi, 5, 30)]
    return Statement(lhs, "==", rhs, dom, assumptions=["omega_T/I^T pure, its rate any pure dual vector"])


def _unit_dq_constraints(q):
    return [sum((q[i] ** 2 for i in range(4)), sp.S.Zero) - 1, sum((q[i] * q[4 + i] for i in range(4)), sp.S.Zero)]


def _pose_kinematics() -> Statement:
    """Eqs. 12-15: d/dt q_S/T (eq. 13) along q_T/I-dot = q_T/I omega_T/I^T / 2 and q_S/I-dot = q_S/I omega_S/I^S / 2
    is pose_rate(q_S/T, omega_S/T^S) with omega_S/T^S of eq. 14."""
    qT = sp.Matrix(sp.symbols("qT_1:9", real=True))
    qS = sp.Matrix(sp.symbols("qS_1:9", real=True))
    WT, wt6 = _pv("omegaTI")
    WSI, wsi6 = _pv("omegaSI")
    q = c.relative_pose(qT, qS)
    rates = list(c.pose_rate(qT, WT)) + list(c.pose_rate(qS, WSI))
    lhs = sp.Matrix([lie_derivative(qi, list(qT) + list(qS), rates) for qi in q])
    rhs = c.pose_rate(q, c.relative_dual_velocity(WSI, WT, q))
    dom = [_unit_dq_var(qT, 7e6), _unit_dq_var(qS, 7e6), box(wt6[0:3, :], -0.01, 0.01),
           box(wt6[3:6, :], -8000, 8000), box(wsi6[0:3, :], -0.01, 0.01), box(wsi6[3:6, :], -8000, 8000)]
    # symbolic=False: the Groebner reduction over 16 variables takes ~50 s (proved that way during development);
    # the residual is exactly (q q* - 1) omega_T/I^T q / 2
    return Statement(lhs, "==", rhs, dom, constraints=_unit_dq_constraints(qT) + _unit_dq_constraints(qS),
                     symbolic=False,
                     assumptions=["q_T/I, q_S/I unit dual quaternions (q_r o q_r = 1, q_r o q_d = 0)"])


def _constraint_dq_forms() -> Statement:
    """Eqs. 42-45, 47-48: beta_T = q o (K_u q) = u . r^S, |U r^S|^2 = eq. 45, eq. 48 = eq. 47, with
    r^S = 2 q_r* q_d (eq. 7) and u = +z_S (as ``apf_terms``)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    RS, RT = sp.symbols("R_S R_T", positive=True)
    K_u = c.camera_axis_matrix(sp.Matrix([0, 0, 1]))
    _, r = c.position_from_dq(q)
    bT = c.beta_T(q, K_u)
    lhs = sp.Matrix([bT, c.off_axis_sq(q, bT), c.beta_ca_dq(q, RS, RT)])
    rhs = sp.Matrix([r[2], r[0] ** 2 + r[1] ** 2, c.beta_ca_vector(r, RS, RT)])
    return Statement(lhs, "==", rhs, [_unit_dq_var(q), box([RS, RT], 0.5, 5)], constraints=_unit_dq_constraints(q),
                     assumptions=["q_r o q_r = 1, q_r o q_d = 0"])


def _fov_dq_form() -> Statement:
    """Eq. 46 = eq. 41 at r^S = 2 q_r* q_d (its square root: numeric)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    K_u = c.camera_axis_matrix(sp.Matrix([0, 0, 1]))
    z_Np = c.fov_vertex_offset(Z_N, R_T, THETA)
    _, r = c.position_from_dq(q)
    lhs = c.beta_fov_dq(q, K_u, THETA, z_Np).replace(Step, lambda a: sp.Heaviside(a, 1))
    return Statement(lhs, "==", c.beta_fov_vector(r, THETA, z_Np), [_unit_dq_var(q)], symbolic=False,
                     assumptions=["unit dual quaternion", "theta, z_N, R_T of sec. 7"])


# ---- spacecraft layer: the APF of eqs. 51-55

def _gradient_statement(printed: bool) -> Statement:
    """Eqs. 54-55 against the derivatives of eqs. 53, 46, 48 (three blocks, see the claim)."""
    L = _Loop(apf=True)
    q, e, qD = L.q, L.e, L.qD
    gF = sp.Matrix(sp.symbols("gFOV_1:9", real=True))
    gC = sp.Matrix(sp.symbols("gCA_1:9", real=True))
    E = [sp.Function(f"DQ_{i + 1}")(*q) for i in range(8)]
    BF, BC = sp.Function("B_FOV")(*q), sp.Function("B_CA")(*q)
    Vp = c.apf(sp.Matrix(E), L.k_a, L.k_r, BF, BC)
    rep = {}
    for qi, a, b in zip(q, gF, gC, strict=True):
        rep[sp.Derivative(BF, qi)], rep[sp.Derivative(BC, qi)] = a, b
        for Ei, di in zip(E, L.dq_err, strict=True):
            rep[sp.Derivative(Ei, qi)] = sp.diff(di, qi)
    dVp = sp.Matrix([sp.diff(Vp, qi) for qi in q]).xreplace(rep).xreplace(
        {BF: L.bF, BC: L.bC, **dict(zip(E, e, strict=True))})
    bF_full = c.beta_fov_dq(q, L.K_u, L.theta, L.z_Np)
    dbF = sp.Matrix([_nostep(sp.diff(bF_full, qi)) for qi in q])
    dbC = sp.Matrix([sp.diff(L.bC_q, qi) for qi in q])
    if printed:
        # eq. 54: 2 V_p/(Dq o Dq) [q_D*]^T Dq - k_r (Dq o Dq)(grad b_F / b_F^2 + grad b_C / b_C^2)
        x = sp.Matrix(sp.symbols("_x0:8", real=True))
        Lm = dq_mul(dq_conj(qD), x).jacobian(x)
        ee = _o(e, e)
        g54 = 2 * c.apf(e, L.k_a, L.k_r, L.bF, L.bC) / ee * (Lm.T * e) - L.k_r * ee * (gF / L.bF**2 + gC / L.bC**2)
        # eq. 55: grad b_F = -2 K_u q + cot^2(theta) (4 q - 2 b_T K_u q) / (b_F + b_T + z_N'), grad b_C = 8 q
        bT = (q.T * L.K_u * q)[0]
        g55F = -2 * L.K_u * q + (4 * q - 2 * bT * L.K_u * q) / sp.tan(L.theta)**2 / (L.bF_q + bT + L.z_Np)
        g55C = 8 * q
    else:
        g54 = c.apf_gradient(e, qD, L.k_a, L.k_r, L.bF, L.bC, gF, gC)
        g55F = _nostep(c.grad_beta_fov(q, L.K_u, L.theta, 0))
        g55C = c.grad_beta_ca(q)
    lhs = sp.Matrix.vstack(dVp, dbF, dbC)
    rhs = sp.Matrix.vstack(g54, g55F, g55C)
    dom = [d for d in L.domain() if not (set(d.symbols) & {L.eps})] + [box(gF, -10, 10), box(gC, -10, 10)]
    dom = [d for d in dom if set(d.symbols) & (lhs.free_symbols | rhs.free_symbols)]
    return Statement(lhs, "==", rhs, dom,
                     assumptions=["off the camera axis (|U r| > 0, where eq. 46 is differentiable)",
                                  "Delta q != 0 for the printed 2 V_p/(Dq o Dq)"])


def _vdot_apf(corrected: bool) -> Statement:
    """Eqs. 53-63 with the APF: V-dot along the loop under eq. 57 with the coded gradient."""
    if not corrected:
        L = _Loop(apf=True, eps=0)
        return Statement(L.Vdot, "==", L.eq63, [d for d in L.domain() if L.eps not in d.symbols],
                         assumptions=["eqs. 54-55 exact (fov_eps = 0)", "Delta d = d^S - d_hat^S"])
    L = _Loop(apf=True, eps=None)
    q = L.q
    bT = (q.T * L.K_u * q)[0]
    s = 4 * (_o(q, q) - 1) - bT**2                           # eq. 45: |U r|^2
    sdot = sum((sp.diff(s, qi) * qd for qi, qd in zip(q, L.qdot, strict=True)), sp.S.Zero)
    R_eps = (L.k_p * L.k_r / sp.tan(L.theta) * _o(L.e, L.e) / L.bF**2
             * (1 / sp.sqrt(s) - 1 / sp.sqrt(s + L.eps**2)) * sdot)
    return Statement(L.Vdot, "==", L.eq63 + R_eps, L.domain(),
                     assumptions=["rpo's eq. 55: 1/sqrt(s) -> 1/sqrt(s + fov_eps^2)", "Delta d = d^S - d_hat^S"])


def _paper_apf(q: sp.Matrix, on_axis: bool = False):
    """V_p of eq. 53 with rpo's gradient, built by ``c.apf_terms`` (as ``C001.law``) with the paper's k_a, k_r,
    geometry and desired pose.

    ``on_axis``: keep eq. 46's ``max(s, 0)`` (as a Heaviside, for numbers on the camera axis); otherwise
    ``Step -> 1`` (differentiable off the axis)."""
    unstep = (lambda e: e.replace(Step, lambda a: sp.Heaviside(a, 1))) if on_axis else _nostep
    a = c.apf_terms(q, sp.Matrix(Q_D), sp.Matrix(R_D), K_A, K_R, sp.Float(THETA), sp.Float(Z_N), sp.Float(R_S),
                    sp.Float(R_T), FOV_EPS)
    return unstep(a["V_p"]), a["dq_err"], unstep(a["grad"])


def _convex() -> Statement:
    """Eq. 56: the Hessian of V_p (eq. 53) is positive definite on the admissible set (k_a >> k_r)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    v = sp.Matrix(sp.symbols("v_1:9", real=True))
    t = sp.Symbol("t", real=True)
    Vp, _, _ = _paper_apf(q)
    d2 = sp.diff(Vp.xreplace(dict(zip(q, q + t * v, strict=True))), t, 2).subs(t, 0)   # v^T (grad^2 V_p) v
    return Statement(d2, ">", 0, [_admissible_var(q, 1e-3), _unit_vector_var(v)], symbolic=False,
                     zero_at=list(v), trials=3000,
                     assumptions=["k_a = 0.75, k_r = 2.5e-5, theta = 45 deg, z_N = 1.2 m, R_S = 2.1 m, R_T = 1.5 m,"
                                  " q_D/T, r_D/T of sec. 7", "admissible pose, off the camera axis"])


def _critical_points(q, crit, dq_err) -> np.ndarray:
    """Roots of vec(q* (E grad V_p)) (rpo's gradient, fov_eps) on the unit dual quaternions, found from
    the desired pose and from its antipode -q_D (same physical pose, other sign of the quaternion)."""
    from scipy.optimize import least_squares
    from scipy.spatial.transform import Rotation

    f = sp.lambdify(list(q), list(crit), "numpy")
    qD = _desired_dq()

    def pose(x, sign):
        qr = sign * (Rotation.from_quat(np.array(Q_D)) * Rotation.from_rotvec(x[:3])).as_quat()
        return _dq_rows(qr[None, :], (np.array(R_D) + x[3:])[None, :])[0]

    out = []
    for sign in (1.0, -1.0):
        res = least_squares(lambda x, s=sign: np.array(f(*pose(x, s)), dtype=float), np.zeros(6),
                            xtol=1e-15, ftol=1e-15, gtol=1e-15)
        p = pose(res.x, sign)
        if float(np.max(np.abs(f(*p)))) > 1e-10:
            raise RuntimeError("critical point of V_p not found")
        out.append(p)
    assert np.allclose(out[0], qD, atol=1e-9)
    return np.array(out)


def _unique_minimum() -> Statement:
    """End of the proof of Prop. 2: vec(q* (E grad V_p)) = 0 only at q_S/T = q_D/T (Dq = 0)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    _, dq_err, grad = _paper_apf(q, on_axis=True)
    crit = _six(c.dq_vec(dq_mul(dq_conj(q), c.dq_swap(grad))))
    pts = _critical_points(q, crit, dq_err)

    def draw(z, env):
        return np.where(z[:, :1] < 0.0, pts[0][None, :], pts[1][None, :])

    dom = [custom(list(q), 1, draw, "critical points of V_p on the unit dual quaternions (roots of "
                                    "vec(q* (E grad V_p)) to 1e-10, scipy least_squares from q_D and -q_D)")]
    return Statement(c.circle(dq_err, dq_err), "==", 0, dom, symbolic=False, trials=20,
                     assumptions=["rpo's gradient (fov_eps = 1e-3 m), the paper's gains and desired pose"])


# --------------------------------------------------------------------------- Proposition 1: the ESO

def _theta_h(y, k1, k2):
    """Theta of eq. 24, typed out: kappa1 sign(y)|y|^(1/2) + kappa2 y."""
    return k1 * sp.sign(y) * sp.sqrt(sp.Abs(y)) + k2 * y


def _phi_h(y, k1, k2):
    """Phi of eq. 24, typed out: kappa1^2/2 sign(y) + 3/2 kappa1 kappa2 sign(y)|y|^(1/2) + kappa2^2 y."""
    return k1**2 / 2 * sp.sign(y) + sp.Rational(3, 2) * k1 * k2 * sp.sign(y) * sp.sqrt(sp.Abs(y)) + k2**2 * y


def _w_h(y, k1, k2):
    """w of eq. 29, typed out: 0.5 kappa1 / |y|^(1/2) + kappa2."""
    return k1 / (2 * sp.sqrt(sp.Abs(y))) + k2


def _lyap_P(k1, k2, Q):
    """P with K~^T P + P K~ = -Q, K~ = [[-k1, 1], [-k2, 0]] (eq. 31-32), solved symbolically."""
    p1, p2, p3 = sp.symbols("_p1:4")
    P = sp.Matrix([[p1, p2], [p2, p3]])
    Kt = sp.Matrix([[-k1, 1], [-k2, 0]])
    sol = sp.solve(list(Kt.T * P + P * Kt + Q), [p1, p2, p3], dict=True)[0]
    return P.xreplace(sol)


def _eig2(A):
    """(lambda_min, lambda_max) of a symmetric 2x2 matrix."""
    m, r = (A[0, 0] + A[1, 1]) / 2, sp.sqrt(((A[0, 0] - A[1, 1]) / 2) ** 2 + A[0, 1] ** 2)
    return m - r, m + r


class _Eso:
    """The ESO (eq. 23) on the lumped model (eq. 21) in the scaled error coordinates of eq. 27.

    ``a`` is the known model acceleration of eq. 21 (any value: it cancels), ``d`` the true d^S with
    rate ``alpha`` (eq. 22).  eta1 = Delta omega / delta, eta2 = Delta d; the rates returned are
    d/dtau with t = delta tau (eq. 27) -- divide by delta for real time.
    """

    def __init__(self, n: int = 6):
        self.n = n
        self.K1 = sp.Matrix(sp.symbols(f"k1_1:{n + 1}", positive=True))
        self.K2 = sp.Matrix(sp.symbols(f"k2_1:{n + 1}", positive=True))
        self.delta, self.kappa1, self.kappa2 = sp.symbols("delta kappa_1 kappa_2", positive=True)
        self.a = sp.Matrix(sp.symbols(f"a_1:{n + 1}", real=True))
        self.w = sp.Matrix(sp.symbols(f"omega_1:{n + 1}", real=True))
        self.d = sp.Matrix(sp.symbols(f"d_1:{n + 1}", real=True))
        self.alpha = sp.Matrix(sp.symbols(f"alpha_1:{n + 1}", real=True))
        self.Q = [sp.symbols(f"Q11_{i + 1} Q12_{i + 1} Q22_{i + 1}", real=True) for i in range(n)]

    def scaled_rates(self, eta1, eta2):
        """(d eta1/d tau, d eta2/d tau) from ``c.eso_rates`` with w_hat = w - delta eta1, d_hat = d - eta2."""
        w_hat = self.w - self.delta * eta1
        d_hat = self.d - eta2
        wh_dot, dh_dot = c.eso_rates(self.a, self.w, w_hat, d_hat, self.K1, self.K2, self.delta,
                                     self.kappa1, self.kappa2)
        return (self.a + self.d) - wh_dot, self.delta * (self.alpha - dh_dot)

    def P(self, i):
        q11, q12, q22 = self.Q[i]
        return _lyap_P(self.K1[i], self.K2[i], sp.Matrix([[q11, q12], [q12, q22]]))

    def Qm(self, i):
        q11, q12, q22 = self.Q[i]
        return sp.Matrix([[q11, q12], [q12, q22]])

    def V1(self, theta, eta2):
        """V1 = sum_i (Theta_i, eta2_i) P_i (Theta_i, eta2_i)^T (eq. 32)."""
        out = sp.S.Zero
        for i in range(self.n):
            x = sp.Matrix([theta[i], eta2[i]])
            out += (x.T * self.P(i) * x)[0]
        return out

    def constants(self, C):
        """gamma, chi, sigma, ||P||, lambda_min(P) of eq. 36 (sigma with the bound C on |alpha|)."""
        lmins, lmaxs, gam, chi = [], [], [], []
        for i in range(self.n):
            lo, hi = _eig2(self.P(i))
            qlo, _ = _eig2(self.Qm(i))
            lmins.append(lo)
            lmaxs.append(hi)
            gam.append(qlo / (4 * sp.sqrt(hi)))
            chi.append(qlo / (2 * hi))
        Pn, Pmin = sp.Max(*lmaxs), sp.Min(*lmins)
        return sp.Min(*gam), sp.Min(*chi), C * Pn / sp.sqrt(Pmin), Pn, Pmin

    # ---- domains
    def gains_domain(self):
        return [box(self.K1, 0.1, 10), box(self.K2, 0.1, 10), box(self.delta, 1e-3, 1),
                box([self.kappa1, self.kappa2], 0.1, 2)]

    def q_domain(self):
        syms = [s for t in self.Q for s in t]

        def draw(z, env):
            out = np.empty_like(z)
            for i in range(self.n):
                a, b = 10.0 ** z[:, 3 * i], 10.0 ** z[:, 3 * i + 2]
                out[:, 3 * i], out[:, 3 * i + 2] = a, b
                out[:, 3 * i + 1] = 0.99 * z[:, 3 * i + 1] * np.sqrt(a * b)
            return out
        return custom(syms, 3 * self.n, draw, "Q_i symmetric positive definite (eigenvalues 0.1..10 scale)")

    def signal_domain(self):
        return [box(self.a, -10, 10), box(self.w, -10, 10), box(self.d, -10, 10)]


def _eso_error_dynamics() -> Statement:
    """Eqs. 20-23 -> 26: spacecraft model minus observer = the abstract error system."""
    idx = list(VEC)
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    W, w6 = _pv("omega")
    WSI, wsi6 = _pv("omegaSI")
    FG, fg6 = _pv("fG")
    FC, fc6 = _pv("fC")
    FD, fd6 = _pv("fD")
    WDT, wdt6 = _pv("omegadotTI")
    _, wh6 = _pv("omegahat")
    _, dh6 = _pv("dhat")
    alpha = sp.Matrix(sp.symbols("alpha_1:7", real=True))
    m = sp.Symbol("m", positive=True)
    Mi = sp.Matrix(sp.symbols("M_1:4", positive=True))
    K1 = sp.Matrix(sp.symbols("k1_1:7", positive=True))
    K2 = sp.Matrix(sp.symbols("k2_1:7", positive=True))
    delta, k1, k2 = sp.symbols("delta kappa_1 kappa_2", positive=True)
    J = c.dual_inertia(m, Mi)
    wdot = c.relative_dual_acceleration(J, FG, FD, FC, WSI, W, q, WDT)                  # eq. 20
    d = _six(c.integrated_disturbance(J, FD, q, WDT))                                     # d^S (eq. 21)
    model = c.eso_model_acceleration(J, FG, FC, WSI, W)                                   # as C001.law
    wh_dot, dh_dot = c.eso_rates(sp.Matrix([model[i] for i in idx]), w6, wh6, dh6, K1, K2, delta, k1, k2)
    lhs = sp.Matrix.vstack(_six(wdot) - wh_dot, alpha - dh_dot)      # (Delta omega-dot, Delta d-dot)
    x = (w6 - wh6) / delta
    rhs = sp.Matrix([-K1[i] * _theta_h(x[i], k1, k2) + d[i] - dh6[i] for i in range(6)]
                    + [-K2[i] * _phi_h(x[i], k1, k2) / delta + alpha[i] for i in range(6)])
    dom = [_unit_dq_var(q), box(w6[0:3, :], -0.01, 0.01), box(w6[3:6, :], -1, 1),
           box(wsi6[0:3, :], -0.01, 0.01), box(wsi6[3:6, :], -8000, 8000),
           box(fg6[0:3, :], -600, 600), box(fg6[3:6, :], -1e-3, 1e-3),
           box(fc6[0:3, :], -0.75, 0.75), box(fc6[3:6, :], -2e-3, 2e-3),
           box(fd6[0:3, :], -0.1, 0.1), box(fd6[3:6, :], -1e-3, 1e-3),
           box(wdt6[0:3, :], -1e-6, 1e-6), box(wdt6[3:6, :], -10, 10),
           box(wh6[0:3, :], -0.01, 0.01), box(wh6[3:6, :], -1, 1), box(dh6, -10, 10),
           box(alpha, -1, 1), box(m, 30, 100), box(Mi, 5, 30),
           box(K1, 1e-5, 1e-2), box(K2, 1e-10, 1e-5), box(delta, 1e-4, 1e-2), box([k1, k2], 0.1, 2)]
    return Statement(lhs, "==", rhs, dom,
                     assumptions=["omega_S/T, omega_S/I measured exactly", "the ESO is fed the f_C the plant "
                                  "applies (rpo: the saturated command, the same limits in law and plant)",
                                  "nominal m, M = the plant's"])


def _time_scaling() -> Statement:
    """Eq. 27: with eta1(tau) = Delta omega(delta tau)/delta, eta2 = Delta d(delta tau)."""
    E = _Eso()
    eta1 = sp.Matrix(sp.symbols("eta1_1:7", real=True))
    eta2 = sp.Matrix(sp.symbols("eta2_1:7", real=True))
    r1, r2 = E.scaled_rates(eta1, eta2)
    k1, k2 = E.kappa1, E.kappa2
    rhs = sp.Matrix([-E.K1[i] * _theta_h(eta1[i], k1, k2) + eta2[i] for i in range(6)]
                    + [-E.K2[i] * _phi_h(eta1[i], k1, k2) + E.delta * E.alpha[i] for i in range(6)])
    dom = [box(eta1, -10, 10), box(eta2, -10, 10), box(E.alpha, -10, 10), *E.signal_domain(), *E.gains_domain()]
    return Statement(sp.Matrix.vstack(r1, r2), "==", rhs, dom)


def _phi_w_theta() -> Statement:
    """Eqs. 29-30: dTheta/deta1 = W and Phi = W Theta, for eta1 = y^2 and eta1 = -y^2 (y > 0)."""
    y = sp.Symbol("y", positive=True)
    k1, k2 = sp.symbols("kappa_1 kappa_2", positive=True)
    rows = []
    for s in (1, -1):
        e1 = s * y**2
        dth = sp.diff(c.sta_theta(e1, k1, k2), y) / sp.diff(e1, y)     # dTheta/deta1 at eta1 = s y^2
        rows += [dth - _w_h(e1, k1, k2), c.sta_phi(e1, k1, k2) - _w_h(e1, k1, k2) * c.sta_theta(e1, k1, k2)]
    return Statement(sp.Matrix(rows), "==", 0, [box(y, 1e-3, 10), box([k1, k2], 0.01, 10)],
                     assumptions=["eta1 != 0 (W is unbounded at 0); eta1 = +-y^2 covers both signs"])


def _eta_blocks(E: _Eso, signs):
    """Per channel eta1_i = s_i y_i^2 (y_i > 0, so |eta1|^(1/2) = y_i stays rational); the code's scaled
    rates; d/dtau y_i = eta1_i-dot / (2 s_i y_i)."""
    y = sp.Matrix(sp.symbols("y_1:7", positive=True))
    eta2 = sp.Matrix(sp.symbols("eta2_1:7", real=True))
    eta1 = sp.Matrix([s * yi**2 for s, yi in zip(signs, y, strict=True)])
    r1, r2 = E.scaled_rates(eta1, eta2)
    ydot = [r / (2 * s * yi) for r, s, yi in zip(r1, signs, y, strict=True)]
    return y, eta1, eta2, r1, r2, ydot


SIGN_PATTERNS = ((1, -1, 1, -1, 1, -1), (-1, 1, -1, 1, -1, 1))
N_BOUND = 2     # channels in the numeric-only ESO bounds (the argument is channel-wise; keeps them fast)


def _eta_dynamics() -> Statement:
    """Eq. 31: eta_i = (Theta_i, eta2_i) obeys eta_i-dot = w_i K~_i eta_i + delta (0, alpha_i)."""
    E = _Eso()
    k1, k2 = E.kappa1, E.kappa2
    lhs, rhs = [], []
    for signs in SIGN_PATTERNS:
        y, eta1, eta2, r1, r2, ydot = _eta_blocks(E, signs)
        for i in range(6):
            dth = sp.diff(c.sta_theta(eta1[i], k1, k2), y[i])          # Theta-dot = dTheta/dy y-dot
            lhs += [dth * ydot[i], r2[i]]
            Kt = sp.Matrix([[-E.K1[i], 1], [-E.K2[i], 0]])
            rhs += list(_w_h(eta1[i], k1, k2) * Kt * sp.Matrix([_theta_h(eta1[i], k1, k2), eta2[i]])
                        + sp.Matrix([0, E.delta * E.alpha[i]]))
    dom = [box(y, 1e-3, 3), box(eta2, -10, 10), box(E.alpha, -10, 10), *E.signal_domain(), *E.gains_domain()]
    return Statement(sp.Matrix(lhs), "==", sp.Matrix(rhs), dom, assumptions=["eta1_i != 0"])


def _v1_definite() -> Statement:
    """Eq. 32: V1 = eta^T P eta > 0 with P_i from K~_i^T P_i + P_i K~_i = -Q_i, Q_i > 0, k1i, k2i > 0."""
    E = _Eso(2)    # V1 is a sum of independent 2x2 blocks; two channels show the sum (no code involved)
    th = sp.Matrix(sp.symbols("Theta_1:3", real=True))
    eta2 = sp.Matrix(sp.symbols("eta2_1:3", real=True))
    dom = [box(th, -10, 10), box(eta2, -10, 10), box(E.K1, 1e-3, 10), box(E.K2, 1e-3, 10), E.q_domain()]
    return Statement(E.V1(th, eta2), ">", 0, dom, symbolic=False, zero_at=list(th) + list(eta2),
                     assumptions=["k1i, k2i > 0 (K~_i Hurwitz)", "Q_i symmetric positive definite"])


def _v1dot_identity() -> Statement:
    """Eqs. 33-34: V1-dot = -sum_i w_i eta_i^T Q_i eta_i + 2 delta alpha~^T P eta (scaled time)."""
    E = _Eso()
    k1, k2 = E.kappa1, E.kappa2
    lhs, rhs = [], []
    for signs in SIGN_PATTERNS:
        y, eta1, eta2, r1, r2, ydot = _eta_blocks(E, signs)
        theta = [c.sta_theta(e, k1, k2) for e in eta1]
        V1 = E.V1(theta, eta2)
        lhs.append(lie_derivative(V1, list(y) + list(eta2), ydot + list(r2)))
        out = sp.S.Zero
        for i in range(6):
            et = sp.Matrix([_theta_h(eta1[i], k1, k2), eta2[i]])
            out += -_w_h(eta1[i], k1, k2) * (et.T * E.Qm(i) * et)[0]
            out += 2 * E.delta * E.alpha[i] * (E.P(i) * et)[1]
        rhs.append(out)
    dom = [box(y, 1e-3, 3), box(eta2, -10, 10), box(E.alpha, -10, 10), *E.signal_domain(),
           *E.gains_domain(), E.q_domain()]
    return Statement(sp.Matrix(lhs), "==", sp.Matrix(rhs), dom,
                     assumptions=["P_i solves K~_i^T P_i + P_i K~_i = -Q_i (eq. 32)", "eta1_i != 0"])


def _w_bound() -> Statement:
    """Text after eq. 35: kappa1 |eta1|^(1/2) <= |Theta| <= ||eta_i||, hence w_i >= 0.5 kappa1^2/||eta_i|| + kappa2."""
    eta1, eta2 = sp.symbols("eta1 eta2", real=True)
    k1, k2 = sp.symbols("kappa_1 kappa_2", positive=True)
    th = c.sta_theta(eta1, k1, k2)
    lhs = _w_h(eta1, k1, k2)
    rhs = k1**2 / (2 * sp.sqrt(th**2 + eta2**2)) + k2
    return Statement(lhs, ">=", rhs, [box(eta1, -10, 10), box(eta2, -10, 10), box([k1, k2], 0.01, 10)],
                     symbolic=False)


def _eta_symbols(n: int):
    return (sp.Matrix(sp.symbols(f"eta1_1:{n + 1}", real=True)),
            sp.Matrix(sp.symbols(f"eta2_1:{n + 1}", real=True)))


def _real_v1dot(E: _Eso):
    """V1 and V1-dot (scaled time) along the code's error system, eta1 real (DiracDelta terms: 0 a.e.)."""
    eta1, eta2 = _eta_symbols(E.n)
    r1, r2 = E.scaled_rates(eta1, eta2)
    V1 = E.V1([c.sta_theta(e, E.kappa1, E.kappa2) for e in eta1], eta2)
    V1dot = lie_derivative(V1, list(eta1) + list(eta2), list(r1) + list(r2))
    V1dot = V1dot.replace(sp.DiracDelta, lambda *a: sp.S.Zero)
    return eta1, eta2, V1, V1dot


def _v1dot_bound() -> Statement:
    """Eqs. 36-37: V1-dot <= -2 (gamma kappa1^2 - delta sigma) V1^(1/2) - 2 chi kappa2 V1, |alpha| <= C."""
    E = _Eso(N_BOUND)
    C = sp.Symbol("C", positive=True)
    eta1, eta2, V1, V1dot = _real_v1dot(E)
    gam, chi, sigma, _, _ = E.constants(C)
    rhs = -2 * (gam * E.kappa1**2 - E.delta * sigma) * sp.sqrt(V1) - 2 * chi * E.kappa2 * V1
    dom = [box(eta1, -10, 10), box(eta2, -10, 10), *E.signal_domain(), *E.gains_domain(), E.q_domain(),
           box(C, 0, 10), ball(E.alpha, C)]
    return Statement(V1dot, "<=", rhs, dom, symbolic=False,
                     assumptions=["||alpha|| <= C (Prop. 1)", "gamma, chi, sigma as defined after eq. 36"])


def _finite_time() -> Statement:
    """Eqs. 37-39, 25: from V1-dot <= -2 a V1^(1/2) - 2 b V1 (a = gamma kappa1^2 - delta sigma, b = chi kappa2),
    y = V1^(1/2) obeys y-dot <= -a - b y, whose comparison solution (eq. 38) reaches 0 at t_max (eq. 39)."""
    a, b, y0, t, Y = sp.symbols("a b y_0 t Y", positive=True)     # Y = V1^(1/2)
    vt = a / b                                               # vartheta
    y = (y0 + vt) * sp.exp(-b * t) - vt                      # eq. 38
    t_max = sp.log(y0 / vt + 1) / b                          # eq. 39
    delta = sp.Symbol("delta", positive=True)
    T = delta * t_max                                        # eq. 25: real settling time T_max = delta t_max
    rows = [(-2 * a * Y - 2 * b * Y**2) / (2 * Y) - (-a - b * Y),   # d V1^(1/2)/dt = V1-dot/(2 V1^(1/2))
            sp.diff(y, t) - (-a - b * y), y.subs(t, 0) - y0, y.subs(t, t_max),
            y.subs(t, T / delta)]                            # y(tau) with tau = t_real/delta vanishes at T_max
    return Statement(sp.Matrix(rows), "==", 0, [box([a, b, y0, Y], 1e-3, 10), box(t, 0, 100), box(delta, 1e-4, 1)],
                     assumptions=["a > 0, i.e. delta < gamma kappa1^2 / sigma (strict: vartheta > 0)"])


def _gain_condition() -> Statement:
    """Eq. 37's condition delta <= gamma kappa1^2 / sigma with the paper's gains (sec. 7) and C at least the
    rate of eq. 67's torque disturbance divided by M (the angular part of alpha = d d^S/dt)."""
    nu = sp.Symbol("nu", real=True)
    n = math.sqrt(MU / SEMI_MAJOR**3)
    nudot = n * (1 + ECC * sp.cos(nu)) ** 2 / (1 - ECC**2) ** 1.5
    tau_dot = [nudot * (TAU_SIN[i] * sp.cos(nu) - TAU_COS[i] * sp.sin(nu)) for i in range(3)]
    C = 0.99 * sp.sqrt(sum((tau_dot[i] / INERTIA[i]) ** 2 for i in range(3)))
    lhs, rhs = [], []
    for k1, k2 in ESO_GAINS.values():
        P = _lyap_P(sp.Float(k1), sp.Float(k2), sp.eye(2))   # Q_i = I; the three angular channels are equal
        lo, hi = _eig2(P)
        gamma = sp.Rational(1, 4) / sp.sqrt(hi)
        lhs.append(DELTA * C * hi / sp.sqrt(lo))             # delta sigma
        rhs.append(gamma * KAPPA1**2)
    return Statement(sp.Matrix(lhs), "<=", sp.Matrix(rhs), [box(nu, -math.pi, math.pi)], symbolic=False,
                     assumptions=["Q_i = I (gamma/sigma does not depend on the scale of Q)",
                                  "optimising over the shape of Q_i raises the admissible C at most to 1.88e-15 "
                                  "(rpo's gains) and leaves 3.83e-8 (printed): still below |alpha|",
                                  "only the angular channels (k12..k14, k22..k24): taking all channels only "
                                  "makes ||P|| larger and gamma smaller",
                                  "alpha_omega = M^-1 d(tau_D)/dt of eq. 67 (the target's rotational term of "
                                  "d^S varies ~1e-3 times slower), x 0.99"])


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


def _convex_far() -> Statement:
    """Eq. 56 on part of the admissible set: |r| in [40, 300] m, the target 20-80 % of the cone off the axis."""
    st = _convex()
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    st.domain[0] = _admissible_var(q, 0.2, 0.8, 40.0, RHO_MAX)
    st.assumptions = st.assumptions[:1] + ["40 m <= |r| <= 300 m, off-axis angle 20-80 % of the cone"]
    st.trials = 800
    return st


# --------------------------------------------------------------------------- claims

def _cl(name, part, layer, eqs, title, paper, **kw) -> Claim:
    return Claim(f"c001.{name}", "c001", part, layer, eqs, title, paper, **kw)


P1, P2, APF = "ESO (Prop. 1)", "pose law (Prop. 2)", "APF (Prop. 2)"

MODEL, CONS = "model (eqs. 12-20)", "constraints (eqs. 42-48)"

CLAIMS = [
    # ---- the model the proof rests on (reconstructed signs)
    _cl("model.pose_kinematics", MODEL, "spacecraft", "12-15",
        "d/dt (q_T/I* q_S/I) = q_S/T omega_S/T^S / 2 with omega_S/T^S of eq. 14", _pose_kinematics,
        note="Identity modulo the unit-dual-quaternion constraints (residual (q q* - 1) omega_T/I^T q / 2); "
             "checked numerically here, the Groebner proof takes ~50 s."),
    _cl("model.relative_acceleration", MODEL, "spacecraft", "14, 17, 19-20",
        "d/dt omega_S/T^S (eq. 14) along eqs. 15, 17 (S) and any omega_T/I-dot^T is eq. 20", _relative_velocity_rate,
        note="Proves the reconstructed signs of eqs. 19-20 (- q* omega_T/I-dot q, + omega_S/T x omega_S/I)."),
    _cl("constraints.dq_forms", CONS, "spacecraft", "42-45, 47-48",
        "beta_T = q o (K_u q) = u . r^S, |U r^S|^2 = eq. 45, eq. 48 = eq. 47 (r^S = 2 q_r* q_d)",
        _constraint_dq_forms),
    _cl("constraints.fov_dq_form", CONS, "spacecraft", "41, 46", "eq. 46 = eq. 41 (sign of u . r as reconstructed)",
        _fov_dq_form),
    # ---- Proposition 1: the super-twisting ESO
    _cl("eso.error_dynamics", P1, "spacecraft", "20-23, 26",
        "eq. 20 minus the ESO (eq. 23) is the error system eq. 26 with d^S of eq. 21", _eso_error_dynamics),
    _cl("eso.time_scaling", P1, "abstract", "27", "time scaling eta1 = Delta omega/delta, eta2 = Delta d",
        _time_scaling),
    _cl("eso.phi_w_theta", P1, "abstract", "29-30", "dTheta/deta1 = W and Phi = W Theta", _phi_w_theta),
    _cl("eso.eta_dynamics", P1, "abstract", "31", "eta-dot = W~ K~ eta + delta alpha~", _eta_dynamics),
    _cl("eso.V1_definite", P1, "abstract", "32", "V1 = eta^T P eta is positive definite (P from the Lyapunov "
        "equation of the Hurwitz K~_i)", _v1_definite),
    _cl("eso.V1dot_identity", P1, "abstract", "33-34",
        "V1-dot = -sum w_i eta_i^T Q_i eta_i + 2 delta alpha~^T P eta", _v1dot_identity),
    _cl("eso.w_bound", P1, "abstract", "35", "w_i >= 0.5 kappa1^2/||eta_i|| + kappa2", _w_bound),
    _cl("eso.V1dot_bound", P1, "abstract", "36-37",
        "V1-dot <= -2 (gamma kappa1^2 - delta sigma) V1^(1/2) - 2 chi kappa2 V1 for |alpha| <= C", _v1dot_bound),
    _cl("eso.finite_time", P1, "abstract", "25, 37-39",
        "comparison solution of eq. 38, the settling time t_max of eq. 39 and T_max = delta t_max (eq. 25)",
        _finite_time,
        note="Rows 1-3 are calculus identities (d sqrt(V1)/dt, the ODE solution, its initial value); the rows that "
             "matter are y(t_max) = 0 and T_max = delta t_max.  The comparison-lemma step (y-dot <= -a - b y => "
             "y <= eq. 38) is not checked.  It assumes a = gamma kappa1^2 - delta sigma > 0, which the sec. 7 gains "
             "violate (c001.eso.gain_condition)."),
    _cl("eso.gain_condition", P1, "spacecraft", "37, sec. 7",
        "delta <= gamma kappa1^2/sigma with the paper's ESO gains and its eq. 67 disturbance rate",
        _gain_condition, about="paper",
        note="Fails at every true anomaly: eq. 67's torque alone makes |alpha_omega| = 0.85..1.17e-7 rad/s^3, "
             "while with Q_i = I the condition admits |alpha| <= 1.6e-15 rad/s^3 for the gains rpo flies "
             "(k1 = 1e-4, k2 = 1.6e-9, the printed values with their lost minus signs) and 3.8e-8 rad/s^3 for "
             "the printed 1e4, 1.6e9.  Q_i = I justifies the scale of Q, not its shape; optimising over the shape "
             "of Q_i (review scratch script) the largest admissible C is 1.88e-15 rad/s^3 for rpo's gains "
             "(1.57e-15 at Q = I) and 3.83e-8 for the printed ones (Q = I optimal): the verdict stands for every "
             "Q_i.  Proposition 1 is sufficient only; rpo's ESO still tracks d^S in "
             "simulation (docs/controllers/c001.md), the Lyapunov bound does not cover that."),
    # ---- Proposition 2, abstract layer: any potential V_p with gradient g
    _cl("pose.V_definite", P2, "abstract", "53, 58",
        "V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V_d is positive definite in (Delta q, omega, Delta d)",
        _v_definite),
    _cl("pose.eq61", P2, "abstract", "61", "the proportional term of eq. 57 does no work (with eq. 15)", _eq61),
    _cl("pose.eq62", P2, "abstract", "62",
        "the gyroscopic and transport terms of eqs. 21 and 57 do no work", _eq62),
    _cl("pose.Vdot_eq60", P2, "abstract", "59-60",
        "V-dot along eqs. 15, 21 under eq. 57 equals the printed eq. 60", _vdot_eq60, about="paper",
        note="Eq. 60 as printed with its lost signs reconstructed (the reconstruction is the one that makes eq. 63 "
             "follow); the statement about rpo's law is c001.pose.Vdot_identity."),
    _cl("pose.Vdot_identity", P2, "abstract", "59-63",
        "V-dot = -k_d omega o omega + omega o (EJE Delta d) + k_v V_d-dot (eq. 63)", _vdot_identity),
    _cl("pose.eq63_first_line", P2, "abstract", "63",
        "printed first line of eq. 63: (E omega) o (-k_v (E omega) + J_E Dd) + k_p V_d-dot",
        _eq63_printed, corrected=_eq63_first_line_corrected,
        correction="(E omega) o (-k_d (E omega) + J_E Delta d) + k_v V_d-dot (the second line of eq. 63 is right)",
        note="Typo in the paper (not the extraction): k_v for k_d in the damping term and k_p for k_v in front of "
             "V_d-dot; the next line of eq. 63 has the right coefficients."),
    _cl("pose.Vd_decay", P2, "abstract", "text before 58, 63",
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
    _cl("pose.Vd_decay_rpo_gains", P2, "spacecraft", "text before 58, 37, sec. 7",
        "the corrected V_d-dot bound with the gains rpo flies (k1 = 1e-4, k2 = 1.6e-9) and eq. 67's |alpha|",
        lambda: _vd_decay_fixed("reconstructed"), about="paper",
        note="Fails: eq. 37's condition is violated by ~1e8 (c001.eso.gain_condition), and the bound itself "
             "fails at small errors (|eta| ~ 1e-6)."),
    _cl("pose.Vd_decay_printed_gains", P2, "spacecraft", "text before 58, 37, sec. 7",
        "the corrected V_d-dot bound with the printed gains (1e4, 1.6e9) and eq. 67's |alpha|",
        lambda: _vd_decay_fixed("printed"), about="paper",
        note="Eq. 37's condition fails by 2.2-3x for these gains, but the bound it is used for was not disproved "
             "numerically (the condition is sufficient only): the search over |eta1| <= 1e-3, |eta2| <= 1e-6 and "
             "smaller scales found no violation."),
    _cl("pose.composed", P2, "abstract", "32-37, 57-64",
        "V = 2 k_p V_p + omega o (EJE omega)/2 + k_v V1 along (q, omega, omega_hat, d_hat, d) under eqs. 57 and 23: "
        "V-dot <= -X^T H X", _composed,
        note="The corrected chain composed: V_d := V1 of Prop. 1 differentiated along the code's ESO on the joint "
             "state, D = 2 chi kappa2 lambda_min(P)/delta; needs eq. 37's condition (not met by the sec. 7 gains)."),
    _cl("pose.equilibrium", P2, "abstract", "57, 21, end of the proof of Prop. 2",
        "at omega = 0, Delta d = 0: omega-dot = -k_p J_E^-1 vec(q* (E grad V_p))", _equilibrium_acc),
    _cl("pose.barrier", APF, "spacecraft", "52-53, after 64",
        f"Delta q o Delta q >= {BARRIER_MIN:g} on beta_FOV = 0 and beta_CA = 0 (so V_p bounded => beta > 0)",
        _barrier, about="paper",
        note="Holds with the paper's q_D/T, r_D/T; the step also needs V non-increasing, which rpo's fov_eps term "
             "(c001.pose.Vdot_apf) and the saturation (c001.pose.saturation_impl) do not guarantee."),
    _cl("pose.H_definite", P2, "spacecraft", "63-64",
        "eq. 64: -V-dot bound = X^T H X > 0 for k_d = 2 and k_v above max J_i^2/(4 k_d D_i)", _h_definite),
    _cl("pose.saturation", P2, "spacecraft", "57, 63, sec. 7",
        "eq. 63 with the force and torque limits of sec. 7 (rpo clips eq. 57 per axis)", _saturated_identity,
        about="paper",
        note="Drawn on consistent states (f_G, omega_S/I, d_hat from one Table 1 orbit state; g the APF gradient "
             "at an admissible pose; sec. 7 gains).  "
             "The proof assumes the unsaturated eq. 57; with the sec. 7 limits (0.75 N, 2 mN m per axis) "
             "V-dot differs by (E omega) o (sat(f_C) - f_C) (c001.pose.saturation_impl), e.g. when k_d |v| > 0.75 N.  "
             "In rpo's scenario saturation is active in the first minutes only (0.14 % / 0.23 % of the steps, "
             "docs/controllers/c001.md)."),
    _cl("pose.saturation_impl", P2, "spacecraft", "57, 63, sec. 7",
        "rpo's clipped law: V-dot = eq. 63 + (E omega) o (sat(f_C) - f_C)", None, corrected=_saturated_impl,
        correction="the saturation term (E omega) o (sat(f_C) - f_C) is not sign-definite; the proof does not "
                   "cover it"),
    # ---- Proposition 2, spacecraft layer: the APF of eqs. 51-55
    _cl("apf.gradient", APF, "spacecraft", "53-55",
        "the gradient of eq. 54 with eq. 55 is the derivative of V_p (eq. 53) with eqs. 46, 48",
        lambda: _gradient_statement(True), corrected=lambda: _gradient_statement(False),
        correction="rpo writes eq. 54 without the 0/0 division (2 (k_a + k_r (1/b_F + 1/b_C)) [q_D*]^T Dq) and "
                   "eq. 55 as -2 K_u q - cot(theta)(4 q - 2 b_T K_u q)/sqrt(s) (same value); with fov_eps > 0 "
                   "the denominator is sqrt(s + fov_eps^2): see c001.pose.Vdot_apf",
        note="Signs as reconstructed (the extraction lost them); the printed forms equal the derivative off the "
             "camera axis (s = |U r|^2 > 0) and away from the goal (Delta q != 0)."),
    _cl("pose.Vdot_apf", APF, "spacecraft", "53-63",
        "V-dot along the loop with the APF and the coded gradient: eq. 63 (plus rpo's fov_eps term)",
        lambda: _vdot_apf(False), corrected=lambda: _vdot_apf(True),
        correction="rpo's law (fov_eps > 0): V-dot = eq. 63 + R_eps, R_eps = k_p k_r cot(theta) (Dq o Dq)/b_F^2 "
                   "(1/sqrt(s) - 1/sqrt(s + eps^2)) s-dot, s = |U r|^2",
        note="With the exact gradient (fov_eps = 0, the paper) eq. 63 holds for the APF.  rpo's regularisation "
             "makes the law the gradient of nothing: R_eps is sign-indefinite, vanishes for |U r| >> fov_eps = 1 mm "
             "(relative size eps^2/(2 s)) and is bounded near the camera axis; the proof does not cover it."),
    _cl("apf.convex", APF, "spacecraft", "56", "the Hessian of V_p is positive definite on the admissible set "
        "(k_a >> k_r)", _convex, about="paper",
        note="Eq. 56 is not implemented in rpo (it serves only this argument); the Hessian here is SymPy's, of the "
             "coded eq. 53.  Its indefinite terms are unbounded on the admissible set: v^T (grad^2 V_p) v = -1.6e6 "
             "3.8 m from the target with the target 1.5 cm off the camera axis (terms ~ 1/|U r|; on the axis, "
             "where the paper starts and ends, V_p is not twice differentiable), and -3.5e4 at 49 m with "
             "beta_FOV = 1e-4 m (terms ~ 1/beta^2), so no ratio k_a/k_r makes it positive definite.  The proof used "
             "convexity only for a unique minimum, i.e. that vec(q* (E grad V_p)) = 0 forces q_S/T = q_D/T; see "
             "c001.apf.unique_minimum (convexity in R^8 would not give that on the unit dual quaternions anyway).  "
             "Not only near the boundary: v^T (grad^2 V_p) v = -0.052 at |r| = 10 m with the target 10-90 % of the "
             "cone off-axis (review); on |r| in [40, 300] m, 20-80 % of the cone it held (c001.apf.convex_far)."),
    _cl("apf.convex_far", APF, "spacecraft", "56", "the Hessian of V_p is positive definite for |r| in [40, 300] m, "
        "20-80 % of the cone off-axis", _convex_far, about="paper",
        note="The region where eq. 56 was not disproved (review: min 2.2e-3); see c001.apf.convex for where it fails."),
    _cl("apf.unique_minimum", APF, "spacecraft", "53, end of the proof of Prop. 2",
        "vec(q* (E grad V_p)) = 0 only at q_S/T = q_D/T", _unique_minimum, about="paper",
        note="q_S/T = -q_D/T (the same physical pose, the other sign of the dual quaternion) shifted ~1e-7 m "
             "radially is also a critical point: Delta q = q_E - 1 is not sign-invariant, V_p ~ 4 k_a there "
             "(a maximum along the attitude directions).  It is an equilibrium of the closed loop with Delta d = 0, "
             "so the convergence to q_D/T is not global; from q_E,w < 0 the loop heads for q_E = +1, the long way "
             "round (unwinding).  rpo: the scenario starts at q_E,w = 0.76 (docs/controllers/c001.md)."),
]


# --------------------------------------------------------------------------- mutations

def _minus_gyro(out, q, grad, w_ST, w_TI_S, J, *rest):
    return out - c.gyroscopic_dual_force(J, w_TI_S)


def _minus_fG(out, q, grad, w_ST, w_TI_S, J, f_G, *rest):
    return out + f_G


def _minus_dhat(out, q, grad, w_ST, w_TI_S, J, f_G, d_hat, *rest):
    return out + c.J_E_times(J, d_hat)


def _eso_without_dhat(out, model_acc, w_meas, w_hat, d_hat, *rest):
    return out[0] - d_hat, out[1]


def _phi_sign_flip(out, x, kappa1, kappa2):
    sgn = x.applyfunc(sp.sign) if isinstance(x, sp.MatrixBase) else sp.sign(x)
    return out - kappa1**2 * sgn          # + kappa1^2/2 sign -> - kappa1^2/2 sign


def _model_without_transport(out, J, f_G, f_applied, w_SI, w_ST):
    return out - c.dq_cross(w_ST, w_SI)


def _model_without_fG(out, J, f_G, f_applied, w_SI, w_ST):
    return out - c.J_E_inv_times(J, f_G)


_LAW = ("c001.pose.Vdot_eq60", "c001.pose.Vdot_identity")
_ESO = ("c001.eso.error_dynamics", "c001.eso.time_scaling")

MUTATIONS = [
    Mutation("c001: +k_d (E omega) in eq. 57", c, "control_dual_force", scale_argument("k_d", -1), _LAW),
    Mutation("c001: +k_p vec(q* (E grad V_p)) in eq. 57", c, "control_dual_force", scale_argument("k_p", -1),
             _LAW + ("c001.pose.eq61",)),
    Mutation("c001: eq. 57 without omega_T/I x (J_E omega_T/I)", c, "control_dual_force",
             replace_output(_minus_gyro), _LAW + ("c001.pose.eq62",)),
    Mutation("c001: eq. 57 without -f_G", c, "control_dual_force", replace_output(_minus_fG), _LAW),
    Mutation("c001: eq. 57 without -J_E d_hat", c, "control_dual_force", replace_output(_minus_dhat), _LAW),
    Mutation("c001: eq. 54 with -k_r (sign of the repulsive gradient)", c, "apf_gradient",
             scale_argument("k_r", -1), ("c001.apf.gradient", "c001.pose.Vdot_apf")),
    Mutation("c001: eq. 55 grad beta_FOV negated", c, "grad_beta_fov", negate_output(), ("c001.apf.gradient",)),
    Mutation("c001: ESO -K1 Theta (eq. 23, gain x -1)", c, "eso_rates", scale_argument("K1", -1),
             _ESO + ("c001.eso.eta_dynamics", "c001.eso.V1dot_identity")),
    Mutation("c001: ESO -K2 Phi (eq. 23, gain x -1)", c, "eso_rates", scale_argument("K2", -1),
             _ESO + ("c001.eso.eta_dynamics", "c001.eso.V1dot_identity")),
    Mutation("c001: ESO without d_hat in omega_hat-dot (eq. 23)", c, "eso_rates",
             replace_output(_eso_without_dhat), _ESO + ("c001.eso.eta_dynamics",)),
    Mutation("c001: ESO model without omega_S/T x omega_S/I (eq. 23)", c, "eso_model_acceleration",
             replace_output(_model_without_transport), ("c001.eso.error_dynamics", "c001.pose.composed")),
    Mutation("c001: ESO model without f_G (eq. 23)", c, "eso_model_acceleration", replace_output(_model_without_fG),
             ("c001.eso.error_dynamics", "c001.pose.composed")),
    Mutation("c001: applied force without the torque limit", c, "applied_dual_force",
             replace_output(lambda out, f_C, F_max, tau_max: c.dual_force(c.dq_parts3(out)[0], c.dq_parts3(f_C)[1])),
             ("c001.pose.saturation_impl",)),
    Mutation("c001: Theta without kappa2 x (eq. 24)", c, "sta_theta",
             drop_terms(lambda: sp.Symbol("kappa_2", positive=True)),
             _ESO + ("c001.eso.phi_w_theta", "c001.eso.eta_dynamics")),
    Mutation("c001: Phi with -kappa1^2/2 sign(x) (eq. 24)", c, "sta_phi", replace_output(_phi_sign_flip),
             _ESO + ("c001.eso.phi_w_theta",)),
]
