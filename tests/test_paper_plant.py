"""The papers' plant options against independent references: free space, ideal actuators, the
papers' disturbance models, sensor noise and bias, and 001's constraint margins.

Each check compares the compiled model with a closed form or a NumPy/scipy computation that
shares nothing with the SymPy source.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rpo.runtime.run.simulate import Simulation

from conftest import quiet_params, target_state

FREE = quiet_params(gravity_on=0, actuators_ideal=1, force_max=0.5, torque_max=0.05)


def _x(model, **fields):
    """A full plant state: the given fields, everything else zero."""
    base = {"q_c": [0, 0, 0, 1], "w_c": [0, 0, 0], "h_w": np.zeros(4), "q_t": [0, 0, 0, 1], "w_t": [0, 0, 0],
            "r": [0, 0, 0], "v": [0, 0, 0], "m_prop": 0.0, **target_state(model)}
    return model.vector("x", {**base, **fields})


def _sim(model, gains=None, **params):
    return Simulation(model, "baseline", params=params, gains=gains)


def test_free_space_coasting_is_a_straight_line(model):
    """No gravity, no force: r(t) = r0 + v0 t exactly (the LVLH frame is frozen to ECI)."""
    sim = _sim(model, gains=dict(kp_att=0, kd_att=0, kp_pos=0, kd_pos=0), **FREE)
    r0, v0 = np.array([30.0, -5.0, 12.0]), np.array([0.2, -0.1, 0.05])
    z0 = sim.initial_state({"q_c": [0, 0, 0, 1], "w_c": [0, 0, 0], "h_w": np.zeros(4), "q_t": [0, 0, 0, 1],
                            "w_t": [0, 0, 0], "r": r0, "v": v0})
    res = sim.run(z0, 50.0)
    r = np.column_stack([res.column(f"r_{c}") for c in "xyz"])
    assert np.abs(r - (r0 + np.outer(res.t, v0))).max() < 1e-10


def test_ideal_force_saturates_per_axis_and_accelerates_the_chaser(model):
    """A PD position command far above the limit gives the saturated force; with a fixed attitude
    the chaser's displacement is 1/2 F/m t^2 for as long as the command stays saturated."""
    m = 80.0
    sim = _sim(model, gains=dict(kp_att=0, kd_att=0, kp_pos=100.0, kd_pos=0.0, r_goal=[0, 0, 0]),
               chaser_mass=m, **FREE)
    r0 = np.array([500.0, -400.0, 300.0])
    z0 = sim.initial_state({"q_c": [0, 0, 0, 1], "w_c": [0, 0, 0], "h_w": np.zeros(4), "q_t": [0, 0, 0, 1],
                            "w_t": [0, 0, 0], "r": r0, "v": [0, 0, 0]})
    res = sim.run(z0, 10.0)
    F = np.column_stack([res.column(f"env_F_applied_{c}") for c in "xyz"])[:-1]
    assert np.allclose(F, -0.5 * np.sign(r0)), "force not saturated at force_max per axis"
    r = np.column_stack([res.column(f"r_{c}") for c in "xyz"])
    expect = r0 - 0.5 * np.sign(r0) / m * res.t[:, None] ** 2 / 2
    assert np.abs(r - expect).max() < 1e-9
    # propellant of ideal thrust: sum |F_i| / (Isp g0)
    mdot = 1.5 / (227.0 * 9.80665)
    assert res.column("m_prop")[-1] == pytest.approx(mdot * 10.0, rel=1e-12)


def test_scenario_disturbance_matches_its_formula(model):
    rng = np.random.default_rng(3)
    names = ("c0", "a1", "b1", "w1", "a2", "b2", "w2", "s_nu", "c_nu")
    par = {f"dist_{kind}_{n}": rng.uniform(-1, 1, 3) for kind in ("force", "torque") for n in names}
    p = model.vector("p", {**quiet_params(), **par})
    orbit = model.functions["target_orbit"]
    off = model.offsets("env")
    for t in rng.uniform(0, 5000, 5):
        nu = float(np.ravel(orbit(t, p)[0])[0])
        x = _x(model, r=[10, 0, 0])
        env = np.ravel(model.env_outputs(x, np.zeros(model.layout_size("u")), t, p,
                                         np.zeros(model.layout_size("w")))[0])
        for kind, fld in (("force", "F_dist"), ("torque", "tau_dist")):
            c = {n: par[f"dist_{kind}_{n}"] for n in names}
            ref = (c["c0"] + c["a1"] * np.sin(c["w1"] * t) + c["b1"] * np.cos(c["w1"] * t)
                   + c["a2"] * np.sin(c["w2"] * t) + c["b2"] * np.cos(c["w2"] * t)
                   + c["s_nu"] * np.sin(nu) + c["c_nu"] * np.cos(nu))
            assert np.allclose(env[off[fld]], ref, rtol=1e-13, atol=1e-14)


def test_measurement_bias_and_noise(model):
    """A bias rotates the measured attitude by that small rotation (checked with scipy); noise has
    the stated standard deviation."""
    rng = np.random.default_rng(4)
    q = Rotation.random(random_state=5).as_quat()
    x = _x(model, q_c=q, w_c=[0.01, 0.02, 0.03], r=[10, 20, 30], v=[1, 2, 3])
    bias = np.array([0.01, -0.02, 0.005])
    p = model.vector("p", quiet_params(meas_att_bias=bias, meas_rate_bias=[1e-3, 0, 0]))
    off = model.offsets("meas")
    meas = np.ravel(model.measure(x, np.zeros(model.layout_size("hold")), 0.0, p, np.zeros(model.layout_size("w")))[0])
    # the small rotation dq = [dtheta/2, 1] normalised, applied in body axes
    dq = np.r_[bias / 2, 1.0]
    ref = (Rotation.from_quat(q) * Rotation.from_quat(dq / np.linalg.norm(dq))).as_quat()
    got = meas[off["q_c"]]
    assert min(np.abs(got - ref).max(), np.abs(got + ref).max()) < 1e-14
    assert np.allclose(meas[off["w_c"]], [0.011, 0.02, 0.03], atol=1e-15)
    p = model.vector("p", quiet_params(meas_pos_std=0.3))
    W = rng.standard_normal((4000, model.layout_size("w")))
    r = np.array([np.ravel(model.measure(x, np.zeros(model.layout_size("hold")), 0.0, p, w)[0])[off["r"]] for w in W])
    assert np.std(r[:, 0] - 10) == pytest.approx(0.3, rel=0.05)
    assert np.abs(r.mean(axis=0) - [10, 20, 30]).max() < 0.03


def _inside_independent(p, theta, z_N, R_T):
    """Is the target sphere (centre p, radius R_T) inside the camera cone (vertex (0,0,z_N), axis +z)?"""
    d = p - np.array([0.0, 0.0, z_N])
    dist = np.linalg.norm(d)
    alpha = np.arccos(np.clip(d[2] / dist, -1, 1))
    return alpha < theta and dist * np.sin(theta - alpha) > R_T


def test_constraint_margins_match_geometry(model):
    """beta_FOV > 0 exactly when the target's envelope sphere lies inside the camera cone, and
    beta_CA equals |r|^2 - (R_S + R_T)^2 (001 eqs. 41, 47), at random relative poses."""
    rng = np.random.default_rng(6)
    p = model.vector("p", quiet_params())
    off = model.offsets("env")
    theta, z_N, R_S, R_T = np.pi / 4, 1.2, 2.1, 1.5
    agree = 0
    for _ in range(300):
        q_c = Rotation.random(random_state=rng.integers(1 << 30)).as_quat()
        r = rng.normal(0, 15, 3)
        x = _x(model, q_c=q_c, r=r)
        env = np.ravel(model.env_outputs(x, np.zeros(model.layout_size("u")), 0.0, p,
                                         np.zeros(model.layout_size("w")))[0])
        # target relative to the chaser, chaser body axes; frame of r is LVLH at t = 0
        q_IL = np.ravel(model.functions["target_orbit"](0.0, p)[7])
        C_cI = Rotation.from_quat(q_c).as_matrix().T
        p_TS = -C_cI @ Rotation.from_quat(q_IL).as_matrix() @ r
        assert env[off["beta_ca"]][0] == pytest.approx(p_TS @ p_TS - (R_S + R_T) ** 2, rel=1e-12)
        b = env[off["beta_fov"]][0]
        if abs(b) > 1e-9:
            assert (b > 0) == _inside_independent(p_TS, theta, z_N, R_T)
            agree += 1
    assert agree > 250


def test_full_plant_override(tmp_path):
    """--plant full switches on the 000 plant and drops the paper's own disturbance tables."""
    from rpo.runtime.scenario import loads_scenario

    text = (tmp_path / "s.toml")
    text.write_text("""
[simulation]
duration = 1.0
[plant]
gravity = false
actuators = "ideal"
max_force = 1.0
max_torque = 0.01
[disturbance.torque]
constant = [0.01, 0.0, 0.0]
[environment]
j2 = false
random_torque_std_chaser = 0.0
[chaser]
quaternion = [0, 0, 0, 1]
attitude_frame = "eci"
mass_profile = "constant"
[target]
quaternion = [0, 0, 0, 1]
attitude_frame = "eci"
[relative]
position = [10.0, 0.0, 0.0]
velocity = [0.0, 0.0, 0.0]
""")
    sc = loads_scenario(text.read_text())
    paper = sc.params()
    full = sc.with_overrides(plant="full").params()
    assert paper["gravity_on"][0] == 0 and paper["actuators_ideal"][0] == 1
    assert paper["dist_torque_c0"][0] == 0.01 and paper["j2_on"][0] == 0
    assert full["gravity_on"][0] == 1 and full["actuators_ideal"][0] == 0
    assert full["dist_torque_c0"][0] == 0 and full["j2_on"][0] == 1 and full["mass_profile_on"][0] == 1
    assert full["chaser_rand_std"][0] == 0.3
