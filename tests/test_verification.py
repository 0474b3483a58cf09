"""The verification layer end to end: every injected defect in a control, adaptation or observer law is
caught by the claims it names; the committed report lists exactly the registered claims; and
``verify.py --check`` fails, readably, when a claim's status changes."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from rpo.symbolic import lyapunov
from rpo.symbolic.lyapunov.certify import plan_for
from rpo.symbolic.lyapunov.check import check_claim
from rpo.symbolic.lyapunov.report import certify_under_mutation, compare

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))     # verify.py (the CLI) is not part of the package
CLAIMS = {c.id: c for c in lyapunov.claims()}
MUTATIONS = lyapunov.mutations()


def test_claim_ids_are_unique_and_every_controller_has_claims():
    ids = [c.id for c in lyapunov.claims()]
    assert len(ids) == len(set(ids))
    assert {c.controller for c in lyapunov.claims()} == set(lyapunov.controllers())


def test_every_controller_has_mutations_in_control_and_adaptation_or_observer_laws():
    for ctrl in lyapunov.controllers():
        muts = lyapunov.mutations(ctrl)
        assert len(muts) >= 3, ctrl
        assert all(m.affects and set(m.affects) <= set(CLAIMS) for m in muts), ctrl


def _committed() -> dict:
    return {c["id"]: c for c in json.loads((ROOT / "docs" / "verification.json").read_text())["claims"]}


def _representative(muts) -> set[str]:
    """Run by default: the first mutation of each controller and every inequality-only one (the others are
    the same check on more functions: ``-m slow``)."""
    first = {}
    for m in muts:
        first.setdefault(m.module.__name__, m.name)
    return set(first.values()) | {m.name for m in muts if m.inequality_only}


_FAST = _representative(MUTATIONS)


@pytest.mark.parametrize("mutation", [m if m.name in _FAST else pytest.param(m, marks=pytest.mark.slow)
                                      for m in MUTATIONS], ids=[m.name for m in MUTATIONS])
def test_mutation_is_caught(mutation):
    """With the defect patched into the symbolic law, every claim the mutation names fails; without it,
    the same claims hold (the committed report, re-checked by ``verify.py --check`` in CI), so it is the
    mutation that is caught, not a claim that always fails."""
    committed = _committed()
    for cid in mutation.affects:
        rec = committed[cid]
        impl = rec["corrected"] if rec["corrected"] is not None else rec["paper"]
        assert impl["holds"], f"{cid} fails even without the mutation"
    with mutation:
        for cid in mutation.affects:
            r = check_claim(CLAIMS[cid], symbolic=False)
            impl = r.corrected if r.corrected is not None else r.paper
            if impl.holds and plan_for(CLAIMS[cid]) is not None:
                # a defect confined to a small region may evade the search: the prover must refuse the claim
                got = certify_under_mutation(CLAIMS[cid])
                assert got != "certified", f"{mutation.name}: {cid} certified under the mutation (not caught)"
                continue
            assert not impl.holds, f"{mutation.name}: {cid} still holds (mutation not caught)"
    assert getattr(mutation.module, mutation.attr) is mutation._orig


def test_committed_report_lists_exactly_the_registered_claims():
    data = json.loads((ROOT / "docs" / "verification.json").read_text())
    assert [c["id"] for c in data["claims"]] == [c.id for c in lyapunov.claims()]
    assert all(m["caught"] for m in data["mutations"])
    assert all(c["implementation_ok"] for c in data["claims"])


def test_compare_names_the_claim_and_both_statuses():
    fresh = [{"id": "c.x", "equations": "7", "status": "fails", "paper": {
        "holds": False, "proved": False, "lhs_value": 1.0, "rhs_value": 0.0, "max_violation": 1.0,
        "residual": "2*a*b", "counterexample": {"a": 1.0, "b": 0.5}}, "corrected": None},
        {"id": "c.new", "equations": "8", "status": "proved", "paper": None, "corrected": None}]
    msgs = compare(fresh, {"claims": [{"id": "c.x", "status": "proved"}, {"id": "c.gone", "status": "proved"}]})
    text = "\n".join(msgs)
    assert "c.x (eq. 7): status changed proved -> fails" in text
    assert "2*a*b" in text and "a=1" in text
    assert "c.new" in text and "new claim" in text
    assert "c.gone" in text


def test_verify_check_fails_readably_when_a_status_changes(tmp_path, capsys):
    """verify.py --check's verdict on a doctored report: one claim re-checked in-process, the others taken from
    the committed report (re-running them all is CI's own step, verify.py --check)."""
    import verify
    from rpo.symbolic.lyapunov.report import _run_one

    data = json.loads((ROOT / "docs" / "verification.json").read_text())
    records = [c for c in data["claims"] if c["controller"] == "c004"]
    target = next(c for c in records if c["id"] == "c004.theorem.G_invertible")
    fresh = _run_one((target["id"], True, 0, "off"))
    assert fresh["status"] == target["status"] == "proved (symbolic)"
    records = [fresh if r["id"] == target["id"] else r for r in records]
    committed = tmp_path / "verification.json"
    committed.write_text(json.dumps(data))
    assert verify.check_against(records, committed, "c004") == 0
    assert "statuses as committed" in capsys.readouterr().out
    target["status"] = "fails"                                    # doctor the committed status
    committed.write_text(json.dumps(data))
    assert verify.check_against(records, committed, "c004") == 1
    out = capsys.readouterr().out
    assert f"STATUS CHANGE: {target['id']}" in out and "FAILED" in out
    committed.write_text("{not json")
    assert verify.check_against(records, committed, "c004") == 1
    assert "not a report written by verify.py" in capsys.readouterr().out
    assert verify.check_against(records, tmp_path / "missing.json", "c004") == 1


def test_verify_check_fails_when_a_certificate_fails_its_recheck(tmp_path, capsys):
    """A certified claim whose certificate does not pass the independent re-check fails --check, named,
    even when every status is as committed."""
    import verify

    data = json.loads((ROOT / "docs" / "verification.json").read_text())
    records = [c for c in data["claims"] if c.get("certificate")]
    assert records, "the committed report has no certified claim"
    committed = tmp_path / "verification.json"
    committed.write_text(json.dumps(data))
    assert verify.check_against(data["claims"], committed) == 0
    capsys.readouterr()
    bad = json.loads(json.dumps(data["claims"]))
    target = next(c for c in bad if c.get("certificate"))
    target["certificate"]["recheck"] = "failed: goal 1 of 1: leaf 3 (M) on box [(0.0, 1.0)]: mean-value bound"
    assert verify.check_against(bad, committed) == 1
    out = capsys.readouterr().out
    assert f"CERTIFICATE FAILS ITS RE-CHECK: {target['id']}" in out and "FAILED" in out


def test_report_statuses_and_evidence_are_consistent():
    """Proved means symbolic or certified evidence; a sampled claim is never called proved; every certified
    claim's certificate passed its re-check; the totals count the sampled-only claims."""
    from rpo.symbolic.lyapunov.report import STATUSES

    data = json.loads((ROOT / "docs" / "verification.json").read_text())
    for c in data["claims"]:
        assert c["status"] in STATUSES, c["id"]
        if c["status"] == "proved (symbolic)":
            assert c["evidence"] == "symbolic", c["id"]
        if c["status"] == "proved (certified)":
            assert c["evidence"] == "certified", c["id"]
        if c["evidence"] == "certified":
            assert c["certificate"]["status"] == "certified" and c["certificate"]["recheck"] == "passed", c["id"]
            assert (ROOT / "docs" / "certificates" / f"{c['id']}.{c['evidence_statement']}.json.gz").exists(), c["id"]
        if c["evidence"] == "sampled":
            assert not c["status"].startswith("proved"), c["id"]
        assert c["domain"], c["id"]
    assert data["totals"]["sampled_only"] == sum(c["evidence"] == "sampled" for c in data["claims"])


@pytest.mark.slow
@pytest.mark.parametrize("mutation", [m for m in MUTATIONS if m.inequality_only],
                         ids=[m.name for m in MUTATIONS if m.inequality_only])
def test_inequality_only_mutation_leaves_every_identity_true(mutation):
    """Only the inequality claims can catch these: no identity claim about rpo's code fails with them."""
    from rpo.symbolic.lyapunov.report import identities_failing

    assert identities_failing(mutation) == []
    assert all((CLAIMS[cid].corrected or CLAIMS[cid].paper)().relation != "==" for cid in mutation.affects)


def test_there_are_inequality_only_mutations_in_several_controllers():
    ineq = [m for m in MUTATIONS if m.inequality_only]
    assert len(ineq) >= 4
    assert len({m.module.__name__ for m in ineq}) >= 3


def _planned(m) -> bool:
    return any(plan_for(CLAIMS[cid]) is not None for cid in m.affects)


#: the mutations that reach a claim with a proof plan: the inequality-only ones run by default, the others (the
#: same check on more defects, a minute or more each) with ``-m slow``
_PLANNED = [m for m in MUTATIONS if _planned(m)]


@pytest.mark.parametrize("mutation", [m if m.inequality_only else pytest.param(m, marks=pytest.mark.slow)
                                      for m in _PLANNED], ids=[m.name for m in _PLANNED])
def test_mutated_claims_are_never_certified(mutation):
    """With the defect applied, the prover certifies none of the affected claims that have a plan (a
    counterexample or "cannot certify"), whether or not the numeric search also fails them: a certificate of a
    claim the defect makes false would be a hole in the prover, and for a defect confined to a small region the
    refusal is what catches it."""
    with mutation:
        for cid in mutation.affects:
            if plan_for(CLAIMS[cid]) is None:
                continue
            # where the search already fails the mutated claim, a certificate would be a certificate of a
            # statement with a known counterexample: test_certify's false statements cover that case; here the
            # prover's refusal is what catches the defect
            r = check_claim(CLAIMS[cid], symbolic=False)
            if not (r.corrected if r.corrected is not None else r.paper).holds:
                continue
            got = certify_under_mutation(CLAIMS[cid])
            assert got != "certified", f"{mutation.name}: {cid} certified under the mutation"
    assert getattr(mutation.module, mutation.attr) is mutation._orig


def test_controllers_are_discovered_and_one_without_claims_is_fine(tmp_path, monkeypatch):
    """Claims modules are found on disk: a controller without one (baseline) is simply not checked, and a new
    claims package next to a new controller module is picked up without editing any list."""
    from rpo.symbolic.lyapunov import controllers

    assert "baseline" not in controllers() and set(controllers()) >= {"c000", "c001", "c002", "c004"}
    ctrl, here = tmp_path / "controllers", tmp_path / "lyapunov"
    ctrl.mkdir()
    here.mkdir()
    for name in ("baseline", "c000", "c007"):
        (ctrl / f"{name}.py").write_text("")
    (here / "c000").mkdir()
    (here / "c000" / "__init__.py").write_text("")
    (here / "c007.py").write_text("")
    (here / "core.py").write_text("")
    monkeypatch.setattr(lyapunov, "_HERE", here)
    monkeypatch.setattr(lyapunov, "_CONTROLLERS_DIR", ctrl)
    assert controllers() == ("c000", "c007")
    with pytest.raises(ValueError, match="no claims module for controller 'baseline'"):
        lyapunov.claims("baseline")


def test_claim_factory_prefixes_the_controller_of_the_package():
    from rpo.symbolic.lyapunov.core import claim_factory

    claim = claim_factory("rpo.symbolic.lyapunov.c009.attitude")
    cl = claim("attitude.V_definite", "attitude", "abstract", "1", "t", None)
    assert (cl.id, cl.controller) == ("c009.attitude.V_definite", "c009")
    assert all(c.id.startswith(c.controller + ".") for c in lyapunov.claims())
