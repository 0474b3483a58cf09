"""Rigid-body attitude dynamics of the chaser (with reaction wheels) and the target (000 eqs. 1-3, 6, 10).

Wheel convention (see ``docs/conventions.md``): ``h_w`` holds each wheel's absolute axial
angular momentum I_w (a_i . omega + Omega_i) [N m s]; ``I_c`` is the chaser inertia without
the wheels' axial inertia; ``T_w`` is the reaction torque each wheel motor exerts on the body
about its axis [N m].  Then the body torque is T_c = A T_w (eq. 46) and dh_w/dt = -T_w, which is
eq. 6 with T_c = -dh_rw/dt, and total angular momentum and energy are exactly conserved when
no external torque acts (``tests/test_attitude.py``).
"""

from __future__ import annotations

from .rotations import cross, dot, quat_to_dcm


def solve3(M, b):
    """M^{-1} b for a 3x3 matrix via its adjugate (closed form, no pivoting branches)."""
    return M.adjugate() * b / M.det()


def chaser_angular_acceleration(I_c, omega, h_rw, T_c, M_ext):
    """omega_dot [rad/s^2] from I_c omega_dot = -S(omega) I_c omega - S(omega) h_rw + T_c + M (000 eq. 6).

    ``h_rw`` = A h_w is the wheels' momentum in body axes, ``T_c`` the wheel torque on the body,
    ``M_ext`` every other torque (gravity gradient, magnetic, random, thrusters) [N m].
    I_c is taken at the current time; like the paper, no dI/dt term (see docs/errata.md).
    """
    return solve3(I_c, -cross(omega, I_c * omega) - cross(omega, h_rw) + T_c + M_ext)


def target_angular_acceleration(I_t, omega, M_ext):
    """omega_dot [rad/s^2] from I_t omega_dot = -S(omega) I_t omega + M_tot_t (000 eq. 10)."""
    return solve3(I_t, -cross(omega, I_t * omega) + M_ext)


def wheel_momentum_rate(T_w):
    """dh_w/dt = -T_w [N m] (000 eq. 6, T_c = -dh_rw/dt, per wheel)."""
    return -T_w


def angular_momentum_inertial(q, I_c, omega, h_rw):
    """Total angular momentum in ECI, C_{I<-B}(q) (I_c omega + h_rw) [N m s] (000 eq. 2)."""
    return quat_to_dcm(q) * (I_c * omega + h_rw)


def kinetic_energy(I_c, omega, h_w, I_w):
    """Rotational kinetic energy 1/2 omega^T I_c omega + sum h_i^2 / (2 I_w) [J]."""
    return dot(omega, I_c * omega) / 2 + dot(h_w, h_w) / (2 * I_w)
