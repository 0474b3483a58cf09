"""002: defects injected into symbolic/controllers/c002.py; each must make the claims it names fail."""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...physics.rotations import dot, skew
from ..core import (
    Mutation,
    drop_terms,
    negate_output,
    replace_output,
    scale_argument,
)
from .common import AHAT, U_R


def _drop_alpha7(out, *a, **kw):
    out = sp.Matrix(out)
    out[6] = 0
    return out


def _plus_gravity(out, R, w_t, w_t_dot, v_t, v_t_dot, sigma_t, g_p):
    return out + 2 * g_p


def _unrotated_target_acceleration(out, R, w_t, w_t_dot, v_t, v_t_dot, sigma_t, g_p):
    return out - R * v_t_dot + v_t_dot


def _coriolis_without_RwtJ(out, J, R, w_t, w_rel):
    return out - skew(R * w_t) * J


def _nr_without_gyro(out, J, R, w_t, w_t_dot):
    return out - skew(R * w_t) * J * R * w_t


def _nr_without_target_acceleration(out, J, R, w_t, w_t_dot):
    return out - J * R * w_t_dot


def _q0_rate_sign(out, q_rel, w_rel):
    out = sp.Matrix(out)
    out[3] = -out[3]
    return out


def _nt_without_centripetal(out, R, w_t, w_t_dot, v_t, v_t_dot, sigma_t, g_p):
    wt = R * w_t
    return out - skew(wt) * skew(wt) * R * sigma_t


def _tanh_offset(delta, axis):
    """tanh(chi) with a constant offset on one component.  Its derivative is unchanged, so the identities that
    differentiate tanh(chi) along eqs. 17-18 or carry the same tanh on both sides still hold; only
    model.law_composition, which types eqs. 15-18 with tanh by hand, sees it among the identities."""
    def f(out, chi):
        out = sp.Matrix(out)
        out[axis] = out[axis] + delta
        return out
    return f


def _x_row_gain(out, *a, **kw):
    out = sp.Matrix(out)
    out[0] = sp.Rational(105, 100) * out[0]
    return out


def _rates_one_norm(out, s1, s2, w_rel, v_rel, r_rel, a_hat, beta, gamma):
    def nrm(x):
        return sp.sqrt(dot(x, x))

    ns1, ns2 = (sum(sp.Abs(x) for x in s) for s in (s1, s2))       # ||s_j||_1 for ||s_j||_2
    w, v, r = nrm(w_rel), nrm(v_rel), nrm(r_rel)
    y = [ns1 * w**2, ns1 * w, ns1, ns2 * w * v, ns2 * w * r, ns2 * w, ns2 * v, ns2 * r, ns2]
    return sp.Matrix([beta[i] * (y[i] - gamma[i] * a_hat[i]) for i in range(9)])


_PLANT_RATE = "c002.plant.relative_rate_dynamics"
_PLANT_TRANSLATION = "c002.plant.relative_translation"

MUTATIONS = [
    Mutation("c002: k4 -> -k4 in eq. 23", c, "attitude_control", scale_argument("k4", -1),
             ("c002.V1.bound", "c002.V1.exponential_att", "c002.model.law_composition")),
    Mutation("c002: sign of eps_r (eq. 23)", c, "attitude_control", negate_output(),
             ("c002.V1.bound", "c002.V1.exponential", "c002.V1.exponential_att", "c002.model.law_composition")),
    Mutation("c002: alpha^_3 term dropped from eq. 23", c, "attitude_control", drop_terms(AHAT[2]),
             ("c002.V1.bound",)),
    Mutation("c002: k3 -> -k3 in eq. 23", c, "attitude_control", scale_argument("k3", -1),
             ("c002.V1.bound",)),
    Mutation("c002: k8 -> -k8 in eq. 24", c, "position_control", scale_argument("k8", -1),
             ("c002.V1.bound", "c002.V1.exponential", "c002.V1.exponential_pos", "c002.model.law_composition")),
    Mutation("c002: k7 -> -k7 in eq. 24", c, "position_control", scale_argument("k7", -1),
             ("c002.V1.bound",)),
    Mutation("c002: alpha^_9 term dropped from eq. 24", c, "position_control", drop_terms(AHAT[8]),
             ("c002.V1.bound",)),
    Mutation("c002: sign of eq. 25", c, "adaptive_rates", negate_output(),
             ("c002.V1.adaptation_cancels", "c002.V1.bound")),
    Mutation("c002: gamma -> -gamma in eq. 25", c, "adaptive_rates", scale_argument("gamma", -1),
             ("c002.V1.adaptation_cancels", "c002.V1.bound", "c002.model.law_composition")),
    Mutation("c002: beta -> -beta in eq. 25", c, "adaptive_rates", scale_argument("beta", -1),
             ("c002.V1.adaptation_cancels",)),
    Mutation("c002: alpha^_7 law dropped (as printed, eq. 25)", c, "adaptive_rates", replace_output(_drop_alpha7),
             ("c002.V1.adaptation_cancels",)),
    Mutation("c002: sign of eq. 17", c, "aux_attitude_rate", negate_output(),
             ("c002.model.s1dot_identity", "c002.V1.closed_loop_identity", "c002.V2.derivative_identity",
              "c002.V2.invariant_set")),
    Mutation("c002: sat(eps_r) dropped from eq. 17", c, "aux_attitude_rate", drop_terms(U_R),
             ("c002.model.s1dot_identity", "c002.V2.derivative_identity")),
    Mutation("c002: kappa2 -> -kappa2 in eq. 18", c, "aux_position_rate", scale_argument("kappa2", -1),
             ("c002.model.s2dot_identity", "c002.V2.derivative_identity", "c002.V2.invariant_set",
              "c002.model.law_composition")),
    Mutation("c002: k1 -> -k1 in the attitude surface (eq. 15)", c, "sliding_surface_attitude",
             scale_argument("k1", -1), ("c002.model.s1dot_identity", "c002.model.law_composition")),
    Mutation("c002: k6 -> -k6 in the position surface (eq. 16)", c, "sliding_surface_position",
             scale_argument("k6", -1), ("c002.model.s2dot_identity", "c002.model.law_composition")),
    Mutation("c002: saturation sign flipped (eq. 13)", c, "saturation", negate_output(),
             ("c002.model.law_composition",)),
    Mutation("c002: sigma_t term of v~ sign flipped (eq. 6)", c, "relative_velocity", scale_argument("sigma_t", -1),
             ("c002.model.law_kinematics",)),
    Mutation("c002: omega~ = omega_p + R omega_t (under eq. 3)", c, "relative_angular_velocity",
             scale_argument("w_t", -1), ("c002.model.law_kinematics",)),
    Mutation("c002: sign of r~_dot (eq. 7)", c, "relative_position_rate", negate_output(),
             ("c002.model.s2dot_identity", "c002.V3.derivative_identity")),
    # n_t enters the Lyapunov identities as opaque symbols; the lumped bounds (eqs. 9, 22, Remark 5) evaluate
    # the code's n_t, and c002.plant.relative_translation holds it against Newton's law (so these two are no
    # longer inequality-only: the plant identity catches them too)
    Mutation("c002: pursuer gravity sign in n_t (eq. 9: + g_p)", c, "translation_nonlinear_term",
             replace_output(_plus_gravity),
             ("c002.model.remark5_nt", "c002.model.lumped_bound_position", _PLANT_TRANSLATION),
             description="the gravities add instead of cancelling: ||R v_t_dot + g_p|| ~ 2 g, not the differential a4"),
    Mutation("c002: v_t_dot not rotated into pursuer axes in n_t (eq. 9)", c, "translation_nonlinear_term",
             replace_output(_unrotated_target_acceleration),
             ("c002.model.remark5_nt", "c002.model.lumped_bound_position", _PLANT_TRANSLATION),
             description="target-axes acceleration used in pursuer axes: a frame error of size g where the "
                         "attitudes differ"),
    # the proof model against the plant (c002/plant.py): functions only the proofs use
    Mutation("c002: (R w_t)^x J dropped from C_r (eq. 4)", c, "attitude_coriolis_matrix",
             replace_output(_coriolis_without_RwtJ), (_PLANT_RATE,),
             description="the proof's Coriolis matrix drifts from the rigid body; the Lyapunov claims only lose a "
                         "proof (remark4_Cr), the plant identity fails"),
    Mutation("c002: (R w_t)^x J R w_t dropped from n_r (eq. 4)", c, "attitude_nonlinear_term",
             replace_output(_nr_without_gyro), (_PLANT_RATE,)),
    Mutation("c002: J R omega_t_dot dropped from n_r (eq. 4)", c, "attitude_nonlinear_term",
             replace_output(_nr_without_target_acceleration), (_PLANT_RATE,)),
    Mutation("c002: sign of tau_d in eq. 11", c, "relative_angular_acceleration",
             scale_argument("tau_d", -1), (_PLANT_RATE,)),
    Mutation("c002: sign of dq~_0/dt (eqs. 2-3)", c, "relative_quaternion_rate", replace_output(_q0_rate_sign),
             ("c002.plant.quaternion_kinematics", "c002.plant.dcm_rate")),
    Mutation("c002: C_t = (w~ - R w_t)^x (under eq. 7)", c, "translation_rate_matrix", scale_argument("w_t", -1),
             (_PLANT_TRANSLATION,),
             description="still skew-symmetric (c002.model.Ct_skew holds): only the plant identity sees it"),
    Mutation("c002: centripetal (R w_t)^x (R w_t)^x R sigma_t dropped from n_t (eq. 9 as printed)", c,
             "translation_nonlinear_term", replace_output(_nt_without_centripetal), (_PLANT_TRANSLATION,)),
    Mutation("c002: sign of f_d in eq. 12", c, "relative_acceleration", scale_argument("f_d", -1),
             (_PLANT_TRANSLATION,)),
    Mutation("c002: sign of r~_dot's C_t r~ (eq. 7)", c, "relative_position_rate", scale_argument("C_t", -1),
             (_PLANT_TRANSLATION,)),
    # small-region and one-axis defects of the functions the certified V2 / V3 claims evaluate
    Mutation("c002: tanh(chi_x) offset by +1e-3 (eqs. 15-18, 37)", c, "tanh_vec", replace_output(_tanh_offset(
             sp.Rational(1, 1000), 0)), ("c002.V2.lemma1", "c002.V2.invariant_set", "c002.V3.rate_bounds",
                                          "c002.model.law_composition"),
             description="Lemma 1 is tight (delta = 0.2785 against max |x| - x tanh x = 0.27846 at |x| = 0.64): "
                         "the offset breaks it for chi_x near -0.64 with chi_y, chi_z small; eq. 17's x axis then "
                         "leaves Omega_2 near kappa tanh(c0) = varpi (varpi/kappa ~ 0.57); w~_x exceeds eq. 42's "
                         "bound at the corner s1_x = o1, q~_x = -o3, chi_x = c1"),
    Mutation("c002: eq. 17's x row 5 % high (one-axis gain)", c, "aux_attitude_rate", replace_output(_x_row_gain),
             ("c002.V2.bound", "c002.V2.derivative_identity"),
             description="chi1_x moves 5 % faster than J_x and k2 allow: where the saturation error pushes chi_x "
                         "outward (varpi_1 > kappa_1 tanh|chi_x|) its V2 term exceeds eq. 38's"),
    Mutation("c002: ||s_j||_1 for ||s_j||_2 in eq. 25", c, "adaptive_rates", replace_output(_rates_one_norm),
             ("c002.V1.adaptation_cancels", "c002.V1.bound"),
             description="the estimates grow with ||s||_1 >= ||s||_2: the cross term alpha~_i (||s||_2 - ||s||_1) "
                         "y_i of V1_dot is positive when alpha^_i > alpha_i"),
]
