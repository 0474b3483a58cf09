"""The checker: symbolic proof where SymPy can decide, adversarial numeric search everywhere.

For every statement the numeric search runs first (it is cheap and it is what finds counterexamples):
``trials`` random points of the domain's box, then L-BFGS-B from the worst points, maximising the
relative violation inside the box (every box point satisfies the stated assumptions by construction of
the domain).  A violation above the tolerance is a counterexample and the statement fails.  Otherwise a
symbolic proof is attempted under a time limit:

* ``==``: the residual lhs - rhs, with ``Abs(x)`` written ``x sign(x)`` and every non-polynomial function
  application replaced by a fresh symbol (after expanding its argument, so equal arguments become the
  same symbol), is brought over a common denominator; the numerator is reduced modulo a Groebner basis
  of the statement's equality constraints (unit quaternions ...).  Remainder zero: proved.  Failing that,
  piecewise residuals (sign, Abs, Max/Min, Heaviside, Step, Piecewise) are split exhaustively on the sign
  of their switching arguments (:func:`prove_zero_cases`), each case reduced the same way.
* ``<=``/``>=``: after the stated assumption substitutions (``D = dbar + delta``), SymPy's assumption
  system must find rhs - lhs (resp. lhs - rhs) nonnegative with the listed symbols positive.
* ``>`` (definiteness in ``zero_at``): lhs - rhs expanded must be a sum of terms each a positive
  coefficient times even powers, with a pure square of every ``zero_at`` coordinate among them.

No symbolic proof means "not-disproved in N trials", never "proved".
"""

from __future__ import annotations

import contextlib
import signal
import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.optimize import differential_evolution, minimize

from ..physics.special import Step
from .core import Claim, Statement

TOL = {"==": 1e-8, "<=": 1e-9, ">=": 1e-9, ">": 1e-9}
ATOL = 1e-12


@dataclass
class Outcome:
    """What the checker found for one statement."""

    holds: bool                    # False: a counterexample was found
    proved: bool                   # True: symbolic proof (only when holds)
    trials: int                    # numeric points evaluated (random + optimiser evaluations)
    max_violation: float           # largest relative violation found (<= tolerance when holds)
    counterexample: dict[str, float] | None = None
    residual: str = ""             # readable lhs - rhs (fails) or the proof's note
    lhs_value: float | None = None
    rhs_value: float | None = None
    symbolic_note: str = ""        # why no symbolic proof, when there is none
    seconds: float = 0.0

    def to_json(self) -> dict:
        return {k: v for k, v in self.__dict__.items()}


@dataclass
class ClaimResult:
    claim: Claim
    status: str
    implementation_ok: bool        # the statement describing rpo's code did not fail
    paper: Outcome | None
    corrected: Outcome | None
    seconds: float
    errors: list[str] = field(default_factory=list)


class _Timeout(Exception):
    pass


@contextlib.contextmanager
def time_limit(seconds: float):
    """Raise _Timeout after ``seconds`` of this process's CPU time (SIGPROF; main thread only, else no limit).

    CPU time, not wall time: a claim's status must not depend on how loaded the machine is (a proof that
    takes 30 s of CPU gave up at a 60 s wall-clock limit on a machine running six jobs on two cores)."""
    try:
        old = signal.signal(signal.SIGPROF, lambda *a: (_ for _ in ()).throw(_Timeout()))
    except ValueError:        # not the main thread
        yield
        return
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, old)


# --------------------------------------------------------------------------- numeric search

def _flatten(e) -> list:
    return list(e) if isinstance(e, sp.MatrixBase) else [e]


class _Evaluator:
    """Box coordinates z -> symbol values -> (lhs, rhs) arrays, vectorised."""

    def __init__(self, st: Statement):
        self.st = st
        self.vars = st.domain
        self.symbols = [s for v in self.vars for s in v.symbols]
        missing = st.free_symbols() - set(self.symbols)
        if missing:
            raise ValueError(f"the domain does not draw {sorted(map(str, missing))}")
        self.dim = sum(v.dim for v in self.vars)
        lhs, rhs = _flatten(st.lhs), _flatten(st.rhs)
        if len(rhs) == 1 and len(lhs) > 1:
            rhs = rhs * len(lhs)
        self.n_out = len(lhs)
        # round-off scale of each component: the sum of |top-level terms| of both sides, so that an
        # identity whose exact value is 0 (or tiny against its terms) is not failed for float noise
        terms = [sum((sp.Abs(t) for side in (a, b) for t in sp.Add.make_args(sp.sympify(side))), sp.S.Zero)
                 for a, b in zip(lhs, rhs, strict=True)]
        self.f = sp.lambdify(self.symbols, lhs + rhs + terms, modules="numpy", cse=True)

    def values(self, z: np.ndarray) -> dict:
        env, k = {}, 0
        for v in self.vars:
            cols = v.draw(z[:, k:k + v.dim], env)
            k += v.dim
            for j, s in enumerate(v.symbols):
                env[s] = cols[:, j]
        return env

    def _evaluate(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        env = self.values(z)
        with np.errstate(all="ignore"):
            out = self.f(*[env[s] for s in self.symbols])
        out = np.array([np.broadcast_to(np.asarray(o, dtype=float), (len(z),)) for o in out])
        return out[:self.n_out], out[self.n_out:2 * self.n_out], out[2 * self.n_out:]

    def lhs_rhs(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lhs, rhs, _ = self._evaluate(z)
        return lhs, rhs

    def violation(self, z: np.ndarray) -> np.ndarray:
        """Violation relative to the size of the terms per point (> tolerance: counterexample); NaN where
        undefined."""
        lhs, rhs, terms = self._evaluate(z)
        scale = np.abs(lhs) + np.abs(rhs) + terms + ATOL
        rel = self.st.relation
        if rel == "==":
            v = np.abs(lhs - rhs) / scale
        elif rel == "<=":
            v = (lhs - rhs) / scale
        else:       # ">=" and ">" (strictness is the symbolic part's business)
            v = (rhs - lhs) / scale
        return np.max(v, axis=0)


@dataclass(frozen=True)
class Search:
    """Budget of the numeric adversarial search (per statement).

    1. ``trials`` uniform random points of the box (default: the statement's own ``trials``);
    2. L-BFGS-B from the worst ``starts`` distinct points (``starts + extra_starts`` for the
       ``global_relations``; gradients by forward differences, all coordinates in one vectorised
       evaluation);
    3. for inequality and definiteness statements (``global_relations``), differential evolution over the
       whole box, its first population the worst random points (so it starts where the violation is
       largest), at most ``global_evals`` evaluations (``global_popsize`` x dim individuals per generation,
       capped at ``global_max_pop``), then L-BFGS-B from its best point.

    Every stage stops as soon as a counterexample is found, so a false statement costs little; the full
    budget is spent only on statements that hold.  Stage 3 exists for violations confined to a small
    region: one that needs several coordinates at once at narrow values, which uniform points hit with
    probability ~ the region's measure and local ascent from the worst points misses when each of them
    lies in a wrong basin; differential evolution recombines coordinates of different good points.
    """

    trials: int | None = None
    starts: int = 6
    extra_starts: int = 0
    local_maxiter: int = 150
    global_evals: int = 40_000
    global_popsize: int = 10
    global_max_pop: int = 400
    global_relations: tuple[str, ...] = ("<=", ">=", ">")


#: the search before stage 3 existed (6 local starts), kept to show what the global stage adds
LOCAL_ONLY = Search(starts=6, extra_starts=0, global_evals=0)
DEFAULT = Search()


def _objective(ev: _Evaluator):
    """-violation at each column of x (dim, S) (scipy's vectorised convention); undefined points count as
    no violation at all (+1: worse than any defined point, whose value is >= -1)."""
    def f(x: np.ndarray) -> np.ndarray:
        v = ev.violation(np.atleast_2d(x.T) if x.ndim == 2 else x[None, :])
        return np.where(np.isfinite(v), -v, 1.0)
    return f


def _local(ev: _Evaluator, z0: np.ndarray, maxiter: int) -> tuple[np.ndarray, float, int]:
    """L-BFGS-B from z0 inside the box; f and its forward-difference gradient from one batch of dim + 1
    points (the step goes inward at the upper bound)."""
    f = _objective(ev)
    h = 1e-7
    n = [0]

    def fg(z):
        step = np.where(z + h <= 1.0, h, -h)
        pts = np.vstack([z, z + np.diag(step)])
        vals = f(pts.T)
        n[0] += len(pts)
        return float(vals[0]), (vals[1:] - vals[0]) / step

    res = minimize(fg, z0, jac=True, method="L-BFGS-B", bounds=[(-1.0, 1.0)] * ev.dim,
                   options={"maxiter": maxiter, "maxfun": 10 * maxiter})
    return res.x, float(-res.fun), n[0]


def _distinct(order: np.ndarray, z: np.ndarray, k: int, radius: float = 0.05) -> list[int]:
    """The first ``k`` indices of ``order`` whose points differ (max-norm > radius) from the ones taken."""
    out: list[int] = []
    if k <= 0:
        return out
    for i in order:
        if all(np.max(np.abs(z[i] - z[j])) > radius for j in out):
            out.append(int(i))
            if len(out) == k:
                break
    return out


def numeric_search(st: Statement, seed: int = 0, trials: int | None = None, search: Search = DEFAULT):
    """Maximise the violation (see :class:`Search`); (evaluator, best z, best violation, evaluations)."""
    ev = _Evaluator(st)
    tol = TOL[st.relation]
    rng = np.random.default_rng(seed)
    n = trials or search.trials or st.trials
    z = rng.uniform(-1.0, 1.0, size=(n, ev.dim))
    v = ev.violation(z)
    evaluated = n
    v = np.where(np.isfinite(v), v, -np.inf)
    order = np.argsort(v)[::-1]
    best_z, best_v = z[order[0]], float(v[order[0]])
    if not ev.dim or best_v > tol:
        return ev, best_z, best_v, evaluated
    inequality = st.relation in search.global_relations
    for i in _distinct(order, z, search.starts + (search.extra_starts if inequality else 0)):
        zz, vv, k = _local(ev, z[i], search.local_maxiter)
        evaluated += k
        if vv > best_v:
            best_z, best_v = zz, vv
        if best_v > tol:
            return ev, best_z, best_v, evaluated
    if search.global_evals and inequality:
        pop = int(min(search.global_max_pop, max(search.global_popsize * ev.dim, 20)))
        gens = max(1, search.global_evals // pop - 1)
        init = np.vstack([best_z, z[order[:pop - 1]]])
        found = []

        def stop(intermediate_result):      # scipy >= 1.11 passes an OptimizeResult
            found.append(-intermediate_result.fun)
            return bool(-intermediate_result.fun > tol)

        res = differential_evolution(_objective(ev), [(-1.0, 1.0)] * ev.dim, maxiter=gens, popsize=pop,
                                     init=init, seed=int(rng.integers(2**31)), vectorized=True,
                                     updating="deferred", polish=False, tol=0.0, atol=0.0, callback=stop)
        evaluated += int(res.nit + 1) * pop     # vectorised: nfev counts calls of pop points
        if -res.fun > best_v:
            best_z, best_v = res.x, float(-res.fun)
        if best_v <= tol:
            zz, vv, k = _local(ev, res.x, search.local_maxiter)
            evaluated += k
            if vv > best_v:
                best_z, best_v = zz, vv
    return ev, best_z, best_v, evaluated


# --------------------------------------------------------------------------- symbolic proof

def _canonical(expr: sp.Expr, table: dict | None = None, normal=None) -> tuple[sp.Expr, dict]:
    """Abs(x) -> x sign(x); each non-polynomial application f(arg) -> a fresh symbol (args expanded);
    a rational power b**(p/q) -> t**p with one symbol t = b**(1/q) per (b, q), so sqrt(b) and 1/sqrt(b)
    share t.  ``table`` (key -> symbol) may be shared between expressions.  ``normal`` (optional) maps an
    expanded argument to a representative congruent to it modulo the constraints (its remainder modulo
    their Groebner basis), so that f(a) and f(b) share one symbol when a - b vanishes wherever the
    constraints hold."""
    expr = expr.replace(lambda e: isinstance(e, sp.Abs), lambda e: e.args[0] * sp.sign(e.args[0]))
    table = {} if table is None else table
    norm = (lambda a: normal(sp.expand(a))) if normal is not None else sp.expand

    def is_opaque(e):
        if isinstance(e, (sp.Function, sp.Max, sp.Min)) and not isinstance(e, sp.Piecewise):
            return True
        return isinstance(e, sp.Pow) and not (e.exp.is_Integer)

    def symbol_for(k):
        if k not in table:
            table[k] = sp.Dummy(f"f{len(table)}", real=True)
        return table[k]

    def sub(e):
        if isinstance(e, sp.Pow):
            if e.exp.is_Rational:
                base = norm(e.base)
                if base == 0 and e.exp > 0:
                    return sp.S.Zero
                return symbol_for(sp.Pow(base, sp.Rational(1, e.exp.q))) ** e.exp.p
            return symbol_for(sp.Pow(norm(e.base), e.exp))
        return symbol_for(e.func(*[norm(a) for a in e.args]))

    # innermost first: replace() walks bottom-up
    return expr.replace(is_opaque, sub), table


def prove_zero(expr: sp.Expr, constraints: list[sp.Expr], congruence: bool = False) -> bool:
    """The residual's numerator is 0 after canonicalisation, or reduces to 0 modulo the constraints and
    the root relations t**q = b of the rational powers.

    ``congruence``: the arguments of the opaque applications are first reduced modulo a Groebner basis of
    the (polynomial) constraints, so f(a) and f(b) become one symbol when a = b wherever the constraints
    hold (sound: they are then equal at every point of the domain)."""
    table: dict = {}
    normal = _constraint_normal_form(constraints) if congruence else None
    e, _ = _canonical(sp.sympify(expr), table, normal)
    num = sp.expand(sp.numer(sp.together(e)))
    if num == 0:
        return True
    cons = [sp.expand(_canonical(sp.sympify(c), table, normal)[0]) for c in constraints]
    cons += [t**k.exp.q - k.base for k, t in list(table.items())
             if isinstance(k, sp.Pow) and k.exp.is_Rational and k.exp.p == 1 and not k.base.has(*table.values())]
    cons = [c for c in cons if c != 0]
    if not cons:
        return False
    gens = sorted(num.free_symbols | set().union(*[c.free_symbols for c in cons]), key=str)
    G = sp.groebner(cons, *gens, order="grevlex")
    _, rem = G.reduce(num)
    return sp.expand(rem) == 0


def _constraint_normal_form(constraints: list[sp.Expr]):
    """p -> its remainder modulo a Groebner basis of the constraints that are polynomials (the others are
    left out: fewer constraints give a coarser but still sound congruence); identity when there are none.
    The remainder r satisfies p - r in the ideal, so p = r at every point where the constraints hold."""
    polys = [sp.expand(c) for c in constraints]
    polys = [c for c in polys if c != 0 and c.is_polynomial(*c.free_symbols)]
    if not polys:
        return lambda p: p
    cgens = sorted(set().union(*[c.free_symbols for c in polys]), key=str)
    G = sp.groebner(polys, *cgens, order="grevlex")     # [1] when no point satisfies them: all congruent

    def normal(p):
        if not p.free_symbols & set(cgens) or not p.is_polynomial(*p.free_symbols):
            return p
        gens = cgens + sorted(p.free_symbols - set(cgens), key=str)
        _, rem = sp.reduced(p, list(G.exprs), *gens, order="grevlex")
        return sp.expand(rem)
    return normal


# ----- case split: identities between piecewise expressions (sign, Abs, Max, Min, Heaviside, Step, Piecewise)

def _switch(e):
    """``(u, value)`` when the application ``e`` is fixed by the sign of one real expression ``u``: ``value(s)``
    is ``e`` for ``sign(u) = s`` in (1, 0, -1), the switching point included; None for anything else."""
    if isinstance(e, sp.sign):
        return e.args[0], sp.Integer
    if isinstance(e, sp.Abs):
        return e.args[0], lambda s: s * e.args[0]
    if isinstance(e, sp.Heaviside):       # Heaviside(u, h0): h0 at u = 0 (SymPy's default 1/2)
        h0 = e.args[1] if len(e.args) > 1 else sp.Heaviside(0)
        return e.args[0], lambda s: {1: sp.S.One, 0: h0, -1: sp.S.Zero}[s]
    if isinstance(e, Step):              # 1 for u >= 0
        return e.args[0], lambda s: sp.S.One if s >= 0 else sp.S.Zero
    if isinstance(e, (sp.Max, sp.Min)):   # Max(a, b, *rest): a if a - b >= 0 (Min: <= 0), then the rest
        a, b, *rest = e.args
        first = (lambda s: s >= 0) if isinstance(e, sp.Max) else (lambda s: s <= 0)
        return a - b, lambda s: e.func(a if first(s) else b, *rest)
    if isinstance(e, sp.Piecewise):      # its first relational condition, decided
        rels = [r for _, cond in e.args for r in sorted(cond.atoms(sp.core.relational.Relational),
                                                        key=sp.default_sort_key)]
        if rels:
            return rels[0].lhs - rels[0].rhs, lambda s: e.xreplace({rels[0]: sp.sympify(_TRUTH[rels[0].rel_op](s))})
    return None


#: a relational ``lhs op rhs`` as a function of sign(lhs - rhs)
_TRUTH = {"==": lambda s: s == 0, "!=": lambda s: s != 0, ">": lambda s: s > 0, ">=": lambda s: s >= 0,
          "<": lambda s: s < 0, "<=": lambda s: s <= 0}


def _sign_form(u):
    """An expanded expression of the same sign as u: its numerator, times -1 if its denominator is negative
    (u itself, expanded, when the denominator's sign is unknown)."""
    n, dn = sp.fraction(sp.together(u))
    if dn.is_positive:
        return sp.expand(n)
    if dn.is_negative:
        return sp.expand(-n)
    return sp.expand(u)


def _known_sign(u, facts) -> int | None:
    """sign(u) from the symbols' assumptions or the case's facts ``(a, s)`` (sign(a) = s, a a sign form),
    else None."""
    for v in (u, _sign_form(u)):
        if v.is_zero:
            return 0
        if v.is_positive:
            return 1
        if v.is_negative:
            return -1
    u = _sign_form(u)
    for a, s in facts:
        if sp.expand(u - a) == 0:
            return s
        if sp.expand(u + a) == 0:
            return -s
    return None


def _decide(e, facts):
    """Replace every switching application whose sign is known by its branch, until none is left."""
    while True:
        rep = {}
        for x in sp.preorder_traversal(e):
            sw = _switch(x)
            if sw is not None and x not in rep:
                s = _known_sign(sw[0], facts)
                if s is not None and sw[1](s) != x:
                    rep[x] = sw[1](s)
        if not rep:
            return e
        e = e.xreplace(rep)


def _undecided(e) -> list:
    return [x for x in sp.preorder_traversal(e) if _switch(x) is not None]


def _split_argument(apps):
    """The argument to split on: one containing no switching application itself (innermost), the smallest."""
    args = [_switch(x)[0] for x in apps]
    inner = [u for u in args if not _undecided(u)] or args
    return min(inner, key=lambda u: (sp.count_ops(u), sp.default_sort_key(u)))


def _linear_in(u, splits):
    """``(x, c, r)`` with u = c x + r, c a nonzero number, r free of x: a symbol to solve for, preferring
    symbols without a sign assumption, then those of earlier splits (``splits``: the fresh symbols, each
    with its value in the statement's symbols), then the others (their sign assumption is kept as a
    hypothesis when they are substituted)."""
    u = sp.expand(u)

    def rank(x):
        return (0 if x.is_positive is None and x.is_negative is None else 1 if x in splits else 2, str(x))

    for x in sorted((x for x in u.free_symbols if isinstance(x, sp.Symbol)), key=rank):
        c = sp.diff(u, x)
        if c.is_number and c != 0 and not sp.expand(u - c * x).has(x):
            return x, c, sp.expand(u - c * x)
    return None


def _sign_hypotheses(x) -> list:
    """What x's assumptions say about its sign, as relationals (kept when x is substituted)."""
    for test, rel in ((x.is_positive, sp.Gt), (x.is_negative, sp.Lt), (x.is_nonnegative, sp.Ge),
                      (x.is_nonpositive, sp.Le)):
        if test:
            return [rel(x, 0)]
    return []


def _rename_real(exprs, positive):
    """The statement's domain is real and ``positive`` symbols are > 0: symbols without assumptions become
    real ones, the listed ones positive (never merging two symbols of one name)."""
    syms = set().union(*[getattr(e, "free_symbols", set()) for e in exprs])
    names = [s.name for s in syms if isinstance(s, sp.Symbol)]
    pos = set(positive)
    rep = {}
    for s in syms:
        if not isinstance(s, sp.Symbol) or isinstance(s, sp.Dummy) or names.count(s.name) > 1:
            continue
        if s in pos and not s.is_positive:
            rep[s] = sp.Symbol(s.name, positive=True)
        elif s.is_real is None:
            rep[s] = sp.Symbol(s.name, real=True)
    return [sp.sympify(e).xreplace(rep) for e in exprs]


def _nonnegative_radicands(e) -> list:
    """Radicands (bases of even roots) that SymPy's assumptions find nonnegative: facts that can empty a case
    (a case ``u < 0`` is empty when u equals one of them modulo the constraints)."""
    return [x.base for x in sp.preorder_traversal(e)
            if isinstance(x, sp.Pow) and x.exp.is_Rational and not x.exp.is_Integer and x.exp.q % 2 == 0
            and x.base.is_nonnegative]


class _CaseLimit(Exception):
    pass


def prove_zero_cases(expr: sp.Expr, constraints=(), hypotheses=(), positive=(),
                     max_leaves: int = 729) -> tuple[bool, str]:
    """``expr == 0`` at every point of the domain, by an exhaustive case split on the sign of the switching
    arguments (``sign``, ``Abs``, ``Max``/``Min``, ``Heaviside``, ``Step``, Piecewise conditions), each leaf by
    :func:`prove_zero` (with congruence modulo the constraints).  Returns (proved, note).

    Each split on an argument u has three cases, u > 0, u = 0, u < 0 (every real value of u, the switching
    point itself included), and every application switched by +-u takes its branch value in each case:

    * u = c x + r linear in a symbol x (c a nonzero number): x is substituted, x = (t - r)/c with a fresh
      t > 0 (u > 0), t = 0, or t = -t' (u < 0), a bijection onto the case; then every switching argument
      whose sign SymPy's assumptions decide (``2 d + t`` with d, t > 0) takes its branch too, and x's own
      sign assumption is kept as a hypothesis;
    * otherwise u = 0 joins the constraints (a polynomial equality), and u > 0, u < 0 are decided only by
      identities that hold regardless; such a case is empty when u reduces modulo the constraints to 0 or
      to a radicand of the expression that SymPy finds nonnegative (of the opposite sign).

    A case is empty (nothing to prove) when one of the ``hypotheses`` (relationals every point of the
    domain satisfies, such as ``Abs(s) <= d``) or a recorded sign assumption evaluates to False in it.
    A leaf with undecided applications left treats them as opaque symbols (valid for every value).
    """
    parts = _rename_real([expr, *constraints, *hypotheses], positive)
    # floats as the exact rationals they are (the Groebner domain cannot mix them with integers)
    parts = [p.xreplace({f: sp.Rational(f) for f in p.atoms(sp.Float)}) for p in parts]
    e, cons, hyps = parts[0], parts[1:1 + len(constraints)], parts[1 + len(constraints):]
    leaves = [0]
    failed: list[str] = []

    def case(e, cons, hyps, facts, cands, splits, where):
        hyps = [_decide(h, facts) for h in hyps]
        if any(h is sp.false or h == sp.false for h in hyps):
            return True
        hyps = [h for h in hyps if h is not sp.true]
        e = _decide(e, facts)
        if e == 0:
            return True
        apps = _undecided(e)
        try:
            if prove_zero(e, cons, congruence=True):
                return True
        except sp.polys.polyerrors.BasePolynomialError:
            pass
        if not apps:
            failed.append(" and ".join(where) or "everywhere")
            return False
        leaves[0] += 2
        if leaves[0] > max_leaves:
            raise _CaseLimit
        u = _sign_form(_split_argument(apps))
        lin = _linear_in(u, splits)
        u_orig = sp.expand(u.xreplace(splits))      # in the statement's symbols, for the note
        for s in (1, 0, -1):
            w = [*where, f"{u_orig} {'>' if s > 0 else '=' if s == 0 else '<'} 0"]
            if lin is not None:
                x, c, r = lin
                t = sp.Dummy("t", positive=True)
                val = {1: t, 0: sp.S.Zero, -1: -t}[s]
                rep = {x: (val - r) / c}

                def put(z, rep=rep):
                    return sp.sympify(z).xreplace(rep)

                ok = case(put(e), [put(c_) for c_ in cons], [put(h) for h in hyps + _sign_hypotheses(x)],
                          [(put(a), sa) for a, sa in facts], [put(z) for z in cands], {**splits, t: s * u_orig}, w)
            else:
                if s == 0:
                    ok = case(e, [*cons, u], hyps, [*facts, (u, 0)], cands, splits, w)
                elif _empty_strict(u, s, cons, cands):
                    ok = True
                else:
                    ok = case(e, cons, hyps + [sp.Gt(u, 0) if s > 0 else sp.Lt(u, 0)], [*facts, (u, s)], cands,
                              splits, w)
            if not ok:
                return False
        return True

    try:
        ok = case(e, cons, hyps, [], _nonnegative_radicands(e), {}, [])
    except _CaseLimit:
        return False, f"case split gave up after {max_leaves} cases"
    return ok, ("" if ok else f"residual does not reduce to 0 where {failed[0]}")


def _empty_strict(u, s, cons, cands) -> bool:
    """No point of the case sign(u) = s (s = +-1) satisfies the constraints: u reduces to 0, or to a
    nonnegative radicand when s < 0 (to minus one when s > 0)."""
    try:
        normal = _constraint_normal_form(cons)
        if normal(sp.expand(u)) == 0:
            return True
        return any(normal(sp.expand(u + s * z)) == 0 for z in cands)
    except sp.polys.polyerrors.BasePolynomialError:
        return False


def _may_split(expr, constraints) -> bool:
    """Worth a case split: a switching application, or opaque applications that the constraints may make
    congruent."""
    if any(_switch(x) is not None for x in sp.preorder_traversal(expr)):
        return True
    return bool(constraints) and any(isinstance(x, (sp.Function, sp.Pow)) and not (
        isinstance(x, sp.Pow) and x.exp.is_Integer) for x in sp.preorder_traversal(expr))


def _positive_version(expr, positive):
    rep = {s: sp.Symbol(s.name, positive=True) for s in positive if isinstance(s, sp.Symbol)}
    return expr.xreplace(rep)


def _real_version(expr):
    rep = {s: sp.Symbol(s.name, real=True) for s in expr.free_symbols
           if isinstance(s, sp.Symbol) and s.is_real is None}
    return expr.xreplace(rep)


def prove_nonnegative(expr: sp.Expr, positive) -> bool:
    e = _real_version(_positive_version(sp.sympify(expr), positive))
    if e.is_nonnegative:
        return True
    ee = sp.expand(e)
    if ee.is_nonnegative or all(t.is_nonnegative for t in sp.Add.make_args(ee)):
        return True
    f = sp.factor(ee)
    return bool(f.is_nonnegative)


def prove_positive_definite(expr: sp.Expr, zero_at, positive) -> bool:
    """A sum of nonnegative terms (positive coefficient x even powers) with, among them, a pure square of
    each ``zero_at`` coordinate times a positive coefficient; tried on the expression as written, then
    expanded."""
    e = _real_version(_positive_version(sp.sympify(expr), positive))
    coords = [_positive_version(c, positive) for c in zero_at]
    return _sum_of_squares(e, coords) or _sum_of_squares(sp.expand(e), coords)


def _sum_of_squares(e, coords) -> bool:
    pure = set()
    for t in sp.Add.make_args(e):
        coeff, rest = sp.S.One, sp.S.One
        for f, p in t.as_powers_dict().items():
            if any(f.has(c) for c in coords):
                if not (p.is_Integer and p % 2 == 0 and f.is_real):
                    return False
                rest *= f**p
            else:
                coeff *= f**p
        if not coeff.is_nonnegative:
            return False
        if rest != 1 and coeff.is_positive and rest.is_Pow and rest.exp == 2 and rest.base in coords:
            pure.add(rest.base)
    return all(c in pure for c in coords)


def symbolic_proof(st: Statement, seconds: float) -> tuple[bool, str]:
    """(proved, note)."""
    t0 = time.perf_counter()
    try:
        with time_limit(seconds):
            lhs, rhs = _flatten(st.lhs), _flatten(st.rhs)
            if len(rhs) == 1 and len(lhs) > 1:
                rhs = rhs * len(lhs)
            if st.relation == "==":
                for a, b in zip(lhs, rhs, strict=True):
                    with contextlib.suppress(sp.polys.polyerrors.BasePolynomialError):   # floats, Piecewise
                        if prove_zero(a - b, st.constraints):
                            continue
                    if not _may_split(a - b, st.constraints):
                        return False, "residual does not reduce to 0 modulo the constraints"
                    ok, note = prove_zero_cases(a - b, st.constraints, st.hypotheses, st.positive)
                    if not ok:
                        return False, note
                return True, ""
            diffs = [sp.sympify(b - a if st.relation == "<=" else a - b).subs(st.substitutions)
                     for a, b in zip(lhs, rhs, strict=True)]
            if st.relation == ">":
                ok = all(prove_positive_definite(d, st.zero_at, st.positive) for d in diffs)
                return ok, ("" if ok else "not recognised as a positive sum of squares")
            ok = all(prove_nonnegative(d, st.positive) for d in diffs)
            return ok, ("" if ok else "SymPy cannot decide the sign")
    except _Timeout:
        return False, f"symbolic proof gave up after {time.perf_counter() - t0:.0f} s"


def readable_residual(st: Statement, seconds: float = 10.0, limit: int = 600) -> str:
    lhs, rhs = _flatten(st.lhs), _flatten(st.rhs)
    if len(rhs) == 1 and len(lhs) > 1:
        rhs = rhs * len(lhs)
    res = [a - b for a, b in zip(lhs, rhs, strict=True)]
    if seconds <= 0:        # no simplification (and no unlimited SIGALRM)
        return _clip(sp.sstr(res[0] if len(res) == 1 else sp.Matrix(res)), limit)
    try:
        with time_limit(seconds):
            res = [sp.factor(sp.simplify(r)) for r in res]
    except _Timeout:
        pass
    return _clip(sp.sstr(res[0] if len(res) == 1 else sp.Matrix(res)), limit)


def _clip(txt: str, limit: int) -> str:
    return txt if len(txt) <= limit else txt[:limit] + f" ... ({len(txt)} characters)"


# --------------------------------------------------------------------------- statements and claims

def check_statement(st: Statement, seed: int = 0, symbolic: bool = True, trials: int | None = None,
                    symbolic_seconds: float = 60.0, search: Search = DEFAULT) -> Outcome:
    t0 = time.perf_counter()
    ev, z, v, n = numeric_search(st, seed=seed, trials=trials, search=search)
    lhs, rhs = ev.lhs_rhs(z[None, :])
    k = int(np.argmax(np.abs(lhs - rhs)[:, 0])) if st.relation == "==" else 0
    if v > TOL[st.relation]:
        env = ev.values(z[None, :])
        cx = {str(s): float(env[s][0]) for s in ev.symbols}
        residual = readable_residual(st, st.residual_seconds if (symbolic and st.symbolic) else 0)
        return Outcome(False, False, n, v, cx, residual, float(lhs[k, 0]), float(rhs[k, 0]),
                       seconds=time.perf_counter() - t0)
    proved, note = (False, "numeric only")
    if symbolic and st.symbolic:
        proved, note = symbolic_proof(st, symbolic_seconds)
    return Outcome(True, proved, n, max(v, 0.0), symbolic_note=note, seconds=time.perf_counter() - t0)


def check_claim(claim: Claim, seed: int = 0, symbolic: bool = True, trials: int | None = None) -> ClaimResult:
    t0 = time.perf_counter()
    paper = check_statement(claim.paper(), seed, symbolic, trials) if claim.paper else None
    corr = check_statement(claim.corrected(), seed, symbolic, trials) if claim.corrected else None
    impl = corr if corr is not None else paper
    if corr is None:
        status = "fails" if not paper.holds else ("proved" if paper.proved else "not-disproved")
    elif paper is None:     # a claim only about the implementation: its own status
        status = ("proved" if corr.proved else "not-disproved") if corr.holds else "fails"
    elif not paper.holds:
        status = "holds-with-stated-correction" if corr.holds else "fails"
    else:       # the printed step holds; the implementation's form must hold too
        status = ("proved" if paper.proved else "not-disproved") if corr.holds else "fails"
    impl_ok = impl.holds if claim.about == "implementation" else True
    return ClaimResult(claim, status, impl_ok, paper, corr, time.perf_counter() - t0)
