"""The verification layer end to end: every injected defect in a control, adaptation or observer law is
caught by the claims it names; the committed report lists exactly the registered claims; and
``verify.py --check`` fails, readably, when a claim's status changes."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rpo.symbolic import lyapunov
from rpo.symbolic.lyapunov.check import check_claim
from rpo.symbolic.lyapunov.report import compare

ROOT = Path(__file__).resolve().parents[1]
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


@pytest.mark.parametrize("mutation", MUTATIONS, ids=[m.name for m in MUTATIONS])
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


def test_verify_check_fails_readably_when_a_status_changes(tmp_path):
    data = json.loads((ROOT / "docs" / "verification.json").read_text())
    target = next(c for c in data["claims"] if c["controller"] == "c004")
    target["status"] = "fails" if target["status"] != "fails" else "proved"
    doctored = tmp_path / "verification.json"
    doctored.write_text(json.dumps(data))
    p = subprocess.run([sys.executable, str(ROOT / "verify.py"), "--check", "--controller", "c004",
                        "--jobs", "1", "--against", str(doctored)], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 1, p.stdout + p.stderr
    assert f"STATUS CHANGE: {target['id']}" in p.stdout
    assert "Traceback" not in p.stderr
