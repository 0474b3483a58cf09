"""Helpers of the 002 Lyapunov claims (symbolic/lyapunov/c002.py): the rewriting and pruning helpers are
exact, the printed steps fail by exactly the stated residual (not an artefact of the search), and the
paper-data numbers quoted in the notes (varpi at t = 0, the Lemma 2 gap) are what the code computes."""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.spatial.transform import Rotation

from rpo.symbolic.controllers import c002 as C
from rpo.symbolic.lyapunov import core
from rpo.symbolic.lyapunov.c002 import common, gains, model, v1, v2
from rpo.symbolic.lyapunov.check import _Evaluator, check_statement
from rpo.symbolic.lyapunov.core import Statement
from rpo.symbolic.lyapunov.domains import ball, box
from rpo.symbolic.physics.rotations import dot

RNG = np.random.default_rng(2)


def _at_random_point(st, n=5):
    ev = _Evaluator(st)
    return ev.lhs_rhs(RNG.uniform(-1, 1, size=(n, ev.dim))), ev


def test_tanh_form_is_the_identity_cosh2_times_1_minus_tanh2():
    x = sp.Symbol("x", real=True)
    e = common._tanh_form(C.aux_phi_inverse(sp.Matrix([x]))[0, 0] * (1 - sp.tanh(x) ** 2))
    assert sp.simplify(e) == 1
    f = sp.lambdify(x, common._tanh_form(sp.cosh(x) ** 2))
    assert np.allclose(f(np.linspace(-3, 3, 7)), np.cosh(np.linspace(-3, 3, 7)) ** 2)


def test_prune_keeps_what_the_draws_depend_on():
    a, r = sp.symbols("a r", positive=True)
    v, u = sp.Matrix(sp.symbols("v1:4", real=True)), sp.Symbol("u", real=True)
    dom = [box(r, 0, 1), box(u, 0, 1), box(a, 0, 1), ball(v, r)]
    kept = core.prune(dom, v[0] + a)
    assert [s for var in kept for s in var.symbols] == [r, a, *v]       # r kept (radius), u dropped


def test_printed_v1_doubles_the_adaptation_term():
    """Eq. 26 with sum alpha~^2/beta: V1_dot - eq. 27 = -sum alpha~_i alpha^_i_dot / beta_i exactly."""
    st = v1._v1_chain(False)()
    S = common._S()
    ad = sp.Matrix(sp.symbols("alphahatdot_1:10", real=True))
    extra = -sum(S.atilde[i] * ad[i] / S.beta[i] for i in range(9))
    assert sp.simplify(st.lhs - st.rhs - extra) == 0


def test_printed_k2_in_eq_27_leaves_m_k5_minus_k2_s2_rdot():
    paper, corr = v1._v1_closed_loop("k2")(), v1._v1_closed_loop("k5")()
    S = common._S()
    s2 = C.sliding_surface_position(S.v, S.r, S.chi2, S.k5, S.k6)
    expect = S.m * (S.k5 - S.k2) * dot(s2, S.v - S.C_t * S.r)
    st = Statement(paper.lhs - paper.rhs, "==", expect, paper.domain)
    (lhs, rhs), _ = _at_random_point(st)
    assert np.allclose(lhs, rhs, rtol=1e-9, atol=1e-9) and np.all(np.abs(rhs) > 1e-6)
    (lhs, rhs), _ = _at_random_point(corr)
    assert np.allclose(lhs, rhs, rtol=1e-9)


def test_remark4_counterexample_is_real():
    """At the checker's counterexample, C_r w~ of the paper's eq. 4 (typed in NumPy) exceeds a1 b1|w| + b1|w|^2."""
    o = check_statement(model._Bounds().remark4_Cr(1), symbolic=False)
    assert not o.holds
    cx = o.counterexample
    J = np.zeros((3, 3))
    for i in range(3):
        for j in range(i, 3):
            J[i, j] = J[j, i] = cx[f"J_{i + 1}{j + 1}"]
    q = np.array([cx["q_1"], cx["q_2"], cx["q_3"], cx["q_0"]])
    R = Rotation.from_quat(q).as_matrix().T                     # C_{p<-t}
    w = np.array([cx[f"omega_{i}"] for i in (1, 2, 3)])
    wt = R @ np.array([cx[f"omega_t_{i}"] for i in (1, 2, 3)])

    def sk(a):
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

    Cr = J @ sk(wt) + sk(wt) @ J - sk(J @ (w + wt))
    a1, b1 = cx["a_1"], cx["b_1"]
    assert np.linalg.norm(wt) <= a1 + 1e-12 and np.linalg.norm(J, 2) <= b1 + 1e-9
    W = np.linalg.norm(w)
    assert np.linalg.norm(Cr @ w) > a1 * b1 * W + b1 * W**2
    assert np.linalg.norm(Cr @ w) <= 3 * a1 * b1 * W + b1 * W**2


def test_lemma2_gap_exceeds_eps_for_the_papers_k3():
    """max_x k (x - x^2/sqrt(x^2 + eps^2)) = 0.3003 k eps: > eps for k > 3.33 (k3 = 4 in the paper)."""
    x = np.linspace(0, 5, 200001)
    gap = (x - x**2 / np.sqrt(x**2 + 1)).max()
    assert abs(gap - 0.30028) < 1e-4
    assert common.PAPER_GAINS["k3"] * gap > 1 > common.PAPER_GAINS["k7"] * gap


def test_varpi_at_t0_of_the_papers_scenario():
    """||sat(eps(0)) - eps(0)||: 2.67 N m (torque limit 1) > kappa1 = 2; 172 N (force limit 1, printed label),
    0.50 N (force limit 100, rpo's reading) against kappa2 = 2."""
    vals = {}
    for key, build in (("att", gains._kappa_condition("att", 2.0, 1.0, "")),
                       ("pos1", gains._kappa_condition("pos", 2.0, 1.0, "")),
                       ("pos100", gains._kappa_condition("pos", 2.0, 100.0, ""))):
        st = build()
        ev = _Evaluator(st)
        vals[key] = float(ev.lhs_rhs(np.zeros((1, ev.dim)))[1][0, 0])
    assert abs(vals["att"] - 2.672) < 1e-3
    assert abs(vals["pos1"] - 171.97) < 0.05
    assert abs(vals["pos100"] - 0.5) < 0.01


def test_eq38_fails_only_through_unequal_weights():
    """The printed eq. 38 fails; at its counterexample the per-axis (corrected) form holds."""
    paper, corr = v2._v2_bound(False)(), v2._v2_bound(True)()
    o = check_statement(paper, symbolic=False)
    assert not o.holds
    ev = _Evaluator(corr)
    z = np.array([[o.counterexample[str(s)] for s in ev.symbols]])
    f = sp.lambdify(ev.symbols, corr.rhs - corr.lhs)
    assert f(*z[0]) >= 0
    chi = [o.counterexample[f"chi1_{i}"] for i in (1, 2, 3)] + [o.counterexample[f"chi2_{i}"] for i in (1, 2, 3)]
    assert np.ptp(np.abs(chi[:3])) > 0.1 or np.ptp(np.abs(chi[3:])) > 0.1


def test_time_varying_inertia_leaves_exactly_the_jdot_mdot_terms():
    """With J(t), m(t), V1_dot - eq. 27 = 1/2 s1^T J_dot s1 + 1/2 m_dot ||s2||^2 exactly."""
    st = v1._v1_time_varying()
    S = common._S()
    Jdot, mdot = common._sym_matrix("Jdot"), sp.Symbol("mdot", real=True)
    extra = dot(S.s1, Jdot * S.s1) / 2 + mdot * dot(S.s2, S.s2) / 2
    assert sp.expand(st.lhs - st.rhs - extra) == 0


def test_eq29_with_11_eps_fails_for_large_k3_k7_at_s_near_eps():
    """The reviewer's hand point: k3 = k7 = 20, |s1| = |s2| = 0.786 eps along x, alpha^ = 0, Phi aligned with s at
    full radius: V1_dot > rhs with 11 eps, < rhs with (9 + k3 + k7) eps."""
    A = v1._Abstract()
    S = A.S
    e, x = 1e-3, 0.7862e-3
    vals = {S.eps: e, S.k3: 20, S.k7: 20, S.k4: 1, S.k8: 1, S.m: 95}
    vals.update(dict(zip(S.Jd.diagonal(), [21, 18, 16], strict=True)))
    u = [1, 0, 0]
    for i in range(3):
        vals.update({S.s1[i]: x * u[i], S.s2[i]: x * u[i], S.w[i]: 0.5 * u[i], S.v[i]: u[i], S.r[i]: 2 * u[i]})
    for i in range(9):
        vals.update({S.ahat[i]: 0, S.alpha[i]: 1, S.beta[i]: 1, S.gamma[i]: 1})
    r1, r2 = 0.25 + 0.5 + 1, 0.5 + 1 + 0.5 + 1 + 2 + 1
    for i in range(3):
        vals.update({A.Phi1[i]: r1 * u[i], A.Phi2[i]: r2 * u[i]})
    lhs = float(A.V1dot.subs(vals))
    assert lhs > float((A.nominal + A.young + 11 * S.eps).subs(vals))
    assert lhs < float((A.nominal + A.young + (9 + S.k3 + S.k7) * S.eps).subs(vals))


def test_law_sat_is_opaque_clip():
    """_opaque_sat rewrites the law's Max(-u, Min(u, e)) and evaluates as a clip."""
    e, u = sp.symbols("e u", real=True)
    expr = model._opaque_sat(C.saturation(sp.Matrix([e]), u)[0])
    assert not expr.has(sp.Max, sp.Min)
    f = sp.lambdify([e, u], expr, "numpy")
    assert np.allclose(f(np.array([-3.0, 0.5, 3.0]), 1.0), [-1.0, 0.5, 1.0])
