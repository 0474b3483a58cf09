"""Lemmas written for the plans of controller c001 (reviewed like the rest of :mod:`.lemmas`).

Each is a small, general fact: its proof re-checks identities symbolically, its text names the textbook
step; a claim-sized lemma does not belong here.

The two Rayleigh bounds give a 2x2 symmetric matrix's eigenvalues in the closed form the c001 claims print
(``(a + b)/2 -+ (((a - b)/2)^2 + c^2)^(1/2)``), so a plan can map ``a, b, c`` to the entries of P_i or Q_i
and the lemma's bound matches the statement's Min/Max arguments literally.
"""

from __future__ import annotations

import sympy as sp

from .lemmas import Lemma

_a, _b, _c, _x, _y = sp.symbols("a_c001 b_c001 c_c001 x_c001 y_c001", real=True)
_d = (_a - _b) / 2
_r = sp.sqrt(_d**2 + _c**2)
_lmin = (_a + _b) / 2 - _r
_lmax = (_a + _b) / 2 + _r
_form = _a * _x**2 + 2 * _c * _x * _y + _b * _y**2


def _zero(e: sp.Expr) -> bool:
    return sp.expand(e) == 0


def _rayleigh_proof(lam: sp.Expr, sign: int) -> bool:
    # G = sign (x^T P x - lam |x|^2) = p x^2 + 2 s c x y + q y^2 with p = sign (a - lam), q = sign (b - lam),
    # s = sign; the claims: p = r +- d, q = r -+ d (so p, q >= 0 as r >= |d|: r^2 - d^2 = c^2 >= 0),
    # p q = c^2, and p G = (p x + s c y)^2 + (p q - c^2) y^2 (so G >= 0 where p > 0; p = 0 forces c = 0
    # and G = q y^2)
    p, q = sign * (_a - lam), sign * (_b - lam)
    gap = sign * (_form - lam * (_x**2 + _y**2))
    pq = _zero(p * q - _c**2)
    p_r = _zero(p - (_r + sign * _d)) and _zero(q - (_r - sign * _d))
    r_ge = _zero(_r**2 - _d**2 - _c**2)
    ldl = _zero(p * gap - ((p * _x + sign * _c * _y) ** 2 + (p * q - _c**2) * _y**2))
    return bool(pq and p_r and r_ge and ldl)


_RAYLEIGH_TEXT = (
    "with d = (a - b)/2, r = (d^2 + c^2)^(1/2) >= |d| (r^2 - d^2 = c^2 >= 0): p = {p} and q = {q} are >= 0 "
    "and p q = r^2 - d^2 = c^2; the gap G = p x^2 {s} 2 c x y + q y^2 satisfies p G = (p x {s} c y)^2 + "
    "(p q - c^2) y^2 = (p x {s} c y)^2 >= 0, so G >= 0 where p > 0, and where p = 0, c^2 = p q = 0 and "
    "G = q y^2 >= 0")

#: x^T P x >= lambda_min(P) |x|^2 for P = [[a, c], [c, b]] (no premises)
RAYLEIGH_MIN2 = Lemma(
    "rayleigh_min_2", (_a, _b, _c, _x, _y), _form - _lmin * (_x**2 + _y**2), (),
    "a x^2 + 2 c x y + b y^2 >= lambda_min (x^2 + y^2), lambda_min = (a + b)/2 - (((a - b)/2)^2 + c^2)^(1/2) "
    "(the Rayleigh bound of a symmetric 2x2 matrix): "
    + _RAYLEIGH_TEXT.format(p="a - lambda_min = r + d", q="b - lambda_min = r - d", s="+"),
    lambda: _rayleigh_proof(_lmin, 1))

#: x^T P x <= lambda_max(P) |x|^2 for P = [[a, c], [c, b]] (no premises)
RAYLEIGH_MAX2 = Lemma(
    "rayleigh_max_2", (_a, _b, _c, _x, _y), _lmax * (_x**2 + _y**2) - _form, (),
    "a x^2 + 2 c x y + b y^2 <= lambda_max (x^2 + y^2), lambda_max = (a + b)/2 + (((a - b)/2)^2 + c^2)^(1/2) "
    "(the Rayleigh bound of a symmetric 2x2 matrix): "
    + _RAYLEIGH_TEXT.format(p="lambda_max - a = r - d", q="lambda_max - b = r + d", s="-"),
    lambda: _rayleigh_proof(_lmax, -1))


_u, _w = sp.symbols("u_c001 w_c001", real=True)


def _max_proof() -> bool:
    t = sp.Symbol("t", positive=True)
    return bool(sp.Max(_w + t, _w) == _w + t and sp.Max(_w, _w + t) == _w + t and sp.Max(_u, _w) == sp.Max(_w, _u))


#: Max(u, w) >= u (no premises); the mirror of ``min_le``
MAX_GE = Lemma(
    "max_ge", (_u, _w), sp.Max(_u, _w) - _u, (),
    "Max(u, w) >= u: Max(u, w) is u where u = w + t (t > 0), w where w = u + t (t > 0), or u = w",
    _max_proof)


def _row_proof() -> bool:
    # lambda_max^2 |x|^2 - |P x|^2 = (a + b) x^T M x, M = lambda_max I - P (det M = 0, so M^2 = tr(M) M by
    # Cayley-Hamilton, tr M = lambda_max - lambda_min, and lambda_max^2 - P^2 = M (2 lambda_max - M) =
    # (lambda_max + lambda_min) M = (a + b) M)
    mform = _lmax * (_x**2 + _y**2) - _form
    px2 = (_a * _x + _c * _y) ** 2 + (_c * _x + _b * _y) ** 2
    return bool(_zero(_lmax**2 * (_x**2 + _y**2) - px2 - (_a + _b) * mform) and _rayleigh_proof(_lmax, -1))


#: (P x)_2 <= lambda_max(P) |x| for P = [[a, c], [c, b]] with trace a + b >= 0
ROW_LE_LMAX2 = Lemma(
    "row_le_lambda_max_2", (_a, _b, _c, _x, _y), _lmax * sp.sqrt(_x**2 + _y**2) - (_c * _x + _b * _y), (_a + _b,),
    "c x + b y <= lambda_max |x| for P = [[a, c], [c, b]] with a + b >= 0 (lambda_max as in rayleigh_max_2): "
    "lambda_max^2 |x|^2 - |P x|^2 = (a + b) x^T (lambda_max I - P) x >= 0 (the identity; "
    "x^T (lambda_max I - P) x >= 0 by rayleigh_max_2), so |P x| <= lambda_max |x| (both >= 0: "
    "lambda_max >= (a + b)/2 >= 0; a^2 >= b^2 implies a >= b) and c x + b y = (P x)_2 <= |(P x)_2| <= |P x|",
    _row_proof)

LEMMAS: tuple = (RAYLEIGH_MIN2, RAYLEIGH_MAX2, MAX_GE, ROW_LE_LMAX2)
