"""Proofs by composition of certified claims: a claim used as a lemma by another claim's plan.

The papers prove their theorems from their lemmas: 004's Theorem 1 bounds V-dot = V1-dot + V2-dot by the
two bounds of eqs. 27 and 36.  A plan states such a step as a :class:`~.plan.Use` of a
:class:`ClaimLemma`: ``gap_B >= 0`` (one component of claim B's statement), subtracted from the using
claim's gap with weight 1 and the identity mapping (B's own symbols, which the using statement shares).

Soundness rests on three checks, all made by :func:`check_claim_use` whenever the using certificate is
derived or re-checked, from the current sources and never from what the plan says:

1. the lemma's gap is component ``component`` of B's statement as built now (structurally equal);
2. B's certified domain contains each region of the using plan where the use applies: some region C of B's
   plan has every coordinate of C among the using region's coordinates (same symbol, not substituted, bounds
   inside C's), the same domain map for every symbol C substitutes, and C's hypotheses among the using
   region's.  Then every point of the using region is a point of C, where ``gap_B >= 0`` is certified;
3. B has a committed certificate for that statement and plan (statement and region hashes current), and B's
   plan uses no claim itself (one level: no cycle can certify two claims by each other).

Whether B's certificate passes its own independent re-check is decided where all claims are re-checked
together (the report): a certificate that depends on B counts as re-checked only when B's does
(:func:`dependencies`).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..core import Claim
from .lemmas import Lemma
from .plan import Plan, Region, Use, gaps, region_hash, statement_hash
from .recheck import CheckError
from .registry import implementation_tag, plan_for
from .store import read


def _no_proof() -> bool:
    # a claim's "proof" is its own certificate, checked by check_claim_use and the report, never here
    return False


@dataclass(frozen=True)
class ClaimLemma(Lemma):
    """Component ``component`` of claim ``claim_id``'s ``tag`` statement, ``gap >= 0`` on its certified domain."""

    claim_id: str = ""
    tag: str = "paper"
    component: int = 0

    @property
    def key(self) -> str:
        """``<claim id>.<paper|corrected>``: the certificate it rests on."""
        return f"{self.claim_id}.{self.tag}"


def find_claim(claim_id: str) -> Claim:
    from .. import claims

    for cl in claims():
        if cl.id == claim_id:
            return cl
    raise CheckError(f"no claim {claim_id!r}")


def _statement(cl: Claim, tag: str):
    build = cl.corrected if tag == "corrected" else cl.paper
    if build is None:
        raise CheckError(f"claim {cl.id} has no {tag} statement")
    return build()


def claim_lemma(claim_id: str, component: int = 0, tag: str | None = None) -> ClaimLemma:
    """The lemma ``gap >= 0`` of one component of a claim (``tag``: default the implementation's statement)."""
    cl = find_claim(claim_id)
    tag = tag or implementation_tag(cl)
    gap = gaps(_statement(cl, tag))[component]
    return ClaimLemma(f"claim {claim_id} [{tag}, component {component}]", (), gap, (),
                      f"{claim_id}, component {component} of its {tag} statement, as certified",
                      _no_proof, claim_id=claim_id, tag=tag, component=component)


def claim_use(claim_id: str, component: int = 0, *, applies_to: int = 0, tag: str | None = None) -> Use:
    """A use of a certified claim in the plan of another (``applies_to``: the using statement's component)."""
    return Use(claim_lemma(claim_id, component, tag), {}, sp.S.One, applies_to)


def _contains(dep: Region, reg: Region) -> str:
    """'' when every point of ``reg`` is a point of ``dep`` (see the module docstring), else why not."""
    coords = {c.symbol: c for c in reg.coords}
    for c in dep.coords:
        u = coords.get(c.symbol)
        if u is None or c.symbol in reg.subs:
            return f"{c.symbol} is not a coordinate of the using region"
        if not (float(u.lo) >= float(c.lo) and float(u.hi) <= float(c.hi)):
            return f"{c.symbol} in [{u.lo:g}, {u.hi:g}] is not inside [{c.lo:g}, {c.hi:g}]"
    for s, e in dep.subs.items():
        if s not in reg.subs or sp.sympify(reg.subs[s]) != sp.sympify(e):
            return f"the domain map of {s} differs"
    hyps = set(map(sp.sympify, reg.hypotheses))
    for h in dep.hypotheses:
        if sp.sympify(h) not in hyps:
            return f"hypothesis {sp.sstr(h)} >= 0 is not one of the using region's"
    return ""


def check_claim_use(use: Use, plan: Plan) -> None:
    """The checks 1-3 of the module docstring for one use (CheckError when one fails)."""

    lem = use.lemma
    if not isinstance(lem, ClaimLemma):
        raise CheckError(f"{lem.name} is not a claim")
    if use.mapping or sp.sympify(use.weight) != 1:
        raise CheckError(f"{lem.name}: a claim is used as it is stated (identity mapping, weight 1)")
    cl = find_claim(lem.claim_id)
    st = _statement(cl, lem.tag)
    gs = gaps(st)
    if not 0 <= lem.component < len(gs) or gs[lem.component] != lem.gap:
        raise CheckError(f"{lem.name}: not the claim's statement as built from the sources")
    make = plan_for(cl, lem.tag)
    if make is None:
        raise CheckError(f"{lem.name}: the claim has no plan")
    dep_plan = make(st)
    if any(isinstance(u.lemma, ClaimLemma) for u in dep_plan.uses):
        raise CheckError(f"{lem.name}: the claim is itself proved from claims (one level only)")
    for ri, reg in enumerate(plan.regions):
        if use.region not in (None, ri):
            continue
        why = [_contains(c, reg) for c in dep_plan.regions]
        if all(why):
            raise CheckError(f"{lem.name}: its certified domain does not contain region {ri} ({why[0]})")
    data = read(cl.id, lem.tag)
    if data is None:
        raise CheckError(f"{lem.name}: no certificate")
    if (data.get("statement_hash") != statement_hash(st)
            or [r["hash"] for r in data.get("regions", [])] != [region_hash(r) for r in dep_plan.regions]):
        raise CheckError(f"{lem.name}: its certificate is stale")


def dependencies(plan: Plan) -> list[str]:
    """The certificates (``<claim id>.<tag>``) a plan's proof rests on, in order of first use."""
    out: list[str] = []
    for u in plan.uses:
        if isinstance(u.lemma, ClaimLemma) and u.lemma.key not in out:
            out.append(u.lemma.key)
    return out


def merge_regions(*regions: Region, describe: str = "") -> Region:
    """One region whose points are points of each of ``regions`` (the union of their coordinates, maps and
    hypotheses); ValueError where two disagree on a coordinate's bounds or a symbol's map."""
    coords: dict = {}
    subs: dict = {}
    hyps: list = []
    for reg in regions:
        for c in reg.coords:
            old = coords.setdefault(c.symbol, c)
            if (float(old.lo), float(old.hi)) != (float(c.lo), float(c.hi)):
                raise ValueError(f"{c.symbol}: [{old.lo:g}, {old.hi:g}] against [{c.lo:g}, {c.hi:g}]")
        for s, e in reg.subs.items():
            if subs.setdefault(s, e) != e:
                raise ValueError(f"two domain maps of {s}")
        for h in reg.hypotheses:
            if h not in hyps:
                hyps.append(h)
    return Region(tuple(coords.values()), subs, tuple(hyps), describe=describe)
