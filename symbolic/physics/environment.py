"""Environment: gravity-gradient, magnetic and random torques; J2 and drag accelerations (000 eqs. 4-5, 12-14, 37-45).

Each model is derived from first principles; where the paper's printed form differs, the
printed form is kept as a ``*_printed`` function (used only by the tests and the errata table)
and the difference is stated here and in ``docs/errata.md``.
"""

from __future__ import annotations

import math

import sympy as sp

from .rotations import cross, dot, norm, vec
from .special import Step

# Vallado (2013) Table 8-4 exponential atmosphere (the paper's ref. 56 for eq. 39):
# base altitude h0 [km], nominal density rho0 [kg/m^3], scale height H [km].
EXPONENTIAL_ATMOSPHERE = (
    (0, 1.225, 7.249), (25, 3.899e-2, 6.349), (30, 1.774e-2, 6.682), (40, 3.972e-3, 7.554),
    (50, 1.057e-3, 8.382), (60, 3.206e-4, 7.714), (70, 8.770e-5, 6.549), (80, 1.905e-5, 5.799),
    (90, 3.396e-6, 5.382), (100, 5.297e-7, 5.877), (110, 9.661e-8, 7.263),
    (120, 2.438e-8, 9.473), (130, 8.484e-9, 12.636), (140, 3.845e-9, 16.149),
    (150, 2.070e-9, 22.523), (180, 5.464e-10, 29.740), (200, 2.789e-10, 37.105),
    (250, 7.248e-11, 45.546), (300, 2.418e-11, 53.628), (350, 9.518e-12, 53.298),
    (400, 3.725e-12, 58.515), (450, 1.585e-12, 60.828), (500, 6.967e-13, 63.822),
    (600, 1.454e-13, 71.835), (700, 3.614e-14, 88.667), (800, 1.170e-14, 124.64),
    (900, 5.245e-15, 181.05), (1000, 3.019e-15, 268.00),
)


# --------------------------------------------------------------------------- torques

def gravity_gradient_torque(mu, r, r_hat_body, inertia):
    """Gravity-gradient torque 3 mu / r^3 (r_hat x I r_hat) [N m], body frame.

    ``r_hat_body`` is the unit position vector (Earth centre to spacecraft) in body axes; valid
    at any attitude and for a full inertia tensor.  000 eq. 4 is its Euler-angle special case.
    """
    return 3 * mu / r**3 * cross(r_hat_body, inertia * r_hat_body)


def gravity_gradient_euler(mu, r, inertia_diag, roll, pitch, *, printed: bool):
    """000 eq. 4: GG torque for a principal-axis body at 3-2-1 (yaw, pitch, roll) attitude
    relative to the orbit frame R (X_R along-track, Z_R nadir).

    ``printed=True`` returns eq. 4 as published; ``printed=False`` the form that follows from
    :func:`gravity_gradient_torque`.  They differ in the z-component: the published
    ``sin(2 theta) cos^2(phi)`` must be ``sin(2 theta) sin(phi)`` (first-order wrong: at small
    angles the published M_z ~ 3 mu/r^3 (I_x - I_y) theta, the true one is second order).
    """
    Ix, Iy, Iz = inertia_diag
    k = 3 * mu / (2 * r**3)
    mz_roll = sp.cos(roll) ** 2 if printed else sp.sin(roll)
    return vec(
        k * (Iz - Iy) * sp.sin(2 * roll) * sp.cos(pitch) ** 2,
        k * (Iz - Ix) * sp.sin(2 * pitch) * sp.cos(roll),
        k * (Ix - Iy) * sp.sin(2 * pitch) * mz_roll,
    )


def dipole_field(mu_mag, r_eci, m_hat):
    """Earth's dipole field B = mu_mag / r^3 (3 (m . r_hat) r_hat - m) [T], ECI.

    Its magnitude is mu_mag / r^3 sqrt(1 + 3 sin^2(lat_m)), 000 eq. 13; eq. 13 gives only the
    magnitude while eq. 12 needs the vector.  ``m_hat`` is the dipole axis (Earth's dipole
    points to geographic south: m_hat = -Z_ECI for an untilted dipole).
    """
    r = norm(r_eci)
    r_hat = r_eci / r
    return mu_mag / r**3 * (3 * dot(m_hat, r_hat) * r_hat - m_hat)


def magnetic_torque(m_residual, b_body):
    """Residual-dipole torque M_res x B [N m] (000 eq. 12), body frame."""
    return cross(m_residual, b_body)


def random_torque(std, unit_normal):
    """Random torque std * w [N m] (000 eq. 5, ``0.3 randn(3,1)``).

    ``unit_normal`` is a standard-normal 3-vector drawn by the runtime from a seeded generator
    and held over one integration step (reproducible; see ``docs/conventions.md``).
    """
    return std * unit_normal


# --------------------------------------------------------------------------- accelerations

def j2_potential(mu, j2, r_e, r_eci):
    """J2 part of the geopotential U_J2 = -mu J2 R_E^2 / (2 r^3) (3 z^2 / r^2 - 1) [m^2/s^2]."""
    x, y, z = r_eci
    r2 = x**2 + y**2 + z**2
    return -mu * j2 * r_e**2 / (2 * r2 ** sp.Rational(3, 2)) * (3 * z**2 / r2 - 1)


def j2_acceleration(mu, j2, r_e, r_eci):
    """J2 acceleration [m/s^2] in ECI (000 eq. 37 corrected).

    a = 3/2 mu J2 R_E^2 / r^5 [x (5 z^2/r^2 - 1), y (5 z^2/r^2 - 1), z (5 z^2/r^2 - 3)],
    the gradient of :func:`j2_potential`.  The paper prints ``r_x (5 r_x^2/r^2 - 1)`` and
    ``r_y (5 r_y^2/r^2 - 1)``: the polar coordinate z enters all three components.  The vector
    is in ECI (the paper says body frame), and is rotated to LVLH for eq. 45.
    """
    x, y, z = r_eci
    r2 = x**2 + y**2 + z**2
    k = sp.Rational(3, 2) * mu * j2 * r_e**2 / r2 ** sp.Rational(5, 2)
    s = 5 * z**2 / r2
    return k * vec(x * (s - 1), y * (s - 1), z * (s - 3))


def j2_acceleration_printed(mu, j2, r_e, r_eci):
    """000 eq. 37 exactly as printed (for the errata table and tests only)."""
    x, y, z = r_eci
    r2 = x**2 + y**2 + z**2
    k = sp.Rational(3, 2) * mu * j2 * r_e**2 / r2 ** sp.Rational(5, 2)
    return k * vec(x * (5 * x**2 / r2 - 1), y * (5 * y**2 / r2 - 1), z * (5 * z**2 / r2 - 3))


def altitude(r_eci, r_equator, flattening):
    """Height above the reference ellipsoid [m], to first order in the flattening f.

    h = |r| - R_eq (1 - f sin^2(phi)), phi the geocentric latitude (sin phi = z / |r|).  Eq. 39
    uses the ellipsoidal height; |r| - R_eq alone is 14 km low at 55 deg latitude (where 000
    scenario III's perigee lies), which overstates the density there by about 28 %.  The
    first-order form is within ~30 m of the exact geodetic height below 1000 km.
    """
    r = norm(r_eci)
    return r - r_equator * (1 - flattening * (r_eci[2] / r) ** 2)


def atmosphere_density(altitude):
    """Exponential atmosphere rho = rho0 exp(-(h - h0) / H) [kg/m^3] (000 eq. 39), h in metres.

    Vallado's piecewise table (the paper's ref. 56); below 0 m the sea-level row is used.
    Within row i, ln rho = c_i - h / H_i with c_i = ln rho0_i + h0_i / H_i.  The row is picked by
    Heaviside steps at the row altitudes: ln rho = c_0 - h/H_0 + sum_i step(h - h_i)
    [(c_i - c_{i-1}) - h (1/H_i - 1/H_{i-1})], which equals the table exactly (including its
    small jumps at row boundaries) and costs one exp and ~6 operations per row.
    """
    h_km = altitude / 1000
    rows = EXPONENTIAL_ATMOSPHERE
    c = [math.log(rho0) + h0 / H for h0, rho0, H in rows]
    inv_h = [1 / H for _h0, _rho0, H in rows]
    log_rho = sp.Float(c[0]) - sp.Float(inv_h[0]) * h_km
    for i in range(1, len(rows)):
        jump = sp.Float(c[i] - c[i - 1]) - sp.Float(inv_h[i] - inv_h[i - 1]) * h_km
        log_rho += Step(h_km - rows[i][0]) * jump
    return sp.exp(log_rho)


def drag_acceleration(rho, cd, area, mass, r_eci, v_eci, omega_earth):
    """Drag acceleration -1/2 rho C_D S / m |v_rel| v_rel [m/s^2], ECI (000 eqs. 38, 40-44 corrected).

    v_rel = v - omega_E x r is the velocity relative to the co-rotating atmosphere (eqs. 40, 43).
    Corrections: eq. 38 lacks the minus sign (drag opposes v_rel), and eqs. 41-42 approximate
    the inertial velocity as purely along-track with the vis-viva magnitude; rpo uses each
    spacecraft's actual inertial velocity (exact for the elliptic orbit).
    """
    v_rel = v_eci - cross(vec(0, 0, omega_earth), r_eci)
    return -rho * cd * area / (2 * mass) * norm(v_rel) * v_rel


def relative_disturbance(a_chaser, a_target):
    """Differential disturbance acceleration a_d = a_chaser - a_target (000 eq. 45 corrected).

    The relative position is r_e = r_c - r_t, so its disturbance is chaser minus target; eq. 45
    prints target minus chaser (a sign error).  Both in the same frame.
    """
    return a_chaser - a_target
