"""Fault events (symbolic/physics/faults.py, runtime/scenario/faults.py, docs/faults.md).

Each check states a consequence of the fault model that a wrong implementation breaks: a failed
wheel's momentum is exactly constant, a stuck-on thruster burns at F / (Isp g0), the fault-aware
allocation over three wheels reproduces the command, a locked wheel keeps its relative speed while
the total angular momentum is conserved, sensor faults act on the measurement as documented, and
a fault after the end of a run changes nothing, bit for bit (scalar and lane runs).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rpo.runtime.errors import ScenarioError
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import load_scenario, loads_scenario

from conftest import ZERO_GAINS, quiet_params, unit

III = "scenarios/000_scenario_III.toml"
NEVER = 1e30


def _iii(model, controller="c000"):
    run = load_scenario(III).with_overrides(controller=controller).to_run(model)
    sim = Simulation(model, controller, params=run.params, gains=run.gains)
    return sim, sim.initial_state(run.plant), run.params


def _with(params: dict, **fields) -> dict:
    out = {k: np.array(v, float, copy=True) for k, v in params.items()}
    for k, v in fields.items():
        out[k] = np.array(v, float)
    return out


def _window(n: int, unit: int, start: float, end: float = NEVER) -> tuple[list[float], list[float]]:
    s, e = [NEVER] * n, [NEVER] * n
    s[unit], e[unit] = start, end
    return s, e


def _col(model, sim, res, layout: str, label: str) -> np.ndarray:
    labels = model.labels(layout)
    arr = res.z if layout == sim.z_layout else res.y
    return arr[:, labels.index(label)]


def test_failed_wheel_momentum_stays_exactly_constant(model):
    sim0, z0, params = _iii(model)
    s, e = _window(4, 1, 0.5)
    sim = Simulation(model, "c000", params=_with(params, fault_wheel_off_start=s, fault_wheel_off_end=e),
                     gains=sim0._gains_given)
    res = sim.run(z0, 2.0)
    k0 = int(math.ceil(0.5 / sim.dt - 1e-9))  # the first step starting at or after the fault
    h2 = _col(model, sim, res, sim.z_layout, "h_w_2")
    assert np.all(h2[k0:] == h2[k0])                       # exactly constant from the fault on
    assert np.ptp(h2[:k0 + 1]) > 0                         # and it was driven before
    assert np.all(_col(model, sim, res, sim.y_layout, "wheel_applied_2")[k0:-1] == 0.0)
    h1 = _col(model, sim, res, sim.z_layout, "h_w_1")
    assert np.ptp(h1[k0:]) > 0                             # the other wheels go on


def test_stuck_on_thruster_burns_at_its_mass_flow(model):
    """With the commands off (zero gains, free space) only the stuck thruster fires: m_prop grows at
    F / (Isp g0) from the first step at or after the fault, and not before."""
    p = quiet_params(gravity_on=0)
    sim0 = Simulation(model, "baseline", params=p, gains=ZERO_GAINS)
    z0 = sim0.initial_state({"q_c": [0, 0, 0, 1], "w_c": [0, 0, 0], "q_t": [0, 0, 0, 1], "w_t": [0, 0, 0],
                             "r": [10, 0, 0], "v": [0, 0, 0]})
    s, e = _window(16, 3, 0.3)
    sim = Simulation(model, "baseline", params={**p, "fault_thr_stuck_on_start": s, "fault_thr_stuck_on_end": e},
                     gains=ZERO_GAINS)
    res = sim.run(z0, 1.0)
    o = model.offsets("p")
    F, isp, g0 = (float(sim.p[o[n]][0]) for n in ("thruster_force", "thruster_isp", "g0"))
    m = _col(model, sim, res, sim.z_layout, "m_prop")
    k0 = int(math.ceil(0.3 / sim.dt - 1e-9))
    assert np.all(m[:k0 + 1] == 0.0)
    t = np.asarray(res.t)
    np.testing.assert_allclose(m[k0:], (t[k0:] - t[k0]) * F / (isp * g0), rtol=1e-12, atol=1e-18)
    level = _col(model, sim, res, sim.y_layout, "thr_on_03")
    assert np.all(level[k0:-1] == 1.0) and np.all(level[:k0] == 0.0)


@pytest.mark.parametrize("failed", [0, 1, 2, 3])
def test_fault_aware_allocation_over_three_wheels_reproduces_the_command(model, failed):
    p = model.vector("p", {"fdir_allocation": 1.0, "fault_wheel_off_start": _window(4, failed, 0.0)[0]})
    o = model.offsets("p")
    beta, T_max = float(p[o["wheel_beta"]][0]), float(p[o["wheel_torque_max"]][0])
    c, s = math.cos(beta), math.sin(beta)
    A = np.array([[c, 0, -c, 0], [0, c, 0, -c], [s, s, s, s]])
    rng = np.random.default_rng(failed)
    within = beyond = 0
    for k in range(40):
        tau = rng.normal(0, 0.03 if k < 20 else 0.3, 3)  # the second half mostly beyond the limits
        T = np.ravel(model.wheel_alloc(tau, 1.0, p)[0])
        assert T[failed] == 0.0
        if np.abs(T).max() < T_max * (1 - 1e-9):  # within the limits: the command exactly
            np.testing.assert_allclose(A @ T, tau, rtol=0, atol=1e-15)
            within += 1
        else:                                      # beyond them: its direction, scaled onto the limit
            assert np.abs(T).max() == pytest.approx(T_max, rel=1e-12)
            np.testing.assert_allclose(np.cross(A @ T, tau), 0, atol=1e-15)
            assert np.dot(A @ T, tau) > 0
            beyond += 1
    assert within >= 10 and beyond >= 10
    # the nominal allocation, for comparison, drives the failed wheel: the faulty wheel's torque is lost
    p_nom = model.vector("p", {"fault_wheel_off_start": _window(4, failed, 0.0)[0]})
    assert np.ravel(model.wheel_alloc(np.array([0.01, 0.02, 0.01]), 1.0, p_nom)[0])[failed] != 0.0


def test_locked_wheel_keeps_its_relative_speed_and_momentum_is_conserved(model):
    """Torque-free (no environment, no commands): a wheel locked at t = 0.2 s keeps its speed
    relative to the body while the body tumbles, and the total angular momentum in ECI stays."""
    from scipy.spatial.transform import Rotation

    p = quiet_params(gravity_on=0)
    s, e = _window(4, 0, 0.2)
    sim = Simulation(model, "baseline", params={**p, "fault_wheel_stuck_start": s, "fault_wheel_stuck_end": e},
                     gains=ZERO_GAINS)
    z0 = sim.initial_state({"q_c": unit([0.1, -0.2, 0.3, 0.9]), "w_c": [0.05, -0.1, 0.08],
                            "h_w": [0.2, -0.1, 0.3, 0.05], "q_t": [0, 0, 0, 1], "w_t": [0, 0, 0],
                            "r": [10, 0, 0], "v": [0, 0, 0]})
    res = sim.run(z0, 5.0)
    speed = _col(model, sim, res, sim.y_layout, "env_wheel_speed_1")[:-1]
    k0 = int(math.ceil(0.2 / sim.dt - 1e-9))
    locked = speed[k0:]
    assert np.ptp(locked) <= 1e-9 * np.abs(locked).max()
    off = model.offsets(sim.z_layout)
    o = model.offsets("p")
    I_vals = sim.p[o["chaser_inertia"]]
    xx, yy, zz, xy, xz, yz = I_vals
    I_c = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    beta = float(sim.p[o["wheel_beta"]][0])
    c, sn = math.cos(beta), math.sin(beta)
    A = np.array([[c, 0, -c, 0], [0, c, 0, -c], [sn, sn, sn, sn]])
    H = []
    for z in res.z:
        q, w, h = z[off["q_c"]], z[off["w_c"]], z[off["h_w"]]
        H.append(Rotation.from_quat(q).apply(I_c @ w + A @ h))
    H = np.array(H)
    assert np.abs(H - H[0]).max() <= 1e-10 * np.linalg.norm(H[0])
    assert np.ptp(res.z[:, off["w_c"]], axis=0).max() > 1e-3   # the body does move


def test_a_fault_after_the_end_of_the_run_changes_nothing_bit_for_bit(model):
    sim, z0, params = _iii(model)
    late = dict(params)
    for name in model.layouts["p"].names:
        if name.startswith("fault_") and name.endswith("_start"):
            late[name] = np.full(np.size(params[name]), 50.0)       # every fault, after a 1 s run
        elif name.endswith("_weak_value"):
            late[name] = np.full(np.size(params[name]), 0.3)
        elif name.startswith("fault_bias_"):
            late[name] = np.full(3, 0.01)
        elif name.startswith("fault_noise_"):
            late[name] = np.array([0.02])
    late["fdir_allocation"] = np.array([0.0])
    ref = sim.run(z0, 1.0, seed=4)
    got = Simulation(model, "c000", params=late, gains=sim._gains_given).run(z0, 1.0, seed=4)
    assert np.array_equal(ref.z, got.z) and np.array_equal(ref.y[:-1], got.y[:-1])
    # and in the lane runs: a batch with the late faults equals the batch without them, lane by lane
    Z0 = np.tile(z0, (3, 1))
    a = sim.run_batch(Z0, 0.5, [1, 2, 3], params=[params] * 3)
    b = sim.run_batch(Z0, 0.5, [1, 2, 3], params=[late] * 3)
    for ra, rb in zip(a, b, strict=True):
        assert np.array_equal(ra.z, rb.z)


def test_faulty_lane_runs_equal_single_runs(model):
    """A batch mixing healthy and faulty runs: each lane is bit-identical to its own run."""
    sim, z0, params = _iii(model)
    cases = [params,
             _with(params, fault_wheel_off_start=_window(4, 2, 0.2)[0]),
             _with(params, fault_thr_stuck_on_start=_window(16, 7, 0.1)[0]),
             _with(params, fdir_allocation=1.0, fault_wheel_stuck_start=_window(4, 0, 0.3)[0]),
             _with(params, fault_sensor_freeze_start=[0.2, NEVER, NEVER, 0.2])]
    batch = sim.run_batch(np.tile(z0, (len(cases), 1)), 0.6, list(range(len(cases))), params=cases)
    for i, (case, rb) in enumerate(zip(cases, batch, strict=True)):
        single = Simulation(model, "c000", params=case, gains=sim._gains_given).run(z0, 0.6, seed=i)
        assert np.array_equal(single.z, rb.z), f"case {i}"


def test_sensor_faults_act_on_the_measurement(model):
    sim0, z0, params = _iii(model, "baseline")
    t_f = 0.3
    win = [t_f, NEVER, NEVER, t_f]   # attitude and velocity sensors
    p = _with(params, meas_att_std=0.0, meas_vel_std=0.0, fault_sensor_bias_start=[NEVER, NEVER, t_f, NEVER],
              fault_bias_pos=[1.0, -2.0, 0.5], fault_sensor_freeze_start=win,
              fault_sensor_noise_start=[NEVER, t_f, NEVER, NEVER], fault_noise_rate_std=[0.01])
    sim = Simulation(model, "baseline", params=p, gains=sim0._gains_given)
    ref = Simulation(model, "baseline", params=_with(params, meas_att_std=0.0, meas_vel_std=0.0),
                     gains=sim0._gains_given)
    a, b = sim.run(z0, 1.0, seed=3), ref.run(z0, 1.0, seed=3)
    k0 = int(math.ceil(t_f / sim.dt - 1e-9))
    yl = model.labels(sim.y_layout)

    def y(res, lbl):
        return res.y[:-1, yl.index(lbl)]

    # before the faults the runs are identical
    assert np.array_equal(a.z[:k0 + 1], b.z[:k0 + 1])
    # bias: the position measurement is the truth + the bias step (no position noise here)
    zl = model.labels(sim.z_layout)
    for i, ax in enumerate("xyz"):
        meas = y(a, f"meas_r_{ax}")[k0:]
        truth = a.z[k0:-1, zl.index(f"r_{ax}")] + float(params["meas_pos_bias"][i])
        np.testing.assert_allclose(meas - truth, [1.0, -2.0, 0.5][i], rtol=0, atol=1e-12)
    # freeze: the attitude and velocity measurements repeat the value of the step before the fault
    for lbl in ("meas_q_c_x", "meas_q_c_w", "meas_v_x", "meas_v_z"):
        m = y(a, lbl)
        assert np.all(m[k0:] == m[k0 - 1]) and np.ptp(m[:k0]) > 0
    # noise: the rate measurement's scatter about the truth jumps to about 0.01 rad/s
    err = y(a, "meas_w_c_x")[k0:] - a.z[k0:-1, zl.index("w_c_x")]
    assert 0.007 < np.std(err) < 0.013


FAULT_BASE = """
[simulation]
duration = 1.0
controller = "c000"
[chaser]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[target]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[relative]
position = [10, 0, 0]
velocity = [0, 0, 0]
"""


@pytest.mark.parametrize("entry, fragment", [
    ('kind = "wheel_off"\nunit = 5\ntime = 1.0', "unit = 5: kind wheel_off needs a wheel 1-4"),
    ('kind = "thruster_off"\nunit = 16\ntime = 1.0', "needs a thruster 0-15"),
    ('kind = "sensor_freeze"\nunit = "gyro"\ntime = 1.0', 'needs a sensor "attitude"'),
    ('kind = "wheel_weak"\nunit = 1\ntime = 1.0', "needs a value"),
    ('kind = "wheel_weak"\nunit = 1\ntime = 1.0\nvalue = 0.0', "use kind wheel_off"),
    ('kind = "thruster_weak"\nunit = 1\ntime = 1.0\nvalue = 1.5', "0 < value <= 1"),
    ('kind = "wheel_off"\nunit = 1\ntime = 1.0\nvalue = 1.0', "takes no value"),
    ('kind = "wheel_off"\nunit = 1\ntime = -1.0', "must be >= 0 s"),
    ('kind = "wheel_off"\nunit = 1\ntime = 2.0\nend = 1.0', "must be > time"),
    ('kind = "sensor_bias"\nunit = "rate"\ntime = 1.0\nvalue = 0.1', "[x, y, z]"),
    ('kind = "sensor_noise"\nunit = "rate"\ntime = 1.0\nvalue = -0.1', ">= 0"),
    ('kind = "wheel_explodes"\nunit = 1\ntime = 1.0', "kind"),
    ('kind = "wheel_off"\nunit = 1\ntime = nan', "time"),
    ('kind = "sensor_bias"\nunit = "attitude"\ntime = 1.0\nvalue = [400.0, 0.0, 0.0]', "must be in [-180, 180] deg"),
    ('kind = "sensor_noise"\nunit = "velocity"\ntime = 1.0\nvalue = 1000.0', "must be in [0, 100] m/s"),
])
def test_bad_fault_entries_are_refused_naming_the_entry(entry, fragment):
    with pytest.raises(ScenarioError) as exc:
        loads_scenario(FAULT_BASE + "[[faults]]\n" + entry + "\n", "s.toml")
    msg = str(exc.value)
    assert "faults[0]" in msg and fragment in msg and "\n" not in msg


def test_two_faults_of_one_kind_on_one_unit_and_ideal_actuators_are_refused():
    two = FAULT_BASE + '[[faults]]\nkind = "wheel_off"\nunit = 2\ntime = 1.0\n' * 2
    with pytest.raises(ScenarioError, match=r"faults\[1\].*second wheel_off fault of unit 2"):
        loads_scenario(two, "s.toml")
    ideal = FAULT_BASE + '[plant]\nactuators = "ideal"\nmax_force = 1.0\nmax_torque = 0.1\n' \
        '[[faults]]\nkind = "thruster_stuck_on"\nunit = 2\ntime = 1.0\n'
    with pytest.raises(ScenarioError, match=r"faults\[0\].kind.*wheels_thrusters"):
        loads_scenario(ideal, "s.toml")
    ok = loads_scenario(FAULT_BASE + '[fdir]\nallocation = "healthy"\n[[faults]]\nkind = "wheel_stuck"\nunit = 4\n'
                        'time = 0.5\nend = 0.8\n[[faults]]\nkind = "sensor_bias"\nunit = "attitude"\ntime = 0.1\n'
                        'value = [1.0, 0.0, 0.0]\n', "s.toml")
    p = ok.params()
    assert list(p["fault_wheel_stuck_start"]) == [NEVER, NEVER, NEVER, 0.5]
    assert list(p["fault_wheel_stuck_end"]) == [NEVER, NEVER, NEVER, 0.8]
    np.testing.assert_allclose(p["fault_bias_att"], [math.radians(1.0), 0, 0])
    assert float(p["fdir_allocation"][0]) == 1.0


def _thruster_B():
    from rpo.symbolic.physics.actuators import thruster_wrench_matrix

    return np.array(thruster_wrench_matrix().tolist(), float)


@pytest.mark.parametrize("kind, unit", [("off", 0), ("off", 9), ("stuck_on", 3), ("stuck_on", 12), ("weak", 4)])
def test_fault_aware_thruster_allocation_reproduces_the_wrench(model, kind, unit):
    """B (d * thrust) F + the stuck thrusters' wrench = the command within the limits; a failed or
    stuck thruster is never commanded; beyond the limits no demand exceeds 1."""
    over = {"fdir_allocation": 1.0, f"fault_thr_{kind}_start": _window(16, unit, 0.0)[0]}
    if kind == "weak":
        over["fault_thr_weak_value"] = [1.0] * 4 + [0.4] + [1.0] * 11
    p = model.vector("p", over)
    F = float(p[model.offsets("p")["thruster_force"]][0])
    B = _thruster_B()
    thrust = np.ones(16)
    if kind == "weak":
        thrust[unit] = 0.4
    stuck = np.zeros(16)
    if kind == "stuck_on":
        stuck[unit] = 1.0
    rng = np.random.default_rng(unit)
    within = 0
    for k in range(40):
        w = rng.normal(0, 0.05 if k < 30 else 2.0, 6)
        d = np.ravel(model.thruster_alloc(w[:3], w[3:], 1.0, p)[0])
        assert np.all(d >= 0) and np.all(d <= 1 + 1e-12)
        if kind in ("off", "stuck_on"):
            assert d[unit] == 0.0
        got = B @ (d * thrust) * F + B @ (stuck * thrust) * F
        if d.max() < 1 - 1e-9:
            np.testing.assert_allclose(got, w, rtol=0, atol=1e-13)
            within += 1
    assert within >= 5


def test_off_beats_stuck_and_a_fault_window_ends(model):
    """Both windows open: the wheel coasts (not locked), the thruster does not fire, and the aware
    allocation does not count a stuck wrench that is not there; after ``end`` the unit is back."""
    both = {"fault_wheel_off_start": _window(4, 1, 0.0)[0], "fault_wheel_stuck_start": _window(4, 1, 0.0)[0],
            "fault_thr_off_start": _window(16, 3, 0.0)[0], "fault_thr_stuck_on_start": _window(16, 3, 0.0)[0],
            "fdir_allocation": 1.0}
    p = model.vector("p", both)
    T, locked = model.wheel_faults(np.array([0.05, 0.05, 0.05, 0.05]), 1.0, p)
    assert np.ravel(T)[1] == 0.0 and np.ravel(locked)[1] == 0.0
    assert np.ravel(model.thruster_faults(np.ones(16), 1.0, p)[0])[3] == 0.0
    w = np.array([0.05, -0.02, 0.01, 0.0, 0.01, -0.01])
    d = np.ravel(model.thruster_alloc(w[:3], w[3:], 1.0, p)[0])
    F = float(p[model.offsets("p")["thruster_force"]][0])
    np.testing.assert_allclose(_thruster_B() @ d * F, w, rtol=0, atol=1e-13)
    # a window that closes: wheel 2 off over [0.2, 0.5) s, driven again after
    sim0, z0, params = _iii(model)
    s, e = _window(4, 1, 0.2, 0.5)
    sim = Simulation(model, "c000", params=_with(params, fault_wheel_off_start=s, fault_wheel_off_end=e),
                     gains=sim0._gains_given)
    res = sim.run(z0, 1.0)
    h2 = _col(model, sim, res, sim.z_layout, "h_w_2")
    k0, k1 = int(math.ceil(0.2 / sim.dt - 1e-9)), int(math.ceil(0.5 / sim.dt - 1e-9))
    assert np.all(h2[k0:k1 + 1] == h2[k0]) and np.ptp(h2[k1:]) > 0


def test_a_weak_fraction_outside_its_range_keeps_the_allocation_finite(model):
    """The schema refuses a weak value <= 0, but a parameter vector given directly may carry one:
    the nominal allocation (fdir 0), blended with the aware one, must not turn NaN."""
    p = model.vector("p", {"fault_thr_weak_start": _window(16, 4, 0.0)[0], "fault_thr_weak_value": [0.0] * 16,
                           "fault_wheel_weak_start": _window(4, 0, 0.0)[0], "fault_wheel_weak_value": [0.0] * 4})
    for fdir in (0.0, 1.0):
        p[model.offsets("p")["fdir_allocation"]] = fdir
        d = np.ravel(model.thruster_alloc(np.array([0.1, 0.0, 0.0]), np.zeros(3), 1.0, p)[0])
        T = np.ravel(model.wheel_alloc(np.array([0.01, 0.0, 0.0]), 1.0, p)[0])
        assert np.all(np.isfinite(d)) and np.all(np.isfinite(T))


def test_a_sensor_frozen_from_the_start_repeats_the_noise_free_first_measurement(model):
    sim0, z0, params = _iii(model, "baseline")
    p = _with(params, meas_pos_bias=[0.5, -0.25, 1.0], meas_pos_std=0.3,
              fault_sensor_freeze_start=[NEVER, NEVER, 0.0, NEVER])
    sim = Simulation(model, "baseline", params=p, gains=sim0._gains_given)
    res = sim.run(sim.initial_state(load_scenario(III).to_run(model).plant), 0.5, seed=1)
    yl, zl = model.labels(sim.y_layout), model.labels(sim.z_layout)
    for i, ax in enumerate("xyz"):
        m = res.y[:-1, yl.index(f"meas_r_{ax}")]
        assert np.all(m == res.z[0, zl.index(f"r_{ax}")] + [0.5, -0.25, 1.0][i])


def test_the_runtime_s_never_is_the_manifest_s(model):
    """runtime/scenario/faults.py cannot import symbolic/ and has no NEVER of its own: the manifest's
    (symbolic/physics/faults.py NEVER) is the default of every window its kinds name, and they name
    every window of p."""
    vocab = model.manifest.faults
    windows = {name for k in vocab.kinds.values() for name in (k.start, k.end)}
    assert windows == {f.name for f in model.layouts["p"]
                       if f.name.startswith("fault_") and f.name.endswith(("_start", "_end"))}
    assert vocab.never == NEVER
    for f in model.layouts["p"]:
        if f.name in windows:
            assert set(f.default or ()) == {vocab.never}, f.name
