"""Relative attitude of the chaser body with respect to the target's interface frame (000 eqs. 15-29).

The interface frame i is the target body frame rotated by +180 deg about X_T (eqs. 15-16), so
that synchronising the chaser with i points the chaser's +Z docking axis along -Z_T.

Corrections (docs/errata.md):
* eq. 23 forms q_i = q_t^{-1} ⊗ q_{t->i}; composing attitudes gives q_i = q_t ⊗ q_{t->i}
  (Hamilton, scalar last).  The printed result [q_t4, q_t1, q_t2, q_t3] is not a rotation of
  q_t by 180 deg about X.
* eqs. 27 and 29 print I_t^{-1} C_t^c M_tot_t; eq. 26 with eq. 10 gives C_t^c I_t^{-1} M_tot_t
  (the target's torque acts through the target's inertia, in target axes, then is rotated).
"""

from __future__ import annotations

import sympy as sp

from .rigid_body import solve3
from .rotations import cross, quat_conj, quat_mul, quat_rate, quat_to_dcm

#: q_{i/t}: 180 deg about X_T (000 eq. 16), scalar last.
Q_INTERFACE_FROM_TARGET = sp.Matrix([1, 0, 0, 0])


def dcm_interface_from_target():
    """C_{i<-t} = diag(1, -1, -1) (000 eq. 15)."""
    return quat_to_dcm(Q_INTERFACE_FROM_TARGET).T


def interface_attitude(q_t):
    """Attitude of the interface frame relative to ECI, q_i = q_t ⊗ q_{i/t} (corrects 000 eq. 23)."""
    return quat_mul(q_t, Q_INTERFACE_FROM_TARGET)


def attitude_error(q_c, q_t):
    """q_e = q_i^{-1} ⊗ q_c: chaser body relative to the interface frame (000 eq. 22)."""
    return quat_mul(quat_conj(interface_attitude(q_t)), q_c)


def relative_attitude_target(q_c, q_t):
    """q_r = q_t^{-1} ⊗ q_c: chaser relative to target body (000 eq. 21); C_t^c = dcm(q_r)^T (eq. 20)."""
    return quat_mul(quat_conj(q_t), q_c)


def rate_error(q_e, omega_c, omega_t):
    """omega_e = omega_c - C_i^c omega_i, omega_i = C_t^i omega_t [rad/s], chaser axes (000 eqs. 17-19)."""
    return omega_c - quat_to_dcm(q_e).T * (dcm_interface_from_target() * omega_t)


def rate_error_dynamics(q_e, omega_e, omega_c, h_rw, I_c, I_t, T_c, M_c, M_t):
    """omega_e_dot [rad/s^2] (000 eqs. 26-28, with the corrected order C_t^c I_t^{-1} M_t).

    omega_e_dot = f(omega_rel) + I_c^{-1} (T_c + M_c) - C_t^c I_t^{-1} M_t, where
    f = -I_c^{-1}[S(w_c) I_c w_c + S(w_c) h_rw] - S(w_c) w_e + C_t^c I_t^{-1} S(w_t) I_t w_t,
    w_t = (C_t^c)^{-1} (w_c - w_e) and C_t^c = C_{c<-t} = C_{c<-i} C_{i<-t}.
    """
    C_ct = quat_to_dcm(q_e).T * dcm_interface_from_target()
    w_t = C_ct.T * (omega_c - omega_e)
    f = (
        -solve3(I_c, cross(omega_c, I_c * omega_c) + cross(omega_c, h_rw))
        - cross(omega_c, omega_e)
        + C_ct * solve3(I_t, cross(w_t, I_t * w_t))
    )
    return f + solve3(I_c, T_c + M_c) - C_ct * solve3(I_t, M_t)


def attitude_error_rate(q_e, omega_e):
    """q_e_dot = 1/2 q_e ⊗ [omega_e, 0] (000 eq. 24; its vector part is eq. 29's second row)."""
    return quat_rate(q_e, omega_e)
