"""The verdict (runtime/outputs/verdict.py): goals reached and when, the main-reason rule on signals with
known answers, and `rpo run` ending with the verdict that metrics.json and run.json store."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.cli.main import main
from rpo.runtime.outputs import metrics as M
from rpo.runtime.outputs.verdict import SATURATION_MIN, verdict

ROOT = Path(__file__).resolve().parents[1]
T = np.linspace(0.0, 100.0, 1001)  # dt = 0.1 s
DEG = np.pi / 180
SETTLES = 10 * DEG * np.exp(-T / 5)      # below 1 deg from 5 ln 10 = 11.5 s
STAYS = 0 * T + 20 * DEG                 # never below 1 deg
REAL = {"actuators_ideal": 0.0, "wheel_torque_max": 0.1, "wheel_speed_max": 700.0, "wheel_delay": 0.002,
        "dt": 0.1}
IDEAL = {"actuators_ideal": 1.0, "force_max": 2.0, "torque_max": 0.5}


def run_verdict(att, pos=None, params=None, divergence=None, **cols):
    columns = {"ctrl_att_err": att, **cols}
    if pos is not None:
        columns.update(ctrl_pos_err_x=pos, ctrl_pos_err_y=0 * T, ctrl_pos_err_z=0 * T)
    p = {k: np.array([v]) for k, v in (params or {}).items()}
    m = M.compute_metrics(T, columns, params=p)
    return verdict(m, T, columns, p, divergence)


def wheels(cmd=0.0, applied=None, speed=0.0, n=4):
    applied = cmd if applied is None else applied
    out = {}
    for i in range(1, n + 1):
        out[f"wheel_cmd_{i}"] = np.broadcast_to(cmd, T.shape) * 1.0
        out[f"wheel_applied_{i}"] = np.broadcast_to(applied, T.shape) * 1.0
        out[f"env_wheel_speed_{i}"] = np.broadcast_to(speed, T.shape) * 1.0
    return out


def test_goals_reached_with_their_times_and_constraints_held():
    v = run_verdict(SETTLES, 3 * np.exp(-T / 10), REAL, env_beta_fov=0 * T + 1.0, env_beta_ca=0 * T + 2.0,
                    **wheels(0.01))
    assert v["status"] == "reached"
    assert v["goals"]["att"]["reached"] and v["goals"]["att"]["time_s"] == pytest.approx(5 * np.log(10), abs=0.05)
    assert v["goals"]["pos"]["time_s"] == pytest.approx(10 * np.log(6), abs=0.05)
    assert v["line"].startswith("verdict: reached: attitude reached at 11.5") and "constraints held" in v["line"]
    assert v["saturation"]["wheel_torque"]["fraction"] == 0 and v["saturation"]["wheel_speed"]["fraction"] == 0


def test_wheel_speed_limit_is_named_before_the_longer_torque_limit():
    # every step asks 0.1 N m (torque-limited 100 %); wheel speed at +700 rad/s with T < 0 after 70 s
    speed = np.where(T >= 70, 700.0, 100.0)
    v = run_verdict(STAYS, None, REAL, **wheels(-0.1, speed=speed))
    g = v["goals"]["att"]
    assert v["status"] == "not reached" and g["reached"] is False and g["reason_kind"] == "wheel_speed"
    assert v["saturation"]["wheel_speed"]["fraction"] == pytest.approx(0.3, abs=0.002)
    assert v["saturation"]["wheel_torque"]["fraction"] == pytest.approx(1.0)
    assert "speed limit" in g["reason"] and "30 %" in g["reason"] and "also" in g["reason"]
    # a wheel at its limit that is driven back (T > 0 at +700 rad/s) is not blocked
    v = run_verdict(STAYS, None, REAL, **wheels(0.1, speed=speed))
    assert v["saturation"]["wheel_speed"]["fraction"] == 0 and v["goals"]["att"]["reason_kind"] == "wheel_torque"


def test_a_wheel_delivering_less_than_allocated_is_torque_saturation_only_without_delay():
    short = wheels(0.05, applied=np.where(T >= 50, 0.0, 0.05))  # every wheel delivers nothing after 50 s
    v = run_verdict(STAYS, None, REAL, **short)
    assert v["saturation"]["wheel_torque"]["fraction"] == pytest.approx(0.5, abs=0.002)
    assert v["goals"]["att"]["reason_kind"] == "wheel_torque"
    # with wheel_delay >= dt the applied torque is an older command: not compared
    v = run_verdict(STAYS, None, {**REAL, "wheel_delay": 0.2}, **short)
    assert v["saturation"]["wheel_torque"]["fraction"] == 0


def test_thrusters_and_ideal_actuators_saturation_by_goal():
    duty = {f"thr_duty_{j:02d}": np.where(T < 40, 1.0, 0.3) for j in range(2)}
    v = run_verdict(SETTLES, 0 * T + 5.0, REAL, **duty, **wheels(0.01))
    assert v["status"] == "partly reached"
    assert v["goals"]["pos"]["reason_kind"] == "thrusters" and "40 %" in v["goals"]["pos"]["reason"]
    assert v["saturation"]["thrusters"]["goals"] == ["pos"]  # no thruster torque commanded
    # ideal actuators: applied below the command on x for 20 % of the run; torque never
    F = np.where(T < 20, 3.0, 1.0)
    cols = dict(cmd_F_x=F, cmd_F_y=0 * T, cmd_F_z=0 * T, env_F_applied_x=np.minimum(F, 2.0), env_F_applied_y=0 * T,
                env_F_applied_z=0 * T, **{f"{g}_{c}": 0 * T + 0.1 for g in ("cmd_tau_w", "env_tau_applied")
                                           for c in "xyz"}, **{f"cmd_tau_thr_{c}": 0 * T for c in "xyz"})
    v = run_verdict(STAYS, 0 * T + 5.0, IDEAL, **cols)
    assert set(v["saturation"]) == {"ideal_force", "ideal_torque"}
    assert v["saturation"]["ideal_force"]["fraction"] == pytest.approx(0.2, abs=0.002)
    assert v["goals"]["pos"]["reason_kind"] == "ideal_force"
    assert v["saturation"]["ideal_torque"]["fraction"] == 0 and v["goals"]["att"]["reason_kind"] == "none"


def test_small_saturation_is_not_the_reason_a_constraint_is_next_then_none():
    brief = np.where(T < SATURATION_MIN * 100 - 1, -0.1, 0.05)  # torque-limited for 4 % of the run
    fov = np.where((T > 30) & (T < 45), -2.0, 1.0)
    v = run_verdict(STAYS, None, REAL, env_beta_fov=fov, **wheels(brief))
    g = v["goals"]["att"]
    assert g["reason_kind"] == "constraint" and "beta_fov" in g["reason"] and "from 30.1 s" in g["reason"]
    assert v["constraints"]["beta_fov"]["violated_fraction"] == pytest.approx(0.149, abs=0.002)
    assert v["constraints"]["beta_fov"]["min"] == -2.0 and "constraints violated" in v["line"]
    v = run_verdict(STAYS, None, REAL, env_beta_fov=0 * T + 1.0, **wheels(brief))
    assert v["goals"]["att"]["reason_kind"] == "none" and "20 deg" in v["goals"]["att"]["reason"]
    assert "most: 4" in v["goals"]["att"]["reason"]


def test_divergence_is_the_main_reason_and_a_goal_not_logged_is_not_measured():
    class Div:
        time, label = 42.0, "xc_chi1_x"

        def message(self):
            return "simulation diverged in step 419"

    v = run_verdict(STAYS, None, REAL, divergence=Div(), **wheels(-0.1))
    assert v["status"] == "diverged" and v["goals"]["att"]["reason_kind"] == "divergence"
    assert "diverged at t = 42 s (xc_chi1_x)" in v["goals"]["att"]["reason"]
    assert v["goals"]["pos"]["reached"] is None and "position not measured" in v["line"]
    json.dumps(v, allow_nan=False)


def test_rpo_run_ends_with_the_verdict_stored_in_metrics_and_run_json(tmp_path, capsys):
    out = tmp_path / "ok"
    rc = main(["run", str(ROOT / "scenarios" / "001_scenario.toml"), "--duration", "2", "--no-plots",
               "--out", str(out)])
    printed = capsys.readouterr().out.strip().splitlines()
    assert rc == 0
    m, r = (json.loads((out / f).read_text()) for f in ("metrics.json", "run.json"))
    assert printed[-1] == m["verdict"]["line"] == r["verdict"]["line"]
    assert printed[-1].startswith("verdict: not reached: attitude NOT reached")  # 2 s is far too short
    assert m["verdict"]["goals"]["att"]["reason_kind"] == "none"
    # a diverging run (002 with the paper's gains) ends with the verdict too, exit code 3
    out = tmp_path / "div"
    rc = main(["run", str(ROOT / "scenarios" / "002_scenario.toml"), "--duration", "2", "--no-plots",
               "--out", str(out)])
    cap = capsys.readouterr()
    assert rc == 3 and "diverged" in cap.err
    line = cap.out.strip().splitlines()[-1]
    assert line.startswith("verdict: diverged:") and "the run diverged at t = 1.705 s" in line
    assert json.loads((out / "metrics.json").read_text())["verdict"]["line"] == line


def test_saturation_and_constraints_alone_equal_the_verdicts_with_nan_samples():
    # the verdict shares the run's hold weights between its fractions and takes the finite-only
    # fast path when no sample is NaN; the public functions (and a NaN sample) give the same
    from rpo.runtime.outputs.verdict import constraints, saturation
    speed = np.where(T >= 70, 700.0, 100.0)
    fov = (T - 30) ** 2 / 100 - 1.0
    fov[[0, 500]] = np.nan
    cols = {"ctrl_att_err": STAYS, **wheels(-0.1, speed=speed), "env_beta_fov": fov, "env_beta_ca": 5 - T / 10,
            "thr_duty_00": np.where(T > 50, 1.0, 0.5), "thr_duty_01": 0 * T, "cmd_tau_thr_x": 0 * T,
            "cmd_tau_thr_y": 0 * T, "cmd_tau_thr_z": np.where(T > 90, 1e-3, 0.0)}
    cols["wheel_cmd_2"] = cols["wheel_cmd_2"].copy()
    cols["wheel_cmd_2"][7] = np.nan
    p = {k: np.array([v]) for k, v in REAL.items()}
    v = verdict(M.compute_metrics(T, cols, params=p), T, cols, p)
    assert v["saturation"] == saturation(T, cols, p) and v["constraints"] == constraints(T, cols)
    assert v["saturation"]["thrusters"]["goals"] == ["pos", "att"]
    assert v["saturation"]["thrusters"]["fraction"] == pytest.approx(0.5, abs=0.002)
    c = v["constraints"]["beta_fov"]
    assert c["min"] == pytest.approx(-1.0) and c["min_t_s"] == pytest.approx(30.0) and c["violated"]
