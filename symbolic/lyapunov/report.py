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
from .check import LOCAL_ONLY, ClaimResult, Outcome, check_claim, check_statement
from .core import Claim, Mutation, Statement
from .units import units_text

FORMAT = 2

#: the statuses of the report: a numeric search result is never called proved
STATUSES = ("proved (symbolic)", "proved (certified)", "holds-with-stated-correction", "not-disproved", "fails")
EVIDENCE = ("symbolic", "certified", "sampled", "counterexample")


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


def evidence_tag(res: ClaimResult) -> str | None:
    """The statement whose proof decides the claim's status: the implementation's (``corrected``) where the
    printed step fails or is absent, else the printed one (see ``check.check_claim``)."""
    if res.corrected is not None and (res.paper is None or not res.paper.holds):
        return "corrected"
    return "paper" if res.paper is not None else None


def domain_text(st: Statement, cl: Claim | None = None) -> str:
    """The search domain as the samplers draw it: each variable's symbols and set, in SI units (``cl``'s
    controller's ``UNITS``, see :mod:`.units`; a dimensionless set has none), then the assumptions.  Without
    ``cl``, no units.  A domain symbol without a declared unit raises :class:`~.units.MissingUnit`."""
    parts = []
    for v in st.domain:
        names = ", ".join(str(s) for s in v.symbols)
        text = f"{names}: {v.describe}" if v.describe else names
        parts.append(text + (units_text(cl, v) if cl is not None else ""))
    text = "; ".join(parts) or "every real value of its symbols (nothing drawn: the statement's symbols are free)"
    if st.assumptions:
        text += " (assumptions: " + "; ".join(st.assumptions) + ")"
    return text


def classify(rec: dict) -> dict:
    """Final status and evidence of a record from the checker's status and the certificate (in place)."""
    base, cert = rec["status"], rec.get("certificate")
    tag = rec.get("evidence_statement")
    o = rec.get(tag) if tag else None
    certified = bool(cert and cert["status"] == "certified" and cert["recheck"] == "passed")
    if base == "fails":
        rec["evidence"] = "counterexample"
    elif cert and cert["status"] == "counterexample":
        # the prover found a point the search missed, evaluated rigorously: the statement fails
        rec["status"], rec["evidence"] = "fails", "counterexample"
        if o is not None:
            o["holds"] = False
            o["counterexample"] = cert["counterexample"]
        if rec["about"] == "implementation" and tag == ("corrected" if rec["corrected"] else "paper"):
            rec["implementation_ok"] = False
    elif o is not None and o["proved"]:
        rec["evidence"] = "symbolic"
        if base == "proved":
            rec["status"] = "proved (symbolic)"
    elif certified:
        rec["evidence"] = "certified"
        if base == "not-disproved":
            rec["status"] = "proved (certified)"
    else:
        rec["evidence"] = "sampled"
    if base == "proved" and rec["status"] == "proved":
        rec["status"] = "proved (symbolic)"
    return rec


def _certify(cl: Claim, res: ClaimResult, mode: str, log) -> tuple[str | None, dict | None, str, dict | None]:
    """(evidence statement, its certificate record or None, domain text, the implementation statement's
    certificate record where that statement is not the evidence one) of one checked claim."""
    from .certify import certify, implementation_tag, plan_for

    tag = evidence_tag(res)
    if tag is None:
        return None, None, "", None

    def one(t: str) -> tuple[dict | None, str]:
        st = (cl.corrected if t == "corrected" else cl.paper)()
        o = getattr(res, t)
        if mode == "off" or not o.holds or o.proved or st.relation == "==" or plan_for(cl, t) is None:
            return None, domain_text(st, cl)
        cert = certify(cl, t, st, mode=mode, log=log)
        return (cert.to_json() if cert is not None else None), domain_text(st, cl)

    cert, domain = one(tag)
    impl = implementation_tag(cl)
    other = one(impl)[0] if impl != tag and getattr(res, impl) is not None else None
    return tag, cert, domain, other


def _run_one(args) -> dict:
    cid, symbolic, seed, cert_mode = args
    cl = next(c for c in all_claims() if c.id == cid)
    res = check_claim(cl, seed=seed, symbolic=symbolic)
    rec = _claim_record(cl, res)
    t0 = time.perf_counter()
    tag, cert, domain, impl_cert = _certify(cl, res, cert_mode, log=lambda *a: None)
    rec["evidence_statement"], rec["certificate"], rec["domain"] = tag, cert, domain
    rec["implementation_certificate"] = impl_cert
    if cert is not None:
        rec["domain"] = cert["domain"]
        rec["search_domain"] = domain
    rec["seconds"] = round(rec["seconds"] + time.perf_counter() - t0, 2)
    rec["_search_status"] = rec["status"]
    rec = classify(rec)
    if rec["evidence"] == "sampled":
        from .certify import uncertified_reason

        rec["sampled_reason"] = uncertified_reason(cl)
    return rec


def resolve_dependencies(records: list[dict]) -> list[str]:
    """A certificate proved from certified claims (``certify/compose.py``) counts as re-checked only when each
    claim it rests on has a certificate that passed its own re-check in the same run: otherwise its re-check
    is marked failed and its record classified again (in place).  Returns the ids of the records changed."""
    certs: dict[str, dict] = {}
    for r in records:
        if r.get("certificate") and r.get("evidence_statement"):
            certs[f"{r['id']}.{r['evidence_statement']}"] = r["certificate"]
        if r.get("implementation_certificate"):
            certs[f"{r['id']}.{'corrected' if r['corrected'] else 'paper'}"] = r["implementation_certificate"]
    changed = []
    for r in records:
        for key in ("certificate", "implementation_certificate"):
            cert = r.get(key)
            if not cert or cert.get("recheck") != "passed":
                continue
            for dep in cert.get("depends", []):
                d = certs.get(dep)
                if d is None or d["status"] != "certified" or d["recheck"] != "passed":
                    state = ("is not in this run" if d is None
                             else f"is {d['status']}, re-check {d['recheck'] or 'not run'}")
                    cert["recheck"] = f"failed: it rests on {dep}, whose certificate {state}"
                    if key == "certificate":
                        changed.append(r["id"])
                    break
    for r in records:
        if r["id"] in changed:
            from .certify import uncertified_reason
            from .certify.compose import find_claim

            r["status"] = r["_search_status"]
            classify(r)
            if r["evidence"] == "sampled":
                r["sampled_reason"] = r["certificate"]["recheck"] + ". " + uncertified_reason(find_claim(r["id"]))
    for r in records:
        r.pop("_search_status", None)
    return changed


def run_claims(controller: str | None = None, symbolic: bool = True, jobs: int = 1, seed: int = 0,
               log=print, certify: str = "reuse") -> list[dict]:
    """Check every claim (of one controller); records in registry order.  ``certify``: what to do with the
    certificates of the claims that have a plan (``certify.MODES``: derive, reuse, check, off)."""
    ids = [c.id for c in all_claims(controller)]
    work = [(cid, symbolic, seed, certify) for cid in ids]
    out: dict[str, dict] = {}
    if jobs > 1:
        with ProcessPoolExecutor(max_workers=jobs) as ex:
            for rec in ex.map(_run_one, work):
                out[rec["id"]] = rec
                log(_line(rec))
    else:
        for w in work:
            rec = _run_one(w)
            out[rec["id"]] = rec
            log(_line(rec))
    records = [out[i] for i in ids]
    for cid in resolve_dependencies(records):
        log(f"  {cid}: {out[cid]['certificate']['recheck']}")
    return records


def _line(rec: dict) -> str:
    cert = rec.get("certificate")
    extra = ""
    if cert:
        extra = f"  [certificate: {cert['status']}, {cert['boxes']} boxes"
        extra += f", re-check {cert['recheck']}]" if cert["recheck"] else "]"
    return f"  {rec['id']:55s} {rec['status']:30s} {rec['seconds']:7.1f} s{extra}"


MUTATION_SECONDS = 60.0     # the prover's time per mutated statement


def certify_under_mutation(cl: Claim) -> str:
    """The certification of ``cl``'s evidence statement as the sources are now (under a patched mutation), never
    written: "certified", "counterexample", "cannot" (a plan that no longer applies counts as "cannot"), or ""
    when the claim has no plan."""
    from .certify import certificate, plan_for

    tag = "corrected" if cl.corrected is not None else "paper"
    make = plan_for(cl, tag)
    if make is None:
        return ""
    st = (cl.corrected if tag == "corrected" else cl.paper)()
    if st.relation == "==":
        return ""
    try:
        plan = make(st)
        # a mutated statement must not hold the check up: a short budget, then "cannot certify"
        plan.seconds = min(plan.seconds, MUTATION_SECONDS)
        plan.max_boxes = min(plan.max_boxes, 100_000)
        res, _ = certificate.derive(cl, tag, st, plan, log=lambda *a: None)
    except Exception as exc:  # noqa: BLE001 - a plan written for the true statement may not fit a mutated one
        return f"cannot (the plan does not apply: {type(exc).__name__})"
    return res.status


def run_mutations(controller: str | None = None, log=print, certify: bool = True) -> list[dict]:
    """Apply each mutation and check the claims it names: the numeric search must fail each of them, or,
    for a claim with a proof plan, the prover must refuse it (a counterexample or "cannot certify"): a
    mutation is caught when no affected claim both passes the search and gets a certificate."""
    by_id = {c.id: c for c in all_claims()}
    recs = []
    for m in all_mutations(controller):
        t0 = time.perf_counter()
        failed, held, certified, refused = [], [], [], {}
        with m:
            for cid in m.affects:
                r = check_claim(by_id[cid], symbolic=False)
                impl = r.corrected if r.corrected is not None else r.paper
                if not impl.holds:
                    failed.append(cid)
                    continue
                got = certify_under_mutation(by_id[cid]) if certify else ""
                if got == "certified":
                    certified.append(cid)
                elif got:
                    refused[cid] = got
                else:
                    held.append(cid)
        caught = bool(m.affects) and not held and not certified
        recs.append({"name": m.name, "target": f"{m.module.__name__.rsplit('.', 1)[1]}.{m.attr}",
                     "description": m.description, "affects": list(m.affects), "failed": failed,
                     "refused": refused, "held": held + certified, "certified": certified, "caught": caught,
                     "seconds": round(time.perf_counter() - t0, 2)})
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
    """Per controller: claims per status, per evidence, the sampled-only count and implementation failures."""
    out: dict[str, dict] = {}
    for r in records:
        s = out.setdefault(r["controller"], {**dict.fromkeys(STATUSES, 0), **dict.fromkeys(EVIDENCE, 0),
                                             "sampled_only": 0, "implementation_failures": 0})
        s[r["status"]] += 1
        s[r["evidence"]] += 1
        s["sampled_only"] += int(r["evidence"] == "sampled")
        s["implementation_failures"] += int(not r["implementation_ok"])
    return out


def totals(records: list[dict]) -> dict:
    """Whole-report figures: sampled-only claims, certificates and their re-check."""
    certs = [r["certificate"] for r in records if r.get("certificate")]
    certified = [c for c in certs if c["status"] == "certified"]
    return {"claims": len(records),
            "sampled_only": sum(r["evidence"] == "sampled" for r in records),
            "certificates": len(certified),
            "certificates_rechecked": sum(c["recheck"] == "passed" for c in certified),
            "certificates_failing_recheck": sum(c["recheck"].startswith("failed") for c in certified),
            "certified_on_smaller_domain": sum(not c.get("covers_search_domain", True) for c in certified),
            "certificate_boxes": sum(c["boxes"] for c in certified),
            "derive_seconds": round(sum(c["seconds"] for c in certified), 1),
            "recheck_seconds": round(sum(c["recheck_seconds"] for c in certified), 1)}


def to_json(records: list[dict], mutations: list[dict] | None) -> dict:
    return {"format": FORMAT, "generated_by": "python verify.py", "summary": summary(records),
            "totals": totals(records), "claims": records, "mutations": mutations}


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
    cert = r.get("certificate")
    if cert and cert["status"] == "counterexample":
        return f"the prover found a counterexample: {cert['reason']} at {cert['counterexample']}"
    if cert and cert["recheck"].startswith("failed"):
        return f"certificate re-check {cert['recheck']}"
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



def _evidence(o: dict | None, rec: dict | None = None) -> str:
    if o is None:
        return "-"
    cert = rec.get("certificate") if rec else None
    if rec is not None and rec.get("evidence") == "certified" and cert:
        methods = ", ".join(f"{k} {v}" for k, v in sorted(cert["methods"].items()))
        text = (f"certified: {cert['boxes']} boxes ({methods}), {cert['goals']} goals, "
                f"{cert['seconds']:.1f} s; re-check {cert['recheck']} ({cert['recheck_seconds']:.1f} s)")
        if not cert.get("covers_search_domain", True):
            text += " -- on a smaller domain than the search's; the rest is not-disproved (see the domain)"
        return text
    if not o["holds"]:
        return f"counterexample (violation {o['max_violation']:.3g})"
    if o["proved"]:
        return "symbolic"
    text = f"sampled: no counterexample in {o['trials']} trials"
    if cert:
        text += f"; certificate: {cert['status']} ({cert['reason'] or cert['recheck']})"
    impl = rec.get("implementation_certificate") if rec else None
    if impl:
        text += (f"; the implementation's statement: {impl['status']} ({impl['boxes']} boxes, re-check "
                 f"{impl['recheck'] or '-'})")
    return text


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
         "Statuses: **proved (symbolic)** (a symbolic proof: identities by Groebner reduction, sign facts by",
         "SymPy); **proved (certified)** (a certificate of rigorous interval arithmetic over the stated domain,",
         "re-checked independently; `symbolic/lyapunov/certify/`); **holds-with-stated-correction** (the printed",
         "step fails with the counterexample shown, the corrected step that rpo implements holds; the evidence",
         "column says by what); **not-disproved** (numeric adversarial search only: no counterexample in N",
         "trials, not a proof); **fails** (counterexample). A failing claim marked *paper* is a finding about",
         "the paper's own data or assumptions; a failing *implementation* claim would be a defect in rpo and",
         "fails the tests. Evidence *sampled* means the numeric search alone: such a claim is not proved.", "",
         "## Summary", "",
         "| controller | claims | proved (symbolic) | proved (certified) | holds with correction "
         "| not-disproved | fails (paper findings) | sampled only | implementation failures |",
         "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for ctrl, s in data["summary"].items():
        n = sum(s[k] for k in STATUSES)
        L.append(f"| {ctrl} | {n} | {s['proved (symbolic)']} | {s['proved (certified)']} "
                 f"| {s['holds-with-stated-correction']} | {s['not-disproved']} | {s['fails']} | {s['sampled_only']} "
                 f"| {s['implementation_failures']} |")
    t = data.get("totals")
    if t:
        L += ["", f"Claims whose only evidence is the numeric search (*sampled only*): **{t['sampled_only']}** of "
              f"{t['claims']}. Certificates: {t['certificates']} ({t['certificate_boxes']} boxes, derived in "
              f"{t['derive_seconds']:.0f} s), re-checked independently: {t['certificates_rechecked']} "
              f"({t['recheck_seconds']:.0f} s), failing the re-check: {t['certificates_failing_recheck']}."]
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
            ev = r.get(r.get("evidence_statement") or "") or (r["corrected"] if r["corrected"] is not None
                                                              else r["paper"])
            L.append(f"| `{r['id']}`: {_cell(r['title'])} | {r['equations']} | {r['layer']} | {r['about']} | "
                     f"**{r['status']}** | {_cell(_evidence(ev, r))} | {r['seconds']:.1f} s |")
        L.append("")
        sampled = [r for r in rs if r["evidence"] == "sampled"]
        if sampled:
            L += ["Claims whose only evidence is the numeric search, and why no certificate:", ""]
            for r in sampled:
                L.append(f"- `{r['id']}`: {_cell(r.get('sampled_reason') or '(no written reason)')}")
            L.append("")
        L += ["Domains (the certified domain where a certificate exists, else the search domain; a search domain's "
              "sets are in SI units, a set without a unit is dimensionless):", ""]
        for r in rs:
            cert = r.get("certificate")
            dom = r.get("domain") or "-"
            if cert and not cert.get("covers_search_domain", True):
                dom += f" (smaller than the search domain: {cert.get('note', '')})"
            L.append(f"- `{r['id']}`: {_cell(dom)}")
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
              "names: each must fail the numeric search, or, where the claim has a proof plan, the prover must",
              "refuse it (a counterexample or 'cannot certify'); a certificate for a mutated claim is a miss.", "",
              "| mutation | function | claims that fail | refused by the prover | caught |",
              "| --- | --- | --- | --- | --- |"]
        for m in muts:
            refused = ", ".join(f"`{k}` ({v})" for k, v in (m.get("refused") or {}).items()) or "-"
            L.append(f"| {_cell(m['name'])} | `{m['target']}` | {', '.join(f'`{x}`' for x in m['failed']) or '-'} | "
                     f"{_cell(refused)} | {'yes' if m['caught'] else '**no**: ' + ', '.join(m['held'])} |")
        L.append("")
    return "\n".join(L)


def write(data: dict, md_path: Path, json_path: Path) -> None:
    """Atomic writes: a reader never sees a half-written report."""
    for path, text in ((json_path, json.dumps(data, indent=1, sort_keys=False) + "\n"), (md_path, markdown(data))):
        tmp = path.with_suffix(path.suffix + f".tmp{os.getpid()}")
        tmp.write_text(text)
        os.replace(tmp, path)
