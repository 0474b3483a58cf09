"""A scenario's goal is the scenario's: ``--controller X`` flies X towards it or refuses in one line.

* the ``[goal]`` table is validated like every key (one line naming the key and what is allowed),
  the keep-out sphere and the camera requirement included;
* a scenario without ``[goal]`` states its goal through its own controller's goal gains, and
  another controller flies that goal (``with_overrides``), not its own paper's;
* each entry of ``rpo.runtime.scenario.goals.DESIGNS`` is right: with the mapped gains, the
  controller's own errors (its ``ctrl_*`` outputs, or ``|r - r_goal|``) are zero at the goal
  pose, on the paper plant, and stay small over a short flight from there;
* refusals are one line, exit 2, nothing written; the run, ``run.json``, the verdict and
  ``rpo validate`` name the goal flown; the report's comparison refuses what cannot fly.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime import frames
from rpo.runtime.cli.main import main
from rpo.runtime.errors import ScenarioError
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import goals, load_scenario, loads_scenario
from rpo.runtime.scenario.goals import DESIGNS, Goal

ROOT = Path(__file__).resolve().parents[1]
SCEN = ROOT / "scenarios"
BASES = ("000_scenario_I", "000_scenario_III", "001_scenario", "002_scenario", "004_scenario")
CONTROLLERS = ("baseline", "c000", "c001", "c002", "c004")
#: which controller flies which shipped scenario's goal (module docstring of goals.py says why)
FLIES = {"000_scenario_I": {"baseline", "c000"}, "000_scenario_III": {"baseline", "c000"},
         "001_scenario": {"c001"}, "002_scenario": {"c002", "c004"}, "004_scenario": {"c002", "c004"}}
#: explicit goals other than the papers', each with the controllers that fly it (the gains are set)
GOAL_001_Z = '[goal]\nposition = [0.0, 0.0, 40.0]\nframe = "target"\nattitude = [1.0, 0.0, 0.0, 0.0]\n' \
             'camera_at_target = true\n'
GOAL_TARGET = '[goal]\nposition = [10.0, -3.0, 2.0]\nframe = "target"\nattitude = [0.0, 0.0, 0.0, 1.0]\n'
GOAL_LVLH = '[goal]\nposition = [20.0, 5.0, -3.0]\nframe = "lvlh"\nattitude = [1.0, 0.0, 0.0, 0.0]\n'
CUSTOM = [("001_scenario", GOAL_001_Z, "c001"), ("004_scenario", GOAL_TARGET, "c004"),
          ("002_scenario", GOAL_TARGET, "c002"), ("000_scenario_III", GOAL_LVLH, "c000"),
          ("000_scenario_III", GOAL_LVLH, "baseline")]


def text(name: str) -> str:
    return (SCEN / f"{name}.toml").read_text()


def with_goal(name: str, goal: str) -> str:
    """The scenario's text with ``goal`` as its [goal] table (before its first [controller.*])."""
    t = text(name)
    i = t.index("\n[controller.")
    return t[:i] + "\n" + goal + t[i:]


def drop_goal_gains(t: str) -> str:
    """The text without the lines that set a goal gain (the goal is then stated once, by [goal])."""
    gains = {n for d in DESIGNS.values() for n in d.gains}
    return "\n".join(ln for ln in t.splitlines() if ln.split("=")[0].strip() not in gains) + "\n"


# --------------------------------------------------------------------------- the table


@pytest.mark.parametrize(("old", "new", "needle"), [
    ("[10.0, -3.0, 2.0]", "[1.0e6, 0.0, 0.0]",
     "goal.position = [1000000.0, 0.0, 0.0]: each component must be in [-100000, 100000] m"),
    ("[10.0, -3.0, 2.0]", "[1.0, 2.0]", "goal.position = [1.0, 2.0]: must have 3 values, got 2"),
    ('"target"', '"eci"', "goal.frame = \"eci\": must be one of 'target' or 'lvlh'"),
    ("[0.0, 0.0, 0.0, 1.0]", "[0.5, 0.0, 0.0, 0.5]", "goal.attitude = [0.5, 0.0, 0.0, 0.5]: must be a unit quaternion"),
    ("[goal]\n", "[goal]\ncamera = true\n",
     "goal.camera = true: unknown key (allowed: position, frame, attitude, camera_at_target, contact)"),
    ('frame = "target"', 'frame = "lvlh"\ncamera_at_target = true',
     'goal.camera_at_target = true: needs frame = "target"'),
])
def test_goal_table_bad_values_are_one_line_naming_the_key(model, old, new, needle):
    goal = GOAL_TARGET.replace(old, new, 1)
    with pytest.raises(ScenarioError) as exc:
        loads_scenario(drop_goal_gains(with_goal("004_scenario", goal)), "x.toml", model.manifest)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("x.toml: ") and needle in msg, msg


def test_goal_table_missing_key_is_named(model):
    goal = GOAL_TARGET.replace('frame = "target"\n', "")
    with pytest.raises(ScenarioError, match=r"^x.toml: goal.frame: required key is missing$"):
        loads_scenario(drop_goal_gains(with_goal("004_scenario", goal)), "x.toml", model.manifest)


def test_goal_inside_the_keep_out_sphere_is_refused_unless_contact(model):
    inside = GOAL_TARGET.replace("[10.0, -3.0, 2.0]", "[0.0, 3.0, 0.0]")
    with pytest.raises(ScenarioError, match=r"goal.position = \[0.0, 3.0, 0.0\]: the goal is inside the keep-out "
                                            r"sphere: \|r\| = 3 m < constraints.chaser_radius \+ "
                                            r"constraints.target_radius = 3.6 m"):
        loads_scenario(drop_goal_gains(with_goal("004_scenario", inside)), "x.toml", model.manifest)
    sc = loads_scenario(drop_goal_gains(with_goal("004_scenario", inside + "contact = true\n")), "x.toml",
                        model.manifest)
    assert sc.goal_flown.text().startswith("contact at r = (0, 3, 0) m in target axes")
    # the sphere is the scenario's [constraints]
    smaller = drop_goal_gains(with_goal("004_scenario", inside)).replace("[disturbance.force]",
                                                       "[constraints]\nchaser_radius = 1.0\n\n[disturbance.force]", 1)
    assert loads_scenario(smaller, "x.toml", model.manifest).goal_flown.mapped


def test_a_goal_stated_by_gains_inside_the_keep_out_sphere_is_flagged(model, tmp_path, capsys):
    """As before [goal] existed (c000's and the baseline's default r_goal is the target's centre):
    flown, and the goal flown says so; the same goal in a [goal] table is refused."""
    t = text("000_scenario_III").replace("r_goal = [5.0, 0.0, 0.0]", "r_goal = [1.0, 0.0, 0.0]")
    sc = loads_scenario(t, "x.toml", model.manifest)
    warning = ("the goal is inside the keep-out sphere: |r| = 1 m < constraints.chaser_radius + "
               "constraints.target_radius = 3.6 m")
    assert sc.goal_flown.warning == warning and sc.goal_flown.text().endswith(f" (WARNING: {warning})")
    other = sc.with_overrides(controller="baseline")  # flown by another controller: still flagged, not refused
    assert other.goal_flown.warning == warning and other.with_overrides(duration=1.0).goal_flown.warning == warning
    f = tmp_path / "x.toml"
    f.write_text(t)
    assert main(["validate", str(f)]) == 0
    assert f"warning: {warning}" in capsys.readouterr().err


def test_camera_at_target_is_checked(model):
    sc = loads_scenario(drop_goal_gains(with_goal("001_scenario", GOAL_001_Z)), "x.toml", model.manifest)
    assert sc.goal_flown.goal.camera_on_target()
    away = GOAL_001_Z.replace("[1.0, 0.0, 0.0, 0.0]", "[0.0, 0.0, 0.0, 1.0]")
    with pytest.raises(ScenarioError, match=r"goal.attitude = \[0.0, 0.0, 0.0, 1.0\]: camera_at_target = true: the "
                                            r"camera \(body \+z\) must point at the target's centre at the goal "
                                            r"\(within 0.057 deg\); it is 180 deg off"):
        loads_scenario(drop_goal_gains(with_goal("001_scenario", away)), "x.toml", model.manifest)


def test_a_gain_that_restates_the_goal_must_equal_it(model):
    # 000 III sets r_goal in both controllers' tables: they restate the goal, so another value is refused
    t = text("000_scenario_III").replace("r_goal = [5.0, 0.0, 0.0]\n", "r_goal = [6.0, 0.0, 0.0]\n")
    sc = loads_scenario(t, "x.toml", model.manifest)  # c000 flies: its own table states the goal
    with pytest.raises(ScenarioError, match=r"controller.baseline.r_goal = \[6.0, 0.0, 0.0\]: differs from the "
                                            r"scenario's goal \(hold r = \(5, 0, 0\) m in LVLH"):
        sc.with_overrides(controller="baseline")
    with pytest.raises(ScenarioError, match=r"controller.c004.p_t = \[0.0, 5.0, 0.0\]: differs from the scenario's "
                                            r"goal"):
        loads_scenario(with_goal("004_scenario", GOAL_TARGET), "x.toml", model.manifest)


# --------------------------------------------------------------------------- which controller flies which goal


@pytest.mark.parametrize("name", BASES)
def test_each_controller_flies_the_scenario_s_goal_or_refuses_in_one_line(model, name):
    sc = load_scenario(SCEN / f"{name}.toml", model.manifest)
    goal = sc.goal_flown.goal
    assert goal is not None and sc.goal_flown.mapped and sc.goal_flown.controller == sc.simulation.controller
    for ctrl in CONTROLLERS:
        if ctrl in FLIES[name]:
            flown = sc.with_overrides(controller=ctrl).goal_flown
            assert flown.goal == goal and flown.mapped  # the same goal, from the same place
            d = DESIGNS[ctrl]
            np.testing.assert_array_equal(sc.with_overrides(controller=ctrl).gains()[d.position_gain], goal.position)
            continue
        with pytest.raises(ScenarioError) as exc:
            sc.with_overrides(controller=ctrl)
        msg = str(exc.value)
        assert "\n" not in msg and f'simulation.controller = "{ctrl}": {ctrl} cannot fly the scenario\'s goal' in msg
        assert f"/{name}.toml [" in msg, msg


def test_the_flown_goal_is_the_file_s_not_the_controller_s_paper_goal(model):
    """The issue: `--controller c004` on 002's scenario used to fly c004's default p_t; now the
    scenario's sigma_t, whatever c004's default."""
    t = text("002_scenario").replace("sigma_t = [0.0, 5.0, 0.0]", "sigma_t = [0.0, 8.0, 0.0]")
    assert t != text("002_scenario")
    sc = loads_scenario(t, "x.toml", model.manifest).with_overrides(controller="c004")
    np.testing.assert_array_equal(sc.gains()["p_t"], [0.0, 8.0, 0.0])
    assert "from x.toml [controller.c002] sigma_t" in sc.goal_flown.text()
    assert sc.with_overrides(duration=1.0).goal_flown.text() == sc.goal_flown.text()  # named where the file states it


def test_refusals_name_the_design_s_reason(model):
    def why(name, ctrl):
        with pytest.raises(ScenarioError) as exc:
            load_scenario(SCEN / f"{name}.toml", model.manifest).with_overrides(controller=ctrl)
        return str(exc.value)

    assert "its design always holds the chaser's axes along the target's" in why("001_scenario", "c004")
    assert "and this goal's attitude is 90 deg from that" in why("001_scenario", "c004")
    assert "000's interface frame" in why("001_scenario", "c000") and "fixed in LVLH" in why("001_scenario", "c000")
    assert "beta_FOV = " in why("004_scenario", "c001") and "001 eq. 53" in why("004_scenario", "c001")
    assert "fixed in target axes, and this goal's is fixed in LVLH" in why("000_scenario_III", "c004")


def test_a_controller_without_a_design_entry_flies_its_own_goal_and_says_so(model, monkeypatch):
    sc = load_scenario(SCEN / "000_scenario_III.toml", model.manifest)
    monkeypatch.delitem(DESIGNS, "baseline")
    flown = sc.with_overrides(controller="baseline").goal_flown
    assert not flown.mapped and flown.gains == {}
    assert flown.text().startswith("baseline's own goal gains, NOT mapped from the scenario's goal (hold r = (5, 0, 0)")
    monkeypatch.delitem(DESIGNS, "c000")  # the scenario's own controller: rpo cannot tell its goal
    sc = load_scenario(SCEN / "000_scenario_III.toml", model.manifest)
    assert sc.goal_flown.goal is None
    with pytest.raises(ScenarioError, match=r'simulation.controller = .c004.: cannot fly the scenario\'s goal: rpo '
                                            r"cannot tell it \(its controller c000 has no goal description"):
        sc.with_overrides(controller="c004")


def test_designs_match_the_manifest(model):
    """Every design names goal gains of its controller with the sizes and units of a goal."""
    assert set(DESIGNS) == set(model.manifest.controllers)  # a new paper controller gets an entry
    for ctrl, d in DESIGNS.items():
        layout = model.manifest.layouts[model.manifest.controllers[ctrl].gains]
        f = layout.field(d.position_gain)
        assert (f.size, f.unit) == (3, "m") and d.frame in f.doc.lower().replace("target body", "target"), (ctrl, f.doc)
        if d.attitude_gain:
            a = layout.field(d.attitude_gain)
            assert (a.size, a.unit) == (4, "-") and "scalar last" in a.doc
        assert (d.attitude_gain is None) != (d.fixed_attitude is None)


# --------------------------------------------------------------------------- the mapping: errors zero at the goal


def goal_pose(run, goal: Goal) -> dict:
    """The plant state at ``goal`` (the scenario's target state, t = 0): the chaser at the goal's
    position and attitude relative to the target, turning with it, with no relative motion in the
    goal's frame."""
    q_t, w_t = run.plant["q_t"], run.plant["w_t"]
    q_IL, n = run.frame_info["q_IL0"], run.frame_info["n0"]
    C_ST = frames.dcm_from_quat(goal.attitude).T
    plant = dict(run.plant, q_c=frames.quat_multiply(q_t, goal.attitude), w_c=C_ST @ w_t)
    pos = np.array(goal.position, float)
    if goal.frame == "target":
        C_LT = frames.dcm_from_quat(frames.quat_multiply(frames.quat_conjugate(q_IL), q_t))
        r_L = C_LT @ pos
        # fixed in target axes: inertial velocity w_t x r; LVLH-frame derivative: minus the frame's n z_L x r
        plant.update(r=r_L, v=C_LT @ np.cross(w_t, pos) - np.cross([0.0, 0.0, n], r_L))
    else:
        plant.update(r=pos, v=np.zeros(3))
    return plant


def errors(model, sim, z, y) -> dict[str, float]:
    """The controller's own errors, as the metrics read them."""
    yo, zo = model.offsets(sim.y_layout), model.offsets(sim.z_layout)
    out = {"att": float(y[yo["ctrl_att_err"]][0])}
    for e in ("pos_err", "rate_err", "vel_err"):
        if f"ctrl_{e}" in yo:
            out[e] = float(np.linalg.norm(y[yo[f"ctrl_{e}"]]))
    if "pos_err" not in out:  # baseline: |r - r_goal|, as rpo.runtime.outputs.metrics with goal = r_goal
        kr = model.offsets(f"k_{sim.controller}")["r_goal"]
        out["pos_err"] = float(np.linalg.norm(z[zo["r"]] - sim.k[kr]))
        out["rate_err"] = float(np.linalg.norm(y[yo["meas_w_e"]]))
        out["vel_err"] = float(np.linalg.norm(z[zo["v"]]))
    return out


CASES = [(name, None, ctrl) for name in BASES for ctrl in sorted(FLIES[name])] + CUSTOM


@pytest.mark.parametrize(("name", "goal", "ctrl"), CASES,
                         ids=[f"{n}-{'own' if g is None else 'custom'}-{c}" for n, g, c in CASES])
def test_mapped_gains_zero_the_controller_s_errors_at_the_goal(model, name, goal, ctrl):
    t = text(name) if goal is None else drop_goal_gains(with_goal(name, goal))
    sc = loads_scenario(t, f"{name}.toml", model.manifest).with_overrides(controller=ctrl, duration=2.0)
    flown = sc.goal_flown
    assert flown.mapped and flown.controller == ctrl
    run = sc.to_run(model)
    for gname, v in flown.gains.items():  # the run's gains are the goal's
        np.testing.assert_array_equal(run.gains[gname], v)
    sim = Simulation(model, ctrl, params=run.params, gains=run.gains)
    z0 = sim.initial_state(goal_pose(run, flown.goal))
    _z1, y0 = (np.ravel(a) for a in sim.step_fn(z0, 0.0, sim.p, sim.k, np.zeros(sim.nw)))
    err = errors(model, sim, z0, y0)
    assert err["att"] < 1e-7 and err["pos_err"] < 1e-7, err
    assert err["rate_err"] < 1e-9 and err["vel_err"] < 1e-7, err
    # the plant's constraint margins at the goal are the ones goals.py computes (001 eqs. 41, 47)
    yo = model.offsets(sim.y_layout)
    if flown.goal.frame == "target":
        p_TS = goals.target_in_chaser_axes(flown.goal.position, flown.goal.attitude)
        prm = {k: float(np.ravel(run.params[k])[0]) for k in ("camera_half_angle", "camera_zn", "target_radius",
                                                               "chaser_radius")}
        assert y0[yo["env_beta_fov"]][0] == pytest.approx(
            goals.camera_margin(p_TS, prm["camera_half_angle"], prm["camera_zn"], prm["target_radius"]), abs=1e-6)
        assert y0[yo["env_beta_ca"]][0] == pytest.approx(
            goals.keep_out_margin(p_TS, prm["chaser_radius"], prm["target_radius"]), abs=1e-6)
    # a short flight from the goal stays there (the paper plant's disturbances move it a little)
    res = sim.run(z0, 2.0, seed=0)
    labels = res.fields
    att = res["ctrl_att_err"][:, 0] if "ctrl_att_err" in labels else None
    assert att is not None and np.max(att) < math.radians(0.5), np.max(att)
    pos = np.linalg.norm(res["ctrl_pos_err"], axis=1) if "ctrl_pos_err" in labels else \
        np.linalg.norm(res["r"] - run.gains["r_goal"], axis=1)
    assert np.max(pos) < 0.1, np.max(pos)


# --------------------------------------------------------------------------- the command, run.json, verdict, report


def test_run_names_the_goal_and_a_refusal_is_one_line(model, tmp_path, capsys):
    out = tmp_path / "refused"
    rc = main(["run", "scenarios/001_scenario.toml", "--controller", "c004", "--plant", "full", "--duration", "1",
               "--no-plots", "--out", str(out)])
    cap = capsys.readouterr()
    lines = cap.err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("error: scenarios/001_scenario.toml (with command-line "
                                                               'overrides): simulation.controller = "c004": c004 '
                                                               "cannot fly the scenario's goal (hold r = (50, 0, 0) m "
                                                               "in target axes, camera at the target")
    assert "Traceback" not in cap.err + cap.out and not out.exists()

    out = tmp_path / "flown"
    rc = main(["run", "scenarios/002_scenario.toml", "--controller", "c004", "--duration", "1", "--no-plots",
               "--out", str(out), "--format", "npz"])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    last = cap.out.strip().splitlines()
    want = ("hold r = (0, 5, 0) m in target axes, the chaser's axes along the target's, q_S/T = (0, 0, 0, 1) "
            "(x, y, z, w), from scenarios/002_scenario.toml [controller.c002] sigma_t")
    assert last[-2] == f"goal: {want}" and last[-1].startswith("verdict: ")
    meta = json.loads((out / "run.json").read_text())
    metrics = json.loads((out / "metrics.json").read_text())
    assert meta["goal"]["text"] == meta["verdict"]["goal"] == want
    assert metrics["verdict"] == {k: v for k, v in meta["verdict"].items() if k != "goal"}  # metrics.json: no file name
    assert meta["goal"]["gains"] == {"p_t": [0.0, 5.0, 0.0]} and meta["goal"]["controller"] == "c004"
    assert meta["inputs"]["goal"] == meta["goal"]
    # the metrics judge the errors from that goal: c004's pos_err at t = 0 is the distance from
    # the scenario's initial position to the goal's (both in target axes, computed here)
    data = np.load(out / "timeseries.npz")
    labels = list(data["y_labels"])
    pos0 = np.array([data["y"][0, labels.index(f"ctrl_pos_err_{a}")] for a in "xyz"])
    run = load_scenario(SCEN / "002_scenario.toml", model.manifest).to_run(model)
    C_TL = frames.dcm_from_quat(frames.quat_multiply(frames.quat_conjugate(run.plant["q_t"]),
                                                     run.frame_info["q_IL0"]))
    assert np.linalg.norm(pos0) == pytest.approx(np.linalg.norm(C_TL @ run.plant["r"] - [0.0, 5.0, 0.0]), rel=1e-9)


def test_validate_prints_the_goal(capsys):
    assert main(["validate", "scenarios/001_scenario.toml"]) == 0
    out = capsys.readouterr().out
    assert ("  goal        hold r = (50, 0, 0) m in target axes, camera at the target, q_S/T = (0, -0.707107, 0, "
            "0.707107) (x, y, z, w), from scenarios/001_scenario.toml [controller.c001] r_D, q_D") in out.splitlines()


def test_the_report_s_comparison_flies_the_scenario_s_goal(model, tmp_path):
    """`rpo report`'s comparison runs go through the same overrides: a controller that cannot fly
    the scenario's goal is "refused" with the reason, one that can flies it (short runs)."""
    from rpo.runtime.jobs.reproduction import PlannedRun, execute

    runs = [PlannedRun(label=f"cmp-{c}", scenario=SCEN / "004_scenario.toml", controller=c, plant="paper", paper=None,
                       case="004", duration=0.5, seed=None, gains=None, thresholds=None, error_times=[])
            for c in ("c000", "c002", "c004")]
    execute(runs, model, tmp_path, plots=False)
    status = {r.controller_used: (r.status, r.reason) for r in runs}
    assert status["c000"][0] == "refused" and "c000 cannot fly the scenario's goal" in status["c000"][1]
    assert status["c004"][0] == "ok"
    assert status["c002"][0] in ("ok", "refused")  # the paper gains may not integrate from 004's start
    if status["c002"][0] == "refused":
        assert "cannot fly" not in status["c002"][1]
    meta = json.loads((tmp_path / "cmp-c004" / "run.json").read_text())
    assert meta["goal"]["source"].endswith("scenarios/004_scenario.toml [controller.c004] p_t")
