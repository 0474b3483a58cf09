"""Proof plans: the certified domain of a statement and the goals the box prover must close.

A statement ``lhs <= rhs`` (or ``>=``, ``>``) holds on a domain when its *gap* (``rhs - lhs``, or
``lhs - rhs``) is >= 0 there.  A :class:`Plan` states that domain physically as one or more
:class:`Region`\\ s: a box of coordinates (each with bounds and a unit), the statement's other symbols as
expressions of the coordinates (the domain map: ``s = u d`` puts a boundary layer's edge on a box face; a
unit quaternion is a point of a chart), and hypotheses ``h >= 0`` that cut the box (``D**2 - |d|**2``).
For each region and each component the goal is the gap with the domain map substituted, optionally
rewritten by the plan's ``reduce`` step (expanded, a positive factor cleared, ...).  Every such step is
re-verified symbolically when the certificate is checked: ``reduce`` must return an expression identical to
its input (residual 0 after canonicalisation), or a ``(factor, rest)`` pair whose product is the input,
where the factor must itself be certified positive.

The plans live beside the claims (``symbolic/lyapunov/<controller>/plans.py``, a ``PLANS`` dict from
claim id to a function of the statement returning a :class:`Plan`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import dataclass, field

import sympy as sp

from ..core import Statement
from .lemmas import Lemma


@dataclass(frozen=True)
class Coordinate:
    """One box coordinate: ``lo <= symbol <= hi`` (floats, exact as written), in ``unit``."""

    symbol: sp.Symbol
    lo: float
    hi: float
    unit: str = ""

    def __post_init__(self):
        if not (float(self.lo) <= float(self.hi)):
            raise ValueError(f"coordinate {self.symbol}: lo {self.lo} > hi {self.hi}")

    def assumption_error(self) -> str:
        """'' when the symbol's SymPy assumptions hold on the whole interval (SymPy simplifies with them:
        ``sqrt(x**2) = x`` for a positive x), else what is violated."""
        s, lo, hi = self.symbol, float(self.lo), float(self.hi)
        checks = [(s.is_positive, lo > 0, "positive"), (s.is_nonnegative, lo >= 0, "nonnegative"),
                  (s.is_negative, hi < 0, "negative"), (s.is_nonpositive, hi <= 0, "nonpositive"),
                  (s.is_nonzero, lo > 0 or hi < 0, "nonzero")]
        for declared, holds, name in checks:
            if declared and not holds:
                return f"coordinate {s} is declared {name} but its interval is [{lo!r}, {hi!r}]"
        if s.is_integer or s.is_real is False:
            return f"coordinate {s} must be a real symbol without integer assumptions"
        return ""

    def describe(self) -> str:
        u = f" {self.unit}" if self.unit else ""
        return f"{self.symbol} in [{self.lo:g}, {self.hi:g}]{u}"


@dataclass(frozen=True)
class Region:
    """A piece of the certified domain (see the module docstring)."""

    coords: tuple[Coordinate, ...]
    subs: dict = field(default_factory=dict)          # statement symbol -> expression of the coordinates
    hypotheses: tuple[sp.Expr, ...] = ()              # each >= 0 on the domain
    describe: str = ""
    equilibria: tuple[dict, ...] = ()                 # coordinate points (exact rationals) where gap = 0

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(c.symbol for c in self.coords)

    def text(self) -> str:
        parts = [c.describe() for c in self.coords]
        parts += [f"{s} = {sp.sstr(e)}" for s, e in self.subs.items()]
        parts += [f"{sp.sstr(h)} >= 0" for h in self.hypotheses]
        return (self.describe + ": " if self.describe else "") + "; ".join(parts)


Reduce = Callable[[sp.Expr], "sp.Expr | tuple[sp.Expr, sp.Expr]"]


@dataclass(frozen=True)
class Use:
    """One instance of a proved lemma in a proof by composition: ``weight * lemma.gap(mapping) >= 0``.

    The goal becomes ``gap - sum_k weight_k * lemma_k.gap(mapping_k)``, and each use adds its side goals:
    ``weight >= 0`` and every premise of the lemma at the mapped point (``mapping`` gives the lemma's
    symbols as expressions of the statement's symbols; the region's domain map is applied after it).
    ``component``: the statement's component it applies to."""

    lemma: Lemma
    mapping: dict
    weight: sp.Expr = sp.S.One
    component: int = 0
    region: int | None = None      # the region it applies to (None: every region)

    def applies(self, region: int, component: int) -> bool:
        return self.component == component and self.region in (None, region)

    def mapped(self, expr: sp.Expr) -> sp.Expr:
        return sp.sympify(expr).xreplace({k: sp.sympify(v) for k, v in self.mapping.items()})


@dataclass
class Plan:
    """How to certify one statement: regions, an optional rewriting step, the box budget."""

    regions: list[Region]
    domain: str                                   # the certified domain in words, with units (the report)
    reduce: Reduce | None = None                  # gap -> equal expression, or (positive factor, rest)
    margin: sp.Expr | None = None                 # '>' statements: gap - margin >= 0, margin > 0 off zero_at
    max_boxes: int = 400_000
    seconds: float = 600.0
    note: str = ""
    covers_search_domain: bool = True             # False: certified on a smaller domain (says ``note``)
    uses: tuple[Use, ...] = ()                    # proved lemmas the proof composes (see :class:`Use`)
    reduce_side: Callable[[sp.Expr], sp.Expr] | None = None   # side goals -> equal expressions (checked)


@dataclass
class Goal:
    """``expr >= 0`` over ``region`` (component ``component`` of the statement; ``part`` 0 the rest, 1 the
    positive factor of a factored gap, 2... the side goals of the lemmas used: weights and premises)."""

    region: int
    component: int
    part: int
    expr: sp.Expr
    raw: sp.Expr                  # the gap with the domain map, before ``reduce``
    step: str                     # "none", "identity", "factor"; side goals: "weight", "premise",
                                  # "assumption" (a substituted symbol's sign assumption)
    strict: bool = False          # expr > 0 (a strict premise of a lemma)


def goal_coordinates(reg: Region, expr: sp.Expr) -> list[Coordinate]:
    """The region's coordinates that the goal or a hypothesis reads (the others would only be split for
    nothing: the goal is constant along them)."""
    used = set(expr.free_symbols).union(*[set(h.free_symbols) for h in reg.hypotheses])
    return [c for c in reg.coords if c.symbol in used]


def gaps(st: Statement) -> list[sp.Expr]:
    """The statement's gap per component: >= 0 exactly where it holds."""
    lhs = list(st.lhs) if isinstance(st.lhs, sp.MatrixBase) else [st.lhs]
    rhs = list(st.rhs) if isinstance(st.rhs, sp.MatrixBase) else [st.rhs]
    if len(rhs) == 1 and len(lhs) > 1:
        rhs = rhs * len(lhs)
    if st.relation == "<=":
        return [sp.sympify(b - a) for a, b in zip(lhs, rhs, strict=True)]
    if st.relation in (">=", ">"):
        return [sp.sympify(a - b) for a, b in zip(lhs, rhs, strict=True)]
    raise ValueError(f"relation {st.relation!r} is not an inequality")


def composed(st: Statement, plan: Plan, region: Region | int, component: int, gap: sp.Expr) -> sp.Expr:
    """The gap of one component over one region (the region or its index), less the lemmas used (before
    ``reduce``)."""
    ri = region if isinstance(region, int) else next(i for i, r in enumerate(plan.regions) if r is region)
    reg = plan.regions[ri]
    g = gap - plan.margin if st.relation == ">" else gap
    for u in plan.uses:
        if u.applies(ri, component):
            g = g - u.weight * u.mapped(u.lemma.gap)
    return g.xreplace(reg.subs) if reg.subs else g


def goals(st: Statement, plan: Plan) -> list[Goal]:
    """Every goal of the plan, in a fixed order (region, component, part).  ValueError when a coordinate's
    SymPy assumptions do not hold on its interval."""
    if st.relation == ">" and plan.margin is None:
        raise ValueError("a '>' statement needs the plan's margin")
    for reg in plan.regions:
        for c in reg.coords:
            err = c.assumption_error()
            if err:
                raise ValueError(err)
    out = []
    for ri, reg in enumerate(plan.regions):
        for ci, g in enumerate(gaps(st)):
            raw = composed(st, plan, ri, ci, g)
            missing = raw.free_symbols - set(reg.symbols)
            if missing:
                raise ValueError(f"region {ri}: the domain map leaves {sorted(map(str, missing))} free")
            if plan.reduce is None:
                out.append(Goal(ri, ci, 0, raw, raw, "none"))
            else:
                red = plan.reduce(raw)
                if isinstance(red, tuple):
                    factor, rest = red
                    out.append(Goal(ri, ci, 0, sp.sympify(rest), raw, "factor"))
                    out.append(Goal(ri, ci, 1, sp.sympify(factor), raw, "factor"))
                else:
                    out.append(Goal(ri, ci, 0, sp.sympify(red), raw, "identity"))
            part = 2
            # a substituted symbol's SymPy assumptions (the statement was simplified with them) must hold
            # for its expression on the domain: side goals
            for sym, e in reg.subs.items():
                for declared, strict, sign in ((sym.is_positive, True, 1), (sym.is_nonnegative, False, 1),
                                               (sym.is_negative, True, -1), (sym.is_nonpositive, False, -1)):
                    if declared:
                        side_e = sp.sympify(sign * e)
                        if not (side_e.is_number and (side_e > 0 or (side_e >= 0 and not strict))):
                            out.append(Goal(ri, ci, part, _side(plan, side_e), side_e, "assumption", strict))
                            part += 1
                        break
            for u in plan.uses:
                if not u.applies(ri, ci):
                    continue
                side = [(u.weight, "weight", False)] + [
                    (u.mapped(h), "premise", u.lemma.strict_premise(k)) for k, h in enumerate(u.lemma.premises)]
                for e, kind, strict in side:
                    e = sp.sympify(e).xreplace(reg.subs) if reg.subs else sp.sympify(e)
                    if e.is_number and (e > 0 or (e >= 0 and not strict)):
                        continue          # a constant of the right sign needs no boxes
                    out.append(Goal(ri, ci, part, _side(plan, e), e, kind, strict))
                    part += 1
    return out


def _side(plan: Plan, e: sp.Expr) -> sp.Expr:
    """A side goal as the plan rewrites it (``reduce_side``; the identity is re-verified)."""
    return sp.sympify(plan.reduce_side(e)) if plan.reduce_side is not None else e


def expr_hash(*exprs: sp.Basic | str) -> str:
    """sha256 of the expressions' ``srepr`` (SymPy's canonical argument order makes it stable)."""
    h = hashlib.sha256()
    for e in exprs:
        h.update((e if isinstance(e, str) else sp.srepr(e)).encode())
        h.update(b"\0")
    return h.hexdigest()


def statement_hash(st: Statement) -> str:
    """The hash of a statement's sources: both sides and the relation, as built from ``symbolic/``."""
    return expr_hash(st.relation, sp.sympify(st.lhs), sp.sympify(st.rhs))


def region_hash(reg: Region) -> str:
    return expr_hash(*[f"{c.symbol.name}:{c.lo!r}:{c.hi!r}" for c in reg.coords],
                     *[f"{k}" for k in reg.subs], *list(reg.subs.values()), *reg.hypotheses,
                     *[sp.Tuple(*sorted(p.items(), key=lambda kv: kv[0].name)) for p in reg.equilibria])


