"""Lemmas written for the plans of controller c002 (reviewed like the rest of :mod:`.lemmas`).

Each is a small, general fact (times a weight k >= 0): its proof re-checks identities symbolically, its
text names the textbook step; a claim-sized lemma does not belong here.

The norm steps of Remarks 4-5 (paper 002): the triangle inequality, |a x b| <= |a| |b| (Lagrange's
identity), |J x| <= b1 |x| for J = C diag(d) C^T (C a rotation, 0 <= d_i <= b1), |R(q) x| = |q|^2 |x|
for the (unnormalised) rotation matrix of a quaternion q; for eq. 21, the shifted spectrum |(J - h I) x| <= h |x|
(0 <= d_i <= 2h), eq. 4's -C_r w - n_r regrouped (an identity) and |1/2 (q_v^x + q0 I) y| <= |q| |y|/2.  Norms
are ``sqrt(x . x)``, written as the claims write them, and matrix-vector products keep the claims' association
((A B) x, not A (B x)), so that a plan composes the lemmas with the claim's expressions term by term; each proof
checks the association identity (A B) x = A (B x) too.  Every gap is k times the fact (k A - k B, k >= 0 a premise:
a nonnegative multiple of a nonnegative number), written term by term so that weighted instances cancel.
"""

from __future__ import annotations

import sympy as sp

from ...physics.rotations import dot, quat_to_dcm, skew
from .lemmas import Lemma


def _vec(name: str, n: int = 3) -> sp.Matrix:
    return sp.Matrix(sp.symbols(f"{name}_1:{n + 1}", real=True))


def _mat(name: str) -> sp.Matrix:
    return sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"{name}_{i + 1}{j + 1}", real=True))


def _nrm(x: sp.Matrix) -> sp.Expr:
    return sp.sqrt(dot(x, x))


def _zero(e) -> bool:
    return sp.expand(e) == 0


def _zero_vec(v: sp.Matrix) -> bool:
    return all(_zero(e) for e in v)


# every lemma carries a weight k >= 0 as a factor of each of its terms (the gap is the sum k A - k B, not
# k (A - B)), so that a plan's weighted instances cancel term by term as SymPy builds the sum
_k = sp.Symbol("lc2_k", real=True)

# generic vectors of the proofs
_u, _v, _z = _vec("lc2_u"), _vec("lc2_v"), _vec("lc2_z")


def _lagrange(a: sp.Matrix, b: sp.Matrix) -> bool:
    """|a x b|^2 + (a . b)^2 = |a|^2 |b|^2 (a x b as skew(a) b)."""
    axb = skew(a) * b
    return _zero(dot(axb, axb) + dot(a, b) ** 2 - dot(a, a) * dot(b, b))


def _cs_square(a: sp.Matrix, b: sp.Matrix) -> bool:
    """|a|^2 |b|^2 - (a . b)^2 is a sum of squares (Lagrange's identity), so a . b <= |a| |b|."""
    lhs = dot(a, a) * dot(b, b) - dot(a, b) ** 2
    rhs = sum((a[i] * b[j] - a[j] * b[i]) ** 2 for i in range(3) for j in range(i + 1, 3))
    return _zero(lhs - rhs)


# --------------------------------------------------------------------------- triangle inequality, norm form

_tx, _ty, _tz, _tw = _vec("lc2_tx"), _vec("lc2_ty"), _vec("lc2_tz"), _vec("lc2_tw")


def _triangle_proof(n: int) -> bool:
    vs = [_u, _v, _z, _vec("lc2_y")][:n]
    total = sum(vs, sp.zeros(3, 1))
    # (sum |x_k|)^2 - |sum x_k|^2 = 2 sum_{k<l} (|x_k| |x_l| - x_k . x_l): an identity (|x|^2 = x . x)
    sq = sp.expand(sum((_nrm(x) for x in vs), sp.S.Zero) ** 2 - dot(total, total))
    cross = 2 * sum(_nrm(vs[k]) * _nrm(vs[m]) - dot(vs[k], vs[m]) for k in range(n) for m in range(k + 1, n))
    return _zero(sq - cross) and _cs_square(_u, _v)


TRIANGLE_V2 = Lemma(
    "c002_triangle_vec2", (_k, *_tx, *_ty), _k * _nrm(_tx) + _k * _nrm(_ty) - _k * _nrm(_tx + _ty), (_k,),
    "|x + y| <= |x| + |y| in R^3: (|x| + |y|)^2 - |x + y|^2 = 2 (|x| |y| - x . y) (identity), >= 0 by "
    "Cauchy-Schwarz (|x|^2 |y|^2 - (x . y)^2 is Lagrange's sum of squares); both sides are >= 0",
    lambda: _triangle_proof(2))

TRIANGLE_V4 = Lemma(
    "c002_triangle_vec4", (_k, *_tx, *_ty, *_tz, *_tw),
    _k * _nrm(_tx) + _k * _nrm(_ty) + _k * _nrm(_tz) + _k * _nrm(_tw) - _k * _nrm(_tx + _ty + _tz + _tw), (_k,),
    "|x + y + z + w| <= |x| + |y| + |z| + |w| in R^3: (sum of the norms)^2 - |sum|^2 = 2 sum over pairs of "
    "(|a| |b| - a . b) (identity), each >= 0 by Cauchy-Schwarz (Lagrange's sum of squares); both sides >= 0",
    lambda: _triangle_proof(4))

_MA, _MB, _MC = _mat("lc2_A"), _mat("lc2_B"), _mat("lc2_C")
_mw = _vec("lc2_mw")


def _triangle_mat_proof() -> bool:
    assoc = _zero_vec((_MA + _MB + _MC) * _mw - (_MA * _mw + _MB * _mw + _MC * _mw))
    return assoc and _triangle_proof(3)


TRIANGLE_M3 = Lemma(
    "c002_triangle_mat3", (_k, *_MA, *_MB, *_MC, *_mw),
    _k * _nrm(_MA * _mw) + _k * _nrm(_MB * _mw) + _k * _nrm(_MC * _mw) - _k * _nrm((_MA + _MB + _MC) * _mw), (_k,),
    "|(A + B + C) w| <= |A w| + |B w| + |C w| for 3x3 matrices A, B, C: (A + B + C) w = A w + B w + C w "
    "(identity), then the triangle inequality for three vectors ((sum of norms)^2 - |sum|^2 = 2 sum over "
    "pairs of (|a| |b| - a . b), identity, each >= 0 by Cauchy-Schwarz)",
    _triangle_mat_proof)

# --------------------------------------------------------------------------- |s x| = s |x| (s >= 0)

_ss, _sx = sp.Symbol("lc2_s", real=True), _vec("lc2_sx")

SCALE = Lemma(
    "c002_scale", (_k, _ss, *_sx), _k * _ss * _nrm(_sx) - _k * _nrm(_ss * _sx), (_k, _ss),
    "|s x| <= s |x| for s >= 0: |s x|^2 = s^2 |x|^2 (identity) and both s |x| and |s x| are >= 0",
    lambda: _zero(dot(_ss * _sx, _ss * _sx) - _ss**2 * dot(_sx, _sx)))

# --------------------------------------------------------------------------- |a x (M b)| <= |a| |M b|
# The cross-product matrix is the lemma's own symbol K with the premises K = a^x (each entry >= 0 and <= 0), so
# that (K M) b is formed as a plan's claim forms it (with a^x's entries as the claim writes them).

_ca, _cb = _vec("lc2_ca"), _vec("lc2_cb")
_CK, _CM, _CN = _mat("lc2_K"), _mat("lc2_M"), _mat("lc2_N")
_skew_equal = [_CK[i, j] - skew(_ca)[i, j] for i in range(3) for j in range(3)]
_skew_premises = (*_skew_equal, *[-e for e in _skew_equal])


def _cross_proof(chain) -> bool:
    at = {_CK[i, j]: skew(_ca)[i, j] for i in range(3) for j in range(3)}
    return _zero_vec(chain.xreplace(at)) and _lagrange(_u, _v)


CROSS_M = Lemma(
    "c002_cross_m", (_k, *_ca, *_CK, *_CM, *_cb),
    _k * _nrm(_ca) * _nrm(_CM * _cb) - _k * _nrm((_CK * _CM) * _cb), (_k, *_skew_premises),
    "k |(K M) b| <= k |a| |M b| for k >= 0, K = a^x (premises: K - a^x >= 0 and <= 0), any 3x3 M: (K M) b = "
    "a x (M b) (identity), and |a x y|^2 = |a|^2 |y|^2 - (a . y)^2 <= |a|^2 |y|^2 (Lagrange's identity); both "
    "sides >= 0",
    lambda: _cross_proof((_CK * _CM) * _cb - skew(_ca) * (_CM * _cb)))

CROSS_MN = Lemma(
    "c002_cross_mn", (_k, *_ca, *_CK, *_CM, *_CN, *_cb),
    _k * _nrm(_ca) * _nrm((_CM * _CN) * _cb) - _k * _nrm(((_CK * _CM) * _CN) * _cb), (_k, *_skew_premises),
    "k |((K M) N) b| <= k |a| |(M N) b| for k >= 0, K = a^x, any 3x3 M, N: ((K M) N) b = a x ((M N) b) "
    "(identity), then Lagrange's identity as in c002_cross_m",
    lambda: _cross_proof(((_CK * _CM) * _CN) * _cb - skew(_ca) * ((_CM * _CN) * _cb)))

# --------------------------------------------------------------------------- |(R(q) S) x| <= |q|^2 |S x|

_rq = sp.Matrix(sp.symbols("lc2_q_1 lc2_q_2 lc2_q_3 lc2_q_0", real=True))     # scalar last, as the claims
_RS, _rx = _mat("lc2_S"), _vec("lc2_rx")
_RQ = quat_to_dcm(_rq).T          # the claims' R~ = C_{p<-t} = quat_to_dcm(q)^T, not normalised


def _rotation_proof() -> bool:
    qq = dot(_rq, _rq)
    orth = all(_zero(e) for e in _RQ.T * _RQ - qq**2 * sp.eye(3))      # R^T R = |q|^4 I
    assoc = _zero_vec((_RQ * _RS) * _rx - _RQ * (_RS * _rx))
    return orth and assoc


ROTATION = Lemma(
    "c002_rotation", (_k, *_rq, *_RS, *_rx),
    _k * dot(_rq, _rq) * _nrm(_RS * _rx) - _k * _nrm((_RQ * _RS) * _rx), (_k,),
    "|(R(q) S) x| <= |q|^2 |S x| (with equality) for R(q) = (q0^2 - |q_v|^2) I + 2 q_v q_v^T - 2 q0 q_v^x "
    "(quat_to_dcm(q)^T, any q, not normalised) and any 3x3 S: (R S) x = R (S x) and R^T R = |q|^4 I "
    "(identities), so |R y|^2 = |q|^4 |y|^2; both sides >= 0",
    _rotation_proof)

# --------------------------------------------------------------------------- |(J S) y| <= b1 |S y|

_jc = sp.Matrix(sp.symbols("lc2_c_1 lc2_c_2 lc2_c_3 lc2_c_0", real=True))
_jd = _vec("lc2_d")
_jb = sp.Symbol("lc2_b", real=True)
_JS, _jy = _mat("lc2_T"), _vec("lc2_jy")
_JJ = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"lc2_J_{min(i, j) + 1}{max(i, j) + 1}", real=True))


def spd_chart(c: sp.Matrix, d) -> sp.Matrix:
    """J = C diag(d) C^T with C = R(c)/|c|^2 (R as in :data:`ROTATION`): a rotation for every c != 0."""
    Rc = quat_to_dcm(c).T
    return Rc * sp.diag(*d) * Rc.T / dot(c, c) ** 2


_JX = spd_chart(_jc, _jd)


def _spd_proof() -> bool:
    # with z = R(c)^T x: |c|^8 (b^2 |x|^2 - |J x|^2) = |c|^4 sum (b^2 - d_i^2) z_i^2, using
    # R^T R = R R^T = |c|^4 I (checked first) for |z|^2 = |c|^4 |x|^2 and |R D z|^2 = |c|^4 |D z|^2
    Rc = quat_to_dcm(_jc).T
    cc = dot(_jc, _jc)
    orth = all(_zero(e) for e in Rc.T * Rc - cc**2 * sp.eye(3)) and all(
        _zero(e) for e in Rc * Rc.T - cc**2 * sp.eye(3))
    x = _u
    z = Rc.T * x
    Jx_num = Rc * sp.diag(*_jd) * z                   # |c|^4 J x
    lhs = cc**4 * _jb**2 * dot(x, x) - dot(Jx_num, Jx_num)
    rhs = cc**2 * sum((_jb**2 - _jd[i] ** 2) * z[i] ** 2 for i in range(3))
    ident = _zero(lhs - rhs)
    assoc = _zero_vec((_JJ * _JS) * _jy - _JJ * (_JS * _jy))
    sym = all(sp.simplify(_JX[i, j] - _JX[j, i]) == 0 for i in range(3) for j in range(i + 1, 3))
    return orth and ident and assoc and sym


_spd_equal = [_JJ[i, j] - _JX[i, j] for i in range(3) for j in range(i, 3)]

SPD_BOUND = Lemma(
    "c002_spd_bound", (_k, *[_JJ[i, j] for i in range(3) for j in range(i, 3)], *_jc, *_jd, _jb,
                       *_JS, *_jy),
    _k * _jb * _nrm(_JS * _jy) - _k * _nrm((_JJ * _JS) * _jy),
    (*_spd_equal, *[-e for e in _spd_equal], dot(_jc, _jc), *_jd, *[_jb - x for x in _jd], _k),
    "|(J S) y| <= b |S y| for a symmetric J = C diag(d) C^T (premises: J_ij - (C diag(d) C^T)_ij >= 0 and <= 0), "
    "C = R(c)/|c|^2 (c != 0), 0 <= d_i <= b, any 3x3 S: (J S) y = J (S y) (identity); with x = S y and z = "
    "R(c)^T x, R^T R = R R^T = |c|^4 I (identities) give |c|^8 (b^2 |x|^2 - |J x|^2) = |c|^4 sum (b^2 - d_i^2) "
    "z_i^2 (identity), >= 0 as b^2 - d_i^2 = (b - d_i)(b + d_i) >= 0; b >= d_i >= 0, so both sides >= 0",
    _spd_proof, strict=(False,) * 12 + (True,))

# --------------------------------------------------------------------------- Lemma 2 (paper 002), sharp constant

_lz, _le = sp.Symbol("lc2_z", real=True), sp.Symbol("lc2_eps", real=True)
LEMMA2_C = sp.Rational(31, 100)          # > max_x x/(sqrt(x^2 + 1)(sqrt(x^2 + 1) + x)) = 0.30028 (x = 0.786)


def _lemma2_proof() -> bool:
    c = LEMMA2_C
    u, e, t, x, T = sp.symbols("u e t x T", positive=True)
    # (1) with t^2 = u^2 + e^2: u^2/t - u + c e = e (c t (t + u) - u e)/(t (t + u))
    lhs = u**2 / t - u + c * e
    rhs = e * (c * t * (t + u) - u * e) / (t * (t + u))
    one = sp.expand(sp.numer(sp.together(lhs - rhs)).subs(t**2, u**2 + e**2)) == 0
    one = one or sp.rem(sp.Poly(sp.numer(sp.together(lhs - rhs)), t), sp.Poly(t**2 - u**2 - e**2, t)).is_zero
    # (2) scaling u = e x, t = e T: c t (t + u) - u e = e^2 (c T (T + x) - x)
    two = sp.expand((c * t * (t + u) - u * e).subs({u: e * x, t: e * T}) - e**2 * (c * T * (T + x) - x)) == 0
    # (3) c T (T + x) - x = c T x - q(x) with q = x - c (x^2 + 1) (T^2 = x^2 + 1); q <= 0 off [1/4, 3] (a concave
    # parabola negative at both ends, its vertex 1/(2c) between them); on [1/4, 3] the polynomial
    # p = c^2 (x^2 + 1) x^2 - q^2 = (c T x)^2 - q^2 has no root (Sturm) and p(1) > 0, so c T x >= |q| there
    q = x - c * (x**2 + 1)
    three = sp.expand(c * T * (T + x) - x - (c * T * x - q)).subs(T**2, x**2 + 1) == 0
    poly = sp.Poly(c**2 * (x**2 + 1) * x**2 - q**2, x)
    ends = q.subs(x, sp.Rational(1, 4)) < 0 and q.subs(x, 3) < 0 and sp.Rational(1, 4) < 1 / (2 * c) < 3
    sturm = poly.count_roots(sp.Rational(1, 4), 3) == 0 and poly.eval(1) > 0
    return bool(one and two and three and ends and sturm)


LEMMA2 = Lemma(
    "c002_lemma2", (_k, _lz, _le),
    _k * _lz / sp.sqrt(_lz + _le**2) - _k * sp.sqrt(_lz) + LEMMA2_C * _k * _le, (_k, _lz, _le),
    "Lemma 2 of paper 002 (times k, with a sharp constant): k sqrt(z) - k z/sqrt(z + eps^2) <= c k eps for k >= 0, "
    "z >= 0, eps > 0, c = 31/100 (z = ||x||^2: -k ||x||^2/sqrt(||x||^2 + eps^2) <= -k ||x|| + c k eps).  With u = "
    "sqrt(z), t = sqrt(z + eps^2): u^2/t - u + c eps = eps (c t (t + u) - u eps)/(t (t + u)) (identity modulo t^2 ="
    " u^2 + eps^2); with u = eps x, t = eps T (T = sqrt(x^2 + 1)) the bracket is eps^2 (c T (T + x) - x) = eps^2 (c"
    " T x - q(x)), q = x - c (x^2 + 1).  Where q <= 0 the bracket is >= c T x >= 0; q > 0 only inside [1/4, 3] "
    "(q(1/4), q(3) < 0, q concave), where p = c^2 (x^2 + 1) x^2 - q^2 has no real root (Sturm count) and p(1) > 0, "
    "so (c T x)^2 > q^2 and c T x > q.  (The sharp value is 0.30028 at x = 0.786.)",
    _lemma2_proof, strict=(False, False, True))


# --------------------------------------------------------------------------- |((J - h I) S) y| <= h |S y|
# The shifted spectrum: J - h I = C diag(d_i - h) C^T has |d_i - h| <= h for 0 <= d_i <= 2h.

_sh = sp.Symbol("lc2_h", real=True)


def _shift_proof() -> bool:
    # as _spd_proof with diag(d - h): with x = S y and z = R(c)^T x, |c|^4 (J - h I) x = R (D - h I) z
    # (J = R D R^T/|c|^4 and R R^T = |c|^4 I), so |c|^8 (h^2 |x|^2 - |(J - h I) x|^2) = |c|^4 sum (h^2 - (d_i -
    # h)^2) z_i^2 = |c|^4 sum d_i (2h - d_i) z_i^2
    Rc = quat_to_dcm(_jc).T
    cc = dot(_jc, _jc)
    orth = all(_zero(e) for e in Rc.T * Rc - cc**2 * sp.eye(3)) and all(
        _zero(e) for e in Rc * Rc.T - cc**2 * sp.eye(3))
    x = _u
    z = Rc.T * x
    # |c|^4 (J - h I) = R (D - h I) R^T (a rational identity: cancel, since expand keeps the denominator |c|^4)
    shifted = all(sp.cancel(e) == 0 for e in cc**2 * (_JX - _sh * sp.eye(3))
                  - Rc * sp.diag(*[di - _sh for di in _jd]) * Rc.T)
    Jx_num = Rc * sp.diag(*[di - _sh for di in _jd]) * z                       # |c|^4 (J - h I) x
    lhs = cc**4 * _sh**2 * dot(x, x) - dot(Jx_num, Jx_num)
    rhs = cc**2 * sum(_jd[i] * (2 * _sh - _jd[i]) * z[i] ** 2 for i in range(3))
    ident = _zero(lhs - rhs)
    assoc = _zero_vec(((_JJ - _sh * sp.eye(3)) * _JS) * _jy - (_JJ - _sh * sp.eye(3)) * (_JS * _jy))
    return orth and shifted and ident and assoc


SPD_SHIFT = Lemma(
    "c002_spd_shift", (_k, *[_JJ[i, j] for i in range(3) for j in range(i, 3)], *_jc, *_jd, _sh, *_JS, *_jy),
    _k * _sh * _nrm(_JS * _jy) - _k * _nrm(((_JJ - _sh * sp.eye(3)) * _JS) * _jy),
    (*_spd_equal, *[-e for e in _spd_equal], dot(_jc, _jc), *_jd, *[2 * _sh - x for x in _jd], _k),
    "|((J - h I) S) y| <= h |S y| for a symmetric J = C diag(d) C^T (premises: J_ij - (C diag(d) C^T)_ij >= 0 and "
    "<= 0), C = R(c)/|c|^2 (c != 0), 0 <= d_i <= 2h, any 3x3 S (the shifted spectrum: J - h I = C diag(d - h) C^T "
    "and |d_i - h| <= h): ((J - h I) S) y = (J - h I)(S y) (identity); with x = S y, z = R(c)^T x, R^T R = R R^T "
    "= |c|^4 I (identities) give |c|^8 (h^2 |x|^2 - |(J - h I) x|^2) = |c|^4 sum d_i (2h - d_i) z_i^2 (identity, "
    "h^2 - (d_i - h)^2 = d_i (2h - d_i)), >= 0; h >= d_i/2 >= 0, so both sides are >= 0",
    _shift_proof, strict=(False,) * 12 + (True,))

# --------------------------------------------------------------------------- eq. 4: -C_r w - n_r, regrouped
# an identity (gap 0): with p = R omega_t and u = w + p, -C_r w - n_r = ((J - h I) u) x u + J (w x p) - (J R) wd
# for every 3x3 J, R and every h ((h u) x u = 0), C_r and n_r as the code builds them (eq. 4)

_ER = _mat("lc2_R")
_ew, _ewt, _ewd = _vec("lc2_ew"), _vec("lc2_ewt"), _vec("lc2_ewd")


def _euler_pieces() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix, sp.Matrix]:
    """(-C_r w - n_r as the code builds it, and its three regrouped terms A, B, C)."""
    from ...controllers import c002

    Cr = c002.attitude_coriolis_matrix(_JJ, _ER, _ewt, _ew)
    nr = c002.attitude_nonlinear_term(_JJ, _ER, _ewt, _ewd)
    p = _ER * _ewt
    u = _ew + p
    A = skew((_JJ - _sh * sp.eye(3)) * u) * u
    B = (_JJ * skew(_ew)) * p
    C = (_JJ * _ER) * (-_ewd)
    return -Cr * _ew - nr, A, B, C


_EV, _EA, _EB, _EC = _euler_pieces()

EULER_FORM = Lemma(
    "c002_euler_form", (_k, *[_JJ[i, j] for i in range(3) for j in range(i, 3)], *_ER, _sh, *_ew, *_ewt, *_ewd),
    _k * _nrm(_EA + _EB + _EC) - _k * _nrm(_EV), (_k,),
    "Eq. 4 regrouped (an identity, gap 0): for any 3x3 J, R, vectors w, omega_t, omegadot_t and scalar h, with p = "
    "R omega_t and u = w + p, the code's -C_r w - n_r (C_r = J p^x + p^x J - (J u)^x, n_r = p^x J p + (J R) "
    "omegadot_t) equals ((J - h I) u) x u + (J w^x) p - (J R) omegadot_t (expanded, the difference is 0: (J u) x u "
    "= (J u) x w + (J w) x p + (J p) x p and (h u) x u = 0), so k |A + B + C| - k |-C_r w - n_r| = 0",
    lambda: _zero_vec(_EV - (_EA + _EB + _EC)))

# --------------------------------------------------------------------------- |1/2 (q_v^x + q0 I) y| <= |q| |y| / 2

_qy = _vec("lc2_qy")


def _quat_rate_vec(q: sp.Matrix, y: sp.Matrix) -> sp.Matrix:
    """q_v_dot = 1/2 (q_v^x + q0 I) y (eq. 3) as the code builds it."""
    from ...controllers import c002

    return c002.relative_quaternion_rate(q, y)[:3, :]


def _quat_rate_proof() -> bool:
    qv, q0 = _rq[:3, :], _rq[3]
    v = (skew(qv) + q0 * sp.eye(3)) * _qy
    form = _zero_vec(2 * _quat_rate_vec(_rq, _qy) - v)
    # |(q_v^x + q0 I) y|^2 = |q|^2 |y|^2 - (q_v . y)^2 (q_v x y is orthogonal to y; Lagrange's identity)
    ident = _zero(dot(v, v) - (dot(_rq, _rq) * dot(_qy, _qy) - dot(qv, _qy) ** 2))
    return form and ident


QUAT_RATE = Lemma(
    "c002_quat_rate", (_k, *_rq, *_qy),
    _k * _nrm(_rq) * _nrm(_qy) / 2 - _k * _nrm(_quat_rate_vec(_rq, _qy)), (_k,),
    "|1/2 (q_v^x + q0 I) y| <= |q| |y| / 2 for any quaternion q (scalar last) and y (eq. 3's q_v_dot as the code "
    "builds it): |(q_v^x + q0 I) y|^2 = |q|^2 |y|^2 - (q_v . y)^2 (identity: q_v x y is orthogonal to y, Lagrange's "
    "identity), <= |q|^2 |y|^2; both sides >= 0",
    _quat_rate_proof)


LEMMAS: tuple = (TRIANGLE_V2, TRIANGLE_V4, TRIANGLE_M3, SCALE, CROSS_M, CROSS_MN, ROTATION, SPD_BOUND, LEMMA2,
                 SPD_SHIFT, EULER_FORM, QUAT_RATE)
