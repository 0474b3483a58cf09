"""001: dual-quaternion pose control with a super-twisting ESO and a FOV/collision APF.

Zheng, Zhang, Wang, Fan, "Pose-Constrained Control of Proximity Maneuvering for Tracking and
Observing Noncooperative Targets with Unknown Acceleration", Aerospace 11 (2024) 828.

Storage (rpo convention, ``docs/conventions.md``): a quaternion is ``[x, y, z, w]`` (Hamilton,
scalar LAST); a dual quaternion is the 8-vector ``[real (4); dual (4)]``.  The paper writes
scalar first; its quaternions are Hamilton with ``v_I = q v_B q*`` (001 eq. 5), i.e. rpo's
meaning of ``q_B_A``, so only the storage order differs.  The paper's "dual vectors" (dual
velocity, dual force) are pure dual quaternions ``(0, a) + eps (0, b)``; stored as 8-vectors
with zero scalar slots (indices 3 and 7).

Frames: I = ECI, S = chaser ("service spacecraft") body, T = target body, D = desired frame.
``r_S/T`` is the position of the chaser relative to the target (chaser minus target, 001 eq.
13); the target centroid seen from the chaser is therefore at ``-r_S/T^S`` in chaser axes.

The text extraction of the paper lost most minus signs; every sign below was re-derived (see
``docs/controllers/c001.md``).  Each paper equation is one module-level function named for what
it computes, with the equation number; :class:`C001.law` only composes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import sympy as sp

from ..physics import actuators as act
from ..physics.layout import XYZ, XYZW, Bounds, Layout
from ..physics.rotations import (
    cross,
    dot,
    dq,
    dq_conj,
    dq_dual,
    dq_mul,
    dq_real,
    quat,
    quat_conj,
    quat_mul,
    quat_to_dcm,
)
from ..physics.special import Step
from . import command_layout

DEG = math.pi / 180
ANG_LIN = ("wx", "wy", "wz", "vx", "vy", "vz")


def _max0(a):
    """``max(a, 0) = a Step(a)``.  SymPy's ``Max``/``Min`` analyse their arguments on construction,
    which takes minutes on these expressions; :class:`Step` does nothing on construction and
    translates to a comparison in C."""
    return a * Step(a)


def _min1(a):
    """``min(a, 1) = a (1 - Step(a - 1)) + Step(a - 1)`` (exact on both branches)."""
    s = Step(a - 1)
    return a * (1 - s) + s


# =========================================================================== dual-quaternion algebra
# (001 section 2: the operations the paper defines; storage [x, y, z, w] per part)

def pure_dq(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Pure dual quaternion ``(0, a) + eps (0, b)`` (dual velocity, dual force, 001 eqs. 10, 17)."""
    return dq(quat(a, 0), quat(b, 0))


def dq_parts3(d: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """Vector parts (real, dual) of a dual quaternion, each a 3-vector."""
    return sp.Matrix(d[0:3]), sp.Matrix(d[4:7])


def dq_left_matrix(a: sp.Matrix) -> sp.Matrix:
    """8x8 matrix ``[[a]]`` with ``[[a]] b = a b`` (001 sec. 2, "matrix generation").

    Built as the (exact, constant) Jacobian of the product, so it inherits rpo's storage order.
    """
    x = sp.Matrix(sp.symbols("_b0:8", real=True))
    return dq_mul(a, x).jacobian(x)


def circle(a: sp.Matrix, b: sp.Matrix):
    """Circle product ``a o b = a_r . b_r + a_d . b_d`` (001 sec. 2): the 8-vector dot product."""
    return dot(a, b)


def dq_vec(a: sp.Matrix) -> sp.Matrix:
    """Vector part ``vec(a)``: both scalar slots set to zero (001 sec. 2)."""
    return sp.Matrix([a[0], a[1], a[2], 0, a[4], a[5], a[6], 0])


def dq_swap(a: sp.Matrix) -> sp.Matrix:
    """``E a`` with ``E = [[0, I4], [I4, 0]]`` (001 sec. 3.4): swaps the real and dual parts."""
    return dq(dq_dual(a), dq_real(a))


def dq_cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """Dual cross product of pure dual quaternions: ``a_r x b_r + eps (a_r x b_d + a_d x b_r)``.

    (``a x b = (a b - b a)/2`` for pure dual quaternions, used in 001 eqs. 17 and 19.)
    """
    ar, ad = dq_parts3(a)
    br, bd = dq_parts3(b)
    return pure_dq(cross(ar, br), cross(ar, bd) + cross(ad, br))


def dq_to_body(q: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    """``q* v q``: a dual vector given in the reference frame, in the body frame (001 eq. 8)."""
    return dq_mul(dq_conj(q), dq_mul(v, q))


# =========================================================================== model (001 eqs. 6-21)

def unit_dq(q: sp.Matrix, r_ref: sp.Matrix) -> sp.Matrix:
    """Pose dual quaternion ``q + eps r^A q / 2`` (001 eq. 6), ``r^A`` in the reference frame A."""
    return dq(q, quat_mul(quat(r_ref, 0), q) / 2)


def position_from_dq(qd: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """Inverse of eq. 6 (001 eq. 7): ``(r^A, r^B) = (2 q_d q_r*, 2 q_r* q_d)`` vector parts, m."""
    qr, qdd = dq_real(qd), dq_dual(qd)
    rA = 2 * quat_mul(qdd, quat_conj(qr))
    rB = 2 * quat_mul(quat_conj(qr), qdd)
    return sp.Matrix(rA[0:3]), sp.Matrix(rB[0:3])


def dual_velocity_body(w_B: sp.Matrix, rdot_B: sp.Matrix) -> sp.Matrix:
    """Dual velocity in body axes ``omega^B + eps rdot^B`` (001 eq. 11; also eq. 12).

    ``omega^B`` [rad/s] is the body rate relative to I in body axes, ``rdot^B`` [m/s] the inertial
    velocity of the body origin expressed in body axes.
    """
    return pure_dq(w_B, rdot_B)


def pose_rate(q: sp.Matrix, w_body: sp.Matrix) -> sp.Matrix:
    """Pose kinematics ``q_dot = q w^B / 2`` (001 eqs. 11, 12 and, relative, 15)."""
    return dq_mul(q, w_body) / 2


def relative_pose(q_TI: sp.Matrix, q_SI: sp.Matrix) -> sp.Matrix:
    """``q_S/T = q_T/I* q_S/I`` (001 eq. 13): pose of the chaser relative to the target."""
    return dq_mul(dq_conj(q_TI), q_SI)


def relative_dual_velocity(w_SI_S: sp.Matrix, w_TI_T: sp.Matrix, q_ST: sp.Matrix) -> sp.Matrix:
    """``omega_S/T^S = omega_S/I^S - q_S/T* omega_T/I^T q_S/T`` (001 eq. 14 and below).

    Real part: relative angular velocity [rad/s]; dual part: ``C_ST d/dt(r_S/T^T)`` [m/s], the
    velocity of the chaser seen from the target body frame, in chaser axes.
    """
    return w_SI_S - dq_to_body(q_ST, w_TI_T)


def dual_inertia(m, M_diag: sp.Matrix) -> sp.Matrix:
    """Dual inertia ``J = diag(J_m, J_M)`` (001 eq. 16), 8x8 in rpo storage.

    ``J_m = diag(m I3, 1)``, ``J_M = diag(M, 1)`` (the unit scalar slots keep J invertible; they
    multiply zero scalar parts).  M is the principal inertia (diagonal) of 001 Sec. 7.
    """
    return sp.diag(m, m, m, 1, M_diag[0], M_diag[1], M_diag[2], 1)


def J_E_times(J: sp.Matrix, a: sp.Matrix) -> sp.Matrix:
    """``J_E a = J E a`` (001 sec. 3.4): dual momentum ``(m rdot) + eps (M omega)`` for a = omega."""
    return J * dq_swap(a)


def J_E_inv_times(J: sp.Matrix, f: sp.Matrix) -> sp.Matrix:
    """``J_E^-1 f = E J^-1 f``: dual force -> dual acceleration (angular real, linear dual)."""
    # element-wise: a SymPy product with the diagonal matrix spends minutes on the zero entries'
    # canonicalisation when f is the full closed-loop expression
    if not J.is_diagonal():
        raise ValueError("J_E^-1 f is written for the diagonal J_E of 001 sec. 3.4")
    return dq_swap(sp.Matrix([f[i] / J[i, i] for i in range(8)]))


def gyroscopic_dual_force(J: sp.Matrix, w: sp.Matrix) -> sp.Matrix:
    """``omega x (J_E omega)`` for ``omega = (0, w) + eps (0, v)`` (001 eqs. 17, 20, 21, 23, 57).

    Equals :func:`dq_cross` ``(omega, J_E omega) = (w x m v) + eps (w x M w + v x m v)`` with the
    identically zero ``v x m v`` left out.  In floating point that term is not zero: with the
    inertial velocity (7.6 km/s) it is ~3e-7 N m of round-off noise in the torque channel.
    """
    wr, wd = dq_parts3(w)
    return pure_dq(cross(wr, J[0, 0] * wd), cross(wr, sp.diag(J[4, 4], J[5, 5], J[6, 6]) * wr))


def dual_force(F: sp.Matrix, tau: sp.Matrix) -> sp.Matrix:
    """Dual force ``(0, F) + eps (0, tau)`` in body axes (001 eq. 17, f_C, f_D)."""
    return pure_dq(F, tau)


def gravity_dual_force(mu, m, M: sp.Matrix, r_S: sp.Matrix) -> sp.Matrix:
    """``f_G^S`` (001 eq. 18): point-mass gravity force and gravity-gradient torque, body axes.

    ``-mu m r/|r|^3 + eps 3 mu r x (M r)/|r|^5``, r = r_S/I^S the chaser position from the Earth's
    centre in chaser axes [m].  The extraction lost the force's minus sign (gravity attracts).
    """
    r2 = dot(r_S, r_S)
    rn = sp.sqrt(r2)
    return dual_force(-mu * m * r_S / (rn * r2), 3 * mu * cross(r_S, M * r_S) / (r2 * r2 * rn))


def inertial_dual_acceleration(J: sp.Matrix, w_SI: sp.Matrix, f_total: sp.Matrix) -> sp.Matrix:
    """``omega_dot_S/I^S = J_E^-1 (f - omega x (J_E omega))`` (001 eq. 17), body components."""
    return J_E_inv_times(J, f_total - gyroscopic_dual_force(J, w_SI))


def relative_dual_acceleration(J, f_G, f_D, f_C, w_SI, w_ST, q_ST, wdot_TI_T) -> sp.Matrix:
    """Relative dynamics (001 eq. 20, with eq. 19).

    ``omega_dot_S/T^S = J_E^-1 (f_G + f_D + f_C - omega_S/I x (J_E omega_S/I))
    - q_S/T* omega_dot_T/I^T q_S/T + omega_S/T x omega_S/I`` (signs re-derived from eq. 19).
    """
    return (J_E_inv_times(J, f_G + f_D + f_C - gyroscopic_dual_force(J, w_SI))
            - dq_to_body(q_ST, wdot_TI_T) + dq_cross(w_ST, w_SI))


def integrated_disturbance(J, f_D, q_ST, wdot_TI_T) -> sp.Matrix:
    """``d^S = J_E^-1 f_D^S - q_S/T* omega_dot_T/I^T q_S/T`` (001 text under eq. 21)."""
    return J_E_inv_times(J, f_D) - dq_to_body(q_ST, wdot_TI_T)


def relative_dual_acceleration_lumped(J, f_G, f_C, w_SI, w_ST, d) -> sp.Matrix:
    """001 eq. 21: ``J_E^-1 (f_G + f_C - omega_S/I x (J_E omega_S/I)) + omega_S/T x omega_S/I + d``."""
    return (J_E_inv_times(J, f_G + f_C - gyroscopic_dual_force(J, w_SI))
            + dq_cross(w_ST, w_SI) + d)


def target_inertial_dual_velocity(w_SI: sp.Matrix, w_ST: sp.Matrix) -> sp.Matrix:
    """``omega_T/I^S = omega_S/I^S - omega_S/T^S`` (001 eq. 14 rearranged): the target's inertial dual
    velocity in chaser axes, the argument of the law's gyroscopic term (eq. 57)."""
    return w_SI - w_ST


def eso_model_acceleration(J, f_G, f_applied, w_SI, w_ST) -> sp.Matrix:
    """Known part of eq. 21 that drives the ESO (001 eq. 23): ``J_E^-1 (f_G + f - omega_S/I x (J_E omega_S/I))
    + omega_S/T x omega_S/I`` with f the dual force actually applied (the saturated command)."""
    return J_E_inv_times(J, f_G + f_applied - gyroscopic_dual_force(J, w_SI)) + dq_cross(w_ST, w_SI)


# =========================================================================== ESO (001 eqs. 23-24)

def sig_pow(x, k):
    """``sgn(x) |x|^k`` (001 sec. 2, ``sign^k``), elementwise on a Matrix or a scalar."""
    if isinstance(x, sp.MatrixBase):
        return x.applyfunc(lambda e: sig_pow(e, k))
    return sp.sign(x) * sp.Abs(x) ** k


def sta_theta(x, kappa1, kappa2):
    """``Theta(x) = kappa1 sign^(1/2)(x) + kappa2 x`` (001 eq. 24), elementwise."""
    return kappa1 * sig_pow(x, sp.Rational(1, 2)) + kappa2 * x


def sta_phi(x, kappa1, kappa2):
    """``Phi(x) = kappa1^2/2 sign(x) + 3/2 kappa1 kappa2 sign^(1/2)(x) + kappa2^2 x`` (001 eq. 24)."""
    sgn = x.applyfunc(sp.sign) if isinstance(x, sp.MatrixBase) else sp.sign(x)
    return (kappa1**2 / 2 * sgn + sp.Rational(3, 2) * kappa1 * kappa2 * sig_pow(x, sp.Rational(1, 2))
            + kappa2**2 * x)


def eso_rates(model_acc, w_meas, w_hat, d_hat, K1, K2, delta, kappa1, kappa2):
    """Super-twisting ESO (001 eq. 23), elementwise over the components of the dual velocity.

    ``w_hat_dot = model_acc + d_hat + K1 Theta(dw/delta)``, ``d_hat_dot = K2 Phi(dw/delta)/delta``
    with ``dw = w_meas - w_hat`` and ``model_acc = J_E^-1 (f_G + f_C - omega_S/I x (J_E omega_S/I))
    + omega_S/T x omega_S/I`` (the known part of eq. 21).  ``K1``, ``K2`` are the diagonals, as
    column matrices of the same length as ``w_hat``.  Returns ``(w_hat_dot, d_hat_dot)``.
    """
    x = (w_meas - w_hat) / delta
    th = sta_theta(x, kappa1, kappa2)
    ph = sta_phi(x, kappa1, kappa2)
    w_hat_dot = model_acc + d_hat + sp.Matrix([K1[i] * th[i] for i in range(len(th))])
    d_hat_dot = sp.Matrix([K2[i] * ph[i] for i in range(len(ph))]) / delta
    return w_hat_dot, d_hat_dot


# =========================================================================== constraints (001 eqs. 40-48)

def fov_vertex_offset(z_N, R_T, theta):
    """``z_N' = z_N + R_T / sin(theta)`` (001 eq. 40): apex of the cone the target centre must stay in, m."""
    return z_N + R_T / sp.sin(theta)


def beta_fov_vector(r_ST_S: sp.Matrix, theta, z_Np):
    """FOV constraint (001 eq. 41), ``> 0`` when the target sphere is inside the camera cone, m.

    Camera along +z_S.  The target centre is at ``p = -r_S/T^S`` from the chaser, so
    ``beta_FOV = u.p - cot(theta) |U p| - z_N' = -u.r - cot(theta) |U r| - z_N'``.  The printed
    eq. 41 shows ``u . r`` without its sign (extraction); the minus is confirmed by the printed
    gradient (eq. 55), whose denominator ``beta_FOV + beta_T + z_N'`` only equals
    ``-cot(theta) |U r|`` with this sign.
    """
    u_r = r_ST_S[2]
    rho = sp.sqrt(r_ST_S[0] ** 2 + r_ST_S[1] ** 2)
    return -u_r - rho / sp.tan(theta) - z_Np


def camera_axis_matrix(u: sp.Matrix) -> sp.Matrix:
    """``K_u = [[0, [q_u]^T], [[q_u], 0]]`` (001 eqs. 43-44), 8x8 symmetric.

    ``[q_u]`` is the 4x4 matrix of right multiplication by ``q_u = (0, u)``: ``q q_u = [q_u] q``
    (eq. 43).  ``q o (K_u q) = 2 q_d . (q_r q_u) = u . r_S/T^S`` (eq. 44).
    """
    x = sp.Matrix(sp.symbols("_q0:4", real=True))
    R = quat_mul(x, quat(u, 0)).jacobian(x)
    Z = sp.zeros(4, 4)
    return sp.Matrix(sp.BlockMatrix([[Z, R.T], [R, Z]]))


def beta_T(q: sp.Matrix, K_u: sp.Matrix):
    """``beta_T = q o (K_u q) = u . r_S/T^S`` (001 eqs. 44, 46), m."""
    return circle(q, K_u * q)


def off_axis_sq(q: sp.Matrix, bT):
    """``|U r_S/T^S|^2 = 4 (q o q - 1) - beta_T^2`` (001 eq. 45), m^2."""
    return 4 * (circle(q, q) - 1) - bT**2


def beta_fov_dq(q: sp.Matrix, K_u: sp.Matrix, theta, z_Np):
    """FOV constraint in the dual quaternion (001 eq. 46), m; equals :func:`beta_fov_vector`.

    ``beta_FOV = -beta_T - cot(theta) sqrt(4 (q o q - 1) - beta_T^2) - z_N'`` (signs as eq. 41).
    ``max(., 0)`` guards the square root against round-off on the camera axis, where the
    argument is an exact zero.
    """
    bT = beta_T(q, K_u)
    return -bT - sp.sqrt(_max0(off_axis_sq(q, bT))) / sp.tan(theta) - z_Np


def beta_ca_vector(r_ST_S: sp.Matrix, R_S, R_T):
    """Collision-avoidance constraint ``|r|^2 - (R_S + R_T)^2`` (001 eq. 47), m^2."""
    return dot(r_ST_S, r_ST_S) - (R_S + R_T) ** 2


def beta_ca_dq(q: sp.Matrix, R_S, R_T):
    """Collision avoidance in the dual quaternion, ``4 (q o q - 1) - (R_S + R_T)^2`` (001 eq. 48), m^2."""
    return 4 * (circle(q, q) - 1) - (R_S + R_T) ** 2


def grad_beta_fov(q: sp.Matrix, K_u: sp.Matrix, theta, eps):
    """Gradient of eq. 46 with respect to the 8-vector q (001 eq. 55), m.

    ``-2 K_u q - cot(theta) (4 q - 2 beta_T K_u q) / sqrt(s)``, s = eq. 45.  The paper writes
    ``1/sqrt(s)`` as ``-cot(theta)/(beta_FOV + beta_T + z_N')``, the same quantity.  The cone is
    not differentiable on its axis (s = 0, where the printed form is 0/0, e.g. at the paper's
    t = 0 with the camera "exactly towards the target"); rpo uses ``sqrt(s + eps^2)`` in the
    denominator only (eps in m; exact for s >> eps^2, zero on the axis).
    """
    bT = beta_T(q, K_u)
    Kq = K_u * q
    s = off_axis_sq(q, bT)
    return -2 * Kq - (4 * q - 2 * bT * Kq) / (sp.tan(theta) * sp.sqrt(_max0(s) + eps**2))


def grad_beta_ca(q: sp.Matrix):
    """Gradient of eq. 48: ``8 q`` (001 eq. 55), m."""
    return 8 * q


# =========================================================================== APF and law (001 eqs. 49-57)

def desired_pose(q_DT: sp.Matrix, r_DT_T: sp.Matrix) -> sp.Matrix:
    """``q_D/T = q_D/T + eps r_D/T^T q_D/T / 2`` (001 eq. 49), r in target axes [m]."""
    return unit_dq(q_DT, r_DT_T)


def pose_error(qd_DT: sp.Matrix, q_ST: sp.Matrix) -> sp.Matrix:
    """``q_E = q_D/T* q_S/T = [[q_D/T*]] q_S/T`` (001 eq. 50)."""
    return dq_mul(dq_conj(qd_DT), q_ST)


def pose_error_offset(q_E: sp.Matrix) -> sp.Matrix:
    """``Delta q = q_E - 1`` (001 text under eq. 51), 1 = identity dual quaternion."""
    return q_E - sp.Matrix([0, 0, 0, 1, 0, 0, 0, 0])


def apf_attractive(dq_err: sp.Matrix, k_a):
    """``V_a = k_a Delta q o Delta q`` (001 eq. 51)."""
    return k_a * circle(dq_err, dq_err)


def apf_repulsive(dq_err: sp.Matrix, k_r, b_fov, b_ca):
    """``V_r = k_r Delta q o Delta q (1/beta_FOV + 1/beta_CA)`` (001 eq. 52)."""
    return k_r * circle(dq_err, dq_err) * (1 / b_fov + 1 / b_ca)


def apf(dq_err: sp.Matrix, k_a, k_r, b_fov, b_ca):
    """Global APF ``V_p = V_a + V_r`` (001 eq. 53)."""
    return apf_attractive(dq_err, k_a) + apf_repulsive(dq_err, k_r, b_fov, b_ca)


def apf_gradient(dq_err, qd_DT, k_a, k_r, b_fov, b_ca, g_fov, g_ca) -> sp.Matrix:
    """``grad V_p`` with respect to q_S/T (001 eq. 54).

    ``2 (k_a + k_r (1/beta_FOV + 1/beta_CA)) [[q_D/T*]]^T Delta q
    - k_r (Delta q o Delta q) (grad beta_FOV / beta_FOV^2 + grad beta_CA / beta_CA^2)``.
    The paper writes the first factor as ``V_p / (Delta q o Delta q)``, which is 0/0 at the goal;
    this is the same quantity without the division.
    """
    L = dq_left_matrix(dq_conj(qd_DT))
    gain = k_a + k_r * (1 / b_fov + 1 / b_ca)
    return 2 * gain * (L.T * dq_err) - k_r * circle(dq_err, dq_err) * (g_fov / b_fov**2 + g_ca / b_ca**2)


def control_dual_force(q_ST, grad_Vp, w_ST, w_TI_S, J, f_G, d_hat, k_p, k_d) -> sp.Matrix:
    """PD-like law (001 eq. 57), dual force in chaser axes (real: force N, dual: torque N m).

    ``f_C = -k_p vec(q_S/T* (E grad V_p)) - k_d (E omega_S/T) + omega_T/I x (J_E omega_T/I)
    - f_G - J_E d_hat``.  Signs (lost in extraction) re-derived from eqs. 60-63: with them
    ``dV/dt = -k_d omega o omega + omega o (EJE Delta d) + ...`` (eq. 63).
    """
    return (-k_p * dq_vec(dq_mul(dq_conj(q_ST), dq_swap(grad_Vp))) - k_d * dq_swap(w_ST)
            + gyroscopic_dual_force(J, w_TI_S) - f_G - J_E_times(J, d_hat))


def saturate(x: sp.Matrix, limit) -> sp.Matrix:
    """Per-axis actuator limit ``[-limit, limit]`` (001 sec. 7: 2 mN m, 750 mN): rpo's one saturation."""
    return act.saturate(x, limit)


def applied_dual_force(f_C: sp.Matrix, F_max, tau_max) -> sp.Matrix:
    """The dual force rpo applies: eq. 57's force and torque clipped per axis (001 sec. 7 limits)."""
    F_raw, tau_raw = dq_parts3(f_C)
    return dual_force(saturate(F_raw, F_max), saturate(tau_raw, tau_max))


def apf_terms(q, q_D, r_D, k_a, k_r, theta, z_N, R_S, R_T, fov_eps) -> dict:
    """Constraints, APF and its gradient at the pose q_S/T (001 eqs. 40, 44-55), camera along +z_S.

    Returns ``q_E``, ``dq_err``, ``b_fov``, ``b_ca``, ``V_p``, ``grad`` (the gradient of eq. 54 with
    rpo's eq. 55, regularised by ``fov_eps``)."""
    K_u = camera_axis_matrix(sp.Matrix([0, 0, 1]))
    z_Np = fov_vertex_offset(z_N, R_T, theta)
    b_fov = beta_fov_dq(q, K_u, theta, z_Np)
    b_ca = beta_ca_dq(q, R_S, R_T)
    g_fov = grad_beta_fov(q, K_u, theta, fov_eps)
    g_ca = grad_beta_ca(q)
    qd = desired_pose(q_D, r_D)
    q_E = pose_error(qd, q)
    dq_err = pose_error_offset(q_E)
    return {"q_E": q_E, "dq_err": dq_err, "b_fov": b_fov, "b_ca": b_ca,
            "V_p": apf(dq_err, k_a, k_r, b_fov, b_ca),
            "grad": apf_gradient(dq_err, qd, k_a, k_r, b_fov, b_ca, g_fov, g_ca)}


# =========================================================================== measurement -> paper variables

def target_relative_velocity(C_TL, v_L, r_T, w_t, n):
    """``d/dt r_S/T^T`` [m/s] from the LVLH relative state (000 eq. 30 variables).

    ``r^T = C_TL r^L`` with T rotating relative to LVLH at ``w_t - C_TL (0, 0, n)``:
    ``d/dt r^T = C_TL v^L - (w_t - C_TL n z_L) x r^T``.
    """
    w_TL = w_t - C_TL * sp.Matrix([0, 0, n])
    return C_TL * v_L - cross(w_TL, r_T)


def chaser_inertial_in_lvlh(r_t, r_t_dot, n, r_L, v_L):
    """Chaser position and inertial velocity from the Earth's centre, LVLH components.

    ``R = (r_t, 0, 0) + r``, ``V = (r_t_dot, r_t n, 0) + v + (0, 0, n) x r`` (LVLH X radial,
    Z orbit normal, rotating at n = nu_dot).
    """
    R = sp.Matrix([r_t + r_L[0], r_L[1], r_L[2]])
    V = sp.Matrix([r_t_dot + v_L[0] - n * r_L[1], r_t * n + v_L[1] + n * r_L[0], v_L[2]])
    return R, V


@dataclass
class C001:
    """001's ESO + APF + PD-like pose controller (the paper's values as defaults)."""

    name: str = "c001"
    k: Layout = field(default_factory=lambda: Layout("k"))
    xc: Layout = field(default_factory=lambda: Layout("xc"))
    diag: Layout = field(default_factory=lambda: Layout("diag"))

    def __post_init__(self):
        k = self.k
        # control law and APF (001 sec. 7)
        k.add("k_p", 1, "-", "PD-like proportional gain k_p (001 eq. 57)", default=0.005,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k_d", 1, "-", "PD-like derivative gain k_d: N s/m and N m s (001 eq. 57)", default=2.0,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k_a", 1, "-", "attractive APF coefficient (001 eq. 51)", default=0.75,
              bounds=Bounds(0.0, 1e3, why="an attractive coefficient, >= 0"))
        k.add("k_r", 1, "-", "repulsive APF coefficient (001 eq. 52; SI numbers: beta_FOV in m, beta_CA in m^2)",
              default=2.5e-5,
              bounds=Bounds(0.0, 1e3, why="a repulsive coefficient, >= 0"))
        # ESO (001 sec. 7; exponents negative: see docs/controllers/c001.md)
        k.add("kappa1", 1, "-", "STA gain kappa_1 (001 eq. 24)", default=0.7,
              bounds=Bounds(0.0, 2.0, lo_open=True, why="an STA exponent, > 0 (the paper's are 0.7, 0.8)"))
        k.add("kappa2", 1, "-", "STA gain kappa_2 (001 eq. 24)", default=0.8,
              bounds=Bounds(0.0, 2.0, lo_open=True, why="an STA exponent, > 0 (the paper's are 0.7, 0.8)"))
        k.add("delta", 1, "s", "ESO scaling delta (001 eq. 23)", default=0.001,
              bounds=Bounds(0.0, 10.0, lo_open=True, why="an ESO scaling time, > 0 (it divides)"))
        k.add("K1", 6, "-", "ESO gains k12..k14 (angular), k16..k18 (linear) (001 eq. 23)", ANG_LIN,
              default=(1.0e-4,) * 3 + (1.5e-3,) * 3,
              bounds=Bounds(0.0, 1e3, why="ESO gains, >= 0"))
        k.add("K2", 6, "-", "ESO gains k22..k24 (angular), k26..k28 (linear) (001 eq. 23)", ANG_LIN,
              default=(1.6e-9,) * 3 + (5.6e-7,) * 3,
              bounds=Bounds(0.0, 1e3, why="ESO gains, >= 0"))
        # nominal chaser model and geometry (001 sec. 7)
        k.add("m", 1, "kg", "nominal chaser mass", default=60.0,
              bounds=Bounds(1e-2, 1e7, why="a nominal mass, as the plant's masses"))
        k.add("M", 3, "kg m^2", "nominal chaser principal inertia", XYZ, default=(15.6, 10.8, 11.5),
              bounds=Bounds(1e-6, 1e10, why="nominal principal moments, as the plant's inertias"))
        k.add("R_S", 1, "m", "chaser envelope radius", default=2.1,
              bounds=Bounds(0.0, 1e3, why="an envelope radius"))
        k.add("R_T", 1, "m", "target envelope radius", default=1.5,
              bounds=Bounds(0.0, 1e3, why="an envelope radius"))
        k.add("theta", 1, "rad", "camera half field of view", default=45 * DEG,
              bounds=Bounds(0.0, math.pi / 2, lo_open=True, hi_open=True, why="a cone half angle"))
        k.add("z_N", 1, "m", "camera cone vertex on +z_S", default=1.2,
              bounds=Bounds(-100.0, 100.0, why="on the body, either side of its centre"))
        k.add("fov_eps", 1, "m", "regularisation of grad beta_FOV on the camera axis (rpo choice)",
              default=1e-3,
              bounds=Bounds(0.0, 10.0, lo_open=True, why="a regularisation length, > 0 (it divides)"))
        # desired pose (001 sec. 7; sign of q_D/T's y component reconstructed)
        k.add("q_D", 4, "-", "desired attitude q_D/T (scalar last)", XYZW,
              default=(0.0, -math.sqrt(0.5), 0.0, math.sqrt(0.5)),
              bounds=Bounds(-1.0, 1.0, why="quaternion components"))
        k.add("r_D", 3, "m", "desired position r_D/T^T, target axes", XYZ, default=(50.0, 0.0, 0.0),
              bounds=Bounds(-1e5, 1e5, why="a position, either sign, within 100 km"))
        # actuator limits in the law (001 sec. 7)
        k.add("tau_max", 1, "N m", "per-axis torque limit", default=2e-3,
              bounds=Bounds(0.0, 1e4, lo_open=True, why="an actuator limit, > 0, as the plant's"))
        k.add("F_max", 1, "N", "per-axis force limit", default=0.75,
              bounds=Bounds(0.0, 1e4, lo_open=True, why="an actuator limit, > 0, as the plant's"))

        x = self.xc
        x.add("w_hat", 3, "rad/s", "ESO estimate of omega_S/T^S, real part (chaser axes)", XYZ, default=(0, 0, 0))
        x.add("v_hat", 3, "m/s", "ESO estimate of omega_S/T^S, dual part (chaser axes)", XYZ, default=(0, 0, 0))
        x.add("dw_hat", 3, "rad/s^2", "ESO estimate of d^S, real part (angular)", XYZ, default=(0, 0, 0))
        x.add("dv_hat", 3, "m/s^2", "ESO estimate of d^S, dual part (linear)", XYZ, default=(0, 0, 0))

        d = self.diag
        d.add("att_err", 1, "rad", "rotation angle from the chaser body to the desired frame D")
        d.add("q_err", 4, "-", "attitude of the chaser relative to D (real part of q_E), scalar last", XYZW)
        d.add("pos_err", 3, "m", "r_S/T^T - r_D/T^T, target axes", XYZ)
        d.add("rate_err", 3, "rad/s", "omega_S/T in target axes", XYZ)
        d.add("vel_err", 3, "m/s", "d/dt r_S/T^T, target axes", XYZ)
        d.add("q_ST", 4, "-", "q_S/T (scalar last); Table 2 lists q_S/T - q_D/T", XYZW)
        d.add("beta_fov", 1, "m", "FOV constraint, dual-quaternion form (001 eq. 46)")
        d.add("beta_ca", 1, "m^2", "collision-avoidance constraint (001 eq. 48)")
        d.add("V_p", 1, "-", "global APF (001 eq. 53)")
        d.add("d_hat", 6, "rad/s^2 | m/s^2", "ESO disturbance estimate d^S (angular, linear), chaser axes", ANG_LIN)
        d.add("eso_err", 6, "rad/s | m/s", "omega_S/T^S - ESO estimate (angular, linear)", ANG_LIN)
        d.add("f_C", 6, "N | N m", "law output before saturation (force, torque), chaser axes",
              ("Fx", "Fy", "Fz", "tx", "ty", "tz"))

    # ------------------------------------------------------------------ measurement -> paper variables
    def paper_state(self, meas, p):
        """Dual-quaternion variables of 001 from the plant measurement (see module docstring)."""
        q_c, w_c, q_t, w_t = meas["q_c"], meas["w_c"], meas["q_t"], meas["w_t"]
        q_L, n = meas["q_L"], meas["n"]
        r_L, v_L = meas["r"], meas["v"]
        q_ST = quat_mul(quat_conj(q_t), q_c)
        C_TL = quat_to_dcm(quat_mul(quat_conj(q_t), q_L))  # C_{T<-L}
        C_SL = quat_to_dcm(quat_mul(quat_conj(q_c), q_L))  # C_{S<-L}
        C_ST = quat_to_dcm(q_ST).T                        # C_{S<-T}
        r_T = C_TL * r_L
        rdot_T = target_relative_velocity(C_TL, v_L, r_T, w_t, n)
        R_L, V_L = chaser_inertial_in_lvlh(meas["r_t"], meas["r_t_dot"], n, r_L, v_L)
        w_SI = dual_velocity_body(w_c, C_SL * V_L)                 # eq. 11
        w_ST = pure_dq(w_c - C_ST * w_t, C_ST * rdot_T)            # eq. 14 (closed form)
        w_TI_S = target_inertial_dual_velocity(w_SI, w_ST)        # omega_T/I^S
        return {"q_ST": unit_dq(q_ST, r_T), "q_ST_att": q_ST, "r_T": r_T, "rdot_T": rdot_T,
                "C_ST": C_ST, "r_SI_S": C_SL * R_L, "w_SI": w_SI, "w_ST": w_ST, "w_TI_S": w_TI_S}

    def law(self, meas, t, p):
        """(cmd, xc_dot, diag) as SymPy column matrices."""
        k, xc = self.k, self.xc
        s = self.paper_state(meas, p)
        q, w_SI, w_ST, w_TI_S = s["q_ST"], s["w_SI"], s["w_ST"], s["w_TI_S"]
        J = dual_inertia(k["m"], k["M"])
        f_G = gravity_dual_force(p["mu"], k["m"], sp.diag(*k["M"]), s["r_SI_S"])  # eq. 18

        # constraints, APF and its gradient (eqs. 40, 44-55)
        a = apf_terms(q, k["q_D"], k["r_D"], k["k_a"], k["k_r"], k["theta"], k["z_N"], k["R_S"], k["R_T"],
                      k["fov_eps"])
        q_E, b_fov, b_ca, V_p, grad = a["q_E"], a["b_fov"], a["b_ca"], a["V_p"], a["grad"]

        # ESO estimate of d (state) and the law (eq. 57), then the actuator limits
        w_hat = pure_dq(xc["w_hat"], xc["v_hat"])
        d_hat = pure_dq(xc["dw_hat"], xc["dv_hat"])
        f_C = control_dual_force(q, grad, w_ST, w_TI_S, J, f_G, d_hat, k["k_p"], k["k_d"])
        F_raw, tau_raw = dq_parts3(f_C)
        f_app = applied_dual_force(f_C, k["F_max"], k["tau_max"])
        F, tau = dq_parts3(f_app)

        # ESO (eq. 23) driven by the force and torque actually commanded
        model_acc = eso_model_acceleration(J, f_G, f_app, w_SI, w_ST)
        idx = [0, 1, 2, 4, 5, 6]  # vector slots; the scalar slots of pure dual quaternions stay 0
        K1, K2 = k["K1"], k["K2"]
        wh_dot, dh_dot = eso_rates(sp.Matrix([model_acc[i] for i in idx]), sp.Matrix([w_ST[i] for i in idx]),
                                   sp.Matrix([w_hat[i] for i in idx]), sp.Matrix([d_hat[i] for i in idx]),
                                   K1, K2, k["delta"], k["kappa1"], k["kappa2"])
        xc_dot = sp.Matrix.vstack(wh_dot, dh_dot)

        # diagnostics (target axes, as the paper's Table 2)
        C_TS = s["C_ST"].T
        q_err = dq_real(q_E)
        att_err = 2 * sp.acos(_min1(sp.Abs(q_err[3])))
        w_rel, _ = dq_parts3(w_ST)
        diag = self.diag.pack({
            "att_err": att_err, "q_err": q_err, "pos_err": s["r_T"] - k["r_D"],
            "rate_err": C_TS * w_rel, "vel_err": s["rdot_T"], "q_ST": s["q_ST_att"],
            "beta_fov": b_fov, "beta_ca": b_ca, "V_p": V_p,
            "d_hat": sp.Matrix.vstack(xc["dw_hat"], xc["dv_hat"]),
            "eso_err": sp.Matrix([w_ST[i] - w_hat[i] for i in idx]),
            "f_C": sp.Matrix.vstack(F_raw, tau_raw),
        })
        cmd = command_layout().pack({"tau_w": tau, "F": F, "tau_thr": sp.zeros(3, 1)})
        return cmd, xc_dot, diag


DESIGN = C001
