"""Check 6: environment and actuator models against independent forms."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from rpo.symbolic.codegen.to_casadi import LAMBDIFY_MODULES
from rpo.symbolic.physics import environment as env

from conftest import DEG

MU, J2, RE = 3.986004418e14, 1.08262668e-3, 6378137.0
rng = np.random.default_rng(3)
R = sp.Matrix(sp.symbols("rx ry rz", real=True))
VV = sp.Matrix(sp.symbols("vx vy vz", real=True))


def lam(args, expr):
    g = sp.lambdify(args, expr, LAMBDIFY_MODULES)
    return lambda *a: np.asarray(g(*a), float).ravel()


def random_positions(n):
    d = rng.normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1)[:, None] * rng.uniform(6.6e6, 4.2e7, size=(n, 1))


# ------------------------------------------------------------------ J2 (000 eq. 37)

def test_j2_is_the_gradient_of_the_j2_geopotential():
    # independent potential, typed from the textbook: U = -mu J2 R^2 / (2 r^3) (3 sin^2(lat) - 1)
    x, y, z = R
    r = sp.sqrt(x**2 + y**2 + z**2)
    U = -MU * J2 * RE**2 / (2 * r**3) * (3 * (z / r) ** 2 - 1)
    grad = lam([list(R)], sp.Matrix([sp.diff(U, c) for c in R]))
    a = lam([list(R)], env.j2_acceleration(MU, J2, RE, R))
    printed = lam([list(R)], env.j2_acceleration_printed(MU, J2, RE, R))
    worst_printed = 0.0
    for p in random_positions(200):
        g = grad(p)
        assert np.allclose(a(p), g, rtol=1e-12, atol=1e-12 * np.linalg.norm(g))
        worst_printed = max(worst_printed, np.linalg.norm(printed(p) - g) / np.linalg.norm(g))
    assert worst_printed > 0.1  # the paper's printed eq. 37 is not the gradient (erratum)


# ------------------------------------------------------------------ gravity gradient (000 eq. 4)

@pytest.mark.parametrize("small", [True, False])
def test_gravity_gradient_vector_form_against_eq4(small):
    """For a principal-axis body at 3-2-1 angles (psi, theta, phi) relative to the orbit frame R
    (X_R along-track, Z_R nadir) the vector form equals eq. 4 (corrected z-component) exactly;
    at small angles the printed eq. 4 differs at first order in M_z."""
    Ix, Iy, Iz = 11.0, 14.0, 13.0
    I = np.diag([Ix, Iy, Iz])
    r0 = 6.9e6
    roll, pitch = sp.symbols("roll pitch", real=True)
    corr = lam([roll, pitch], env.gravity_gradient_euler(MU, r0, (Ix, Iy, Iz), roll, pitch, printed=False))
    prnt = lam([roll, pitch], env.gravity_gradient_euler(MU, r0, (Ix, Iy, Iz), roll, pitch, printed=True))
    rh = sp.Matrix(sp.symbols("hx hy hz", real=True))
    Is = sp.Matrix(I)
    gg = lam([list(rh)], env.gravity_gradient_torque(MU, r0, rh, Is))
    scale = 3 * MU / r0**3 * (Iy - Ix)
    mz_diff = []
    for _ in range(30):
        ang = rng.uniform(-0.05, 0.05, 3) if small else rng.uniform(-1.2, 1.2, 3)
        yaw, th, ph = ang
        C_bR = Rotation.from_euler("ZYX", [yaw, th, ph]).inv().as_matrix()  # C_{B<-R}
        r_hat_b = C_bR @ np.array([0, 0, -1.0])  # Earth -> spacecraft = -nadir
        M = gg(r_hat_b)
        assert np.allclose(M, corr(ph, th), atol=1e-12 * abs(scale))
        mz_diff.append(abs(prnt(ph, th)[2] - M[2]) / abs(scale * th))
    if small:
        assert max(mz_diff) > 0.5  # printed M_z is wrong at first order in pitch


# ------------------------------------------------------------------ magnetic (000 eqs. 12-13)

def test_dipole_magnitude_matches_eq13_and_points_north_at_the_equator():
    mu_mag = 8.1e15
    B = lam([list(R)], env.dipole_field(mu_mag, R, sp.Matrix([0, 0, -1])))
    for p in random_positions(50):
        r = np.linalg.norm(p)
        lat = np.arcsin(p[2] / r)
        assert np.isclose(np.linalg.norm(B(p)), mu_mag / r**3 * np.sqrt(1 + 3 * np.sin(lat) ** 2), rtol=1e-12)
    assert B(np.array([7e6, 0, 0]))[2] > 0  # field lines point north at the equator


# ------------------------------------------------------------------ drag (000 eqs. 38-44)

def test_drag_decays_a_circular_orbit_at_the_king_hele_rate():
    """Work of drag = loss of orbital energy: over one revolution of a circular orbit in a
    non-rotating atmosphere of constant density, da = -2 pi (C_D S / m) rho a^2 (King-Hele)."""
    cd, S, m, rho = 2.2, 1.0, 100.0, 3.725e-12
    a_drag = lam([list(R), list(VV)], env.drag_acceleration(rho, cd, S, m, R, VV, 0.0))
    a0 = RE + 400e3
    v0 = np.sqrt(MU / a0)
    period = 2 * np.pi * np.sqrt(a0**3 / MU)

    def f(_t, s):
        r, v = s[:3], s[3:]
        return np.concatenate([v, -MU * r / np.linalg.norm(r) ** 3 + a_drag(r, v)])

    sol = solve_ivp(f, (0, period), [a0, 0, 0, 0, v0, 0], method="DOP853", rtol=1e-12, atol=1e-6)
    r, v = sol.y[:3, -1], sol.y[3:, -1]
    energy = 0.5 * v @ v - MU / np.linalg.norm(r)
    a_end = -MU / (2 * energy)
    expected = -2 * np.pi * cd * S / m * rho * a0**2
    assert expected < 0
    assert np.isclose(a_end - a0, expected, rtol=0.01), (a_end - a0, expected)
    # and the acceleration opposes the velocity relative to the atmosphere
    p, vel = np.array([a0, 0, 0]), np.array([0, v0, 0])
    assert np.dot(a_drag(p, vel), vel) < 0


def test_density_table_and_altitude():
    h = sp.Symbol("h", real=True)
    rho = lam([h], env.atmosphere_density(h))
    for h0, rho0, H in env.EXPONENTIAL_ATMOSPHERE:
        hm = h0 * 1000 + 0.3 * H * 1000
        assert np.isclose(rho(hm)[0], rho0 * np.exp(-0.3), rtol=1e-12)
    alt = lam([list(R)], env.altitude(R, RE, 1 / 298.257223563))
    assert np.isclose(alt(np.array([RE + 400e3, 0, 0]))[0], 400e3)
    # at the pole the ellipsoid is 21.4 km lower than the equatorial radius
    assert np.isclose(alt(np.array([0, 0, RE + 400e3]))[0], 400e3 + 21384.7, atol=1.0)


# ------------------------------------------------------------------ actuators (000 eqs. 46-47)

A_STAR = np.array([  # eq. 47 typed from the paper
    [np.cos(30 * DEG), 0, -np.cos(30 * DEG), 0],
    [0, np.cos(30 * DEG), 0, -np.cos(30 * DEG)],
    [np.sin(30 * DEG)] * 4,
])


def test_pyramid_allocation_reproduces_the_command_within_limits(model):
    p = model.vector("p")
    tmax = 0.1
    for _ in range(200):
        cmd = rng.normal(size=3) * 0.03
        T = model.wheel_alloc(cmd, 0.0, p)[0]
        if np.abs(T).max() < tmax * (1 - 1e-9):
            assert np.allclose(A_STAR @ T, cmd, atol=1e-15)
    for _ in range(200):  # beyond the envelope: direction kept, every wheel within its limit
        cmd = rng.normal(size=3) * 1.0
        T = model.wheel_alloc(cmd, 0.0, p)[0]
        assert np.abs(T).max() <= tmax * (1 + 1e-12)
        got = A_STAR @ T
        assert np.allclose(np.cross(got, cmd), 0, atol=1e-12) and got @ cmd > 0


def test_thruster_allocation_is_exact_non_negative_and_never_fires_opposed_pairs(model):
    from rpo.symbolic.physics.actuators import thruster_layout

    pos, dirs = thruster_layout()
    B = np.array([np.concatenate([np.array(d, float).ravel(), np.cross(np.array(p, float).ravel(),
                                                                        np.array(d, float).ravel())])
                  for p, d in zip(pos, dirs, strict=True)]).T  # 6 x 16, from the geometry with numpy's cross
    p = model.vector("p")
    for _ in range(300):
        F, tau = rng.normal(size=3) * 0.3, rng.normal(size=3) * 0.05
        d = model.thruster_alloc(F, tau, 0.0, p)[0]
        assert d.min() >= 0 and d.max() <= 1 + 1e-12
        assert np.all(d[0::2] * d[1::2] == 0)  # one thruster of each coaxial pair at most
        w = B @ d
        if d.max() < 1 - 1e-9:
            assert np.allclose(w, np.concatenate([F, tau]), atol=1e-13)
        else:  # saturated: direction kept
            want = np.concatenate([F, tau])
            assert np.allclose(w / np.linalg.norm(w), want / np.linalg.norm(want), atol=1e-12)


@pytest.mark.parametrize("demand", [0.05, 0.2, 0.5, 0.8])
def test_pwpf_duty_cycle_tracks_the_demand(model, demand):
    """PWPF is quasi-linear: the mean on-time follows a constant demand (Fig. 7 modulator)."""
    p = model.vector("p")
    f = np.zeros(16)
    on = np.zeros(16)
    duty = np.full(16, demand)
    ons = []
    for _ in range(6000):  # 60 s at 100 Hz
        on = model.pwpf(f, on, duty, p)[0]
        f = model.pwpf_filter(f, duty, on, p)[0]
        ons.append(on[0])
    mean = np.mean(ons[1000:])
    assert abs(mean - demand) < 0.05 * max(demand, 0.2), (demand, mean)
    assert 0 < mean < 1


def test_wheel_transport_delay_is_exact_within_the_step(model):
    """A torque command issued at t_k acts only after t_k + delay: with the chaser at rest, the
    wheel momentum after one step changes by T (dt - delay) and by T dt in the next step."""
    from rpo.runtime.run.simulate import Simulation

    from conftest import Q_C0_III, Q_T0_III, quiet_params, unit

    sim = Simulation(model, params=quiet_params(wheel_delay=0.002),
                     gains=dict(kp_att=0, kd_att=0.0, kp_pos=0, kd_pos=0))
    z0 = sim.initial_state({"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "w_t": [0.02, 0, 0], "r": [60, 0, 25]})
    # w_e = -C w_t != 0, so kd_att would command a torque; use a pure rate-damping gain instead
    sim = Simulation(model, params=quiet_params(wheel_delay=0.002),
                     gains=dict(kp_att=0, kd_att=0.5, kp_pos=0, kd_pos=0))
    res = sim.run(z0, 0.02)
    wheel_cmd = np.column_stack([res.column(f"wheel_cmd_{c}") for c in "1234"])
    h = np.column_stack([res.column(f"h_w_{c}") for c in "1234"])
    T0 = wheel_cmd[0]
    assert np.abs(T0).max() > 1e-3
    dh1 = h[1] - h[0]
    # dh/dt = -T; over the first step only dt - delay = 8 ms of the new command acts
    assert np.allclose(dh1, -T0 * 0.008, rtol=1e-9, atol=1e-15)
