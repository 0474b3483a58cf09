"""Rigorous interval enclosures of SymPy expressions over many boxes at once (NumPy, outward rounding).

The prover's engine.  An expression is compiled once into a straight-line program (common subexpressions
shared); the program then maps arrays of boxes, ``lo`` and ``hi`` of shape (n_boxes, n_vars), to the
enclosure ``[lo_f, hi_f]`` of the expression's range over each box.

Soundness rests on three facts:

* IEEE 754 ``+ - * / sqrt`` are correctly rounded (error <= 1/2 ulp), so widening each result by one ulp
  outward (``np.nextafter``) encloses the exact value; a result that is exact (its rounding error, computed
  by the error-free transformations TwoSum and TwoProduct, is 0) is kept as is, so that an expression that
  is exactly 0 at a point (an equilibrium, a domain's edge) encloses to exactly [0, 0] there;
* the library functions (``tanh``, ``exp``, ``log``, ``cosh``) are not correctly rounded but are within a
  few ulps; their results are widened by :data:`LIBM_REL` relative plus :data:`TINY` absolute, far more;
* each operation is evaluated by its monotonicity on the argument's interval (``x**2`` over [-1, 2] is
  [0, 4], not [-2, 4]); constants that are not exactly representable become one-ulp intervals.

Besides the enclosure, :meth:`Program.evaluate` reports per box whether every *non-smooth* operation
(``Abs``, ``sign``, ``Max``/``Min``, steps, ``Piecewise``) has an argument that does not straddle its
switching point: only there is the expression differentiable on the whole box and a mean-value form
valid.  A step function (``Step``, ``Heaviside``, ``sign``) is discontinuous; its SymPy derivative is 0
or a Dirac delta, so the mean-value form must never be used across it.

An operation that is undefined somewhere on a box (``sqrt`` of a negative, ``1/x`` across 0) gives the
whole real line there, never NaN: the prover then cannot conclude on that box and splits it.

The independent re-check (:mod:`.recheck`) walks the same SymPy expressions with arb balls
(``python-flint``); it shares no code with this module.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ...physics.special import Fmax, Step

INF = np.inf
LIBM_REL = 1e-13       # relative widening of libm results (their error is a few ulps, ~1e-15)
TINY = 1e-300          # absolute widening of libm results (covers denormal and zero results)


def down(x: np.ndarray) -> np.ndarray:
    return np.nextafter(x, -INF)


def up(x: np.ndarray) -> np.ndarray:
    return np.nextafter(x, INF)


def _libm(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return lo - np.abs(lo) * LIBM_REL - TINY, hi + np.abs(hi) * LIBM_REL + TINY


def _clean(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """NaN bounds (inf - inf, 0 * inf) become the whole line."""
    return np.where(np.isnan(lo), -INF, lo), np.where(np.isnan(hi), INF, hi)


# --------------------------------------------------------------------------- elementary interval operations

def _add_rounded(x: np.ndarray, y: np.ndarray, rounding) -> np.ndarray:
    """x + y rounded outward, left as is when the sum is exact (Knuth's TwoSum error is 0), so that an
    enclosure of an expression that is exactly 0 at a point can be exactly [0, 0] there."""
    with np.errstate(invalid="ignore", over="ignore"):
        s = x + y
        bb = s - x
        err = (x - (s - bb)) + (y - bb)
    exact = (err == 0) & np.isfinite(s)
    return np.where(exact, s, rounding(s))


_SPLIT = 134217729.0        # 2**27 + 1, Veltkamp's splitter for float64


def _mul_rounded(x: np.ndarray, y: np.ndarray, rounding) -> np.ndarray:
    """x * y rounded outward, left as is when the product is exact (Dekker's TwoProduct error is 0)."""
    with np.errstate(invalid="ignore", over="ignore"):
        p = x * y
        cx, cy = _SPLIT * x, _SPLIT * y
        xh, yh = cx - (cx - x), cy - (cy - y)
        xl, yl = x - xh, y - yh
        err = ((xh * yh - p) + xh * yl + xl * yh) + xl * yl
    exact = (err == 0) & np.isfinite(p) & (np.abs(x) < 1e150) & (np.abs(y) < 1e150) & \
        ((p == 0) | (np.abs(p) > 1e-290))
    return np.where(exact, p, rounding(p))


def i_add(a, b):
    return _add_rounded(a[0], b[0], down), _add_rounded(a[1], b[1], up)


def i_neg(a):
    return -a[1], -a[0]


def i_mul(a, b):
    (alo, ahi), (blo, bhi) = a, b
    lows = [_mul_rounded(u, v, down) for u, v in ((alo, blo), (alo, bhi), (ahi, blo), (ahi, bhi))]
    highs = [_mul_rounded(u, v, up) for u, v in ((alo, blo), (alo, bhi), (ahi, blo), (ahi, bhi))]
    # 0 * inf is NaN in IEEE; as a product of bounds (an infinite bound means 'unbounded') it is 0 when
    # the zero is an end point, and the other products bound the rest
    lo = np.min(np.stack([np.where(np.isnan(v), 0.0, v) for v in lows]), axis=0)
    hi = np.max(np.stack([np.where(np.isnan(v), 0.0, v) for v in highs]), axis=0)
    return lo, hi


def i_scale(c: float, exact: bool, a):
    """c * a for a float constant c (exact: c is the exact value, else c is within one ulp of it)."""
    if exact:
        lo, hi = (a[0], a[1]) if c >= 0 else (a[1], a[0])
        cc = np.full_like(lo, c)
        return _mul_rounded(cc, lo, down), _mul_rounded(cc, hi, up)
    return i_mul((np.full_like(a[0], down(np.float64(c))), np.full_like(a[0], up(np.float64(c)))), a)


def _pow_nonneg(x: np.ndarray, n: int, rounding) -> np.ndarray:
    """x**n for x >= 0 by repeated multiplication, each product rounded in one direction."""
    out = np.ones_like(x)
    for _ in range(n):
        out = _mul_rounded(out, x, rounding)
    return out


def i_pow_int(a, n: int):
    """a**n, n a nonzero integer (negative: the reciprocal)."""
    if n < 0:
        return i_recip(i_pow_int(a, -n))
    lo, hi = a
    if n % 2 == 1:
        # odd: monotone increasing; sign-split so each bound's magnitude is rounded outward
        plo = np.where(lo >= 0, _pow_nonneg(np.abs(lo), n, down), -_pow_nonneg(np.abs(lo), n, up))
        phi = np.where(hi >= 0, _pow_nonneg(np.abs(hi), n, up), -_pow_nonneg(np.abs(hi), n, down))
        return plo, phi
    mag_lo = np.where(lo >= 0, lo, np.where(hi <= 0, -hi, 0.0))
    mag_hi = np.maximum(np.abs(lo), np.abs(hi))
    return _pow_nonneg(mag_lo, n, down), _pow_nonneg(mag_hi, n, up)


def i_recip(a):
    """1/a: the whole line where a contains 0 inside; half-lines where 0 is an end point."""
    lo, hi = a
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        q_lo, q_hi = 1.0 / hi, 1.0 / lo
        # exact quotients (q * x == 1 exactly) kept, the others rounded outward
        rlo = np.where((_mul_rounded(q_lo, hi, down) == 1.0) & (_mul_rounded(q_lo, hi, up) == 1.0), q_lo, down(q_lo))
        rhi = np.where((_mul_rounded(q_hi, lo, down) == 1.0) & (_mul_rounded(q_hi, lo, up) == 1.0), q_hi, up(q_hi))
    pos_from_zero = (lo == 0) & (hi > 0)          # [0, hi]: [1/hi, inf)
    neg_to_zero = (hi == 0) & (lo < 0)            # [lo, 0]: (-inf, 1/lo]
    across = (lo < 0) & (hi > 0) | ((lo == 0) & (hi == 0))
    rhi = np.where(pos_from_zero | across, INF, rhi)
    rlo = np.where(neg_to_zero | across, -INF, rlo)
    return rlo, rhi


def i_sqrt(a):
    lo, hi = a
    with np.errstate(invalid="ignore"):
        r_lo, r_hi = np.sqrt(np.maximum(lo, 0.0)), np.sqrt(np.maximum(hi, 0.0))
        # exact roots (r * r == x exactly, checked by TwoProduct) are kept, the others rounded outward
        slo = np.where((_mul_rounded(r_lo, r_lo, down) == lo) & (_mul_rounded(r_lo, r_lo, up) == lo), r_lo, down(r_lo))
        shi = np.where((_mul_rounded(r_hi, r_hi, down) == hi) & (_mul_rounded(r_hi, r_hi, up) == hi), r_hi, up(r_hi))
    slo = np.maximum(slo, 0.0)
    bad = lo < 0          # undefined on part of the box: no conclusion there
    return np.where(bad, -INF, slo), np.where(bad, INF, shi)


def i_monotone(f, a, increasing: bool = True, clamp: tuple[float, float] | None = None):
    with np.errstate(all="ignore"):
        flo, fhi = (f(a[0]), f(a[1])) if increasing else (f(a[1]), f(a[0]))
    flo, fhi = _libm(flo, fhi)
    if clamp is not None:
        flo, fhi = np.maximum(flo, clamp[0]), np.minimum(fhi, clamp[1])
    return _clean(flo, fhi)


def i_cosh(a):
    lo, hi = a
    with np.errstate(over="ignore"):
        clo = np.where(lo > 0, np.cosh(lo), np.where(hi < 0, np.cosh(hi), 1.0))
        chi = np.maximum(np.cosh(lo), np.cosh(hi))
    clo, chi = _libm(clo, chi)
    return np.maximum(clo, 1.0), chi


def i_log(a):
    lo, hi = a
    with np.errstate(divide="ignore", invalid="ignore"):
        r = i_monotone(np.log, (np.maximum(lo, 0.0), hi))
    bad = lo <= 0
    return np.where(bad, -INF, r[0]), np.where(bad, INF, r[1])


def i_abs(a):
    lo, hi = a
    alo = np.where(lo >= 0, lo, np.where(hi <= 0, -hi, 0.0))
    return alo, np.maximum(np.abs(lo), np.abs(hi))


def i_sign(a):
    return np.sign(a[0]), np.sign(a[1])


def i_step(a, at_zero: float):
    def h(x):
        return np.where(x > 0, 1.0, np.where(x < 0, 0.0, at_zero))
    lo, hi = a
    # monotone nondecreasing, except that the value at 0 may exceed the value just right of 0 for
    # at_zero > 1 (never here); take the hull of the three candidates to be safe
    vals = np.stack([h(lo), h(hi), np.where((lo <= 0) & (hi >= 0), at_zero, h(lo))])
    return vals.min(axis=0), vals.max(axis=0)


def i_max(args):
    return np.max(np.stack([a[0] for a in args]), axis=0), np.max(np.stack([a[1] for a in args]), axis=0)


def i_min(args):
    return np.min(np.stack([a[0] for a in args]), axis=0), np.min(np.stack([a[1] for a in args]), axis=0)


def i_sin_cos(a, cos: bool):
    """Crude but sound: the hull of the end values, widened to [-1, 1] where an extremum may lie inside."""
    lo, hi = a
    f = np.cos if cos else np.sin
    flo, fhi = np.minimum(f(lo), f(hi)), np.maximum(f(lo), f(hi))
    shift = 0.0 if cos else np.pi / 2          # maxima of cos at 2k pi, of sin at pi/2 + 2k pi
    k_max = np.ceil((lo - shift) / (2 * np.pi) - 1e-12)
    has_max = k_max * 2 * np.pi + shift <= hi + 1e-12
    k_min = np.ceil((lo - shift - np.pi) / (2 * np.pi) - 1e-12)
    has_min = k_min * 2 * np.pi + shift + np.pi <= hi + 1e-12
    flo, fhi = _libm(flo, fhi)
    return np.where(has_min, -1.0, np.maximum(flo, -1.0)), np.where(has_max, 1.0, np.minimum(fhi, 1.0))


# --------------------------------------------------------------------------- constants

def constant(c: sp.Expr) -> tuple[float, float, bool]:
    """(lo, hi, exact) floats enclosing the SymPy number ``c``."""
    if c.is_Rational:
        v = float(c)
        if sp.Rational(v) == c:
            return v, v, True
        return float(down(np.float64(v))), float(up(np.float64(v))), False
    if c.is_Float:
        v = float(c)
        if sp.Rational(v) == sp.Rational(c):
            return v, v, True
        return float(down(np.float64(v))), float(up(np.float64(v))), False
    # pi, E, sqrt(2), ...: 30 digits, then one ulp each side
    v = float(sp.N(c, 30))
    return float(down(down(np.float64(v)))), float(up(up(np.float64(v)))), False


# --------------------------------------------------------------------------- compilation

#: one-argument functions and the program's operation for each
UNARY = {sp.exp: "exp", sp.log: "log", sp.tanh: "tanh", sp.cosh: "cosh", sp.sin: "sin", sp.cos: "cos",
         sp.atan: "atan", sp.Abs: "abs", sp.sign: "sign"}

NONSMOOTH = (sp.Abs, sp.sign, sp.Heaviside, Step, sp.Max, sp.Min, Fmax, sp.Piecewise)


class Unsupported(Exception):
    """An operation the interval engine has no enclosure for (the prover reports 'cannot certify')."""


@dataclass
class Program:
    """A compiled list of expressions over ``variables``; see :func:`compile_exprs`."""

    variables: tuple[sp.Symbol, ...]
    ops: list[tuple]            # (kind, out slot, *operands)
    outputs: list[int]          # slot of each expression
    n_slots: int

    def evaluate(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Enclosures of every output over each box: (lo, hi) of shape (n_out, n_boxes) and ``smooth``
        (n_boxes,): True where no non-smooth operation's argument straddles its switching point."""
        n = lo.shape[0]
        slots: list = [None] * self.n_slots
        smooth = np.ones(n, dtype=bool)
        for j in range(len(self.variables)):
            slots[j] = (lo[:, j], hi[:, j])
        for op in self.ops:
            kind, out = op[0], op[1]
            if kind == "const":
                slots[out] = (np.full(n, op[2]), np.full(n, op[3]))
            elif kind == "add":
                acc = slots[op[2][0]]
                for k in op[2][1:]:
                    acc = i_add(acc, slots[k])
                slots[out] = acc
            elif kind == "mul":
                acc = slots[op[2][0]]
                for k in op[2][1:]:
                    acc = i_mul(acc, slots[k])
                slots[out] = acc
            elif kind == "scale":
                slots[out] = i_scale(op[2], op[3], slots[op[4]])
            elif kind == "neg":
                slots[out] = i_neg(slots[op[2]])
            elif kind == "powi":
                slots[out] = i_pow_int(slots[op[2]], op[3])
            elif kind == "sqrt":
                slots[out] = i_sqrt(slots[op[2]])
            elif kind == "recip":
                slots[out] = i_recip(slots[op[2]])
            elif kind == "tanh":
                slots[out] = i_monotone(np.tanh, slots[op[2]], clamp=(-1.0, 1.0))
            elif kind == "exp":
                slots[out] = i_monotone(np.exp, slots[op[2]], clamp=(0.0, INF))
            elif kind == "log":
                slots[out] = i_log(slots[op[2]])
            elif kind == "cosh":
                slots[out] = i_cosh(slots[op[2]])
            elif kind in ("sin", "cos"):
                slots[out] = i_sin_cos(slots[op[2]], kind == "cos")
            elif kind == "atan":
                slots[out] = i_monotone(np.arctan, slots[op[2]], clamp=(-np.pi / 2 - 1e-15, np.pi / 2 + 1e-15))
            else:
                # non-smooth operations: record where the box straddles the switching point
                if kind == "abs":
                    a = slots[op[2]]
                    slots[out] = i_abs(a)
                    smooth &= ~((a[0] < 0) & (a[1] > 0))
                elif kind == "sign":
                    a = slots[op[2]]
                    slots[out] = i_sign(a)
                    smooth &= ~((a[0] <= 0) & (a[1] >= 0))
                elif kind == "dirac":
                    a = slots[op[2]]
                    at = (a[0] <= 0) & (a[1] >= 0)
                    slots[out] = (np.where(at, -INF, 0.0), np.where(at, INF, 0.0))
                    smooth &= ~at
                elif kind == "step":
                    a = slots[op[2]]
                    slots[out] = i_step(a, op[3])
                    smooth &= ~((a[0] <= 0) & (a[1] >= 0))
                elif kind in ("max", "min"):
                    args = [slots[k] for k in op[2]]
                    slots[out] = i_max(args) if kind == "max" else i_min(args)
                    # smooth only where one argument dominates every other on the whole box
                    los, his = np.stack([a[0] for a in args]), np.stack([a[1] for a in args])
                    if kind == "max":
                        top = np.argmax(los, axis=0)
                        best_lo = np.take_along_axis(los, top[None], 0)[0]
                        others = np.where(np.arange(len(args))[:, None] == top[None], -INF, his).max(axis=0)
                        smooth &= best_lo > others
                    else:
                        top = np.argmin(his, axis=0)
                        best_hi = np.take_along_axis(his, top[None], 0)[0]
                        others = np.where(np.arange(len(args))[:, None] == top[None], INF, los).min(axis=0)
                        smooth &= best_hi < others
                elif kind == "piecewise":
                    # op[2]: list of (value slot, condition program (kind, a slot, b slot) or None)
                    los, his, certain_done = [], [], np.zeros(n, dtype=bool)
                    lo_acc, hi_acc = np.full(n, INF), np.full(n, -INF)
                    for vslot, cond in op[2]:
                        v = slots[vslot]
                        if cond is None:
                            maybe, sure = np.ones(n, bool), np.ones(n, bool)
                        else:
                            maybe, sure = _relation(cond[0], slots[cond[1]], slots[cond[2]])
                        take = maybe & ~certain_done
                        lo_acc = np.where(take, np.minimum(lo_acc, v[0]), lo_acc)
                        hi_acc = np.where(take, np.maximum(hi_acc, v[1]), hi_acc)
                        smooth &= ~(take & ~sure)        # a branch decided on part of the box only
                        certain_done |= sure
                    slots[out] = (lo_acc, hi_acc)
                else:
                    raise Unsupported(kind)
            lo_o, hi_o = slots[out]
            if lo_o.dtype != np.float64:
                slots[out] = (lo_o.astype(float), hi_o.astype(float))
        outs_lo = np.stack([slots[k][0] for k in self.outputs]) if self.outputs else np.zeros((0, n))
        outs_hi = np.stack([slots[k][1] for k in self.outputs]) if self.outputs else np.zeros((0, n))
        return outs_lo, outs_hi, smooth


def _relation(kind: str, a, b):
    """(maybe, surely) for ``a kind b`` over intervals, row-wise."""
    if kind in ("<", "<="):
        a, b = b, a
        kind = ">" if kind == "<" else ">="
    if kind == ">":
        return a[1] > b[0], a[0] > b[1]
    if kind == ">=":
        return a[1] >= b[0], a[0] >= b[1]
    raise Unsupported(f"relation {kind}")


def compile_exprs(exprs: Sequence[sp.Expr], variables: Sequence[sp.Symbol]) -> Program:
    """A :class:`Program` for ``exprs`` in ``variables`` (every free symbol must be one of them)."""
    variables = tuple(variables)
    index: dict = {v: i for i, v in enumerate(variables)}
    ops: list[tuple] = []
    n = [len(variables)]

    def new() -> int:
        n[0] += 1
        return n[0] - 1

    def emit(e) -> int:
        if e in index:
            return index[e]
        if e.is_Symbol:
            raise ValueError(f"symbol {e} is not a variable of the box")
        out = _emit(e)
        index[e] = out
        return out

    def _emit(e) -> int:
        if e.is_Number or e.is_NumberSymbol:
            lo, hi, _ = constant(e)
            k = new()
            ops.append(("const", k, lo, hi))
            return k
        if isinstance(e, sp.Add):
            args = [emit(a) for a in e.args]
            k = new()
            ops.append(("add", k, args))
            return k
        if isinstance(e, sp.Mul):
            coeff, rest = e.as_coeff_Mul()
            if coeff != 1 and coeff.is_Number:
                inner = emit(rest)
                k = new()
                if coeff == -1:
                    ops.append(("neg", k, inner))
                else:
                    lo, hi, exact = constant(coeff)
                    if exact:
                        ops.append(("scale", k, lo, True, inner))
                    else:
                        c = emit(coeff)
                        ops.append(("mul", k, [c, inner]))
                return k
            args = [emit(a) for a in e.args]
            k = new()
            ops.append(("mul", k, args))
            return k
        if isinstance(e, sp.Pow):
            b, x = e.args
            if x.is_Integer:
                inner = emit(b)
                k = new()
                if int(x) == -1:
                    ops.append(("recip", k, inner))
                else:
                    ops.append(("powi", k, inner, int(x)))
                return k
            if x.is_Rational and x.q == 2:
                root = _sqrt_slot(b)
                if x.p == 1:
                    return root
                k = new()
                ops.append(("powi", k, root, int(x.p)))
                return k
            # general power b**x = exp(x log b)
            return emit(sp.exp(x * sp.log(b)))
        if type(e) in UNARY:
            return _unary(UNARY[type(e)], e.args[0])
        if isinstance(e, sp.sinh):
            return emit((sp.exp(e.args[0]) - sp.exp(-e.args[0])) / 2)
        if isinstance(e, sp.Heaviside):
            h0 = e.args[1] if len(e.args) > 1 else sp.Rational(1, 2)
            inner = emit(e.args[0])
            k = new()
            ops.append(("step", k, inner, float(h0)))
            return k
        if isinstance(e, Step):
            inner = emit(e.args[0])
            k = new()
            ops.append(("step", k, inner, 1.0))
            return k
        if isinstance(e, sp.DiracDelta):
            # the derivative of a step: 0 away from its point, no bound where the box contains it
            inner = emit(e.args[0])
            k = new()
            ops.append(("dirac", k, inner))
            return k
        if isinstance(e, (sp.Max, Fmax)):
            args = [emit(a) for a in e.args]
            k = new()
            ops.append(("max", k, args))
            return k
        if isinstance(e, sp.Min):
            args = [emit(a) for a in e.args]
            k = new()
            ops.append(("min", k, args))
            return k
        if isinstance(e, sp.Piecewise):
            branches = []
            for val, cond in e.args:
                if cond is sp.true:
                    branches.append((emit(val), None))
                    break
                if not isinstance(cond, (sp.StrictLessThan, sp.LessThan, sp.StrictGreaterThan,
                                         sp.GreaterThan)):
                    raise Unsupported(f"Piecewise condition {cond}")
                branches.append((emit(val), (cond.rel_op, emit(cond.lhs), emit(cond.rhs))))
            k = new()
            ops.append(("piecewise", k, branches))
            return k
        raise Unsupported(f"{type(e).__name__}: {sp.sstr(e)[:80]}")

    def _sqrt_slot(b) -> int:
        key = ("sqrt", b)
        if key in index:
            return index[key]
        inner = emit(b)
        k = new()
        ops.append(("sqrt", k, inner))
        index[key] = k
        return k

    def _unary(kind, arg) -> int:
        inner = emit(arg)
        k = new()
        ops.append((kind, k, inner))
        return k

    outputs = [emit(sp.sympify(e)) for e in exprs]
    return Program(variables, ops, outputs, n[0])
