"""Proved lemmas for proofs by composition: the norm steps the papers use, each with its own proof.

A :class:`Lemma` is ``gap >= 0`` for every real value of its symbols where each premise is >= 0 (> 0 for
the strict ones).  Its ``proof`` is re-run whenever a certificate that uses it is checked; each proof is a
short chain of exact SymPy identities plus a textbook step named in ``text`` (a square is >= 0;
for a, b >= 0, a**2 >= b**2 implies a >= b).  A plan uses a lemma through :class:`~.plan.Use`, which maps
the lemma's symbols to expressions of the statement's.

This library is the trusted base of the certificates: a lemma's proof is code that checks identities, and
the textbook step that turns them into ``gap >= 0`` is in its text.  So every lemma is small, general and
reviewed here, and the checker refuses a lemma that is not in :data:`.library.LIBRARY` (a claim-sized "lemma"
defined in a plan would carry its proof unchecked).  The one other kind of lemma is a claim that is itself
certified (:mod:`.compose`), checked against its own certificate and domain.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Lemma:
    name: str
    symbols: tuple[sp.Symbol, ...]
    gap: sp.Expr                                  # >= 0 under the premises
    premises: tuple[sp.Expr, ...]                 # each >= 0 (see ``strict``)
    text: str                                     # the statement and its proof in words
    proof: Callable[[], bool]                     # the symbolic steps, re-checked
    strict: tuple[bool, ...] = ()                 # per premise: must be > 0 (default: >= 0)

    def verify(self) -> bool:
        return bool(self.proof())

    def strict_premise(self, k: int) -> bool:
        return bool(self.strict[k]) if k < len(self.strict) else False


def _zero(e: sp.Expr) -> bool:
    return sp.expand(e) == 0


def _r(names: str):
    return sp.symbols(names, real=True)


# --------------------------------------------------------------------------- Young

_a, _b, _e = _r("a b epsilon")

YOUNG = Lemma(
    "young", (_a, _b, _e), _a**2 / (2 * _e) + _e * _b**2 / 2 - _a * _b, (_e,),
    "a b <= a^2/(2 eps) + eps b^2/2 for eps > 0: 2 eps times the gap is (a - eps b)^2 >= 0",
    lambda: _zero(2 * _e * (_a**2 / (2 * _e) + _e * _b**2 / 2 - _a * _b) - (_a - _e * _b) ** 2),
    strict=(True,))

# --------------------------------------------------------------------------- |s| D >= s d when |d| <= D

_s, _d, _D = _r("s d D")

ABS_PRODUCT = Lemma(
    "abs_product", (_s, _d, _D), sp.Abs(_s) * _D - _s * _d, (_D - sp.Abs(_d),),
    "s d <= |s| D for |d| <= D: the gap is |s| (D - |d|) + (|s d| - s d), a product of two nonnegative "
    "factors plus a nonnegative difference",
    lambda: _zero(sp.Abs(_s) * _D - _s * _d - (sp.Abs(_s) * (_D - sp.Abs(_d)) + (sp.Abs(_s * _d) - _s * _d))
                  .subs(sp.Abs(_s * _d), sp.Abs(_s) * sp.Abs(_d))))

# --------------------------------------------------------------------------- Cauchy-Schwarz in R^3

_x = sp.Matrix(_r("x_1:4"))
_y = sp.Matrix(_r("y_1:4"))
_nx, _ny = sp.sqrt((_x.T * _x)[0]), sp.sqrt((_y.T * _y)[0])


def _lagrange() -> bool:
    lhs = (_x.T * _x)[0] * (_y.T * _y)[0] - (_x.T * _y)[0] ** 2
    rhs = sum((_x[i] * _y[j] - _x[j] * _y[i]) ** 2 for i in range(3) for j in range(i + 1, 3))
    return _zero(lhs - rhs)


CAUCHY_SCHWARZ3 = Lemma(
    "cauchy_schwarz_3", (*_x, *_y), _nx * _ny - (_x.T * _y)[0], (),
    "x . y <= |x| |y| in R^3: Lagrange's identity |x|^2 |y|^2 - (x . y)^2 = sum_{i<j} (x_i y_j - x_j y_i)^2 "
    ">= 0, and |x| |y| >= 0, so |x| |y| >= |x . y| >= x . y",
    _lagrange)

# --------------------------------------------------------------------------- |x|_2 <= |x|_1 in R^3

_norm1 = sum(sp.Abs(v) for v in _x)

NORM2_LE_NORM1 = Lemma(
    "norm2_le_norm1_3", tuple(_x), _norm1 - _nx, (),
    "|x|_2 <= |x|_1 in R^3: |x|_1^2 - |x|_2^2 = 2 sum_{i<j} |x_i| |x_j| >= 0, both norms >= 0",
    lambda: _zero((_norm1**2 - (_x.T * _x)[0]).subs({sp.Abs(v)**2: v**2 for v in _x})
                  - 2 * sum(sp.Abs(_x[i]) * sp.Abs(_x[j]) for i in range(3) for j in range(i + 1, 3))))

# --------------------------------------------------------------------------- s . d <= |s| rho for |d| <= rho

_rho = sp.Symbol("rho", real=True)

DOT_BALL3 = Lemma(
    "dot_ball_3", (*_x, *_y, _rho), _nx * _rho - (_x.T * _y)[0], (_rho**2 - (_y.T * _y)[0], _rho),
    "x . y <= |x| rho for |y| <= rho (rho >= 0): Cauchy-Schwarz, then |y| <= rho (both >= 0)",
    _lagrange)

# --------------------------------------------------------------------------- a 2x2 quadratic form, LDL^T

_p, _u, _v, _xx, _yy = _r("p u v x y")
_ldl_gap = _p * _xx**2 + 2 * _p * _u * _xx * _yy + (_p * _u**2 + _v) * _yy**2

LDL2 = Lemma(
    "ldl_2", (_p, _u, _v, _xx, _yy), _ldl_gap, (_p, _v),
    "p x^2 + 2 p u x y + (p u^2 + v) y^2 >= 0 for p, v >= 0: it is p (x + u y)^2 + v y^2 (the LDL^T "
    "factorisation of a 2x2 quadratic form), a sum of nonnegative terms",
    lambda: _zero(_ldl_gap - (_p * (_xx + _u * _yy) ** 2 + _v * _yy**2)))


# --------------------------------------------------------------------------- reaching the boundary layer

def _layer_lemma() -> Lemma:
    """The per-axis step of paper 000's eqs. 68-72: for the code's layer S = max(s - d, 0) + min(s + d, 0)
    (``c000.boundary_layer_surface``), d >= 0, |delta| <= D and eps >= 0:
    (delta - (D + eps) sign(s)) S <= -eps |S|."""
    from ...controllers import c000

    s, d, delta, D, eps = _r("s d delta D epsilon")
    S = c000.boundary_layer_surface(s, d)
    gap = -eps * sp.Abs(S) - (delta - (D + eps) * sp.sign(s)) * S

    def proof() -> bool:
        # three cases that cover every s for d >= 0: s = d + v (v > 0), s = -d - v (v > 0), and
        # |s| <= d as d = (p + q)/2, s = (q - p)/2 with p = d - s >= 0, q = d + s >= 0
        v = sp.Symbol("v", positive=True)
        dn, p, q = (sp.Symbol(n, nonnegative=True) for n in ("d_n", "p", "q"))
        outside_pos = gap.xreplace({d: dn}).xreplace({s: dn + v}) - (D - delta) * v
        outside_neg = gap.xreplace({d: dn}).xreplace({s: -dn - v}) - (D + delta) * v
        inside = gap.xreplace({d: (p + q) / 2, s: (q - p) / 2})
        return all(sp.expand(e) == 0 for e in (outside_pos, outside_neg, inside))

    return Lemma("boundary_layer_reaching", (s, d, delta, D, eps), gap, (D - delta, D + delta, eps, d),
                 "(delta - (D + eps) sign(s)) S_aug <= -eps |S_aug| for |delta| <= D, eps >= 0, S_aug = "
                 "max(s - d, 0) + min(s + d, 0), d >= 0: for s > d the gap is (D - delta)(s - d), for s < -d it is "
                 "(D + delta)(-d - s), inside |s| <= d S_aug = 0 (each case an exact SymPy identity), products "
                 "of nonnegative factors", proof)


LAYER = _layer_lemma()

# --------------------------------------------------------------------------- paper 002's Lemma 1 and companions
# (written for the V2/V3 claims of controller c002; each is a general fact with its own proof)

DELTA_002 = sp.Rational(2785, 10000)     # Lemma 1's delta (mu = 1); the same as c002/common.py's DELTA


def _sym(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)



_xs, _ys = _sym("x"), _sym("y")


def _lemma1_proof() -> bool:
    """The steps of :data:`LEMMA1_002` (see its text)."""
    gap = DELTA_002 - sp.Abs(_xs) + _xs * sp.tanh(_xs)
    t, u = sp.Symbol("t", positive=True), sp.Symbol("u", real=True)
    even = sp.expand(gap.xreplace({_xs: -_xs}) - gap) == 0
    # t >= 0: delta - t + t tanh t = (delta (e^{2t} + 1) - 2t) / (e^{2t} + 1)
    form = (DELTA_002 * (sp.exp(2 * t) + 1) - 2 * t) / (sp.exp(2 * t) + 1)
    ident = sp.simplify((gap.xreplace({_xs: t}) - form).rewrite(sp.exp)) == 0
    # e^u >= T_10(u) for u >= 0, and p(u) = delta (1 + T_10(u)) - u has no real root and p(0) > 0
    p = sp.Poly(DELTA_002 * (1 + sum(u**k / sp.factorial(k) for k in range(11))) - u, u)
    poly = p.count_roots() == 0 and p.eval(0) > 0
    return bool(even and ident and poly)


LEMMA1_002 = Lemma(
    "lemma1_scalar", (_xs,), DELTA_002 - sp.Abs(_xs) + _xs * sp.tanh(_xs), (),
    "Lemma 1 (mu = 1): |x| - x tanh(x) <= delta = 0.2785 for every real x.  The gap is even, and for "
    "t = |x| >= 0 it equals (delta (e^{2t} + 1) - 2t)/(e^{2t} + 1); with u = 2t, e^u >= T_10(u) (the "
    "degree-10 Taylor polynomial, all terms >= 0 for u >= 0), so the numerator is >= p(u) = delta (1 + "
    "T_10(u)) - u, a polynomial with rational coefficients that has no real root (Sturm count) and "
    "p(0) = 2 delta > 0.  (The maximum of t (1 - tanh t) is 0.27846 at t = 0.639.)",
    _lemma1_proof)

COSH_TANH = Lemma(
    "cosh_sq_tanh", (_xs, _ys), _ys * sp.cosh(_xs) ** 2 - _ys / (1 - sp.tanh(_xs) ** 2), (),
    "y cosh^2(x) - y/(1 - tanh^2(x)) = 0 >= 0 for all real x, y: cosh^2 (1 - tanh^2) = cosh^2 - sinh^2 = 1",
    lambda: sp.simplify((sp.cosh(_xs) ** 2 - 1 / (1 - sp.tanh(_xs) ** 2)).rewrite(sp.exp)) == 0)

# Theorem 1 ii's step outside Omega_2, on one axis: x = (k delta + y)/(k - p) >= k delta/(k - p) and
# |e| <= p give x (k tanh x - e) >= 0; here e = p w with |w| <= 1.
_ks, _ps, _ws = _sym("k"), _sym("p"), _sym("w")
_Xs = (_ks * DELTA_002 + _ys) / (_ks - _ps)


def _outside_proof() -> bool:
    if not LEMMA1_002.verify():
        return False
    gap = _Xs * (_ks * sp.tanh(_Xs) - _ps * _ws)
    parts = _ks * (DELTA_002 - _Xs + _Xs * sp.tanh(_Xs)) + _ps * _Xs * (1 - _ws) + _ys
    return sp.cancel(sp.expand(gap - parts)) == 0


OUTSIDE_002 = Lemma(
    "lemma1_outside", (_ys, _ws, _ks, _ps), _Xs * (_ks * sp.tanh(_Xs) - _ps * _ws),
    (_ys, 1 - sp.Abs(_ws), _ps, _ks - _ps),
    "x (k tanh x - p w) >= 0 for x = (k delta + y)/(k - p), y >= 0, |w| <= 1, p >= 0, k - p > 0: the gap "
    "is k (delta - x + x tanh x) + p x (1 - w) + y (exact, since (k - p) x - k delta = y), with k > 0, x > 0 "
    "(so |x| = x and the first bracket is Lemma 1, lemma1_scalar), p x (1 - w) >= 0 and y >= 0",
    _outside_proof, strict=(False, False, False, True))


_as, _bs, _cs = _sym("a"), _sym("b"), _sym("c")


def _triangle_proof() -> bool:
    n1 = sp.Abs(_as) + sp.Abs(_bs) + sp.Abs(_cs)
    sq = {sp.Abs(v) ** 2: v**2 for v in (_as, _bs, _cs)}
    cross = 2 * sum(sp.Abs(u) * sp.Abs(v) - u * v for u, v in ((_as, _bs), (_as, _cs), (_bs, _cs)))
    return sp.expand(sp.expand(n1**2).subs(sq) - (_as + _bs + _cs) ** 2 - cross) == 0


TRIANGLE3 = Lemma(
    "triangle_3", (_as, _bs, _cs), sp.Abs(_as) + sp.Abs(_bs) + sp.Abs(_cs) - sp.Abs(_as + _bs + _cs), (),
    "|a + b + c| <= |a| + |b| + |c|: (|a| + |b| + |c|)^2 - (a + b + c)^2 = 2 sum_{u<v} (|u| |v| - u v) >= 0 "
    "(|u| |v| = |u v| >= u v), and both sides are >= 0",
    _triangle_proof)

_Cs = _sym("C")


def _tanh_proof() -> bool:
    odd = sp.tanh(-_ys) + sp.tanh(_ys) == 0
    slope = sp.simplify((sp.diff(sp.tanh(_ys), _ys) - 1 / sp.cosh(_ys) ** 2).rewrite(sp.exp)) == 0
    return bool(odd and slope)


TANH_MONO = Lemma(
    "tanh_unit", (_Cs, _ys), sp.tanh(_Cs) - sp.Abs(sp.tanh(_Cs * _ys)), (_Cs, 1 - sp.Abs(_ys)),
    "|tanh(C y)| <= tanh(C) for C >= 0, |y| <= 1: tanh is odd and increasing (its derivative is "
    "1/cosh^2 > 0), so |tanh(C y)| = tanh(C |y|) <= tanh(C) as C |y| <= C",
    _tanh_proof)


def _min_proof() -> bool:
    y, t = _sym("y"), sp.Symbol("t", positive=True)
    return bool(sp.Min(y + t, y) == y and sp.Min(y, y + t) == y and sp.Min(_xs, y) == sp.Min(y, _xs))


MIN_LE = Lemma(
    "min_le", (_xs, _ys), _xs - sp.Min(_xs, _ys), (),
    "Min(x, y) <= x: Min(x, y) is y where x = y + t (t > 0) and x where y = x + t (t > 0), or x = y",
    _min_proof)




def vector_mapping(lemma: Lemma, **vectors) -> dict:
    """Mapping helper: ``vector_mapping(CAUCHY_SCHWARZ3, x=s, y=d)`` maps x_1..3, y_1..3 to the entries."""
    out = {}
    for name, vec in vectors.items():
        syms = [s for s in lemma.symbols if s.name.startswith(f"{name}_")]
        if len(syms) != len(vec):
            raise ValueError(f"lemma {lemma.name}: {name} has {len(syms)} entries, got {len(vec)}")
        out.update(dict(zip(syms, list(vec), strict=True)))
    return out
