"""001, the proof model is the plant: the dual-quaternion model of eqs. 6-17 (``pose_rate``,
``relative_dual_velocity``, ``inertial_dual_acceleration`` of :mod:`rpo.symbolic.controllers.c001`, which the
Lyapunov claims integrate) equals the motion of rpo's own rigid bodies.

The plant side is built from ``symbolic/`` alone, never from the controller module:

* attitude kinematics of each body, q_dot = 1/2 q (x) [omega, 0] (:func:`rpo.symbolic.physics.rotations.quat_rate`,
  000 eq. 24), q = C_{I<-B} scalar last, omega the body rate in body axes [rad/s];
* the pose as a unit dual quaternion, :func:`rpo.symbolic.physics.rotations.dq_from_pose` (position r [m] of the body's
  origin in inertial axes, frame "A");
* Newton's law in inertial axes, r_ddot = F/m with the force F [N] given in body axes;
* Euler's equation J omega_dot = -omega^x J omega + tau
  (:func:`rpo.symbolic.physics.rigid_body.chaser_angular_acceleration`, 000 eq. 6, h_rw = 0: 001's chaser is one
  rigid body with the principal inertia M).

With eq. 20's derivation from these functions (``c001.model.relative_acceleration``), the proof's model is tied
to the plant end to end.  Every identity holds modulo the unit-quaternion constraints (Groebner reduction).
"""

from __future__ import annotations

import sympy as sp

from ...controllers import c001 as c
from ...physics.rigid_body import chaser_angular_acceleration
from ...physics.rotations import dq_from_pose, quat_conj, quat_mul, quat_rate, quat_to_dcm
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
    quat_norm_constraint,
    symbols_vec,
)
from ..domains import box, unit_quaternion
from .common import MODEL

claim = claim_factory(__name__)


def _quat(name: str) -> sp.Matrix:
    return sp.Matrix(sp.symbols(f"{name}_1:5", real=True))


def _dt(vec, states, rates) -> sp.Matrix:
    return sp.Matrix([lie_derivative(e, states, rates) for e in vec])


def _body_pose_kinematics() -> Statement:
    """d/dt of the body's pose dual quaternion (rpo's ``dq_from_pose``, eq. 6) along rpo's quaternion kinematics
    and r_dot = V (inertial position r [m], velocity V [m/s]) is the code's q_dot = q omega^B / 2 (eqs. 11-12),
    omega^B = omega + eps C_{B<-I} V (``dual_velocity_body``, eq. 11)."""
    Q = _quat("Q")
    w, r, V = symbols_vec("omega"), symbols_vec("r"), symbols_vec("V")
    lhs = _dt(dq_from_pose(Q, r, "A"), [Q, r], [quat_rate(Q, w), V])
    rhs = c.pose_rate(c.unit_dq(Q, r), c.dual_velocity_body(w, quat_to_dcm(Q).T * V))
    dom = [unit_quaternion(Q), box(w, -0.01, 0.01), box(r, -7e6, 7e6), box(V, -8000, 8000)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(Q)],
                     assumptions=["|Q| = 1", "rpo's quat_rate"])


def _inertial_dual_acceleration() -> Statement:
    """d/dt omega^B = (omega, C_{B<-I} V) along the plant is the code's eq. 17, J_E^-1 (f - omega x J_E omega)
    [rad/s^2, m/s^2]: the real part is rpo's Euler equation (principal inertia M [kg m^2], torque tau [N m]),
    the dual part Newton's law V_dot = C_{I<-B} F / m (force F [N], body axes) seen in body axes."""
    Q = _quat("Q")
    w, V, F, tau = symbols_vec("omega"), symbols_vec("V"), symbols_vec("F"), symbols_vec("tau")
    m = sp.Symbol("m", positive=True)
    Mi = sp.Matrix(sp.symbols("M_1:4", positive=True))
    C_BI = quat_to_dcm(Q).T
    W = c.dual_velocity_body(w, C_BI * V)
    rates = [quat_rate(Q, w), chaser_angular_acceleration(sp.diag(*Mi), w, sp.zeros(3, 1), tau, sp.zeros(3, 1)),
             C_BI.T * F / m]
    lhs = _dt(W, [Q, w, V], rates)
    rhs = c.inertial_dual_acceleration(c.dual_inertia(m, Mi), W, c.dual_force(F, tau))
    dom = [unit_quaternion(Q), box(w, -0.01, 0.01), box(V, -8000, 8000), box(F, -1, 1), box(tau, -0.01, 0.01),
           box(m, 30, 100), box(Mi, 5, 30)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(Q)],
                     assumptions=["|Q| = 1", "principal axes (J = diag M)", "h_rw = 0"])


def _relative_dual_velocity() -> Statement:
    """The code's omega_S/T^S = omega_S/I^S - q_S/T* omega_T/I^T q_S/T (eq. 14) at the plant's relative pose
    q_S/T (eq. 13: attitude q_T^-1 (x) q_S, position r^T = C_{T<-I} (r_S - r_T) [m]) is the relative motion of
    the plant: omega_S - C_{S<-T} omega_T [rad/s] + eps C_{S<-T} d/dt r^T [m/s], d/dt r^T along the target's
    quaternion kinematics and both bodies' r_dot = V (inertial)."""
    qT, qS = _quat("qT"), _quat("qS")
    wT, wS, rT, rS, VT, VS = (symbols_vec(n) for n in ("omegaT", "omegaS", "rT", "rS", "VT", "VS"))
    q = quat_mul(quat_conj(qT), qS)
    C_TI = quat_to_dcm(qT).T
    C_ST = quat_to_dcm(q).T
    r_T = C_TI * (rS - rT)
    rdot_T = _dt(r_T, [qT, rS, rT], [quat_rate(qT, wT), VS, VT])
    W_SI = c.dual_velocity_body(wS, quat_to_dcm(qS).T * VS)
    W_TI = c.dual_velocity_body(wT, C_TI * VT)
    lhs = c.relative_dual_velocity(W_SI, W_TI, dq_from_pose(q, r_T, "A"))
    rhs = c.pure_dq(wS - C_ST * wT, C_ST * rdot_T)
    dom = [unit_quaternion(qT), unit_quaternion(qS), box(wT, -0.01, 0.01), box(wS, -0.01, 0.01),
           box(rT, -7e6, 7e6), box(rS, -7e6, 7e6), box(VT, -8000, 8000), box(VS, -8000, 8000)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(qT), quat_norm_constraint(qS)],
                     assumptions=["|q_T| = |q_S| = 1", "rpo's quat_rate"])


CLAIMS = [
    claim("plant.body_pose_kinematics", MODEL, "spacecraft", "6, 11-12",
          "eqs. 11-12: q_dot = q omega^B / 2 of the code is d/dt of rpo's pose dual quaternion along rpo's "
          "quaternion kinematics (000 eq. 24) and r_dot = V", _body_pose_kinematics,
          note="Ties the proof's pose_rate to rotations.quat_rate and dq_from_pose."),
    claim("plant.inertial_dual_acceleration", MODEL, "spacecraft", "16-17",
          "eq. 17: J_E^-1 (f - omega x J_E omega) of the code is rpo's Euler equation (000 eq. 6) and Newton's law "
          "in body axes", _inertial_dual_acceleration,
          note="Ties the proof's inertial_dual_acceleration to rigid_body.chaser_angular_acceleration."),
    claim("plant.relative_dual_velocity", MODEL, "spacecraft", "13-14",
          "eq. 14: omega_S/T^S of the code is the plant's relative rate and C_{S<-T} d/dt r_S/T^T at eq. 13's "
          "q_S/T", _relative_dual_velocity,
          note="Ties the proof's relative_dual_velocity to the plant (the C code uses eq. 14's closed form)."),
]
