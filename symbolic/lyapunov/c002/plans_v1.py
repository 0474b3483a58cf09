"""002: proof plans of the model, V1 and gain claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...rotations import dot
from ..certify import Coordinate, Plan, Region
from ..certify.lemmas import Lemma
from ..certify.plan import Use, composed, gaps
from ..core import Statement
from .common import _nrm


def _named(st: Statement, *names: str) -> list[sp.Symbol]:
    """The statement's symbols of the given names (in that order)."""
    by = {s.name: s for s in st.free_symbols()}
    return [by[n] for n in names]


def _table_reduce(st: Statement, plan: Plan, forms: dict) -> None:
    """Install ``plan.reduce`` as a lookup: the raw goal of (region, component) -> its hand-written form
    ``forms[(region, component)]`` (an equal expression, or a (positive factor, rest) pair).  The certificate
    re-verifies every form as an exact identity of the raw goal, so the table carries no trust."""
    table = {}
    for ri, reg in enumerate(plan.regions):
        for ci, g in enumerate(gaps(st)):
            table[composed(st, plan, reg, ci, g)] = forms[(ri, ci)]
    plan.reduce = table.__getitem__


def _ball3(c: list[sp.Symbol]) -> list[sp.Expr]:
    """The closed unit ball of R^3 as the image of the cube [-1, 1]^3 (onto; no hypothesis needed):
    y3 = c3, y2 = c2 sqrt(1 - c3^2), y1 = c1 sqrt((1 - c2^2)(1 - c3^2)), so that
    1 - |y|^2 = (1 - c1^2)(1 - c2^2)(1 - c3^2), a product of factors >= 0 on the box."""
    return [c[0] * sp.sqrt((1 - c[1] ** 2) * (1 - c[2] ** 2)), c[1] * sp.sqrt(1 - c[2] ** 2), c[2]]


# --------------------------------------------------------------------------- Lemma 2 times k (eq. 29)

def _lemma2_unit(st: Statement) -> Plan:
    """-k x^2/sqrt(x^2 + eps^2) <= -k x + k eps (x = ||s||): with x = eps u the gap is
    k eps (1 - u + eps u^2/t) = k eps (1 - u eps^2/(t (t + eps u))), t = sqrt(eps^2 u^2 + eps^2) (rationalised:
    u - eps u^2/t cancels catastrophically for large u, its rationalised form does not; t is kept as the
    statement writes it, since the identity check does not pull eps out of the root); k eps > 0 is factored
    out and the rest, >= 1/2, closes on the box."""
    x, k, e = _named(st, "snorm", "k", "varepsilon")
    u = sp.Symbol("u", nonnegative=True)
    reg = Region((Coordinate(e, 0.001, 0.1, "(units of ||s||)"), Coordinate(k, 0.01, 10.0, "1/s"),
                  Coordinate(u, 0.0, 1.0e6, "1")), subs={x: e * u},
                 describe="||s|| = eps u, u in [0, 1e6] (the search draws ||s|| in [0, (1e6 - 1) eps])")
    t = sp.sqrt(e**2 * u**2 + e**2)        # sqrt(||s||^2 + eps^2), as the statement has it
    plan = Plan([reg], "eps in [0.001, 0.1], k in [0.01, 10], ||s|| in [0, 1e6 eps]")
    _table_reduce(st, plan, {(0, 0): (k * e, 1 - u * e**2 / (t * (t + e * u)))})
    return plan


# --------------------------------------------------------------------------- eq. 34: the residual set

def _residual_set(st: Statement) -> Plan:
    """Omega_1 (corrected): 1/2 s1^T J s1 <= B1 gives ||s1||^2 <= 2 B1/min(J); 1/2 m ||s2||^2 <= B2 gives
    ||s2||^2 <= 2 B2/m.  Domain map: s1_i = sqrt(2 B1/J_i) y_i, s2 = sqrt(2 B2/m) z with y, z in the unit
    ball (the cube chart of :func:`_ball3`), one region per index of min(J): J_k = a, J_j = a + d_j, d_j >= 0
    (then SymPy's Min(J) is a).  Per region the gap is (2 B1/a) [(1 - |y|^2) + sum_{j != k} y_j^2 d_j/(a + d_j)]
    and (2 B2/m)(1 - |z|^2): sums of products of factors >= 0."""
    J = _named(st, "J_1", "J_2", "J_3")
    B1, B2, m = _named(st, "B_1", "B_2", "m")
    s1 = _named(st, "s_1_1", "s_1_2", "s_1_3")
    s2 = _named(st, "s_2_1", "s_2_2", "s_2_3")
    a = sp.Symbol("a", positive=True)
    d = [sp.Symbol(f"d_{j + 1}", nonnegative=True) for j in range(3)]
    cy = list(sp.symbols("cy_1:4", real=True))
    cz = list(sp.symbols("cz_1:4", real=True))
    y, z = _ball3(cy), _ball3(cz)
    ysq = [cy[0] ** 2 * (1 - cy[1] ** 2) * (1 - cy[2] ** 2), cy[1] ** 2 * (1 - cy[2] ** 2), cy[2] ** 2]
    one_minus_y = (1 - cy[0] ** 2) * (1 - cy[1] ** 2) * (1 - cy[2] ** 2)
    one_minus_z = (1 - cz[0] ** 2) * (1 - cz[1] ** 2) * (1 - cz[2] ** 2)
    regions, forms = [], {}
    for k in range(3):
        others = [j for j in range(3) if j != k]
        Jk = {J[k]: a, **{J[j]: a + d[j] for j in others}}
        subs = {**Jk, **{s1[i]: sp.sqrt(2 * B1 / Jk[J[i]]) * y[i] for i in range(3)},
                **{s2[i]: sp.sqrt(2 * B2 / m) * z[i] for i in range(3)}}
        coords = (Coordinate(a, 0.1, 40.0, "(any unit of inertia)"),
                  *[Coordinate(d[j], 0.0, 39.9, "(unit of J)") for j in others],
                  Coordinate(m, 0.1, 200.0, "(any unit of mass)"), Coordinate(B1, 0.001, 10.0, "(unit of V1)"),
                  Coordinate(B2, 0.001, 10.0, "(unit of V1)"),
                  *[Coordinate(c, -1.0, 1.0, "1") for c in cy + cz])
        regions.append(Region(coords, subs, describe=f"min(J) = J_{k + 1}"))
        rest1 = one_minus_y + sum(ysq[j] * d[j] / (a + d[j]) for j in others)
        forms[(k, 0)] = (2 * B1 / a, rest1)
        forms[(k, 1)] = (2 * B2 / m, one_minus_z)
    plan = Plan(regions, "J = diag(J_1, J_2, J_3), J_i in [0.1, 40] (each J_i - min(J) in [0, 39.9]), "
                         "m in [0.1, 200], B_1, B_2 in [0.001, 10], 1/2 s1^T J s1 <= B1, 1/2 m |s2|^2 <= B2 "
                         "(s1, s2 anywhere in these ellipsoids)")
    _table_reduce(st, plan, forms)
    return plan


# --------------------------------------------------------------------------- Remark 4: ||C_r w~||

def _ball4(t: list[sp.Symbol], sg: sp.Symbol) -> list[sp.Expr]:
    """The closed unit ball of R^4 as the image of [-1, 1]^4 (onto; the unit sphere at sg = +-1): the ball chart
    of :func:`_ball3` for the first three entries, the fourth sg sqrt((1 - t1^2)(1 - t2^2)(1 - t3^2)), so that
    1 - |.|^2 = (1 - sg^2)(1 - t1^2)(1 - t2^2)(1 - t3^2)."""
    return [*_ball3(t), sg * sp.sqrt((1 - t[0] ** 2) * (1 - t[1] ** 2) * (1 - t[2] ** 2))]


def _expand0(e) -> bool:
    return sp.expand(e) == 0


def _remark4_lemma_proof() -> bool:
    """The identities of the Remark 4 chain (see the lemma's text)."""
    Jg = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"jg_{min(i, j) + 1}{max(i, j) + 1}", real=True))
    p, w, uu, vv = (sp.Matrix(sp.symbols(f"{n}_1:4", real=True)) for n in ("pg", "wg", "ug", "vg"))
    X = c.attitude_coriolis_matrix(Jg, sp.eye(3), p, w) * w
    parts = Jg * p.cross(w) + p.cross(Jg * w) - (Jg * p).cross(w) - (Jg * w).cross(w)
    split = all(_expand0(a - b) for a, b in zip(X, parts, strict=True))
    Rs = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"rg_{i + 1}{j + 1}", real=True))
    via_p = all(_expand0(e) for e in c.attitude_coriolis_matrix(Jg, Rs, p, w)
                - c.attitude_coriolis_matrix(Jg, sp.eye(3), Rs * p, w))
    lagrange = _expand0(dot(uu.cross(vv), uu.cross(vv)) + dot(uu, vv) ** 2 - dot(uu, uu) * dot(vv, vv))
    qg = sp.Matrix(sp.symbols("qg_1:5", real=True))
    Rg = c.dcm_pursuer_from_target(qg)
    orth = all(_expand0(e) for e in Rg.T * Rg - dot(qg, qg) ** 2 * sp.eye(3))
    t, sg = list(sp.symbols("tg_1:4", real=True)), sp.Symbol("sg", real=True)
    prod3 = (1 - t[0] ** 2) * (1 - t[1] ** 2) * (1 - t[2] ** 2)
    ball4 = _expand0(1 - sum(x**2 for x in _ball4(t, sg)) - (1 - sg**2) * prod3)
    unit4 = _expand0(sum(x**2 for x in _ball4(t, 1)) - 1)
    ball3 = _expand0(1 - sum(x**2 for x in _ball3(t)) - prod3)
    return split and via_p and lagrange and orth and ball4 and unit4 and ball3


def _remark4_charts(Jm, q, wt, a1, cy, t, sg, u, b1, f) -> dict:
    """The charts, as a substitution of the symbols of J (upper triangle), q and omega_t:
    J = C diag(b1 f) C^T with C = R(c(u)), c(u) = :func:`_ball4` at sg = 1 (a unit quaternion),
    q = :func:`_ball4` (t, sg) (the unit ball of R^4), omega_t = a1 :func:`_ball3` (cy)."""
    Cm = c.dcm_pursuer_from_target(sp.Matrix(_ball4(u, 1)))
    J = Cm * sp.diag(*[b1 * x for x in f]) * Cm.T
    return {**{Jm[i, j]: J[i, j] for i in range(3) for j in range(i, 3)}, **dict(zip(q, _ball4(t, sg), strict=True)),
            **dict(zip(wt, [a1 * y for y in _ball3(cy)], strict=True))}


def _remark4_lemma(w, a1, cy, t, sg, u, b1, f) -> Lemma:
    """Remark 4 (corrected) in the charts of the plan: J = C diag(b1 f) C^T with C = R(c(u)), c(u) a unit
    quaternion (:func:`_ball4` at sg = 1), R = R(q(t, sg)), omega_t = a1 y(cy) (:func:`_ball3`)."""
    Jg = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"jg_{min(i, j) + 1}{max(i, j) + 1}", real=True))
    qg, wtg = sp.Matrix(sp.symbols("qg_1:5", real=True)), sp.Matrix(sp.symbols("wtg_1:4", real=True))
    wv = sp.Matrix(w)
    nw = _nrm(wv)
    generic = 3 * a1 * b1 * nw + b1 * nw**2 - _nrm(c.attitude_coriolis_matrix(Jg, c.dcm_pursuer_from_target(qg),
                                                                             wtg, wv) * wv)
    gap = generic.xreplace(_remark4_charts(Jg, qg, wtg, a1, cy, t, sg, u, b1, f))
    prem = (a1, b1, *[1 - x**2 for x in (*cy, *t, sg, *u)], *[1 - x for x in f], *f)
    text = ("||C_r w|| <= 3 a1 b1 ||w|| + b1 ||w||^2 for C_r = J p^x + p^x J - (J (w + p))^x (eq. 4), p = R omega_t "
            "(C_r depends on R, omega_t only through p: identity), J = C diag(b1 f) C^T with 0 <= f_i <= 1, "
            "C = R(c(u)), |c(u)| = 1, R = R(q), |q| <= 1, |omega_t| <= a1: "
            "(1) C_r w = J (p x w) + p x (J w) - (J p) x w - (J w) x w (identity); (2) the triangle inequality "
            "(Cauchy-Schwarz) bounds its norm by the sum of the four norms; (3) |a x b| <= |a| |b| (Lagrange: "
            "|a x b|^2 + (a.b)^2 = |a|^2 |b|^2, identity); (4) |J x| <= b1 |x|: R(c)^T R(c) = |c|^4 I (identity) and "
            "|c(u)|^2 = 1 (identity) make C orthogonal, so |J x|^2 = sum b1^2 f_i^2 (C^T x)_i^2 <= b1^2 |x|^2; "
            "(5) |p| = |q|^2 |omega_t| (R^T R = |q|^4 I) with 1 - |q(t, sg)|^2 = (1 - sg^2) prod(1 - t_i^2) >= 0 "
            "and a1^2 - |omega_t|^2 = a1^2 prod(1 - cy_i^2) >= 0 (identities), so |p| <= a1.  Sum of (2)-(5): "
            "||C_r w|| <= b1 |p| |w| + |p| b1 |w| + b1 |p| |w| + b1 |w|^2 <= 3 a1 b1 |w| + b1 |w|^2.")
    syms = (*w, a1, *cy, *t, sg, *u, b1, *f)
    return Lemma("remark4_Cr_chart", tuple(syms), gap, prem, text, _remark4_lemma_proof)


def _remark4_Cr(st: Statement) -> Plan:
    """Remark 4 (corrected, factor 3): proved by the lemma above, stated in the plan's charts, so the goal
    left to the boxes is the statement's gap less the lemma's (identically 0) and the lemma's premises
    (box faces).  J's eigenvalues b1 f_i with f_i in [1/8, 1] contain every d_i in [5, b1]; b1 >= max d
    (the claim's b1 = max d) is a superset; q in the unit ball of R^4 contains the unit quaternions."""
    w = _named(st, "omega_1", "omega_2", "omega_3")
    wt = _named(st, "omega_t_1", "omega_t_2", "omega_t_3")
    q = _named(st, "q_1", "q_2", "q_3", "q_0")
    Jn = {(i, j): _named(st, f"J_{i + 1}{j + 1}")[0] for i in range(3) for j in range(i, 3)}
    a1, b1 = _named(st, "a_1", "b_1")
    cy = list(sp.symbols("cy_1:4", real=True))
    t = list(sp.symbols("t_1:4", real=True))
    u = list(sp.symbols("u_1:4", real=True))
    sg = sp.Symbol("sg", real=True)
    f = list(sp.symbols("f_1:4", positive=True))
    Jm = sp.Matrix(3, 3, lambda i, j: Jn[min(i, j), max(i, j)])
    subs = _remark4_charts(Jm, q, wt, a1, cy, t, sg, u, b1, f)
    coords = (*[Coordinate(x, -0.01, 0.01, "rad/s") for x in w], Coordinate(a1, 0.05, 0.5, "rad/s"),
              *[Coordinate(x, -1.0, 1.0, "1") for x in cy + t + [sg] + u], Coordinate(b1, 5.0, 40.0, "kg m^2"),
              *[Coordinate(x, 0.125, 1.0, "1") for x in f])
    reg = Region(coords, subs, describe="J = R(c(u)) diag(b1 f) R(c(u))^T, q = q(t, sg) in the unit ball, "
                                        "omega_t = a1 y(cy) in the a1-ball")
    lem = _remark4_lemma(w, a1, cy, t, sg, u, b1, f)
    return Plan([reg], "omega~ in [-0.01, 0.01]^3 rad/s, a1 in [0.05, 0.5] rad/s, ||omega_t|| <= a1, q any "
                       "quaternion with |q| <= 1 (contains the unit ones), J = C diag(d) C^T with C any rotation and "
                       "d_i in [b1/8, b1], b1 in [5, 40] kg m^2 (contains d_i in [5, 40], b1 = max d)",
                uses=(Use(lem, {}),), reduce=_zero_goal(b1))


def _zero_goal(x: sp.Symbol):
    """The goal left after a lemma that is the whole statement is the constant 0, which the box prover cannot
    take (no coordinate: an empty box array); 0 * x (unevaluated, x a coordinate) is the same goal on a box."""
    return lambda g: sp.Mul(sp.S.Zero, x, evaluate=False) if g == 0 else g


# --------------------------------------------------------------------------- Remark 5: ||m n_t||

def _remark5_lemma_proof() -> bool:
    """The identities of the Remark 5 chain (see the lemma's text), besides those of Remark 4's."""
    Rs = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"rg_{i + 1}{j + 1}", real=True))
    wt, wd, vt, vd, sig, dg = (sp.Matrix(sp.symbols(f"{n}_1:4", real=True))
                               for n in ("wtg", "wdg", "vtg", "vdg", "sgg", "dgg"))
    n_t = c.translation_nonlinear_term(Rs, wt, wd, vt, vd, sig, Rs * vd - dg)
    pv = Rs * wt
    parts = pv.cross(Rs * vt) + pv.cross(pv.cross(Rs * sig)) - Rs * sig.cross(wd) + dg
    return all(_expand0(a - b) for a, b in zip(n_t, parts, strict=True)) and _remark4_lemma_proof()


def _remark5_generic(m, a, sn, w):
    """Remark 5's gap (corrected) built as the claim builds it, over generic symbols (returned with it)."""
    qg = sp.Matrix(sp.symbols("qg_1:5", real=True))
    vecs = {n: sp.Matrix(sp.symbols(f"{n}_1:4", real=True)) for n in ("wtg", "wdg", "vtg", "vdg", "sgg", "gpg", "dgg")}
    R = c.dcm_pursuer_from_target(qg)
    n_t = c.translation_nonlinear_term(R, vecs["wtg"], vecs["wdg"], vecs["vtg"], vecs["vdg"], vecs["sgg"], vecs["gpg"])
    lhs = _nrm(m * n_t).xreplace(dict(zip(vecs["gpg"], R * vecs["vdg"] - vecs["dgg"], strict=True)))
    a1, a2, a3, a4 = a
    rhs = m * a1 * a3 + m * a4 + m * sn * a1 * _nrm(sp.Matrix(w)) + m * sn * a2 + m * a1**2 * sn
    return rhs - lhs, qg, vecs


def _remark5_charts(qg, vecs, a, sn, ch, t, sg) -> dict:
    """q = :func:`_ball4` (t, sg); omega_t, omega_t_dot, v_t, sigma_t, Deltag, v_t_dot = radius x :func:`_ball3`
    with radii a1, a2, a3, sigmanorm, a4, 10."""
    a1, a2, a3, a4 = a
    out = dict(zip(qg, _ball4(t, sg), strict=True))
    for n, r in (("wtg", a1), ("wdg", a2), ("vtg", a3), ("sgg", sn), ("dgg", a4), ("vdg", 10)):
        out.update(zip(vecs[n], [r * y for y in _ball3(ch[n])], strict=True))
    return out


def _remark5_nt(st: Statement) -> Plan:
    """Remark 5 (corrected, with gravity): proved by a lemma stated in the plan's charts (as Remark 4), so the
    boxes close only the lemma's premises (box faces) and the constant 0 left of the main goal."""
    m, b3, sn = _named(st, "m", "b_3", "sigmanorm")
    a = _named(st, "a_1", "a_2", "a_3", "a_4")
    w = _named(st, "omega_1", "omega_2", "omega_3")
    q = _named(st, "q_1", "q_2", "q_3", "q_0")
    names = {"wtg": "omega_t", "wdg": "omegadot_t", "vtg": "v_t", "vdg": "vdot_t", "sgg": "sigma_t", "dgg": "Deltag"}
    by = {x.name: x for x in st.free_symbols()}
    ch = {n: list(sp.symbols(f"c{n[:2]}_1:4", real=True)) for n in names}
    t, sg = list(sp.symbols("t_1:4", real=True)), sp.Symbol("sg", real=True)
    gap, qg, vecs = _remark5_generic(m, a, sn, w)
    charts = _remark5_charts(qg, vecs, a, sn, ch, t, sg)
    prem = (m, sn, *a, *[1 - x**2 for x in (*t, sg, *[y for n in names for y in ch[n]])])
    text = ("||m n_t|| <= m (a1 a3 + a4 + sigmanorm a1 ||w~|| + sigmanorm a2 + a1^2 sigmanorm) for n_t of eq. 9 "
            "(corrected) with g_p = R v_t_dot - Deltag: (1) n_t = p x (R v_t) + p x (p x (R sigma_t)) "
            "- R (sigma_t x omega_t_dot) + Deltag, p = R omega_t (identity); (2) the triangle inequality and "
            "|a x b| <= |a| |b| (Lagrange's identity); (3) |R x| = |q|^2 |x| <= |x| (R^T R = |q|^4 I and "
            "1 - |q(t, sg)|^2 = (1 - sg^2) prod(1 - t_i^2), identities); (4) each vector in its ball: "
            "r^2 - |r y(c)|^2 = r^2 prod(1 - c_i^2) (identity); the sum is <= the bound (its a1 ||w~|| term >= 0).")
    lem = Lemma("remark5_nt_chart", (m, sn, *a, *w, *t, sg, *[y for n in names for y in ch[n]]),
                gap.xreplace(charts), prem, text, _remark5_lemma_proof)
    subs = {b3: m, **{qs: charts[qq] for qs, qq in zip(q, qg, strict=True)}}
    for n, base in names.items():
        if f"{base}_1" in by:
            subs.update({by[f"{base}_{i + 1}"]: charts[vecs[n][i]] for i in range(3)})
    coords = (*[Coordinate(x, -1.0, 1.0, "rad/s") for x in w], Coordinate(a[0], 0.001, 0.5, "rad/s"),
              Coordinate(a[1], 0.001, 0.5, "rad/s^2"), Coordinate(a[2], 0.01, 10.0, "m/s"),
              Coordinate(a[3], 0.01, 10.0, "m/s^2"), Coordinate(m, 20.0, 200.0, "kg"),
              Coordinate(sn, 0.1, 10.0, "m"),
              *[Coordinate(x, -1.0, 1.0, "1") for x in (*t, sg, *[y for n in names for y in ch[n]])])
    reg = Region(coords, subs, describe="b3 = m; q = q(t, sg) in the unit ball of R^4; omega_t, omega_t_dot, v_t, "
                                        "sigma_t, Deltag, v_t_dot in their balls by the cube chart")
    return Plan([reg], "omega~ in [-1, 1]^3 rad/s, a1, a2 in [0.001, 0.5], a3, a4 in [0.01, 10], m = b3 in [20, 200] "
                       "kg, sigmanorm in [0.1, 10] m, ||omega_t|| <= a1, ||omega_t_dot|| <= a2, ||v_t|| <= a3, "
                       "||sigma_t|| <= sigmanorm, ||Deltag|| <= a4, ||v_t_dot|| <= 10, q any quaternion with |q| <= 1 "
                       "(contains the unit ones)", uses=(Use(lem, {}),), reduce=_zero_goal(m))


PLANS: dict = {
    "c002.V1.lemma2_unit_terms": _lemma2_unit,
    "c002.V1.residual_set": _residual_set,
    "c002.model.remark4_Cr": _remark4_Cr,
    "c002.model.remark5_nt": _remark5_nt,
}
