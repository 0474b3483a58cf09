"""004: nonlinear robust adaptive relative position and attitude control (Sun & Huo), MRPs, chaser body frame.

Paper model (free-space rigid bodies, no gravity) and notation:

* frames: F_i inertial, F_c chaser body, F_t target body; every relative quantity of the paper is
  expressed in the chaser body frame F_c;
* ``R = C_{c<-t}`` maps target-frame components to chaser-frame components (eq. 9); in rpo's
  convention ``R = quat_to_dcm(q_ct).T`` with ``q_ct = q_t* ⊗ q_c`` (chaser relative to target);
* ``sigma_e`` = MRPs of the chaser attitude relative to the target, ``sigma_e = q_v / (1 + q_w)`` of
  ``q_ct`` with the shadow set chosen so that ``|sigma_e| <= 1`` (the paper's constraint; its own
  initial value [0.5, -0.6, 0.7] has norm 1.049 and is replaced by its shadow set);
* ``r_e = r - R r_pt`` (chaser relative to the docking point P, F_c), ``v_e = v - R v_pt``
  (inertial velocity difference in F_c components: NOT the F_c-frame derivative of r_e, see
  eq. 13), ``omega_e = omega - R omega_t`` (eq. 12).

Every paper equation is one module-level function below, taking the paper's variables as SymPy
matrices/symbols (numbers work too).  :class:`C004.law` composes them from the measurement.
Errata (corrected here, listed in ``docs/controllers/c004.md``):

* eq. 9: printed ``+ 8 S(s)^T S(s) / (1 + s^2)^2``; a rotation matrix needs ``+ 8 S(s)^2``;
* eq. 22: printed ``y = g + Lambda1 v_e + Lambda1 S(omega) r_e``; the line above it in (22) gives
  ``y = g - Lambda1 v_e + Lambda1 S(omega) r_e``;
* operator L: row 1 printed with five entries ``[a1 0 0 a3 a2]``; ``J a = L(a) theta`` needs
  ``[a1, 0, 0, 0, a3, a2]``;
* Y (under eq. 31): printed ``- L(Lambda2 G(sigma_e) omega_e)``; eq. 30 gives ``+``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..physics.layout import XYZ, XYZW, Bounds, Layout
from ..physics.rotations import dot, quat_conj, quat_from_mrp, quat_mul, quat_to_dcm, quat_vec, skew
from . import command_layout

THETA = ("11", "22", "33", "23", "13", "12")


# --------------------------------------------------------------------------- notation (section 2)

def S(a):
    """Skew matrix S(a), S(a) b = a x b (004 notation)."""
    return skew(a)


def sgn(a):
    """Component-wise sign with sgn(0) = 0 (004 notation).

    ``evaluate=False``: SymPy's automatic simplification of sign/Abs of the large measurement
    expressions (with the shadow-set Piecewise) takes minutes and gains nothing.
    """
    return sp.Matrix([sp.sign(ai, evaluate=False) for ai in a])


def norm1(a):
    """Vector 1-norm ||a||_1 (004 notation)."""
    return sp.Add(*[sp.Abs(ai, evaluate=False) for ai in a])


def norm2(a):
    """Vector 2-norm ||a||."""
    return sp.sqrt(dot(a, a))


def diag3(d):
    """3x3 diagonal gain matrix from its 3 diagonal entries (the paper's gains are multiples of I)."""
    return sp.diag(d[0], d[1], d[2])


# --------------------------------------------------------------------------- chaser and target (2.1)

def position_kinematics(r, v, omega):
    """r_dot = v - S(omega) r [m/s]: body-frame components of an inertial position (004 eqs. 1, 5, 13).

    ``r`` inertial position in body components [m], ``v`` inertial velocity in body components
    [m/s], ``omega`` body rate rel. inertial, body axes [rad/s].  Eq. 13 is the same form with
    (r_e, v_e, omega).
    """
    return v - S(omega) * r


def mrp_kinematics_matrix(sigma):
    """G(sigma) = 1/4 [(1 - sigma^T sigma) I + 2 S(sigma) + 2 sigma sigma^T] (004 eqs. 2, 6, 14)."""
    return ((1 - dot(sigma, sigma)) * sp.eye(3) + 2 * S(sigma) + 2 * sigma * sigma.T) / 4


def mrp_kinematics(sigma, omega):
    """sigma_dot = G(sigma) omega [1/s] (004 eqs. 2, 6, 14); omega of the frame rel. its reference, in it."""
    return mrp_kinematics_matrix(sigma) * omega


def translational_dynamics(m, v, omega, f, d_f):
    """v_dot [m/s^2] from m v_dot + m S(omega) v = f + d_f (004 eq. 3; eq. 7 with f = d_f = 0).

    ``f``, ``d_f`` control and disturbance force in body axes [N], ``m`` mass [kg].
    """
    return (f + d_f) / m - S(omega) * v


def rotational_dynamics(J, omega, tau, d_tau):
    """omega_dot [rad/s^2] from J omega_dot + S(omega) J omega = tau + d_tau (004 eq. 4; eq. 8 with 0)."""
    return J.inv() * (tau + d_tau - S(omega) * J * omega)


def target_kinetic_energy(m_t, v_t, J_t, omega_t):
    """E = 1/2 (m_t v_t^T v_t + omega_t^T J_t omega_t) [J], constant for eqs. 7-8 (004 Claim 1)."""
    return (m_t * dot(v_t, v_t) + dot(omega_t, J_t * omega_t)) / 2


# --------------------------------------------------------------------------- relative motion (2.2)

def rotation_matrix(sigma_e):
    """R = C_{c<-t} from the relative MRPs (004 eq. 9, corrected).

    004 eq. 9 as printed has ``+ 8 S(sigma_e)^T S(sigma_e) / (1 + s^2)^2``; S^T S = -S^2 is
    positive semidefinite, so the printed matrix is not orthogonal.  Corrected (Shuster's
    ``A(sigma)`` with S = -[[sigma]]): ``+ 8 S(sigma_e)^2 / (1 + s^2)^2``.
    R(sigma) = R(shadow(sigma)).
    """
    s2 = dot(sigma_e, sigma_e)
    Se = S(sigma_e)
    return sp.eye(3) - 4 * (1 - s2) / (1 + s2) ** 2 * Se + 8 / (1 + s2) ** 2 * Se * Se


def relative_mrp(sigma, sigma_t):
    """sigma_e, MRPs of F_c relative to F_t, from the chaser and target MRPs rel. F_i (004 eq. 10).

    May return the non-principal set (|sigma_e| > 1); see :func:`principal_mrp` for the switch.
    Singular when 1 + |sigma_t|^2 |sigma|^2 + 2 sigma_t . sigma = 0 (sigma = -sigma_t on the unit
    sphere: identical attitudes in opposite MRP sets), which is why :meth:`C004.law` forms
    sigma_e from the relative quaternion instead.
    """
    num = sigma_t * (dot(sigma, sigma) - 1) + sigma * (1 - dot(sigma_t, sigma_t)) - 2 * S(sigma_t) * sigma
    den = 1 + dot(sigma_t, sigma_t) * dot(sigma, sigma) + 2 * dot(sigma_t, sigma)
    return num / den


def principal_mrp(q):
    """MRPs with |sigma| <= 1 of the unit quaternion q (scalar last): shadow-set switching.

    ``sign(w) q_v / (1 + |w|)``, which equals ``mrp_switch(mrp_from_quat(q))`` wherever the
    latter is defined, but has no 0/0 at w = -1 (q and -q are the same attitude and the plant's
    quaternions carry no sign convention).  Written with a Piecewise factor so sign(0) = +1.
    """
    s = sp.Piecewise((-1, q[3] < 0), (1, True))
    return s * quat_vec(q) / (1 + s * q[3])


def docking_point(r_t, v_t, omega_t, p_t):
    """(r_pt, v_pt): position [m] and inertial velocity [m/s] of the docking point P in F_t (004 eq. 11).

    ``p_t`` constant offset of P from the target's centre of mass, target axes [m].
    """
    return r_t + p_t, v_t + S(omega_t) * p_t


def relative_state(r, v, omega, R, r_pt, v_pt, omega_t):
    """(r_e, v_e, omega_e) in chaser axes (004 eq. 12): r - R r_pt, v - R v_pt, omega - R omega_t."""
    return r - R * r_pt, v - R * v_pt, omega - R * omega_t


def target_angular_acceleration(J_t, R, omega, omega_e):
    """omega_t_dot [rad/s^2], target axes, torque-free target (004 eq. 18), from chaser-side variables."""
    w_t = R.T * (omega - omega_e)
    return -J_t.inv() * S(w_t) * J_t * w_t


def docking_point_acceleration(R, v, v_e, omega, omega_e, p_t, omega_t_dot):
    """R v_pt_dot [m/s^2], chaser axes: the docking point's acceleration term (004 eq. 17, last line)."""
    w_tc = omega - omega_e
    return -S(w_tc) * (v - v_e - S(w_tc) * R * p_t) - R * S(p_t) * omega_t_dot


def relative_velocity_rate_coupled(m, v, v_e, omega, omega_e, R_vpt_dot, f, d_f):
    """v_e_dot [m/s^2] (004 eq. 15): m v_e_dot = -m[S(omega - omega_e) v + S(omega_e) v_e + R v_pt_dot] + f + d_f."""
    return (-m * (S(omega - omega_e) * v + S(omega_e) * v_e + R_vpt_dot) + f + d_f) / m


def relative_rate_rate_coupled(J, omega, omega_e, R, omega_t_dot, tau, d_tau):
    """omega_e_dot [rad/s^2] (004 eq. 16): J omega_e_dot = -S(w)Jw - J[R w_t_dot - S(w_e)(w - w_e)] + tau + d_tau."""
    rhs = -S(omega) * J * omega - J * (R * omega_t_dot - S(omega_e) * (omega - omega_e)) + tau + d_tau
    return J.inv() * rhs


def coupling_g(omega, omega_e, v_e, R, p_t):
    """g = S(omega) v_e + S(omega - omega_e)^2 R p_t [m/s^2] (004, under eq. 20)."""
    w_tc = S(omega - omega_e)
    return S(omega) * v_e + w_tc * w_tc * R * p_t


def coupling_n1(R, p_t, J_t, omega, omega_e):
    """n_1 = R S(p_t) J_t^-1 S(R^T(w - w_e)) J_t R^T(w - w_e) [m/s^2] (004, under eq. 20)."""
    w_t = R.T * (omega - omega_e)
    return R * S(p_t) * J_t.inv() * S(w_t) * J_t * w_t


def coupling_n2(R, J_t, omega, omega_e):
    """n_2 = R J_t^-1 S(R^T(w - w_e)) J_t R^T(w - w_e) [rad/s^2] (004, under eq. 20)."""
    w_t = R.T * (omega - omega_e)
    return R * J_t.inv() * S(w_t) * J_t * w_t


def relative_velocity_rate(m, g, n1, f, d_f):
    """v_e_dot [m/s^2] (004 eq. 19): m v_e_dot = -m g - m n_1 + f + d_f."""
    return (-m * g - m * n1 + f + d_f) / m


def relative_rate_rate(J, omega, omega_e, n2, tau, d_tau):
    """omega_e_dot [rad/s^2] (004 eq. 20): J w_e_dot = -S(w)Jw + J S(w_e)(w - w_e) + J n_2 + tau + d_tau."""
    return J.inv() * (-S(omega) * J * omega + J * S(omega_e) * (omega - omega_e) + J * n2 + tau + d_tau)


# --------------------------------------------------------------------------- position controller (3.1)

def position_surface(v_e, r_e, Lambda1):
    """s_1 = v_e + Lambda1 r_e [m/s] (004 eq. 21)."""
    return v_e + Lambda1 * r_e


def position_regressor(g, v_e, r_e, omega, Lambda1):
    """y = g - Lambda1 v_e + Lambda1 S(omega) r_e [m/s^2] (004 eq. 22, corrected).

    004 prints ``y = g + Lambda1 v_e + Lambda1 S(omega) r_e``, but the middle line of eq. 22,
    ``... + m Lambda1 v_e - m Lambda1 S(omega) r_e = -m y ...``, i.e. m Lambda1 r_e_dot with eq. 13,
    requires ``-Lambda1 v_e``: y = g - Lambda1 r_e_dot.
    """
    return g - Lambda1 * v_e + Lambda1 * S(omega) * r_e


def position_surface_dynamics(m, y, n1, f, d_f):
    """m s_1_dot [N] (004 eq. 22): -m y - m n_1 + f + d_f."""
    return -m * y - m * n1 + f + d_f


def position_lyapunov(k0, r_e, m, s1, m_tilde, rho_f_tilde, rho_m_tilde, gamma1, gamma2, gamma3):
    """V_1 [J] (004 eq. 23)."""
    return (k0 * dot(r_e, r_e) + m * dot(s1, s1) + m_tilde**2 / gamma1 + rho_f_tilde**2 / gamma2
            + rho_m_tilde**2 / gamma3) / 2


def position_control(k0, K1, r_e, s1, m0, m_hat_delta, y, rho_f_hat, rho_m_hat, p_t, omega, omega_e):
    """Control force f [N], chaser axes (004 eq. 25).

    f = -k0 r_e - K1 s1 + (m0 + m_hat_delta) y - rho_f_hat sgn(s1) - rho_m_hat ||p_t|| ||w - w_e||^2 sgn(s1).
    ``||omega - omega_e|| = ||omega_t||`` bounds the unknown coupling n_1 with rho_m.
    """
    w_tc = omega - omega_e
    robust = rho_f_hat + rho_m_hat * norm2(p_t) * dot(w_tc, w_tc)
    return -k0 * r_e - K1 * s1 + (m0 + m_hat_delta) * y - robust * sgn(s1)


def position_adaptation(gamma1, gamma2, gamma3, y, s1, p_t, omega, omega_e):
    """(m_hat_delta_dot [kg/s], rho_f_hat_dot [N/s], rho_m_hat_dot [kg/s]) (004 eq. 27)."""
    w_tc = omega - omega_e
    n1s = norm1(s1)
    return -gamma1 * dot(y, s1), gamma2 * n1s, gamma3 * norm2(p_t) * dot(w_tc, w_tc) * n1s


# --------------------------------------------------------------------------- attitude controller (3.2)

def attitude_surface(omega_e, sigma_e, Lambda2):
    """s_2 = omega_e + Lambda2 sigma_e [rad/s] (004 eq. 29)."""
    return omega_e + Lambda2 * sigma_e


def attitude_surface_dynamics(J, omega, omega_e, sigma_e, Lambda2, n2, tau, d_tau):
    """J s_2_dot [N m] (004 eq. 30): -S(w)Jw + J S(w_e)(w - w_e) + J Lambda2 G(sigma_e) w_e + tau + d_tau + J n_2."""
    return (-S(omega) * J * omega + J * S(omega_e) * (omega - omega_e)
            + J * Lambda2 * mrp_kinematics(sigma_e, omega_e) + tau + d_tau + J * n2)


def inertia_operator(a):
    """L(a) with J a = L(a) theta, theta = [J11, J22, J33, J23, J13, J12] (004, above eq. 31, corrected).

    Row 1 is printed with five entries ``[a1 0 0 a3 a2]``; (J a)_1 = J11 a1 + J12 a2 + J13 a3 needs
    ``[a1, 0, 0, 0, a3, a2]`` (a zero lost in print or extraction).
    """
    a1, a2, a3 = a[0], a[1], a[2]
    return sp.Matrix([[a1, 0, 0, 0, a3, a2],
                      [0, a2, 0, a3, 0, a1],
                      [0, 0, a3, a2, a1, 0]])


def inertia_parameters(J):
    """theta = [J11, J22, J33, J23, J13, J12] [kg m^2] of a symmetric J (004, above eq. 31)."""
    return sp.Matrix([J[0, 0], J[1, 1], J[2, 2], J[1, 2], J[0, 2], J[0, 1]])


def attitude_regressor(omega, omega_e, sigma_e, Lambda2):
    """Y [rad/s^2] with Y theta = -S(w)Jw + J S(w_e)(w - w_e) + J Lambda2 G w_e (004 eq. 31, corrected).

    Printed: ``Y = L(S(w_e)(w - w_e)) - S(w)L(w) - L(Lambda2 G(sigma_e) w_e)``; eq. 30 has
    ``+ J Lambda2 G(sigma_e) w_e``, so the last sign is ``+``.
    """
    return (inertia_operator(S(omega_e) * (omega - omega_e)) - S(omega) * inertia_operator(omega)
            + inertia_operator(Lambda2 * mrp_kinematics(sigma_e, omega_e)))


def attitude_lyapunov(J, s2, theta_tilde, rho_tau_tilde, rho_J_tilde, gamma4, gamma5, gamma6):
    """V_2 [J] (004 eq. 32)."""
    return (dot(s2, J * s2) + dot(theta_tilde, theta_tilde) / gamma4 + rho_tau_tilde**2 / gamma5
            + rho_J_tilde**2 / gamma6) / 2


def attitude_control(K2, s2, Y, theta0, theta_hat_delta, rho_tau_hat, rho_J_hat, omega, omega_e):
    """Control torque tau [N m], chaser axes (004 eq. 34).

    tau = -K2 s2 - Y (theta0 + theta_hat_delta) - rho_tau_hat sgn(s2) - rho_J_hat ||w - w_e||^2 sgn(s2).
    """
    w_tc = omega - omega_e
    return -K2 * s2 - Y * (theta0 + theta_hat_delta) - (rho_tau_hat + rho_J_hat * dot(w_tc, w_tc)) * sgn(s2)


def attitude_adaptation(gamma4, gamma5, gamma6, Y, s2, omega, omega_e):
    """(theta_hat_delta_dot (6) [kg m^2/s], rho_tau_hat_dot [N m/s], rho_J_hat_dot [kg m^2/s]) (004 eq. 36)."""
    w_tc = omega - omega_e
    n1s = norm1(s2)
    return gamma4 * Y.T * s2, gamma5 * n1s, gamma6 * dot(w_tc, w_tc) * n1s


# --------------------------------------------------------------------------- actuators (not in 004)

def split_torque(tau, limit):
    """(tau_w, tau_thr) [N m]: tau clipped per axis to +-limit for the wheels, the remainder for the thrusters.

    004 commands one torque tau to ideal actuators; tau_w + tau_thr = tau exactly, so the paper
    plant (which applies sat(tau_w + tau_thr)) is unaffected.  In the full plant this lets the
    thrusters carry what the 000 wheels (0.1 N m, about 1 N m s) cannot.
    """
    # the thruster part is formed directly (not as tau - clip(tau)) so that it is exactly 0 in floating
    # point whenever |tau_i| <= limit
    tau_thr = sp.Matrix([sp.Max(0, ti - limit, evaluate=False) + sp.Min(0, ti + limit, evaluate=False) for ti in tau])
    return tau - tau_thr, tau_thr


# --------------------------------------------------------------------------- measurement -> paper variables

def paper_relative_state(q_c, w_c, q_t, w_t, r_L, v_L, q_L, n, p_t):
    """The paper's (sigma_e, R, r_e, v_e, omega_e) from rpo's measurement (not a paper equation).

    ``r_L``, ``v_L``: chaser minus target position, and its LVLH-frame derivative, in LVLH (a frame
    fixed in ECI in the free-space plant: q_L = identity, n = 0).  The inertial velocity
    difference is ``v_L + [0, 0, n] x r_L`` (LVLH rotates about its Z axis at n).  Expressed in
    chaser axes with C_{c<-L}, these are eq. 12's ``r - R r_t`` and ``v - R v_t``: eqs. 11-12 are
    applied with the origin at the target's centre of mass (r_t = v_t = 0), which leaves r_e,
    v_e unchanged because eq. 12 is linear in (r, r_t) and (v, v_t).
    """
    q_ct = quat_mul(quat_conj(q_t), q_c)
    sigma_e = principal_mrp(q_ct)              # shadow-set switched, |sigma_e| <= 1
    R = rotation_matrix(sigma_e)               # eq. 9: C_{c<-t}
    C_cL = quat_to_dcm(quat_mul(quat_conj(q_L), q_c)).T
    r_rel = C_cL * r_L
    v_rel = C_cL * (v_L + S(sp.Matrix([0, 0, n])) * r_L)
    zero = sp.zeros(3, 1)
    r_pt, v_pt = docking_point(zero, zero, w_t, p_t)
    r_e, v_e, w_e = relative_state(r_rel, v_rel, w_c, R, r_pt, v_pt, w_t)
    return sigma_e, R, r_e, v_e, w_e


@dataclass
class C004:
    """004's position (eqs. 21, 25, 27) and attitude (eqs. 29-36) controllers."""

    name: str = "c004"
    k: Layout = field(default_factory=lambda: Layout("k"))
    xc: Layout = field(default_factory=lambda: Layout("xc"))
    diag: Layout = field(default_factory=lambda: Layout("diag"))

    def __post_init__(self):
        k = self.k
        k.add("k0", 1, "N/m", "relative-position gain k_0 (eq. 25)", default=0.1,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("K1", 3, "N s/m", "diagonal of K_1 (eq. 25)", XYZ, default=(20, 20, 20),
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("K2", 3, "N m s", "diagonal of K_2 (eq. 34)", XYZ, default=(100, 100, 100),
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("Lambda1", 3, "1/s", "diagonal of Lambda_1 (eq. 21)", XYZ, default=(0.05, 0.05, 0.05),
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("Lambda2", 3, "1/s", "diagonal of Lambda_2 (eq. 29)", XYZ, default=(0.2, 0.2, 0.2),
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("gamma1", 1, "kg s^2/m^2", "adaptation gain of m_hat_delta (eq. 27)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma2", 1, "N/m", "adaptation gain of rho_f_hat (eq. 27)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma3", 1, "kg s^2/m^2", "adaptation gain of rho_m_hat (eq. 27)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma4", 1, "kg m^2 s^2", "adaptation gain of theta_hat_delta (eq. 36)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma5", 1, "N m", "adaptation gain of rho_tau_hat (eq. 36)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma6", 1, "kg m^2 s^2", "adaptation gain of rho_J_hat (eq. 36)", default=0.02,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("m0", 1, "kg", "nominal chaser mass m_0 (Hypothesis 1)", default=50.0,
              bounds=Bounds(1e-2, 1e7, why="a nominal mass, as the plant's masses"))
        k.add("theta0", 6, "kg m^2", "nominal inertia parameters [J11, J22, J33, J23, J13, J12]", THETA,
              default=(580, 400, 300, 0, 0, 0),
              bounds=Bounds(-1e10, 1e10, why="inertia entries (products either sign), as the plant's inertias"))
        k.add("p_t", 3, "m", "docking point P in the target body frame (eq. 11)", XYZ, default=(0, 5, 0),
              bounds=Bounds(-1e5, 1e5, why="a position, either sign, within 100 km"))
        k.add("tau_wheel_max", 1, "N m", "not in 004: per-axis share of tau sent to the wheels, the rest to the "
              "thrusters (the sum is applied unchanged by ideal actuators)", default=1e3,
              bounds=Bounds(0.0, 1e4, why="a torque share, >= 0"))

        x = self.xc
        x.add("m_hat_delta", 1, "kg", "mass-uncertainty estimate (eq. 27)", default=0.0)
        x.add("rho_f_hat", 1, "N", "disturbance-force bound estimate (eq. 27)", default=0.0)
        x.add("rho_m_hat", 1, "kg", "estimate of rho_m = |m| ||J_t^-1|| ||J_t|| (eq. 27)", default=0.0)
        x.add("theta_hat_delta", 6, "kg m^2", "inertia-uncertainty estimate (eq. 36)", THETA, default=(0,) * 6)
        x.add("rho_tau_hat", 1, "N m", "disturbance-torque bound estimate (eq. 36)", default=0.0)
        x.add("rho_J_hat", 1, "kg m^2", "estimate of rho_J = ||J|| ||J_t^-1|| ||J_t|| (eq. 36)", default=0.0)

        d = self.diag
        d.add("att_err", 1, "rad", "rotation angle chaser body -> target body, 4 atan |sigma_e|")
        d.add("q_err", 4, "-", "chaser attitude relative to the target body frame (scalar last, w >= 0)", XYZW)
        d.add("pos_err", 3, "m", "r_e: chaser minus docking point P, chaser body axes (eq. 12)", XYZ)
        d.add("rate_err", 3, "rad/s", "omega_e = omega - R omega_t, chaser body axes (eq. 12)", XYZ)
        d.add("vel_err", 3, "m/s", "v_e = v - R v_pt, inertial velocity difference in chaser axes (eq. 12)", XYZ)
        d.add("sigma_e", 3, "-", "relative MRPs, shadow-set switched (|sigma_e| <= 1)", XYZ)
        d.add("s1", 3, "m/s", "position sliding surface (eq. 21)", XYZ)
        d.add("s2", 3, "rad/s", "attitude sliding surface (eq. 29)", XYZ)
        d.add("y", 3, "m/s^2", "position regressor y (eq. 22, corrected)", XYZ)
        d.add("m_hat_delta", 1, "kg", "mass-uncertainty estimate")
        d.add("rho_f_hat", 1, "N", "disturbance-force bound estimate")
        d.add("rho_m_hat", 1, "kg", "rho_m estimate")
        d.add("theta_hat_delta", 6, "kg m^2", "inertia-uncertainty estimate", THETA)
        d.add("rho_tau_hat", 1, "N m", "disturbance-torque bound estimate")
        d.add("rho_J_hat", 1, "kg m^2", "rho_J estimate")

    def law(self, meas, t, p):
        """(cmd, xc_dot, diag) as SymPy column matrices (eqs. 9, 11, 12, 21, 22, 25, 27, 29, 31, 34, 36)."""
        k, xc = self.k, self.xc
        Lambda1, Lambda2 = diag3(k["Lambda1"]), diag3(k["Lambda2"])
        K1, K2 = diag3(k["K1"]), diag3(k["K2"])
        p_t = k["p_t"]
        w = meas["w_c"]
        sigma_e, R, r_e, v_e, w_e = paper_relative_state(
            meas["q_c"], w, meas["q_t"], meas["w_t"], meas["r"], meas["v"], meas["q_L"], meas["n"], p_t)

        # position (3.1)
        g = coupling_g(w, w_e, v_e, R, p_t)
        s1 = position_surface(v_e, r_e, Lambda1)
        y = position_regressor(g, v_e, r_e, w, Lambda1)
        f = position_control(k["k0"], K1, r_e, s1, k["m0"], xc["m_hat_delta"], y, xc["rho_f_hat"],
                             xc["rho_m_hat"], p_t, w, w_e)
        dm, drf, drm = position_adaptation(k["gamma1"], k["gamma2"], k["gamma3"], y, s1, p_t, w, w_e)

        # attitude (3.2)
        s2 = attitude_surface(w_e, sigma_e, Lambda2)
        Y = attitude_regressor(w, w_e, sigma_e, Lambda2)
        tau = attitude_control(K2, s2, Y, k["theta0"], xc["theta_hat_delta"], xc["rho_tau_hat"],
                               xc["rho_J_hat"], w, w_e)
        dth, drt, drJ = attitude_adaptation(k["gamma4"], k["gamma5"], k["gamma6"], Y, s2, w, w_e)

        tau_w, tau_thr = split_torque(tau, k["tau_wheel_max"])
        cmd = command_layout().pack({"tau_w": tau_w, "F": f, "tau_thr": tau_thr})
        xc_dot = xc.pack({"m_hat_delta": dm, "rho_f_hat": drf, "rho_m_hat": drm, "theta_hat_delta": dth,
                          "rho_tau_hat": drt, "rho_J_hat": drJ})
        diag = self.diag.pack({
            "att_err": 4 * sp.atan(norm2(sigma_e)), "q_err": quat_from_mrp(sigma_e), "pos_err": r_e,
            "rate_err": w_e, "vel_err": v_e, "sigma_e": sigma_e, "s1": s1, "s2": s2, "y": y,
            "m_hat_delta": xc["m_hat_delta"], "rho_f_hat": xc["rho_f_hat"], "rho_m_hat": xc["rho_m_hat"],
            "theta_hat_delta": xc["theta_hat_delta"], "rho_tau_hat": xc["rho_tau_hat"],
            "rho_J_hat": xc["rho_J_hat"],
        })
        return cmd, xc_dot, diag


DESIGN = C004


def initial_state_from_relative(sigma_e, omega_e, r_e, v_e, p_t, q_c, w_c, q_L, n):
    """Plant initial state (q_t, w_t, r_L, v_L) from the paper's relative state (004 Table 1).

    Inverse of :func:`paper_relative_state` for a given chaser attitude ``q_c`` (rel. ECI) and rate
    ``w_c``: ``q_t = q_c ⊗ q_ct*`` with ``q_ct`` from ``sigma_e`` (either MRP set), ``omega_t =
    R^T (omega - omega_e)``, ``r - R r_t = r_e + R p_t``, ``v - R v_t = v_e + R S(omega_t) p_t``
    (eqs. 11-12 about the target's centre of mass), then rotated to LVLH.  Used to derive the
    scenario's numbers; works on numbers and symbols.
    """
    q_ct = quat_from_mrp(sigma_e)
    q_t = quat_mul(q_c, quat_conj(q_ct))
    R = rotation_matrix(sigma_e)
    w_t = R.T * (w_c - omega_e)
    C_Lc = quat_to_dcm(quat_mul(quat_conj(q_L), q_c))
    r_L = C_Lc * (r_e + R * p_t)
    v_L = C_Lc * (v_e + R * S(w_t) * p_t) - S(sp.Matrix([0, 0, n])) * r_L
    return q_t, w_t, r_L, v_L
