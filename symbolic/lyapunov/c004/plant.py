"""004, the proof model is the plant: the model functions of :mod:`rpo.symbolic.controllers.c004` that the
Lyapunov claims integrate (eqs. 1, 3-8, 13-20: kinematics, Newton and Euler in body axes, the relative rate
and velocity dynamics) equal the motion of rpo's own rigid bodies.

The plant side is built from ``symbolic/`` alone, never from the controller module:

* attitude kinematics of each body, q_dot = 1/2 q (x) [omega, 0] (:func:`rpo.symbolic.physics.rotations.quat_rate`,
  000 eq. 24), q = C_{I<-B} scalar last, omega the body rate in body axes [rad/s]; the relative attitude
  q_ct = q_t^-1 (x) q_c (chaser c relative to target t) and its MRPs (:func:`mrp_from_quat`);
* Newton's law in inertial axes, x^I_ddot = (f + d_f)/m with the force [N] given in body axes;
* Euler's equation of the chaser J omega_dot = -omega^x J omega + tau + d_tau
  (:func:`rpo.symbolic.physics.rigid_body.chaser_angular_acceleration`, 000 eq. 6, wheel momentum h_rw = 0: 004's
  chaser is one rigid body) and of the torque-free target (:func:`target_angular_acceleration`, 000 eq. 10).

R = C_{c<-t} = quat_to_dcm(q_ct)^T is the plant's rotation; every identity holds modulo |q| = 1 (Groebner
reduction), so a dropped or mis-signed term of a proof-model function fails with a counterexample.
"""

from __future__ import annotations

import sympy as sp

from ...controllers import c004 as c
from ...physics.rigid_body import chaser_angular_acceleration, target_angular_acceleration
from ...physics.rotations import mrp_from_quat, quat_conj, quat_mul, quat_rate, quat_to_dcm, skew
from ..core import (
    Statement,
    claim_factory,
    quat_norm_constraint,
    symbols_vec,
)
from ..domains import box, rotation_matrix, spd_rotated, unit_quaternion
from .common import _inverse_var, _opaque_inverse, _rotation_symbols, _s_dot, _sym3

claim = claim_factory(__name__)


def _quat(name: str) -> sp.Matrix:
    """Quaternion of real symbols name_1..name_4 (scalar last)."""
    return sp.Matrix(sp.symbols(f"{name}_1:5", real=True))


def _relative_mrp_kinematics() -> Statement:
    """d/dt sigma_e of the plant equals the code's eq. 14 [1/s]: sigma_e = MRPs of q_ct = q_t^-1 (x) q_c
    (eq. 10's relative attitude, as ``C004.law`` forms it), each body along rpo's quaternion kinematics,
    omega_e = omega - R omega_t (eq. 12) with the plant's R = C_{c<-t}."""
    q_t, q_c = _quat("q_t"), _quat("q_c")
    w, w_t = symbols_vec("omega"), symbols_vec("omega_t")
    q = quat_mul(quat_conj(q_t), q_c)
    lhs = _s_dot(mrp_from_quat(q), [q_t, q_c], [quat_rate(q_t, w_t), quat_rate(q_c, w)])
    R = quat_to_dcm(q).T
    rhs = c.mrp_kinematics(mrp_from_quat(q), w - R * w_t)
    dom = [unit_quaternion(q_t), unit_quaternion(q_c), box(w, -0.1, 0.1), box(w_t, -0.1, 0.1)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(q_t), quat_norm_constraint(q_c)],
                     assumptions=["|q_t| = |q_c| = 1", "rpo's quat_rate for both bodies"])


def _body_translation() -> Statement:
    """Newton in body axes (eqs. 1, 3; eqs. 5, 7 for the target with f = d_f = 0): r^B = C_{B<-I} r^I and
    v^B = C_{B<-I} v^I along rpo's quaternion kinematics and r^I_dot = v^I, v^I_dot = C_{I<-B} (f + d_f)/m
    have the derivatives the code's ``position_kinematics`` and ``translational_dynamics`` state [m/s, m/s^2].
    r [m], v [m/s] inertial position and velocity, f, d_f [N] body axes, m [kg]."""
    Q = _quat("Q")
    w, r, v = symbols_vec("omega"), symbols_vec("rI"), symbols_vec("vI")
    f, d_f = symbols_vec("f"), symbols_vec("d_f")
    m = sp.Symbol("m", positive=True)
    C_BI = quat_to_dcm(Q).T
    states, rates = [Q, r, v], [quat_rate(Q, w), v, C_BI.T * (f + d_f) / m]
    r_B, v_B = C_BI * r, C_BI * v
    lhs = sp.Matrix.vstack(_s_dot(r_B, states, rates), _s_dot(v_B, states, rates))
    rhs = sp.Matrix.vstack(c.position_kinematics(r_B, v_B, w), c.translational_dynamics(m, v_B, w, f, d_f))
    dom = [unit_quaternion(Q), box(w, -0.1, 0.1), box(r, -40, 40), box(v, -2, 2), box(f, -10, 10),
           box(d_f, -1, 1), box(m, 20, 200)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(Q)],
                     assumptions=["|Q| = 1", "Newton's law in inertial axes"])


def _body_rotation() -> Statement:
    """Euler's equations (eqs. 4, 8, 18) [rad/s^2]: the code's ``rotational_dynamics`` is rpo's
    ``chaser_angular_acceleration`` (h_rw = 0) for the chaser and ``target_angular_acceleration`` for the
    torque-free target; eq. 18 (the target's omega_t_dot from chaser-side variables, omega_t = R^T (omega -
    omega_e)) is the target's Euler equation at omega_e = omega - R omega_t.  J, J_t symmetric [kg m^2],
    tau, d_tau [N m] chaser axes."""
    q = _quat("q")
    w, w_t, tau, d_tau = symbols_vec("omega"), symbols_vec("omega_t"), symbols_vec("tau"), symbols_vec("d_tau")
    J, J_t = _sym3("J"), _sym3("Jt")
    J_to = _opaque_inverse("Jt")       # the same J_t, its inverse as symbols (drawn as the true inverse)
    zero = sp.zeros(3, 1)
    R = quat_to_dcm(q).T
    lhs = sp.Matrix.vstack(c.rotational_dynamics(J, w, tau, d_tau), c.rotational_dynamics(J_t, w_t, zero, zero),
                           c.target_angular_acceleration(J_to, R, w, w - R * w_t))
    rhs = sp.Matrix.vstack(chaser_angular_acceleration(J, w, zero, tau, d_tau),
                           target_angular_acceleration(J_t, w_t, zero), c.rotational_dynamics(J_to, w_t, zero, zero))
    dom = [unit_quaternion(q), box(w, -0.1, 0.1), box(w_t, -0.1, 0.1), box(tau, -10, 10), box(d_tau, -1, 1),
           spd_rotated(J, 200, 700), spd_rotated(J_t, 2000, 3500), _inverse_var(J_to)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(q)],
                     assumptions=["|q| = 1", "J, J_t symmetric", "h_rw = 0 (004's rigid chaser)",
                                  "torque-free target (eq. 8)"])


def _one_det(m: sp.Matrix) -> sp.Matrix:
    """Each reciprocal 1/b (b a polynomial: det J, det J_t) with b expanded.  rpo's ``solve3`` writes det J by
    cofactors, SymPy's ``J.inv()`` (the code's functions) expanded; the same value, but two written forms
    would put det J twice into the residual's common denominator (a numerator of thousands of terms)."""
    return m.applyfunc(lambda e: e.replace(lambda x: x.is_Pow and x.exp.is_negative and x.base.is_Add,
                                           lambda x: sp.expand(x.base) ** x.exp))


def _orthogonality(R: sp.Matrix) -> list[sp.Expr]:
    """R^T R - I and R R^T - I, entry by entry, and det R - 1 (each == 0 for a rotation matrix; det R = 1 gives
    R S(a) = S(R a) R, which eq. 17 uses)."""
    I3 = sp.eye(3)
    return [sp.expand(M[i, j]) for M in (R.T * R - I3, R * R.T - I3) for i in range(3) for j in range(i, 3)] + [
        sp.expand(R.det() - 1)]


def _relative_rate_dynamics() -> Statement:
    """d/dt omega_e of the plant equals the code's eq. 20 with n_2 (under eq. 20) [rad/s^2], in two rows.

    omega_e = omega - R omega_t (eq. 12, chaser axes), R = C_{c<-t} nine opaque entries drawn as a rotation,
    with the orthogonality constraints.  The plant: R_dot = -omega_e^x R (the relative attitude kinematics:
    c004.plant.relative_mrp_kinematics and c004.model.R_dot), the chaser's Euler equation
    (``chaser_angular_acceleration``, h_rw = 0) and the target's rate derivative u.  Row 1: for any u, the
    plant's derivative is eq. 20 with n_2 = -R u; row 2: for the torque-free target's u
    (``target_angular_acceleration``, 000 eq. 10 = 004 eq. 8), -R u is the code's n_2.  Eq. 20 is linear in
    n_2, so the rows together are the identity; split, each proof takes seconds.  The plant's derivative is
    taken in the bodies' variables (R, omega, omega_t), then evaluated at omega_t = R^T (omega - omega_e).
    J, J_t symmetric [kg m^2], tau, d_tau [N m] chaser axes, u [rad/s^2] target axes."""
    R = _rotation_symbols()
    w, w_t, w_e, u = symbols_vec("omega"), symbols_vec("omega_t"), symbols_vec("omega_e"), symbols_vec("omegadot_t")
    tau, d_tau = symbols_vec("tau"), symbols_vec("d_tau")
    J, J_t = _sym3("J"), _sym3("Jt")
    zero = sp.zeros(3, 1)
    states = [R, w, w_t]
    rates = [-skew(w - R * w_t) * R, chaser_angular_acceleration(J, w, zero, tau, d_tau), u]
    at_e = dict(zip(w_t, R.T * (w - w_e), strict=True))
    plant = _s_dot(w - R * w_t, states, rates).xreplace(at_e)
    n2_plant = -R * target_angular_acceleration(J_t, w_t, zero).xreplace(at_e)
    lhs = sp.Matrix.vstack(plant, n2_plant)
    rhs = sp.Matrix.vstack(c.relative_rate_rate(J, w, w_e, -R * u, tau, d_tau), c.coupling_n2(R, J_t, w, w_e))
    dom = [rotation_matrix(list(R)), box(w, -0.1, 0.1), box(w_e, -0.1, 0.1), box(u, -0.01, 0.01),
           box(tau, -10, 10), box(d_tau, -1, 1), spd_rotated(J, 200, 700), spd_rotated(J_t, 2000, 3500)]
    return Statement(_one_det(lhs), "==", _one_det(rhs), dom, constraints=_orthogonality(R),
                     assumptions=["R^T R = R R^T = I, det R = 1", "R_dot = -S(omega_e) R", "J, J_t symmetric",
                                  "h_rw = 0", "torque-free target (eq. 8) in row 2"])


def _relative_velocity_dynamics() -> Statement:
    """d/dt v_e of the plant equals the code's eq. 19 with g and n_1 (under eq. 20) [m/s^2], in two rows as
    ``c004.plant.relative_rate_dynamics`` (row 1: any target rate derivative u, n_1 = -R S(p_t) u; row 2: the
    torque-free target's u gives the code's n_1).

    v_e = v - R v_pt (eq. 12), v_pt = v_t + omega_t^x p_t (eq. 11, the code's ``docking_point``, which the C
    code uses); v, v_t [m/s] each body's inertial velocity in its own axes, p_t [m] fixed in the target, R as
    in ``c004.plant.relative_rate_dynamics``.  The plant: Newton in body axes (``c004.plant.body_translation``
    derives it from rotations.py), v_dot = (f + d_f)/m - omega^x v for the chaser and v_t_dot =
    -omega_t^x v_t for the force-free target (eq. 7), R_dot = -omega_e^x R; evaluated at
    omega_t = R^T (omega - omega_e), v_t = R^T (v - v_e) - omega_t^x p_t (eqs. 11-12 solved for the target)."""
    R = _rotation_symbols()
    w, w_t, w_e, v, v_t, v_e, p_t = (symbols_vec(n) for n in ("omega", "omega_t", "omega_e", "v", "v_t", "v_e",
                                                                 "p_t"))
    u, f, d_f = symbols_vec("omegadot_t"), symbols_vec("f"), symbols_vec("d_f")
    m = sp.Symbol("m", positive=True)
    J_t = _sym3("Jt")
    zero = sp.zeros(3, 1)
    _, v_pt = c.docking_point(zero, v_t, w_t, p_t)
    states = [R, v, v_t, w_t]
    rates = [-skew(w - R * w_t) * R, (f + d_f) / m - skew(w) * v, -skew(w_t) * v_t, u]
    plant = _s_dot(v - R * v_pt, states, rates)
    at_e = dict(zip(w_t, R.T * (w - w_e), strict=True))
    plant = plant.xreplace(dict(zip(v_t, R.T * (v - v_e) - skew(w_t) * p_t, strict=True))).xreplace(at_e)
    n1_plant = -R * skew(p_t) * target_angular_acceleration(J_t, w_t, zero).xreplace(at_e)
    lhs = sp.Matrix.vstack(plant, n1_plant)
    rhs = sp.Matrix.vstack(c.relative_velocity_rate(m, c.coupling_g(w, w_e, v_e, R, p_t), -R * skew(p_t) * u, f, d_f),
                           c.coupling_n1(R, p_t, J_t, w, w_e))
    dom = [rotation_matrix(list(R)), box(w, -0.1, 0.1), box(w_e, -0.1, 0.1), box(v, -2, 2), box(v_e, -2, 2),
           box(u, -0.01, 0.01), box(p_t, -6, 6), box(f, -10, 10), box(d_f, -1, 1), box(m, 20, 200),
           spd_rotated(J_t, 2000, 3500)]
    return Statement(_one_det(lhs), "==", _one_det(rhs), dom, constraints=_orthogonality(R),
                     assumptions=["R^T R = R R^T = I, det R = 1", "R_dot = -S(omega_e) R", "J_t symmetric",
                                  "p_t fixed in the target", "force-free target (eq. 7)",
                                  "torque-free target (eq. 8) in row 2"])


CLAIMS = [
    claim("plant.relative_mrp_kinematics", "relative model", "spacecraft", "2, 6, 10, 12, 14",
          "eq. 14: sigma_e-dot = G(sigma_e) omega_e of the code is d/dt MRP(q_t^-1 (x) q_c) along rpo's "
          "quaternion kinematics (000 eq. 24)", _relative_mrp_kinematics,
          note="Ties the proof's mrp_kinematics (eqs. 2, 6, 14) to rotations.quat_rate and mrp_from_quat."),
    claim("plant.body_translation", "relative model", "spacecraft", "1, 3, 5, 7",
          "eqs. 1, 3 (5, 7): r_dot = v - S(w) r, m v_dot + m S(w) v = f + d_f of the code are Newton's law in "
          "inertial axes, written in body axes", _body_translation,
          note="Ties position_kinematics and translational_dynamics to the plant, through rotations.quat_rate."),
    claim("plant.body_rotation", "relative model", "spacecraft", "4, 8, 18",
          "eqs. 4, 8, 18: the code's rotational_dynamics and omega_t-dot are rpo's Euler equations "
          "(000 eqs. 6, 10)", _body_rotation,
          note="Ties rotational_dynamics and target_angular_acceleration (eq. 18) to rigid_body.py."),
    claim("plant.relative_rate_dynamics", "relative model", "spacecraft", "12, 16, 18, 20",
          "eq. 20: J w_e-dot = -S(w)Jw + J S(w_e)(w - w_e) + J n_2 + tau + d_tau of the code is the plant's "
          "Euler equations for w_e = w - R w_t", _relative_rate_dynamics,
          note="Ties the proof's relative_rate_rate and coupling_n2 (not in the generated C) to rigid_body.py."),
    claim("plant.relative_velocity_dynamics", "relative model", "spacecraft", "7, 11, 12, 15, 17, 19",
          "eq. 19: m v_e-dot = -m g - m n_1 + f + d_f of the code is Newton's law for both bodies, "
          "differentiated through eqs. 11-12", _relative_velocity_dynamics,
          note="Ties the proof's relative_velocity_rate, coupling_g and coupling_n1 to the plant."),
]
