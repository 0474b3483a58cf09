"""002: proof plans of the inequality claims (certified domains; see ``symbolic/lyapunov/certify``).

Most of these proofs are symbolic compositions: the gap of a claim is the weighted sum of proved lemmas
(Lemma 1 of the paper, ``s d <= |s| D``, Young, the identity cosh^2 = 1/(1 - tanh^2)), the remainder is
an exact rewriting that the boxes close at once, and the boxes certify the weights and the premises.
"""

from __future__ import annotations

import sympy as sp

from ..certify import Coordinate, Plan, Region
from ..certify.lemmas import ABS_PRODUCT, COSH_TANH, MIN_LE, TANH_MONO, TRIANGLE3, YOUNG
from ..certify.lemmas import LEMMA1_002 as LEMMA1
from ..certify.lemmas import OUTSIDE_002 as OUTSIDE
from ..certify.plan import Use
from ..core import Statement
from .common import DELTA
from .plans_v1 import PLANS as _PLANS_V1


def _sym(name: str, **kw) -> sp.Symbol:
    return sp.Symbol(name, real=True, **kw)


def _by_name(st: Statement) -> dict:
    """The statement's symbols and its domain's (a bound such as varpi_j may appear in the domain only)."""
    out = {s.name: s for v in st.domain for s in v.symbols}
    out.update({s.name: s for s in st.free_symbols()})
    return out


def _zero_goal(raw: sp.Expr, anchor: sp.Symbol) -> sp.Expr:
    """The remainder of a proof by composition that cancels exactly: 0, written ``0 * anchor`` (unevaluated)
    so that the goal keeps one box coordinate (the prover needs at least one; 0 >= 0 on any box).  The
    identity raw = 0 is the plan's reduction step, re-verified symbolically at every check."""
    if sp.expand(raw) != 0:
        return sp.expand(raw)            # not a cancellation: hand the expanded remainder to the boxes
    return sp.Mul(sp.S.Zero, anchor, evaluate=False)


# =========================================================================== lemma symbols
# (the lemmas themselves are in the reviewed library, certify/lemmas.py; a mapping's keys are their symbols)

_x, _y = _sym("x"), _sym("y")
_k, _p, _w = _sym("k"), _sym("p"), _sym("w")
_a, _b, _c = _sym("a"), _sym("b"), _sym("c")
_C = _sym("C")


# =========================================================================== V2 (eqs. 35-38)

def _v2_lemma1(st: Statement) -> Plan:
    """Lemma 1 (mu = 1) summed over the three axes: kappa_1 > 0 factored out, the rest on the box."""
    chi = sorted((s for s in st.free_symbols() if s.name.startswith("chi1_")), key=lambda s: s.name)
    (kappa,) = [s for s in st.free_symbols() if s.name == "kappa_1"]
    reg = Region(tuple(Coordinate(c, -4.0, 4.0) for c in chi) + (Coordinate(kappa, 0.01, 5.0, "N m"),),
                 describe="the search domain")

    def reduce(g):
        rest = sp.expand(g / kappa)
        return kappa, rest

    return Plan([reg], "chi1_i in [-4, 4] (i = 1..3, dimensionless), kappa_1 in [0.01, 5] N m", reduce=reduce)


def _axes(n: dict):
    """Per axis (j, i) of the auxiliary systems: chi, e, kappa, varpi, the inertia (J_i or m)."""
    for j in (1, 2):
        for i in (1, 2, 3):
            yield (j, i, n[f"chi{j}_{i}"], n[f"e_{j}_{i}"], n[f"kappa_{j}"], n[f"varpi_{j}"],
                   n[f"J_{i}"] if j == 1 else n["m"])


def _v2_bound(st: Statement) -> Plan:
    """Eq. 38 as corrected (axis by axis).  Per axis, with A = 1/(J (1 - tanh^2 chi)) = cosh^2(chi)/J:
    gap = kappa A (delta - |chi| + chi tanh chi) + A (varpi |chi| - chi e) + [cosh^2 - 1/(1 - tanh^2)]
    chi (kappa tanh chi - e)/J, exactly; Lemma 1, s d <= |s| D (|e_i| <= varpi) and the cosh/tanh identity
    leave 0.  The boxes certify the weights (>= 0) and the premises varpi - |e_i| >= 0."""
    n = _by_name(st)
    coords, subs, uses = [], {}, []
    for j in (1, 2):
        coords += [Coordinate(n[f"kappa_{j}"], 0.1, 5.0), Coordinate(n[f"varpi_{j}"], 0.0, 5.0)]
    coords += [Coordinate(n[f"J_{i}"], 5.0, 40.0, "kg m^2") for i in (1, 2, 3)]
    coords += [Coordinate(n["m"], 20.0, 200.0, "kg")]
    for j, i, chi, e, kap, vp, inertia in _axes(n):
        w = _sym(f"w_{j}_{i}")
        coords += [Coordinate(chi, -3.0, 3.0), Coordinate(w, -1.0, 1.0)]
        subs[e] = vp * w
        a = 1 / (inertia * (1 - sp.tanh(chi) ** 2))
        uses += [Use(LEMMA1, {_x: chi}, kap * a),
                 Use(ABS_PRODUCT, dict(zip(ABS_PRODUCT.symbols, (chi, e, vp), strict=True)), a),
                 Use(COSH_TANH, {_x: chi, _y: chi * (kap * sp.tanh(chi) - e) / inertia})]
    reg = Region(tuple(coords), subs, describe="e_j = varpi_j w_j, w_j in the cube [-1, 1]^3 (contains the ball)")
    anchor = n["kappa_1"]
    return Plan([reg], "kappa_j in [0.1, 5], varpi_j in [0, 5], chi_ji in [-3, 3], |e_ji| <= varpi_j (the box "
                       "e_j = varpi_j w_j, w_j in [-1, 1]^3, which contains the search's ball ||e_j|| <= varpi_j), "
                       "J_i in [5, 40] kg m^2, m in [20, 200] kg",
                reduce=lambda g: _zero_goal(g, anchor), uses=tuple(uses),
                note="Lemma 1 and the cosh/tanh identity hold for every real chi: the chi box only bounds the "
                     "weights' enclosures.")


def _v2_invariant_set(st: Statement) -> Plan:
    """Theorem 1 ii per axis (corrected): chi_ji chi_ji_dot <= 0 where |chi_ji| >= kappa_j delta/(kappa_j -
    varpi_j).  Each component is -cosh^2(chi)/(J k) times chi (e - kappa tanh chi) and is certified by the
    lemma ``lemma1_outside`` (Lemma 1 plus |e| <= varpi), with weight cosh^2(chi)/(J k) >= 0.

    Domain map: varpi_j = kappa_j (1 - u_j) (u_j in [0.05, 1]: varpi_j in [0, 0.95 kappa_j]), chi_ji =
    sigma (kappa_j delta + y_ji)/(kappa_j u_j) with y_ji in [0, 15], so |chi_ji| = c_j + y_ji/(kappa_j u_j)
    runs from the threshold c_j = kappa_j delta/(kappa_j - varpi_j) to beyond c_j + 3 (the sampler's range:
    kappa_j u_j <= 5), and e_ji = sigma varpi_j w_ji with w_ji in [-1, 1] (the box that contains the ball
    ||e_j|| <= varpi_j; the sign sigma of chi_ji only reorders it).  The two signs of each of the six
    chi_ji make 2^6 regions."""
    n = _by_name(st)
    base = [Coordinate(n[f"k_{k}"], 0.001, 1.0) for k in (2, 6)]
    base += [Coordinate(n[f"J_{i}"], 5.0, 40.0, "kg m^2") for i in (1, 2, 3)] + [Coordinate(n["m"], 20.0, 200.0, "kg")]
    us, axes = {}, list(_axes(n))
    for j in (1, 2):
        us[j] = sp.Symbol(f"u_{j}", positive=True)
        base += [Coordinate(n[f"kappa_{j}"], 0.1, 5.0), Coordinate(us[j], 0.05, 1.0)]
    ys, ws = {}, {}
    for j, i, chi, _e, _kap, _vp, _inertia in axes:
        ys[chi] = sp.Symbol(f"y_{j}_{i}", nonnegative=True)
        ws[chi] = _sym(f"w_{j}_{i}")
        base += [Coordinate(ys[chi], 0.0, 15.0), Coordinate(ws[chi], -1.0, 1.0)]
    regions = []
    for mask in range(64):
        subs = {n[f"varpi_{j}"]: n[f"kappa_{j}"] * (1 - us[j]) for j in (1, 2)}
        signs = ""
        for b, (j, _i, chi, e, kap, _vp, _inertia) in enumerate(axes):
            sg = -1 if mask >> b & 1 else 1
            signs += "+" if sg > 0 else "-"
            # expanded, so that tanh(chi) and cosh(chi) take the sign out when built (the identity check
            # canonicalises function arguments by expanding them)
            subs[chi] = sg * sp.expand((kap * DELTA + ys[chi]) / (kap * us[j]))
            subs[e] = sg * kap * (1 - us[j]) * ws[chi]
        regions.append(Region(tuple(base), subs, describe="signs of chi_ji: " + signs))
    uses = []
    for ci, (j, _i, chi, _e, kap, vp, inertia) in enumerate(axes):
        gain = n["k_2"] if j == 1 else n["k_6"]
        # y and w are the regions' coordinates y_ji, w_ji (the same in every region: with e = sigma varpi w
        # and chi = sigma x the component is the lemma's x (kappa tanh x - varpi w) in both signs); a lemma
        # holds for any real values of its symbols, so an instance in coordinates is as valid as one in the
        # statement's symbols, and the main goal's identity ties it to the statement
        mapping = {_y: ys[chi], _w: ws[chi], _k: kap, _p: vp}
        uses.append(Use(OUTSIDE, mapping, sp.cosh(chi) ** 2 / (inertia * gain), component=ci))
    anchor = n["kappa_1"]
    return Plan(regions, "kappa_j in [0.1, 5], varpi_j in [0, 0.95 kappa_j], |e_ji| <= varpi_j (the box, which "
                         "contains the ball ||e_j|| <= varpi_j), |chi_ji| = kappa_j delta/(kappa_j - varpi_j) + "
                         "y_ji/(kappa_j - varpi_j) with y_ji in [0, 15] (covers the sampler's |chi_ji| <= "
                         "kappa_j delta/(kappa_j - varpi_j) + 3), both signs; k2, k6 in [0.001, 1], "
                         "J_i in [5, 40] kg m^2, m in [20, 200] kg",
                reduce=lambda g: _zero_goal(g, anchor), uses=tuple(uses),
                note="The lemma holds for every |chi| beyond the threshold; the cap y_ji <= 15 only bounds the "
                     "box (it covers the search domain).")


# =========================================================================== V3 (eqs. 39-43)

def _v3_upper(st: Statement) -> Plan:
    """Eq. 40: the gap is 4 - (1 - q0)^2 >= 0 for q0 in [-1, 1]; certified on the cube q in [-1, 1]^4,
    which contains the unit sphere (every unit quaternion)."""
    n = _by_name(st)
    coords = [Coordinate(n[f"q_{i}"], -1.0, 1.0) for i in (1, 2, 3, 0)]
    coords += [Coordinate(n[f"r_{i}"], -20.0, 20.0, "m") for i in (1, 2, 3)]
    return Plan([Region(tuple(coords), describe="the cube [-1, 1]^4 around the unit quaternions")],
                "q in [-1, 1]^4 (contains every unit quaternion), r~ in [-20, 20]^3 m")


def _ball_charts(s: sp.Matrix, radius: sp.Symbol, tag: str):
    """The ball ||s|| <= radius as two regions' maps: s = radius rho u, rho in [0, 1], u on the unit sphere by
    the stereographic chart u = (2a, 2b, +-(1 - a^2 - b^2))/(1 + a^2 + b^2), (a, b) in [-1, 1]^2: each sign
    covers the closed hemisphere +-u_3 >= 0 (its points have a^2 + b^2 <= 1).  Rational, so ||u|| = 1 is
    an identity of rational functions."""
    rho = sp.Symbol(f"rho_{tag}", nonnegative=True)
    a, b = _sym(f"a_{tag}"), _sym(f"b_{tag}")
    coords = (Coordinate(rho, 0.0, 1.0), Coordinate(a, -1.0, 1.0), Coordinate(b, -1.0, 1.0))
    den = 1 + a**2 + b**2
    out = []
    for sg in (1, -1):
        u = (2 * a / den, 2 * b / den, sg * (1 - a**2 - b**2) / den)
        out.append((coords, {s[i]: radius * rho * u[i] for i in range(3)}, "+" if sg > 0 else "-"))
    return rho, out


def _v3_tracking(st: Statement, exponential: bool) -> Plan:
    """Eq. 41 as corrected: V3_dot = q~_v.(s1 - k1 q~_v + k2 tanh chi1) + r~.(s2 - k5 r~ + k6 tanh chi2) (the
    C_t = W^x terms cancel: r~^T W^x r~ = 0).  Young (ab <= a^2/4 + b^2) on q~_i s1_i, q~_i k2 tanh chi1_i
    and the same for r~ leaves exactly o1^2 - ||s1||^2 + k2^2 (3 - sum tanh^2 chi1_i) + (the same for 2),
    >= 0 on the balls ||s_j|| <= o_j (a chart each: s_j = o_j rho_j u_j, so o_j^2 - ||s_j||^2 =
    o_j^2 (1 - rho_j^2)).  The exponential form adds -min(k1 - 1/2, 2 k5 - 1) V3: Min <= each argument
    (weights q~_v^T q~_v + (1 - q~0)^2 and r~^T r~/2) leaves (k1 - 1/2)(4 - (1 - q~0)^2) >= 0.

    q is certified on the cube [-1, 1]^4, which contains the unit quaternions (the gap does not need
    ||q|| = 1: q~0 enters only through (1 - q~0)^2 <= 4)."""
    n = _by_name(st)
    q = [n[f"q_{i}"] for i in (1, 2, 3)]
    r = [n[f"r_{i}"] for i in (1, 2, 3)]
    c1 = [n[f"chi1_{i}"] for i in (1, 2, 3)]
    c2 = [n[f"chi2_{i}"] for i in (1, 2, 3)]
    s1 = sp.Matrix([n[f"s_1_{i}"] for i in (1, 2, 3)])
    s2 = sp.Matrix([n[f"s_2_{i}"] for i in (1, 2, 3)])
    k1, k2, k5, k6, o1, o2, q0 = (n[k] for k in ("k_1", "k_2", "k_5", "k_6", "o_1", "o_2", "q_0"))
    base = [Coordinate(x, -1.0, 1.0) for x in (*q, q0)] + [Coordinate(x, -20.0, 20.0, "m") for x in r]
    base += [Coordinate(x, -3.0, 3.0) for x in (*c1, *c2)] + [Coordinate(x, 0.001, 1.0) for x in (o1, o2)]
    base += [Coordinate(x, 0.5, 5.0) for x in (k1, k5)] + [Coordinate(x, 0.001, 1.0) for x in (k2, k6)]
    base += [Coordinate(n[f"W_{i}"], -0.5, 0.5, "rad/s") for i in (1, 2, 3)]
    rho1, ch1 = _ball_charts(s1, o1, "1")
    rho2, ch2 = _ball_charts(s2, o2, "2")
    regions = [Region(tuple(base) + cs1 + cs2, {**m1, **m2}, describe=f"s1 hemisphere {t1}, s2 hemisphere {t2}")
               for cs1, m1, t1 in ch1 for cs2, m2, t2 in ch2]
    ya, yb, ye = YOUNG.symbols
    uses = []
    for i in range(3):
        for a, b in ((q[i], s1[i]), (q[i], k2 * sp.tanh(c1[i])), (r[i], s2[i]), (r[i], k6 * sp.tanh(c2[i]))):
            uses.append(Use(YOUNG, {ya: a, yb: b, ye: 2}))
    target = (o1**2 * (1 - rho1**2) + k2**2 * (3 - sum(sp.tanh(x) ** 2 for x in c1))
              + o2**2 * (1 - rho2**2) + k6**2 * (3 - sum(sp.tanh(x) ** 2 for x in c2)))
    if exponential:
        half = sp.S.Half
        qq, rr = sum(x**2 for x in q), sum(x**2 for x in r)
        uses.append(Use(MIN_LE, {_x: k1 - half, _y: 2 * k5 - 1}, qq + (1 - q0) ** 2))
        uses.append(Use(MIN_LE, {_x: 2 * k5 - 1, _y: k1 - half}, rr / 2))
        target += (k1 - half) * (4 - (1 - q0) ** 2)
    dom = ("q in [-1, 1]^4 (contains every unit quaternion), r~ in [-20, 20]^3 m, chi_j in [-3, 3]^3, "
           "o_j in [0.001, 1], ||s_j|| <= o_j (two stereographic hemisphere charts each), k1, k5 in [0.5, 5], "
           "k2, k6 in [0.001, 1], W in [-0.5, 0.5]^3 rad/s")
    # the remainder is the same expression in every chart (a_j, b_j cancel); the check verifies raw = target
    return Plan(regions, dom, reduce=lambda g: target, uses=tuple(uses))


def _v3_rate_bounds(st: Statement) -> Plan:
    """Eqs. 42-43 per axis, |-k q~_i + g tanh(chi_i) + s_i| <= o + k o3 + g tanh(c): the triangle inequality
    (``triangle_3``) and |tanh(chi_i)| <= tanh(c) (``tanh_unit``, weight g) leave o (1 - |w|) + k o3 (1 - |v|)
    in the unit coordinates of the map s_j = o_j w, q~_v = o3 v, r~ = o4 v, chi_j = c_j y.  Certified on the
    boxes |s_ji| <= o_j, |q~_i| <= o3, |r~_i| <= o4, |chi_ji| <= c_j, which contain the search's balls."""
    n = _by_name(st)
    o = [n[f"o_{i}"] for i in (1, 2, 3, 4)]
    c1, c2, k1, k2, k5, k6 = (n[k] for k in ("c_1", "c_2", "k_1", "k_2", "k_5", "k_6"))
    coords = [Coordinate(x, 0.001, 1.0) for x in o] + [Coordinate(x, 0.01, 3.0) for x in (c1, c2)]
    coords += [Coordinate(x, 0.5, 5.0) for x in (k1, k5)] + [Coordinate(x, 0.001, 1.0) for x in (k2, k6)]
    subs, uses, rest = {}, [], {}
    axes = [(n[f"s_1_{i}"], n[f"q_{i}"], n[f"chi1_{i}"], o[0], k1, o[2], k2, c1) for i in (1, 2, 3)]
    axes += [(n[f"s_2_{i}"], n[f"r_{i}"], n[f"chi2_{i}"], o[1], k5, o[3], k6, c2) for i in (1, 2, 3)]
    for ci, (s_, x_, chi, a_, k_, p_, g_, c_) in enumerate(axes):
        uw, uv, uy = _sym(f"w_{s_.name}"), _sym(f"v_{x_.name}"), _sym(f"y_{chi.name}")
        coords += [Coordinate(uw, -1.0, 1.0), Coordinate(uv, -1.0, 1.0), Coordinate(uy, -1.0, 1.0)]
        subs.update({s_: a_ * uw, x_: p_ * uv, chi: c_ * uy})
        uses += [Use(TRIANGLE3, {_a: -k_ * x_, _b: g_ * sp.tanh(chi), _c: s_}, component=ci),
                 Use(TANH_MONO, {_C: c_, _y: chi / c_}, g_, component=ci)]
        rest[sp.Abs(uw)] = (a_, k_ * p_, sp.Abs(uv))

    def reduce(g):
        # what the lemmas leave: o - o |w| + k o3 - k o3 |v|, written o (1 - |w|) + k o3 (1 - |v|)
        for aw, (a_, kp, av) in rest.items():
            if g.has(aw):
                return a_ * (1 - aw) + kp * (1 - av)
        return g

    reg = Region(tuple(coords), subs, describe="s_j = o_j w, q~_v = o3 v, r~ = o4 v, chi_j = c_j y (unit boxes)")
    return Plan([reg], "o_1..4 in [0.001, 1], c_j in [0.01, 3], k1, k5 in [0.5, 5], k2, k6 in [0.001, 1]; "
                       "|s_ji| <= o_j, |q~_i| <= o3, |r~_i| <= o4, |chi_ji| <= c_j (boxes that contain the "
                       "search's balls)", reduce=reduce, uses=tuple(uses))


PLANS = {
    "c002.V2.lemma1": _v2_lemma1,
    "c002.V2.bound": _v2_bound,
    "c002.V2.invariant_set": _v2_invariant_set,
    "c002.V3.upper_bound": _v3_upper,
    "c002.V3.bound": lambda st: _v3_tracking(st, False),
    "c002.V3.exponential": lambda st: _v3_tracking(st, True),
    "c002.V3.rate_bounds": _v3_rate_bounds,
    **_PLANS_V1,
}

#: why each remaining claim has no certificate (the report prints it)
UNCERTIFIED: dict = {}
