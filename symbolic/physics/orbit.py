"""Target orbit as a function of time: Kepler (000 eqs. 31-34) and the LVLH frame rate (eqs. 9, 35-36).

The target flies an unperturbed Keplerian orbit; its LVLH frame (000 §"Essential coordinate
systems": X_L radial, Y_L along-track in the orbit plane, Z_L orbit normal) is the frame of the
relative translation model (eq. 30).

Correction of the paper (derived from first principles, see ``docs/errata.md``): eq. 30 needs
the angular rate of the LVLH frame, which for an elliptic orbit is the true-anomaly rate
``nu_dot = sqrt(mu p) / r^2`` and its derivative ``nu_ddot = -2 r_dot nu_dot / r``.  The paper's
eq. 9 ``n = sqrt(mu / r^3)`` and its derivative eq. 35 hold only for a circular orbit
(at perigee eq. 9 equals ``nu_dot / sqrt(1 + e)``: 6.3 % low for 000 scenario III's
e = 0.138); with them the relative model departs from two independently integrated orbits.
"""

from __future__ import annotations

import sympy as sp

from .kepler import KeplerE
from .rotations import vec


def mean_motion(mu, a):
    """Mean motion n_bar = sqrt(mu / a^3) [rad/s]; the period of 000 eq. 31 is T = 2 pi / n_bar."""
    return sp.sqrt(mu / a**3)


def mean_anomaly_from_true(nu, e):
    """Mean anomaly [rad] at true anomaly ``nu`` (inverse of eqs. 32-33), continuous in ``nu``."""
    beta = e / (1 + sp.sqrt(1 - e**2))
    E = nu - 2 * sp.atan2(beta * sp.sin(nu), 1 + beta * sp.cos(nu))
    return E - e * sp.sin(E)


def mean_anomaly(M0, n_bar, t):
    """M = M0 + n_bar t (000 eq. 31, with t measured from the scenario start)."""
    return M0 + n_bar * t


def eccentric_anomaly(M, e):
    """E solving Kepler's equation E - e sin E = M (000 eq. 32)."""
    return KeplerE(M, e)


def true_anomaly(E, e):
    """True anomaly from eccentric anomaly (000 eq. 33).

    Written as ``nu = E + 2 atan2(beta sin E, 1 - beta cos E)``,
    ``beta = e / (1 + sqrt(1 - e^2))``: identical to tan(nu/2) = sqrt((1+e)/(1-e)) tan(E/2) but
    continuous in E (no quadrant ambiguity, no tan(pi/2)).
    """
    beta = e / (1 + sp.sqrt(1 - e**2))
    return E + 2 * sp.atan2(beta * sp.sin(E), 1 - beta * sp.cos(E))


def semi_latus_rectum(a, e):
    """p = a (1 - e^2) [m]."""
    return a * (1 - e**2)


def radius(a, e, nu):
    """Orbit radius r = a (1 - e^2) / (1 + e cos nu) [m] (000 eq. 34)."""
    return semi_latus_rectum(a, e) / (1 + e * sp.cos(nu))


def radial_velocity(mu, a, e, nu):
    """r_dot = sqrt(mu / p) e sin nu [m/s] (eq. 36 times nu_dot, simplified)."""
    return sp.sqrt(mu / semi_latus_rectum(a, e)) * e * sp.sin(nu)


def lvlh_rate(mu, a, e, r):
    """Angular rate of the LVLH frame nu_dot = sqrt(mu p) / r^2 [rad/s] (corrects 000 eq. 9)."""
    return sp.sqrt(mu * semi_latus_rectum(a, e)) / r**2


def lvlh_rate_dot(r, r_dot, nu_dot):
    """nu_ddot = -2 r_dot nu_dot / r [rad/s^2] (corrects 000 eqs. 35-36)."""
    return -2 * r_dot * nu_dot / r


def mean_motion_circular(mu, r):
    """000 eq. 9 as printed, n = sqrt(mu / r^3): kept only to quantify the erratum."""
    return sp.sqrt(mu / r**3)


def rot1(x):
    """Active rotation matrix about X by angle x."""
    c, s = sp.cos(x), sp.sin(x)
    return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot3(x):
    """Active rotation matrix about Z by angle x."""
    c, s = sp.cos(x), sp.sin(x)
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def dcm_eci_from_lvlh(raan, inc, u):
    """C_{ECI<-LVLH} = R3(raan) R1(inc) R3(u), u = argument of latitude (omega + nu).

    Its columns are the LVLH axes in ECI: X_L = r_hat, Z_L = h_hat, Y_L = Z_L x X_L.
    """
    return rot3(raan) * rot1(inc) * rot3(u)


def target_orbit(t, mu, a, e, inc, raan, argp, nu0):
    """Everything the plant needs about the target orbit at time t [s].

    Returns a dict with ``nu`` [rad], ``r`` [m], ``r_dot`` [m/s], ``n`` (LVLH rate, rad/s),
    ``n_dot`` [rad/s^2], ``C_IL`` (C_{ECI<-LVLH}), ``r_eci`` [m], ``v_eci`` [m/s].
    """
    n_bar = mean_motion(mu, a)
    M = mean_anomaly(mean_anomaly_from_true(nu0, e), n_bar, t)
    nu = true_anomaly(eccentric_anomaly(M, e), e)
    r = radius(a, e, nu)
    r_dot = radial_velocity(mu, a, e, nu)
    n = lvlh_rate(mu, a, e, r)
    C_IL = dcm_eci_from_lvlh(raan, inc, argp + nu)
    return {
        "nu": nu,
        "r": r,
        "r_dot": r_dot,
        "n": n,
        "n_dot": lvlh_rate_dot(r, r_dot, n),
        "C_IL": C_IL,
        "r_eci": C_IL * vec(r, 0, 0),
        "v_eci": C_IL * vec(r_dot, r * n, 0),
    }
