"""runtime/outputs/metrics.py on synthetic signals with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from rpo.runtime.outputs import metrics as M

T = np.linspace(0.0, 100.0, 10001)  # dt = 0.01 s


def decaying(e0=1.0, tau=10.0):
    return e0 * np.exp(-T / tau)


def test_settling_time_of_exponential_decay():
    # |e| = e0 exp(-t / tau) < thr from t = tau ln(e0 / thr) on
    e = decaying(2.0, 10.0)
    assert M.settling_time(T, e, 0.5) == pytest.approx(10.0 * np.log(4.0), abs=1e-4)
    assert M.settling_time(T, e, 3.0) == 0.0            # below from the start
    assert M.settling_time(T, e, 1e-6) is None          # not below at the end: not settled


def test_settling_time_requires_staying_below():
    e = decaying(2.0, 10.0)
    e[(T > 50) & (T < 60)] = 1.0                      # a late excursion above the threshold
    assert M.settling_time(T, e, 0.5) == pytest.approx(60.0, abs=0.011)


def test_settling_ignores_trailing_nan():
    e = decaying(2.0, 10.0)
    e[-1] = np.nan                                    # the last y row of a run
    assert M.settling_time(T, e, 0.5) == pytest.approx(10.0 * np.log(4.0), abs=1e-4)


def square(amplitude=2.0, period=4.0):
    return amplitude * np.sign(np.sin(2 * np.pi * (T + 0.005) / period))


def test_chatter_of_square_wave():
    # +-A switching every P/2: 2A per switch, 2/P switches per second
    u = np.column_stack([square(2.0, 4.0), np.zeros_like(T), np.ones_like(T)])
    tv, sc = M.chatter(T, u)
    assert tv == pytest.approx(4 * 2.0 / 4.0, rel=0.02)
    assert sc == pytest.approx(2 / 4.0, rel=0.02)


def columns_for(att, pos_err, rate_err=None, vel_err=None, **extra):
    cols = {"ctrl_att_err": att}
    for name, b in (("pos", pos_err), ("rate", rate_err), ("vel", vel_err)):
        if b is not None:
            for i, c in enumerate("xyz"):
                cols[f"ctrl_{name}_err_{c}"] = b[:, i]
    cols.update(extra)
    return cols


def test_compute_metrics_known_values():
    att = np.radians(10.0) * np.exp(-T / 5.0)              # 10 deg -> 1 deg at 5 ln 10 s
    pos = np.column_stack([3 * np.exp(-T / 20.0), 4 * np.exp(-T / 20.0), 0 * T])  # |pos| = 5 exp(-t/20)
    const = np.full_like(T, 0.01)
    rate = np.column_stack([const, 0 * T, 0 * T])
    F = np.column_stack([0 * T + 3.0, 0 * T + 4.0, 0 * T])  # |F| = 5 N
    cols = columns_for(att, pos, rate, rate,
                       env_F_applied_x=F[:, 0], env_F_applied_y=F[:, 1], env_F_applied_z=F[:, 2],
                       env_tau_applied_x=0 * T + 0.1, env_tau_applied_y=0 * T, env_tau_applied_z=0 * T,
                       env_m_c=0 * T + 50.0, m_prop=T * 1e-3,
                       h_w_1=np.sin(T), h_w_2=-1.5 * np.cos(T) * 0, h_w_3=0 * T - 0.7, h_w_4=0 * T,
                       env_beta_fov=(T - 30) ** 2 + 0.25, env_beta_ca=10 - T / 10)
    m = M.compute_metrics(T, cols)
    assert m["att_settling_time_s"] == pytest.approx(5 * np.log(10), abs=1e-4)
    assert m["pos_settling_time_s"] == pytest.approx(20 * np.log(10), abs=1e-4)
    assert m["pos_err_final_m"] == pytest.approx(5 * np.exp(-5))
    # steady state: RMS of |pos| over t in [90, 100]
    tail = T >= 90
    assert m["pos_err_ss_rms_m"] == pytest.approx(np.sqrt(np.mean((5 * np.exp(-T[tail] / 20)) ** 2)))
    assert m["rate_err_ss_rms_rad_s"] == pytest.approx(0.01)
    assert m["force_effort_N_s"] == pytest.approx(500.0)
    assert m["torque_effort_N_m_s"] == pytest.approx(10.0)
    assert m["delta_v_m_s"] == pytest.approx(10.0)
    assert m["propellant_kg"] == pytest.approx(0.1)
    assert m["wheel_momentum_peak_N_m_s"] == pytest.approx(1.0, abs=1e-6)
    assert m["beta_fov_min_m"] == pytest.approx(0.25) and m["beta_fov_min_t_s"] == pytest.approx(30.0)
    assert m["beta_ca_min_m2"] == pytest.approx(0.0) and m["beta_ca_min_t_s"] == pytest.approx(100.0)
    assert m["converged"] is True
    assert m["wheel_speed_peak_rad_s"] is None and "wheel_speed_peak_rad_s" in m["unavailable"]
    assert "chatter_cmd_F_tv_per_s" in m["unavailable"]
    # the printed table: the wheels' peak, unless the run flew ideal actuators (no wheel exists)
    wheels = [ln for ln in M.format_table(m).splitlines() if ln.split()[0] == "wheels"]
    assert wheels and "peak |h_w| 1 N m s" in wheels[0]
    wheels = [ln for ln in M.format_table(m, ideal_actuators=True).splitlines() if ln.split()[0] == "wheels"]
    assert wheels and "none: ideal force and torque actuators" in wheels[0] and "h_w" not in wheels[0]


def test_missing_fields_are_reported_not_fatal():
    cols = {"ctrl_att_err": np.radians(5.0) * np.exp(-T)}   # the baseline logs only this
    m = M.compute_metrics(T, cols)
    assert m["att_settling_time_s"] is not None
    assert m["pos_settling_time_s"] is None and "pos_settling_time_s" in m["unavailable"]
    assert m["converged"] is True  # only what is measured counts
    assert "position" in M.format_table(m) and "not logged" in M.format_table(m)
    # the position error falls back on r - goal when a goal is given
    cols.update(r_x=1 + np.exp(-T), r_y=0 * T, r_z=0 * T)
    m = M.compute_metrics(T, cols, goal=[1.0, 0, 0])
    assert m["pos_settling_time_s"] == pytest.approx(np.log(2.0), abs=1e-4)
    assert "r - goal" in m["sources"]["pos"]


def test_errors_at():
    pos = np.column_stack([T, 2 * T, -T])
    q = np.column_stack([0 * T + 0.1, 0 * T, 0 * T, 0 * T + 1.0])
    cols = columns_for(0 * T, pos)
    cols.update({f"ctrl_q_err_{c}": q[:, i] for i, c in enumerate("xyzw")})
    out = M.errors_at(T, cols, [30.0, 30.004, 100.0, 150.0])
    assert out[0]["pos_m"] == pytest.approx([30.0, 60.0, -30.0])
    assert out[1]["t_sample"] == pytest.approx(30.0)
    assert out[2]["pos_m"] == pytest.approx([100.0, 200.0, -100.0])
    assert out[0]["q"] == pytest.approx([0.1, 0, 0, 1.0])
    assert out[3]["pos_m"] is None and out[3]["rate_rad_s"] is None  # after the end of the run


def test_metrics_json_ready():
    import json
    m = M.compute_metrics(T, columns_for(decaying(), np.column_stack([decaying()] * 3)), error_times=[50.0])
    json.dumps(m, allow_nan=False)


def test_numbered_components_are_accepted():
    pos = {f"ctrl_pos_err_{i}": (i + 1) * np.exp(-T) for i in range(3)}
    m = M.compute_metrics(T, {"ctrl_att_err": 0 * T, **pos})
    assert m["pos_err_final_m"] == pytest.approx(np.sqrt(14) * np.exp(-100))


def test_fast_helpers_give_the_bits_of_the_numpy_calls_they_replace():
    # norm_rows / stack_columns stand for np.linalg.norm(np.column_stack(...), axis=1) and
    # np.column_stack (the metrics of a campaign must not change by a bit); chatter's vectorised
    # sign-change count for the per-axis loop
    rng = np.random.default_rng(7)
    for _ in range(200):
        cols = [rng.standard_normal(301) * 10.0 ** rng.uniform(-8, 8, 301) for _ in range(4)]
        b = np.column_stack(cols)
        assert np.array_equal(M.stack_columns(cols), b) and M.stack_columns(cols).flags.c_contiguous
        assert np.array_equal(M.norm_rows(*cols[:3]), np.linalg.norm(b[:, :3], axis=1))
        assert np.array_equal(M.norm_rows(*cols), np.linalg.norm(b, axis=1))
        assert np.array_equal(M._quat_angle_of(*cols), M.quat_angle(b))
        u = np.round(rng.standard_normal((301, 3)), 1) * (rng.uniform(size=(301, 3)) > 0.3)
        t = np.arange(301.0)
        changes = 0
        for col in u.T:
            s = np.sign(col[np.abs(col) > 0.05 * np.max(np.abs(u))])
            changes += int(np.count_nonzero(s[1:] != s[:-1]))
        assert M.chatter(t, u, 0.05)[1] == changes / 300.0


def test_error_signals_without_components():
    cols = columns_for(decaying(), np.column_stack([decaying()] * 3), ctrl_q_err_x=0 * T, ctrl_q_err_y=0 * T,
                       ctrl_q_err_z=0 * T + 0.1, ctrl_q_err_w=0 * T + 1)
    sig, comp, src = M.error_signals(cols)
    sig2, comp2, src2 = M.error_signals(cols, components=False)
    assert set(comp) == {"q", "pos"} and comp2 == {} and src == src2 and list(sig) == list(sig2)
    assert all(np.array_equal(sig[k], sig2[k]) for k in sig)


# --------------------------------------------------------------------------- per-unit use

WHEEL_P = {"wheel_torque_max": np.array([0.1]), "wheel_speed_max": np.array([700.0]), "thruster_force": np.array([2.0]),
           "thruster_isp": np.array([200.0]), "g0": np.array([10.0]), "actuators_ideal": np.array([0.0])}


def unit_cols():
    """Wheel 1 at +-0.1 N m for t < 25 s then 0.05 N m; wheel 2 ramps to 700 rad/s at t = 50 s;
    thruster 00 pulses 1 s on / 1 s off (50 firings); thruster 01 on at half thrust from t = 80 s."""
    sign = np.where(T < 12.5, 1.0, -1.0)
    cols = {"wheel_applied_1": np.where(T < 25, 0.1 * sign, 0.05), "wheel_applied_2": 0 * T + 0.01,
            "env_wheel_speed_1": 0 * T + 10.0, "env_wheel_speed_2": -np.minimum(14 * T, 700.0),
            "thr_on_00": (np.floor(T) % 2 == 0).astype(float), "thr_on_01": np.where(T >= 80, 0.5, 0.0)}
    return cols


def test_per_wheel_use_known_values():
    m = M.compute_metrics(T, {"ctrl_att_err": 0 * T, **unit_cols()}, params=WHEEL_P)
    w1, w2 = m["per_wheel"]
    assert (w1["wheel"], w2["wheel"]) == ("1", "2")  # the key was "unit" (renamed: it is no unit)
    assert w1["torque_peak_N_m"] == pytest.approx(0.1) and w2["torque_peak_N_m"] == pytest.approx(0.01)
    # RMS over [0, 100) s, sample-and-hold: 0.1^2 for 25 s, 0.05^2 for 75 s
    assert w1["torque_rms_N_m"] == pytest.approx(np.sqrt((25 * 0.01 + 75 * 0.0025) / 100), rel=1e-3)
    assert w1["torque_limit_fraction"] == pytest.approx(0.25, abs=1e-3) and w2["torque_limit_fraction"] == 0
    assert w2["speed_peak_rad_s"] == pytest.approx(700.0)
    # |speed| >= 0.99 * 700 from t = 49.5 s
    assert w2["speed_limit_fraction"] == pytest.approx(0.505, abs=1e-3) and w1["speed_limit_fraction"] == 0
    assert "wheel 2" in M.format_table(m) and "at the speed limit 50.5 %" in M.format_table(m)


def test_per_thruster_use_known_values():
    m = M.compute_metrics(T, {"ctrl_att_err": 0 * T, **unit_cols()}, params=WHEEL_P)
    t0, t1 = m["per_thruster"]
    assert t0["thruster"] == "00" and t0["firings"] == 50 and t0["on_time_s"] == pytest.approx(50.0, abs=0.02)
    assert t1["firings"] == 1 and t1["on_time_s"] == pytest.approx(20.0, abs=0.02)
    flow = 2.0 / (200.0 * 10.0)  # kg/s at full thrust
    assert t0["propellant_kg"] == pytest.approx(50 * flow, rel=1e-3)
    assert t1["propellant_kg"] == pytest.approx(10 * flow, rel=1e-3)  # half thrust for 20 s
    assert t0["propellant_share"] + t1["propellant_share"] == pytest.approx(1.0)
    assert t0["propellant_share"] == pytest.approx(50 / 60, rel=1e-3)
    assert "thrusters" in M.format_table(m)


def test_per_unit_use_without_params_or_on_ideal_actuators():
    cols = {"ctrl_att_err": 0 * T, **unit_cols()}
    m = M.compute_metrics(T, cols)  # no limits known: the fractions and the propellant are None
    assert m["per_wheel"][0]["torque_limit_fraction"] is None and m["per_wheel"][0]["torque_peak_N_m"] == 0.1
    assert m["per_thruster"][0]["propellant_kg"] is None and m["per_thruster"][0]["firings"] == 50
    m = M.compute_metrics(T, cols, params={**WHEEL_P, "actuators_ideal": np.array([1.0])})
    assert m["per_wheel"] is None and m["per_thruster"] is None and "ideal" in m["unavailable"]["per_wheel"]
    m = M.compute_metrics(T, {"ctrl_att_err": 0 * T})
    assert m["per_wheel"] is None and "wheel_applied" in m["unavailable"]["per_wheel"]


def test_per_thruster_propellant_adds_up_to_the_plants_on_a_run(model):
    """On a real run (000 scenario III's wheels and PWPF thrusters), the units' propellant sums to
    the plant's m_prop and the shares to 1; no wheel exceeds its limits."""
    from rpo.runtime.run.simulate import Simulation

    from conftest import Q_C0_III, Q_T0_III, unit
    sim = Simulation(model, "baseline")
    res = sim.run(sim.initial_state({"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "w_t": [0.1, 0.0, 0.05],
                                     "r": [60, 0, 25], "v": [3, -0.5, 5]}), 3.0)
    params = {name: sim.p[sl] for name, sl in model.offsets("p").items()}
    m = M.compute_metrics(res.t, M.result_columns(res), params=params)
    thr = m["per_thruster"]
    assert len(thr) == 16 and len(m["per_wheel"]) == 4
    assert m["propellant_kg"] > 0
    assert sum(e["propellant_kg"] for e in thr) == pytest.approx(m["propellant_kg"], rel=1e-9)
    assert sum(e["propellant_share"] for e in thr if e["propellant_share"]) == pytest.approx(1.0)
    assert sum(e["firings"] for e in thr) > 0
    assert all(e["torque_peak_N_m"] <= params["wheel_torque_max"][0] * (1 + 1e-12) for e in m["per_wheel"])
