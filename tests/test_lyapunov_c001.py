"""001's Lyapunov claims (symbolic/lyapunov/c001.py): the local domain helpers draw what they say, the
hand-typed printed forms differ from the code by exactly the documented typos, and the paper findings come
with counterexamples that really violate the printed step (numeric only; the full symbolic check is
``verify.py``)."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from scipy.linalg import solve_continuous_lyapunov

from rpo.symbolic.controllers import c001 as c
from rpo.symbolic.lyapunov import c001 as L
from rpo.symbolic.lyapunov import domains
from rpo.symbolic.lyapunov.c001 import apf, common, eso, pose
from rpo.symbolic.lyapunov.check import _Evaluator, check_statement
from rpo.symbolic.lyapunov.core import Statement
from rpo.symbolic.physics import constraints
from rpo.symbolic.physics.rotations import dq_conj, dq_mul

CLAIMS = {cl.id: cl for cl in L.CLAIMS}
rng = np.random.default_rng(1)


def _draw(domain, n=300):
    ev = _Evaluator(Statement(0, "==", 0, domain))
    return ev.values(rng.uniform(-1, 1, size=(n, ev.dim)))


def test_claim_ids_and_mutations():
    assert len(CLAIMS) == len(L.CLAIMS)
    assert all(i.startswith("c001.") and cl.controller == "c001" for i, cl in CLAIMS.items())
    assert len(L.MUTATIONS) >= 6
    attrs = {m.attr for m in L.MUTATIONS}
    assert {"control_dual_force", "eso_rates"} <= attrs          # control law and observer law
    for m in L.MUTATIONS:
        assert m.affects and set(m.affects) <= set(CLAIMS), m.name
        assert hasattr(c, m.attr)


def test_admissible_poses_satisfy_both_constraints_by_the_vector_forms():
    """The pose sampler (any attitude, target inside the cone) against constraints.py (not c001)."""
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    env = _draw([common._admissible_var(q, 1e-3)], 500)
    Q = np.column_stack([env[s] for s in q])
    assert np.allclose(np.linalg.norm(Q[:, :4], axis=1), 1.0)
    assert np.allclose(np.sum(Q[:, :4] * Q[:, 4:], axis=1), 0.0, atol=1e-9)   # q_r . q_d = 0
    p = sp.Matrix(sp.symbols("p_1:4", real=True))
    fov = sp.lambdify(list(p), constraints.beta_fov(p, common.THETA, common.Z_N, common.R_T))
    ca = sp.lambdify(list(p), constraints.beta_ca(p, common.R_S, common.R_T))
    for row in Q[:100]:
        qr, qd = row[:4], row[4:]
        r_S = 2 * domains.qmul(np.array([qr * [-1, -1, -1, 1]]), np.array([qd]))[0, :3]   # eq. 7: 2 q_r* q_d
        assert fov(*(-r_S)) > 0 and ca(*(-r_S)) > 0
        assert common.RHO_MIN - 1e-9 <= np.linalg.norm(r_S) <= common.RHO_MAX + 1e-9
    # the coded dual-quaternion forms (eqs. 46, 48) agree
    bF = sp.lambdify(list(q), common._nostep(c.beta_fov_dq(q, c.camera_axis_matrix(sp.Matrix([0, 0, 1])), common.THETA,
                                                      common.Z_NP)))
    assert min(bF(*row) for row in Q) > 0


def test_boundary_fraction_reaches_the_fov_boundary():
    draw = common._admissible_draw(0.999999, 1.0 - 1e-12)
    Q = draw(rng.uniform(-1, 1, size=(50, 7)), {})
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    bF = sp.lambdify(list(q), common._nostep(c.beta_fov_dq(q, c.camera_axis_matrix(sp.Matrix([0, 0, 1])), common.THETA,
                                                      common.Z_NP)))
    vals = np.array([bF(*row) for row in Q])
    assert np.all(vals > -1e-9) and np.max(vals) < 1e-3


def test_desired_pose_and_lyapunov_solution():
    qD = np.array([float(x) for x in c.desired_pose(sp.Matrix(common.Q_D), sp.Matrix(common.R_D))])
    assert np.allclose(common._desired_dq(), qD, atol=1e-12)
    k1, k2 = sp.symbols("k1 k2", positive=True)
    Qs = sp.Matrix(2, 2, sp.symbols("a b b d"))
    P = eso._lyap_P(k1, k2, Qs)
    vals = {k1: 0.7, k2: 2.3, sp.Symbol("a"): 1.5, sp.Symbol("b"): 0.2, sp.Symbol("d"): 0.9}
    Kt = np.array([[-0.7, 1.0], [-2.3, 0.0]])
    Pn = solve_continuous_lyapunov(Kt.T, -np.array([[1.5, 0.2], [0.2, 0.9]]))
    assert np.allclose(np.array(P.subs(vals), dtype=float), Pn)


def test_printed_eq63_differs_by_exactly_the_two_coefficient_typos():
    printed, corrected = pose._eq63_printed(), pose._eq63_first_line_corrected()
    lp = pose._Loop()
    diff = sp.expand(printed.rhs - corrected.rhs)
    assert sp.expand(diff - ((lp.k_d - lp.k_v) * lp.ww + (lp.k_p - lp.k_v) * lp.Vd_dot)) == 0


def test_vd_decay_counterexample_of_the_paper_step():
    """At Delta omega = 0 and alpha = 0, V_d-dot = 0 > -V_d for any Delta d != 0 and D > 0."""
    st = pose._vd_decay(False)
    syms = sorted(st.free_symbols(), key=str)
    vals = [0.0 if s.name.startswith(("eta1", "alpha")) else 1.0 for s in syms]
    vd_dot, minus_vd = (float(sp.lambdify(syms, e)(*vals)) for e in (st.lhs, st.rhs))
    assert vd_dot == 0.0 and minus_vd < 0


def test_gain_condition_fails_for_every_anomaly_with_independent_numbers():
    n = math.sqrt(common.MU / common.SEMI_MAJOR**3)
    nu = np.linspace(-np.pi, np.pi, 2001)
    nudot = n * (1 + common.ECC * np.cos(nu)) ** 2 / (1 - common.ECC**2) ** 1.5
    a = np.linalg.norm([nudot * (common.TAU_SIN[i] * np.cos(nu) - common.TAU_COS[i] * np.sin(nu)) / common.INERTIA[i]
                        for i in range(3)], axis=0)
    for k1, k2 in common.ESO_GAINS.values():
        P = solve_continuous_lyapunov(np.array([[-k1, 1.0], [-k2, 0.0]]).T, -np.eye(2))
        lo, hi = np.linalg.eigvalsh(P)
        c_max = 0.25 / math.sqrt(hi) * common.KAPPA1**2 * math.sqrt(lo) / (common.DELTA * hi)
        assert c_max < a.min()
    out = check_statement(eso._gain_condition(), symbolic=False, trials=200)
    assert not out.holds


def test_antipodal_critical_point_is_the_same_physical_pose():
    q = sp.Matrix(sp.symbols("q_1:9", real=True))
    _, dq_err, grad = common._paper_apf(q, on_axis=True)
    crit = common._six(c.dq_vec(dq_mul(dq_conj(q), c.dq_swap(grad))))
    pts = apf._critical_points(q, crit, dq_err)
    qD = common._desired_dq()
    assert np.allclose(pts[1][:4], -qD[:4], atol=1e-12)                  # attitude: -q_D (same rotation)
    r = 2 * domains.qmul(np.array([pts[1][:4] * [-1, -1, -1, 1]]), np.array([pts[1][4:]]))[0, :3]   # r^S
    r_D = 2 * domains.qmul(np.array([qD[:4] * [-1, -1, -1, 1]]), np.array([qD[4:]]))[0, :3]
    assert 0 < np.linalg.norm(r - r_D) < 1e-6                             # shifted ~1e-7 m
    f = sp.lambdify(list(q), [c.circle(dq_err, dq_err)] + list(crit))
    vals = np.array(f(*pts[1]), dtype=float)
    assert abs(vals[0] - 4.0) < 1e-9 and np.max(np.abs(vals[1:])) < 1e-10


def test_constants_are_the_controller_defaults():
    k = {f.name: f.default for f in c.C001().k.fields}
    assert (common.K_P, common.K_D, common.K_A, common.K_R) == (k["k_p"][0], k["k_d"][0], k["k_a"][0], k["k_r"][0])
    assert common.ESO_GAINS["reconstructed"] == (k["K1"][0], k["K2"][0]) and common.FOV_EPS == k["fov_eps"][0]
    assert (common.F_MAX, common.TAU_MAX) == (k["F_max"][0], k["tau_max"][0])


def test_orbit_states_make_the_law_force_small():
    """On consistent orbit states f_G (~500 N) cancels against omega_T/I x (J_E omega_T/I) and J_E d_hat: the
    unsaturated force of eq. 57 is of the size of its PD and J_E Delta d terms (a few N), not ~1e4 N as with
    independent draws.  (The torque is not small: k_p vec(q* (E grad V_p)) couples the position error of the
    APF into the torque channel, ~1e2 N m at 100 m for arbitrary admissible attitudes.)"""
    st = pose._saturated_identity()
    lp = pose._Loop()
    env = _draw(st.domain, 300)
    byname = {s.name: s for s in env}
    syms = sorted(lp.fC.free_symbols, key=str)
    f = sp.lambdify(syms, list(lp.fC), "numpy")
    out = np.array([np.broadcast_to(np.asarray(o, float), (300,)) for o in f(*[env[byname[s.name]] for s in syms])])
    assert np.max(np.abs(out[[0, 1, 2]])) < 10.0
