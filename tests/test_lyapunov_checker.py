"""The Lyapunov checker itself (symbolic/lyapunov/check.py, core.py) on planted true and false statements:
it proves what is true, fails what is false with a counterexample that really violates the statement,
uses the constraints it is given and only those, and never calls a numeric result a proof."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

from rpo.symbolic.lyapunov import core
from rpo.symbolic.lyapunov.check import (
    DEFAULT,
    LOCAL_ONLY,
    TOL,
    Search,
    _Evaluator,
    check_claim,
    check_statement,
    numeric_search,
    prove_zero_cases,
)
from rpo.symbolic.lyapunov.core import Claim, Statement
from rpo.symbolic.lyapunov.domains import ball, box, unit_quaternion
from rpo.symbolic.physics import rotations as rot

a, b, x, y, z = sp.symbols("a b x y z", real=True)
k, d = sp.symbols("k delta", positive=True)


def test_true_polynomial_identity_is_proved():
    o = check_statement(Statement((a + b) ** 2, "==", a**2 + 2 * a * b + b**2, [box([a, b], -3, 3)]))
    assert o.holds and o.proved


def test_false_identity_fails_with_a_counterexample_that_violates_it():
    o = check_statement(Statement((a + b) ** 2, "==", a**2 + b**2, [box([a, b], -3, 3)]))
    assert not o.holds and not o.proved
    va, vb = o.counterexample["a"], o.counterexample["b"]
    assert abs((va + vb) ** 2 - (va**2 + vb**2)) > 1e-3          # it really is a counterexample
    assert o.residual == "2*a*b"                                 # readable residual


def test_unit_quaternion_identity_needs_its_constraint():
    """|p (x) q|^2 = 1 holds on unit quaternions only: proved with the constraints, numeric-only without."""
    p, q = core.symbols_vec("p", 4), core.symbols_vec("q", 4)
    lhs = rot.dot(rot.quat_mul(p, q), rot.quat_mul(p, q))
    dom = [unit_quaternion(p), unit_quaternion(q)]
    with_c = check_statement(Statement(lhs, "==", 1, dom, constraints=[core.quat_norm_constraint(p),
                                                                       core.quat_norm_constraint(q)]))
    without = check_statement(Statement(lhs, "==", 1, dom))
    assert with_c.holds and with_c.proved
    assert without.holds and not without.proved                  # not-disproved, never "proved"
    off_sphere = check_statement(Statement(lhs, "==", 1, [box(p, -1, 1), box(q, -1, 1)]))
    assert not off_sphere.holds


def test_sign_and_abs_identity():
    """s sign(s) = |s| (the form in which V-dots meet the switching terms)."""
    s = sp.Symbol("s", real=True)
    o = check_statement(Statement(-k * s * sp.sign(s), "==", -k * sp.Abs(s), [box(s, -2, 2), box(k, 0.1, 2)]))
    assert o.holds and o.proved


def test_inequality_proved_from_positive_gains_and_a_stated_bound():
    """-k s^2 + s d - D|s| <= 0 with |d| <= D: proved after writing D = |d| + delta (delta > 0)."""
    s, dd, D = sp.symbols("s d D", real=True)
    st = Statement(-k * s**2 + s * dd - D * sp.Abs(s), "<=", 0,
                   [box(s, -2, 2), box(k, 0.1, 2), box(D, 0, 1), ball([dd], D), box(d, 0, 1)],
                   positive=[k, d], substitutions={D: sp.Abs(dd) + d})
    # the numeric part cannot know delta is tied to D; the symbolic part uses the substitution
    o = check_statement(st)
    assert o.holds
    assert not o.proved        # s d - |d||s| has no sign SymPy can see term by term: honest "not proved"
    st2 = Statement(-k * s**2 - d * sp.Abs(s), "<=", 0, [box(s, -2, 2), box([k, d], 0.1, 2)], positive=[k, d])
    assert check_statement(st2).proved


def test_local_optimisation_finds_what_random_sampling_misses():
    """x + y <= 1.9 on [-1, 1]^2 fails only near the corner; 8 random points miss it, L-BFGS-B does not."""
    st = Statement(x + y, "<=", 1.9, [box([x, y], -1, 1)], symbolic=False)
    _, _, v_random, _ = numeric_search(st, seed=1, trials=8, search=Search(starts=0, global_evals=0))
    assert v_random <= 0
    o = check_statement(st, seed=1, trials=8, search=LOCAL_ONLY)
    assert not o.holds
    assert o.counterexample["x"] + o.counterexample["y"] > 1.9


@pytest.mark.parametrize(("V", "expect"), [
    (k * x**2 + 3 * y**2 + k * (x - y) ** 2, "proved"),
    (x**2 - y**2, "fails"),
    (x**2 * y**2 + z**2, "not-disproved"),   # >= 0 but zero on the x = z = 0 line: not definite in x
])
def test_definiteness(V, expect):
    zero_at = [x, y, z] if V.has(z) else [x, y]
    st = Statement(V, ">", 0, [box([x, y, z], -2, 2), box(k, 0.1, 3)], positive=[k], zero_at=zero_at)
    o = check_statement(st)
    got = "fails" if not o.holds else ("proved" if o.proved else "not-disproved")
    assert got == expect


def test_ball_and_unit_quaternion_domains_satisfy_their_constraints():
    rng = np.random.default_rng(0)
    v, r = core.symbols_vec("v"), sp.Symbol("r", positive=True)
    q = core.symbols_vec("q", 4)
    st = Statement(0, "==", 0, [box(r, 0, 2), ball(v, r), unit_quaternion(q)])
    from rpo.symbolic.lyapunov.check import _Evaluator
    ev = _Evaluator(st)
    env = ev.values(rng.uniform(-1, 1, size=(500, ev.dim)))
    norms = np.linalg.norm(np.column_stack([env[s] for s in v]), axis=1)
    assert np.all(norms <= env[r] + 1e-12)
    qn = np.linalg.norm(np.column_stack([env[s] for s in q]), axis=1)
    assert np.allclose(qn, 1.0)


def test_domain_must_draw_every_symbol():
    with pytest.raises(ValueError, match="b"):
        check_statement(Statement(a + b, "==", b + a, [box(a, 0, 1)]))


def test_lie_derivative_along_a_known_flow():
    """V = x^2 + y^2 along the rotation x' = -y, y' = x is constant; along x' = -x it decays as -2x^2."""
    V = x**2 + y**2
    assert sp.simplify(core.lie_derivative(V, [x, y], [-y, x])) == 0
    assert sp.expand(core.lie_derivative(V, [x, y], [-x, 0])) == -2 * x**2
    with pytest.raises(ValueError):
        core.lie_derivative(V, [x, y], [-x])


def _stmt(lhs, rhs):
    return lambda: Statement(lhs, "==", rhs, [box([a, b], -2, 2)])


@pytest.mark.parametrize(("paper", "corrected", "about", "status", "impl_ok"), [
    (_stmt(a * b, b * a), None, "implementation", "proved", True),
    (_stmt(a * b, -b * a), _stmt(a * b, b * a), "implementation", "holds-with-stated-correction", True),
    (_stmt(a * b, -b * a), _stmt(a * b, 2 * b * a), "implementation", "fails", False),
    (_stmt(a * b, -b * a), None, "implementation", "fails", False),
    (_stmt(a * b, -b * a), None, "paper", "fails", True),       # a finding about the paper, not a defect
    (None, _stmt(a * b, b * a), "implementation", "proved", True),    # a step of ours, not the paper's
])
def test_claim_status_logic(paper, corrected, about, status, impl_ok):
    cl = Claim("t.x", "t", "p", "abstract", "1", "t", paper, corrected, about=about)
    r = check_claim(cl)
    assert (r.status, r.implementation_ok) == (status, impl_ok)


def test_mutation_patches_and_restores_even_on_error():
    import types
    mod = types.SimpleNamespace(f=lambda g, s: g * s)
    m = core.Mutation("flip", mod, "f", core.scale_argument("g", -1), ())
    orig = mod.f
    with pytest.raises(RuntimeError), m:
        assert mod.f(2, x) == -2 * x
        raise RuntimeError
    assert mod.f is orig
    with core.Mutation("neg", mod, "f", core.negate_output(), ()):
        assert mod.f(2, x) == -2 * x
    with core.Mutation("drop", mod, "f", core.drop_terms(y), ()):
        assert mod.f(1, x + y) == x


def test_rotation_domain_used_by_claims_is_a_rotation():
    """The MRP -> matrix map the claims draw R from (domains.rotation_matrix) is scipy's (independent of the
    model's eq. 9)."""
    from rpo.symbolic.lyapunov.domains import rotation_matrix

    z = np.random.default_rng(2).uniform(-1, 1, size=(50, 3))
    R = rotation_matrix(sp.symbols("R_1:10")).draw(z, {}).reshape(-1, 3, 3)
    assert np.allclose(np.einsum("nij,nkj->nik", R, R), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(R), 1.0)
    sig = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1.0)
    assert np.allclose(R[0], Rotation.from_mrp(sig[0]).as_matrix())


def test_identity_whose_value_is_zero_is_not_failed_for_round_off():
    """(a + b)^2 - a^2 - 2ab - b^2 == 0 at large a, b: float noise is judged against the terms' size."""
    st = Statement((a + b) ** 2 - a**2 - 2 * a * b - b**2, "==", 0, [box([a, b], 1e3, 1e5)], symbolic=False)
    assert check_statement(st).holds
    st_false = Statement((a + b) ** 2 - a**2 - 2 * a * b - b**2 + 1e-3 * a, "==", 0, [box([a, b], 1e3, 1e5)],
                         symbolic=False)
    assert not check_statement(st_false).holds


def test_roots_and_function_constraints_share_their_symbols():
    """x / sqrt(x) = sqrt(x) needs t**2 = x for t = sqrt(x); a constraint on sign(s) reaches the residual."""
    xp = sp.Symbol("xp", positive=True)
    o = check_statement(Statement(xp / sp.sqrt(xp), "==", sp.sqrt(xp), [box(xp, 0.1, 4)]))
    assert o.holds and o.proved
    s = sp.Symbol("s", real=True)
    st = Statement(sp.sign(s) ** 2 * a, "==", a, [box([s, a], 0.1, 2)], constraints=[sp.sign(s) ** 2 - 1])
    assert check_statement(st).proved


# --------------------------------------------------------------------------- piecewise identities (case split)

_H = sp.Symbol("h", real=True)      # any value of Heaviside at 0


@pytest.mark.parametrize("lhs, rhs", [
    (sp.sign(x) * x, sp.Abs(x)),
    (sp.Max(x, 0), (x + sp.Abs(x)) / 2),
    (sp.Heaviside(x, _H) * x, sp.Max(x, 0)),                  # whatever Heaviside(0) is
    (sp.sign(x), 2 * sp.Heaviside(x) - 1),                    # SymPy's Heaviside(0) = 1/2
    (sp.Abs(x - 1) + sp.Abs(x + 1), 2 * sp.Max(sp.Abs(x), 1)),
    (sp.Max(x - d, 0) + sp.Min(x + d, 0), x - d * sp.Max(-1, sp.Min(1, x / d))),    # s - d sat(s/d)
    (sp.Piecewise((0, sp.Abs(x) <= d), (x - d * sp.sign(x), True)), sp.Max(x - d, 0) + sp.Min(x + d, 0)),
])
def test_case_split_proves_true_piecewise_identities(lhs, rhs):
    assert prove_zero_cases(lhs - rhs, positive=[d]) == (True, "")
    assert check_statement(Statement(lhs, "==", rhs, [box(x, -2, 2), box([d, _H], 0.1, 1)])).proved


@pytest.mark.parametrize("lhs, rhs, where", [
    (sp.sign(x), 2 * sp.Heaviside(x, 1) - 1, "x = 0"),                    # false at the switching point only
    (sp.Max(x, 0), sp.Piecewise((x, x > 0), (1, sp.Eq(x, 0)), (0, True)), "x = 0"),
    (sp.Max(x, 0), x * sp.Heaviside(x - sp.Rational(1, 10**6)), "= 0"),   # false on 0 < x <= 1e-6
    (sp.Abs(x - 1) + sp.Abs(x + 1), 2 * sp.Max(sp.Abs(x), 1) + sp.Max(0, sp.Rational(1, 10**6) - sp.Abs(x)),
     " 0"),                                                                   # false on |x| < 1e-6
])
def test_case_split_refuses_identities_false_on_a_small_set(lhs, rhs, where):
    """The numeric search cannot see these (a point, or a set of measure 1e-6): it reports them as holding,
    and the case split must not call them proved; its note names the case that fails."""
    ok, note = prove_zero_cases(lhs - rhs)
    assert not ok and where in note
    o = check_statement(Statement(lhs, "==", rhs, [box(x, -2, 2)]))
    assert o.holds and not o.proved                           # not-disproved, never proved


def test_case_split_uses_the_stated_hypotheses_and_only_those():
    """S = max(s - d, 0) + min(s + d, 0) is 0 inside the layer |s| <= d only: the cases outside are empty
    under the hypothesis, and not without it."""
    S = sp.Max(x - d, 0) + sp.Min(x + d, 0)
    assert prove_zero_cases(S, hypotheses=[sp.Abs(x) <= d])[0]
    assert not prove_zero_cases(S)[0]
    assert not prove_zero_cases(S, hypotheses=[sp.Abs(x) <= 2 * d])[0]


def test_case_split_decides_a_nonlinear_switch_modulo_the_constraints():
    """sqrt(max(q^T q - 1 + a^2 + b^2, 0)) = sqrt(a^2 + b^2) on unit quaternions: the radicands agree modulo
    q^T q = 1, and the case q^T q - 1 + a^2 + b^2 < 0 is empty because it equals a^2 + b^2 >= 0 there."""
    q = core.symbols_vec("q", 4)
    u = rot.dot(q, q) - 1 + a**2 + b**2
    for lhs in (sp.sqrt(sp.Max(u, 0)), sp.sqrt(u * sp.Heaviside(u, 1))):
        assert prove_zero_cases(lhs - sp.sqrt(a**2 + b**2), [core.quat_norm_constraint(q)])[0]
        assert not prove_zero_cases(lhs - sp.sqrt(a**2 + b**2))[0]       # the constraint is needed


# --------------------------------------------------------------------------- violations in small regions

_XS = sp.symbols("x1:7", real=True)
_HAT_A, _HAT_W, _HAT_S = 0.5, 0.294, 0.005     # top-hat [0.5, 0.794] of each coordinate, edges 0.005 wide


def _planted_small_region() -> Statement:
    """sum_i h(x_i) <= 6.45 on [-1, 1]^6, h = 0.2 (1 - x^2) + a smooth top-hat of height 1 on [0.5, 0.794].

    False only where all six coordinates are on their top-hats (each one off it costs >= 0.875, more than the
    0.45 the broad part can give back): a region of measure ~ (0.147)^6 ~ 1e-5 of the box.  Local ascent
    from a point with one coordinate off its top-hat climbs the broad hump at 0 instead (the top-hat's flanks
    are 0.005 wide), so L-BFGS-B from the worst random points only finds the region if one of them already
    lies in it; differential evolution recombines the good coordinates of different points."""
    def h(x):
        return (sp.Rational(1, 5) * (1 - x**2)
                + (sp.tanh((x - _HAT_A) / _HAT_S) - sp.tanh((x - _HAT_A - _HAT_W) / _HAT_S)) / 2)
    return Statement(sum(h(x) for x in _XS), "<=", 6 * 1.075, [box(list(_XS), -1, 1)], symbolic=False)


def test_planted_violation_region_has_measure_about_1e_5():
    """The planted region's measure, estimated inside the product of the top-hats (which contains it)."""
    ev = _Evaluator(_planted_small_region())
    rng = np.random.default_rng(0)
    lo, hi = _HAT_A - 0.01, _HAT_A + _HAT_W + 0.01
    inside = np.mean(ev.violation(rng.uniform(lo, hi, size=(200_000, 6))) > 0)
    measure = inside * ((hi - lo) / 2) ** 6
    assert 3e-6 < measure < 3e-5
    # and off the top-hats nothing is violated: 200,000 uniform points of the box hit it about twice
    assert np.sum(ev.violation(rng.uniform(-1, 1, size=(200_000, 6))) > 0) <= 6


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_global_stage_finds_a_violation_that_sampling_and_local_ascent_miss(seed):
    st = _planted_small_region()
    tol = TOL["<="]
    # 2000 uniform points (the default trials) miss it ...
    _, _, v_uniform, _ = numeric_search(st, seed=seed, search=Search(starts=0, global_evals=0))
    assert v_uniform <= tol
    # ... and so does the search before the global stage (L-BFGS-B from the worst 6 of them)
    _, _, v_local, _ = numeric_search(st, seed=seed, search=LOCAL_ONLY)
    assert v_local <= tol
    # the default search (same samples and starts, then differential evolution) finds it
    o = check_statement(st, seed=seed, search=DEFAULT)
    assert not o.holds
    vals = [o.counterexample[str(x)] for x in _XS]
    assert all(_HAT_A <= v <= _HAT_A + _HAT_W for v in vals)          # really inside the region
    assert o.trials <= 2000 + 6 * 1500 + DEFAULT.global_evals + 1500  # within the stated budget


def test_global_stage_is_not_run_for_identities():
    """A true identity costs only the samples and the local starts (its proof is symbolic)."""
    st = Statement((a + b) ** 2, "==", a**2 + 2 * a * b + b**2, [box([a, b], -3, 3)], symbolic=False)
    _, _, _, n = numeric_search(st, search=DEFAULT)
    assert n < DEFAULT.global_evals


def test_scenario_data_follow_extends_and_match_the_claims():
    """The claims read the papers' data from scenarios/*.toml; a variant inherits its base's tables."""
    from rpo.symbolic.lyapunov.c002.common import PAPER_GAINS
    from rpo.symbolic.lyapunov.scenarios import controller_gains, scenario

    base, variant = scenario("000_scenario_III"), scenario("000_III_no_acc_d")
    assert "extends" not in variant
    assert variant["controller"]["c000"]["acc_d_on"] == 0.0
    assert variant["controller"]["c000"]["lam_pos"] == base["controller"]["c000"]["lam_pos"]
    assert PAPER_GAINS["k3"] == controller_gains("002_scenario", "c002")["k3"] == 4.0
