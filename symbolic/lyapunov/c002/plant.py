"""002, the proof model is the plant: the relative model of eqs. 2-4, 11 (the functions of
:mod:`rpo.symbolic.controllers.c002` that only the proof uses, never the generated C code) equals the
relative motion of rpo's own rigid bodies.

The plant side is built from ``symbolic/`` alone, never from the controller module:

* attitude kinematics of each body, q_dot = 1/2 q (x) [omega, 0] (:func:`rpo.symbolic.rotations.quat_rate`,
  000 eq. 24), q = C_{I<-B} scalar last, omega the body rate in body axes [rad/s];
* the pursuer's Euler equation J omega_p_dot = -omega_p^x J omega_p + tau + tau_d
  (:func:`rpo.symbolic.rigid_body.chaser_angular_acceleration`, 000 eq. 6, wheel momentum h_rw = 0:
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
from ...rigid_body import chaser_angular_acceleration
from ...rotations import quat_conj, quat_mul, quat_rate, quat_to_dcm, skew
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
]
