"""Requirements of a campaign: parsing, the Clopper-Pearson verdicts (Hanson & Beard's run counts),
``rpo mc plan``, the verdicts in report.md and summary.parquet, and the sequential mode (its error
rate by simulation, and a stopped campaign's summary against a campaign of that many runs)."""

from __future__ import annotations

import json
import math
from functools import cache

import numpy as np
import pyarrow.parquet as pq
import pytest
from drift_scenario import drift_scenario
from scipy import stats

from rpo.runtime.campaign import loads_campaign, run_campaign, start_folder, storage
from rpo.runtime.campaign.reporting import write_report
from rpo.runtime.campaign.requirements import (
    METRIC_COLUMNS,
    SUMMARY_KEY,
    Requirement,
    decide,
    lower_bound,
    read_summary_verdicts,
    runs_needed,
    upper_bound,
)
from rpo.runtime.campaign.sequential import look_points
from rpo.runtime.errors import CampaignError

# --------------------------------------------------------------------------- the statistics


def test_hanson_beard_0_9973_at_95_percent_needs_1109_runs():
    # NASA/TP-2010-216447: 0.9973 met at 95 % confidence with no failure needs 1109 runs
    assert runs_needed(0.9973, 0.95) == 1109
    req = Requirement("r", "pos_err_final_m", "max", 0.5, 0.9973, 0.95)
    assert decide(req, 1109, 0).verdict == "PASS"
    v = decide(req, 1108, 0)
    assert v.verdict == "UNDECIDED" and v.runs_still_needed == 1
    # the classic success-run counts: 0.95 / 95 % -> 59 (Wilks' first order), 0.99 / 95 % -> 299
    assert runs_needed(0.95, 0.95) == 59
    assert runs_needed(0.99, 0.95) == 299


@pytest.mark.parametrize("p,c,k", [(0.9973, 0.95, 1), (0.9973, 0.95, 2), (0.99, 0.9, 3), (0.9, 0.99, 5),
                                   (0.5, 0.95, 0)])
def test_runs_needed_is_the_smallest_n_by_the_binomial_tail(p, c, k):
    # independent of the beta quantile: the lower bound reaches p iff P(failures <= k | failure rate 1 - p) <= a
    n = runs_needed(p, c, k)
    a = 1.0 - c
    assert stats.binom.cdf(k, n, 1.0 - p) <= a
    assert stats.binom.cdf(k, n - 1, 1.0 - p) > a


def test_bounds_agree_with_the_binomial_tails():
    for s, n, c in [(7, 10, 0.9), (95, 100, 0.95), (0, 5, 0.95), (5, 5, 0.8), (1, 30, 0.99)]:
        lo, up = lower_bound(s, n, c), upper_bound(s, n, c)
        a = 1.0 - c
        if s > 0:  # P(S >= s | lo) = a
            assert stats.binom.sf(s - 1, n, lo) == pytest.approx(a, rel=1e-9)
        else:
            assert lo == 0.0
        if s < n:  # P(S <= s | up) = a
            assert stats.binom.cdf(s, n, up) == pytest.approx(a, rel=1e-9)
        else:
            assert up == 1.0


def test_verdicts_pass_fail_undecided():
    req = Requirement("r", "pos_err_final_m", "max", 0.5, 0.9, 0.95)
    assert decide(req, 100, 2).verdict == "PASS"         # lower bound 0.9389
    fail = decide(req, 100, 20)
    assert fail.verdict == "FAIL" and fail.upper < 0.9 and fail.runs_still_needed is None
    und = decide(req, 40, 3)
    assert und.verdict == "UNDECIDED" and und.lower < 0.9 <= und.upper
    assert und.runs_still_needed == runs_needed(0.9, 0.95, 3) - 40
    assert decide(req, 40 + und.runs_still_needed, 3).verdict == "PASS"
    # a Bonferroni look is stricter than a single one
    assert decide(req, 100, 2, looks=10).lower < decide(req, 100, 2).lower


# --------------------------------------------------------------------------- the campaign file

BASE = drift_scenario("req", 60.0) + """[dispersions.relative.position]
dist = "normal"
std = [2.0, 3.0, 1.5]
"""


def campaign_text(requirements: str, campaign: str = "runs = 40\nseed = 3\nrate_hz = 0.1") -> str:
    return BASE + f"[campaign]\n{campaign}\n" + requirements


REQ = """
[requirements.flown_to_the_end]
metric = "t_end_s"
min = 59.0
probability = 0.9
confidence = 0.95
description = "every run reaches the end"
"""


def test_requirements_parsed_into_the_resolved_campaign(model):
    camp = loads_campaign(campaign_text(REQ), "req.toml", model.manifest)
    (r,) = camp.requirements
    assert (r.name, r.metric, r.kind, r.bound, r.probability, r.confidence) == (
        "flown_to_the_end", "t_end_s", "min", 59.0, 0.9, 0.95)
    assert r.description == "every run reaches the end"
    assert camp.resolved()["requirements"][0]["metric"] == "t_end_s"
    # a campaign without requirements keeps the resolved form (and hash) it always had
    assert "requirements" not in loads_campaign(campaign_text(""), "req.toml", model.manifest).resolved()


@pytest.mark.parametrize("body,fragment", [
    ('metric = "pos_err"\nmax = 1.0\nprobability = 0.9\nconfidence = 0.9',
     'requirements.a.metric = "pos_err": not a metric column of the summary; available: t_end_s'),
    ('metric = "pos_err_final_m"\nmax = 1.0\nmin = 0.0\nprobability = 0.9\nconfidence = 0.9',
     "requirements.a: give exactly one of max"),
    ('metric = "pos_err_final_m"\nprobability = 0.9\nconfidence = 0.9', "got neither"),
    ('metric = "pos_err_final_m"\nmax = 1.0\nprobability = 1.0\nconfidence = 0.9',
     "requirements.a.probability = 1.0: must be in (0, 1)"),
    ('metric = "pos_err_final_m"\nmax = 1.0\nprobability = 0.9\nconfidence = 0',
     "requirements.a.confidence = 0: must be in (0, 1)"),
    ('metric = "pos_err_final_m"\nmax = "big"\nprobability = 0.9\nconfidence = 0.9',
     "requirements.a.max = \"big\": must be a finite number"),
    ('metric = "pos_err_final_m"\nmax = 1.0\nprobability = 0.9', "requirements.a.confidence: required"),
    ('metric = "pos_err_final_m"\nmax = 1.0\nprobability = 0.9\nconfidence = 0.9\nmaximum = 2',
     "requirements.a.maximum: unknown field"),
])
def test_bad_requirements_are_one_line_errors(model, body, fragment):
    with pytest.raises(CampaignError) as exc:
        loads_campaign(campaign_text(f"[requirements.a]\n{body}\n"), "req.toml", model.manifest)
    msg = str(exc.value)
    assert fragment in msg and "\n" not in msg
    if "not a metric column" in fragment:
        assert all(m in msg for m in METRIC_COLUMNS)


@pytest.mark.parametrize("campaign,fragment", [
    ("runs = 40\nsequential = true", "needs [requirements.<name>]"),
    ("runs = 40\nlooks = 4", "campaign.looks = 4: only with campaign.sequential = true"),
    ('runs = 40\nsequential = true\nsampling = "lhs"', "a sequential campaign needs"),
])
def test_bad_sequential_settings(model, campaign, fragment):
    text = campaign_text(REQ if "requirements" not in fragment else "", campaign)
    with pytest.raises(CampaignError, match=None) as exc:
        loads_campaign(text, "req.toml", model.manifest)
    assert fragment in str(exc.value)


# --------------------------------------------------------------------------- verdicts of a flown campaign

TWO = REQ + """
[requirements.never_met]
metric = "t_end_s"
max = 1.0
probability = 0.5
confidence = 0.9
"""


@pytest.fixture(scope="module")
def flown(model, tmp_path_factory):
    camp = loads_campaign(campaign_text(TWO), "req.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path_factory.mktemp("req") / "mc")
    out = run_campaign(camp, model, folder, workers=1)
    assert out.counts["ok"] == 40
    return folder


def test_summary_metadata_holds_the_verdicts(flown):
    meta = read_summary_verdicts(flown)
    assert meta is not None and meta["looks"] == 1
    by = {v["name"]: v for v in meta["verdicts"]}
    t_end = pq.read_table(flown / storage.SUMMARY).column("t_end_s").to_numpy()
    met = int(np.sum(t_end >= 59.0))
    assert by["flown_to_the_end"]["met"] == met == 40
    assert by["flown_to_the_end"]["verdict"] == ("PASS" if lower_bound(met, 40, 0.95) >= 0.9 else "UNDECIDED")
    assert by["flown_to_the_end"]["lower"] == pytest.approx(0.05 ** (1 / 40))  # 0.9279 >= 0.9: PASS
    assert by["never_met"]["met"] == 0 and by["never_met"]["verdict"] == "FAIL"
    # the other metadata keys are still there
    md = pq.read_schema(flown / storage.SUMMARY).metadata
    assert b"rpo.units" in md and b"rpo.campaign" in md and SUMMARY_KEY.encode() in md


def test_report_has_the_requirement_table(flown, tmp_path):
    text = write_report(flown, out=tmp_path, figures=False).read_text()
    sec = text.split("## Requirements", 1)[1].split("\n## ", 1)[0]
    assert "| requirement | metric | bound | met k/n |" in sec
    row = next(line for line in sec.splitlines() if line.startswith("| `flown_to_the_end`"))
    assert "every run reaches the end" in row and "| 40/40 |" in row and "**PASS**" in row and ">= 59 s" in row
    row = next(line for line in sec.splitlines() if line.startswith("| `never_met`"))
    assert "| 0/40 |" in row and "**FAIL**" in row


def test_a_run_that_did_not_finish_fails_every_requirement():
    from rpo.runtime.campaign.requirements import judge
    req = Requirement("r", "pos_err_final_m", "max", 1.0, 0.5, 0.9)
    status = np.array(["ok", "ok", "diverged", "error", "invalid", "ok"], dtype=object)
    values = {"pos_err_final_m": np.array([0.5, 2.0, 0.1, np.nan, np.nan, np.nan])}
    (v,) = judge([req], status, values)
    assert (v.n, v.met, v.failures) == (6, 1, 5)


def test_plan_command(tmp_path, capsys):
    from rpo.runtime.cli.main import main
    f = tmp_path / "plan.toml"
    f.write_text(campaign_text("""
[requirements.position_final]
metric = "pos_err_final_m"
max = 0.5
probability = 0.9973
confidence = 0.95
"""))
    assert main(["mc", "plan", str(f), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["requirements"][0]["runs"] == {"0": 1109, "1": runs_needed(0.9973, 0.95, 1),
                                              "2": runs_needed(0.9973, 0.95, 2)}
    assert out["most"]["0"] == 1109
    assert main(["mc", "plan", str(f)]) == 0
    text = capsys.readouterr().out
    assert "1109" in text and "too few" in text
    assert main(["mc", "plan", str(f), "--set", "campaign.sequential=true", "--set", "campaign.looks=5",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["most"]["0"] == runs_needed(0.9973, 0.99) == 1704
    assert main(["mc", "plan", str(f), "--set", "requirements.position_final.metric=nope"]) == 2
    err = capsys.readouterr().err
    assert "requirements.position_final.metric" in err and "Traceback" not in err and len(err.splitlines()) == 1


# --------------------------------------------------------------------------- sequential mode


@cache
def _verdict(p: float, c: float, n: int, k: int, looks: int) -> str:
    return decide(Requirement("r", "t_end_s", "min", 0.0, p, c), n, k, looks).verdict


def simulate(p_true: float, p_req: float, conf: float, runs: int, looks: int, reps: int, seed: int,
             rule_looks: int | None = None) -> tuple[float, float]:
    """(false-PASS-or-PASS rate, FAIL rate) of the sequential rule over ``reps`` campaigns of Bernoulli runs
    (success probability ``p_true``); ``rule_looks`` = 1 judges each look at the full confidence (the naive rule)."""
    rng = np.random.default_rng(seed)
    points = look_points(runs, looks)
    fails = np.cumsum(rng.random((reps, runs)) >= p_true, axis=1)[:, np.array(points) - 1]
    n_pass = n_fail = 0
    for row in fails:
        for n, k in zip(points, row, strict=True):
            v = _verdict(p_req, conf, n, int(k), rule_looks or len(points))
            if v != "UNDECIDED":
                n_pass += v == "PASS"
                n_fail += v == "FAIL"
                break
    return n_pass / reps, n_fail / reps


@pytest.mark.parametrize("p_true", [0.95, 0.94])
def test_sequential_rule_keeps_its_confidence(p_true):
    # required 0.95 at 90 % (a = 0.1), 400 runs at most, 8 looks; the true probability at and
    # beyond the boundary: a PASS is wrong, and must happen at most a of the time (within 3 MC errors)
    reps, a = 4000, 0.1
    false_pass, _ = simulate(p_true, 0.95, 0.9, 400, 8, reps, seed=1)
    assert false_pass <= a + 3 * math.sqrt(a * (1 - a) / reps)
    # the naive rule (every look at the full confidence) breaks it at the boundary: the check can fail
    if p_true == 0.95:
        naive, _ = simulate(p_true, 0.95, 0.9, 400, 8, reps, seed=1, rule_looks=1)
        assert naive > a + 3 * math.sqrt(a * (1 - a) / reps)


def test_sequential_rule_false_fail_rate_and_power():
    reps, a = 4000, 0.1
    _, false_fail = simulate(0.95, 0.95, 0.9, 400, 8, reps, seed=2)   # at the boundary a FAIL is wrong
    assert false_fail <= a + 3 * math.sqrt(a * (1 - a) / reps)
    good, _ = simulate(0.995, 0.95, 0.9, 400, 8, reps, seed=3)         # with margin it passes, mostly early
    assert good > 0.9
    _, bad = simulate(0.8, 0.95, 0.9, 400, 8, reps, seed=4)
    assert bad > 0.9


def test_sequential_campaign_stops_and_its_summary_is_a_shorter_campaign(model, tmp_path):
    seq = loads_campaign(campaign_text(REQ, "runs = 80\nseed = 3\nrate_hz = 0.1\nsequential = true\nlooks = 4"),
                         "seq.toml", model.manifest)
    folder = start_folder(seq, model, tmp_path / "seq")
    out = run_campaign(seq, model, folder, workers=1)
    # 0.9 at 95 % / 4 looks needs 42 runs with no failure: looks at 20, 40, 60 -> stops at 60
    assert runs_needed(0.9, 1 - 0.05 / 4) == 42
    assert out.decided and out.look == 3 and out.looks == 4 and out.runs_judged == 60 and out.flown_now == 60
    assert out.verdicts[0]["verdict"] == "PASS" and out.missing == list(range(60, 80))
    assert sorted(storage.read_rows(folder)) == list(range(60))
    assert read_summary_verdicts(folder)["verdicts"][0]["verdict"] == "PASS"
    plain = loads_campaign(campaign_text(REQ, "runs = 60\nseed = 3\nrate_hz = 0.1"), "plain.toml", model.manifest)
    other = start_folder(plain, model, tmp_path / "plain")
    run_campaign(plain, model, other, workers=1)
    a, b = pq.read_table(folder / storage.SUMMARY), pq.read_table(other / storage.SUMMARY)
    assert a.column_names == b.column_names
    assert all(a.column(n).equals(b.column(n)) for n in a.column_names)
    text = write_report(folder, out=tmp_path / "rep", figures=False).read_text()
    assert "stopped after 60 of at most 80 runs (look 3 of 4)" in text and "Incomplete campaign" not in text
    # resuming a decided campaign flies nothing more
    again = run_campaign(seq, model, folder, workers=1)
    assert again.flown_now == 0 and sorted(storage.read_rows(folder)) == list(range(60))
