"""Seed 002: adaptive sliding-mode rendezvous control with a tanh anti-saturation auxiliary system.

Z. Li, G. Yu, Q. Zhang, S. Song, H. Cui, "Adaptive Sliding Mode Control for Spacecraft Rendezvous
With Unknown System Parameters and Input Saturation", IEEE Access 9 (2021).

Frames and variables (the paper's, Section II).  ``p`` = pursuer (the chaser) body frame,
``t`` = target body frame.  Every vector of the controller is expressed in ``p``:

* ``q_rel`` = Q~ = Q_t^{-1} (x) Q_p (eq. 1), chaser relative to target body, scalar LAST here;
* ``R`` = R~ = C_{p<-t} = quat_to_dcm(q_rel)^T (rpo convention: quat_to_dcm gives C_{A<-B});
* ``w_rel`` = omega~ = omega_p - R omega_t [rad/s] (under eq. 3);
* ``r_rel`` = r~ = r_p - R (r_t + sigma_t) [m] (eq. 5): the chaser's position relative to the
  rendezvous point sigma_t (fixed in the target body), in p axes;
* ``v_rel`` = v~ = v_p - R (v_t + omega_t x sigma_t) [m/s] (eq. 6), v_p, v_t being the inertial
  velocities in their own body axes.

The controller drives Q~ -> [0, 0, 0, 1] (chaser axes parallel to the target's) and r~ -> 0.

Every paper equation is one module-level function below (cited by number), so the Lyapunov
checker can call the same functions with abstract symbols; :meth:`C002.law` only composes them.
Errata and choices: ``docs/controllers/c002.md`` (summarised beside the code).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..physics import actuators as act
from ..physics.layout import XYZ, XYZW, Bounds, Layout
from ..physics.rotations import dot, quat, quat_conj, quat_mul, quat_to_dcm, quat_vec, skew
from . import command_layout

# =========================================================================== relative model
# (eqs. 1-12; used by the law only through eqs. 1, 3, 5, 6; the rest is for the proof checker
# and for tests/test_c002.py, which holds them against rigid-body and orbital physics)


def relative_quaternion(Q_t, Q_p):
    """Q~ = Q_t^{-1} (x) Q_p (002 eq. 1): pursuer attitude relative to the target body (scalar last)."""
    return quat_mul(quat_conj(Q_t), Q_p)


def dcm_pursuer_from_target(q_rel):
    """R~ = C_{p<-t} [-] of Q~ (002 eqs. 1, 4): maps target-body components to pursuer-body ones."""
    return quat_to_dcm(q_rel).T


def relative_quaternion_rate(q_rel, w_rel):
    """dQ~/dt (002 eqs. 2-3), scalar last: [1/2 (q_v^x + q_0 I_3) w~ ; -1/2 q_v^T w~].

    (Eq. 3 as extracted prints ``J_3`` for the identity ``I_3``.)
    """
    qv, q0 = quat_vec(q_rel), q_rel[3]
    return quat((skew(qv) + q0 * sp.eye(3)) * w_rel / 2, -dot(qv, w_rel) / 2)


def relative_angular_velocity(w_p, R, w_t):
    """omega~ = omega_p - R~ omega_t [rad/s], pursuer axes (002, definition under eq. 3)."""
    return w_p - R * w_t


def attitude_coriolis_matrix(J, R, w_t, w_rel):
    """C_r = J (R w_t)^x + (R w_t)^x J - (J (w~ + R w_t))^x [kg m^2/s] (002 eq. 4)."""
    wt = R * w_t
    return J * skew(wt) + skew(wt) * J - skew(J * (w_rel + wt))


def attitude_nonlinear_term(J, R, w_t, w_t_dot):
    """n_r = (R w_t)^x J R w_t + J R omega_t_dot [N m] (002 eq. 4, corrected).

    002 eq. 4 as printed has ``J R_dot omega_t``; the derivation (omega_p = w~ + R w_t, Euler's
    equation for the pursuer) gives ``J R omega_t_dot`` -- the form Remark 4 itself bounds
    (``J R omega_t_dot``).  ``R_dot omega_t = (R w_t)^x w~`` is already inside C_r.
    ``w_t_dot``: target angular acceleration in target axes.
    """
    wt = R * w_t
    return skew(wt) * J * wt + J * R * w_t_dot


def relative_angular_acceleration(J, C_r, n_r, w_rel, tau, tau_d):
    """d omega~/dt from J w~_dot = -C_r w~ - n_r + tau + tau_d [rad/s^2] (002 eqs. 4, 11).

    Eq. 11 is this with tau = u(eps_r) (eq. 13) and tau_d = d_r (eq. 10).  ``J`` is the
    pursuer inertia [kg m^2], torques in pursuer axes [N m].
    """
    return J.inv() * (-C_r * w_rel - n_r + tau + tau_d)


def relative_position(r_p, R, r_t, sigma_t):
    """r~ = r_p - R~ (r_t + sigma_t) [m], pursuer axes (002 eq. 5 solved for r~).

    r_p: pursuer position (p axes), r_t: target position (t axes), sigma_t: rendezvous point
    fixed in the target body (t axes).  Only r_p - R r_t (the relative position of the two
    centres, in p axes) matters.
    """
    return r_p - R * (r_t + sigma_t)


def relative_velocity(v_p, R, v_t, w_t, sigma_t):
    """v~ = v_p - R~ (v_t + omega_t^x sigma_t) [m/s], pursuer axes (002 eq. 6 solved for v~)."""
    return v_p - R * (v_t + skew(w_t) * sigma_t)


def translation_rate_matrix(w_rel, R, w_t):
    """C_t = (w~ + R w_t)^x = omega_p^x [1/s] (002, under eq. 7)."""
    return skew(w_rel + R * w_t)


def relative_position_rate(v_rel, C_t, r_rel):
    """d r~/dt = v~ - C_t r~ [m/s] (002 eq. 7): component derivative in the rotating p frame."""
    return v_rel - C_t * r_rel


def translation_nonlinear_term(R, w_t, w_t_dot, v_t, v_t_dot, sigma_t, g_p):
    """n_t [m/s^2] of 002 eq. 9, corrected:

        n_t = (R w_t)^x R v_t + R v_t_dot + (R w_t)^x (R w_t)^x R sigma_t - R sigma_t^x w_t_dot - g_p

    with v_t_dot the component derivative of the target's inertial velocity in target axes
    (it contains the target's gravity) and g_p the pursuer's gravitational acceleration in p
    axes.  As printed, eq. 9 (a) has ``w~^x R sigma_t^x w_t`` for the third term: the
    centripetal acceleration of the rendezvous point, -(R w_t)^x R sigma_t^x w_t, is what the
    derivative of eq. 6 gives; (b) has no pursuer gravity, which is right only in free space
    (g_p = 0, v_t_dot = -w_t^x v_t).  ``tests/test_c002.py`` checks this form against two
    independently integrated rigid bodies in a central gravity field.
    """
    wt = R * w_t
    return (skew(wt) * R * v_t + R * v_t_dot + skew(wt) * skew(wt) * R * sigma_t
            - R * skew(sigma_t) * w_t_dot - g_p)


def translation_nonlinear_term_printed(R, w_rel, w_t, w_t_dot, v_t, v_t_dot, sigma_t):
    """002 eq. 9's n_t exactly as printed; kept only to quantify the erratum in the tests."""
    wt = R * w_t
    return skew(wt) * R * v_t + R * v_t_dot + skew(w_rel) * R * skew(sigma_t) * w_t - R * skew(sigma_t) * w_t_dot


def relative_acceleration(m, C_t, v_rel, n_t, f, f_d):
    """d v~/dt from m v~_dot = -m C_t v~ - m n_t + f + f_d [m/s^2] (002 eqs. 9, 12).

    Eq. 12 is this with f = u(eps_t) (eq. 13), f_d = d_t (eq. 10); forces in p axes [N].
    """
    return -C_t * v_rel - n_t + (f + f_d) / m


def saturation(eps, u_max):
    """u(eps) = sat(eps) per component, |u_i| <= u_max (002 eq. 13, corrected).

    As printed, eq. 13 switches on ``eps_i >= u_M`` (not |eps_i| >= u_M), which would leave
    large negative commands unsaturated; the text ("u_M is the upper bound") means |u_i| <= u_M.
    """
    return act.saturate(sp.Matrix(eps), u_max)


# =========================================================================== controller


def tanh_vec(chi):
    """Component-wise tanh."""
    return chi.applyfunc(sp.tanh)


def sliding_surface_attitude(w_rel, qv, chi1, k1, k2):
    """s_1 = w~ + k_1 q~_v - k_2 tanh(chi_1) [rad/s] (002 eq. 15)."""
    return w_rel + k1 * qv - k2 * tanh_vec(chi1)


def sliding_surface_position(v_rel, r_rel, chi2, k5, k6):
    """s_2 = v~ + k_5 r~ - k_6 tanh(chi_2) [m/s] (002 eq. 16)."""
    return v_rel + k5 * r_rel - k6 * tanh_vec(chi2)


def aux_phi(chi):
    """phi = diag(1 - tanh^2(chi_i)) [-] (002, under eq. 18)."""
    return sp.diag(*[1 - sp.tanh(c) ** 2 for c in chi])


def aux_phi_inverse(chi):
    """phi^{-1} = diag(cosh^2(chi_i)): identical to 1/(1 - tanh^2), but finite in floating point
    until |chi| ~ 355 where 1 - tanh^2 already rounds to 0 at |chi| ~ 19."""
    return sp.diag(*[sp.cosh(c) ** 2 for c in chi])


def aux_attitude_rate(chi1, J, k2, kappa1, eps_r, u_r):
    """d chi_1/dt = phi_1^{-1} J^{-1} [-kappa_1 tanh(chi_1) + sat(eps_r) - eps_r] / k_2 [1/s] (002 eq. 17).

    ``J``: nominal pursuer inertia [kg m^2]; ``eps_r``: commanded torque, ``u_r = sat(eps_r)``
    [N m].  chi_1(0) = 0.
    """
    return aux_phi_inverse(chi1) * J.inv() * (-kappa1 * tanh_vec(chi1) + u_r - eps_r) / k2


def aux_position_rate(chi2, m, k6, kappa2, eps_t, u_t):
    """d chi_2/dt = phi_2^{-1} [-kappa_2 tanh(chi_2) + sat(eps_t) - eps_t] / (k_6 m) [1/s] (002 eq. 18).

    ``m``: nominal pursuer mass [kg]; forces [N].  chi_2(0) = 0.
    """
    return aux_phi_inverse(chi2) * (-kappa2 * tanh_vec(chi2) + u_t - eps_t) / (k6 * m)


def adaptive_term(s, a_hat, y2, eps):
    """-s a^2 y^2 / sqrt(|s|^2 a^2 y^2 + eps^2): the form of each adaptive term of 002 eqs. 23-24.

    ``y2`` is the squared regressor (|w~|^4, |w~|^2, 1, |w~|^2 |v~|^2, ...); by Lemma 2 it
    bounds s^T(.) <= -|s| a y + eps.
    """
    g = a_hat**2 * y2
    return -s * g / sp.sqrt(dot(s, s) * g + eps**2)


def attitude_control(s1, w_rel, a1, a2, a3, k3, k4, eps):
    """eps_r [N m], pursuer axes (002 eq. 23)."""
    w2 = dot(w_rel, w_rel)
    return (adaptive_term(s1, a1, w2**2, eps) + adaptive_term(s1, a2, w2, eps) + adaptive_term(s1, a3, 1, eps)
            - k3 * s1 / sp.sqrt(dot(s1, s1) + eps**2) - k4 * s1)


def position_control(s2, w_rel, v_rel, r_rel, a4, a5, a6, a7, a8, a9, k7, k8, eps):
    """eps_t [N], pursuer axes (002 eq. 24)."""
    w2, v2, r2 = dot(w_rel, w_rel), dot(v_rel, v_rel), dot(r_rel, r_rel)
    return (adaptive_term(s2, a4, w2 * v2, eps) + adaptive_term(s2, a5, w2 * r2, eps)
            + adaptive_term(s2, a6, w2, eps) + adaptive_term(s2, a7, v2, eps) + adaptive_term(s2, a8, r2, eps)
            + adaptive_term(s2, a9, 1, eps) - k7 * s2 / sp.sqrt(dot(s2, s2) + eps**2) - k8 * s2)


def adaptive_rates(s1, s2, w_rel, v_rel, r_rel, a_hat, beta, gamma):
    """d alpha^_i/dt = beta_i (|s_j| y_i - gamma_i alpha^_i), i = 1..9 (002 eq. 25).

    Regressors y_i: |w~|^2, |w~|, 1 (with |s_1|); |w~||v~|, |w~||r~|, |w~|, |v~|, |r~|, 1 (with
    |s_2|), the bounds of eqs. 21-22.  Eq. 25 as printed omits alpha^_7's law; the one used here,
    beta_7 (|s_2| |v~| - gamma_7 alpha^_7), follows the pattern and the proof (eq. 29 needs it to
    cancel the alpha_7 |s_2| |v~| term of eq. 22).
    """
    def nrm(x):
        return sp.sqrt(dot(x, x))

    ns1, ns2 = nrm(s1), nrm(s2)
    w, v, r = nrm(w_rel), nrm(v_rel), nrm(r_rel)
    y = [ns1 * w**2, ns1 * w, ns1, ns2 * w * v, ns2 * w * r, ns2 * w, ns2 * v, ns2 * r, ns2]
    return sp.Matrix([beta[i] * (y[i] - gamma[i] * a_hat[i]) for i in range(9)])


# =========================================================================== target orbit (paper's simulation)


def semimajor_axis(R_E, r_pa, e):
    """a = (R_E + r_pa) / (1 - e) [m] (002, under eq. 45, corrected).

    Printed ``a = R_E + r_pa / (1 - e)``; the perigee radius is R_E + r_pa = a (1 - e).
    """
    return (R_E + r_pa) / (1 - e)


def target_orbit_radius(a, e, nu):
    """r_t = a (1 - e^2) / (1 + e cos nu) [m] (002 eq. 44)."""
    return a * (1 - e**2) / (1 + e * sp.cos(nu))


def true_anomaly_rates(n, e, nu):
    """(nu_dot, nu_ddot) [rad/s, rad/s^2] with n = sqrt(mu / a^3) (002 eq. 45, corrected sign).

    As printed nu_ddot = +2 n^2 e (1 + e cos nu)^3 sin nu / (1 - e^2)^3; differentiating nu_dot
    gives the opposite sign (nu_dot falls after perigee).
    """
    c = 1 + e * sp.cos(nu)
    return n * c**2 / (1 - e**2) ** sp.Rational(3, 2), -2 * n**2 * e * c**3 * sp.sin(nu) / (1 - e**2) ** 3


# =========================================================================== the design


@dataclass
class C002:
    """002's two anti-saturation adaptive sliding-mode controllers (attitude and position)."""

    name: str = "c002"
    k: Layout = field(default_factory=lambda: Layout("k"))
    xc: Layout = field(default_factory=lambda: Layout("xc"))
    diag: Layout = field(default_factory=lambda: Layout("diag"))

    def __post_init__(self):
        k = self.k
        # gains: 002 Section IV ("The control parameters are selected as follows")
        k.add("k1", 1, "1/s", "eq. 15 attitude surface gain on q~_v (k1 > 1/2)", default=2.0,
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("k2", 1, "rad/s", "eq. 15 weight of tanh(chi_1)", default=0.1,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("kappa1", 1, "N m", "eq. 17 auxiliary damping", default=2.0,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k3", 1, "N m", "eq. 23 unit-vector gain", default=4.0,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k4", 1, "N m s", "eq. 23 linear gain", default=0.5,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k5", 1, "1/s", "eq. 16 position surface gain on r~", default=0.5,
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("k6", 1, "m/s", "eq. 16 weight of tanh(chi_2)", default=0.001,
              bounds=Bounds(0.0, 1e3, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("kappa2", 1, "N", "eq. 18 auxiliary damping", default=2.0,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k7", 1, "N", "eq. 24 unit-vector gain", default=0.5,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("k8", 1, "N s/m", "eq. 24 linear gain", default=20.0,
              bounds=Bounds(0.0, 1e4, why="a feedback gain: >= 0 (a negative one inverts the loop)"))
        k.add("eps", 1, "-", "eqs. 23-24 smoothing constant epsilon (mixed units, as in the paper)",
              default=0.001,
              bounds=Bounds(0.0, 1e3, lo_open=True, why="a smoothing constant, > 0 (it divides)"))
        k.add("beta", 9, "-", "eq. 25 adaptation rates beta_1..9", tuple(str(i) for i in range(1, 10)),
              default=(10, 5, 0.1, 0.01, 0.01, 0.01, 0.001, 0.001, 0.001),
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma", 9, "-", "eq. 25 leakage gamma_1..9", tuple(str(i) for i in range(1, 10)),
              default=(1,) * 9,
              bounds=Bounds(0.0, 1e6, why="a leakage, >= 0"))
        # nominal model used by eqs. 17-18 (002 Table 1: J and m are the pursuer's)
        k.add("J_nom", 3, "kg m^2", "pursuer inertia diagonal used by eq. 17 (Table 1 J)", XYZ,
              default=(21.0, 18.0, 16.0),
              bounds=Bounds(1e-6, 1e10, why="nominal principal moments, as the plant's inertias"))
        k.add("m_nom", 1, "kg", "pursuer mass used by eq. 18 (Table 1 m)", default=95.0,
              bounds=Bounds(1e-2, 1e7, why="a nominal mass, as the plant's masses"))
        k.add("sigma_t", 3, "m", "rendezvous point in target body axes (Section IV delta_r)", XYZ,
              default=(0.0, 5.0, 0.0),
              bounds=Bounds(-1e5, 1e5, why="a position, either sign, within 100 km"))
        # eq. 13 limits.  Printed: "position subsystem +-1 N m, attitude +-100 N m"; taken as
        # swapped (torque 1 N m, force 100 N): see docs/controllers/c002.md
        k.add("tau_max", 1, "N m", "eq. 13 torque limit u_M per axis (attitude)", default=1.0,
              bounds=Bounds(0.0, 1e4, lo_open=True, why="an actuator limit, > 0, as the plant's"))
        k.add("f_max", 1, "N", "eq. 13 force limit u_M per axis (position)", default=100.0,
              bounds=Bounds(0.0, 1e4, lo_open=True, why="an actuator limit, > 0, as the plant's"))

        xc = self.xc
        xc.add("chi1", 3, "-", "eq. 17 attitude auxiliary state, chi_1(0) = 0", XYZ, default=(0, 0, 0))
        xc.add("chi2", 3, "-", "eq. 18 position auxiliary state, chi_2(0) = 0", XYZ, default=(0, 0, 0))
        xc.add("alpha_hat", 9, "-", "eq. 25 adaptive estimates alpha^_1..9 (units of eqs. 21-22), 0 at start",
               tuple(str(i) for i in range(1, 10)), default=(0,) * 9)

        d = self.diag
        d.add("att_err", 1, "rad", "rotation angle of Q~ (chaser relative to target body; shorter way)")
        d.add("q_err", 4, "-", "Q~ = Q_t^-1 (x) Q_p (eq. 1), scalar last, sign as used by the law", XYZW)
        d.add("pos_err", 3, "m", "r~: chaser minus rendezvous point, chaser body axes (eq. 5)", XYZ)
        d.add("rate_err", 3, "rad/s", "w~ = w_p - R w_t, chaser body axes", XYZ)
        d.add("vel_err", 3, "m/s", "v~ (eq. 6), chaser body axes", XYZ)
        d.add("s1", 3, "rad/s", "attitude sliding surface (eq. 15)", XYZ)
        d.add("s2", 3, "m/s", "position sliding surface (eq. 16)", XYZ)
        d.add("eps_r", 3, "N m", "unsaturated torque command (eq. 23), chaser body", XYZ)
        d.add("eps_t", 3, "N", "unsaturated force command (eq. 24), chaser body", XYZ)
        d.add("chi1", 3, "-", "attitude auxiliary state (eq. 17)", XYZ)
        d.add("chi2", 3, "-", "position auxiliary state (eq. 18)", XYZ)
        d.add("alpha_hat", 9, "-", "adaptive estimates (eq. 25)", tuple(str(i) for i in range(1, 10)))

    def law(self, meas, t, p):
        """(cmd, xc_dot, diag): torque sat(eps_r) and force sat(eps_t) in chaser body axes.

        The commands are saturated here with the limits of ``k`` (eq. 13) so that the
        auxiliary systems (eqs. 17-18) see exactly what is commanded; the plant's own limits
        should be the same or wider.
        """
        k, xc = self.k, self.xc
        chi1, chi2, a = xc["chi1"], xc["chi2"], xc["alpha_hat"]
        J = sp.diag(*k["J_nom"])
        sigma = k["sigma_t"]

        q_rel = relative_quaternion(meas["q_t"], meas["q_c"])                 # eq. 1
        R = dcm_pursuer_from_target(q_rel)
        w_rel = relative_angular_velocity(meas["w_c"], R, meas["w_t"])        # under eq. 3
        # eqs. 5-6 with the target's centre as origin: r_p - R r_t = C_{p<-L} r and
        # v_p - R v_t = C_{p<-L} (v + w_L x r) are the measured relative position and inertial
        # relative velocity (w_L = [0, 0, n], LVLH); avoids differencing two orbit radii.
        C_pL = quat_to_dcm(meas["q_cL"]).T
        zero = sp.zeros(3, 1)
        r_rel = relative_position(C_pL * meas["r"], R, zero, sigma)           # eq. 5
        v_in = C_pL * (meas["v"] + skew(sp.Matrix([0, 0, meas["n"]])) * meas["r"])
        v_rel = relative_velocity(v_in, R, zero, meas["w_t"], sigma)           # eq. 6

        s1 = sliding_surface_attitude(w_rel, quat_vec(q_rel), chi1, k["k1"], k["k2"])  # eq. 15
        s2 = sliding_surface_position(v_rel, r_rel, chi2, k["k5"], k["k6"])          # eq. 16
        eps_r = attitude_control(s1, w_rel, a[0], a[1], a[2], k["k3"], k["k4"], k["eps"])  # eq. 23
        eps_t = position_control(s2, w_rel, v_rel, r_rel, *[a[i] for i in range(3, 9)],
                                 k["k7"], k["k8"], k["eps"])                          # eq. 24
        u_r = saturation(eps_r, k["tau_max"])                                 # eq. 13
        u_t = saturation(eps_t, k["f_max"])

        xc_dot = xc.pack({
            "chi1": aux_attitude_rate(chi1, J, k["k2"], k["kappa1"], eps_r, u_r),      # eq. 17
            "chi2": aux_position_rate(chi2, k["m_nom"], k["k6"], k["kappa2"], eps_t, u_t),  # eq. 18
            "alpha_hat": adaptive_rates(s1, s2, w_rel, v_rel, r_rel, a, k["beta"], k["gamma"]),  # eq. 25
        })
        cmd = command_layout().pack({"tau_w": u_r, "F": u_t, "tau_thr": zero})
        att_err = 2 * sp.acos(sp.Min(1, sp.Abs(q_rel[3])))
        diag = self.diag.pack({
            "att_err": att_err, "q_err": q_rel, "pos_err": r_rel, "rate_err": w_rel, "vel_err": v_rel,
            "s1": s1, "s2": s2, "eps_r": eps_r, "eps_t": eps_t, "chi1": chi1, "chi2": chi2, "alpha_hat": a,
        })
        return cmd, xc_dot, diag


DESIGN = C002
