"""Time-varying chaser mass and inertia (000 Figs. 9-10, described in words only).

The paper shows the profiles as figures; SPEC.md gives the described features and leaves the
rest to choose.  The profiles are written as factors of the nominal values (m0 = 100 kg,
diag(I0) = 11, 14, 13 kg m^2 in 000), so the same shape can scale another chaser.  Products of
inertia keep their nominal values.  Choices (also in docs/scenarios.md):

* mass: 100 kg; 80 kg from t = 20 s (a 20 % drop); linear 80 -> 116 kg over 50-170 s; then
  116 + 2 sin(2 pi (t - 170) / 60 s) kg, i.e. between 114 and 118 kg with a chosen 60 s period.
* I_xx: 11; jump to 22 at 20 s; ramp 22 -> 25 over 20-40 s (0.15 kg m^2/s) and 25 -> 26 over
  40-60 s (0.05 kg m^2/s, the "two slow ramps of different slope over 40 s"); 26 until 200 s;
  jump to 18 at 200 s (value chosen).
* I_yy: 14; jump to 21 at 30 s; from 100 s, 21 + 2 sin(2 pi (t - 100) / 80 s): 19 to 23 with
  a chosen 80 s period.
* I_zz: 13; linear rise to 27 over 30-100 s (0.2 kg m^2/s), linear fall back to 13 with the same
  slope over 100-170 s; 13 afterwards.

The inertia satisfies the triangle inequalities at every t (checked in the tests), so it stays
physically realisable.  No dI/dt or dm/dt thrust terms are modelled (as in the paper, the
variation acts as a parameter change; see docs/errata.md).
"""

from __future__ import annotations

import sympy as sp

_R = sp.Rational


def _ramp(t, t0, t1, v0, v1):
    return v0 + (v1 - v0) * (t - t0) / (t1 - t0)


def mass_profile_000(t):
    """Chaser mass [kg] for the 000 nominal m0 = 100 kg."""
    return sp.Piecewise(
        (100, t < 20),
        (80, t < 50),
        (_ramp(t, 50, 170, 80, 116), t < 170),
        (116 + 2 * sp.sin(2 * sp.pi * (t - 170) / 60), True),
    )


def inertia_diag_profile_000(t):
    """(I_xx, I_yy, I_zz) [kg m^2] for the 000 nominal diag(11, 14, 13)."""
    ixx = sp.Piecewise(
        (11, t < 20),
        (_ramp(t, 20, 40, 22, 25), t < 40),
        (_ramp(t, 40, 60, 25, 26), t < 60),
        (26, t < 200),
        (18, True),
    )
    iyy = sp.Piecewise(
        (14, t < 30),
        (21, t < 100),
        (21 + 2 * sp.sin(2 * sp.pi * (t - 100) / 80), True),
    )
    izz = sp.Piecewise(
        (13, t < 30),
        (_ramp(t, 30, 100, 13, 27), t < 100),
        (_ramp(t, 100, 170, 27, 13), t < 170),
        (13, True),
    )
    return ixx, iyy, izz


def chaser_mass_properties(t, m0, I0, profile_on):
    """Mass [kg] and inertia [kg m^2] at time t.

    ``profile_on`` (0 or 1) selects the 000 profile, applied as factors of the 000 nominal
    values to the scenario's nominal ``m0`` and ``I0`` (3x3).  With 0 the values are constant.
    """
    f_m = 1 + profile_on * (mass_profile_000(t) / 100 - 1)
    diag0 = (11, 14, 13)
    prof = inertia_diag_profile_000(t)
    I = sp.Matrix(I0)
    for i in range(3):
        I[i, i] = I0[i, i] * (1 + profile_on * (prof[i] / diag0[i] - 1))
    return m0 * f_m, I


def spacecraft_inertia_with_wheels(I_body, J_s, axes, wheels_on=1):
    """The whole spacecraft's inertia about its centre of mass [kg m^2], body axes:
    I_body + J_s sum_i a_i a_i^T.

    rpo's chaser inertia I_c (000 eq. 6's J) excludes the wheels' spin-axis inertia J_s, which
    eq. 6 carries in the wheel momenta; the mass distribution that the gravity gradient acts on
    (000 eq. 4, :func:`.environment.gravity_gradient_torque`) is the whole spacecraft's, rotors
    included (Basilisk's gravity-gradient effector uses the hub plus its wheels' inertia the same
    way).  ``axes``: the wheels' true spin axes as columns (3 x 4); ``wheels_on`` = 0 drops them
    (the ideal actuators of 001/002/004 have no wheels).  000 prints eq. 4 with the body inertia
    alone: the difference is J_s / I ~ 1e-3 of the torque (docs/full_plant.md)."""
    return I_body + wheels_on * J_s * axes * axes.T
