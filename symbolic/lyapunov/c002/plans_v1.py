"""002: proof plans of the model, V1 and gain claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ..certify import Coordinate, Plan, Region
from ..certify.plan import composed, gaps
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


PLANS: dict = {
    "c002.V1.lemma2_unit_terms": _lemma2_unit,
    "c002.V1.residual_set": _residual_set,
}
