"""Seed 000: adaptive sliding-mode pose controller with adjustable desired acceleration.

Attitude: 000 eqs. 48-56, 66-67, 73-80 on the error to the interface frame (eqs. 15-29), per
chaser body axis j in {x, y, z}.  Translation: 000 eqs. 81-88, 96-101, 105-108, 113-116,
119-122, 127-128 in the target's LVLH frame (eq. 30).  Every equation is one small module-level
function of the paper's variables (SymPy scalars or matrices), so the Lyapunov checker can call
the same functions with abstract symbols; :meth:`C000.law` only composes them from ``meas``.

Table 1 of the paper (the variable change that puts eq. 49 into the form of eq. 48) is lost in
the extraction; it is derived here from eq. 49 (with eq. 61 for the x axis, whose eq. 49-a is
printed as a second copy of the y equation) in :func:`table1_attitude_axis`:

    omega_e_dot_j + sum_{i=1..6} a_ji f_ji = b_j T_cj + d_j,   (j, k, l) cyclic in (x, y, z)

    i | a_ji (unknown parameter)            | f_ji (measured regressor)
    1 | 1 (known)                           | (omega_c x omega_e)_j = w_ck w_el - w_cl w_ek
    2 | (I_cl - I_ck) / I_cj                | w_ck w_cl
    3 | 1 / I_cj                            | (omega_c x h_rw)_j = w_ck h_l - w_cl h_k
    4 | -(I_tz - I_ty) / I_tx              | c_j1 delta_2 delta_3
    5 | -(I_tx - I_tz) / I_ty              | c_j2 delta_1 delta_3
    6 | -(I_ty - I_tx) / I_tz              | c_j3 delta_1 delta_2
      | b_j = 1 / I_cj,  u_j = T_cj,  d_j = M_tot_j / I_cj - (C_t^c I_t^-1 M_tot_t)_j

with c_jm the entries of C_t^c (eq. 20) and delta = (C_t^c)^-1 (omega_c - omega_e) = omega_t in
target axes (eq. 50).  The estimates of the law are a_hat_ji -> a_ji / b_j and b_hat_j -> 1 / b_j.

Corrections of the printed equations (each also beside its function; summary in
docs/controllers/c000.md):

* eq. 49-a is a duplicate of the y equation, and eq. 49's right side prints I_ty^-1 T_cy for
  I_cy^-1 T_cy; eq. 49 uses c_ij as entries of C_t^c while eq. 50 says they are entries of
  (C_t^c)^-1 -- they are the rows of C_t^c in eq. 49 and of its transpose in eq. 50.
* eq. 52 (and 79, 80, 84, 106, 119) prints S_aug = s - d sign(s); the text ("inside the boundary
  layer S_aug = 0") is Slotine's s_delta = s - d sat(s/d), implemented.
* eq. 55 adds the "known" a_x1 f_x1 (rad/s^2) to a torque: the proof (eqs. 62-64) needs
  a_x1 f_x1 / b_x = I_cx f_x1.  Since I_cx is the uncertain parameter, it is estimated with eq. 66's
  own law extended to i = 1 (switch ``adapt_a1``; 0 holds it at its nominal initial value).
* eq. 81 leaves the known term -mu/r_c^2 out of the law (eq. 86) and into the bound of eq. 104,
  D_xx >= |-mu/r_c^2 + A_dx| ~ 8.7 m/s^2 in LEO, i.e. an ~870 N switching force for 1 N
  thrusters.  It is grouped with mu f_xx2 (the same parameter mu / b), so the regressor is
  f_xx2 - 1/r_c^2, which is small (the two ~8.7 m/s^2 terms cancel inside the regressor).
* eqs. 89, 109, 123 are not positive definite (the parameter errors of the alpha / a estimates
  enter with a minus sign); with a positive-definite V the adaptation laws of those estimates
  (eqs. 96-100, 113-114, 127) change sign: theta_dot = +gamma phi S_aug.  Eq. 115 (the term
  printed with a plus sign in eq. 109) keeps its sign.
* eqs. 101, 116, 128 give three different laws for one h_hat: one estimate per axis here.
* adaptation gains: the paper's laws have unit gains, which are not dimensionally consistent with
  the Lyapunov function (S^2 in 1/s^2 or m^2/s^2 vs b (a_hat - a/b)^2 in kg m^2 or kg); gains
  gamma (default 1 = the printed laws) scale them.

The error variable: eq. 54 defines e_x = q_1 - q_1d (a quaternion component), but the proof
(eqs. 59-60) writes s_dot = e_ddot + lambda_0 e_dot = omega_e_dot - omega_e_dot_d + lambda_0 e_dot,
i.e. it takes the "e_dot" of eq. 53 to be the rate error omega_e, while d/dt q_ev =
1/2 (q_e4 omega_e + q_ev x omega_e) (eq. 24) is not omega_e and q_ev_ddot is not omega_e_dot.
Implemented so that the proof's identity holds on the spacecraft equations (tests/test_c000.py):

    e = sgn(q_e4) q_ev (q_d = identity),  s = omega_e + lambda_0 e  (eq. 53 with omega_e for e_dot),
    u_1 = -omega_e_dot_d + lambda_0 e_dot  with e_dot = sgn(q_e4) d/dt q_ev from eq. 24 (eq. 56),

so that s_dot = omega_e_dot + lambda_0 e_dot exactly.  On s = 0, |q_ev| decays at rate
lambda_0 |q_e4| / 2.  The sign picks the shorter rotation (switch ``shortest``; 0 = the paper's
literal q_ev, which unwinds when q_e4 < 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..physics.layout import XYZ, Bounds, Layout
from ..physics.relative_attitude import attitude_error_rate
from ..physics.rotations import quat_to_dcm, quat_vec
from . import command_layout

AXES = (0, 1, 2)
#: nominal values of the paper's controller model ("Simulation": m_c, I_c diagonal, I_t diagonal)
M_NOM = 100.0
I_C_NOM = (11.0, 14.0, 13.0)
I_T_NOM = (3336.0, 3184.0, 2423.0)
MU_EARTH = 3.986004418e14


def _cyc(j):
    """(k, l) such that (j, k, l) is a cyclic permutation of (0, 1, 2)."""
    return (j + 1) % 3, (j + 2) % 3


# ============================================================== relative attitude model

def dcm_target_to_chaser(q_e):
    """C_t^c = C_{c<-t} = C_{c<-i} C_{i<-t} (000 eqs. 15, 19-20), from q_e = q_{c/i}.

    C_{c<-i} = quat_to_dcm(q_e)^T; C_{i<-t} = diag(1, -1, -1) (eq. 15).
    """
    return quat_to_dcm(q_e).T * sp.diag(1, -1, -1)


def target_rate_in_target_axes(C_tc, omega_c, omega_e):
    """delta = (C_t^c)^-1 (omega_c - omega_e) [rad/s], target axes (000 eq. 50).

    omega_c - omega_e = C_t^c omega_t (eq. 17 with eq. 18), so delta is the target's rate.
    eq. 50 writes delta_i = sum_j c_ij (...) with c_ij "entries of (C_t^c)^-1": correct here.
    """
    return C_tc.T * (omega_c - omega_e)


def table1_attitude_axis(j, I_c, I_t, omega_c, omega_e, h_rw, C_tc, delta):
    """Derived Table 1, axis j (0, 1, 2): lists a_j (6), f_j (6) and b_j of eq. 48 for eq. 49.

    ``I_c``, ``I_t``: diagonal inertias (3 entries each) [kg m^2] -- the paper's model assumes
    principal axes.  ``C_tc``: C_t^c (eq. 20); in eq. 49 the c_jm are the entries of row j of
    C_t^c (eq. 49 as printed says they are entries of its inverse, which is eq. 50's matrix).
    Units: a_j1 [-], f_j1 [rad/s^2]; a_j2 [-], f_j2 [rad^2/s^2]; a_j3 [1/(kg m^2)], f_j3 [N m];
    a_j4..6 [-], f_j4..6 [rad^2/s^2]; b_j [1/(kg m^2)].
    """
    k, l = _cyc(j)
    wc, we, h = omega_c, omega_e, h_rw
    d1, d2, d3 = delta
    a = [
        sp.Integer(1),
        (I_c[l] - I_c[k]) / I_c[j],
        1 / I_c[j],
        -(I_t[2] - I_t[1]) / I_t[0],
        -(I_t[0] - I_t[2]) / I_t[1],
        -(I_t[1] - I_t[0]) / I_t[2],
    ]
    f = [
        wc[k] * we[l] - wc[l] * we[k],
        wc[k] * wc[l],
        wc[k] * h[l] - wc[l] * h[k],
        C_tc[j, 0] * d2 * d3,
        C_tc[j, 1] * d1 * d3,
        C_tc[j, 2] * d1 * d2,
    ]
    return a, f, 1 / I_c[j]


def attitude_disturbance_axis(j, I_c, I_t, C_tc, M_c, M_t):
    """d_j = M_tot_j / I_cj - (C_t^c I_t^-1 M_tot_t)_j [rad/s^2] (000 eqs. 49, 51).

    eq. 49 prints (c_j1 M_t1 + c_j2 M_t2 + c_j3 M_t3) I_tj^-1 and eq. 51 uses row 3 for the x axis;
    eq. 26 with eq. 10 gives sum_m c_jm M_tm / I_tm (docs/errata.md, eqs. 27/29).
    """
    return M_c[j] / I_c[j] - sum(C_tc[j, m] * M_t[m] / I_t[m] for m in AXES)


def attitude_model_axis(a, f, b, u, d):
    """omega_e_dot_j = -sum_i a_ji f_ji + b_j u_j + d_j [rad/s^2] (000 eq. 48 with Table 1 = eq. 49)."""
    return -sum(ai * fi for ai, fi in zip(a, f, strict=True)) + b * u + d


def attitude_model(q_e, omega_e, omega_c, h_rw, I_c, I_t, T_c, M_c, M_t):
    """omega_e_dot (3) of 000 eq. 49 (all three axes) through the derived Table 1 [rad/s^2]."""
    C_tc = dcm_target_to_chaser(q_e)
    delta = target_rate_in_target_axes(C_tc, omega_c, omega_e)
    out = []
    for j in AXES:
        a, f, b = table1_attitude_axis(j, I_c, I_t, omega_c, omega_e, h_rw, C_tc, delta)
        out.append(attitude_model_axis(a, f, b, T_c[j], attitude_disturbance_axis(j, I_c, I_t, C_tc, M_c, M_t)))
    return sp.Matrix(out)


# ============================================================== sliding-mode law, per axis (abstract)

def tracking_error(x, x_d):
    """e = x - x_d (000 eq. 54 for the attitude, e_xx = x - x_d for the translation)."""
    return x - x_d


def sliding_surface(e_dot, e, lam):
    """s = e_dot + lambda_0 e (000 eqs. 53, 85, 107, 120).

    Attitude: ``e_dot`` is the rate error omega_e (whose derivative is eq. 49's omega_e_dot), ``e`` is
    sgn(q_e4) q_ev (module doc); translation: v and r - r_goal.
    """
    return e_dot + lam * e


def boundary_layer_surface(s, d):
    """S_aug = s - d sat(s/d) (000 eqs. 52, 79, 80, 84, 106, 119, corrected).

    Printed: s - d sign(s), which inside |s| < d is nonzero and of the opposite sign of s; the
    text says S_aug = 0 inside the layer and S_aug_dot = s_dot outside: Slotine's s_delta.
    Written as max(s - d, 0) + min(s + d, 0) (d >= 0), which allows d = 0 (then S_aug = s) and keeps
    s out of Piecewise conditions (s itself may contain the Piecewise of the shorter rotation).
    """
    return sp.Max(s - d, 0) + sp.Min(s + d, 0)


def u1_term(acc_d, lam, e_dot):
    """u_1 = -acc_d + lambda_0 e_dot (000 eqs. 56, 88, and u_1yy, 122).

    ``acc_d``: the user-set desired (relative) acceleration: omega_e_dot_d [rad/s^2] or x_ddot_d [m/s^2].
    """
    return -acc_d + lam * e_dot


def attitude_control_axis(b_hat, u1, D, eps, s, a_hat, f):
    """u_2j = -b_hat_j [u_1j + (D_j + eps_j) sign(s_j)] + sum_{i=1..6} a_hat_ji f_ji [N m] (000 eqs. 55, 73, 74).

    Printed: "+ a_x1 f_x1 + sum_{i=2..6} a_hat f"; a_x1 f_x1 is an acceleration, and the proof
    (eqs. 62-64) needs a_x1 f_x1 / b_x: that is a_hat_x1 here (estimated or held, see module doc).
    """
    return -b_hat * (u1 + (D + eps) * sp.sign(s)) + sum(ai * fi for ai, fi in zip(a_hat, f, strict=True))


def attitude_param_rate(f, S_aug, gamma):
    """a_hat_ji_dot = -gamma f_ji S_aug_j (000 eqs. 66, 75, 77; gamma = 1 as printed)."""
    return -gamma * f * S_aug


def gain_estimate_rate(u1, D, eps, s, S_aug, gamma):
    """b_hat_dot (000 eqs. 67, 76, 78) and h_hat_dot (eqs. 101, 116, 128): gamma (u_1 + (D + eps) sign(s)) S_aug."""
    return gamma * (u1 + (D + eps) * sp.sign(s)) * S_aug


# ============================================================== relative translation model

def chaser_orbit_radius(r_t, r_e):
    """r_c = |r_t X_L + r_e| [m] (000 eq. 30's r_c; available from GPS in the paper)."""
    x, y, z = r_e
    return sp.sqrt((r_t + x) ** 2 + y**2 + z**2)


def f_xx1(r_e):
    """f_xx1 = |r_e| [m] (000 eq. 82)."""
    return sp.sqrt(r_e[0] ** 2 + r_e[1] ** 2 + r_e[2] ** 2)


def f_xx2(r_c, r_e):
    """f_xx2 = 1 / (r_c - |r_e|)^2 [1/m^2] (000 eq. 83).

    It is mu / r_t^2 / mu under the paper's scalar substitution r_t = r_c - |r_e| (exact only for a
    radial offset, see tests); with eq. 81's -mu (r_c - |r_e| + x)/r_c^3 the x row departs from
    eq. 30 by ~3 mu (|r_e| - x) / r^3, below 1e-3 m/s^2 within 100 m in LEO (tests/test_c000.py).
    """
    return 1 / (r_c - f_xx1(r_e)) ** 2


def translation_model(r_e, v_e, n, n_dot, r_c, mu, a_ctrl, a_d):
    """r_e_ddot [m/s^2], LVLH (000 eqs. 81, 105 and eq. 30's z row), with r_t = r_c - |r_e|.

    x: 2 n y_dot + (n^2 - mu/r_c^3) x + n_dot y - mu/r_c^2 + mu f_xx2 + mu/r_c^3 f_xx1 + b F_x + a_dx
    y: alpha_yy1 x_dot + alpha_yy2 y - alpha_yy3 x + b F_y + a_dy (alpha = -2n, n^2 - mu/r_c^3, n_dot)
    z: -mu/r_c^3 z + b F_z + a_dz.   ``a_ctrl`` = b F = C_c^LVLH F_c / m_c (eq. 87), LVLH.
    """
    x, y, z = r_e
    xd, yd, _ = v_e
    k3 = mu / r_c**3
    theta = ([2 * n, n**2 - k3, n_dot, k3, mu], [-2 * n, n**2 - k3, n_dot], [-k3])
    phi = ([yd, x, y, f_xx1(r_e), f_xx2(r_c, r_e)], [xd, y, -x], [z])
    known = (-mu / r_c**2, 0, 0)
    return sp.Matrix([known[j] + translation_model_axis(theta[j], phi[j], 1, a_ctrl[j], a_d[j]) for j in AXES])


def translation_model_axis(theta, phi, b, u, d):
    """r_e_ddot_j = sum_i theta_ji phi_ji + b u_j + d_j [m/s^2] (000 eqs. 81, 105, 30-z: the abstract
    per-axis form of the translation proof; ``b u`` = C_c^LVLH F_c / m_c, eq. 87)."""
    return sum(ti * pi for ti, pi in zip(theta, phi, strict=True)) + b * u + d


def translation_regressors(r_e, v_e, n, n_dot, r_c, mu):
    """(theta, phi) per LVLH axis: r_e_ddot_j = sum_i theta_ji phi_ji + b F_j + a_dj (000 eqs. 81-83, 105, 121).

    x: theta = (alpha_xx1, alpha_xx2, alpha_xx3, a_xx1, a_xx2) = (2n, n^2 - mu/r_c^3, n_dot, mu/r_c^3, mu),
       phi = (y_dot, x, y, f_xx1, f_xx2 - 1/r_c^2)  -- the known -mu/r_c^2 of eq. 81 grouped with
       mu f_xx2 (correction, module doc);
    y: theta = (alpha_yy1, alpha_yy2, alpha_yy3) = (-2n, n^2 - mu/r_c^3, n_dot), phi = (x_dot, y, -x)
       (eq. 105's "- alpha_yy3 x" as the regressor -x);
    z: theta = (a_zz1,) = (-mu/r_c^3,), phi = (z,).
    The estimates of the law are theta_hat -> theta / b = m_c theta.
    """
    x, y, z = r_e
    xd, yd, _ = v_e
    k3 = mu / r_c**3
    theta = [
        [2 * n, n**2 - k3, n_dot, k3, mu],
        [-2 * n, n**2 - k3, n_dot],
        [-k3],
    ]
    phi = [
        [yd, x, y, f_xx1(r_e), f_xx2(r_c, r_e) - 1 / r_c**2],
        [xd, y, -x],
        [z],
    ]
    return theta, phi


def translation_control_axis(h_hat, u1, D, eps, s, theta_hat, phi):
    """u_2jj = -h_hat_j [u_1jj + (D_jj + eps_jj) sign(s_jj)] - sum_i theta_hat_ji phi_ji [N], LVLH.

    000 eqs. 86, 108, 121.
    eq. 86 prints b_hat^-1 for h_hat (h = 1/b = m_c, eq. 89).
    """
    return -h_hat * (u1 + (D + eps) * sp.sign(s)) - sum(ti * pi for ti, pi in zip(theta_hat, phi, strict=True))


def translation_param_rate(phi, S_aug, gamma):
    """theta_hat_ji_dot = +gamma phi_ji S_aug_j (000 eqs. 96-100, 113-115, 127, sign corrected).

    Printed: -phi S_aug (eqs. 96-100, 113, 114, 127), derived from the indefinite V of eqs. 89,
    109, 123; a positive-definite V = S^2/2 + b/(2 gamma) sum (theta_hat - theta/b)^2 gives +.
    With phi_yy3 = -x, eq. 115's printed -x S_aug is this same law (its V term was positive).
    """
    return gamma * phi * S_aug


def lvlh_to_body_force(q_cL, F_L):
    """F_body = (C_c^LVLH)^T F_LVLH [N] (000 eq. 87's b = C_c^LVLH / m_c, inverted for the thrusters).

    ``q_cL`` = q_{c/L}, so quat_to_dcm(q_cL) = C_{L<-c} = C_c^LVLH and the plant's LVLH acceleration
    is C_c^LVLH F_body / m_c = F_L / m_c.
    """
    return quat_to_dcm(q_cL).T * F_L


# ============================================================== the design

def _initial_attitude_estimates(I_c=I_C_NOM, I_t=I_T_NOM):
    """Nominal a_hat_ji = a_ji / b_j (i = 1..6) and b_hat_j = 1/b_j = I_cj, from Table 1."""
    out = []
    for j in AXES:
        k, l = _cyc(j)
        a = [1.0, (I_c[l] - I_c[k]) / I_c[j], 1 / I_c[j], -(I_t[2] - I_t[1]) / I_t[0],
             -(I_t[0] - I_t[2]) / I_t[1], -(I_t[1] - I_t[0]) / I_t[2]]
        out.append(([ai * I_c[j] for ai in a], I_c[j]))
    return out


TRANSLATION_PARAMS = (("alpha_xx1", "alpha_xx2", "alpha_xx3", "a_xx1", "a_xx2"),
                      ("alpha_yy1", "alpha_yy2", "alpha_yy3"), ("a_zz1",))
TRANSLATION_UNITS = (("kg/s", "kg/s^2", "kg/s^2", "kg/s^2", "kg m^3/s^2"), ("kg/s", "kg/s^2", "kg/s^2"),
                     ("kg/s^2",))


@dataclass
class C000:
    """000's adaptive sliding-mode pose controller (attitude: interface frame; translation: LVLH)."""

    name: str = "c000"
    k: Layout = field(default_factory=lambda: Layout("k"))
    xc: Layout = field(default_factory=lambda: Layout("xc"))
    diag: Layout = field(default_factory=lambda: Layout("diag"))

    def __post_init__(self):
        k = self.k
        # --- attitude (Table 2 lost: chosen, see docs/controllers/c000.md)
        k.add("lam_att", 1, "1/s", "lambda_0 of the attitude surfaces (eqs. 53, 79, 80)", default=0.2,
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("D_att", 3, "rad/s^2", "disturbance bound D_j (eq. 51)", XYZ, default=(0.0075,) * 3,
              bounds=Bounds(0.0, 1e3, why="a disturbance bound, >= 0"))
        k.add("eps_att", 3, "rad/s^2", "reaching margin eps_j (eq. 55)", XYZ, default=(0.0075,) * 3,
              bounds=Bounds(0.0, 1e3, why="a reaching margin, >= 0"))
        k.add("d_att", 3, "rad/s", "boundary-layer width d_j (eq. 52)", XYZ, default=(0.002,) * 3,
              bounds=Bounds(0.0, 1e3, lo_open=True, why="a boundary-layer width, > 0 (it divides)"))
        k.add("wdot_d", 3, "rad/s^2", "user-set desired relative angular acceleration (eq. 56), chaser axes",
              XYZ, default=(0, 0, 0),
              bounds=Bounds(-1e3, 1e3, why="either sign, within 1e3"))
        k.add("gamma_a", 1, "-", "adaptation gain of a_hat (eq. 66; 1 = printed)", default=1.0,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma_b", 1, "-", "adaptation gain of b_hat (eq. 67; 1 = printed)", default=1.0,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("adapt_a1", 1, "-", "1: estimate a_x1/b_x = I_cx by eq. 66; 0: hold it (paper: 'known')",
              default=1.0,
              bounds=Bounds(0.0, 1.0, why="a 0/1 switch (blends in between)"))
        k.add("shortest", 1, "-", "1: e = sgn(q_e4) q_ev (shorter rotation); 0: e = q_ev (eq. 54)", default=1.0,
              bounds=Bounds(0.0, 1.0, why="a 0/1 switch (blends in between)"))
        # --- translation
        k.add("lam_pos", 1, "1/s", "lambda_0 of the translation surfaces (eqs. 85, 107, 120)", default=0.03,
              bounds=Bounds(0.0, 1e3, per_step=1.0, why="a rate >= 0 the step must resolve: value x dt <= 1"))
        k.add("D_pos", 3, "m/s^2", "disturbance bound D_jj (eqs. 104, 118)", XYZ, default=(0.02,) * 3,
              bounds=Bounds(0.0, 1e3, why="a disturbance bound, >= 0"))
        k.add("eps_pos", 3, "m/s^2", "reaching margin eps_jj", XYZ, default=(0.02,) * 3,
              bounds=Bounds(0.0, 1e3, why="a reaching margin, >= 0"))
        k.add("d_pos", 3, "m/s", "boundary-layer width d_jj (eqs. 84, 106, 119)", XYZ, default=(0.01,) * 3,
              bounds=Bounds(0.0, 1e3, lo_open=True, why="a boundary-layer width, > 0 (it divides)"))
        k.add("acc_d", 3, "m/s^2", "user-set desired relative acceleration x_ddot_d (eqs. 88, 122), LVLH", XYZ,
              default=(0, 0, 0),
              bounds=Bounds(-1e3, 1e3, why="either sign, within 1e3"))
        k.add("acc_d_on", 1, "-", "1: feed wdot_d and acc_d into u_1 (eqs. 56, 88); 0: off", default=1.0,
              bounds=Bounds(0.0, 1.0, why="a 0/1 switch (blends in between)"))
        k.add("gamma_theta", 1, "-", "adaptation gain of alpha_hat, a_hat (eqs. 96-100...; 1 = printed)",
              default=1e-8,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("gamma_h", 1, "-", "adaptation gain of h_hat (eqs. 101, 116, 128; 1 = printed)", default=1.0,
              bounds=Bounds(0.0, 1e6, why="an adaptation rate: >= 0 (a negative one unlearns)"))
        k.add("r_goal", 3, "m", "goal relative position, LVLH", XYZ, default=(0, 0, 0),
              bounds=Bounds(-1e5, 1e5, why="a position, either sign, within 100 km"))
        # --- nominal model (initial estimates, see xc0)
        k.add("m_nom", 1, "kg", "nominal chaser mass (paper: 100 kg)", default=M_NOM,
              bounds=Bounds(1e-2, 1e7, why="a nominal mass, as the plant's masses"))
        k.add("I_c_nom", 3, "kg m^2", "nominal chaser principal inertia (paper: diag 11, 14, 13)", XYZ,
              default=I_C_NOM,
              bounds=Bounds(1e-6, 1e10, why="nominal principal moments, as the plant's inertias"))
        k.add("I_t_nom", 3, "kg m^2", "nominal target principal inertia (paper: diag 3336, 3184, 2423)", XYZ,
              default=I_T_NOM,
              bounds=Bounds(1e-6, 1e10, why="nominal principal moments, as the plant's inertias"))

        xc = self.xc
        init = _initial_attitude_estimates()
        for j, ax in enumerate(XYZ):
            a0, b0 = init[j]
            xc.add(f"a_hat_{ax}", 6, "-", f"a_hat_{ax}i = a_{ax}i / b_{ax}, i = 1..6 (Table 1; units: kg m^2 for "
                   "i = 1, 2, 4-6, - for i = 3)", tuple(str(i) for i in range(1, 7)), default=a0)
            xc.add(f"b_hat_{ax}", 1, "kg m^2", f"b_hat_{ax} -> 1/b_{ax} = I_c{ax} (eq. 67)", default=b0)
        for j, ax in enumerate(XYZ):
            names = TRANSLATION_PARAMS[j]
            xc.add(f"theta_{ax}{ax}", len(names), "mixed", f"m_c x ({', '.join(names)}), units "
                   f"{', '.join(TRANSLATION_UNITS[j])}", names, default=self._theta0()[j])
            xc.add(f"h_hat_{ax}{ax}", 1, "kg", f"h_hat -> 1/b = m_c, {ax} axis (eq. {(101, 116, 128)[j]})",
                   default=M_NOM)

        dg = self.diag
        dg.add("att_err", 1, "rad", "rotation angle from the chaser body to the interface frame")
        dg.add("q_err", 4, "-", "q_e (eq. 22), sign chosen so that w >= 0 when shortest = 1", ("x", "y", "z", "w"))
        dg.add("pos_err", 3, "m", "r - r_goal, LVLH", XYZ)
        dg.add("rate_err", 3, "rad/s", "omega_e (eq. 17), chaser axes", XYZ)
        dg.add("vel_err", 3, "m/s", "v (LVLH-frame derivative), LVLH", XYZ)
        dg.add("s_att", 3, "rad/s", "attitude sliding surface s_j (eq. 53)", XYZ)
        dg.add("S_aug_att", 3, "rad/s", "attitude S_aug_j (eq. 52)", XYZ)
        dg.add("s_pos", 3, "m/s", "translation sliding surface s_jj (eq. 85)", XYZ)
        dg.add("S_aug_pos", 3, "m/s", "translation S_aug_jj (eq. 84)", XYZ)
        dg.add("b_hat", 3, "kg m^2", "b_hat_j (estimates I_cj)", XYZ)
        dg.add("h_hat", 3, "kg", "h_hat_jj (estimates m_c)", XYZ)
        dg.add("a_hat_x", 6, "-", "a_hat_xi, i = 1..6", tuple(str(i) for i in range(1, 7)))
        dg.add("a_hat_y", 6, "-", "a_hat_yi, i = 1..6", tuple(str(i) for i in range(1, 7)))
        dg.add("a_hat_z", 6, "-", "a_hat_zi, i = 1..6", tuple(str(i) for i in range(1, 7)))
        dg.add("theta_xx", 5, "mixed", "m_c x (alpha_xx1..3, a_xx1, a_xx2) estimates", TRANSLATION_PARAMS[0])
        dg.add("theta_yy", 3, "mixed", "m_c x (alpha_yy1..3) estimates", TRANSLATION_PARAMS[1])
        dg.add("theta_zz", 1, "kg/s^2", "m_c x a_zz1 estimate")
        dg.add("tau_cmd", 3, "N m", "attitude control u_2 (eqs. 55, 73, 74), chaser body", XYZ)
        dg.add("F_lvlh", 3, "N", "translation control u_2 (eqs. 86, 108, 121), LVLH", XYZ)

    @staticmethod
    def _theta0(m=M_NOM):
        """Default initial translation estimates: m0 x theta with the orbit terms zero (set by xc0).

        a_xx2 / b = m mu is orbit-independent (its regressor is tiny, so it barely adapts).
        """
        return ((0.0, 0.0, 0.0, 0.0, m * MU_EARTH), (0.0, 0.0, 0.0), (0.0,))

    # ------------------------------------------------------------------ law
    def law(self, meas, t, p):
        """(cmd, xc_dot, diag) as SymPy column matrices."""
        k, xc = self.k, self.xc
        q_e, w_e, w_c, h_rw = meas["q_e"], meas["w_e"], meas["w_c"], meas["h_rw"]
        r, v = meas["r"], meas["v"]
        n, n_dot, r_t = meas["n"], meas["n_dot"], meas["r_t"]
        on = k["acc_d_on"]

        # ---- attitude, per chaser axis (eqs. 48-56, 66-67, 73-80)
        sgn4 = k["shortest"] * sp.Piecewise((-1, q_e[3] < 0), (1, True)) + (1 - k["shortest"])
        e_att = tracking_error(sgn4 * quat_vec(q_e), sp.zeros(3, 1))  # q_d: identity (synchronised)
        edot_att = sgn4 * quat_vec(attitude_error_rate(q_e, w_e))  # d/dt e (eq. 24), for u_1 (module doc)
        C_tc = dcm_target_to_chaser(q_e)
        delta = target_rate_in_target_axes(C_tc, w_c, w_e)
        tau, s_a, S_a, xdot_a = [], [], [], {}
        for j, ax in enumerate(XYZ):
            _, f, _ = table1_attitude_axis(j, k["I_c_nom"], k["I_t_nom"], w_c, w_e, h_rw, C_tc, delta)
            a_hat, b_hat = xc[f"a_hat_{ax}"], xc[f"b_hat_{ax}"]
            s = sliding_surface(w_e[j], e_att[j], k["lam_att"])  # omega_e in the place of e_dot (module doc)
            S = boundary_layer_surface(s, k["d_att"][j])
            u1 = u1_term(on * k["wdot_d"][j], k["lam_att"], edot_att[j])
            tau.append(attitude_control_axis(b_hat, u1, k["D_att"][j], k["eps_att"][j], s, list(a_hat), f))
            rates = [attitude_param_rate(fi, S, k["gamma_a"]) for fi in f]
            rates[0] = k["adapt_a1"] * rates[0]
            xdot_a[f"a_hat_{ax}"] = sp.Matrix(rates)
            xdot_a[f"b_hat_{ax}"] = gain_estimate_rate(u1, k["D_att"][j], k["eps_att"][j], s, S, k["gamma_b"])
            s_a.append(s)
            S_a.append(S)
        tau = sp.Matrix(tau)

        # ---- translation, per LVLH axis (eqs. 81-88, 96-101, 105-108, 113-116, 119-122, 127-128)
        r_c = chaser_orbit_radius(r_t, r)
        mu = p["mu"] * p["gravity_on"]  # free space (gravity_on = 0): no gravity terms
        _, phi = translation_regressors(r, v, n, n_dot, r_c, mu)
        e_pos = tracking_error(r, k["r_goal"])
        F_L, s_p, S_p, xdot_p = [], [], [], {}
        for j, ax in enumerate(XYZ):
            th, h_hat = xc[f"theta_{ax}{ax}"], xc[f"h_hat_{ax}{ax}"]
            th = [th] if not isinstance(th, sp.MatrixBase) else list(th)
            s = sliding_surface(v[j], e_pos[j], k["lam_pos"])
            S = boundary_layer_surface(s, k["d_pos"][j])
            u1 = u1_term(on * k["acc_d"][j], k["lam_pos"], v[j])
            F_L.append(translation_control_axis(h_hat, u1, k["D_pos"][j], k["eps_pos"][j], s, th, phi[j]))
            xdot_p[f"theta_{ax}{ax}"] = sp.Matrix([translation_param_rate(ph, S, k["gamma_theta"]) for ph in phi[j]])
            xdot_p[f"h_hat_{ax}{ax}"] = gain_estimate_rate(u1, k["D_pos"][j], k["eps_pos"][j], s, S, k["gamma_h"])
            s_p.append(s)
            S_p.append(S)
        F_L = sp.Matrix(F_L)
        # b = C_c^LVLH / m_c (eq. 87): the rotation is known, the force is commanded in LVLH and
        # rotated into the chaser body for the thrusters.
        F_body = lvlh_to_body_force(meas["q_cL"], F_L)

        cmd = command_layout().pack({"tau_w": tau, "F": F_body, "tau_thr": sp.zeros(3, 1)})
        xc_dot = xc.pack({**xdot_a, **xdot_p})
        q_err = sgn4 * q_e
        diag = self.diag.pack({
            "att_err": 2 * sp.acos(sp.Min(1, sp.Abs(q_e[3]))),
            "q_err": q_err, "pos_err": e_pos, "rate_err": w_e, "vel_err": v,
            "s_att": sp.Matrix(s_a), "S_aug_att": sp.Matrix(S_a),
            "s_pos": sp.Matrix(s_p), "S_aug_pos": sp.Matrix(S_p),
            "b_hat": sp.Matrix([xc[f"b_hat_{ax}"] for ax in XYZ]),
            "h_hat": sp.Matrix([xc[f"h_hat_{ax}{ax}"] for ax in XYZ]),
            "a_hat_x": xc["a_hat_x"], "a_hat_y": xc["a_hat_y"], "a_hat_z": xc["a_hat_z"],
            "theta_xx": xc["theta_xx"], "theta_yy": xc["theta_yy"], "theta_zz": xc["theta_zz"],
            "tau_cmd": tau, "F_lvlh": F_L,
        })
        return cmd, xc_dot, diag

    # ------------------------------------------------------------------ initial estimates
    def xc0(self, meas, p):
        """Initial estimates from the first measurement and the nominal model in ``k``.

        Attitude: a_hat_ji = a_ji / b_j and b_hat_j = I_cj of Table 1 with I_c_nom, I_t_nom.
        Translation: theta_hat = m_nom theta(t = 0) (n, n_dot, r_c measured), h_hat = m_nom.
        """
        k = self.k
        I_c, I_t, m = k["I_c_nom"], k["I_t_nom"], k["m_nom"]
        vals = {}
        for j, ax in enumerate(XYZ):
            a, _, b = table1_attitude_axis(j, I_c, I_t, sp.zeros(3, 1), sp.zeros(3, 1), sp.zeros(3, 1),
                                           sp.eye(3), sp.zeros(3, 1))
            vals[f"a_hat_{ax}"] = sp.Matrix([ai / b for ai in a])
            vals[f"b_hat_{ax}"] = 1 / b
        r, v = meas["r"], meas["v"]
        r_c = chaser_orbit_radius(meas["r_t"], r)
        theta, _ = translation_regressors(r, v, meas["n"], meas["n_dot"], r_c, p["mu"] * p["gravity_on"])
        for j, ax in enumerate(XYZ):
            vals[f"theta_{ax}{ax}"] = sp.Matrix([m * th for th in theta[j]])
            vals[f"h_hat_{ax}{ax}"] = m
        return self.xc.pack(vals)


DESIGN = C000

