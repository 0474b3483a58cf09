"""001: defects injected into symbolic/controllers/c001.py; each must make the claims it names fail."""

from __future__ import annotations

import inspect

import sympy as sp

from ...controllers import c001 as c
from ..core import (
    Mutation,
    drop_terms,
    negate_output,
    replace_output,
    scale_argument,
)

# --------------------------------------------------------------------------- mutations

def _minus_gyro(out, q, grad, w_ST, w_TI_S, J, *rest):
    return out - c.gyroscopic_dual_force(J, w_TI_S)


def _minus_fG(out, q, grad, w_ST, w_TI_S, J, f_G, *rest):
    return out + f_G


def _minus_dhat(out, q, grad, w_ST, w_TI_S, J, f_G, d_hat, *rest):
    return out + c.J_E_times(J, d_hat)


def _eso_without_dhat(out, model_acc, w_meas, w_hat, d_hat, *rest):
    return out[0] - d_hat, out[1]


def _phi_sign_flip(out, x, kappa1, kappa2):
    sgn = x.applyfunc(sp.sign) if isinstance(x, sp.MatrixBase) else sp.sign(x)
    return out - kappa1**2 * sgn          # + kappa1^2/2 sign -> - kappa1^2/2 sign


def _model_without_transport(out, J, f_G, f_applied, w_SI, w_ST):
    return out - c.dq_cross(w_ST, w_SI)


def _model_without_fG(out, J, f_G, f_applied, w_SI, w_ST):
    return out - c.J_E_inv_times(J, f_G)


def _relative_without_transport(out, J, f_G, f_D, f_C, w_SI, w_ST, q_ST, wdot_TI_T):
    return out - c.dq_cross(w_ST, w_SI)


def _pose_rate_in_reference_axes(out, q, w_body):
    return c.dq_mul(w_body, q) / 2


def _eq17_without_gyro(out, J, w_SI, f_total):
    return out + c.J_E_inv_times(J, c.gyroscopic_dual_force(J, w_SI))


def _apf_gains_swapped(fn):
    """``apf_terms`` called with k_a and k_r in each other's place (attractive 2.5e-5, repulsive 0.75)."""
    sig = inspect.signature(fn)

    def mutated(*a, **kw):
        b = sig.bind(*a, **kw)
        b.arguments["k_a"], b.arguments["k_r"] = b.arguments["k_r"], b.arguments["k_a"]
        return fn(*b.args, **b.kwargs)
    return mutated


_LAW = ("c001.pose.Vdot_eq60", "c001.pose.Vdot_identity")
_ESO = ("c001.eso.error_dynamics", "c001.eso.time_scaling")

MUTATIONS = [
    Mutation("c001: +k_d (E omega) in eq. 57", c, "control_dual_force", scale_argument("k_d", -1), _LAW),
    Mutation("c001: +k_p vec(q* (E grad V_p)) in eq. 57", c, "control_dual_force", scale_argument("k_p", -1),
             _LAW + ("c001.pose.eq61",)),
    Mutation("c001: eq. 57 without omega_T/I x (J_E omega_T/I)", c, "control_dual_force",
             replace_output(_minus_gyro), _LAW + ("c001.pose.eq62",)),
    Mutation("c001: eq. 57 without -f_G", c, "control_dual_force", replace_output(_minus_fG), _LAW),
    Mutation("c001: eq. 57 without -J_E d_hat", c, "control_dual_force", replace_output(_minus_dhat), _LAW),
    Mutation("c001: eq. 54 with -k_r (sign of the repulsive gradient)", c, "apf_gradient",
             scale_argument("k_r", -1), ("c001.apf.gradient", "c001.pose.Vdot_apf")),
    Mutation("c001: eq. 55 grad beta_FOV negated", c, "grad_beta_fov", negate_output(), ("c001.apf.gradient",)),
    Mutation("c001: ESO -K1 Theta (eq. 23, gain x -1)", c, "eso_rates", scale_argument("K1", -1),
             _ESO + ("c001.eso.eta_dynamics", "c001.eso.V1dot_identity")),
    Mutation("c001: ESO -K2 Phi (eq. 23, gain x -1)", c, "eso_rates", scale_argument("K2", -1),
             _ESO + ("c001.eso.eta_dynamics", "c001.eso.V1dot_identity")),
    Mutation("c001: ESO without d_hat in omega_hat-dot (eq. 23)", c, "eso_rates",
             replace_output(_eso_without_dhat), _ESO + ("c001.eso.eta_dynamics",)),
    Mutation("c001: ESO model without omega_S/T x omega_S/I (eq. 23)", c, "eso_model_acceleration",
             replace_output(_model_without_transport), ("c001.eso.error_dynamics", "c001.pose.composed")),
    Mutation("c001: ESO model without f_G (eq. 23)", c, "eso_model_acceleration", replace_output(_model_without_fG),
             ("c001.eso.error_dynamics", "c001.pose.composed")),
    Mutation("c001: applied force without the torque limit", c, "applied_dual_force",
             replace_output(lambda out, f_C, F_max, tau_max: c.dual_force(c.dq_parts3(out)[0], c.dq_parts3(f_C)[1])),
             ("c001.pose.saturation_impl",)),
    Mutation("c001: Theta without kappa2 x (eq. 24)", c, "sta_theta",
             drop_terms(lambda: sp.Symbol("kappa_2", positive=True)),
             _ESO + ("c001.eso.phi_w_theta", "c001.eso.eta_dynamics")),
    Mutation("c001: Phi with -kappa1^2/2 sign(x) (eq. 24)", c, "sta_phi", replace_output(_phi_sign_flip),
             _ESO + ("c001.eso.phi_w_theta",)),
    # the proof model (eq. 20) against its derivation from eqs. 14, 15, 17 (c001.model.relative_acceleration)
    Mutation("c001: eq. 20 without omega_S/T x omega_S/I", c, "relative_dual_acceleration",
             replace_output(_relative_without_transport), ("c001.model.relative_acceleration",)),
    # the proof model against the plant (c001/plant.py): rotations.py, rigid_body.py, Newton
    Mutation("c001: q_dot = omega q / 2 (eqs. 11-12, omega taken in the reference axes)", c, "pose_rate",
             replace_output(_pose_rate_in_reference_axes), ("c001.plant.body_pose_kinematics",)),
    Mutation("c001: eq. 17 without omega x (J_E omega)", c, "inertial_dual_acceleration",
             replace_output(_eq17_without_gyro), ("c001.plant.inertial_dual_acceleration",)),
    Mutation("c001: omega_S/T = omega_S/I + q* omega_T/I q (eq. 14)", c, "relative_dual_velocity",
             scale_argument("w_TI_T", -1), ("c001.plant.relative_dual_velocity",)),
    # inequality-only: the identity claims build V_p and its gradient from c.apf and c.apf_gradient with symbolic
    # gains; only the claims on the paper's data go through c.apf_terms (as C001.law does), and of those only eq. 56
    # (k_a >> k_r) depends on which gain is which
    Mutation("c001: k_a and k_r swapped in apf_terms (eqs. 51-53)", c, "apf_terms", _apf_gains_swapped,
             ("c001.apf.convex_far",), inequality_only=True,
             description="the law's APF with k_a = 2.5e-5, k_r = 0.75: the repulsive term dominates and its "
                         "Hessian is indefinite far from the constraints (|r| in [40, 300] m)"),
]
