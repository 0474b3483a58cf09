"""004's Lyapunov claims (symbolic/lyapunov/c004.py): the hand-typed printed forms differ from the code by
exactly the documented errata, the local domain helpers draw what they say, and the paper findings come
with counterexamples that really violate the printed step (numeric only; the full symbolic check is
``verify.py``)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from rpo.symbolic.controllers import c004 as c
from rpo.symbolic.lyapunov import c004 as L
from rpo.symbolic.lyapunov import core, domains
from rpo.symbolic.lyapunov.c004 import common, position
from rpo.symbolic.lyapunov.check import _Evaluator, check_claim
from rpo.symbolic.lyapunov.core import Statement, symbols_vec
from rpo.symbolic.lyapunov.domains import ball

CLAIMS = {cl.id: cl for cl in L.CLAIMS}
rng = np.random.default_rng(4)


def _num(e, subs):
    return np.array(sp.Matrix(e).subs(subs).evalf(), dtype=float)


def test_claim_ids_are_unique_and_every_mutation_names_existing_claims():
    assert len(CLAIMS) == len(L.CLAIMS)
    assert all(i.startswith("c004.") and cl.controller == "c004" for i, cl in CLAIMS.items())
    assert len(L.MUTATIONS) >= 8
    for m in L.MUTATIONS:
        assert m.affects and set(m.affects) <= set(CLAIMS), m.name
        assert hasattr(c, m.attr)
    # the report puts titles, corrections and mutation names in Markdown tables
    assert not any("|" in t for cl in L.CLAIMS for t in (cl.title, cl.correction, cl.equations))
    assert not any("|" in m.name for m in L.MUTATIONS)


def test_printed_y_and_Y_differ_from_the_code_by_the_documented_terms():
    g, v_e, r_e, w, w_e, sig = (symbols_vec(n) for n in ("g", "v_e", "r_e", "omega", "omega_e", "sigma_e"))
    L1, L2 = sp.diag(*sp.symbols("l1:4")), sp.diag(*sp.symbols("m1:4"))
    dy = common._printed_y(g, v_e, r_e, w, L1) - c.position_regressor(g, v_e, r_e, w, L1)
    assert sp.expand(dy - 2 * L1 * v_e) == sp.zeros(3, 1)
    dY = c.attitude_regressor(w, w_e, sig, L2) - common._printed_Y(w, w_e, sig, L2)
    assert sp.expand(dY - 2 * c.inertia_operator(L2 * c.mrp_kinematics(sig, w_e))) == sp.zeros(3, 6)


def test_printed_L_row_1_and_printed_eq9_fail_where_the_code_holds():
    J = common._sym3("J")
    a = symbols_vec("a")
    th = c.inertia_parameters(J)
    assert sp.expand(c.inertia_operator(a) * th - J * a) == sp.zeros(3, 1)
    assert sp.expand(common._printed_L(a) * th - J * a)[0] != 0
    assert sp.expand(common._printed_L(a) * th - J * a)[1:, :] == sp.zeros(2, 1)      # rows 2, 3 as printed are right
    s = {x: v for x, v in zip(symbols_vec("sigma_e"), (0.3, -0.5, 0.6), strict=True)}
    sig = symbols_vec("sigma_e")
    R_code, R_printed = _num(c.rotation_matrix(sig), s), _num(common._printed_R(sig), s)
    assert np.allclose(R_code.T @ R_code, np.eye(3), atol=1e-12)
    assert np.abs(R_printed.T @ R_printed - np.eye(3)).max() > 0.5


def _draw(domain, n=200):
    st = Statement(0, "==", 0, domain)
    ev = _Evaluator(st)
    return ev.values(rng.uniform(-1, 1, size=(n, ev.dim)))


def test_domain_helpers_draw_positive_definite_inertias_their_inverses_and_the_code_rotation():
    J = common._opaque_inverse("J")
    sig, R = symbols_vec("sigma_e"), common._rotation_symbols()
    dom = [domains.spd_dominant(J, (200, 700), 60), common._inverse_var(J), ball(sig, 1.0),
           common._code_rotation(R, sig)]
    env = _draw(core.prune(dom, sp.Matrix([*J, *J.inv(), *R])))
    Jn, Ji, Rn = common._stack(list(J), env), common._stack(list(J.inv()), env), common._stack(list(R), env)
    assert np.all(np.linalg.eigvalsh(Jn)[:, 0] > 0)
    assert np.allclose(Jn @ Ji, np.eye(3), atol=1e-12)
    f = sp.lambdify(list(sig), c.rotation_matrix(sig), "numpy")
    k = 7
    assert np.allclose(Rn[k], np.array(f(*[env[x][k] for x in sig]), dtype=float), atol=1e-12)
    assert np.allclose(np.einsum("nji,njk->nik", Rn, Rn), np.eye(3), atol=1e-12)


def test_finish_keeps_what_the_statement_and_its_kept_entries_need():
    P = position._Position()
    dom = core.prune(P.domain(), c.dot(P.s1, P.d_f) * P.rho_m)
    drawn = {s for v in dom for s in v.symbols}
    assert set(P.d_f) | {P.rho_f, P.rho_m, P.m} | set(domains.upper(P.Jt)) <= drawn     # ball radius, rho_m's inputs
    assert not (set(P.k1) | set(P.R) | set(P.p_t)) & drawn                         # unused: dropped
    assert len(drawn) == sum(len(v.symbols) for v in dom)                          # nothing drawn twice


def test_opaque_inverse_is_what_the_code_functions_call():
    J = common._opaque_inverse("J")
    w, t = symbols_vec("w"), symbols_vec("t")
    out = c.rotational_dynamics(J, w, t, sp.zeros(3, 1))
    assert out.free_symbols & set(J.inv()) and not any(isinstance(e, sp.Pow) and e.exp < 0
                                                       for e in sp.preorder_traversal(out[0]))


def test_printed_steps_fail_with_real_counterexamples_and_the_corrected_hold_numerically():
    for cid in ("c004.position.surface_dynamics", "c004.attitude.regressor_form", "c004.model.eq9_rotation"):
        r = check_claim(CLAIMS[cid], symbolic=False, trials=300)
        assert r.status == "holds-with-stated-correction" and r.implementation_ok, cid
        assert not r.paper.holds and r.paper.counterexample


def test_shadow_switch_finding_is_a_real_upward_jump_on_an_outward_crossing():
    r = check_claim(CLAIMS["c004.attitude.V2_shadow_switch"], symbolic=False, trials=500)
    assert r.status == "fails" and r.implementation_ok          # a finding about the paper, not a defect
    cx = r.paper.counterexample
    sig = np.array([cx[f"sigma_e_{i}"] for i in (1, 2, 3)])
    w_e = np.array([cx[f"omega_e_{i}"] for i in (1, 2, 3)])
    assert abs(np.linalg.norm(sig) - 1) < 1e-9 and sig @ w_e >= 0
    s_before, s_after = w_e + 0.2 * sig, w_e - 0.2 * sig          # shadow of a unit sigma is -sigma
    assert s_after @ common.J_PAPER @ s_after > s_before @ common.J_PAPER @ s_before


@pytest.mark.parametrize("name", ["c004: printed eq. 9 (S^T S)", "c004: -gamma6 in the rho^_J adaptation (eq. 36)"])
def test_a_mutation_fails_its_claims(name):
    m = next(x for x in L.MUTATIONS if x.name == name)
    with m:
        for cid in m.affects[:2]:
            r = check_claim(CLAIMS[cid], symbolic=False, trials=300)
            assert not (r.corrected or r.paper).holds, cid


def test_sigma_e0_finding_and_the_shadow_set_used_by_rpo():
    s = np.array(common.SIGMA_E0)
    assert s @ s > 1
    r = check_claim(CLAIMS["c004.theorem.sigma_e0_constraint"], symbolic=False)
    assert r.status == "holds-with-stated-correction"
