#!/usr/bin/env python3
"""Check the controllers' Lyapunov claims on the SymPy model in ``symbolic/`` and write the report.

    python verify.py                     # check every claim and mutation, write docs/verification.{md,json};
                                         # certificates re-checked, derived where missing or stale
    python verify.py --rederive          # the same, every certificate derived from scratch
    python verify.py --check             # check every claim, re-check every certificate (re-deriving only
                                         # those whose sources changed); exit 1 if a status differs from the
                                         # committed docs/verification.json, a certificate fails its
                                         # re-check, or a claim about rpo's code fails
    python verify.py --controller c004   # check one controller's claims and print them (writes nothing)

Claims live in ``symbolic/lyapunov/<controller>/``, discovered (a controller without one is not checked);
the method is in ``docs/verification_method.md``.
Like build.py, this uses *this checkout's* symbolic/ (``pip install -e .`` here; else one line and exit 2).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

from build import require_checkout

ROOT = Path(__file__).resolve().parent
MD, JSON = ROOT / "docs" / "verification.md", ROOT / "docs" / "verification.json"


def main(argv: list[str] | None = None) -> int:
    require_checkout("verify.py")
    from rpo.symbolic.lyapunov import controllers

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true",
                    help="compare statuses with docs/verification.json; exit 1 on any change")
    ap.add_argument("--against", type=Path, default=JSON,
                    help="the report --check compares with (default: %(default)s)")
    ap.add_argument("--controller", choices=controllers(),
                    help="only this controller's claims (prints; writes nothing)")
    ap.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1),
                    help="claims checked in parallel (default: min(2, cores))")
    ap.add_argument("--no-mutations", action="store_true", help="skip the mutation check when writing")
    ap.add_argument("--rederive", action="store_true",
                    help="derive every certificate from scratch (default: re-check the committed ones)")
    args = ap.parse_args(argv)
    if args.jobs < 1:
        print(f"verify.py: --jobs must be >= 1 (got {args.jobs})", file=sys.stderr)
        return 2

    from rpo.symbolic.lyapunov import report

    t0 = time.perf_counter()
    print(f"checking claims ({args.jobs} process{'es' if args.jobs > 1 else ''}) ...")
    mode = "check" if args.check else ("derive" if args.rederive else "reuse")
    if args.check and args.rederive:
        print("verify.py: --check re-checks the committed certificates; --rederive is for writing", file=sys.stderr)
        return 2
    records = report.run_claims(args.controller, jobs=args.jobs, certify=mode)
    elapsed = time.perf_counter() - t0
    bad = [r for r in records if not r["implementation_ok"]]
    for r in bad:
        print(f"IMPLEMENTATION CLAIM FAILS: {r['id']} (eq. {r['equations']}): {report._why(r)}")
    t = report.totals(records)
    print(f"{t['claims']} claims in {elapsed:.0f} s: {t['sampled_only']} sampled only; {t['certificates']} "
          f"certificates ({t['certificate_boxes']} boxes), {t['certificates_rechecked']} re-checked "
          f"({t['recheck_seconds']:.0f} s), {t['certificates_failing_recheck']} failing the re-check")

    if args.check:
        return check_against(records, args.against, args.controller, elapsed)
    if args.controller:
        print(f"{len(records)} claims in {elapsed:.0f} s (nothing written: --controller)")
        return 1 if bad else 0

    muts = None
    if not args.no_mutations:
        print("checking mutations ...")
        muts = report.run_mutations()
    data = report.to_json(records, muts)
    report.write(data, MD, JSON)
    missed = [m for m in (muts or []) if not m["caught"]]
    print(f"wrote {MD.relative_to(ROOT)} and {JSON.relative_to(ROOT)}: {len(records)} claims "
          f"({elapsed:.0f} s), {len(muts or [])} mutations, {len(missed)} not caught")
    return 1 if (bad or missed) else 0


def check_against(records: list[dict], against: Path, controller: str | None = None,
                  elapsed: float | None = None) -> int:
    """The --check verdict: 0 if every status is as committed in ``against`` and no claim about rpo's code
    fails; 1 otherwise, naming each changed claim (separate from running the claims, so it is testable on a
    doctored report without re-checking anything)."""
    from rpo.symbolic.lyapunov import report

    bad = [r for r in records if not r["implementation_ok"]]
    failing = [r for r in records if (r.get("certificate") or {}).get("recheck", "").startswith("failed")]
    for r in failing:
        print(f"CERTIFICATE FAILS ITS RE-CHECK: {r['id']} (eq. {r['equations']}): {r['certificate']['recheck']}")
    if not against.exists():
        print(f"verify.py --check: {against} is missing; run `python verify.py` and commit it")
        return 1
    try:
        committed = json.loads(against.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        print(f"verify.py --check: {against} is not a report written by verify.py ({exc})")
        return 1
    if controller:
        committed = {"claims": [c for c in committed["claims"] if c["controller"] == controller]}
    changes = report.compare(records, committed)
    for msg in changes:
        print(f"STATUS CHANGE: {msg}")
    if changes or bad or failing:
        print(f"verify.py --check: FAILED ({len(changes)} status changes, {len(bad)} implementation claims "
              f"failing, {len(failing)} certificates failing their re-check). If the change is intended, run "
              f"`python verify.py` and commit docs/verification.* and docs/certificates/")
        return 1
    took = f" ({elapsed:.0f} s)" if elapsed is not None else ""
    print(f"verify.py --check: {len(records)} claims, statuses as committed{took}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
