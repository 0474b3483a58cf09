"""Lemmas written for the plans of controller c000 (reviewed like the rest of :mod:`.lemmas`).

Each is a small, general fact: its proof re-checks identities symbolically, its text names the textbook
step; a claim-sized lemma does not belong here.
"""

from __future__ import annotations

import sympy as sp

from .lemmas import Lemma

_v = sp.Matrix(sp.symbols("v_1:4", real=True))
_norm_v = sp.sqrt((_v.T * _v)[0])


def _component_proof() -> bool:
    # |v|^2 - v_1^2 = v_2^2 + v_3^2: a sum of squares
    return sp.expand(_norm_v**2 - _v[0] ** 2 - (_v[1] ** 2 + _v[2] ** 2)) == 0


#: |v_1| <= |v| in R^3 (no premises)
NORM_GE_COMPONENT3 = Lemma(
    "norm_ge_component_3", tuple(_v), _norm_v - _v[0], (),
    "v_1 <= |v| for v in R^3: |v|^2 - v_1^2 = v_2^2 + v_3^2 >= 0 and |v| >= 0, so |v| >= |v_1| >= v_1",
    _component_proof)


_a, _k, _u = sp.symbols("a_c000 k_c000 u_c000", real=True)
_m = _norm_v - _v[0]


def _abs_multiple_proof() -> bool:
    # with a = k u m, k >= 0, m >= 0: |a| = k m |u| (checked with nonnegative stand-ins for k and m)
    kn, mn = sp.Symbol("k_n", nonnegative=True), sp.Symbol("m_n", nonnegative=True)
    factored = sp.Abs(kn * _u * mn) - kn * mn * sp.Abs(_u) == 0
    return bool(_component_proof() and factored)


#: |a| <= k (|v| - v_1) when a = k u (|v| - v_1), k >= 0, |u| <= 1
ABS_NORM_EXCESS3 = Lemma(
    "abs_le_norm_excess_3", (_a, _k, _u, *_v), _k * _m - sp.Abs(_a),
    (_k, 1 - sp.Abs(_u), _a - _k * _u * _m, _k * _u * _m - _a),
    "|a| <= k (|v| - v_1) for a = k u (|v| - v_1) (the last two premises), k >= 0 and |u| <= 1, v in R^3: "
    "m = |v| - v_1 >= 0 (norm_ge_component_3: |v|^2 - v_1^2 = v_2^2 + v_3^2), so |a| = |k u m| = k m |u| "
    "<= k m, a product of nonnegative factors times |u| <= 1",
    _abs_multiple_proof)

LEMMAS: tuple = (NORM_GE_COMPONENT3, ABS_NORM_EXCESS3)
