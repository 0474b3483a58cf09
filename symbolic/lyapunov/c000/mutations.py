"""000: defects injected into symbolic/controllers/c000.py; each must make the claims it names fail."""

from __future__ import annotations

import sympy as sp

from ...controllers import c000 as c
from ...physics.rotations import quat_to_dcm
from ..core import (
    Mutation,
    negate_output,
    replace_output,
    scale_argument,
)
from .common import AXES, _printed_layer

# =====================================================================================================
# Mutations
# =====================================================================================================

def _flip_switching(out, b_hat, u1, D, eps, s, a_hat, f):
    return out + 2 * b_hat * (D + eps) * sp.sign(s)


def _drop_regression_att(out, b_hat, u1, D, eps, s, a_hat, f):
    return out - sum(a * fi for a, fi in zip(a_hat, f, strict=True))


def _flip_regression_tr(out, h_hat, u1, D, eps, s, theta_hat, phi):
    return out + 2 * sum(t * p for t, p in zip(theta_hat, phi, strict=True))


def _drop_lambda_edot(out, acc_d, lam, e_dot):
    return -acc_d


def _ungroup_mu(out, r_e, v_e, n, n_dot, r_c, mu):
    theta, phi = out
    phi = [list(p) for p in phi]
    phi[0][4] = c.f_xx2(r_c, r_e)
    return theta, phi


def _drop_wheel_regressor(out, *a, **kw):
    a_, f, b = out
    f = list(f)
    f[2] = sp.Integer(0)
    return a_, f, b


_AI, _AS = "c000.attitude.Vdot_identity", "c000.attitude.spacecraft_Vdot"


def _t(ax, name):
    return f"c000.translation_{ax}.{name}"


def _transpose_rotation(out, q_cL, F_L):
    return quat_to_dcm(q_cL) * F_L


def _drop_target_torque(out, j, I_c, I_t, C_tc, M_c, M_t):
    return M_c[j] / I_c[j]


# ----- defects confined to |s| < 1e-3: harmless inside a layer of width d >= 1e-3 (S_aug = 0 there), so they
# show only where the spacecraft claims allow thinner layers (d_att in [0, 0.01] rad/s, d_pos in [0, 0.05] m/s)

_NARROW = sp.Rational(1, 1000)


def _dead_zone_sign(x):
    """sign(x) with a dead zone: 0 for |x| < 1e-3."""
    return sp.Piecewise((0, sp.Abs(x) < _NARROW), (sp.sign(x), True))


def _sat_sign(x):
    """sat(x / 1e-3) = max(-1, min(1, x / 1e-3)) in place of sign(x)."""
    return sp.Max(-1, sp.Min(1, x / _NARROW))


def _att_dead_zone(out, b_hat, u1, D, eps, s, a_hat, f):
    return -b_hat * (u1 + (D + eps) * _dead_zone_sign(s)) + sum(ai * fi for ai, fi in zip(a_hat, f, strict=True))


def _tr_sat(out, h_hat, u1, D, eps, s, theta_hat, phi):
    return -h_hat * (u1 + (D + eps) * _sat_sign(s)) - sum(ti * pi for ti, pi in zip(theta_hat, phi, strict=True))


MUTATIONS = [
    Mutation("c000: switching term sign flipped (eq. 55)", c, "attitude_control_axis",
             replace_output(_flip_switching), (_AI, _AS, "c000.attitude.Vdot_bound")),
    Mutation("c000: sum a_hat f dropped from eq. 55", c, "attitude_control_axis",
             replace_output(_drop_regression_att), (_AI, _AS)),
    Mutation("c000: b_hat x -1 in eq. 55", c, "attitude_control_axis", scale_argument("b_hat", -1), (_AI,)),
    Mutation("c000: sign of the a_hat adaptation (eq. 66)", c, "attitude_param_rate", negate_output(), (_AI, _AS)),
    Mutation("c000: gamma_a x -1 in eq. 66", c, "attitude_param_rate", scale_argument("gamma", -1), (_AI,)),
    Mutation("c000: sign of the b_hat / h_hat adaptation (eqs. 67, 101, 116, 128)", c, "gain_estimate_rate",
             negate_output(), (_AI, _t("y", "Vdot_identity"), _t("x", "spacecraft_Vdot"))),
    Mutation("c000: lambda_0 e_dot dropped from u_1 (eqs. 56, 88, 122)", c, "u1_term",
             replace_output(_drop_lambda_edot), (_AI, _AS, _t("z", "Vdot_identity"), _t("y", "spacecraft_Vdot"))),
    Mutation("c000: sum theta_hat phi sign flipped (eqs. 86, 108, 121)", c, "translation_control_axis",
             replace_output(_flip_regression_tr), tuple(_t(ax, "Vdot_identity") for ax in AXES)),
    Mutation("c000: h_hat x -1 in eqs. 86, 108, 121", c, "translation_control_axis", scale_argument("h_hat", -1),
             (_t("x", "Vdot_identity"), _t("z", "spacecraft_Vdot"))),
    Mutation("c000: printed sign of the theta adaptation (eqs. 96-100, 113-114, 127)", c, "translation_param_rate",
             negate_output(), (*(_t(ax, "adaptation_sign") for ax in AXES), _t("y", "spacecraft_Vdot"))),
    Mutation("c000: -mu/r_c^2 not grouped into phi_xx5 (eq. 81)", c, "translation_regressors",
             replace_output(_ungroup_mu), (_t("x", "regressors"), _t("x", "spacecraft_Vdot"))),
    Mutation("c000: printed boundary layer s - d sign(s)", c, "boundary_layer_surface",
             replace_output(lambda out, s, d: _printed_layer(s, d)),
             ("c000.boundary_layer.sign", "c000.boundary_layer.zero_inside", "c000.attitude.Vdot_bound",
              _t("x", "Vdot_bound"))),
    Mutation("c000: lambda_0 -> -lambda_0 in the sliding surface (eqs. 53, 85, 107, 120)", c, "sliding_surface",
             scale_argument("lam", -1), ("c000.attitude.sliding_decay", "c000.attitude.e_ddot",
                                         _t("y", "Vdot_identity"))),
    Mutation("c000: wheel-momentum regressor f_j3 dropped (Table 1)", c, "table1_attitude_axis",
             replace_output(_drop_wheel_regressor), ("c000.attitude.table1", _AS)),
    Mutation("c000: LVLH->body force rotation transposed (eq. 87)", c, "lvlh_to_body_force",
             replace_output(_transpose_rotation), tuple(_t(ax, "spacecraft_Vdot") for ax in AXES)),
    # inequality-only: eq. 49's model (attitude_model) enters no identity claim; the bound on what it leaves out
    # (products of inertia, torques within D_att) is the only check of it
    Mutation("c000: chaser rate sign in eq. 49's model (omega_c -> -omega_c)", c, "attitude_model",
             scale_argument("omega_c", -1), ("c000.attitude.principal_axes",), inequality_only=True,
             description="the law's model of omega_e_dot with the chaser's rate of the wrong sign: the residual "
                         "against the rigid bodies exceeds D_att"),
    # the proof model against the plant: eq. 49's disturbance and eq. 48's form are used only by the proofs,
    # c000.attitude.table1 holds them against relative_attitude.rate_error_dynamics (the two rigid bodies)
    Mutation("c000: target torque term dropped from d_j (eqs. 49, 51)", c, "attitude_disturbance_axis",
             replace_output(_drop_target_torque), ("c000.attitude.table1",)),
    Mutation("c000: b_j u_j sign flipped in eq. 48", c, "attitude_model_axis", scale_argument("u", -1),
             ("c000.attitude.table1", _AI)),
    Mutation("c000: b u dropped from the per-axis translation form (eqs. 81, 105)", c, "translation_model_axis",
             scale_argument("b", 0), tuple(_t(ax, "form_eq30") for ax in AXES)),
    # small-region defects of the switching term: the abstract V-dot bounds (d >= 1e-3) cannot see them, the
    # spacecraft bounds (layers down to d = 0) can; the spacecraft_Vdot identities type sign(s) and are false in
    # the same region, so these are not inequality-only
    Mutation("c000: dead zone |s| < 1e-3 in eq. 55's sign(s)", c, "attitude_control_axis",
             replace_output(_att_dead_zone), ("c000.attitude.spacecraft_Vdot_bound", _AS),
             description="no switching torque for |s_j| < 1e-3 rad/s while b_hat_j still adapts with sign(s_j): "
                         "for d_att,j < |s_j| < 1e-3, V_j-dot = (d_j - (D_j + eps_j)(1 - b_j b_hat_j) sign(s_j)) "
                         "S_j exceeds -eps_j |S_j| whenever b_hat_j > 0"),
    Mutation("c000: sign(s) -> sat(s / 1e-3) in eqs. 86, 108, 121", c, "translation_control_axis",
             replace_output(_tr_sat), ("c000.translation.spacecraft_Vdot_bound",),
             description="a second, inner boundary layer of width 1e-3 m/s in the force law only (h_hat still "
                         "adapts with sign(s)): for d_pos,j < |s_j| < 1e-3 the switching force falls short by "
                         "h_hat_j (D_j + eps_j)(1 - |s_j|/1e-3) and V_j-dot > -eps_j |S_j|"),
]
