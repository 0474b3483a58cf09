"""``--set KEY=VALUE``: a value changed from the command line is validated exactly as in the file, and
a run with it equals the run of the edited file."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from rpo.runtime.errors import ScenarioError
from rpo.runtime.scenario.overrides import apply_sets, parse_sets
from tests.test_cli import III, ROOT, assert_user_error, rpo


def test_values_are_read_as_toml_never_evaluated():
    got = parse_sets(["chaser.mass=90", "relative.position=[60, 0, 25]", "environment.j2=false",
                      "simulation.controller=c004", "a.b=__import__('os').system('true')"])
    assert got == {"chaser.mass": 90, "relative.position": [60, 0, 25], "environment.j2": False,
                   "simulation.controller": "c004", "a.b": "__import__('os').system('true')"}
    with pytest.raises(ScenarioError, match="KEY=VALUE"):
        parse_sets(["chaser.mass"])
    with pytest.raises(ScenarioError, match="KEY=VALUE"):
        parse_sets(["chaser..mass=1"])
    with pytest.raises(ScenarioError, match="chaser.mass is a value, not a table"):
        apply_sets({"chaser": {"mass": 1.0}}, {"chaser.mass.x": 2})
    with pytest.raises(ScenarioError, match="chaser is a table"):
        apply_sets({"chaser": {"mass": 1.0}}, {"chaser": 2})
    data = {"chaser": {"mass": 1.0}}
    assert apply_sets(data, {"chaser.mass": 2.0, "new.key": 1}) == {"chaser": {"mass": 2.0}, "new": {"key": 1}}
    assert data == {"chaser": {"mass": 1.0}}  # the table read is not changed


def test_bad_values_are_refused_like_the_file_would_be():
    for cmd in ("validate", "run", "linearize"):
        assert_user_error(rpo(cmd, III, "--set", "chaser.mass=-5"), "chaser.mass = -5", "allowed range")
    assert_user_error(rpo("validate", III, "--set", "chaser.mas=5"), "chaser.mas", "did you mean 'mass'")
    assert_user_error(rpo("validate", III, "--set", "chaser.mass=os.system('true')"), "chaser.mass")


def test_a_run_with_set_equals_the_run_of_the_edited_file(tmp_path):
    edited = tmp_path / "edited.toml"
    text = III.read_text()
    assert text.count("\n[chaser]\n") == 1 and "\nmass = " not in text.split("\n[chaser]\n")[1].split("\n[")[0]
    edited.write_text(text.replace("\n[chaser]\n", "\n[chaser]\nmass = 90.0\n", 1))
    a, b = tmp_path / "a", tmp_path / "b"
    res_a = rpo("run", III, "--set", "chaser.mass=90.0", "--duration", "2", "--no-plots", "--out", a, timeout=300)
    res_b = rpo("run", edited, "--duration", "2", "--no-plots", "--out", b, timeout=300, cwd=ROOT)
    assert res_a.returncode == 0 and res_b.returncode == 0, res_a.stderr + res_b.stderr
    ta, tb = pd.read_parquet(a / "timeseries.parquet"), pd.read_parquet(b / "timeseries.parquet")
    assert ta.equals(tb)
    copy = next(p for p in a.iterdir() if p.suffix == ".toml")
    assert copy.read_text().startswith("# chaser.mass = 90.0  (rpo --set")
    verdict = [json.loads((f / "metrics.json").read_text())["verdict"]["line"] for f in (a, b)]
    assert verdict[0] == verdict[1]


def test_mc_run_takes_set_and_refuses_a_bad_value_before_any_folder(tmp_path):
    camp = ROOT / "scenarios" / "campaigns" / "000_III_mc.toml"
    out = tmp_path / "mc"
    assert_user_error(rpo("mc", "run", camp, "--runs", "2", "--duration", "0.5", "--set", "chaser.mass=-3",
                          "--out", out), "chaser.mass = -3")
    assert not out.exists()
    res = rpo("mc", "run", camp, "--runs", "2", "--duration", "0.5", "--set", "campaign.seed=7", "--out", out, "-q",
              timeout=300)
    assert res.returncode == 0, res.stderr
    resolved = json.loads((out / "resolved.json").read_text())
    assert '"seed": 7' in json.dumps(resolved)  # the campaign flown is the changed one, recorded so
    assert "campaign.seed" in (out / "campaign.toml").read_text()  # and its copy names the override


def test_mc_resume_applies_the_set_values_the_campaign_was_started_with(tmp_path):
    """`rpo mc resume` re-reads the campaign file: without the recorded --set values it would see a
    different campaign and refuse ("the campaign changed")."""
    camp = ROOT / "scenarios" / "campaigns" / "000_III_mc.toml"
    out = tmp_path / "mc"
    res = rpo("mc", "run", camp, "--runs", "2", "--duration", "0.5", "--set", "chaser.mass=95.0", "--out", out, "-q",
              timeout=300)
    assert res.returncode == 0, res.stderr
    resolved = json.loads((out / "resolved.json").read_text())
    assert resolved["overrides"]["set"] == {"chaser.mass": "95.0"}
    assert resolved["scenario"]["chaser"]["mass"] == 95.0
    summary = (out / "summary.parquet").read_bytes()
    res = rpo("mc", "resume", out, "-q", timeout=300)
    assert res.returncode == 0, res.stderr
    assert (out / "summary.parquet").read_bytes() == summary  # nothing was missing: nothing flown again
