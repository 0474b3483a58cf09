"""Physically absurd scenarios: values each within its range whose combination no spacecraft flies.

The manifest's bounds are per parameter and wide on purpose (any central body from a small moon to
the Sun, a 10 g chip to beyond the ISS); these checks read several keys at once and refuse, naming
the key, its value and the physical reason (:func:`check_physical`, called by
:func:`~.checks.cross_checks`, so ``rpo validate``, ``rpo run`` and each draw of a campaign refuse
alike):

* **an Earth orbit whose perigee is below 100 km** (the central body is the Earth when ``mu`` is
  within 1 % of the Earth's).  100 km is the Karman line: the US Standard Atmosphere 1976 gives
  5.6e-7 kg/m^3 there, where a body of ballistic coefficient m / (C_D A) = 45 kg/m^2 (000's chaser:
  100 kg, C_D 2.2, 1 m^2) loses 2 pi (C_D A / m) rho a^2 ~ 3000 km of semi-major axis per
  revolution: the orbit ends within its first perigee pass.  (Below the surface itself is refused
  for any body by :func:`~.checks.cross_checks`.)  The perigee is ``a (1 - e)`` whichever form the
  orbit is given in (``semi_major_axis`` or ``perigee_altitude``, the manifest defaults otherwise);
* **an Earth orbit whose apogee is beyond the Earth's Hill sphere**, a_E (m_E / (3 M_S))^(1/3) =
  1.5e9 m: there the Sun's pull, which the model does not have, exceeds the Earth's and the orbit is
  not the Keplerian ellipse flown;
* **the chaser below that floor at t = 0** (with gravity on: its radius ``|r_T + r|``, ``r`` in
  LVLH, X radial, from the target's radius on the orbit at the initial true anomaly);
* **the chaser at the target's centre or inside the keep-out sphere at t = 0**: ``|relative.position|``
  < ``constraints.chaser_radius + constraints.target_radius`` (001's two envelope
  spheres, ``symbolic/physics/constraints.py``: the sphere a goal must stay out of, unless it is a
  contact goal) means the bodies start inside each
  other.

Eccentricities >= 1 (no closed orbit), masses and inertias that are not positive, or an inertia that
breaks the triangle inequality are refused by the sections and bounds already.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.scenario.messages import field_error

if TYPE_CHECKING:
    from rpo.runtime.scenario.schema import Scenario, ScenarioSchema

#: The Earth's gravitational parameter [m^3/s^2] (the manifest default, EGM96).
MU_EARTH = 3.986004418e14
#: A central body whose ``mu`` is within this fraction of :data:`MU_EARTH` is the Earth.
EARTH_TOL = 0.01
#: Lowest perigee altitude [m] of an Earth orbit: the Karman line (see the module's docstring).
MIN_PERIGEE_ALTITUDE = 100e3
#: The Earth's Hill sphere radius [m]: 1.496e11 m x (3.003e-6 / 3)^(1/3).
EARTH_HILL_RADIUS = 1.5e9


def is_earth(mu: float) -> bool:
    """Whether a central body of gravitational parameter ``mu`` [m^3/s^2] is the Earth."""
    return abs(mu - MU_EARTH) <= EARTH_TOL * MU_EARTH


def check_physical(sc: Scenario, schema: ScenarioSchema, p: Any, orbit_key: Callable[[], str]) -> None:
    """Refuse the physically absurd combinations of the module's docstring (a pydantic error on the
    key to change).  ``p[name]``: a parameter in SI (the scenario's, else the default);
    ``orbit_key()``: the orbit key the scenario sets (named in the orbit's refusals)."""
    a, e, r_e, mu = p["orbit_a"], p["orbit_e"], p["r_earth"], p["mu"]
    earth = is_earth(mu)
    orbit = f"a = {a:.7g} m, e = {e:g}"
    if earth:
        h_p = a * (1 - e) - r_e
        if h_p < MIN_PERIGEE_ALTITUDE:
            key = orbit_key()
            raise field_error(key, sc.get(key), f"perigee altitude a (1 - e) - R_E = {h_p / 1e3:.4g} km ({orbit}) is "
                                                f"below {MIN_PERIGEE_ALTITUDE / 1e3:g} km: the atmosphere would end "
                                                "the orbit within its first perigee pass")
        r_a = a * (1 + e)
        if r_a > EARTH_HILL_RADIUS:
            key = "orbit.eccentricity" if e > 0 and sc.get("orbit.eccentricity") is not None else orbit_key()
            raise field_error(key, sc.get(key), f"apogee radius a (1 + e) = {r_a:.4g} m ({orbit}) is beyond the "
                                                f"Earth's Hill sphere ({EARTH_HILL_RADIUS:.2g} m): the Sun, not "
                                                "modelled, would dominate and the orbit would not be an Earth orbit")
    r = np.asarray(sc.relative.position, float)
    dist = float(np.linalg.norm(r))
    if p["gravity_on"] == 1.0:
        nu = p["orbit_nu0"]
        r_t = a * (1 - e * e) / (1 + e * math.cos(nu))
        r_c = float(np.linalg.norm(r + np.array([r_t, 0.0, 0.0])))  # LVLH X is radial, from the Earth
        floor = r_e + (MIN_PERIGEE_ALTITUDE if earth else 0.0)
        if r_c < floor:
            what = f"the {MIN_PERIGEE_ALTITUDE / 1e3:g} km floor of an Earth orbit" if earth else "the surface"
            raise field_error("relative.position", list(sc.relative.position),
                              f"puts the chaser at altitude {(r_c - r_e) / 1e3:.4g} km at t = 0 (the target at "
                              f"{(r_t - r_e) / 1e3:.4g} km, LVLH X radial): below {what}")
    keep_out = p["chaser_radius"] + p["target_radius"]
    radii = " + ".join(schema.param(n).key for n in ("chaser_radius", "target_radius"))
    if dist < keep_out or dist == 0.0:
        where = "at the target's centre" if dist == 0.0 else f"|r| = {dist:.4g} m from the target's centre"
        raise field_error("relative.position", list(sc.relative.position),
                          f"puts the chaser {where} at t = 0, inside the keep-out sphere {radii} = {keep_out:.4g} m: "
                          "the two bodies would start inside each other's envelope")
