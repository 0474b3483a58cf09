"""Proved lemmas for proofs by composition: the norm steps the papers use, each with its own proof.

A :class:`Lemma` is ``gap >= 0`` for every real value of its symbols where each premise is >= 0 (> 0 for
the strict ones).  Its ``proof`` is re-run whenever a certificate that uses it is checked; each proof is a
short chain of exact SymPy identities plus a textbook step named in ``text`` (a square is >= 0;
for a, b >= 0, a**2 >= b**2 implies a >= b).  A plan uses a lemma through :class:`~.plan.Use`, which maps
the lemma's symbols to expressions of the statement's.
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

LIBRARY: dict[str, Lemma] = {lem.name: lem for lem in (YOUNG, ABS_PRODUCT, CAUCHY_SCHWARZ3, NORM2_LE_NORM1,
                                                       DOT_BALL3)}


def vector_mapping(lemma: Lemma, **vectors) -> dict:
    """Mapping helper: ``vector_mapping(CAUCHY_SCHWARZ3, x=s, y=d)`` maps x_1..3, y_1..3 to the entries."""
    out = {}
    for name, vec in vectors.items():
        syms = [s for s in lemma.symbols if s.name.startswith(f"{name}_")]
        if len(syms) != len(vec):
            raise ValueError(f"lemma {lemma.name}: {name} has {len(syms)} entries, got {len(vec)}")
        out.update(dict(zip(syms, list(vec), strict=True)))
    return out
