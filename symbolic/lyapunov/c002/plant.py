"""002, the proof model is the plant: the relative model of eqs. 2-4, 11 (the functions of
:mod:`rpo.symbolic.controllers.c002` that only the proof uses, never the generated C code) equals the
relative motion of rpo's own rigid bodies.

The plant side is built from ``symbolic/`` alone, never from the controller module:

* attitude kinematics of each body, q_dot = 1/2 q (x) [omega, 0] (:func:`rpo.symbolic.physics.rotations.quat_rate`,
  000 eq. 24), q = C_{I<-B} scalar last, omega the body rate in body axes [rad/s];
* the pursuer's Euler equation J omega_p_dot = -omega_p^x J omega_p + tau + tau_d
  (:func:`rpo.symbolic.physics.rigid_body.chaser_angular_acceleration`, 000 eq. 6, wheel momentum h_rw = 0:
  002's pursuer is one rigid body; with wheels, -omega_p^x h_rw is part of d_r);
* the target's rate and its derivative omega_t, omega_t_dot [rad/s, rad/s^2] (target axes) are exogenous:
  free symbols, as in the paper (eq. 4 holds for any target motion).

So a term dropped from C_r or n_r (eq. 4) changes the relative acceleration of the model but not the
plant's, and the identity fails with a counterexample, where the Lyapunov claims (which take C_r, n_r as
opaque symbols or only bound them) might at most lose a proof.
"""

from __future__ import annotations

import sympy as sp

from ...controllers import c002 as c
from ...physics.rigid_body import chaser_angular_acceleration
from ...physics.rotations import quat_conj, quat_mul, quat_rate, quat_to_dcm, skew
from ..core import (
    Statement,
    claim_factory,
    lie_derivative,
    quat_norm_constraint,
    symbols_vec,
)
from ..domains import box, rotation_matrix, spd_rotated, unit_quaternion
from .common import _sym_matrix, _vec_lie

claim = claim_factory(__name__)


def _relative_quaternion_kinematics() -> Statement:
    """d/dt (Q_t^-1 (x) Q_p) along each body's q_dot = 1/2 q (x) [omega, 0] equals the code's
    dQ~/dt (eqs. 2-3) at Q~ = Q_t^-1 (x) Q_p, omega~ = omega_p - R~ omega_t (R~ = C_{p<-t})."""
    Qt = sp.Matrix(sp.symbols("Q_t1:5", real=True))
    Qp = sp.Matrix(sp.symbols("Q_p1:5", real=True))
    w_t, w_p = symbols_vec("omega_t"), symbols_vec("omega_p")
    q = quat_mul(quat_conj(Qt), Qp)                     # the plant's relative attitude (000 eq. 21's form)
    lhs = _vec_lie(q, [Qt, Qp], [quat_rate(Qt, w_t), quat_rate(Qp, w_p)])
    R = quat_to_dcm(q).T                                 # C_{p<-t}
    rhs = c.relative_quaternion_rate(q, w_p - R * w_t)
    dom = [unit_quaternion(Qt), unit_quaternion(Qp), box(w_t, -0.2, 0.2), box(w_p, -1, 1)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(Qt), quat_norm_constraint(Qp)],
                     assumptions=["|Q_t| = |Q_p| = 1", "rpo's quat_rate for both bodies"])


def _dcm_rate() -> Statement:
    """d/dt R~(Q~) along the code's dQ~/dt (eqs. 2-3) is -omega~^x R~ [1/s]: R~ = C_{p<-t} turns with the
    pursuer's rate relative to the target, in pursuer axes."""
    q = sp.Matrix(sp.symbols("q_1 q_2 q_3 q_0", real=True))     # Q~, scalar last
    w = symbols_vec("omega")
    R = c.dcm_pursuer_from_target(q)
    R_dot = sp.Matrix(3, 3, lambda i, j: lie_derivative(R[i, j], [q], [c.relative_quaternion_rate(q, w)]))
    return Statement(R_dot, "==", -skew(w) * R, [unit_quaternion(q), box(w, -1, 1)],
                     constraints=[quat_norm_constraint(q)], assumptions=["|Q~| = 1"])


def _relative_rate_dynamics() -> Statement:
    """d/dt omega~ of the plant equals the code's eq. 4 / eq. 11 (C_r, n_r of eq. 4) [rad/s^2].

    omega~ = omega_p - R~ omega_t (pursuer axes); the plant's derivative is omega_p_dot (Euler,
    :func:`chaser_angular_acceleration`) - R~_dot omega_t - R~ omega_t_dot with R~_dot = -omega~^x R~
    (``c002.plant.dcm_rate``) and omega_p = omega~ + R~ omega_t.  R~ enters as nine opaque entries (no
    orthogonality is used), J is a general symmetric inertia [kg m^2], tau, tau_d torques [N m] in pursuer
    axes."""
    R = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"R_{i + 1}{j + 1}", real=True))
    w, w_t, wd_t = symbols_vec("omega"), symbols_vec("omega_t"), symbols_vec("omegadot_t")
    tau, tau_d = symbols_vec("tau"), symbols_vec("tau_d")
    J = _sym_matrix("J")
    w_p = w + R * w_t
    plant = chaser_angular_acceleration(J, w_p, sp.zeros(3, 1), tau, tau_d) + skew(w) * R * w_t - R * wd_t
    C_r = c.attitude_coriolis_matrix(J, R, w_t, w)
    n_r = c.attitude_nonlinear_term(J, R, w_t, wd_t)
    model = c.relative_angular_acceleration(J, C_r, n_r, w, tau, tau_d)
    dom = [rotation_matrix(R), box(w, -1, 1), box(w_t, -0.2, 0.2), box(wd_t, -0.05, 0.05), box(tau, -1, 1),
           box(tau_d, -0.01, 0.01), spd_rotated(J, 5, 40)]
    return Statement(plant, "==", model, dom,
                     assumptions=["J symmetric", "h_rw = 0 (002's rigid pursuer)", "R~_dot = -omega~^x R~",
                                  "omega_t, omega_t_dot any (exogenous)"])


def _body_axes_rate() -> Statement:
    """The transport theorem from rpo's rotations: x^B = C_{B<-I}(Q) x^I along q_dot = 1/2 Q (x) [omega, 0]
    (:func:`quat_rate`) and x^I_dot has d/dt x^B = C_{B<-I} x^I_dot - omega^x x^B (omega: body rate, body
    axes).  Used below to write each body's Newton equation in its own axes, as eqs. 5-9 do."""
    Q = sp.Matrix(sp.symbols("Q_1:5", real=True))
    w, x, xd = symbols_vec("omega"), symbols_vec("x"), symbols_vec("xdot")
    C = quat_to_dcm(Q).T                                 # C_{B<-I}
    lhs = _vec_lie(C * x, [Q, x], [quat_rate(Q, w), xd])
    return Statement(lhs, "==", C * xd - skew(w) * (C * x),
                     [unit_quaternion(Q), box(w, -1, 1), box(x, -100, 100), box(xd, -10, 10)],
                     constraints=[quat_norm_constraint(Q)], assumptions=["|Q| = 1"])


def _relative_translation() -> Statement:
    """d/dt (r~, v~) of the plant equals the code's eq. 7 and eqs. 9, 12 (C_t, n_t) [m/s, m/s^2].

    r~, v~ are the code's eqs. 5-6 (the functions the C code uses) of r_p, v_p (the pursuer's inertial
    position and velocity in p axes), r_t, v_t (the target's, t axes), Q~ and omega_t.  The plant: Newton
    for the pursuer in its own axes (``c002.plant.body_axes_rate``), r_p_dot = v_p - omega_p^x r_p,
    v_p_dot = (f + f_d)/m + g_p - omega_p^x v_p (f, f_d, g_p: force [N], disturbance force [N], gravity
    [m/s^2], p axes), omega_p = omega~ + R~ omega_t; the target's r_t_dot = v_t - omega_t^x r_t and any
    v_t_dot (the component derivative of eq. 9, gravity included), omega_t_dot; Q~ along the code's dQ~/dt
    (``c002.plant.quaternion_kinematics``).  sigma_t [m] is fixed in the target body."""
    q = sp.Matrix(sp.symbols("q_1 q_2 q_3 q_0", real=True))     # Q~, scalar last
    w = symbols_vec("omega")                                    # omega~
    r_p, v_p, r_t, v_t = (symbols_vec(n) for n in ("r_p", "v_p", "r_t", "v_t"))
    w_t, wd_t, vd_t = symbols_vec("omega_t"), symbols_vec("omegadot_t"), symbols_vec("vdot_t")
    f, f_d, g_p, sig = symbols_vec("f"), symbols_vec("f_d"), symbols_vec("g_p"), symbols_vec("sigma_t")
    m = sp.Symbol("m", positive=True)
    R = c.dcm_pursuer_from_target(q)
    w_p = w + R * w_t
    r = c.relative_position(r_p, R, r_t, sig)                   # eq. 5
    v = c.relative_velocity(v_p, R, v_t, w_t, sig)              # eq. 6
    states = [q, r_p, v_p, r_t, v_t, w_t]
    rates = [c.relative_quaternion_rate(q, w), v_p - skew(w_p) * r_p, (f + f_d) / m + g_p - skew(w_p) * v_p,
             v_t - skew(w_t) * r_t, vd_t, wd_t]
    lhs = sp.Matrix.vstack(_vec_lie(r, states, rates), _vec_lie(v, states, rates))
    C_t = c.translation_rate_matrix(w, R, w_t)
    n_t = c.translation_nonlinear_term(R, w_t, wd_t, v_t, vd_t, sig, g_p)
    rhs = sp.Matrix.vstack(c.relative_position_rate(v, C_t, r), c.relative_acceleration(m, C_t, v, n_t, f, f_d))
    dom = [unit_quaternion(q), box(w, -1, 1), box(r_p, -100, 100), box(v_p, -2, 2), box(r_t, -100, 100),
           box(v_t, -2, 2), box(w_t, -0.2, 0.2), box(wd_t, -0.05, 0.05), box(vd_t, -10, 10), box(f, -100, 100),
           box(f_d, -0.01, 0.01), box(g_p, -10, 10), box(sig, -5, 5), box(m, 20, 200)]
    return Statement(lhs, "==", rhs, dom, constraints=[quat_norm_constraint(q)],
                     assumptions=["|Q~| = 1", "sigma_t fixed in the target body",
                                  "omega_t, omega_t_dot, v_t_dot, g_p any (exogenous)"])


CLAIMS = [
    claim("plant.quaternion_kinematics", "attitude", "spacecraft", "1-3",
          "eqs. 2-3: dQ~/dt of the code is d/dt (Q_t^-1 (x) Q_p) along rpo's quaternion kinematics (000 eq. 24)",
          _relative_quaternion_kinematics,
          note="Ties the proof's relative_quaternion_rate (not in the generated C) to the plant's kinematics."),
    claim("plant.dcm_rate", "attitude", "spacecraft", "1-4",
          "R~ = C_{p<-t}(Q~) of eq. 4 turns as R~_dot = -omega~^x R~ along the code's dQ~/dt (eqs. 2-3)", _dcm_rate,
          note="The step from eq. 3 to eq. 4 (-R~_dot omega_t = omega~^x R~ omega_t); used by "
               "c002.plant.relative_rate_dynamics."),
    claim("plant.relative_rate_dynamics", "attitude", "spacecraft", "3-4, 11",
          "eqs. 4, 11: J omega~_dot = -C_r omega~ - n_r + tau + tau_d of the code is the plant's Euler equation "
          "(000 eq. 6) for omega~ = omega_p - R omega_t",
          _relative_rate_dynamics,
          note="Ties the proof's C_r, n_r and relative_angular_acceleration (not in the generated C) to "
               "rigid_body.chaser_angular_acceleration: a term dropped from C_r or n_r fails here."),
    claim("plant.body_axes_rate", "position", "spacecraft", "5-9",
          "d/dt (C_{B<-I} x) = C_{B<-I} x_dot - omega^x C_{B<-I} x along rpo's quaternion kinematics (000 eq. 24)",
          _body_axes_rate,
          note="The transport theorem each body's Newton equation is written in (eqs. 5-9), from rotations.py."),
    claim("plant.relative_translation", "position", "spacecraft", "5-7, 9, 12",
          "eqs. 7, 9, 12: r~_dot = v~ - C_t r~ and m v~_dot = -m C_t v~ - m n_t + f + f_d of the code are Newton's "
          "law for both bodies, differentiated through eqs. 5-6",
          _relative_translation,
          note="Ties the proof's C_t, n_t, relative_position_rate and relative_acceleration (not in the generated C) "
               "to the plant, through the eqs. 5-6 functions the C code uses; the symbolic counterpart of "
               "tests/test_c002.py's integrated bodies."),
]
