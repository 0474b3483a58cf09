"""The independent checker of certificates: every leaf box re-evaluated in ``mpmath.iv`` at 80 bits.

This module shares no arithmetic with the prover (:mod:`.intervals`, NumPy float64 with outward
rounding): it walks the SymPy goal with mpmath's interval type, which rounds each endpoint outward at
:data:`PREC` bits.  It trusts no stored bound: it regenerates every box from the root of the region by
the tree's split decisions (so a removed box breaks the tree, an edited bound cannot be expressed) and
re-derives each leaf's method on its own:

* ``X``: some hypothesis has an enclosure entirely < 0;
* ``N``: the enclosure of the goal has lower bound >= 0;
* ``M``: the goal is differentiable on the box and g(c) + sum_i dg/dx_i(box) [x_i - c_i] >= 0, c the
  exact centre;
* ``C``: as ``M``'s premise; the coordinates where this checker's own gradient enclosure has a fixed sign
  are fixed at the smaller end, and the face's natural or mean-value bound is >= 0;
* ``H``: the box contains an equilibrium x0 of the plan with g(x0) = 0 and grad g(x0) = 0 exactly
  (SymPy, rational arithmetic), the goal is twice differentiable on the box and its interval Hessian
  passes Gershgorin's test for positive semidefiniteness.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from mpmath import iv, mpf

from ...special import Fmax, Step

PREC = 80


class CheckError(Exception):
    """A certificate that does not check: the message says which goal, which box and why."""


def _point(x) -> iv.mpf:
    return iv.mpf([x, x])


def _hull(a, b):
    return iv.mpf([min(a.a, b.a), max(a.b, b.b)])


def _monotone_point(f, a, increasing=True):
    """f over interval a for a monotone f given on points (f returns an enclosure of f(point))."""
    lo, hi = f(_point(a.a)), f(_point(a.b))
    return iv.mpf([lo.a, hi.b]) if increasing else iv.mpf([hi.a, lo.b])


def _tanh_point(x):
    e = iv.exp(2 * x)
    return 1 - 2 / (e + 1)


def _iv_tanh(a):
    r = _monotone_point(_tanh_point, a)
    return iv.mpf([max(r.a, -1), min(r.b, 1)])


def _iv_cosh(a):
    def ch(x):
        return (iv.exp(x) + iv.exp(-x)) / 2
    ends = _hull(ch(_point(a.a)), ch(_point(a.b)))
    if a.a <= 0 <= a.b:
        return iv.mpf([1, ends.b])
    return ends


def _straddles(a, closed: bool) -> bool:
    return (a.a <= 0 <= a.b) if closed else (a.a < 0 < a.b)


class IvProgram:
    """A SymPy expression list compiled to mpmath interval operations (own walker, own op set)."""

    def __init__(self, exprs, variables):
        self.variables = list(variables)
        self.exprs = [sp.sympify(e) for e in exprs]

    def evaluate(self, box: list) -> tuple[list, bool]:
        """(enclosures of the expressions, smooth) over ``box`` (one iv.mpf per variable)."""
        memo: dict = dict(zip(self.variables, box, strict=True))
        state = {"smooth": True}
        out = [self._ev(e, memo, state) for e in self.exprs]
        return out, state["smooth"]

    def _ev(self, e, memo, state):
        if e in memo:
            return memo[e]
        r = self._ev_new(e, memo, state)
        memo[e] = r
        return r

    def _ev_new(self, e, memo, state):
        ev = self._ev
        if e.is_Rational:
            return iv.mpf(int(e.p)) / iv.mpf(int(e.q)) if e.q != 1 else iv.mpf(int(e.p))
        if e.is_Float:
            return iv.mpf(sp.Rational(e).p) / iv.mpf(sp.Rational(e).q)
        if e.is_NumberSymbol:
            return iv.mpf(str(sp.N(e, 40)))  # a 40-digit decimal, widened by mpmath's string conversion
        if e.is_Symbol:
            raise CheckError(f"symbol {e} is not a coordinate")
        if isinstance(e, sp.Add):
            acc = ev(e.args[0], memo, state)
            for a in e.args[1:]:
                acc = acc + ev(a, memo, state)
            return acc
        if isinstance(e, sp.Mul):
            acc = ev(e.args[0], memo, state)
            for a in e.args[1:]:
                acc = acc * ev(a, memo, state)
            return acc
        if isinstance(e, sp.Pow):
            b, x = e.args
            if x.is_Integer:
                return _ipow(ev(b, memo, state), int(x))
            if x.is_Rational and x.q == 2:
                base = ev(b, memo, state)
                if base.a < 0:
                    return iv.mpf(["-inf", "inf"])
                root = iv.sqrt(base)
                if x.p == 1:
                    return root
                return _ipow(root, int(x.p))
            return ev(sp.exp(x * sp.log(b)), memo, state)
        if isinstance(e, sp.exp):
            return iv.exp(ev(e.args[0], memo, state))
        if isinstance(e, sp.log):
            a = ev(e.args[0], memo, state)
            return iv.mpf(["-inf", "inf"]) if a.a <= 0 else iv.log(a)
        if isinstance(e, sp.tanh):
            return _iv_tanh(ev(e.args[0], memo, state))
        if isinstance(e, sp.cosh):
            return _iv_cosh(ev(e.args[0], memo, state))
        if isinstance(e, sp.sinh):
            return ev((sp.exp(e.args[0]) - sp.exp(-e.args[0])) / 2, memo, state)
        if isinstance(e, sp.sin):
            return iv.sin(ev(e.args[0], memo, state))
        if isinstance(e, sp.cos):
            return iv.cos(ev(e.args[0], memo, state))
        if isinstance(e, sp.atan):
            return iv.atan(ev(e.args[0], memo, state))
        if isinstance(e, sp.Abs):
            a = ev(e.args[0], memo, state)
            if _straddles(a, closed=False):
                state["smooth"] = False
            return abs(a)
        if isinstance(e, sp.sign):
            a = ev(e.args[0], memo, state)
            if _straddles(a, closed=True):
                state["smooth"] = False
            sgn = [(-1 if v < 0 else (1 if v > 0 else 0)) for v in (a.a, a.b)]
            return iv.mpf(sgn)
        if isinstance(e, (sp.Heaviside, Step)):
            h0 = (e.args[1] if len(e.args) > 1 else sp.Rational(1, 2)) if isinstance(e, sp.Heaviside) else 1
            a = ev(e.args[0], memo, state)
            vals = []
            for v in (a.a, a.b):
                vals.append(1 if v > 0 else (0 if v < 0 else float(h0)))
            if _straddles(a, closed=True):
                state["smooth"] = False
                vals.append(float(h0))
            return iv.mpf([min(vals), max(vals)])
        if isinstance(e, (sp.Max, Fmax, sp.Min)):
            args = [ev(a, memo, state) for a in e.args]
            is_max = not isinstance(e, sp.Min)
            lo = (max if is_max else min)(a.a for a in args)
            hi = (max if is_max else min)(a.b for a in args)
            # smooth only where one argument dominates the others on the whole box
            if is_max:
                top = max(range(len(args)), key=lambda k: args[k].a)
                if not all(args[top].a > args[k].b for k in range(len(args)) if k != top):
                    state["smooth"] = False
            else:
                top = min(range(len(args)), key=lambda k: args[k].b)
                if not all(args[top].b < args[k].a for k in range(len(args)) if k != top):
                    state["smooth"] = False
            return iv.mpf([lo, hi])
        if isinstance(e, sp.Piecewise):
            acc, decided = None, False
            for val, cond in e.args:
                if cond is sp.true:
                    maybe, sure = True, True
                else:
                    a, b = ev(cond.lhs, memo, state), ev(cond.rhs, memo, state)
                    op = cond.rel_op
                    if op in ("<", "<="):
                        a, b, op = b, a, (">" if op == "<" else ">=")
                    if op == ">":
                        maybe, sure = a.b > b.a, a.a > b.b
                    elif op == ">=":
                        maybe, sure = a.b >= b.a, a.a >= b.b
                    else:
                        raise CheckError(f"Piecewise condition {cond}")
                if maybe:
                    v = ev(val, memo, state)
                    acc = v if acc is None else _hull(acc, v)
                    if not sure:
                        state["smooth"] = False
                if sure:
                    decided = True
                    break
            if acc is None or not decided:
                raise CheckError("Piecewise without a branch for part of a box")
            return acc
        raise CheckError(f"no interval rule for {type(e).__name__}")


def _ipow(base, n: int):
    if n > 0 and n % 2 == 0:
        return abs(base) ** n
    if n < 0:
        if base.a <= 0 <= base.b:
            return iv.mpf(["-inf", "inf"])
        return 1 / (base ** (-n))
    return base ** n


@dataclass
class LeafChecker:
    """Checks the leaves of one goal (see the module docstring)."""

    g: sp.Expr
    coords: list
    hypotheses: list
    equilibria: list
    strict: bool = False

    def __post_init__(self):
        self.prog = IvProgram([self.g], self.coords)
        self.hyp = IvProgram(self.hypotheses, self.coords) if self.hypotheses else None
        self._grad = None
        self._hess = None
        self.eq_points = []
        for p in self.equilibria:
            sub = {k: sp.Rational(v) for k, v in p.items()}
            if set(sub) != set(self.coords):
                continue
            if sp.simplify(self.g.xreplace(sub)) == 0 and all(
                    sp.simplify(sp.diff(self.g, x).xreplace(sub)) == 0 for x in self.coords):
                self.eq_points.append([sub[x] for x in self.coords])

    @property
    def grad(self) -> IvProgram:
        if self._grad is None:
            self._grad = IvProgram([sp.diff(self.g, x) for x in self.coords], self.coords)
        return self._grad

    @property
    def hess(self) -> IvProgram:
        if self._hess is None:
            n = len(self.coords)
            self._hess = IvProgram([sp.diff(self.g, self.coords[i], self.coords[j])
                                    for i in range(n) for j in range(n)], self.coords)
        return self._hess

    def _mean_value(self, box) -> tuple[mpf | None, list | None]:
        """Lower bound of the mean-value form (None where g is not differentiable on the box), and the
        gradient enclosure."""
        (gv,), smooth = self.prog.evaluate(box)
        if not smooth:
            return None, None
        grads, gsmooth = self.grad.evaluate(box)
        centre = [iv.mpf([(b.a + b.b) / 2, (b.a + b.b) / 2]) for b in box]
        (gc,), _ = self.prog.evaluate(centre)
        acc = gc
        for d, b, c in zip(grads, box, centre, strict=True):
            acc = acc + d * (b - c)
        return acc.a, grads

    def _ok(self, lower) -> bool:
        return lower > 0 if self.strict else lower >= 0

    def check(self, method: str, box: list) -> str:
        """'' when the leaf's method holds on ``box``, else the reason."""
        if method == "X":
            if self.hyp is None:
                return "excluded by a hypothesis, but the goal has none"
            hs, _ = self.hyp.evaluate(box)
            return "" if any(h.b < 0 for h in hs) else "no hypothesis is < 0 on the whole box"
        if method == "N":
            (gv,), _ = self.prog.evaluate(box)
            return "" if self._ok(gv.a) else f"enclosure lower bound {gv.a} too low"
        if method == "M":
            lo, _ = self._mean_value(box)
            if lo is None:
                return "the goal is not differentiable on the box"
            return "" if self._ok(lo) else f"mean-value lower bound {lo} too low"
        if method == "C":
            (gv,), smooth = self.prog.evaluate(box)
            if not smooth:
                return "the goal is not differentiable on the box"
            grads, _ = self.grad.evaluate(box)
            face = []
            for d, b in zip(grads, box, strict=True):
                if d.a >= 0:
                    face.append(iv.mpf([b.a, b.a]))
                elif d.b <= 0:
                    face.append(iv.mpf([b.b, b.b]))
                else:
                    face.append(b)
            (fv,), _ = self.prog.evaluate(face)
            if self._ok(fv.a):
                return ""
            lo, _ = self._mean_value(face)
            return "" if (lo is not None and self._ok(lo)) else f"face lower bound {fv.a} too low"
        if method == "H":
            if self.strict:
                return "a second-order certificate proves g >= 0 only, the goal is strict"
            inside = [p for p in self.eq_points if all(b.a <= _mpq(v) <= b.b for v, b in zip(p, box, strict=True))]
            if not inside:
                return "the box contains no verified equilibrium"
            n = len(box)
            hs, smooth = self.hess.evaluate(box)
            (_,), gsmooth = self.prog.evaluate(box)
            if not (smooth and gsmooth):
                return "the goal is not twice differentiable on the box"
            for i in range(n):
                off = iv.mpf(0)
                for j in range(n):
                    if j != i:
                        off = off + abs(hs[i * n + j])
                if not hs[i * n + i].a >= off.b:
                    return f"Gershgorin row {i}: {hs[i * n + i].a} < {off.b}"
            return ""
        return f"unknown method {method!r}"


def _mpq(v: sp.Rational):
    return mpf(int(v.p)) / mpf(int(v.q))


def walk(tree: bytes, root: list[tuple[float, float]], checker: LeafChecker, leaf_names: dict[int, str]) -> int:
    """Regenerate every box of ``tree`` from ``root`` and check each leaf; the number of leaves.  Raises
    :class:`CheckError` on a malformed tree or a leaf that does not hold."""
    iv.prec = PREC
    stack = [list(root)]
    pos = 0
    leaves = 0
    n = len(root)
    while stack:
        box = stack.pop()
        if pos >= len(tree):
            raise CheckError(f"the tree ends with {len(stack) + 1} boxes not covered")
        c = tree[pos]
        pos += 1
        if c in leaf_names:
            why = checker.check(leaf_names[c], [iv.mpf([a, b]) for a, b in box])
            if why:
                raise CheckError(f"leaf {leaves} ({leaf_names[c]}) on box "
                                 f"{[(float(a), float(b)) for a, b in box]}: {why}")
            leaves += 1
            continue
        if c >= n:
            raise CheckError(f"split along coordinate {c}, but the box has {n}")
        a, b = box[c]
        s = 0.5 * a + 0.5 * b
        if not (a < s < b):
            raise CheckError(f"split of [{a!r}, {b!r}] along coordinate {c} has no interior point")
        left, right = list(box), list(box)
        left[c], right[c] = (a, s), (s, b)
        stack += [right, left]
    if pos != len(tree):
        raise CheckError(f"{len(tree) - pos} tree entries after every box was closed")
    return leaves
