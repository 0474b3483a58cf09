"""Certificates: derive (search), store (committed data), re-check (independently), per claim statement.

A certificate is one gzipped JSON file per certified statement,
``docs/certificates/<claim id>.<paper|corrected>.json.gz``:

* the claim, which statement (``paper`` or ``corrected``), its relation and the sha256 of its sources
  (``statement_hash``: both sides as built from ``symbolic/``, so any edit of a function the statement
  uses makes the certificate stale);
* the plan's certified domain in words and each region (box, domain map, hypotheses, with its hash);
* per goal: the hash of the goal expression, the reduction step (``none``, ``identity``, ``factor``), the
  branch-and-bound tree (base64 of the preorder bytes: a split coordinate, or a leaf method), the number of
  boxes per method, and the seconds the search took.

:func:`recheck` never repeats the search: it rebuilds the statement and the plan's goals from the current
sources (a changed hash means stale: re-derive), re-verifies every symbolic step (the reduction identity,
the margin's definiteness) with SymPy, and re-evaluates every leaf box in ``mpmath.iv``
(:mod:`.recheck`).  Files are written atomically, with a fixed gzip timestamp (byte-reproducible for the
same tree).
"""

from __future__ import annotations

import base64
import time
from dataclasses import dataclass, field

import sympy as sp

from ..core import Claim, Statement
from . import bnb
from .compose import ClaimLemma, check_claim_use, dependencies
from .library import LIBRARY
from .plan import Plan, expr_hash, gaps, goal_coordinates, goals, region_hash, statement_hash
from .recheck import CheckError, LeafChecker, walk
from .store import STORE, path_for, read, write  # noqa: F401  (re-exported: the certificate's file)

FORMAT = 1


@dataclass
class Certification:
    """What certification found for one statement (the report's record)."""

    status: str                        # "certified", "counterexample", "cannot", "stale"
    domain: str = ""
    covers_search_domain: bool = True
    boxes: int = 0
    methods: dict = field(default_factory=dict)
    goals: int = 0
    seconds: float = 0.0               # the search (derive) time, as recorded
    recheck: str = ""                  # "passed", "failed: ...", "" (not re-checked)
    recheck_seconds: float = 0.0
    reason: str = ""
    counterexample: dict | None = None
    note: str = ""
    depends: list = field(default_factory=list)   # certificates (``<claim id>.<tag>``) the proof uses

    def to_json(self) -> dict:
        d = dict(self.__dict__)
        d["seconds"] = round(d["seconds"], 2)
        d["recheck_seconds"] = round(d["recheck_seconds"], 2)
        return d


def _goal_key(g) -> str:
    return expr_hash(g.expr)


def derive(claim: Claim, tag: str, st: Statement, plan: Plan, log=print) -> tuple[Certification, dict | None]:
    """Run the prover on every goal; (result, certificate data or None)."""
    t0 = time.perf_counter()
    try:
        _check_steps(st, plan, seconds=plan.seconds)
        gl = goals(st, plan)
    except (CheckError, ValueError) as exc:
        return Certification("cannot", plan.domain, plan.covers_search_domain, reason=f"the plan does not check: {exc}",
                             note=plan.note), None
    out_goals, boxes, methods = [], 0, {}
    for g in gl:
        reg = plan.regions[g.region]
        coords = [(c.symbol, c.lo, c.hi) for c in goal_coordinates(reg, g.expr)]
        left = max(1.0, plan.seconds - (time.perf_counter() - t0))
        names = {c[0] for c in coords}
        eqs = [{k: v for k, v in p.items() if k in names} for p in reg.equilibria]
        r = bnb.prove(g.expr, coords, list(reg.hypotheses), eqs, plan.max_boxes, left, strict=g.strict)
        if r.status != "certified":
            cx = None
            if r.counterexample is not None:
                cx = _statement_point(reg, r.counterexample)
            why = r.reason or f"g = {r.value:.4g} {'<=' if g.strict else '<'} 0 at {cx}"
            status = r.status
            if status == "counterexample" and not (g.part == 0 and g.step in ("none", "identity") and not plan.uses):
                # a failing side goal, factor or composed rest does not make the statement false
                status, cx = "cannot", None
                why = f"{g.step} goal fails: {why}"
            return Certification(status, plan.domain, plan.covers_search_domain, boxes + r.boxes, methods,
                                 len(gl), time.perf_counter() - t0,
                                 reason=f"goal {len(out_goals) + 1} of {len(gl)} (region {g.region}, component "
                                        f"{g.component}): {why}", counterexample=cx, note=plan.note), None
        boxes += r.boxes
        for k, v in r.methods.items():
            methods[k] = methods.get(k, 0) + v
        out_goals.append({"region": g.region, "component": g.component, "part": g.part, "step": g.step,
                          "strict": g.strict,
                          "goal_hash": _goal_key(g), "boxes": r.boxes, "methods": r.methods,
                          "seconds": round(r.seconds, 2), "tree": base64.b64encode(r.tree).decode()})
        log(f"    {claim.id} goal {len(out_goals)}/{len(gl)}: {r.boxes} boxes {r.methods} {r.seconds:.1f} s")
    elapsed = time.perf_counter() - t0
    data = {"format": FORMAT, "claim": claim.id, "statement": tag, "relation": st.relation,
            "statement_hash": statement_hash(st), "domain": plan.domain,
            "covers_search_domain": plan.covers_search_domain, "note": plan.note,
            "regions": [{"text": reg.text(), "hash": region_hash(reg)} for reg in plan.regions],
            "goals": out_goals, "boxes": boxes, "methods": methods, "seconds": round(elapsed, 2),
            "derived_with": "rpo.symbolic.lyapunov.certify.bnb (NumPy float64 intervals, outward rounding)"}
    if dependencies(plan):
        data["depends"] = dependencies(plan)
    return Certification("certified", plan.domain, plan.covers_search_domain, boxes, methods, len(gl), elapsed,
                         note=plan.note, depends=dependencies(plan)), data


def _statement_point(reg, point: dict) -> dict:
    """A counterexample in coordinates, mapped to the statement's symbols too."""
    sub = {c.symbol: sp.Float(point[str(c.symbol)], 17) for c in reg.coords if str(c.symbol) in point}
    out = dict(point)
    for s, e in reg.subs.items():
        val = e.xreplace(sub)
        if val.is_number:
            out[str(s)] = float(val)
    return out


def _check_steps(st: Statement, plan: Plan, seconds: float | None = None) -> None:
    """The symbolic steps of the plan, verified: every goal comes from the gap by an exact identity, and a
    '>' statement's margin is positive off the zero set.  ``seconds``: a budget for all of it (CheckError when
    it runs out), so that a plan that does not fit (a mutated statement) is refused quickly."""
    deadline = None if seconds is None else time.perf_counter() + seconds

    def identical(a, b) -> bool:
        if deadline is None:
            return _identical(a, b)
        left = deadline - time.perf_counter()
        if left <= 0:
            raise CheckError(f"the plan's symbolic steps take more than {seconds:g} s")
        return _identical(a, b, min(30.0, left), total=left)

    from ..check import prove_positive_definite

    if st.relation == ">":
        if plan.margin is None or not prove_positive_definite(plan.margin, st.zero_at, st.positive):
            raise CheckError("the margin of a '>' statement is not a positive sum of squares in zero_at")
    checked: set[str] = set()        # each lemma's proof once per plan (a plan may use one lemma many times)
    for u in plan.uses:
        if isinstance(u.lemma, ClaimLemma):
            # a certified claim: its statement, domain and certificate, checked from the current sources
            check_claim_use(u, plan)
            continue
        # only the reviewed library: a lemma's proof is code, and a claim-sized "lemma" whose inequality
        # steps are argued in prose would carry the whole proof unchecked
        if LIBRARY.get(u.lemma.name) is not u.lemma:
            raise CheckError(f"lemma {u.lemma.name} is not in the library of proved lemmas (certify/lemmas.py)")
        if u.lemma.name not in checked and not u.lemma.verify():
            raise CheckError(f"the proof of lemma {u.lemma.name} does not check")
        checked.add(u.lemma.name)
    gl = goals(st, plan)
    by_raw: dict = {}
    for g in gl:
        by_raw.setdefault((g.region, g.component), []).append(g)
    for (_ri, _ci), parts in by_raw.items():
        raw = parts[0].raw
        if parts[0].step == "identity":
            if not identical(raw, parts[0].expr):
                raise CheckError(f"the reduction of goal (region {_ri}, component {_ci}) is not an identity")
        elif parts[0].step == "factor":
            rest = next(p.expr for p in parts if p.part == 0)
            factor = next(p.expr for p in parts if p.part == 1)
            if not identical(raw, factor * rest):
                raise CheckError(f"the factorisation of goal (region {_ri}, component {_ci}) is not exact")
            # factor >= 0 and rest >= 0 give raw >= 0: both are goals of the certificate
        for p in parts:
            if p.part >= 2 and p.expr != p.raw and not identical(p.raw, p.expr):
                raise CheckError(f"the rewriting of a {p.step} goal (region {_ri}, component {_ci}) is not an "
                                 "identity")


def _identical(a: sp.Expr, b: sp.Expr, seconds: float = 30.0, total: float | None = None) -> bool:
    """a == b for all values: the symbolic stage's canonical reduction (``check.prove_zero``), else SymPy's
    ``simplify`` of the difference reaching 0 (roots whose radicands agree only as rational functions),
    within ``seconds``.  ``total``: a limit on the whole test, the canonical reduction included (a derivation
    with a budget; the re-check gives the reduction all the time it needs)."""
    from ..check import _Timeout, prove_zero, time_limit

    try:
        if total is None:
            if prove_zero(a - b, []):
                return True
        else:
            with time_limit(total):
                if prove_zero(a - b, []):
                    return True
    except _Timeout:
        return False
    try:
        with time_limit(seconds if total is None else max(0.001, min(seconds, total))):
            return sp.simplify(sp.sympify(a - b)) == 0
    except _Timeout:
        return False


def recheck(claim: Claim, tag: str, st: Statement, plan: Plan, data: dict) -> Certification:
    """Re-check a stored certificate against the current sources (status "stale" when they changed)."""
    t0 = time.perf_counter()
    base = dict(domain=plan.domain, covers_search_domain=plan.covers_search_domain, note=plan.note,
                depends=dependencies(plan))
    if data.get("format") != FORMAT or data.get("claim") != claim.id or data.get("statement") != tag:
        return Certification("stale", reason="certificate of another claim, statement or format", **base)
    if data["statement_hash"] != statement_hash(st):
        return Certification("stale", reason="the statement's sources changed", **base)
    if [r["hash"] for r in data["regions"]] != [region_hash(r) for r in plan.regions]:
        return Certification("stale", reason="the plan's regions changed", **base)
    gl = goals(st, plan)
    if [g["goal_hash"] for g in data["goals"]] != [_goal_key(g) for g in gl]:
        return Certification("stale", reason="the plan's goals changed", **base)
    boxes, methods = 0, {}
    try:
        _check_steps(st, plan)
        if len(gaps(st)) * len(plan.regions) > len({(g.region, g.component) for g in gl}):
            raise CheckError("a component or region has no goal")
        for g, rec in zip(gl, data["goals"], strict=True):
            reg = plan.regions[g.region]
            if (rec["region"], rec["component"], rec["part"]) != (g.region, g.component, g.part):
                raise CheckError("the goals are out of order")
            cs = goal_coordinates(reg, g.expr)
            eqs = [{k: v for k, v in p.items() if k in {c.symbol for c in cs}} for p in reg.equilibria]
            checker = LeafChecker(g.expr, [c.symbol for c in cs], list(reg.hypotheses), eqs, g.strict)
            root = [(float(c.lo), float(c.hi)) for c in cs]
            tree = base64.b64decode(rec["tree"], validate=True)
            try:
                n = walk(tree, root, checker, bnb.LEAF_NAME)
            except CheckError as exc:
                raise CheckError(f"goal {gl.index(g) + 1} of {len(gl)}: {exc}") from exc
            boxes += n
            for k, v in rec["methods"].items():
                methods[k] = methods.get(k, 0) + v
            if n != rec["boxes"]:
                raise CheckError(f"goal {gl.index(g) + 1}: {n} leaves, the certificate says {rec['boxes']}")
    except (CheckError, ValueError) as exc:
        return Certification("certified", boxes=boxes, methods=methods, goals=len(gl), seconds=data["seconds"],
                             recheck=f"failed: {exc}", recheck_seconds=time.perf_counter() - t0, **base)
    return Certification("certified", boxes=boxes, methods=methods, goals=len(gl), seconds=data["seconds"],
                         recheck="passed", recheck_seconds=time.perf_counter() - t0, **base)
