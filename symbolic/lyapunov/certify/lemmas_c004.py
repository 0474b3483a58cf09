"""Lemmas written for the plans of controller c004 (reviewed like the rest of :mod:`.lemmas`).

Each is a small, general fact: its proof re-checks identities symbolically, its text names the textbook
step; a claim-sized lemma does not belong here.

They are the norm steps of paper 004's bounds ||m n1|| <= rho_m ||p_t|| ||w~||^2 and ||J n2|| <= rho_J
||w~||^2 (under eq. 27 and eq. 36): norms of matrix-vector products peeled one factor at a time.  Each
carries a scalar factor ``k`` (a norm step multiplied by k >= 0) so that a chain of them telescopes with
unit weights, and each writes its products with generic 3x3 symbol matrices, so that a plan can map them
onto the factors of the claim's own product (the matrices a claim builds, left to right) and the terms of
consecutive steps are the same expressions.  Equalities (orthogonality, a spectral factorisation, a skew
matrix) are premises written as pairs ``e >= 0``, ``-e >= 0``.
"""

from __future__ import annotations

import sympy as sp

from ...physics.rotations import dot, skew
from .lemmas import Lemma

_PRE = "c4"        # lemma symbols carry this prefix (no clash with a statement's names)


def _r(name: str) -> sp.Symbol:
    return sp.Symbol(f"{_PRE}{name}", real=True)


def _vec(name: str) -> sp.Matrix:
    return sp.Matrix([_r(f"{name}_{i}") for i in range(1, 4)])


def _mat(name: str) -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: _r(f"{name}_{i + 1}{j + 1}"))


def _norm(v: sp.Matrix) -> sp.Expr:
    return sp.sqrt(dot(v, v))


def _zero(e) -> bool:
    return sp.expand(e) == 0


def _pair(E: sp.Matrix, symmetric: bool) -> tuple:
    """E = 0 as premises e >= 0 and -e >= 0 per entry (upper triangle when E is symmetric)."""
    out = []
    for i in range(3):
        for j in range(i if symmetric else 0, 3):
            out += [E[i, j], -E[i, j]]
    return tuple(out)


K = _r("k")
X = _vec("x")
Y = _vec("y")
A = _mat("A")
B = _mat("B")
M = _mat("M")
Q = _mat("Q")
D = _vec("d")
LAM = _r("lambda")
I3 = sp.eye(3)

# --------------------------------------------------------------------------- k |y| = |k y| for k >= 0

def _hom_proof() -> bool:
    kp = sp.Symbol("kp", positive=True)
    sq = _zero(dot(K * Y, K * Y) - K**2 * dot(Y, Y))
    root = sp.sqrt(kp**2 * dot(Y, Y)) == kp * sp.sqrt(dot(Y, Y))
    return bool(sq and root)


NORM_HOMOGENEOUS = Lemma(
    "c004_norm_homogeneous", (K, *Y), K * _norm(Y) - _norm(K * Y), (K,),
    "|k y| = k |y| for k >= 0 (y in R^3): |k y|^2 = k^2 |y|^2 (expanded), and sqrt(k^2 Y) = k sqrt(Y) for "
    "k >= 0, Y >= 0",
    _hom_proof)

# --------------------------------------------------------------------------- |(A B) x| = |A (B x)|

ASSOC_NORM = Lemma(
    "c004_assoc_norm", (K, *A, *B, *X), K * _norm(A * (B * X)) - K * _norm((A * B) * X), (),
    "k |A (B x)| - k |(A B) x| = 0 for 3x3 matrices A, B, x in R^3, any k: matrix products are associative "
    "(A (B x) - (A B) x expands to 0), so both norms are of the same vector",
    lambda: all(_zero(e) for e in A * (B * X) - (A * B) * X))

# --------------------------------------------------------------------------- |M x| = |x| for M^T M = I

_E_M = M.T * M - I3

ORTHOGONAL_NORM = Lemma(
    "c004_orthogonal_norm", (K, *M, *X), K * _norm(X) - K * _norm(M * X), _pair(_E_M, True),
    "k |x| - k |M x| = 0 for M^T M = I (premises: each entry of M^T M - I is >= 0 and <= 0), any k: "
    "|x|^2 - |M x|^2 = -x^T (M^T M - I) x (an identity), which is 0, so the two norms are equal",
    lambda: _zero(dot(X, X) - dot(M * X, M * X) + (X.T * _E_M * X)[0, 0]))

# --------------------------------------------------------------------------- |a x b| <= |a| |b|

_AV = _vec("a")

SKEW_NORM = Lemma(
    "c004_skew_norm", (K, *_AV, *B, *X), K * _norm(_AV) * _norm(X) - K * _norm(B * X),
    (K, *_pair(B - skew(_AV), False)),
    "k |B x| <= k |a| |x| for B = S(a) (the cross-product matrix; premises: each entry of B - S(a) is >= 0 "
    "and <= 0) and k >= 0: Lagrange's identity |a|^2 |x|^2 - |a x x|^2 = (a . x)^2 >= 0 (checked), both "
    "norms >= 0, so |a x x| <= |a| |x|",
    lambda: _zero(dot(_AV, _AV) * dot(X, X) - dot(skew(_AV) * X, skew(_AV) * X) - dot(_AV, X) ** 2))

# --------------------------------------------------------------------------- |M x| <= lambda |x| for M = Q D Q^T

_DM = sp.diag(*D)
_E_Q = Q.T * Q - I3
_F_Q = Q * Q.T - I3
_QDQ = Q * _DM * Q.T


def _spectral_proof() -> bool:
    qx = Q.T * X
    lhs = LAM**2 * dot(X, X) - dot(_QDQ * X, _QDQ * X)
    rhs = (LAM**2 * (X.T * (-_F_Q) * X)[0, 0] + sum((LAM**2 - D[i] ** 2) * qx[i] ** 2 for i in range(3))
           - (qx.T * _DM * _E_Q * _DM * qx)[0, 0])
    return _zero(lhs - rhs)


SPECTRAL_NORM = Lemma(
    "c004_spectral_norm", (K, LAM, *M, *Q, *D, *X), K * LAM * _norm(X) - K * _norm(M * X),
    (K, *[LAM - d for d in D], *[LAM + d for d in D], *_pair(M - _QDQ, False), *_pair(_E_Q, True),
     *_pair(_F_Q, True)),
    "k |M x| <= k lambda |x| for M = Q diag(d) Q^T with Q^T Q = Q Q^T = I, |d_i| <= lambda (premises "
    "lambda - d_i >= 0, lambda + d_i >= 0; the equalities as pairs of inequalities) and k >= 0: with y = Q^T x, "
    "lambda^2 |x|^2 - |Q D Q^T x|^2 = lambda^2 x^T (I - Q Q^T) x + sum_i (lambda^2 - d_i^2) y_i^2 "
    "- y^T D (Q^T Q - I) D y (an identity, checked); under the premises it is sum_i (lambda - d_i)(lambda + "
    "d_i) y_i^2 >= 0, and lambda >= 0, so |M x| <= lambda |x|",
    _spectral_proof)

# --------------------------------------------------------------------------- k p (q + z) = k p q + k p z

P = _r("p")
QS = _r("q")
Z = _r("z")
_DIST_GAP = K * P * (QS + Z) - K * P * QS - K * P * Z

DISTRIBUTE = Lemma(
    "c004_distribute", (K, P, QS, Z), _DIST_GAP, (),
    "k p (q + z) - k p q - k p z = 0 >= 0 for all reals (distributivity, expanded to 0).  A plan uses it to "
    "split one summand z out of a product k p (q + z) of a Lie derivative as the claim writes it, so that the "
    "split term cancels exactly against the same expression in another lemma's instance",
    lambda: _zero(_DIST_GAP))

# --------------------------------------------------------------------------- k l |y| = k |l y| for k, l >= 0

L_ = _r("l")


def _scale_proof() -> bool:
    lp = sp.Symbol("lp", positive=True)
    sq = _zero(dot(L_ * Y, L_ * Y) - L_**2 * dot(Y, Y))
    root = sp.sqrt(lp**2 * dot(Y, Y)) == lp * sp.sqrt(dot(Y, Y))
    return bool(sq and root)


NORM_SCALE = Lemma(
    "c004_norm_scale", (K, L_, *Y), K * L_ * _norm(Y) - K * _norm(L_ * Y), (K, L_),
    "k l |y| - k |l y| = 0 for k, l >= 0 (y in R^3): |l y|^2 = l^2 |y|^2 (expanded), and sqrt(l^2 Y) = "
    "l sqrt(Y) for l >= 0, Y >= 0; then times k",
    _scale_proof)

LEMMAS: tuple = (NORM_HOMOGENEOUS, ASSOC_NORM, ORTHOGONAL_NORM, SKEW_NORM, SPECTRAL_NORM, DISTRIBUTE, NORM_SCALE)

# --------------------------------------------------------------------------- p^T B x = s^T x for p = A s, A^T B = I

S_ = _vec("s")
PV = _vec("pv")
_E_AB = A.T * B - I3
_PAIR_GAP = dot(S_, X) - dot(PV, B * X)

INVERSE_PAIRING = Lemma(
    "c004_inverse_pairing", (*S_, *X, *PV, *A, *B), _PAIR_GAP,
    (*[e for i in range(3) for e in (PV[i] - (A * S_)[i], -(PV[i] - (A * S_)[i]))], *_pair(_E_AB, False)),
    "s^T x - p^T B x = 0 for p = A s and A^T B = I (3x3 matrices; premises: each entry of p - A s and of "
    "A^T B - I is >= 0 and <= 0): s^T x - p^T B x = -(p - A s)^T B x - s^T (A^T B - I) x (an identity, "
    "checked), which is 0 under the premises.  With A = J, B = J^-1 it turns (J s)^T J^-1 x into s^T x",
    lambda: _zero(_PAIR_GAP + dot(PV - A * S_, B * X) + (S_.T * _E_AB * X)[0, 0]))

LEMMAS = (*LEMMAS, INVERSE_PAIRING)
