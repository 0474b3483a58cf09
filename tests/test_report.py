"""``rpo report`` on a tiny declared run list, the metrics of a real short run, the diag figures."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SCEN = ROOT / "scenarios"

RUN_LIST = f"""
[paper."000"]
title = "tiny"
controller = "baseline"

[[paper."000".claim]]
case = "III"
what = "attitude settles"
metric = "att_settling_time_s"
unit = "s"
published = 60.0
published_text = "about 60 s"

[[paper."000".claim]]
case = "III"
what = "final attitude error"
metric = "att_err_final_rad"
unit = "deg"
published = 0.0

[paper."000".table2]
case = "III"
times = [0.5, 1.0, 5.0]
q = [[1, 2, 3, 4], [1, 2, 3, 4], [1, 2, 3, 4]]
pos = [[1, 2, 3], [1, 2, 3], [1, 2, 3]]
rate_deg_s = [[1, 2, 3], [1, 2, 3], [1, 2, 3]]
vel = [[1, 2, 3], [1, 2, 3], [1, 2, 3]]

[[run]]
label = "iii-paper"
paper = "000"
case = "III"
scenario = "{SCEN / '000_scenario_III.toml'}"
controller = "baseline"
plant = "paper"
duration = 1.0
error_times = [0.25]  # the Table 2 times are added
gains = {{ kp_att = 0.3 }}

[[run]]
label = "iii-missing-controller"
paper = "000"
case = "III"
scenario = "{SCEN / '000_scenario_III.toml'}"
controller = "c999"
plant = "full"

[[comparison]]
case = "I"
scenario = "{SCEN / '000_scenario_I.toml'}"
controllers = ["baseline", "c999"]
plants = ["paper"]
duration = 0.5
"""

NOTES = '''
intro = "Intro text."
[paper]
"000" = "Why our numbers differ: a hand-written note."
'''


def rpo(*args, cwd):
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], cwd=cwd, capture_output=True,
                          text=True, timeout=300)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("report")
    (tmp / "runs.toml").write_text(RUN_LIST)
    (tmp / "notes.toml").write_text(NOTES)
    args = ["report", tmp / "runs.toml", "--out", tmp / "runs", "--md", tmp / "rep.md", "--json", tmp / "rep.json",
            "--notes", tmp / "notes.toml", "--no-plots"]
    res = rpo(*args, cwd=tmp)
    assert res.returncode == 0, res.stderr
    (tmp / "first.md").write_text((tmp / "rep.md").read_text())
    (tmp / "first.json").write_text((tmp / "rep.json").read_text())
    return tmp, res, args


def test_report_markdown_rows(report):
    tmp, res, _ = report
    md = (tmp / "first.md").read_text()
    assert "| case | claim | published | ours (paper plant) | ours (full plant) |" in md
    row = next(line for line in md.splitlines() if line.startswith("| III | attitude settles |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[2] == "about 60 s"
    assert cells[3] == "not settled"                      # 1 s is far too short
    assert cells[4] == "not run (no run declared)"        # the paper's controller has no full-plant run
    row = next(line for line in md.splitlines() if line.startswith("| III | final attitude error |"))
    assert row.split("|")[4].strip().endswith(" deg")
    # the Table 2 layout: a row per quantity and time, vectors of finite numbers up to the end of the run
    t2 = [line for line in md.splitlines() if line.startswith("| position [m] |")]
    assert len(t2) == 3
    assert t2[0].split("|")[3].strip() == "(1, 2, 3)"
    assert t2[0].split("|")[4].strip().startswith("(")
    assert "n/a" in t2[2].split("|")[4]                   # 5 s is after the end of the 1 s run
    assert any(line.startswith("| min beta_FOV [m] |") for line in md.splitlines())
    # the comparison table and the notes
    assert "| I | paper | baseline | ok |" in md
    assert "| I | paper | c999 | not run (controller c999 not generated yet) |" in md
    assert "Intro text." in md and "a hand-written note." in md
    assert "## Round-off sensitivity" in md and "## Summary" in md
    row = next(line for line in md.splitlines() if line.startswith("| III | attitude settles |"))
    assert row.split("|")[6].strip() == "0/16, -"          # perturbed copies reaching it: paper, full
    assert "iii-paper" in res.stdout


def test_report_json_twin_and_run_folders(report):
    tmp, _, args = report
    twin = json.loads((tmp / "first.json").read_text())
    runs = {r["label"]: r for r in twin["runs"]}
    assert set(runs) == {"iii-paper", "iii-missing-controller", "cmp-I-baseline-paper", "cmp-I-c999-paper"}
    ok = runs["iii-paper"]
    assert ok["status"] == "ok" and Path(ok["folder"]).parent == Path(twin["runs_dir"])
    assert (Path(ok["folder"]) / "metrics.json").exists()
    meta = json.loads((Path(ok["folder"]) / "run.json").read_text())
    assert meta["overrides"]["gains"] == {"kp_att": [0.3]}
    assert runs["iii-missing-controller"]["status"] == "not run"
    # every run that flew was flown again from perturbed initial states (16 copies by default)
    assert ok["roundoff"]["copies"] == 16 and ok["roundoff"]["att_settled"] == 0  # 1 s is far too short
    assert runs["iii-missing-controller"]["roundoff"] is None
    assert twin["tables"]["papers"]["000"]["claims"][0]["published_value"] == 60.0
    # a second invocation writes a fresh folder and keeps the first
    res = rpo(*args, "--only", "cmp-I-baseline-paper", cwd=tmp)
    assert res.returncode == 0, res.stderr
    twin2 = json.loads((tmp / "rep.json").read_text())
    assert twin2["runs_dir"] != twin["runs_dir"] and Path(ok["folder"]).is_dir()


def test_bad_run_list_is_one_line_error(tmp_path):
    (tmp_path / "runs.toml").write_text('[[run]]\nlabel = "x"\nscenario = "a.toml"\nplant = "moon"\n')
    res = rpo("report", tmp_path / "runs.toml", "--out", tmp_path / "runs", "--md", tmp_path / "r.md",
              "--json", tmp_path / "r.json", cwd=tmp_path)
    assert res.returncode == 2
    assert res.stderr.strip().startswith("error: ") and "run.0.plant" in res.stderr
    assert not (tmp_path / "r.md").exists()


def test_metrics_of_a_real_short_run_are_finite(report):
    tmp, _, _ = report
    twin = json.loads((tmp / "first.json").read_text())
    m = next(r for r in twin["runs"] if r["label"] == "iii-paper")["metrics"]
    for key in ("t_end_s", "att_err_final_rad", "att_err_ss_rms_rad", "pos_err_final_m", "rate_err_final_rad_s",
                "vel_err_final_m_s", "torque_effort_N_m_s", "force_effort_N_s", "delta_v_m_s", "propellant_kg",
                "wheel_momentum_peak_N_m_s", "wheel_speed_peak_rad_s", "beta_fov_min_m", "beta_ca_min_m2",
                "chatter_cmd_tau_w_tv_per_s", "chatter_cmd_F_sign_changes_per_s"):
        assert isinstance(m[key], float) and math.isfinite(m[key]), key
    assert m["t_end_s"] == pytest.approx(1.0)
    assert [e["t"] for e in m["errors_at"]] == [0.25, 0.5, 1.0, 5.0]
    assert m["errors_at"][1]["t_sample"] == pytest.approx(0.5)


def test_diag_figures_one_panel_per_extra_field(model, tmp_path):
    """Controller-specific ctrl_* fields get one panel each in diagnostics.png; absent standard
    fields are skipped."""
    from rpo.runtime.outputs.plots import make_plots
    from rpo.runtime.run.simulate import Simulation
    from rpo.runtime.scenario import load_scenario

    inputs = load_scenario(SCEN / "000_scenario_III.toml").with_overrides(controller="baseline").to_run(model)
    sim = Simulation(model, "baseline", params=inputs.params, gains=inputs.gains)
    res = sim.run(sim.initial_state(inputs.plant), 0.2)
    n = len(res.t)
    res.y = np.column_stack([res.y, np.ones((n, 2)), np.zeros(n)])
    res.y_labels = [*res.y_labels, "ctrl_s_att_x", "ctrl_s_att_y", "ctrl_theta_hat"]
    res.y_units = [*res.y_units, "-", "-", "kg"]

    from rpo.runtime.model.manifest import LayoutField

    class Fake:
        layouts = {**model.layouts, "y_baseline": [
            *model.layouts["y_baseline"],
            LayoutField(name="ctrl_s_att", size=2, unit="-", labels=("ctrl_s_att_x", "ctrl_s_att_y")),
            LayoutField(name="ctrl_theta_hat", size=1, unit="kg", labels=("ctrl_theta_hat",))]}

    from rpo.runtime.outputs.plotdata import PlotData
    from rpo.runtime.outputs.plots import diag_fields

    written = make_plots(res, Fake(), tmp_path)
    assert {"diagnostics.png", "controller.png", "constraints.png"} <= set(written)
    assert [f.name for f in diag_fields(PlotData.from_result(res, Fake()))] == ["ctrl_s_att", "ctrl_theta_hat"]
    for name in written:
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"


# --------------------------------------------------------------------------- runs discovered in scenario files


def test_report_reads_scenarios_through_the_one_loader():
    """Regression: the report's own TOML reader ignored ``extends`` and found no controller in
    000_III_no_acc_d.toml (its base selects c000); it now reads scenarios as load_scenario does."""
    from rpo.runtime.jobs.reproduction import PlannedRun, execute, scenario_controller
    from rpo.runtime.scenario import load_scenario, read_scenario

    path = SCEN / "000_III_no_acc_d.toml"
    assert "controller" not in path.read_text().split("[controller.c000]")[0]  # only the base names it
    assert scenario_controller(read_scenario(path)) == load_scenario(path).simulation.controller == "c000"

    class NoControllers:  # a model that has none: the report must say which one it looked for
        manifest = SimpleNamespace(controllers={})

    r = PlannedRun(label="x", scenario=path, controller=None, plant="paper", paper=None, case=None, duration=None,
                   seed=None, gains=None, thresholds=None, error_times=[])
    execute([r], NoControllers(), Path("unused"))
    assert (r.status, r.reason, r.controller_used) == ("not run", "controller c000 not generated yet", "c000")


def test_discovered_runs_are_the_committed_report_s_runs(model):
    """The [reproduction] tables of scenarios/ declare exactly the runs of docs/reproduction.json."""
    from rpo.runtime.jobs.reproduction import discover, fault_runs, plan

    run_list = discover(SCEN, model.manifest.controllers)
    runs = plan(run_list, SCEN) + fault_runs(SCEN, model.manifest.controllers)
    twin = json.loads((ROOT / "docs" / "reproduction.json").read_text())
    assert sorted(r.label for r in runs) == sorted(r["label"] for r in twin["runs"])
    by_label = {r["label"]: r for r in twin["runs"]}
    for r in runs:
        old = by_label[r.label]
        assert (Path(old["scenario"]).name, old["plant"], old["paper"], old["case"]) == \
            (r.scenario.name, r.plant, r.paper, r.case), r.label
    assert list(run_list.paper) == list(twin["tables"]["papers"])
    for pid, paper in run_list.paper.items():
        old = twin["tables"]["papers"][pid]
        assert (paper.title, paper.controller) == (old["title"], old["controller"])
        assert sorted((c.case, c.what) for c in paper.claim) == sorted((c["case"], c["what"]) for c in old["claims"])
    ideal = next(r for r in runs if r.label == "000-III-ideal-no-acc-paper")
    assert ideal.gains == {"acc_d_on": 0.0} and ideal.controller == "c000"
    assert next(r for r in runs if r.label == "002-kappa3-full").thresholds == {"pos_m": 0.3}  # paper-level


def test_a_new_scenario_file_adds_its_runs(tmp_path, model):
    """Adding a scenario with a [reproduction] table adds its runs and claims, no list edited."""
    from rpo.runtime.errors import RpoError
    from rpo.runtime.jobs.reproduction import discover, plan

    base = (SCEN / "000_scenario_III.toml").read_text()
    (tmp_path / "base.toml").write_text(base)
    (tmp_path / "variant.toml").write_text(
        'extends = "base.toml"\n[meta]\nname = "v"\n[reproduction]\npaper = "000"\n'
        '[[reproduction.run]]\ncase = "V"\nplants = ["full"]\n'
        '[[reproduction.claim]]\ncase = "V"\nwhat = "w"\nmetric = "pos_err_final_m"\n')
    run_list = discover(tmp_path, ["baseline", "c000"])
    labels = [r.label for r in plan(run_list, tmp_path)]
    # the base's own runs are not inherited by the variant; its comparison takes every controller
    assert labels == ["000-III-paper", "000-III-full", "000-V-full", "cmp-000-III-baseline-paper",
                      "cmp-000-III-baseline-full"]
    assert [c.case for c in run_list.paper["000"].claim] == ["III", "III", "V"]
    (tmp_path / "other.toml").write_text(
        base.replace('[reproduction]\npaper = "000"\n', '[reproduction]\npaper = "000"\ntitle = "again"\n'))
    (tmp_path / "third.toml").write_text(
        base.replace('[reproduction]\npaper = "000"\n', '[reproduction]\npaper = "000"\ntitle = "twice"\n'))
    with pytest.raises(RpoError, match="reproduction.title: paper 000's title is given in"):
        discover(tmp_path, ["c000"])


# --------------------------------------------------------------------------- outcomes from data, round-off

DOCS = ROOT / "docs"
#: words that state an outcome: only generated text (runtime/jobs/reproduction_prose.py) may use them
OUTCOME_WORDS = re.compile(r"\b(reach\w*|settl\w*|converg\w*|later than|earlier than|slower|faster|yes|reproduc\w*|"
                           r"diverg\w*|fail\w*|meets?|succeed\w*)\b", re.IGNORECASE)


def _committed():
    from rpo.runtime.jobs.reproduction import Notes, _load_toml

    twin = json.loads((DOCS / "reproduction.json").read_text())
    return twin, _load_toml(DOCS / "reproduction_notes.toml", Notes, "notes file")


def test_committed_report_is_its_json_rendered():
    """docs/reproduction.md is exactly what its JSON twin and the notes render to: every number and
    every outcome sentence comes from the data (re-run `rpo report` after editing either)."""
    from rpo.runtime.jobs.reproduction import rerender

    twin, notes = _committed()
    assert (DOCS / "reproduction.md").read_text() == rerender(twin, notes), \
        "docs/reproduction.md is not docs/reproduction.json rendered: run `rpo report` (after editing only the " \
        "notes: `python -c \"from rpo.runtime.jobs.reproduction import rerender_files; rerender_files()\"`)"


def test_notes_state_no_outcome():
    """The hand-written notes explain; the sentences that say reached, settled, converged, later than
    published... are generated from the runs (code spans, e.g. file names, are not text)."""
    _twin, notes = _committed()
    for where, text in (("intro", notes.intro), ("comparison", notes.comparison), ("faults", notes.faults),
                        *((f"paper.{k}", v) for k, v in notes.paper.items())):
        words = [m.group(0) for m in OUTCOME_WORDS.finditer(re.sub(r"`[^`]*`", "", text))]
        assert not words, f"docs/reproduction_notes.toml {where} states an outcome by hand: {words}"


def test_committed_outcomes_follow_the_verdict_rule():
    """Every goal the report calls reached (a settling time, "yes") is reached by the verdict's rule in
    that run's own metrics: its settling time exists and its final error is below the threshold; every
    run that flew has its perturbed copies."""
    from rpo.runtime.jobs.reproduction_roundoff import outcome, reached

    twin, _ = _committed()
    runs = {r["label"]: r for r in twin["runs"]}
    for r in twin["runs"]:
        m = r["metrics"]
        if r["status"] not in ("ok", "diverged"):
            continue
        assert r["roundoff"] and r["roundoff"]["copies"] >= 1, r["label"]
        for q, final_key, scale in (("att", "att_err_final_rad", 180 / math.pi), ("pos", "pos_err_final_m", 1.0)):
            if m[final_key] is None:
                continue
            th = m["thresholds"]["att_deg" if q == "att" else "pos_m"]
            assert reached(m, q) == m["verdict"]["goals"][q]["reached"], (r["label"], q)
            if reached(m, q):
                assert m[final_key] * scale < th, (r["label"], q)
    for row in twin["tables"]["comparison"]:
        if row["outcome"] is None:
            continue
        m = runs[row["run"]]["metrics"]
        assert row["converged"] == ("yes" if outcome(m, None, "both")["reached"] else "no"), row["run"]
        assert row["outcome"]["reached"] == m["converged"], row["run"]
    for paper in twin["tables"]["papers"].values():
        for row in paper["claims"]:
            for plant, d in row["plants"].items():
                if d["outcome"] is None:
                    continue
                m = runs[d["run"]]["metrics"]
                assert d["outcome"]["reached"] == reached(m, row["goal"]), (d["run"], plant)
                assert (row[f"ours_{plant}"] == "not settled") == (not d["outcome"]["reached"]), (d["run"], plant)


def test_perturbed_states_are_seeded_and_at_round_off_level():
    from rpo.runtime.jobs.reproduction_roundoff import REL, outcome, perturbed, summarize

    z0 = np.array([1.0, -2.5e6, 0.0, 3e-4])
    a, b = perturbed(z0, 16), perturbed(z0, 16)
    assert np.array_equal(a, b) and a.shape == (16, 4)          # the same copies on every invocation
    rel = np.abs(a[:, [0, 1, 3]] / z0[[0, 1, 3]] - 1)
    assert (rel > 0).any() and rel.max() < 10 * REL               # a few units in the last place
    assert (a[:, 2] == 0).all()                                   # an exact zero stays zero
    s = summarize([{"att": True, "pos": True, "diverged": False}] * 3 + [{"att": False, "pos": True,
                                                                          "diverged": True}], 4)
    assert (s["att_settled"], s["pos_settled"], s["converged"], s["diverged"]) == (3, 4, 3, 1)
    m = {"att_err_final_rad": 0.001, "att_settling_time_s": 10.0, "pos_err_final_m": 0.1, "pos_settling_time_s": 5.0}
    assert outcome(m, s, "att") == {"reached": True, "k": 3, "n": 4, "depends": True}
    assert outcome(m, s, "pos")["depends"] is False
    assert outcome(m, None, "both") == {"reached": True, "k": None, "n": None, "depends": False}


def test_unperturbed_copies_repeat_the_run(model, tmp_path):
    """Copies with a zero perturbation are the run itself (the lockstep lanes give the run's bits), so
    a disagreement of perturbed copies is the perturbation's doing."""
    from rpo.runtime.jobs.reproduction_roundoff import fly_copies
    from rpo.runtime.jobs.runner import execute_run

    o = execute_run(SCEN / "004_scenario.toml", tmp_path / "run", model, duration=120.0, plots=False)
    assert o.metrics["converged"]
    s = fly_copies(o, model, 3, rel=0.0)
    assert (s["att_settled"], s["pos_settled"], s["converged"], s["diverged"]) == (3, 3, 3, 0)
