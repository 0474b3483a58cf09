"""Run the claims (optionally in parallel), compare with the committed report, write Markdown and JSON."""

from __future__ import annotations

import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from . import claims as all_claims
from . import mutations as all_mutations
from . import title
from .check import LOCAL_ONLY, Outcome, check_claim, check_statement
from .core import Mutation

FORMAT = 1


def _claim_record(cl, res) -> dict:
    def out(o: Outcome | None):
        if o is None:
            return None
        d = o.to_json()
        d["seconds"] = round(d["seconds"], 2)
        if d["counterexample"]:
            d["counterexample"] = {k: float(f"{v:.6g}") for k, v in d["counterexample"].items()}
        for k in ("max_violation", "lhs_value", "rhs_value"):
            if d[k] is not None:
                d[k] = float(f"{d[k]:.4g}")
        return d

    return {"id": cl.id, "controller": cl.controller, "part": cl.part, "layer": cl.layer,
            "equations": cl.equations, "title": cl.title, "about": cl.about, "status": res.status,
            "implementation_ok": res.implementation_ok, "correction": cl.correction, "note": cl.note,
            "seconds": round(res.seconds, 2), "paper": out(res.paper), "corrected": out(res.corrected)}


def _run_one(args) -> dict:
    cid, symbolic, seed = args
    cl = next(c for c in all_claims() if c.id == cid)
    return _claim_record(cl, check_claim(cl, seed=seed, symbolic=symbolic))


def run_claims(controller: str | None = None, symbolic: bool = True, jobs: int = 1, seed: int = 0,
               log=print) -> list[dict]:
    """Check every claim (of one controller); records in registry order."""
    ids = [c.id for c in all_claims(controller)]
    work = [(cid, symbolic, seed) for cid in ids]
    out: dict[str, dict] = {}
    if jobs > 1:
        with ProcessPoolExecutor(max_workers=jobs) as ex:
            for rec in ex.map(_run_one, work):
                out[rec["id"]] = rec
                log(f"  {rec['id']:55s} {rec['status']:30s} {rec['seconds']:7.1f} s")
    else:
        for w in work:
            rec = _run_one(w)
            out[rec["id"]] = rec
            log(f"  {rec['id']:55s} {rec['status']:30s} {rec['seconds']:7.1f} s")
    return [out[i] for i in ids]


def run_mutations(controller: str | None = None, log=print) -> list[dict]:
    """Apply each mutation and check the claims it names (numeric search only)."""
    by_id = {c.id: c for c in all_claims()}
    recs = []
    for m in all_mutations(controller):
        t0 = time.perf_counter()
        failed, held = [], []
        with m:
            for cid in m.affects:
                r = check_claim(by_id[cid], symbolic=False)
                impl = r.corrected if r.corrected is not None else r.paper
                (failed if not impl.holds else held).append(cid)
        caught = bool(m.affects) and not held
        recs.append({"name": m.name, "target": f"{m.module.__name__.rsplit('.', 1)[1]}.{m.attr}",
                     "description": m.description, "affects": list(m.affects), "failed": failed,
                     "held": held, "caught": caught, "seconds": round(time.perf_counter() - t0, 2)})
        log(f"  mutation {m.name:60s} {'caught' if caught else 'NOT CAUGHT'}")
    return recs


def identities_failing(m: Mutation) -> list[str]:
    """Ids of the identity claims (implementation statement ``==``) of the mutated module's controller that
    fail with the mutation applied: empty for a mutation that only the inequality claims can catch.  Numeric
    search only, without the global stage (a false identity fails almost everywhere).  Claims about the
    paper's data are skipped: some of them fail without any mutation."""
    ctrl = m.module.__name__.rsplit(".", 1)[1]
    out = []
    with m:
        for cl in all_claims(ctrl):
            if cl.about != "implementation":
                continue
            build = cl.corrected or cl.paper
            st = build()
            if st.relation == "==" and not check_statement(st, symbolic=False, search=LOCAL_ONLY).holds:
                out.append(cl.id)
    return out


def summary(records: list[dict]) -> dict:
    out: dict[str, dict] = {}
    for r in records:
        s = out.setdefault(r["controller"], {"proved": 0, "holds-with-stated-correction": 0,
                                             "not-disproved": 0, "fails": 0, "implementation_failures": 0})
        s[r["status"]] += 1
        s["implementation_failures"] += int(not r["implementation_ok"])
    return out


def to_json(records: list[dict], mutations: list[dict] | None) -> dict:
    return {"format": FORMAT, "generated_by": "python verify.py", "summary": summary(records),
            "claims": records, "mutations": mutations}


def compare(records: list[dict], committed: dict) -> list[str]:
    """Readable reasons the fresh statuses differ from the committed report (empty: none)."""
    old = {c["id"]: c for c in committed.get("claims", [])}
    msgs = []
    for r in records:
        o = old.pop(r["id"], None)
        if o is None:
            msgs.append(f"{r['id']} (eq. {r['equations']}): new claim, not in the committed report "
                        f"(now {r['status']})")
        elif o["status"] != r["status"]:
            why = _why(r)
            msgs.append(f"{r['id']} (eq. {r['equations']}): status changed {o['status']} -> {r['status']}"
                        + (f"\n      {why}" if why else ""))
    msgs += [f"{cid}: claim in the committed report no longer exists" for cid in old]
    return msgs


def _why(r: dict) -> str:
    for tag in ("corrected", "paper"):
        o = r.get(tag)
        if o and not o["holds"]:
            cx = ", ".join(f"{k}={v:.4g}" for k, v in list((o["counterexample"] or {}).items())[:8])
            return (f"{tag} statement fails: lhs={o['lhs_value']}, rhs={o['rhs_value']}, relative violation "
                    f"{o['max_violation']}; residual {o['residual'][:200]}; at {cx}")
    for tag in ("corrected", "paper"):
        o = r.get(tag)
        if o and o["holds"] and not o["proved"]:
            return f"{tag}: {o['symbolic_note']}"
    return ""


# --------------------------------------------------------------------------- Markdown



def _evidence(o: dict | None) -> str:
    if o is None:
        return "-"
    if not o["holds"]:
        return f"counterexample (violation {o['max_violation']:.3g})"
    if o["proved"]:
        return "symbolic"
    return f"no counterexample in {o['trials']} trials"


def _cx(o: dict, n: int = 14) -> str:
    items = list((o.get("counterexample") or {}).items())
    txt = ", ".join(f"{k} = {v:.6g}" for k, v in items[:n])
    return txt + (f", ... ({len(items)} values in the JSON)" if len(items) > n else "")


def _cell(text: str) -> str:
    """Table-cell text: a literal '|' would end the cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown(data: dict) -> str:
    recs, muts = data["claims"], data.get("mutations")
    L = ["# Verification: the papers' Lyapunov arguments, checked on rpo's equations", "",
         "Generated by `python verify.py` (do not edit; `python verify.py --check` in CI fails when a status",
         "changes). Every V-dot is V differentiated along the closed loop built from the functions in",
         "`symbolic/controllers/` that generate the C code; claims are in `symbolic/lyapunov/<controller>/`,",
         "the checker in `symbolic/lyapunov/check.py` (method: `docs/verification_method.md`).", "",
         "Statuses: **proved** (symbolic); **holds-with-stated-correction** (the printed step fails with the",
         "counterexample shown, the corrected step that rpo implements holds); **not-disproved** (numeric",
         "adversarial search only: no counterexample in N trials, not a proof); **fails** (counterexample). A",
         "failing claim marked *paper* is a finding about the paper's own data or assumptions; a failing",
         "*implementation* claim would be a defect in rpo and fails the tests.", "",
         "## Summary", "",
         "| controller | claims | proved | holds with correction | not-disproved | fails (paper findings) "
         "| implementation failures |",
         "| --- | --- | --- | --- | --- | --- | --- |"]
    for ctrl, s in data["summary"].items():
        n = sum(s[k] for k in ("proved", "holds-with-stated-correction", "not-disproved", "fails"))
        L.append(f"| {ctrl} | {n} | {s['proved']} | {s['holds-with-stated-correction']} | {s['not-disproved']} "
                 f"| {s['fails']} | {s['implementation_failures']} |")
    total = sum(r["seconds"] for r in recs)
    L += ["", f"Checking time, sum over claims: {total:.0f} s.", ""]
    if muts is not None:
        caught = sum(m["caught"] for m in muts)
        L += [f"Mutation check: {caught} of {len(muts)} injected defects caught (table at the end).", ""]

    for ctrl in dict.fromkeys(r["controller"] for r in recs):
        L += [f"## {title(ctrl)}", "",
              "| claim | eq. | layer | about | status | evidence | time |",
              "| --- | --- | --- | --- | --- | --- | --- |"]
        rs = [r for r in recs if r["controller"] == ctrl]
        for r in rs:
            impl = r["corrected"] if r["corrected"] is not None else r["paper"]
            L.append(f"| `{r['id']}`: {_cell(r['title'])} | {r['equations']} | {r['layer']} | {r['about']} | "
                     f"**{r['status']}** | {_evidence(impl)} | {r['seconds']:.1f} s |")
        L.append("")
        for r in rs:
            p, c = r["paper"], r["corrected"]
            if not ((p and not p["holds"]) or (c and not c["holds"]) or r["note"]):
                continue
            L.append(f"**`{r['id']}`** (eq. {r['equations']}, {r['status']}). {r['note']}".rstrip())
            L.append("")
            for tag, o in (("printed", p), ("corrected", c)):
                if o and not o["holds"]:
                    L.append(f"- {tag}: fails, lhs = {o['lhs_value']:.6g}, rhs = {o['rhs_value']:.6g} "
                             f"(relative violation {o['max_violation']:.3g}).")
                    if o["residual"]:
                        L.append(f"  Residual lhs - rhs: `{o['residual']}`")
                    L.append(f"  Counterexample: {_cx(o)}.")
            if r["correction"]:
                L.append(f"- correction: {r['correction']}")
                if c:
                    L.append(f"  corrected step: {_evidence(c)}.")
            L.append("")

    errata = [r for r in recs if r["paper"] and not r["paper"]["holds"]]
    L += ["## Paper steps that fail", "",
          "| claim | eq. | what fails | corrected form | rpo |", "| --- | --- | --- | --- | --- |"]
    for r in errata:
        rpo = {"holds-with-stated-correction": "implements the correction",
               "fails": "finding (paper data)" if r["about"] == "paper" else "FAILS"}.get(r["status"], r["status"])
        L.append(f"| `{r['id']}` | {r['equations']} | {_cell(r['title'])} | {_cell(r['correction'] or '-')} | {rpo} |")
    L.append("")
    if muts is not None:
        L += ["## Mutations", "",
              "Each row injects one defect into a function of `symbolic/controllers/` and re-checks the claims it",
              "names (numeric search); every one must fail.", "",
              "| mutation | function | claims that fail | caught |", "| --- | --- | --- | --- |"]
        for m in muts:
            L.append(f"| {_cell(m['name'])} | `{m['target']}` | {', '.join(f'`{x}`' for x in m['failed']) or '-'} | "
                     f"{'yes' if m['caught'] else '**no**: ' + ', '.join(m['held'])} |")
        L.append("")
    return "\n".join(L)


def write(data: dict, md_path: Path, json_path: Path) -> None:
    """Atomic writes: a reader never sees a half-written report."""
    for path, text in ((json_path, json.dumps(data, indent=1, sort_keys=False) + "\n"), (md_path, markdown(data))):
        tmp = path.with_suffix(path.suffix + f".tmp{os.getpid()}")
        tmp.write_text(text)
        os.replace(tmp, path)
