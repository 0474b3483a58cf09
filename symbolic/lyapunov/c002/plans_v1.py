"""002: proof plans of the model, V1 and gain claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...physics.rotations import dot, skew
from ..certify import Coordinate, Plan, Region
from ..certify import lemmas_c002 as lc
from ..certify.lemmas import ABS_PRODUCT, DOT_BALL3, MIN_LE, YOUNG
from ..certify.plan import Use, composed, gaps
from ..core import Statement
from .common import PAPER_GAINS


#: the note of a plan that leaves out a declared-positive symbol's value 0, which the search also draws
def _positive_note(what: str) -> str:
    return (f"{what} is declared positive in the statement, the search also draws 0: the certified domain takes "
            f"it in [1e-300, ...] and the sliver below 1e-300 (0 included) is left not-disproved")


def _by_name(st: Statement) -> dict:
    """The statement's symbols by name."""
    return {s.name: s for s in st.free_symbols()}


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
                       "the statement's symbol is declared)", covers_search_domain=False,
                note=_positive_note("||s||"))
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
    ("c002_lemma2", "z"): [lc._lz], ("c002_lemma2", "eps"): [lc._le],
    ("c002_rotation", "q"): list(lc._rq), ("c002_rotation", "S"): list(lc._RS), ("c002_rotation", "x"): list(lc._rx),
    ("c002_spd_bound", "J"): [lc._JJ[i, j] for i in range(3) for j in range(i, 3)],
    ("c002_spd_bound", "c"): list(lc._jc), ("c002_spd_bound", "d"): list(lc._jd),
    ("c002_spd_bound", "b"): [lc._jb], ("c002_spd_bound", "S"): list(lc._JS), ("c002_spd_bound", "y"): list(lc._jy),
    ("c002_spd_shift", "J"): [lc._JJ[i, j] for i in range(3) for j in range(i, 3)],
    ("c002_spd_shift", "c"): list(lc._jc), ("c002_spd_shift", "d"): list(lc._jd),
    ("c002_spd_shift", "h"): [lc._sh], ("c002_spd_shift", "S"): list(lc._JS), ("c002_spd_shift", "y"): list(lc._jy),
    ("c002_euler_form", "J"): [lc._JJ[i, j] for i in range(3) for j in range(i, 3)],
    ("c002_euler_form", "R"): list(lc._ER), ("c002_euler_form", "h"): [lc._sh],
    ("c002_euler_form", "w"): list(lc._ew), ("c002_euler_form", "wt"): list(lc._ewt),
    ("c002_euler_form", "wd"): list(lc._ewd),
    ("c002_quat_rate", "q"): list(lc._rq), ("c002_quat_rate", "y"): list(lc._qy),
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


def _nt_chain(n: dict):
    """The composition of Remark 5 (see :func:`_remark5_nt`) for |m n_t| as the lemmas bound it: the uses, the
    rest they leave (``target``), the charts (``subs``, ``coords``) and the pieces the plans share (the
    rotation R, p = R omega_t, the ball of q and |q|^2 on it)."""

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
    return {"uses": uses, "target": target, "subs": subs, "coords": coords, "R": R, "p": p, "q": q, "Qc": Qc,
            "Qt": Qt, "y1": ys[0], "ny1": ny[0], "wt": wt, "w": w, "nt": nt}


def _remark5_nt(st: Statement) -> Plan:
    """Remark 5 (corrected, with gravity), eq. 9: with g_p = R v_t_dot - Deltag the claim's n_t is
    n_t = (P R) v_t + Deltag + ((P P) R) sigma_t - (R sigma_t^x) omegadot_t, p = R omega_t, P = p^x.  Composed of
    the lemmas of ``lemmas_c002`` (:func:`_nt_chain`):

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
    ch = _nt_chain(n)
    reg = Region(ch["coords"], ch["subs"], describe="b3 = m; omega_t, omegadot_t, v_t, sigma_t, Deltag = radius "
                                                    "times the unit-ball chart; q in the unit ball of R^4")
    return Plan([reg], "omega~ in [-1, 1]^3 rad/s, a1, a2 in [0.001, 0.5], a3, a4 in [0.01, 10], m = b3 in "
                       "[20, 200] kg, sigmanorm in [0.1, 10] m, ||omega_t|| <= a1, ||omegadot_t|| <= a2, "
                       "||v_t|| <= a3, ||sigma_t|| <= sigmanorm, ||Deltag|| <= a4, q any quaternion with |q| <= 1 "
                       "(contains the unit ones), v_t_dot any (it cancels from R v_t_dot - g_p = Deltag)",
                reduce=lambda g, target=ch["target"]: target, reduce_side=_small_factor, uses=tuple(ch["uses"]))


def _lumped_position(st: Statement) -> Plan:
    """Eq. 22 (corrected alpha9, with gravity): Phi2 = a + b + d_t + e + f with a = -m C_t v~, b = -m n_t,
    e = k5 m r~_dot (r~_dot = v~ - C_t r~), f = kappa2 tanh chi2, C_t = (w~ + p)^x, p = R omega_t (eq. 7).
    Composed of the lemmas of ``lemmas_c002``:

    |Phi2| <= |a| + |b| + |d_t| + |e + f|,  |e + f| <= |e| + |f|                 triangle
    |a| = |(-m C_t) v~| <= |m (w~ + p)| |v~| <= m (|w~| + |p|) |v~|            cross, scale, triangle
    |e| <= k5 m |r~_dot| <= k5 m (|v~| + |C_t r~|) <= k5 m (|v~| + (|w~| + |p|) |r~|)
    |p| = |q|^2 |omega_t| <= |q|^2 a1 |y1|                                       rotation, scale
    |b| <= Remark 5's chain (:func:`_nt_chain`),  |d_t| = D2 |y6|,  |f| = kappa2 |tanh chi2|   (scale)

    which leaves m a1 (|v~| + k5 |r~|)(1 - Q |y1|) + Remark 5's rest + D2 (1 - |y6|) + kappa2 (sqrt 3 - |tanh chi2|),
    a sum of nonnegative terms (|tanh chi_i| <= tanh 3 on the box): one natural enclosure each.  Charts as in
    Remark 5, d_t = D2 y6 (unit-ball cube chart)."""
    from .model import _Bounds

    n = {s_.name: s_ for s_ in st.free_symbols()}
    ch = _nt_chain(n)
    B = _Bounds()
    S = B.S
    w, v, r, chi = S.w, S.v, S.r, S.chi2
    m, k5, kap, D2, a1 = S.m, S.k5, S.kappa2, B.D2, n["a_1"]
    R, p, q, wt = ch["R"], ch["p"], ch["q"], ch["wt"]
    I3 = sp.eye(3)
    nrm = lc._nrm
    C_t = c.translation_rate_matrix(w, R, wt)
    rdot = c.relative_position_rate(v, C_t, r)
    a = -m * C_t * v
    b = -m * ch["nt"]
    e = k5 * m * rdot
    f = kap * c.tanh_vec(chi)
    cd = list(sp.symbols("cy6_1:4", real=True))
    y6 = sp.Matrix(_ball3(cd))
    Qc = ch["Qc"]
    wp = -(w + p)
    uses = [*ch["uses"],
            _use(lc.TRIANGLE_V4, sp.S.One, x=a, y=b, z=S.d_t, w=e + f),
            _use(lc.TRIANGLE_V2, sp.S.One, x=e, y=f),
            # |a|
            _use(lc.CROSS_M, sp.S.One, a=m * wp, K=skew(m * wp), M=I3, b=v),
            _use(lc.SCALE, nrm(v), s=m, x=wp),
            _use(lc.TRIANGLE_V2, m * nrm(v), x=-w, y=-p),
            _use(lc.ROTATION, m * nrm(v), q=q, S=I3, x=-wt),
            _use(lc.SCALE, m * nrm(v) * Qc, s=a1, x=ch["y1"]),
            # |e|
            _use(lc.SCALE, sp.S.One, s=k5 * m, x=rdot),
            _use(lc.TRIANGLE_V2, k5 * m, x=v, y=-(C_t * r)),
            _use(lc.CROSS_M, k5 * m, a=wp, K=-C_t, M=I3, b=r),
            _use(lc.TRIANGLE_V2, k5 * m * nrm(r), x=-w, y=-p),
            _use(lc.ROTATION, k5 * m * nrm(r), q=q, S=I3, x=-wt),
            _use(lc.SCALE, k5 * m * nrm(r) * Qc, s=a1, x=ch["y1"]),
            # |d_t|, |f|
            _use(lc.SCALE, sp.S.One, s=D2, x=y6),
            _use(lc.SCALE, sp.S.One, s=kap, x=c.tanh_vec(chi))]
    target = (ch["target"] + m * a1 * (nrm(v) + k5 * nrm(r)) * (1 - ch["Qt"] * ch["ny1"])
              + D2 * (1 - sp.sqrt(1 - _prod1m(cd))) + kap * (sp.sqrt(3) - nrm(c.tanh_vec(chi))))
    subs = {**ch["subs"], **dict(zip(S.d_t, [D2 * x for x in y6], strict=True))}
    coords = (*ch["coords"], *[Coordinate(x, -2.0, 2.0, "m/s") for x in v],
              *[Coordinate(x, -20.0, 20.0, "m") for x in r], *[Coordinate(x, -3.0, 3.0, "1") for x in chi],
              Coordinate(k5, 0.5, 3.0, "1/s"), Coordinate(kap, 0.01, 2.0, "N"),
              Coordinate(D2, 1e-300, 0.01, "N"), *[Coordinate(x, -1.0, 1.0, "1") for x in cd])
    reg = Region(coords, subs, describe="b3 = m; omega_t, omegadot_t, v_t, sigma_t, Deltag, d_t = radius times the "
                                        "unit-ball chart; q in the unit ball of R^4")
    return Plan([reg], "omega~ in [-1, 1]^3 rad/s, v~ in [-2, 2]^3 m/s, r~ in [-20, 20]^3 m, chi2 in [-3, 3]^3, "
                       "k5 in [0.5, 3] 1/s, kappa2 in [0.01, 2] N, D2 in (0, 0.01] N (declared positive), a1, a2 in "
                       "[0.001, 0.5], a3, a4 in [0.01, 10], m = b3 in [20, 200] kg, sigmanorm in [0.1, 10] m, "
                       "||omega_t|| <= a1, ||omegadot_t|| <= a2, ||v_t|| <= a3, ||sigma_t|| <= sigmanorm, "
                       "||Deltag|| <= a4, ||d_t|| <= D2, q any quaternion with |q| <= 1 (contains the unit ones), "
                       "v_t_dot any (it cancels from R v_t_dot - g_p = Deltag)",
                reduce=lambda g: target, reduce_side=_small_factor, uses=tuple(uses), covers_search_domain=False,
                note=_positive_note("D2"))


def _lumped_attitude(st: Statement) -> Plan:
    """Eq. 21 with the paper's alpha1..3 (Remark 4), eqs. 3-4: Phi1 = V + d_r + K + T with V = -C_r w~ - n_r,
    K = k1 J q_v_dot, T = kappa1 tanh chi1.  With p = R omega_t, u = w~ + p and c = b1/2, eq. 4 regrouped
    (``c002_euler_form``, an identity) is V = A + B + C, A = ((J - c I) u) x u, B = (J w~^x) p, C = (J R)(-omegadot_t).
    Composed of the lemmas of ``lemmas_c002``:

    |Phi1| <= |V| + |d_r| + |K| + |T|,  |V| = |A + B + C| <= |A| + |B| + |C|          triangle, eq. 4 regrouped
    |A| <= |(J - c I) u| |u| <= c |u|^2 <= c (|w~| + |p|)^2        cross, shifted spectrum (|d_i - c| <= c), triangle
    |B| <= b1 |w~^x p| <= b1 |w~| |p|,  |C| <= b1 |R omegadot_t| = b1 |q|^2 |omegadot_t|   J bound, cross, rotation
    |K| <= b1 |k1 q_v_dot| <= b1 k1 |q| |w~| / 2                    J bound, scale, |(q_v^x + q0 I) y| <= |q| |y|
    |p| = |q|^2 |omega_t|, |omega_t| = a1 |y1|, |omegadot_t| = a2 |y2|, |d_r| = D1 |y3|, |T| = kappa1 |tanh chi1|
    b1 |w~| P <= b1 |w~|^2/2 + b1 P^2/2  (Young, P = |q|^2 a1 |y1|)

    which leaves b1 a1 |w~| (1 - Q |y1|) + b1 a1^2 (1 - Q^2 |y1|^2) + b1 a2 (1 - Q |y2|) + D1 (1 - |y3|) + k1 b1 |w~|
    (1 - |q|)/2 + kappa1 (sqrt 3 - |tanh chi1|), Q = |q|^2 = 1 - A_q and |y_k| = sqrt(1 - B_k) with A_q, B_k products of
    factors in [0, 1]: a sum of nonnegative terms, one natural enclosure.  (The bilinear part totals 2 a1 b1 |w~|,
    Remark 4 counts a1 b1 |w~|; the shifted spectrum gives |(J u) x u| <= b1/2 |u|^2, half of what alpha1 = b1 and
    alpha3's a1^2 b1 allow, and Young spends that slack on the second a1 b1 |w~|.)
    Charts as in :func:`_remark4_Cr` (J = C diag(b1 f) C^T, C = R(c)/|c|^2 on the four cube faces of c; q in the unit
    ball of R^4), omega_t = a1 y1, omegadot_t = a2 y2, d_r = D1 y3 (unit-ball cube charts)."""
    from .model import _Bounds

    n = {s_.name: s_ for s_ in st.free_symbols()}
    B = _Bounds()
    S = B.S
    w, chi, J = S.w, S.chi1, S.J
    wt, wd = B.w_t, B.wd_t
    q = S.q
    a1, a2, b1, D1, k1, kap = (n[x] for x in ("a_1", "a_2", "b_1", "D_1", "k_1", "kappa_1"))
    cys = [list(sp.symbols(f"cy{k}_1:4", real=True)) for k in range(1, 4)]
    ys = [sp.Matrix(_ball3(cy)) for cy in cys]
    t = list(sp.symbols("t_1:4", real=True))
    sg = sp.Symbol("sg", real=True)
    u_ = list(sp.symbols("u_1:4", real=True))
    f = list(sp.symbols("f_1:4", positive=True))
    nrm = lc._nrm
    I3 = sp.eye(3)
    R = c.dcm_pursuer_from_target(q)
    p = R * wt
    u = w + p
    h = b1 / 2
    qc = _ball4(t, sg)
    Qc = dot(q, q).xreplace(dict(zip(q, qc, strict=True)))
    Q = dot(q, q)
    # the claim's pieces, built as model._Bounds builds Phi1
    n_r = c.attitude_nonlinear_term(J, R, wt, wd)
    V = -B.C_r * w - n_r
    K = S.k1 * J * c.relative_quaternion_rate(q, w)[:3, :]
    T = S.kappa1 * c.tanh_vec(chi)
    qv_dot = c.relative_quaternion_rate(q, w)[:3, :]
    a = (J - h * I3) * u
    A = skew(a) * u
    Bv = (J * skew(w)) * p
    Cv = (J * R) * (-wd)
    d = [b1 * x for x in f]
    ya, yb, ye = YOUNG.symbols
    uses = [_use(lc.TRIANGLE_V4, sp.S.One, x=V, y=S.d_r, z=K, w=T),
            _use(lc.EULER_FORM, sp.S.One, J=_upper(J), R=list(R), h=h, w=w, wt=wt, wd=wd),
            _use(lc.TRIANGLE_V4, sp.S.One, x=A, y=Bv, z=Cv, w=sp.zeros(3, 1)),
            # |A|
            _use(lc.CROSS_M, sp.S.One, a=a, K=skew(a), M=I3, b=u),
            _use(lc.TRIANGLE_V2, h * nrm(u), x=w, y=p),
            _use(lc.TRIANGLE_V2, h * nrm(w), x=w, y=p),
            _use(lc.TRIANGLE_V2, h * nrm(p), x=w, y=p),
            # |B|
            _use(lc.CROSS_M, b1, a=w, K=skew(w), M=I3, b=p),
            # |p| (2 b1 |w~| |p| from A and B; c |p|^2 from A), |omegadot_t|
            _use(lc.ROTATION, 2 * b1 * nrm(w), q=q, S=I3, x=wt),
            _use(lc.SCALE, 2 * b1 * nrm(w) * Qc, s=a1, x=ys[0]),
            _use(lc.ROTATION, h * nrm(p), q=q, S=I3, x=wt),
            _use(lc.ROTATION, h * Q * nrm(wt), q=q, S=I3, x=wt),
            _use(lc.ROTATION, b1, q=q, S=I3, x=-wd),
            _use(lc.SCALE, b1 * Qc, s=a2, x=ys[1]),
            # |K|
            _use(lc.SCALE, b1, s=k1, x=qv_dot),
            _use(lc.QUAT_RATE, b1 * k1, q=q, y=w),
            # |d_r|, |T|
            _use(lc.SCALE, sp.S.One, s=D1, x=ys[2]),
            _use(lc.SCALE, sp.S.One, s=kap, x=c.tanh_vec(chi)),
            Use(YOUNG, {ya: nrm(w), yb: Qc * a1 * nrm(ys[0]), ye: sp.S.One}, b1)]
    coords = (*[Coordinate(x, -1.0, 1.0, "rad/s") for x in w],
              Coordinate(a1, 0.001, 0.5, "rad/s"), Coordinate(a2, 0.001, 0.5, "rad/s^2"),
              Coordinate(b1, 5.0, 40.0, "kg m^2"), *[Coordinate(x, 0.125, 1.0, "1") for x in f],
              *[Coordinate(x, -1.0, 1.0, "1") for x in sum(cys, []) + t + [sg] + u_],
              *[Coordinate(x, -3.0, 3.0, "1") for x in chi], Coordinate(k1, 0.5, 3.0, "1/s"),
              Coordinate(kap, 0.01, 2.0, "N m"), Coordinate(D1, 1e-300, 0.01, "N m"))
    regions = []
    for k, face in enumerate(_faces(u_)):
        Jc = lc._JX.xreplace({**dict(zip(lc._jc, face, strict=True)), **dict(zip(lc._jd, d, strict=True))})
        subs = {**dict(zip(_upper(J), _upper(Jc), strict=True)), **dict(zip(q, qc, strict=True))}
        for vec_, r_, y in zip((wt, wd, S.d_r), (a1, a2, D1), ys, strict=True):
            subs.update(dict(zip(vec_, [r_ * x for x in y], strict=True)))
        regions.append(Region(coords, subs, describe=f"J = C diag(b1 f) C^T, C = R(c)/|c|^2, c_{(1, 2, 3, 0)[k]} = 1; "
                                                     "omega_t, omegadot_t, d_r = radius times the unit-ball chart"))
        spd = {"J": _upper(J), "c": face, "d": d}
        uses += [_use(lc.SPD_SHIFT, nrm(u), k, S=I3, y=u, h=h, **spd),        # |(J - c I) u| <= c |u|
                 _use(lc.SPD_BOUND, sp.S.One, k, S=skew(w), y=p, b=b1, **spd),   # |J w~^x p| <= b1 |w~^x p|
                 _use(lc.SPD_BOUND, sp.S.One, k, S=R, y=-wd, b=b1, **spd),       # |(J R) wd| <= b1 |R wd|
                 _use(lc.SPD_BOUND, sp.S.One, k, S=k1 * I3, y=qv_dot, b=b1, **spd)]   # |(k1 J) qv_dot|
    Aq = (1 - sg**2) * _prod1m(t)
    Bs = [_prod1m(cy) for cy in cys]
    ny = [sp.sqrt(1 - B_) for B_ in Bs]
    Qt = 1 - Aq
    nw = nrm(w)
    target = (b1 * a1 * nw * (1 - Qt * ny[0]) + b1 * a1**2 * (1 - Qt**2 * (1 - Bs[0])) + b1 * a2 * (1 - Qt * ny[1])
              + D1 * (1 - ny[2]) + k1 * b1 * nw * (1 - sp.sqrt(Qt)) / 2
              + kap * (sp.sqrt(3) - nrm(c.tanh_vec(chi))))
    return Plan(regions, "omega~ in [-1, 1]^3 rad/s, a1 in [0.001, 0.5] rad/s, a2 in [0.001, 0.5] rad/s^2, "
                          "||omega_t|| <= a1, ||omegadot_t|| <= a2, ||d_r|| <= D1, D1 in (0, 0.01] N m (declared "
                          "positive), k1 in [0.5, 3] 1/s, kappa1 in [0.01, 2] N m, chi1 in [-3, 3]^3, q any quaternion "
                          "with |q| <= 1 (contains the unit ones), J = C diag(d) C^T with C any rotation and d_i in "
                          "[b1/8, b1], b1 in [5, 40] kg m^2 (contains d_i in [5, 40] with b1 = max d)",
                reduce=lambda g: target, reduce_side=_small_factor, uses=tuple(uses), covers_search_domain=False,
                note=_positive_note("D1"))


# --------------------------------------------------------------------------- eq. 29: the bound on V1_dot

def _v1_bound(st: Statement) -> Plan:
    """Eq. 29 (corrected 9 + k3 + k7, or the printed 11 at the paper's gains): after eq. 25 the parameter-error
    terms of V1_dot cancel against sum gamma_i alpha~_i alpha^_i exactly (c002.V1.adaptation_cancels), the k4, k8
    terms cancel, and what is left is, exactly,

    sum_i [Lemma 2 at X_i = alpha^_i Y_i ||s_j||] + sum_i [|alpha^_i| - alpha^_i] ||s_j|| Y_i
    + Lemma 2 (times k3, k7) at ||s_1||, ||s_2|| + sum_j [||s_j|| rho_j - s_j . Phi_j] + rest,

    with Y_i the regressors of eq. 25 and rho_j the bounds of eqs. 21-22 (sum_i alpha_i Y_i): Lemma 2
    (``c002_lemma2``, constant c = 0.31, with z = X_i^2 as the statement writes the root), s d <= |s| D
    (``abs_product``) and the ball form of Cauchy-Schwarz (``dot_ball_3``, Phi_j in the ball of radius rho_j)
    leave rest = (c_eps - 0.31 (9 + k3 + k7)) eps, >= 0 for c_eps = 9 + k3 + k7 and for 11 at k3 + k7 = 4.5.
    The boxes certify the weights and premises (z_i >= 0, rho_j >= 0, rho_j^2 - |Phi_j|^2 >= 0: the chart
    Phi_j = rho_j y, y in the unit ball (cube chart))."""
    n = _by_name(st)

    def vec(name):
        return sp.Matrix([n[f"{name}_{i}"] for i in (1, 2, 3)])

    w, v, r = vec("omega"), vec("v"), vec("r")
    s1, s2, P1, P2 = vec("s_1"), vec("s_2"), vec("Phi1"), vec("Phi2")
    ah = [n[f"alphahat_{i}"] for i in range(1, 10)]
    al = [n[f"alpha_{i}"] for i in range(1, 10)]
    ga = [n[f"gamma_{i}"] for i in range(1, 10)]
    k3, k4, k7, k8, eps = (n[x] for x in ("k_3", "k_4", "k_7", "k_8", "varepsilon"))
    nrm = lc._nrm
    nw, nv, nr = nrm(w), nrm(v), nrm(r)
    Y = [nw**2, nw, sp.S.One, nw * nv, nw * nr, nw, nv, nr, sp.S.One]
    sj = [s1] * 3 + [s2] * 6
    rho = [sum(al[i] * Y[i] for i in range(3)), sum(al[i] * Y[i] for i in range(3, 9))]
    sa, da, Da = ABS_PRODUCT.symbols
    uses = []
    for i in range(9):
        ss = dot(sj[i], sj[i])
        uses.append(_use(lc.LEMMA2, sp.S.One, z=ah[i] ** 2 * Y[i] ** 2 * ss, eps=eps))
        uses.append(Use(ABS_PRODUCT, {sa: ah[i], da: nrm(sj[i]) * Y[i], Da: nrm(sj[i]) * Y[i]}))
    for k_, s_ in ((k3, s1), (k7, s2)):
        uses.append(_use(lc.LEMMA2, k_, z=dot(s_, s_), eps=eps))
    dx, dy, dr = DOT_BALL3.symbols[:3], DOT_BALL3.symbols[3:6], DOT_BALL3.symbols[6]
    for s_, P_, rh in ((s1, P1, rho[0]), (s2, P2, rho[1])):
        uses.append(Use(DOT_BALL3, {**dict(zip(dx, s_, strict=True)), **dict(zip(dy, P_, strict=True)), dr: rh}))
    c_eps = sp.expand(gaps(st)[0]).coeff(eps).subs({x: 0 for x in (*s1, *s2, *w, *v, *r, *P1, *P2, *ah, *al, *ga,
                                                                    k4, k8)})
    cy = [list(sp.symbols(f"cphi{j}_1:4", real=True)) for j in (1, 2)]
    ys = [_ball3(c_) for c_ in cy]
    subs = {**dict(zip(P1, [rho[0] * x for x in ys[0]], strict=True)),
            **dict(zip(P2, [rho[1] * x for x in ys[1]], strict=True))}
    paper = k3 not in c_eps.free_symbols     # eq. 29 as printed, at the paper's gains (c002.gains.eq29_constant)
    coords = []
    for sym, lo, hi, unit in ((k3, 0.01, 40.0, "1/s"), (k7, 0.01, 40.0, "1/s"), (k4, 0.01, 10.0, "1/s"),
                              (k8, 0.1, 50.0, "1/s"), (eps, 0.0001, 0.1, "1")):
        if paper:
            lo = hi = float(PAPER_GAINS[sym.name.replace("_", "").replace("varepsilon", "eps")])
        coords.append(Coordinate(sym, lo, hi, unit))
    coords += [Coordinate(x, -2.0, 2.0, "(unit of s1)") for x in s1]
    coords += [Coordinate(x, -5.0, 5.0, "(unit of s2)") for x in s2]
    coords += [Coordinate(x, -1.0, 1.0, "rad/s") for x in w] + [Coordinate(x, -2.0, 2.0, "m/s") for x in v]
    coords += [Coordinate(x, -20.0, 20.0, "m") for x in r] + [Coordinate(x, -1.0, 5.0, "1") for x in ah]
    coords += [Coordinate(x, 1e-300, 5.0, "1") for x in al] + [Coordinate(x, 0.1, 2.0, "1") for x in ga]
    coords += [Coordinate(x, -1.0, 1.0, "1") for x in cy[0] + cy[1]]
    reg = Region(tuple(coords), subs, describe="Phi_j = rho_j y_j, y_j in the unit ball (cube chart)")
    target = (c_eps - lc.LEMMA2_C * (9 + k3 + k7)) * eps
    ball_forms = [(rho[j] ** 2 * _prod1m(cy[j]), set(cy[j])) for j in range(2)]

    def reduce_side(e):
        for form, cs in ball_forms:
            if e.free_symbols & cs and sp.expand(e - form) == 0:
                return form
        return _small_factor(e)

    gains = ("k3 = 4, k4 = 0.5, k7 = 0.5, k8 = 20 1/s, eps = 0.001 (the paper's, eq. 46)" if paper else
             "k3, k7 in [0.01, 40], k4 in [0.01, 10], k8 in [0.1, 50] 1/s, eps in [1e-4, 0.1]")
    return Plan([reg], gains + ", s1 in "
                       "[-2, 2]^3, s2 in [-5, 5]^3 (contain the search's balls), omega~ in [-1, 1]^3 rad/s, v~ in "
                       "[-2, 2]^3 m/s, r~ in [-20, 20]^3 m, alpha^ in [-1, 5]^9, alpha in (0, 5]^9 (declared "
                       "positive), gamma in [0.1, 2]^9, ||Phi1|| <= alpha1 |w|^2 + alpha2 |w| + alpha3, ||Phi2|| <= "
                       "eq. 22's bound", reduce=lambda g: target, reduce_side=reduce_side, uses=tuple(uses),
                covers_search_domain=False, note=_positive_note("each alpha_i"))


# --------------------------------------------------------------------------- eqs. 30-33: exponential forms

def _v1_exponential(st: Statement) -> Plan:
    """Eqs. 30-33 as corrected, per subsystem (V1att, V1pos) or both: the chain of :func:`_v1_bound` on the
    subsystem's terms (Lemma 2 per term with c = 0.31, s d <= |s| D, the ball form of Cauchy-Schwarz), then
    Young (eq. 30, weight gamma_i: gamma alpha~ alpha^ <= -gamma (2l - 1)/(2l) alpha~^2 + gamma l alpha^2/2)
    and Min(...) <= each of its arguments (``min_le``, y the Min of the others, which SymPy flattens into the
    statement's Min), weights 1/2 s^T J s (or 1/2 m ||s2||^2) and alpha~_i^2/(2 beta_i).  What is left is, exactly,
    k4 sum_{j != k} s1_j^2 d_j/a + k3 ||s1|| + 0.69 (3 + k3) eps (attitude) and k7 ||s2|| + 0.69 (6 + k7) eps
    (position), where J_k = a = max(J) and J_j = a - d_j, d_j = a h_j (one region per index k of the maximum,
    so that Max(J_1, J_2, J_3) is a): sums of nonnegative terms."""
    n = _by_name(st)

    def vec(name):
        return sp.Matrix([n[f"{name}_{i}"] for i in (1, 2, 3)])

    parts = [j for j, key in ((0, "s_1_1"), (1, "s_2_1")) if key in n]
    idx = [i for j in parts for i in ((0, 1, 2) if j == 0 else (3, 4, 5, 6, 7, 8))]
    w = vec("omega")
    v, r = (vec("v"), vec("r")) if 1 in parts else (sp.zeros(3, 1), sp.zeros(3, 1))     # (position only)
    sv = [vec("s_1") if 0 in parts else None, vec("s_2") if 1 in parts else None]
    Pv = [vec("Phi1") if 0 in parts else None, vec("Phi2") if 1 in parts else None]
    g = lambda name: {i: n[f"{name}_{i + 1}"] for i in idx}          # noqa: E731
    ah, al, ga, be, ll = g("alphahat"), g("alpha"), g("gamma"), g("beta"), g("l")
    eps = n["varepsilon"]
    kk = [(n["k_3"], n["k_4"]) if 0 in parts else None, (n["k_7"], n["k_8"]) if 1 in parts else None]
    nrm = lc._nrm
    nw, nv, nr = nrm(w), nrm(v), nrm(r)
    Y = [nw**2, nw, sp.S.One, nw * nv, nw * nr, nw, nv, nr, sp.S.One]
    sa, da, Da = ABS_PRODUCT.symbols
    ya, yb, ye = YOUNG.symbols
    mx, my = MIN_LE.symbols
    dx, dy, dr = DOT_BALL3.symbols[:3], DOT_BALL3.symbols[3:6], DOT_BALL3.symbols[6]
    J = [n[f"J_{i}"] for i in (1, 2, 3)] if 0 in parts else []
    m = n["m"] if 1 in parts else None
    uses, subs, cys, rhos = [], {}, {}, {}
    for j in parts:
        ij = [i for i in idx if (i < 3) == (j == 0)]
        s_, P_ = sv[j], Pv[j]
        k_lin, k_quad = kk[j]
        rho = sum(al[i] * Y[i] for i in ij)
        for i in ij:
            uses.append(_use(lc.LEMMA2, sp.S.One, z=ah[i] ** 2 * Y[i] ** 2 * dot(s_, s_), eps=eps))
            uses.append(Use(ABS_PRODUCT, {sa: ah[i], da: nrm(s_) * Y[i], Da: nrm(s_) * Y[i]}))
            uses.append(Use(YOUNG, {ya: al[i] - ah[i], yb: al[i], ye: ll[i]}, ga[i]))
        uses.append(_use(lc.LEMMA2, k_lin, z=dot(s_, s_), eps=eps))
        uses.append(Use(DOT_BALL3, {**dict(zip(dx, s_, strict=True)), **dict(zip(dy, P_, strict=True)), dr: rho}))
        rates = {i: be[i] * ga[i] * (2 * ll[i] - 1) / ll[i] for i in ij}
        first = 2 * k_quad / (sp.Max(*J) if j == 0 else m)
        energy = sum(J[i] * s_[i] ** 2 for i in range(3)) / 2 if j == 0 else m * dot(s_, s_) / 2
        args = [first, *rates.values()]
        for a_, wgt in [(first, energy), *[(rates[i], (al[i] - ah[i]) ** 2 / (2 * be[i])) for i in ij]]:
            others = [x for x in args if x is not a_]
            uses.append(Use(MIN_LE, {mx: a_, my: sp.Min(*others)}, wgt))
        cy = list(sp.symbols(f"cphi{j + 1}_1:4", real=True))
        cys[j], rhos[j] = cy, rho
        subs.update(dict(zip(P_, [rho * x for x in _ball3(cy)], strict=True)))
    base = []
    for j in parts:
        k_lin, k_quad = kk[j]
        base += [Coordinate(k_lin, 0.01, 40.0, "1/s"),
                 Coordinate(k_quad, *((0.01, 10.0) if j == 0 else (0.1, 50.0)), "1/s")]
        base += [Coordinate(x, -(2.0 if j == 0 else 5.0), 2.0 if j == 0 else 5.0, f"(unit of s{j + 1})") for x in sv[j]]
        base += [Coordinate(x, -1.0, 1.0, "1") for x in cys[j]]
    base += [Coordinate(eps, 0.0001, 0.1, "1")]
    base += [Coordinate(x, -1.0, 1.0, "rad/s") for x in w]
    if 1 in parts:
        base += [Coordinate(x, -2.0, 2.0, "m/s") for x in v] + [Coordinate(x, -20.0, 20.0, "m") for x in r]
        base += [Coordinate(m, 20.0, 200.0, "kg")]
    for i in idx:
        base += [Coordinate(ah[i], -1.0, 5.0, "1"), Coordinate(al[i], 1e-300, 5.0, "1"),
                 Coordinate(ga[i], 0.1, 2.0, "1"), Coordinate(be[i], 0.001, 10.0, "1"),
                 Coordinate(ll[i], 0.5, 5.0, "1")]
    c = lc.LEMMA2_C
    pos_rest = 0
    if 1 in parts:
        k7 = kk[1][0]
        pos_rest = k7 * nrm(sv[1]) + (1 - c) * (6 + k7) * eps
    regions, forms, side_forms = [], {}, []
    a_ = sp.Symbol("Jmax", positive=True)
    h_ = [sp.Symbol(f"hJ_{i + 1}", nonnegative=True) for i in range(3)]
    for k in (range(3) if 0 in parts else [None]):
        sub = dict(subs)
        coords = list(base)
        hyps = ()
        target = pos_rest
        if k is not None:
            others = [i for i in range(3) if i != k]
            # J_j = a - a h_j in [a/8, a] (contains J_j in [5, 40] for a = max J); SymPy orders a - a h_j <= a
            sub.update({J[k]: a_, **{J[i]: a_ - a_ * h_[i] for i in others}})
            coords += [Coordinate(a_, 5.0, 40.0, "kg m^2"), *[Coordinate(h_[i], 0.0, 0.875, "1") for i in others]]
            k3, k4 = kk[0]
            # the weight 1/2 s1^T J s1 of min_le, written so that each term encloses >= 0
            side_forms.append(a_ * (sv[0][k] ** 2 + sum((1 - h_[i]) * sv[0][i] ** 2 for i in others)) / 2)
            target += (k4 * sum(sv[0][i] ** 2 * h_[i] for i in others) + k3 * nrm(sv[0])
                       + (1 - c) * (3 + k3) * eps)
        regions.append(Region(tuple(coords), sub, hyps, describe=(f"max(J) = J_{k + 1}; " if k is not None else "")
                              + "Phi_j = rho_j y_j, y_j in the unit ball (cube chart)"))
        forms[(len(regions) - 1, 0)] = target
    ball_forms = [(rhos[j] ** 2 * _prod1m(cys[j]), set(cys[j])) for j in parts]

    def reduce_side(e):
        for form, cs in ball_forms:
            if e.free_symbols & cs and sp.expand(e - form) == 0:
                return form
        for form in side_forms:
            if sp.expand(e - form) == 0:
                return form
        # J_j = a (1 - h_j): factored, each factor encloses >= 0 (the identity is re-verified)
        return sp.factor(e) if a_ in e.free_symbols else _small_factor(e)

    dom = []
    if 0 in parts:
        dom.append("k3 in [0.01, 40], k4 in [0.01, 10] 1/s, J = diag(J_1, J_2, J_3), J_i in [5, 40] kg m^2, "
                   "s1 in [-2, 2]^3")
    if 1 in parts:
        dom.append("k7 in [0.01, 40], k8 in [0.1, 50] 1/s, m in [20, 200] kg, s2 in [-5, 5]^3, v~ in [-2, 2]^3 "
                   "m/s, r~ in [-20, 20]^3 m")
    dom.append("eps in [1e-4, 0.1], omega~ in [-1, 1]^3 rad/s, alpha^_i in [-1, 5], alpha_i in (0, 5] (declared "
               "positive), gamma_i in [0.1, 2], beta_i in [0.001, 10], l_i in [0.5, 5], ||Phi_j|| <= the bounds of "
               "eqs. 21-22 (the s_j boxes contain the search's balls)")
    plan = Plan(regions, "; ".join(dom), reduce_side=reduce_side, uses=tuple(uses), covers_search_domain=False,
                note=_positive_note("each alpha_i"))
    _table_reduce(st, plan, forms)
    return plan


PLANS: dict = {
    "c002.V1.lemma2_unit_terms": _lemma2_unit,
    "c002.V1.residual_set": _residual_set,
    "c002.model.remark4_Cr": _remark4_Cr,
    "c002.model.remark5_nt": _remark5_nt,
    "c002.model.lumped_bound_position": _lumped_position,
    "c002.model.lumped_bound_attitude": _lumped_attitude,
    "c002.V1.bound": _v1_bound,
    "c002.gains.eq29_constant": _v1_bound,
    "c002.V1.exponential_att": _v1_exponential,
    "c002.V1.exponential_pos": _v1_exponential,
    "c002.V1.exponential": _v1_exponential,
}
