"""benchmarks/basilisk_case.py: Basilisk's side of the speed comparison (extras ``bench``, ``xcheck``).

Marker ``xcheck``: it runs in .ci/run's Basilisk step (which installs it) and fails, never skips,
without Basilisk; the default run deselects it.

A 1 s run of the case: J2 is on and the translation matches an RK4 of point mass + J2 from the
same state; the hub's rate is the gravity-gradient torque's (the wheel command is in the null space
of the pyramid, so the wheels spin up without torquing the hub).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import basilisk_case  # noqa: E402

pytestmark = pytest.mark.xcheck


def _acc(r, mu, j2, r_e):
    x, y, z = r
    r2 = float(r @ r)
    k = 1.5 * mu * j2 * r_e**2 / r2**2.5
    s = 5 * z * z / r2
    return -mu * r / r2**1.5 + k * np.array([x * (s - 1), y * (s - 1), z * (s - 3)])


def _rk4(r, v, duration, dt, mu, j2, r_e):
    def f(s):
        return np.concatenate([s[3:], _acc(s[:3], mu, j2, r_e)])

    s = np.concatenate([r, v])
    for _ in range(int(round(duration / dt))):
        k1 = f(s)
        k2 = f(s + dt / 2 * k1)
        k3 = f(s + dt / 2 * k2)
        k4 = f(s + dt * k3)
        s = s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return s[:3], s[3:]


def test_one_second_of_the_case_is_point_mass_plus_j2_with_gravity_gradient():
    res = basilisk_case.basilisk_us_per_step(duration=1.0, dt=0.01, repeat=1)
    for key in ("us_per_step", "steps", "run_s", "setup_s", "import_s", "basilisk_version", "configuration"):
        assert key in res
    assert res["steps"] == 100 and res["us_per_step"] > 0
    assert res["basilisk_version"].startswith("2.")
    p = res["params"]
    mu, j2, r_e = p["mu"], p["j2"], p["r_earth"]

    # scenario III starts at perigee: |r0| = a (1 - e)
    assert np.linalg.norm(res["r0_N"]) == pytest.approx(p["orbit_a"] * (1 - p["orbit_e"]), rel=1e-12)
    r_j2, v_j2 = _rk4(res["r0_N"], res["v0_N"], 1.0, 0.01, mu, j2, r_e)
    r_kep, _ = _rk4(res["r0_N"], res["v0_N"], 1.0, 0.01, mu, 0.0, r_e)
    assert np.linalg.norm(res["r_N"] - r_j2) < 1e-3  # m; measured: equal to rounding
    assert np.linalg.norm(res["v_N"] - v_j2) < 1e-6
    assert np.linalg.norm(res["r_N"] - r_kep) > 5e-3  # J2 is on: 8.6 mm after 1 s

    # wheels: constant command u, Omega = u t / Js
    om = basilisk_case.WHEEL_TORQUE / p["wheel_inertia"] * 1.0
    np.testing.assert_allclose(res["wheel_speeds"], [om, -om, om, -om], rtol=1e-4)

    # the hub's rate after 1 s from rest: I^-1 (gravity-gradient torque at t = 0) t, to a few %
    I = basilisk_case.inertia_tensor(p["chaser_inertia"])
    r0 = res["r0_N"]
    r_hat_b = res["dcm_NB0"].T @ r0 / np.linalg.norm(r0)
    tau = 3 * mu / np.linalg.norm(r0) ** 3 * np.cross(r_hat_b, I @ r_hat_b)
    np.testing.assert_allclose(res["omega_BN_B"], np.linalg.solve(I, tau) * 1.0, rtol=0.01)  # measured: 0.09 %
