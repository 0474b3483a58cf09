"""Nonlinear relative translation of the chaser about the target in the target's LVLH frame (000 eq. 30).

State: r_e = [x, y, z] (chaser minus target, LVLH components) [m] and its LVLH-frame derivative
v_e [m/s].  Exact for a Keplerian target orbit when ``n`` and ``n_dot`` are the LVLH rate and
its derivative (see :mod:`rpo.symbolic.physics.orbit` for the correction of eqs. 9 and 35).
"""

from __future__ import annotations

import sympy as sp

from .rotations import vec


def relative_acceleration(r_e, v_e, r_t, n, n_dot, mu, a_control, a_disturbance):
    """LVLH-frame second derivative of r_e [m/s^2] (000 eq. 30).

    ``a_control`` is C_c^LVLH F_c / m_c and ``a_disturbance`` is a_d (eq. 45), both in LVLH.
    r_c = |r_t X_L + r_e| is the chaser orbit radius.
    """
    x, y, z = r_e
    xd, yd, _zd = v_e
    r_c3 = ((r_t + x) ** 2 + y**2 + z**2) ** sp.Rational(3, 2)
    return vec(
        2 * n * yd + n**2 * x + n_dot * y + mu / r_t**2 - mu * (r_t + x) / r_c3,
        -2 * n * xd + n**2 * y - n_dot * x - mu * y / r_c3,
        -mu * z / r_c3,
    ) + a_control + a_disturbance


def chaser_inertial_state(r_t_eci, v_t_eci, C_IL, w_L, r_e, v_e):
    """Chaser ECI position and velocity from the target's and the LVLH relative state.

    r_c = r_t + C_IL r_e;  v_c = v_t + C_IL (v_e + w_L x r_e), with w_L the LVLH frame's rate
    relative to ECI in LVLH components: [0, 0, n] for a Keplerian target, [w_x, 0, n] for a
    perturbed one (:mod:`.target_orbit_state`).
    """
    return r_t_eci + C_IL * r_e, v_t_eci + C_IL * (v_e + w_L.cross(r_e))


def frame_tilt_acceleration(r_e, v_e, w_x, w_x_dot, w_z):
    """The terms that a rotation of the LVLH frame about X_L (rate ``w_x``, its derivative
    ``w_x_dot``; a perturbed target orbit, :mod:`.target_orbit_state`) adds to eq. 30 [m/s^2].

    Eq. 30 is -2 w x v_e - w_dot x r_e - w x (w x r_e) + gravity difference for w = [0, 0, n];
    for w = [w_x, 0, w_z] the same kinematics add these terms, each with a factor w_x or
    w_x_dot (exactly 0 for a Keplerian target, so eq. 30 keeps its value there)."""
    x, y, z = r_e
    _xd, yd, zd = v_e
    return vec(
        -w_x * w_z * z,
        2 * w_x * zd + w_x_dot * z + w_x**2 * y,
        -2 * w_x * yd - w_x_dot * y - w_x * w_z * x + w_x**2 * z,
    )

