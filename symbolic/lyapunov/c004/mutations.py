"""004: defects injected into symbolic/controllers/c004.py; each must make the claims it names fail."""

from __future__ import annotations

import sympy as sp

from ...controllers import c004 as c
from ...physics.rotations import quat_vec
from ..core import (
    Mutation,
    drop_terms,
    negate_output,
    replace_output,
    scale_argument,
    symbols_vec,
)
from .common import _C, _printed_L, _printed_R, _printed_Y, _printed_y

# --------------------------------------------------------------------------- mutations

_RF_HAT, _RJ_HAT = sp.Symbol("rhohat_f", real=True), sp.Symbol("rhohat_J", real=True)
_TH_HAT = list(symbols_vec("thetahat_Delta", 6))


def _id(name: str) -> str:
    return f"{_C}.{name}"


def _euler_without_gyro(out, J, omega, tau, d_tau):
    return out + J.inv() * c.S(omega) * J * omega


def _eq20_without_transport(out, J, omega, omega_e, n2, tau, d_tau):
    return out - c.S(omega_e) * (omega - omega_e)


def _g_without_centripetal(out, omega, omega_e, v_e, R, p_t):
    w_tc = c.S(omega - omega_e)
    return out - w_tc * w_tc * R * p_t


def _mrp_without_shadow_switch(out, q):
    return quat_vec(q) / (1 + q[3])


def _mrp_without_cross(out, sigma, omega):
    return out - c.S(sigma) * omega / 2


_KIN, _TRANS, _ROT = _id("plant.relative_mrp_kinematics"), _id("plant.body_translation"), _id("plant.body_rotation")
_RATE, _VEL = _id("plant.relative_rate_dynamics"), _id("plant.relative_velocity_dynamics")


MUTATIONS = [
    # position law (25)
    Mutation("c004: +K1 s1 in eq. 25", c, "position_control", scale_argument("K1", -1),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"),
              _id("position.V1dot_bound"))),
    Mutation("c004: +k0 r_e in eq. 25", c, "position_control", scale_argument("k0", -1),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"))),
    Mutation("c004: drop rho^_f sgn(s1) from eq. 25", c, "position_control", drop_terms(_RF_HAT),
             (_id("position.eq26_identity"), _id("position.V1dot_identity"), _id("position.closed_loop"),
              _id("position.V1dot_bound"))),
    Mutation("c004: printed y (+L1 v_e) in eq. 22", c, "position_regressor",
             replace_output(lambda out, g, v_e, r_e, omega, Lambda1: _printed_y(g, v_e, r_e, omega, Lambda1)),
             (_id("position.surface_dynamics"), _id("position.eq24_identity"), _id("position.V1dot_identity"))),
    # position adaptation (27)
    Mutation("c004: sign of the m_hat adaptation (eq. 27)", c, "position_adaptation", negate_output(0),
             (_id("position.V1dot_identity"),)),
    Mutation("c004: -gamma3 in the rho^_m adaptation (eq. 27)", c, "position_adaptation",
             scale_argument("gamma3", -1), (_id("position.V1dot_identity"),)),
    # attitude law (34)
    Mutation("c004: +K2 s2 in eq. 34", c, "attitude_control", scale_argument("K2", -1),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"),
              _id("attitude.V2dot_bound"))),
    Mutation("c004: drop Y theta^_Delta from eq. 34", c, "attitude_control", drop_terms(_TH_HAT),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"))),
    Mutation("c004: drop rho^_J ‖w_t‖^2 sgn(s2) from eq. 34", c, "attitude_control", drop_terms(_RJ_HAT),
             (_id("attitude.eq35_identity"), _id("attitude.V2dot_identity"), _id("attitude.closed_loop"),
              _id("attitude.V2dot_bound"))),
    Mutation("c004: printed Y sign (under eq. 31)", c, "attitude_regressor",
             replace_output(lambda out, omega, omega_e, sigma_e, Lambda2: _printed_Y(omega, omega_e, sigma_e,
                                                                                     Lambda2)),
             (_id("attitude.regressor_form"), _id("attitude.eq33_identity"), _id("attitude.V2dot_identity"))),
    Mutation("c004: printed row 1 of L", c, "inertia_operator", replace_output(lambda out, a: _printed_L(a)),
             (_id("attitude.L_operator"), _id("attitude.regressor_form"), _id("attitude.V2dot_identity"))),
    # attitude adaptation (36)
    Mutation("c004: sign of the theta^ adaptation (eq. 36)", c, "attitude_adaptation", negate_output(0),
             (_id("attitude.V2dot_identity"),)),
    Mutation("c004: -gamma6 in the rho^_J adaptation (eq. 36)", c, "attitude_adaptation",
             scale_argument("gamma6", -1), (_id("attitude.V2dot_identity"),)),
    Mutation("c004: -gamma5 in the rho^_tau adaptation (eq. 36)", c, "attitude_adaptation",
             scale_argument("gamma5", -1), (_id("attitude.V2dot_identity"),)),
    # relative model (eq. 9)
    Mutation("c004: printed eq. 9 (S^T S)", c, "rotation_matrix", replace_output(lambda out, s: _printed_R(s)),
             (_id("model.eq9_rotation"), _id("model.R_dot"), _id("model.eq13"), _id("model.eq17"),
              _id("position.n1_bound"))),
    # inequality-only: the identity claims use opaque n1, n2 (or c.norm2 on both sides); the coupling bounds
    # under eqs. 27 and 36 are where ||.|| itself matters
    Mutation("c004: ‖a‖ computed as ‖a‖^2 (norm2)", c, "norm2", replace_output(lambda out, a: out**2),
             (_id("position.n1_bound"), _id("attitude.n2_bound")), inequality_only=True,
             description="a missing square root: the coupling bounds rho ||p_t|| ||w_t||^2 fail where the norms "
                         "are below 1"),
    # the proof model against the plant (c004/plant.py): the model functions the Lyapunov claims integrate
    Mutation("c004: G(sigma) without 2 S(sigma) (eqs. 2, 6, 14)", c, "mrp_kinematics",
             replace_output(_mrp_without_cross), (_KIN,)),
    Mutation("c004: r_dot = v + S(w) r (eqs. 1, 5, 13)", c, "position_kinematics", scale_argument("omega", -1),
             (_TRANS,)),
    Mutation("c004: m v_dot = f + d_f + m S(w) v (eqs. 3, 7)", c, "translational_dynamics",
             scale_argument("omega", -1), (_TRANS,)),
    Mutation("c004: S(w) J w dropped from eq. 4", c, "rotational_dynamics", replace_output(_euler_without_gyro),
             (_ROT,)),
    Mutation("c004: sign of omega_t-dot (eq. 18)", c, "target_angular_acceleration", negate_output(), (_ROT,)),
    Mutation("c004: J S(w_e)(w - w_e) dropped from eq. 20", c, "relative_rate_rate",
             replace_output(_eq20_without_transport), (_RATE,)),
    Mutation("c004: sign of n_2 (under eq. 20)", c, "coupling_n2", negate_output(), (_RATE,)),
    Mutation("c004: sign of d_f in eq. 19", c, "relative_velocity_rate", scale_argument("d_f", -1), (_VEL,)),
    Mutation("c004: centripetal S(w - w_e)^2 R p_t dropped from g (under eq. 20)", c, "coupling_g",
             replace_output(_g_without_centripetal), (_VEL,)),
    Mutation("c004: sign of n_1 (under eq. 20)", c, "coupling_n1", negate_output(), (_VEL,)),
    # inequality-only: no identity claim evaluates principal_mrp (the model claims take sigma_e as a symbol);
    # the law forms sigma_e(0) with it, and the proof needs ||sigma_e|| <= 1 (Table 1's sigma_e(0) is outside)
    Mutation("c004: sigma_e without the shadow-set switch (principal_mrp)", c, "principal_mrp",
             replace_output(_mrp_without_shadow_switch), (_id("theorem.sigma_e0_constraint"),), inequality_only=True,
             description="q_v/(1 + q_w) for every q: Table 1's sigma_e(0) keeps its norm 1.049 > 1"),
]
