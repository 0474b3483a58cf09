"""002: proof plans of the model, V1 and gain claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...rotations import dot, skew
from ..certify import Coordinate, Plan, Region
from ..certify import lemmas_c002 as lc
from ..certify.plan import Use, composed, gaps
from ..core import Statement


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
                  Coordinate(u, 1e-300, 1.0e6, "1")), subs={x: e * u},
                 describe="||s|| = eps u, u in [1e-300, 1e6] (the statement's ||s|| is a positive symbol; the "
                          "search draws ||s|| in [0, (1e6 - 1) eps])")
    t = sp.sqrt(e**2 * u**2 + e**2)        # sqrt(||s||^2 + eps^2), as the statement has it
    plan = Plan([reg], "eps in [0.001, 0.1], k in [0.01, 10], ||s|| in [1e-300 eps, 1e6 eps] (||s|| > 0, as "
                       "the statement's symbol is declared)")
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


# --------------------------------------------------------------------------- Remarks 4-5: norm bounds

def _ball4(t: list[sp.Symbol], sg: sp.Symbol) -> list[sp.Expr]:
    """The closed unit ball of R^4 as the image of [-1, 1]^4 (onto): :func:`_ball3` for the first three
    entries, the fourth sg sqrt((1 - t1^2)(1 - t2^2)(1 - t3^2)), so that 1 - |.|^2 = (1 - sg^2) prod (1 - t_i^2)
    (the unit sphere is the faces sg = +-1)."""
    return [*_ball3(t), sg * sp.sqrt((1 - t[0] ** 2) * (1 - t[1] ** 2) * (1 - t[2] ** 2))]


def _prod1m(xs) -> sp.Expr:
    """prod (1 - x^2): in [0, 1] on the cube, and exactly so in interval arithmetic."""
    out = sp.S.One
    for x in xs:
        out *= 1 - x**2
    return out


def _faces(u: list[sp.Symbol]) -> list[sp.Matrix]:
    """The four cube faces c_k = 1 (others u in [-1, 1]^3) of a quaternion c (scalar last): every rotation is
    R(c)/|c|^2 for c on one of them (scale a unit quaternion by 1/max |c_k|, and its sign)."""
    out = []
    for k in range(4):
        it = iter(u)
        out.append(sp.Matrix([sp.S.One if i == k else next(it) for i in range(4)]))
    return out


def _small_factor(e: sp.Expr) -> sp.Expr:
    """Side goals as products where SymPy factors them cheaply (b1 - b1 f = b1 (1 - f): the premise's zero on
    the face f = 1 then encloses exactly); the identity is re-verified by the checker."""
    return sp.factor(e) if sp.count_ops(e) < 12 else e


def _use(lem, weight=sp.S.One, region=None, **vectors) -> Use:
    """A use of a lemma of ``lemmas_c002`` given by its named vectors/matrices/scalars (``_LEMMA_SYMBOLS``);
    the weight is the lemma's own factor k (a factor of each of its terms, so that the weighted terms cancel
    as SymPy builds the composed gap), its side goal k >= 0 a premise."""
    mapping = {lc._k: sp.sympify(weight)}
    for name, value in vectors.items():
        syms = _LEMMA_SYMBOLS[(lem.name, name)]
        vals = list(value) if isinstance(value, (sp.MatrixBase, list, tuple)) else [value]
        if len(syms) != len(vals):
            raise ValueError(f"{lem.name}.{name}: {len(syms)} symbols, {len(vals)} values")
        mapping.update(dict(zip(syms, vals, strict=True)))
    return Use(lem, mapping, sp.S.One, 0, region)


_LEMMA_SYMBOLS = {
    ("c002_triangle_vec2", "x"): list(lc._tx), ("c002_triangle_vec2", "y"): list(lc._ty),
    **{("c002_triangle_vec4", k): list(v) for k, v in zip("xyzw", (lc._tx, lc._ty, lc._tz, lc._tw), strict=True)},
    ("c002_triangle_mat3", "A"): list(lc._MA), ("c002_triangle_mat3", "B"): list(lc._MB),
    ("c002_triangle_mat3", "C"): list(lc._MC), ("c002_triangle_mat3", "w"): list(lc._mw),
    ("c002_scale", "s"): [lc._ss], ("c002_scale", "x"): list(lc._sx),
    ("c002_cross_m", "a"): list(lc._ca), ("c002_cross_m", "M"): list(lc._CM), ("c002_cross_m", "b"): list(lc._cb),
    ("c002_cross_m", "K"): list(lc._CK), ("c002_cross_mn", "K"): list(lc._CK),
    ("c002_cross_mn", "a"): list(lc._ca), ("c002_cross_mn", "M"): list(lc._CM),
    ("c002_cross_mn", "N"): list(lc._CN), ("c002_cross_mn", "b"): list(lc._cb),
    ("c002_rotation", "q"): list(lc._rq), ("c002_rotation", "S"): list(lc._RS), ("c002_rotation", "x"): list(lc._rx),
    ("c002_spd_bound", "J"): [lc._JJ[i, j] for i in range(3) for j in range(i, 3)],
    ("c002_spd_bound", "c"): list(lc._jc), ("c002_spd_bound", "d"): list(lc._jd),
    ("c002_spd_bound", "b"): [lc._jb], ("c002_spd_bound", "S"): list(lc._JS), ("c002_spd_bound", "y"): list(lc._jy),
}


def _upper(M: sp.Matrix) -> list:
    return [M[i, j] for i in range(3) for j in range(i, 3)]


def _remark4_Cr(st: Statement) -> Plan:
    """Remark 4 (corrected, factor 3), eq. 4: C_r w = (J P + P J - (J (w + p))^x) w with p = R omega_t,
    P = p^x.  Composed of the lemmas of ``lemmas_c002`` (norms as the claim writes them):

    |C_r w| <= |J P w| + |P J w| + |(J v)^x w|              triangle (matrix form), v = w + p
    |J P w| <= b1 |P w| <= b1 |p| |w|                          J bound, cross product (weight b1)
    |P J w| <= |p| |J w| <= b1 |p| |w|                         cross product, J bound (weight |p|)
    |(J v)^x w| <= |J v| |w| <= b1 |v| |w| <= b1 (|w| + |p|) |w|   cross, J bound (|w|), triangle (b1 |w|)
    |p| = |q|^2 |omega_t| <= |q|^2 a1 |y|                       rotation (weight 3 b1 |w|), scale (3 b1 |w| |q|^2)

    which leaves 3 a1 b1 |w| (1 - |q|^2 |y|) = 3 a1 b1 |w| (1 - (1 - A) sqrt(1 - B)) with A, B products of
    factors in [0, 1] (the charts below), closed by one natural enclosure.  Charts: J = C diag(b1 f) C^T with
    C = R(c)/|c|^2, c on a cube face (4 regions), f in [1/8, 1]^3 (the eigenvalues d_i = b1 f_i cover
    [5, b1] for b1 in [5, 40]; b1 = max d is the case f_max = 1); q in the unit ball of R^4 (contains the
    unit quaternions); omega_t = a1 y, y in the unit ball of R^3 (cube charts)."""
    n = {s.name: s for s in st.free_symbols()}
    w = sp.Matrix([n[f"omega_{i}"] for i in (1, 2, 3)])
    wt = sp.Matrix([n[f"omega_t_{i}"] for i in (1, 2, 3)])
    q = sp.Matrix([n[f"q_{i}"] for i in (1, 2, 3, 0)])
    a1, b1 = n["a_1"], n["b_1"]
    J = sp.Matrix(3, 3, lambda i, j: n[f"J_{min(i, j) + 1}{max(i, j) + 1}"])
    cy, t, u = (list(sp.symbols(f"{x}_1:4", real=True)) for x in ("cy", "t", "u"))
    sg = sp.Symbol("sg", real=True)
    f = list(sp.symbols("f_1:4", positive=True))
    R = c.dcm_pursuer_from_target(q)
    p = R * wt
    P = skew(p)
    I3 = sp.eye(3)
    y = _ball3(cy)
    nw, npv = sp.sqrt(dot(w, w)), sp.sqrt(dot(p, p))
    Q = dot(q, q)
    coords = (*[Coordinate(x, -0.01, 0.01, "rad/s") for x in w], Coordinate(a1, 0.05, 0.5, "rad/s"),
              *[Coordinate(x, -1.0, 1.0, "1") for x in cy + t + [sg] + u], Coordinate(b1, 5.0, 40.0, "kg m^2"),
              *[Coordinate(x, 0.125, 1.0, "1") for x in f])
    d = [b1 * x for x in f]
    regions, uses = [], []
    for k, face in enumerate(_faces(u)):
        # the J chart exactly as the lemma's premise builds it (so that J - C diag(d) C^T is 0 as written)
        Jc = lc._JX.xreplace({**dict(zip(lc._jc, face, strict=True)), **dict(zip(lc._jd, d, strict=True))})
        subs = {**dict(zip(_upper(J), _upper(Jc), strict=True)), **dict(zip(q, _ball4(t, sg), strict=True)),
                **dict(zip(wt, [a1 * x for x in y], strict=True))}
        regions.append(Region(coords, subs, describe=f"J = C diag(b1 f) C^T, C = R(c)/|c|^2, c_{(1, 2, 3, 0)[k]} = 1"))
        spd = {"J": _upper(J), "c": face, "d": d, "b": b1}
        uses += [_use(lc.SPD_BOUND, sp.S.One, k, S=P, y=w, **spd),           # |J P w| <= b1 |P w|
                 _use(lc.SPD_BOUND, npv, k, S=I3, y=w, **spd),               # |J w| <= b1 |w|
                 _use(lc.SPD_BOUND, nw, k, S=-I3, y=w + p, **spd)]           # |J v| <= b1 |v|
    uses += [_use(lc.TRIANGLE_M3, A=J * P, B=P * J, C=-skew(J * (w + p)), w=w),
             _use(lc.CROSS_M, b1, a=p, K=P, M=I3, b=w),
             _use(lc.CROSS_M, sp.S.One, a=p, K=P, M=J, b=w),
             _use(lc.CROSS_M, sp.S.One, a=-(J * (w + p)), K=-skew(J * (w + p)), M=I3, b=w),
             _use(lc.TRIANGLE_V2, b1 * nw, x=-w, y=-p),
             _use(lc.ROTATION, 2 * b1 * nw, q=q, S=I3, x=wt),
             _use(lc.ROTATION, b1 * nw, q=q, S=I3, x=-wt),
             _use(lc.SCALE, 3 * b1 * nw * Q.xreplace(dict(zip(q, _ball4(t, sg), strict=True))), s=a1, x=y)]
    A = (1 - sg**2) * _prod1m(t)
    B = _prod1m(cy)
    target = 3 * a1 * b1 * nw * (1 - (1 - A) * sp.sqrt(1 - B))
    return Plan(regions, "omega~ in [-0.01, 0.01]^3 rad/s, a1 in [0.05, 0.5] rad/s, ||omega_t|| <= a1, q any "
                         "quaternion with |q| <= 1 (contains the unit ones), J = C diag(d) C^T with C any rotation "
                         "and d_i in [b1/8, b1], b1 in [5, 40] kg m^2 (contains d_i in [5, 40] with b1 = max d)",
                reduce=lambda g: target, reduce_side=_small_factor, uses=tuple(uses))


def _remark5_nt(st: Statement) -> Plan:
    """Remark 5 (corrected, with gravity), eq. 9: with g_p = R v_t_dot - Deltag the claim's n_t is
    n_t = (P R) v_t + Deltag + ((P P) R) sigma_t - (R sigma_t^x) omegadot_t, p = R omega_t, P = p^x.  Composed of
    the lemmas of ``lemmas_c002``:

    |m n_t| = m |n_t| <= m (|(P R) v_t| + |Deltag| + |((P P) R) sigma_t| + |(R sigma_t^x) omegadot_t|)
    |(P R) v_t| <= |p| |R v_t|,  |((P P) R) sigma| <= |p| |(P R) sigma| <= |p|^2 |R sigma|   (cross products)
    |(R sigma^x) omegadot| = |q|^2 |sigma^x omegadot| <= |q|^2 |sigma| |omegadot|             (rotation, cross)
    |R x| = |q|^2 |x| (rotation), and the ball charts x = a y (scale: |a y| = a |y|)

    which leaves m [a1 a3 (1 - Q^2 |y1| |y3|) + a4 (1 - |y5|) + sigmanorm a1 |w~| + sigmanorm a2 (1 - Q |y4| |y2|)
    + a1^2 sigmanorm (1 - Q^3 |y4| |y1|^2)] with Q = |q|^2 = 1 - A and |y_k| = sqrt(1 - B_k), A, B_k products of
    factors in [0, 1]: one natural enclosure.  Charts: omega_t = a1 y1, omegadot_t = a2 y2, v_t = a3 y3,
    sigma_t = sigmanorm y4, Deltag = a4 y5 with y_k in the unit ball (cube charts), q in the unit ball of R^4,
    b3 = m (the claim's domain)."""
    n = {s_.name: s_ for s_ in st.free_symbols()}

    def vec(name):
        return sp.Matrix([n[f"{name}_{i}"] for i in (1, 2, 3)])

    w, wt, wd, vt, sig, dg = (vec(x) for x in ("omega", "omega_t", "omegadot_t", "v_t", "sigma_t", "Deltag"))
    q = sp.Matrix([n[f"q_{i}"] for i in (1, 2, 3, 0)])
    a1, a2, a3, a4, m, b3, sn = (n[x] for x in ("a_1", "a_2", "a_3", "a_4", "m", "b_3", "sigmanorm"))
    cys = [list(sp.symbols(f"cy{k}_1:4", real=True)) for k in range(1, 6)]
    t = list(sp.symbols("t_1:4", real=True))
    sg = sp.Symbol("sg", real=True)
    ys = [sp.Matrix(_ball3(cy)) for cy in cys]
    R = c.dcm_pursuer_from_target(q)
    p = R * wt
    P = skew(p)
    Ks = skew(sig)
    I3 = sp.eye(3)
    nrm = lc._nrm
    qc = _ball4(t, sg)
    Q = dot(q, q)
    Qc = Q.xreplace(dict(zip(q, qc, strict=True)))
    pp = dot(p, p)
    C = (R * Ks) * wd
    nt = P * R * vt + dg + P * P * R * sig - C
    radii = (a1, a2, a3, sn, a4)
    scale = [_use(lc.SCALE, wk, s=r_, x=y) for wk, r_, y in (
        (m * Qc**2 * nrm(vt), a1, ys[0]),                 # |omega_t| in Q^2 |omega_t| |v_t|
        (m * Qc**2 * a1 * nrm(ys[0]), a3, ys[2]),         # |v_t|
        (m, a4, ys[4]),                                   # |Deltag|
        (m * Qc**3 * a1**2 * dot(ys[0], ys[0]), sn, ys[3]),   # |sigma|
        (m * Qc * nrm(wd), sn, ys[3]),                    # |sigma| in Q |sigma| |omegadot|
        (m * Qc * sn * nrm(ys[3]), a2, ys[1]))]           # |omegadot|
    uses = [_use(lc.SCALE, sp.S.One, s=m, x=nt),
            _use(lc.TRIANGLE_V4, m, x=P * R * vt, y=dg, z=P * P * R * sig, w=-C),
            _use(lc.CROSS_M, m, a=p, K=P, M=R, b=vt),
            _use(lc.CROSS_MN, m, a=p, K=P, M=P, N=R, b=sig),
            _use(lc.CROSS_M, m * nrm(p), a=p, K=P, M=R, b=sig),
            _use(lc.ROTATION, m, q=q, S=Ks, x=-wd),
            _use(lc.CROSS_M, m * Q, a=sig, K=Ks, M=I3, b=-wd),
            _use(lc.ROTATION, m * nrm(p), q=q, S=I3, x=vt),              # |R v_t|
            _use(lc.ROTATION, m * Q * nrm(vt), q=q, S=I3, x=wt),         # |p|
            _use(lc.ROTATION, m * pp, q=q, S=I3, x=sig),                 # |R sigma|
            _use(lc.ROTATION, m * Q * nrm(sig) * nrm(p), q=q, S=I3, x=wt),   # |p|^2 = |p| |p|
            _use(lc.ROTATION, m * Q**2 * nrm(sig) * nrm(wt), q=q, S=I3, x=wt),
            *scale]
    A = (1 - sg**2) * _prod1m(t)
    Bs = [_prod1m(cy) for cy in cys]
    ny = [sp.sqrt(1 - B) for B in Bs]
    Qt = 1 - A
    target = m * (a1 * a3 * (1 - Qt**2 * ny[0] * ny[2]) + a4 * (1 - ny[4]) + sn * a1 * nrm(w)
                  + sn * a2 * (1 - Qt * ny[3] * ny[1]) + a1**2 * sn * (1 - Qt**3 * ny[3] * (1 - Bs[0])))
    subs = {b3: m, **dict(zip(q, qc, strict=True))}
    for vec_, r_, y in zip((wt, wd, vt, sig, dg), radii, ys, strict=True):
        subs.update(dict(zip(vec_, [r_ * x for x in y], strict=True)))
    coords = (*[Coordinate(x, -1.0, 1.0, "rad/s") for x in w],
              *[Coordinate(x, 0.001, 0.5, u_) for x, u_ in ((a1, "rad/s"), (a2, "rad/s^2"))],
              Coordinate(a3, 0.01, 10.0, "m/s"), Coordinate(a4, 0.01, 10.0, "m/s^2"),
              Coordinate(m, 20.0, 200.0, "kg"), Coordinate(sn, 0.1, 10.0, "m"),
              *[Coordinate(x, -1.0, 1.0, "1") for x in sum(cys, []) + t + [sg]])
    reg = Region(coords, subs, describe="b3 = m; omega_t, omegadot_t, v_t, sigma_t, Deltag = radius times the "
                                        "unit-ball chart; q in the unit ball of R^4")
    return Plan([reg], "omega~ in [-1, 1]^3 rad/s, a1, a2 in [0.001, 0.5], a3, a4 in [0.01, 10], m = b3 in "
                       "[20, 200] kg, sigmanorm in [0.1, 10] m, ||omega_t|| <= a1, ||omegadot_t|| <= a2, "
                       "||v_t|| <= a3, ||sigma_t|| <= sigmanorm, ||Deltag|| <= a4, q any quaternion with |q| <= 1 "
                       "(contains the unit ones), v_t_dot any (it cancels from R v_t_dot - g_p = Deltag)",
                reduce=lambda g: target, reduce_side=_small_factor, uses=tuple(uses))


PLANS: dict = {
    "c002.V1.lemma2_unit_terms": _lemma2_unit,
    "c002.V1.residual_set": _residual_set,
    "c002.model.remark4_Cr": _remark4_Cr,
    "c002.model.remark5_nt": _remark5_nt,
}
