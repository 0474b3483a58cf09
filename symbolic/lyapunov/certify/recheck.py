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

from ...physics.special import Fmax, Step

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
    """A SymPy expression list compiled to mpmath interval operations (own walker, own op set).

    The expressions are walked once into a list of closures over slots (common subexpressions share a
    slot); :meth:`evaluate` runs the list on one box."""

    def __init__(self, exprs, variables):
        self.variables = list(variables)
        self.exprs = [sp.sympify(e) for e in exprs]
        self._index: dict = {v: i for i, v in enumerate(self.variables)}
        self._ops: list = []
        self._n = len(self.variables)
        self.outputs = [self._emit(e) for e in self.exprs]

    def evaluate(self, box: list) -> tuple[list, bool]:
        """(enclosures of the expressions, smooth) over ``box`` (one iv.mpf per variable)."""
        slots = list(box) + [None] * (self._n - len(box))
        state = [True]
        for f, out, args in self._ops:
            slots[out] = f(state, *[slots[a] for a in args])
        return [slots[k] for k in self.outputs], state[0]

    def _new(self, f, args) -> int:
        k = self._n
        self._n += 1
        self._ops.append((f, k, tuple(args)))
        return k

    def _emit(self, e) -> int:
        if e in self._index:
            return self._index[e]
        k = self._emit_new(e)
        self._index[e] = k
        return k

    def _const(self, value) -> int:
        return self._new(lambda st, v=value: v, [])

    def _emit_new(self, e) -> int:
        em = self._emit
        if e.is_Rational:
            return self._const(iv.mpf(int(e.p)) / iv.mpf(int(e.q)) if e.q != 1 else iv.mpf(int(e.p)))
        if e.is_Float:
            r = sp.Rational(e)
            return self._const(iv.mpf(int(r.p)) / iv.mpf(int(r.q)))
        if e.is_NumberSymbol:
            return self._const(iv.mpf(str(sp.N(e, 40))))
        if e.is_Symbol:
            raise CheckError(f"symbol {e} is not a coordinate")
        if isinstance(e, sp.Add):
            return self._new(_op_add, [em(a) for a in e.args])
        if isinstance(e, sp.Mul):
            return self._new(_op_mul, [em(a) for a in e.args])
        if isinstance(e, sp.Pow):
            b, x = e.args
            if x.is_Integer:
                return self._new(lambda st, a, n=int(x): _ipow(a, n), [em(b)])
            if x.is_Rational and x.q == 2:
                return self._new(lambda st, a, n=int(x.p): _op_half_pow(a, n), [em(b)])
            return em(sp.exp(x * sp.log(b)))
        if isinstance(e, sp.exp):
            return self._new(lambda st, a: iv.exp(a), [em(e.args[0])])
        if isinstance(e, sp.log):
            return self._new(lambda st, a: iv.mpf(["-inf", "inf"]) if a.a <= 0 else iv.log(a), [em(e.args[0])])
        if isinstance(e, sp.tanh):
            return self._new(lambda st, a: _iv_tanh(a), [em(e.args[0])])
        if isinstance(e, sp.cosh):
            return self._new(lambda st, a: _iv_cosh(a), [em(e.args[0])])
        if isinstance(e, sp.sinh):
            return em((sp.exp(e.args[0]) - sp.exp(-e.args[0])) / 2)
        if isinstance(e, sp.sin):
            return self._new(lambda st, a: iv.sin(a), [em(e.args[0])])
        if isinstance(e, sp.cos):
            return self._new(lambda st, a: iv.cos(a), [em(e.args[0])])
        if isinstance(e, sp.atan):
            return self._new(lambda st, a: iv.atan(a), [em(e.args[0])])
        if isinstance(e, sp.Abs):
            return self._new(_op_abs, [em(e.args[0])])
        if isinstance(e, sp.sign):
            return self._new(_op_sign, [em(e.args[0])])
        if isinstance(e, (sp.Heaviside, Step)):
            h0 = (e.args[1] if len(e.args) > 1 else sp.Rational(1, 2)) if isinstance(e, sp.Heaviside) else 1
            return self._new(lambda st, a, h=float(h0): _op_step(st, a, h), [em(e.args[0])])
        if isinstance(e, sp.DiracDelta):
            return self._new(_op_dirac, [em(e.args[0])])
        if isinstance(e, (sp.Max, Fmax, sp.Min)):
            is_max = not isinstance(e, sp.Min)
            return self._new(lambda st, *a, m=is_max: _op_maxmin(st, a, m), [em(a) for a in e.args])
        if isinstance(e, sp.Piecewise):
            branches, args = [], []
            for val, cond in e.args:
                if cond is sp.true:
                    branches.append((len(args), None))
                    args.append(em(val))
                    continue
                if not isinstance(cond, (sp.StrictLessThan, sp.LessThan, sp.StrictGreaterThan, sp.GreaterThan)):
                    raise CheckError(f"Piecewise condition {cond}")
                branches.append((len(args), cond.rel_op))
                args += [em(val), em(cond.lhs), em(cond.rhs)]
            return self._new(lambda st, *a, br=tuple(branches): _op_piecewise(st, a, br), args)
        raise CheckError(f"no interval rule for {type(e).__name__}")


def _op_add(st, *args):
    acc = args[0]
    for a in args[1:]:
        acc = acc + a
    return acc


def _op_mul(st, *args):
    acc = args[0]
    for a in args[1:]:
        acc = acc * a
    return acc


def _op_half_pow(a, n: int):
    if a.a < 0:
        return iv.mpf(["-inf", "inf"])
    root = iv.sqrt(a)
    return root if n == 1 else _ipow(root, n)


def _op_abs(st, a):
    if _straddles(a, closed=False):
        st[0] = False
    return abs(a)


def _op_sign(st, a):
    if _straddles(a, closed=True):
        st[0] = False
    return iv.mpf([(-1 if v < 0 else (1 if v > 0 else 0)) for v in (a.a, a.b)])


def _op_dirac(st, a):
    if _straddles(a, closed=True):
        st[0] = False
        return iv.mpf(["-inf", "inf"])
    return iv.mpf(0)


def _op_step(st, a, h0: float):
    vals = [1 if v > 0 else (0 if v < 0 else h0) for v in (a.a, a.b)]
    if _straddles(a, closed=True):
        st[0] = False
        vals.append(h0)
    return iv.mpf([min(vals), max(vals)])


def _op_maxmin(st, args, is_max: bool):
    lo = (max if is_max else min)(a.a for a in args)
    hi = (max if is_max else min)(a.b for a in args)
    # smooth only where one argument dominates the others on the whole box
    if is_max:
        top = max(range(len(args)), key=lambda k: args[k].a)
        if not all(args[top].a > args[k].b for k in range(len(args)) if k != top):
            st[0] = False
    else:
        top = min(range(len(args)), key=lambda k: args[k].b)
        if not all(args[top].b < args[k].a for k in range(len(args)) if k != top):
            st[0] = False
    return iv.mpf([lo, hi])


def _op_piecewise(st, args, branches):
    acc, decided = None, False
    for start, op in branches:
        if op is None:
            maybe = sure = True
        else:
            a, b = args[start + 1], args[start + 2]
            if op in ("<", "<="):
                a, b, op = b, a, (">" if op == "<" else ">=")
            if op == ">":
                maybe, sure = a.b > b.a, a.a > b.b
            else:
                maybe, sure = a.b >= b.a, a.a >= b.b
        if maybe:
            v = args[start]
            acc = v if acc is None else _hull(acc, v)
            if not sure:
                st[0] = False
        if sure:
            decided = True
            break
    if acc is None or not decided:
        raise CheckError("Piecewise without a branch for part of a box")
    return acc


def _ipow(base, n: int):
    """base**n for an integer n, even powers through |base| (tight), negative powers as the reciprocal with
    half-lines where 0 is an end point (as the prover's), the whole line where 0 is inside."""
    if n < 0:
        p = _ipow(base, -n)
        if p.a > 0 or p.b < 0:
            return 1 / p
        if p.a == 0 and p.b > 0:
            return iv.mpf([(1 / iv.mpf([p.b, p.b])).a, "inf"])
        if p.b == 0 and p.a < 0:
            return iv.mpf(["-inf", (1 / iv.mpf([p.a, p.a])).b])
        return iv.mpf(["-inf", "inf"])
    if n % 2 == 0:
        return abs(base) ** n
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
        """The goal and its gradient in one program (shared subexpressions): outputs g, dg/dx_1, ..."""
        if self._grad is None:
            self._grad = IvProgram([self.g, *[sp.diff(self.g, x) for x in self.coords]], self.coords)
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
        # differentiability is the goal's own (a non-smooth operation of g switching inside the box); its
        # derivative may hold sign(x) with x = 0 at an end point only, a valid enclosure of the interior
        (_,), smooth = self.prog.evaluate(box)
        if not smooth:
            return None, None
        out, _ = self.grad.evaluate(box)
        grads = out[1:]
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
            (_,), smooth = self.prog.evaluate(box)
            if not smooth:
                return "the goal is not differentiable on the box"
            out, _ = self.grad.evaluate(box)
            grads = out[1:]
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
