"""Helpers of the 000 Lyapunov claims (symbolic/lyapunov/c000.py): the hand-typed printed forms are the
printed equations, the law wrapper feeds the spacecraft claims what C000.law generates, and the paper's
failing steps fail for the stated reason (not for an artefact of the search)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import sympy as sp

from rpo.symbolic.controllers import c000 as C
from rpo.symbolic.lyapunov.c000 import attitude, boundary_layer, common, translation
from rpo.symbolic.lyapunov.check import check_statement
from rpo.symbolic.physics.relative_translation import relative_acceleration
from rpo.symbolic.physics.rotations import quat_to_dcm

ROOT = Path(__file__).resolve().parents[1]


def test_printed_translation_laws_in_the_codes_regressor_convention():
    """eqs. 113-115 print -x_dot S, -y S, -x S; the code's y regressors are (x_dot, y, -x), so the printed
    factors of phi S are (-1, -1, +1); x (eqs. 96-100) and z (eq. 127) are all -phi S."""
    r, v = sp.Matrix(sp.symbols("x y z", real=True)), sp.Matrix(sp.symbols("xd yd zd", real=True))
    S = sp.Symbol("S", real=True)
    _, phi = C.translation_regressors(r, v, 0, 0, sp.Symbol("r_c", positive=True), 0)
    printed = [-v[0] * S, -r[1] * S, -r[0] * S]
    assert [sg * p * S for sg, p in zip(translation.PRINTED_RATE_SIGNS[1], phi[1], strict=True)] == printed
    assert translation.PRINTED_RATE_SIGNS[0] == [-1] * 5 and translation.PRINTED_RATE_SIGNS[2] == [-1]
    # eq. 109: + for alpha_yy3 and h, - for alpha_yy1, alpha_yy2
    assert translation.PRINTED_V_SIGNS[1] == [-1, -1, 1]


def test_law_wrapper_has_no_branches_and_returns_the_body_force():
    ctrl, M, tau, F, rates, dg, sig, mu = common._law()
    for e in (tau, F, *rates.values(), *dg.values()):
        assert not e.atoms(sp.Piecewise)
    assert sig in tau.free_symbols and set(M["q_cL"]) <= F.free_symbols
    # at q_cL = identity F is the LVLH force of eqs. 86, 108, 121
    F_id = F.xreplace(dict(zip(M["q_cL"], [0, 0, 0, 1], strict=True)))
    assert sp.simplify(F_id[2] - C.translation_control_axis(
        ctrl.xc["h_hat_zz"], C.u1_term(ctrl.k["acc_d"][2], ctrl.k["lam_pos"], M["v"][2]), ctrl.k["D_pos"][2],
        ctrl.k["eps_pos"][2], dg["s_pos"][2], [ctrl.xc["theta_zz"]], [M["r"][2]])) == 0


def test_force_rotation_is_the_inverse_of_the_plants():
    """C000.law's body force, rotated back by the plant's C_{L<-c}(q_cL) (quat_to_dcm of q_{c/L}), is F_LVLH."""
    q = sp.Matrix([0.3, -0.5, 0.1, 0.8])
    q = q / q.norm()
    F_L = sp.Matrix([0.7, -0.2, 0.4])
    back = quat_to_dcm(q) * C.lvlh_to_body_force(q, F_L)
    assert max(abs(float(x)) for x in back - F_L) < 1e-12
    assert max(abs(float(x)) for x in quat_to_dcm(q).T * F_L - F_L) > 0.1      # not the identity


def test_scenario_III_data_match_the_scenario_file():
    cfg = tomllib.loads((ROOT / "scenarios" / "000_scenario_III.toml").read_text())["controller"]["c000"]
    for key, val in translation.SCENARIO_III.items():
        assert list(np.atleast_1d(cfg[key])) == list(np.atleast_1d(val)), key


def test_printed_eq49_rows_differ_only_by_the_stated_slips():
    """With T_c = 0 and M_t = 0 the hand-typed 49-b and 49-c are the rigid-body rows (so the claim fails only on
    the printed slips: I_ty^-1 T_cy, the I_tj^-1 on the target torque, the duplicated 49-a)."""
    st = attitude._table1_vs_rigid(True)()
    syms = {s.name: s for s in st.free_symbols()}
    zero = {syms[n]: 0 for n in ("T_c1", "T_c2", "T_c3", "M_t1", "M_t2", "M_t3")}
    ev = {syms[n]: v for n, v in zip(("q_1", "q_2", "q_3", "q_4"), (0.5, -0.5, 0.5, 0.5), strict=True)}
    rng = np.random.default_rng(0)
    for s in st.free_symbols():
        if s not in zero and s not in ev:
            ev[s] = rng.uniform(0.05, 0.15) if not s.name.startswith("I_") else rng.uniform(10, 3000)
    diff = (st.lhs - st.rhs).xreplace(zero).xreplace(ev)
    assert abs(float(diff[1])) < 1e-12 and abs(float(diff[2])) < 1e-12 and abs(float(diff[0])) > 1e-6


def test_eq104_fails_outside_the_layer():
    """Eq. 104 with A_dx the upper bound allows D = mu/r_c^2 - A_dx; the counterexample is outside the layer."""
    o = check_statement(translation._tr_Vdot_bound(0, True)(), symbolic=False)
    assert not o.holds
    cx = o.counterexample
    s = cx["edot_x"] + cx["lambda_0"] * cx["e_x"]
    assert abs(s) > cx["d_x"] and cx["a_dx"] < 0


def test_quaternion_second_derivative_residual_is_the_analytic_one():
    """The printed premise e_ddot = omega_e_dot fails by (q4 w_dot + q_v x w_dot)/2 - |w|^2 q_v/4 - w_dot."""
    st = attitude._e_ddot_printed()
    q, w, wdot = [sp.Matrix(sp.symbols(n, real=True)) for n in ("q_1:5", "omega_e1:4", "omegadot_e1:4")]
    qv = q[:3, 0]
    expect = (q[3] * wdot + qv.cross(wdot)) / 2 - w.dot(w) * qv / 4 - wdot
    assert sp.expand(st.lhs - st.rhs - expect) == sp.zeros(3, 1)


def test_substitution_counterexample_is_off_radial_and_radial_offsets_are_exact():
    o = check_statement(translation._form(0, True)(), symbolic=False)
    assert not o.holds
    cx = o.counterexample
    assert abs(cx["y"]) + abs(cx["z"]) > 1.0                  # off the radial direction
    r_e, v_e = sp.Matrix([60.0, 0, 0]), sp.Matrix([3.0, -0.5, 5.0])
    r_t, n, ndot, z3 = 6.778e6, 1.1e-3, -2e-8, sp.zeros(3, 1)
    r_c = C.chaser_orbit_radius(r_t, r_e)
    exact = relative_acceleration(r_e, v_e, r_t, n, ndot, common.MU, z3, z3)[0]
    model = C.translation_model(r_e, v_e, n, ndot, r_c, common.MU, z3, z3)[0]
    assert abs(float(exact - model)) < 1e-12


def test_printed_boundary_layer_formula_is_nonzero_inside_the_layer():
    """The notation erratum: eq. 52's s - d sign(s) alone is nonzero inside |s| < d."""
    o = check_statement(boundary_layer._bl_zero_inside(True)(), symbolic=False)
    assert not o.holds
    assert abs(o.counterexample["s"]) < o.counterexample["d"]


def test_principal_axis_model_misses_the_products_of_inertia():
    """Eq. 49 with the diagonals of the paper's I_c, I_t differs from the rigid bodies by more than 1e-4 rad/s^2
    (the implementation's bound on that residual is the claim c000.attitude.principal_axes)."""
    o = check_statement(attitude._principal_axes_paper(), symbolic=False)
    assert not o.holds and abs(o.lhs_value - o.rhs_value) > 1e-4
