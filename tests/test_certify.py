"""The certifying prover (symbolic/lyapunov/certify): enclosures are sound, no false statement is ever
certified, a certificate re-checks independently, and a tampered certificate fails its re-check."""

from __future__ import annotations

import base64
import copy

import numpy as np
import pytest
import sympy as sp
from mpmath import mp, mpf

from rpo.symbolic import lyapunov
from rpo.symbolic.lyapunov.certify import certificate as C
from rpo.symbolic.lyapunov.certify import plan_for
from rpo.symbolic.lyapunov.certify.bnb import LEAF, LEAF_NAME, prove
from rpo.symbolic.lyapunov.certify.intervals import compile_exprs
from rpo.symbolic.lyapunov.certify.library import LIBRARY
from rpo.symbolic.lyapunov.certify.plan import Coordinate, Plan, Region, goals
from rpo.symbolic.lyapunov.certify.recheck import CheckError, LeafChecker, walk

x, y, z = sp.symbols("x y z", real=True)
CLAIMS = {c.id: c for c in lyapunov.claims()}

EXPRS = [
    x**2 - 2 * x * y + y**2,
    sp.sqrt(x**2 + y**2 + sp.Rational(1, 3)) * sp.tanh(z) - x / (1 + y**2),
    sp.Abs(x - y) * sp.sign(z) + sp.Max(x, y, z) - sp.Min(x, z),
    sp.exp(x) * sp.cosh(y) - sp.log(2 + z**2) + x**3 * y**5,
    sp.Heaviside(x) * y + (x + y) ** 4 / 7 - sp.Rational(1, 10) ** 3 * z,
    sp.Piecewise((x * y, x > y), (x - z, True)),
]


@pytest.mark.parametrize("expr", EXPRS, ids=[sp.sstr(e)[:30] for e in EXPRS])
def test_enclosures_contain_every_value(expr):
    """Random boxes (some degenerate, some straddling 0): every value at random points of the box, computed
    in 60-digit arithmetic, lies in the NumPy enclosure."""
    rng = np.random.default_rng(7)
    prog = compile_exprs([expr], [x, y, z])
    f = sp.lambdify([x, y, z], expr, modules="mpmath")
    n = 300
    c = rng.uniform(-2, 2, (n, 3))
    w = rng.choice([0.0, 1e-9, 0.1, 1.0], (n, 3)) * rng.uniform(0, 1, (n, 3))
    lo, hi = c - w, c + w
    elo, ehi, _ = prog.evaluate(lo, hi)
    mp.dps = 60
    for i in range(n):
        for t in (0.0, 1.0, rng.uniform()):
            p = np.clip(lo[i] + t * (hi[i] - lo[i]), lo[i], hi[i])      # rounding may step outside
            v = f(*[mpf(float(q)) for q in p])
            assert mpf(elo[0, i]) <= v <= mpf(ehi[0, i]), (i, p, v, elo[0, i], ehi[0, i])
    mp.dps = 15


def test_exact_results_are_kept_so_an_exact_zero_encloses_to_zero():
    prog = compile_exprs([sp.sqrt(x) - x, x * y - y * x + (x - 1) ** 2], [x, y])
    lo, hi, _ = prog.evaluate(np.array([[1.0, 3.0]]), np.array([[1.0, 3.0]]))
    assert list(lo[:, 0]) == [0.0, 0.0] and list(hi[:, 0]) == [0.0, 0.0]


TRUE = [
    (sp.sqrt(x) - x, [(x, 0.0, 1.0)]),                                    # zeros at both ends
    (x * sp.tanh(x) - sp.Abs(x) + sp.Rational(557, 2000), [(x, -4.0, 4.0)]),     # Lemma 1, margin 3.6e-5
    (x**2 + y**2 - x * y, [(x, -1.0, 1.0), (y, -1.0, 1.0)]),             # zero at an interior point
]


@pytest.mark.parametrize("g, box", TRUE, ids=["sqrt", "lemma1", "quadratic"])
def test_true_statements_are_certified_and_the_certificate_rechecks(g, box):
    eq = [{x: 0, y: 0}] if len(box) == 2 else []
    r = prove(g, box, equilibria=eq, max_boxes=200_000)
    assert r.status == "certified", r.reason
    checker = LeafChecker(g, [b[0] for b in box], [], eq)
    assert walk(r.tree, [(b[1], b[2]) for b in box], checker, LEAF_NAME) == r.boxes


FALSE = [
    (x**2 - 1e-6, [(x, -1.0, 1.0)]),                                     # fails on |x| < 1e-3 only
    (sp.Abs(x - sp.Rational(1, 3)) - sp.Rational(1, 1000) * sp.Heaviside(x - sp.Rational(1, 3)),
     [(x, -1.0, 1.0)]),                                                  # a jump, false on [1/3, 1/3 + 1e-3)
    (x * sp.tanh(x) - sp.Abs(x) + sp.Rational(2784, 10000), [(x, -4.0, 4.0)]),   # below Lemma 1's delta
    (1 - x**2 - y**2 - z**2 + 1e-9 * sp.sign(x - sp.Rational(1, 7)), [(x, -1.0, 1.0), (y, -1.0, 1.0),
                                                                     (z, -1.0, 1.0)]),
    (sp.sign(x) * x - sp.Abs(x) - sp.Rational(1, 10**12) * (1 - sp.Heaviside(x) * 2) ** 2,
     [(x, -1.0, 1.0)]),                                                  # false exactly at x = 0 only
]


@pytest.mark.parametrize("g, box", FALSE, ids=["dip", "jump", "lemma1_tight", "sphere", "at_zero_only"])
def test_false_statements_are_never_certified(g, box):
    """Each is false somewhere, several on a tiny set only: the prover must end with a counterexample (a point
    where g < 0, rigorously) or 'cannot certify', never a certificate."""
    r = prove(g, box, max_boxes=100_000, seconds=60)
    assert r.status in ("counterexample", "cannot")
    if r.status == "counterexample":
        pt = {s: r.counterexample[str(s)] for s, _, _ in box}
        mp.dps = 50
        assert sp.N(g.xreplace({k: sp.Float(v, 30) for k, v in pt.items()}), 40) < 0
        mp.dps = 15


def test_hypotheses_cut_the_box_and_strict_goals_exclude_zero():
    box = [(x, -1.0, 1.0), (y, -1.0, 1.0)]
    assert prove(x - y + sp.Rational(1, 10), box).status == "counterexample"
    assert prove(x - y + sp.Rational(1, 10), box, hypotheses=[x - y]).status == "certified"
    assert prove(x**2 + 1, [(x, -1.0, 1.0)], strict=True).status == "certified"
    assert prove(x**2, [(x, -1.0, 1.0)], strict=True, max_boxes=2000).status != "certified"


# --------------------------------------------------------------------------- tampering

def _lemma1_tree():
    g = x * sp.tanh(x) - sp.Abs(x) + sp.Rational(557, 2000)
    r = prove(g, [(x, -4.0, 4.0)])
    assert r.status == "certified"
    return g, r.tree


def test_a_removed_box_or_an_edited_leaf_fails_the_recheck():
    g, tree = _lemma1_tree()
    checker = LeafChecker(g, [x], [], [])
    root = [(-4.0, 4.0)]
    assert walk(tree, root, checker, LEAF_NAME) > 10
    leaves = [i for i, b in enumerate(tree) if b in LEAF_NAME]
    with pytest.raises(CheckError):                 # a box removed
        walk(tree[:leaves[3]] + tree[leaves[3] + 1:], root, checker, LEAF_NAME)
    with pytest.raises(CheckError):                 # a box added
        walk(tree + bytes([LEAF["N"]]), root, checker, LEAF_NAME)
    # a leaf closed by the mean-value form claimed closed by the natural enclosure instead
    m = next(i for i in leaves if tree[i] == LEAF["M"])
    with pytest.raises(CheckError, match="enclosure lower bound"):
        walk(tree[:m] + bytes([LEAF["N"]]) + tree[m + 1:], root, checker, LEAF_NAME)
    # every leaf declared excluded by a hypothesis the goal does not have
    with pytest.raises(CheckError):
        walk(bytes(LEAF["X"] if b in LEAF_NAME else b for b in tree), root, checker, LEAF_NAME)
    # a bound of the domain edited: the same tree over a wider root box no longer closes
    with pytest.raises(CheckError):
        walk(tree, [(-4.0, 40.0)], checker, LEAF_NAME)


def _claim_certificate(cid: str):
    cl = CLAIMS[cid]
    tag = "corrected" if cl.corrected else "paper"
    st = (cl.corrected or cl.paper)()
    plan = plan_for(cl)(st)
    res, data = C.derive(cl, tag, st, plan, log=lambda *a: None)
    assert res.status == "certified", res.reason
    return cl, tag, st, plan, data


def test_a_claim_certificate_rechecks_and_tampering_is_caught():
    cl, tag, st, plan, data = _claim_certificate("c001.eso.w_bound")
    assert C.recheck(cl, tag, st, plan, data).recheck == "passed"
    bad = copy.deepcopy(data)                     # a box removed from a goal's tree
    tree = base64.b64decode(bad["goals"][0]["tree"])
    bad["goals"][0]["tree"] = base64.b64encode(tree[:-1]).decode()
    assert C.recheck(cl, tag, st, plan, bad).recheck.startswith("failed")
    bad = copy.deepcopy(data)                     # the box count edited
    bad["goals"][0]["boxes"] += 1
    assert C.recheck(cl, tag, st, plan, bad).recheck.startswith("failed")
    bad = copy.deepcopy(data)                     # another statement's certificate
    bad["statement_hash"] = "0" * 64
    assert C.recheck(cl, tag, st, plan, bad).status == "stale"
    bad = copy.deepcopy(data)                     # a region's bound edited in the plan
    reg = plan.regions[0]
    c0 = reg.coords[0]
    wider = Region((Coordinate(c0.symbol, c0.lo, c0.hi * 2, c0.unit), *reg.coords[1:]), reg.subs, reg.hypotheses,
                   reg.describe, reg.equilibria)
    plan2 = Plan([wider, *plan.regions[1:]], plan.domain, plan.reduce, plan.margin)
    assert C.recheck(cl, tag, st, plan2, bad).status == "stale"


def test_the_library_lemmas_are_proved_and_a_plan_lemma_is_refused():
    from rpo.symbolic.lyapunov.certify.lemmas import Lemma
    from rpo.symbolic.lyapunov.certify.plan import Use

    assert all(lem.verify() for lem in LIBRARY.values())
    cl = CLAIMS["c002.V2.lemma1"]
    tag = "corrected" if cl.corrected else "paper"
    st = (cl.corrected or cl.paper)()
    plan = plan_for(cl)(st)
    fake = Lemma("anything_goes", (x,), -x**2, (), "false: -x^2 >= 0", lambda: True)
    plan.uses = (Use(fake, {x: sp.Symbol("chi1_1", real=True)}),)
    res, data = C.derive(cl, tag, st, plan, log=lambda *a: None)
    assert data is None and res.status == "cannot" and "not in the library" in res.reason


def test_a_coordinate_whose_box_contradicts_its_assumptions_is_refused():
    p = sp.Symbol("p", positive=True)
    reg = Region((Coordinate(p, -1.0, 1.0),))
    st = lyapunov.core.Statement(p, ">=", 0, [])
    with pytest.raises(ValueError, match="declared positive"):
        goals(st, Plan([reg], "p in [-1, 1]"))


def test_a_theorem_is_certified_from_certified_claims_and_only_inside_their_domain():
    """004's eq. 38 from the certified eqs. 27 and 36 (certify/compose.py): certified, rests on both; a region
    reaching outside a used claim's certified domain, an edited used statement, or a claim without a
    certificate is refused."""
    from dataclasses import replace

    from rpo.symbolic.lyapunov.certify.compose import check_claim_use, claim_use
    from rpo.symbolic.lyapunov.certify.plan import Use

    cl = CLAIMS["c004.theorem.Vdot_bound"]
    st = cl.paper()
    plan = plan_for(cl, "paper")(st)
    res, data = C.derive(cl, "paper", st, plan, log=lambda *a: None)
    assert res.status == "certified" and data is not None
    assert data["depends"] == ["c004.position.V1dot_bound.paper", "c004.attitude.V2dot_bound.paper"]
    assert C.recheck(cl, "paper", st, plan, data).recheck == "passed"
    use = plan.uses[0]
    reg = plan.regions[0]
    k = next(i for i, c in enumerate(reg.coords) if c.symbol.name == "k1_1")
    c0 = reg.coords[k]
    wider = replace(reg, coords=(*reg.coords[:k], Coordinate(c0.symbol, c0.lo, 2 * c0.hi, c0.unit),
                                 *reg.coords[k + 1:]))
    with pytest.raises(CheckError, match="does not contain region 0"):
        check_claim_use(use, Plan([wider], plan.domain, uses=plan.uses))
    edited = Use(replace(use.lemma, gap=use.lemma.gap + 1), {}, 1, 0)
    with pytest.raises(CheckError, match="not the claim's statement"):
        check_claim_use(edited, plan)
    plan.uses = (*plan.uses, claim_use("c001.apf.convex_far", 0))       # not certified: no plan
    got, _ = C.derive(cl, "paper", st, plan, log=lambda *a: None)
    assert got.status == "cannot" and "has no plan" in got.reason


def test_a_certificate_resting_on_a_failed_one_does_not_count():
    from rpo.symbolic.lyapunov.report import resolve_dependencies

    def rec(cid, recheck, depends=()):
        cert = {"status": "certified", "recheck": recheck, "depends": list(depends)}
        return {"id": cid, "status": "proved (certified)", "_search_status": "not-disproved", "corrected": None,
                "evidence_statement": "paper", "certificate": cert, "implementation_certificate": None,
                "about": "abstract", "paper": {"proved": False, "holds": True}, "evidence": "certified"}

    good = [rec("a", "passed"), rec("b", "passed", ["a.paper"])]
    assert resolve_dependencies(good) == [] and good[1]["status"] == "proved (certified)"
    bad = [rec("c004.position.V1dot_bound", "failed: a leaf"), rec("c004.theorem.Vdot_bound", "passed",
                                                                     ["c004.position.V1dot_bound.paper"])]
    assert resolve_dependencies(bad) == ["c004.theorem.Vdot_bound"]
    assert bad[1]["certificate"]["recheck"].startswith("failed: it rests on c004.position.V1dot_bound.paper")
    assert bad[1]["status"] == "not-disproved" and bad[1]["evidence"] == "sampled"
    alone = [rec("c004.theorem.Vdot_bound", "passed", ["missing.paper"])]
    assert resolve_dependencies(alone) == ["c004.theorem.Vdot_bound"]
    assert "is not in this run" in alone[0]["certificate"]["recheck"]
