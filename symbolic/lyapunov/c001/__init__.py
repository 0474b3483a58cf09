"""Claims of 001 (Zheng et al.): the ESO (Proposition 1, eqs. 21-39) and the pose law (Proposition 2,
eqs. 53-64).

Every statement is built from the functions of :mod:`rpo.symbolic.controllers.c001` that generate the C
code, looked up on the module at check time (mutations are seen):

* Proposition 1 (finite-time ESO): the estimation-error dynamics are the spacecraft model (eq. 20, its
  lumped form eq. 21 with ``d^S``) minus the observer (``eso_rates``, eq. 23, with ``sta_theta`` /
  ``sta_phi``, eq. 24); the abstract steps (time scaling eq. 27, ``Phi = W Theta`` eq. 30, the eta
  system eq. 31, ``V1 = eta^T P eta`` eqs. 32-37, the settling time eqs. 25, 38-39) are checked on the
  error system built from ``eso_rates``.
* Proposition 2 (PD-like law): V-dot is ``lie_derivative`` of eq. 58 along the pose kinematics
  (``pose_rate``, eq. 15) and the lumped dynamics (``relative_dual_acceleration_lumped``, eq. 21) driven
  by the law (``control_dual_force``, eq. 57).  Abstract layer: ``V_p`` any function of ``q_S/T`` with
  gradient ``g`` (eqs. 59-63 hold for every potential).  Spacecraft layer: ``V_p`` is the APF of eq. 53
  (``apf``, ``beta_fov_dq``, ``beta_ca_dq``) and ``g`` the coded gradient (``apf_gradient``,
  ``grad_beta_fov``, ``grad_beta_ca``, eqs. 54-55), including rpo's regularisation ``fov_eps``.

The full measurement -> law chain of ``C001.law`` takes minutes to build; the claims use the
equation-level functions on symbolic intermediate variables instead: exogenous quantities
(``omega_S/I``, ``f_G``, ``d_hat``, the model acceleration of the ESO) are free symbols, and inside the
spacecraft V-dot ``Delta q``, ``beta_FOV`` and ``beta_CA`` are symbols whose derivatives are the code's
(chain rule through undefined functions), which keeps each symbolic proof to seconds.  The numeric
search draws those symbols consistently (``derived``) from admissible poses.

``C001.law`` calls the same module functions for what it composes: ``target_inertial_dual_velocity``
(omega_T/I = omega_S/I - omega_S/T), ``eso_model_acceleration`` (the ESO's model acceleration),
``applied_dual_force`` (the clipped force and torque) and ``apf_terms`` (constraints, APF and gradient
wiring); the gains and limits are read from ``C001().k``'s defaults.
"""

from __future__ import annotations

from . import apf, common, eso, model, mutations, plant, pose

TITLE = "001: dual quaternions, super-twisting ESO, artificial potential"

CLAIMS = [*model.CLAIMS, *plant.CLAIMS, *eso.CLAIMS, *pose.CLAIMS, *apf.CLAIMS]
MUTATIONS = mutations.MUTATIONS
UNITS = common.UNITS
