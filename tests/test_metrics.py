"""runtime/metrics.py on synthetic signals with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from rpo.runtime import metrics as M

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
