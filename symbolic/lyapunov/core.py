"""Claims, statements, search domains and mutations: the data the Lyapunov checker works on.

A *claim* is one step of a paper's stability argument (a candidate V is positive definite; V-dot along
the closed loop equals a stated expression; that expression is <= 0 under stated assumptions; the
spacecraft equations have the abstract form the proof assumes).  Each claim holds one or two
*statements*:

* ``paper``: the step as printed (hand-typed where it differs from the code: a printed sign, a printed
  bound), and
* ``corrected``: the step as rpo implements it, built from the very functions in
  ``symbolic/controllers/`` that generate the C code.

A statement is ``lhs <relation> rhs`` with SymPy expressions, the equality constraints its symbols obey
(unit quaternion, ...), and a search *domain* (how to draw its symbols inside the stated assumptions)
for the numeric adversarial search.  Statements are built lazily (``build()`` is called at check time)
so a mutation patched into a controller module is seen by the next check.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import ModuleType
from typing import Literal

import numpy as np
import sympy as sp

from .domains import Var

Relation = Literal["==", "<=", ">=", ">"]
Status = Literal["proved", "holds-with-stated-correction", "not-disproved", "fails"]
STATUSES: tuple[str, ...] = ("proved", "holds-with-stated-correction", "not-disproved", "fails")


# --------------------------------------------------------------------------- statements and claims

@dataclass
class Statement:
    """``lhs <relation> rhs`` over the domain.  ``">"`` means positive for every point of the domain
    except where the ``zero_at`` symbols all vanish (definiteness)."""

    lhs: sp.Expr | sp.MatrixBase
    relation: Relation
    rhs: sp.Expr | sp.MatrixBase
    domain: list[Var]
    constraints: list[sp.Expr] = field(default_factory=list)   # polynomial equalities, each == 0
    assumptions: list[str] = field(default_factory=list)        # readable, for the report
    positive: Sequence[sp.Symbol] = ()   # symbols the symbolic proof may take as > 0 (gains, masses)
    substitutions: dict = field(default_factory=dict)  # assumption as equality, e.g. {D: dbar + delta}
    zero_at: Sequence[sp.Symbol] = ()    # ">" (definiteness): the state coordinates; lhs - rhs = 0 only there
    # "==": inequalities (SymPy relationals, e.g. Abs(s) <= d) that every point of the domain satisfies (its draw
    # must enforce them); the symbolic case split drops a case in which one of them is false
    hypotheses: list = field(default_factory=list)
    symbolic: bool = True                # try a symbolic proof (False: numeric only, too large)
    trials: int = 2000                   # random points before local optimisation
    residual_seconds: float = 10.0       # time allowed to simplify a counterexample's residual for the report

    def free_symbols(self) -> set[sp.Symbol]:
        out = set()
        for e in (self.lhs, self.rhs):
            out |= getattr(e, "free_symbols", set())
        return out


@dataclass
class Claim:
    """One step of a paper's Lyapunov argument.

    ``about`` says what a failure means:

    * ``"implementation"``: the statement that holds for rpo's code (``corrected`` if given, else
      ``paper``) must not fail -- a failure is a test failure;
    * ``"paper"``: a statement about the paper's own data or assumptions (its gains, its disturbance
      bound); a failure is a finding, reported, not a test failure.
    """

    id: str
    controller: str
    part: str                       # "attitude", "translation x", "position", ...
    layer: Literal["abstract", "spacecraft"]
    equations: str                  # "89, 96-101"
    title: str
    paper: Callable[[], Statement] | None
    corrected: Callable[[], Statement] | None = None
    correction: str = ""            # the corrected form, in words/formula, for the errata list
    about: Literal["implementation", "paper"] = "implementation"
    note: str = ""


def claim_factory(module_name: str) -> Callable[..., Claim]:
    """The one way to build a claim: ``claim = claim_factory(__name__)`` in a claims module of
    ``symbolic/lyapunov/<controller>/``, then ``claim("attitude.V_definite", part, layer, equations, title,
    paper, corrected, **kw)``.  The controller is the package's name and prefixes the id, so a copied
    claims package only needs renaming."""
    parts = module_name.split(".")
    controller = parts[parts.index("lyapunov") + 1] if "lyapunov" in parts[:-1] else parts[-1]

    def claim(name: str, part: str, layer: Literal["abstract", "spacecraft"], equations: str, title: str,
              paper: Callable[[], Statement] | None, corrected: Callable[[], Statement] | None = None,
              **kw) -> Claim:
        return Claim(f"{controller}.{name}", controller, part, layer, equations, title, paper, corrected, **kw)

    claim.controller = controller
    return claim


def prune(domain: Sequence[Var], *exprs) -> list[Var]:
    """The variables of ``domain`` that ``exprs`` need: those drawing a symbol of the expressions, and,
    transitively, those whose symbols a kept variable's draw reads (declared in ``Var.needs``, or found by a
    trial draw, where a missing dependency raises KeyError).  A variable whose symbols are all drawn by an
    earlier one is a duplicate and dropped.  Unused variables would only add search dimensions."""
    seen: set = set()
    flat = []
    for v in domain:
        if set(v.symbols) <= seen:
            continue
        seen |= set(v.symbols)
        flat.append(v)
    used: set = set()
    for x in exprs:
        used |= getattr(x, "free_symbols", set())
    keep = set()
    for v in reversed(flat):
        if set(v.symbols) & used:
            keep.add(id(v))
            used |= v.needs
    owner = {s: v for v in flat for s in v.symbols}
    while True:
        ordered = [v for v in flat if id(v) in keep]
        env, z = {}, np.zeros((1, sum(v.dim for v in ordered)))
        try:
            k = 0
            for v in ordered:
                cols = v.draw(z[:, k:k + v.dim], env)
                k += v.dim
                env.update({s: cols[:, j] for j, s in enumerate(v.symbols)})
            return ordered
        except KeyError as exc:
            if exc.args[0] not in owner or id(owner[exc.args[0]]) in keep:
                raise
            keep.add(id(owner[exc.args[0]]))


def statement(lhs, relation: Relation, rhs, domain: Sequence[Var], **kw) -> Statement:
    """A :class:`Statement` over the part of ``domain`` it uses (:func:`prune`)."""
    return Statement(lhs, relation, rhs, prune(domain, lhs, rhs), **kw)


@dataclass
class Mutation:
    """A defect injected into one function of a symbolic module; ``affects`` must all then fail.

    ``inequality_only``: the defect leaves every identity claim of the controller true (they use opaque
    symbols for the function, or both sides absorb it), so only the inequality claims in ``affects`` can
    catch it -- the mutations that test the adversarial search rather than the algebra."""

    name: str
    module: ModuleType
    attr: str
    transform: Callable[[Callable], Callable]
    affects: tuple[str, ...]
    description: str = ""
    inequality_only: bool = False

    def __enter__(self):
        self._orig = getattr(self.module, self.attr)
        setattr(self.module, self.attr, self.transform(self._orig))
        return self

    def __exit__(self, *exc):
        setattr(self.module, self.attr, self._orig)
        return False


# --------------------------------------------------------------------------- mutation transforms

def _map(out, f):
    if isinstance(out, tuple):
        return tuple(_map(o, f) for o in out)
    if isinstance(out, list):
        return [_map(o, f) for o in out]
    if isinstance(out, sp.MatrixBase):
        return out.applyfunc(f)
    return f(sp.sympify(out))


def negate_output(index: int | None = None) -> Callable[[Callable], Callable]:
    """Flip the sign of the function's result (or of element ``index`` of a returned tuple)."""
    def transform(fn):
        def mutated(*a, **kw):
            out = fn(*a, **kw)
            if index is None:
                return _map(out, lambda e: -e)
            out = list(out)
            out[index] = _map(out[index], lambda e: -e)
            return tuple(out)
        return mutated
    return transform


def scale_argument(name: str, factor: float = -1) -> Callable[[Callable], Callable]:
    """Call the function with argument ``name`` (a gain) multiplied by ``factor``."""
    import inspect

    def transform(fn):
        sig = inspect.signature(fn)

        def mutated(*a, **kw):
            b = sig.bind(*a, **kw)
            b.arguments[name] = b.arguments[name] * factor
            return fn(*b.args, **b.kwargs)
        return mutated
    return transform


def drop_terms(contains: Callable[[], sp.Basic | Sequence[sp.Basic]] | sp.Basic,
               index: int | None = None) -> Callable[[Callable], Callable]:
    """Drop every additive term of the (expanded) result that contains the given symbol(s).

    ``contains`` may be a callable returning the symbols, evaluated at call time; ``index`` picks one
    element of a returned tuple.
    """
    def strip(e):
        atoms = contains() if callable(contains) else contains
        atoms = atoms if isinstance(atoms, (list, tuple, set)) else [atoms]
        e = sp.expand(e)
        terms = sp.Add.make_args(e)
        return sp.Add(*[t for t in terms if not any(t.has(a) for a in atoms)])

    def transform(fn):
        def mutated(*a, **kw):
            out = fn(*a, **kw)
            if index is None:
                return _map(out, strip)
            out = list(out)
            out[index] = _map(out[index], strip)
            return tuple(out)
        return mutated
    return transform


def replace_output(f: Callable) -> Callable[[Callable], Callable]:
    """Any other mutation: ``f(result, *args, **kwargs)`` returns the mutated result."""
    def transform(fn):
        def mutated(*a, **kw):
            return f(fn(*a, **kw), *a, **kw)
        return mutated
    return transform


# --------------------------------------------------------------------------- closed-loop derivative

def lie_derivative(V: sp.Expr, states: Sequence[sp.Symbol], rates: Sequence[sp.Expr],
                   t: sp.Symbol | None = None) -> sp.Expr:
    """V-dot = sum_i dV/dx_i x_i_dot (+ dV/dt): V differentiated along the vector field ``rates``.

    ``states`` and ``rates`` are flat sequences of equal length (matrices are flattened).
    """
    xs, fs = _flat(states), _flat(rates)
    if len(xs) != len(fs):
        raise ValueError(f"{len(xs)} states but {len(fs)} rates")
    out = sum((sp.diff(V, x) * f for x, f in zip(xs, fs, strict=True)), sp.S.Zero)
    return out + (sp.diff(V, t) if t is not None else 0)


def _flat(seq) -> list:
    out = []
    for s in seq:
        if isinstance(s, sp.MatrixBase):
            out.extend(list(s))
        elif isinstance(s, (list, tuple)):
            out.extend(_flat(s))
        else:
            out.append(s)
    return out


def symbols_vec(name: str, n: int = 3, **assumptions) -> sp.Matrix:
    """Column of real symbols name_1..name_n."""
    return sp.Matrix(sp.symbols(f"{name}_1:{n + 1}", real=True, **assumptions))


def quat_norm_constraint(q: sp.MatrixBase) -> sp.Expr:
    """q^T q - 1 (== 0 for a unit quaternion)."""
    return sum(qi**2 for qi in q) - 1
