"""Helpers of the 000 Lyapunov claims (symbolic/lyapunov/c000.py): the hand-typed printed forms are the
printed equations, the law wrapper feeds the spacecraft claims what C000.law generates, and the paper's
failing steps fail for the stated reason (not for an artefact of the search)."""

from __future__ import annotations

import sympy as sp

from rpo.symbolic.controllers import c000 as C
from rpo.symbolic.lyapunov import c000 as L
from rpo.symbolic.lyapunov.check import check_statement
from rpo.symbolic.relative_translation import relative_acceleration


def test_printed_translation_laws_in_the_codes_regressor_convention():
    """eqs. 113-115 print -x_dot S, -y S, -x S; the code's y regressors are (x_dot, y, -x), so the printed
    factors of phi S are (-1, -1, +1); x (eqs. 96-100) and z (eq. 127) are all -phi S."""
    r, v = sp.Matrix(sp.symbols("x y z", real=True)), sp.Matrix(sp.symbols("xd yd zd", real=True))
    S = sp.Symbol("S", real=True)
    _, phi = C.translation_regressors(r, v, 0, 0, sp.Symbol("r_c", positive=True), 0)
    printed = [-v[0] * S, -r[1] * S, -r[0] * S]
    assert [sg * p * S for sg, p in zip(L.PRINTED_RATE_SIGNS[1], phi[1], strict=True)] == printed
    assert L.PRINTED_RATE_SIGNS[0] == [-1] * 5 and L.PRINTED_RATE_SIGNS[2] == [-1]
    # eq. 109: + for alpha_yy3 and h, - for alpha_yy1, alpha_yy2
    assert L.PRINTED_V_SIGNS[1] == [-1, -1, 1]


def test_law_wrapper_has_no_branches_and_rotates_nothing():
    ctrl, M, tau, F, rates, dg, sig, mu = L._law()
    for e in (tau, F, *rates.values(), *dg.values()):
        assert not e.atoms(sp.Piecewise)
    assert sig in tau.free_symbols and not M["q_cL"].free_symbols & F.free_symbols
    # F is the LVLH force of eqs. 86, 108, 121 (q_cL = identity)
    assert sp.simplify(F[2] - C.translation_control_axis(
        ctrl.xc["h_hat_zz"], C.u1_term(ctrl.k["acc_d"][2], ctrl.k["lam_pos"], M["v"][2]), ctrl.k["D_pos"][2],
        ctrl.k["eps_pos"][2], dg["s_pos"][2], [ctrl.xc["theta_zz"]], [M["r"][2]])) == 0


def test_quaternion_second_derivative_residual_is_the_analytic_one():
    """The printed premise e_ddot = omega_e_dot fails by (q4 w_dot + q_v x w_dot)/2 - |w|^2 q_v/4 - w_dot."""
    st = L._e_ddot_printed()
    q, w, wdot = [sp.Matrix(sp.symbols(n, real=True)) for n in ("q_1:5", "omega_e1:4", "omegadot_e1:4")]
    qv = q[:3, 0]
    expect = (q[3] * wdot + qv.cross(wdot)) / 2 - w.dot(w) * qv / 4 - wdot
    assert sp.expand(st.lhs - st.rhs - expect) == sp.zeros(3, 1)


def test_substitution_counterexample_is_off_radial_and_radial_offsets_are_exact():
    o = check_statement(L._form(0, True)(), symbolic=False)
    assert not o.holds
    cx = o.counterexample
    assert abs(cx["y"]) + abs(cx["z"]) > 1.0                  # off the radial direction
    r_e, v_e = sp.Matrix([60.0, 0, 0]), sp.Matrix([3.0, -0.5, 5.0])
    r_t, n, ndot, z3 = 6.778e6, 1.1e-3, -2e-8, sp.zeros(3, 1)
    r_c = C.chaser_orbit_radius(r_t, r_e)
    exact = relative_acceleration(r_e, v_e, r_t, n, ndot, L.MU, z3, z3)[0]
    model = C.translation_model(r_e, v_e, n, ndot, r_c, L.MU, z3, z3)[0]
    assert abs(float(exact - model)) < 1e-12


def test_printed_boundary_layer_makes_vdot_positive_inside_the_layer():
    """The printed S_aug = s - d sign(s) inside the layer: V-dot = (D + eps - d_dist sign s)|S_aug| > 0."""
    o = check_statement(L._att_Vdot_bound(True)(), symbolic=False)
    assert not o.holds
    cx = o.counterexample
    s = cx["edot"] + cx["lambda_0"] * cx["e"]
    assert abs(s) < cx["d"] and o.lhs_value > 0


def test_principal_axis_model_misses_the_products_of_inertia():
    """Eq. 49 with the diagonals of the paper's I_c, I_t differs from the rigid bodies by more than 1e-4 rad/s^2
    (the implementation's bound on that residual is the claim c000.attitude.principal_axes)."""
    o = check_statement(L._principal_axes_paper(), symbolic=False)
    assert not o.holds and abs(o.lhs_value - o.rhs_value) > 1e-4
