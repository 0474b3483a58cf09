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

Relation = Literal["==", "<=", ">=", ">"]
Status = Literal["proved", "holds-with-stated-correction", "not-disproved", "fails"]
STATUSES: tuple[str, ...] = ("proved", "holds-with-stated-correction", "not-disproved", "fails")


# --------------------------------------------------------------------------- search domains

@dataclass(frozen=True)
class Var:
    """Symbols drawn together from ``dim`` box coordinates z in [-1, 1]^dim.

    ``draw(z, env)`` maps an (n, dim) array of box coordinates to an (n, len(symbols)) array of values;
    ``env`` holds the values of the variables listed before this one (for dependent bounds such as
    ``|d| <= D``).  Every point of the box is a valid point of the claim's assumptions, so the local
    optimiser can search the box freely.
    """

    symbols: tuple[sp.Symbol, ...]
    dim: int
    draw: Callable[[np.ndarray, dict], np.ndarray]
    describe: str = ""


def _syms(symbols) -> tuple[sp.Symbol, ...]:
    if isinstance(symbols, sp.MatrixBase):
        return tuple(symbols)
    if isinstance(symbols, sp.Symbol):
        return (symbols,)
    return tuple(symbols)


def box(symbols, lo: float, hi: float) -> Var:
    """Each symbol independently in [lo, hi]."""
    s = _syms(symbols)
    return Var(s, len(s), lambda z, env: lo + (z + 1.0) * 0.5 * (hi - lo), f"in [{lo:g}, {hi:g}]")


def ball(symbols, radius: float | sp.Symbol | Callable[[dict], np.ndarray]) -> Var:
    """A vector with Euclidean norm <= radius (radius: a number, a symbol drawn earlier, or f(env))."""
    s = _syms(symbols)

    def draw(z, env):
        n = np.linalg.norm(z, axis=1, keepdims=True)
        unit_ball = z / np.maximum(n, 1.0)
        return unit_ball * _radius(radius, env, len(z))[:, None]

    return Var(s, len(s), draw, f"|.| <= {radius}")


def _radius(radius, env, n):
    if isinstance(radius, sp.Symbol):
        return np.asarray(env[radius], dtype=float).reshape(n)
    if callable(radius):
        return np.asarray(radius(env), dtype=float).reshape(n)
    return np.full(n, float(radius))


def unit_quaternion(symbols) -> Var:
    """Four symbols on the unit sphere (any order; normalised 4-vector)."""
    s = _syms(symbols)
    assert len(s) == 4

    def draw(z, env):
        n = np.linalg.norm(z, axis=1, keepdims=True)
        return np.where(n > 1e-9, z / np.maximum(n, 1e-12), np.array([0.0, 0.0, 0.0, 1.0]))

    return Var(s, 4, draw, "unit quaternion")


def fixed(symbols, values) -> Var:
    """Symbols held at given values (a gain set, a known inertia)."""
    s = _syms(symbols)
    vals = np.asarray(values, dtype=float).reshape(len(s))
    return Var(s, 0, lambda z, env: np.broadcast_to(vals, (len(z), len(s))).copy(), "fixed")


def derived(symbols, exprs, depends: Sequence[sp.Symbol]) -> Var:
    """Symbols defined from earlier ones, e.g. ``rho = |d|`` (``exprs`` in terms of ``depends``)."""
    s = _syms(symbols)
    exprs = list(exprs) if isinstance(exprs, (list, tuple, sp.MatrixBase)) else [exprs]
    f = sp.lambdify(list(depends), exprs, "numpy")

    def draw(z, env):
        cols = f(*[np.asarray(env[d], dtype=float) for d in depends])
        return np.column_stack([np.broadcast_to(np.asarray(c, dtype=float), (len(z),)) for c in cols])

    return Var(s, 0, draw, "derived")


def custom(symbols, dim: int, draw: Callable[[np.ndarray, dict], np.ndarray], describe: str) -> Var:
    """Any other parameterisation of a constraint set by box coordinates (documented by ``describe``)."""
    return Var(_syms(symbols), dim, draw, describe)


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


@dataclass
class Mutation:
    """A defect injected into one function of a symbolic module; ``affects`` must all then fail."""

    name: str
    module: ModuleType
    attr: str
    transform: Callable[[Callable], Callable]
    affects: tuple[str, ...]
    description: str = ""

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
