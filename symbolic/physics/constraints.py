"""Pose constraints of seed 001 in vector form: camera field of view and collision avoidance.

The plant logs both for every controller (so the side-by-side comparison can report how close
each design comes to them); 001's controller uses their dual-quaternion forms (001 eqs. 46, 48),
which its tests check against these.

``p_TS`` is the target's centroid relative to the chaser's centroid, in chaser body axes [m]. 001
writes the constraints with r_S/T^S, the chaser relative to the target, so p_TS = -r_S/T^S. The
camera looks along chaser body +z from the lens vertex (0, 0, z_N) (001 section 5.1).
"""

from __future__ import annotations

import sympy as sp

from .rotations import vec


def beta_fov(p_TS, half_angle, z_N, R_T):
    """001 eq. 41: beta_FOV = u.p - cot(theta) |U p| - z_N' > 0 keeps the target sphere in view [m].

    u = (0, 0, 1), U = diag(1, 1, 0); z_N' = z_N + R_T / sin(theta) is the vertex of the cone
    shrunk by the target's envelope radius R_T (001 Fig. 3).
    """
    u = vec(0, 0, 1)
    z_shift = z_N + R_T / sp.sin(half_angle)
    lateral = sp.sqrt(p_TS[0] ** 2 + p_TS[1] ** 2)
    return (u.T * p_TS)[0] - lateral / sp.tan(half_angle) - z_shift


def beta_ca(p_TS, R_S, R_T):
    """001 eq. 47: beta_CA = |r|^2 - (R_S + R_T)^2 > 0 keeps the envelope spheres apart [m^2]."""
    return (p_TS.T * p_TS)[0] - (R_S + R_T) ** 2
