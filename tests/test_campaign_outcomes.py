"""A campaign counts constraints by the rule of each run's verdict (rpo.runtime.outputs.verdict.
violated_constraints): its `constraint_violated` count equals the number of runs whose verdict says a
constraint was violated, whether or not the scenario declares [constraints]; `failed` counts only
the declared ones; the report says both rules."""

from __future__ import annotations

import numpy as np
import pytest
from test_campaign import BASE

from rpo.runtime.campaign import loads_campaign, run_campaign, start_folder, storage
from rpo.runtime.campaign.reporting import summary_table, write_report
from rpo.runtime.outputs.verdict import CONSTRAINT_RULE, CONSTRAINTS, declared_constraints, violated_constraints

#: the CW pair with the baseline law's default gains: it reaches the goal at the origin, through the
#: envelope spheres and mostly outside the default camera cone; no [constraints] table
CAMPAIGN = BASE.split("[controller.baseline]")[0].replace("duration = 1500.0", "duration = 200.0") + """
[campaign]
runs = 16
seed = 5
[dispersions.relative.position]
dist = "normal"
std = [30.0, 30.0, 60.0]
"""
DECLARED = CAMPAIGN + """
[constraints]
camera_half_angle_deg = 45.0
camera_zn = 1.2
chaser_radius = 2.1
target_radius = 1.5
"""


def fly(model, tmp_path, text, name):
    camp = loads_campaign(text, f"{name}.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path / name)
    run_campaign(camp, model, folder, workers=1)
    rows = storage.read_rows(folder)
    cols = summary_table(folder)
    lines = [rows[int(c)]["verdict"] for c in cols["case"]]
    return folder, cols, lines


@pytest.mark.parametrize("text,name", [(CAMPAIGN, "undeclared"), (DECLARED, "declared")])
def test_constraint_count_equals_the_verdicts_and_failed_counts_the_declared(model, tmp_path, text, name):
    folder, cols, lines = fly(model, tmp_path, text, name)
    says = np.array(["constraints violated:" in line for line in lines])
    flagged = cols["constraint_violated"] == 1.0
    assert 0 < says.sum() == flagged.sum() and np.array_equal(says, flagged)  # run by run
    missed = (cols["att_reached"] == 0.0) | (cols["pos_reached"] == 0.0) | (cols["diverged"] == 1.0)
    if name == "declared":
        assert np.array_equal(cols["failed"] == 1.0, missed | flagged)
    else:  # a constraint the scenario does not declare is counted, and fails no run
        assert np.array_equal(cols["failed"] == 1.0, missed)
        assert np.any(flagged & ~missed)  # the case the two rules tell apart
    report = write_report(folder, figures=False).read_text()
    row = next(ln for ln in report.splitlines() if ln.startswith("| constraint violated |"))
    assert row.split("|")[2].strip() == str(int(flagged.sum()))
    assert CONSTRAINT_RULE in report
    assert ("declares none" in report) == (name == "undeclared")


def test_one_rule_names_the_violated_and_the_declared_constraints():
    con = {"beta_fov": {"violated": True}, "beta_ca": {"violated": False}}
    assert violated_constraints(con) == ["beta_fov"]
    assert violated_constraints(con, only=()) == [] and violated_constraints(con, only=("beta_fov",)) == ["beta_fov"]
    assert declared_constraints({"constraints": {}}) == tuple(n for n, _, _ in CONSTRAINTS.values())
    assert declared_constraints({"chaser": {}}) == ()
