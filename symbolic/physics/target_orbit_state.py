"""The target's own orbit as a state: its LVLH frame, frame rate and frame acceleration from the
propagated position and velocity (rpo's full plant; 000 uses a Keplerian target, :mod:`.orbit`).

The target's ECI position r and velocity v are integrated with its full acceleration
a = -mu r / |r|^3 + a_p (a_p: J2 and drag, the same environment as the chaser's).  The LVLH
frame of that state (X_L = r / |r|, Z_L = h / |h| with h = r x v, Y_L = Z_L x X_L, as in
:mod:`.orbit`) turns relative to ECI with (derivation in ``docs/full_plant.md``)

    omega_L = [r a_pz / h, 0, h / r^2]                    (LVLH components)

where a_pz = a_p . Z_L is the perturbation's orbit-normal component (the in-plane
perturbation changes |h| but not the plane; the normal one tilts the plane about X_L), and

    d|h|/dt = r a_py,   d(h / r^2)/dt = r a_py / r^2 - 2 h r_dot / r^3,
    d(r a_pz / h)/dt = r_dot a_pz / h + r (da_p/dt . Z_L - r a_pz a_py / h) / h - r a_pz r a_py / h^2

with a_py = a_p . Y_L and da_p/dt = (d a_p / d r) v + (d a_p / d v) a, the perturbation's
rate along the trajectory (its Jacobians are taken symbolically from the same a_p expression,
so no derivative is typed by hand).  With a_p = 0 these are 000's Keplerian nu_dot and nu_ddot
(:func:`.orbit.lvlh_rate`, :func:`.orbit.lvlh_rate_dot`) and omega_Lx = 0.
"""

from __future__ import annotations

import sympy as sp

from .rotations import cross, dot, norm, vec


def lvlh_basis(r_eci, v_eci) -> sp.Matrix:
    """C_{ECI<-LVLH} of the orbit state: columns X_L = r / |r|, Y_L = Z_L x X_L, Z_L = h / |h|."""
    h = cross(r_eci, v_eci)
    x_l = r_eci / norm(r_eci)
    z_l = h / norm(h)
    return sp.Matrix.hstack(x_l, cross(z_l, x_l), z_l)


def lvlh_rates(r_eci, v_eci, a_p, a_p_rate):
    """(omega_L, omega_L_dot) of the LVLH frame of (r, v) relative to ECI, LVLH components [rad/s,
    rad/s^2], under a perturbing acceleration ``a_p`` (ECI) whose rate along the trajectory is
    ``a_p_rate`` (ECI); module docstring."""
    C_IL = lvlh_basis(r_eci, v_eci)
    y_l, z_l = C_IL[:, 1], C_IL[:, 2]
    r = norm(r_eci)
    h = norm(cross(r_eci, v_eci))
    r_dot = dot(r_eci, v_eci) / r
    a_py, a_pz = dot(a_p, y_l), dot(a_p, z_l)
    h_dot = r * a_py
    w_z = h / r**2
    w_x = r * a_pz / h
    # d Z_L / dt = -(r a_pz / h) Y_L, so d(a_p . Z_L)/dt = a_p_rate . Z_L - (r a_pz / h) a_py
    a_pz_dot = dot(a_p_rate, z_l) - w_x * a_py
    w_z_dot = h_dot / r**2 - 2 * h * r_dot / r**3
    w_x_dot = r_dot * a_pz / h + r * a_pz_dot / h - r * a_pz * h_dot / h**2
    return vec(w_x, 0, w_z), vec(w_x_dot, 0, w_z_dot)


def perturbation_rate(a_p, r_sym, v_sym, v_eci, a_eci):
    """da_p/dt along the trajectory: (d a_p / d r) v + (d a_p / d v) a [m/s^3], ECI.

    ``r_sym``, ``v_sym``: the symbols ``a_p`` is an expression of.  Taken as SymPy's derivative
    of a_p(r + s v, v + s a) in s at s = 0 (a directional derivative: about twice the cost of
    a_p, where the two 3 x 3 Jacobians would cost six times); the density's row steps count as
    constant (their derivative is zero almost everywhere)."""
    s = sp.Dummy("s")
    shift = {**{ri: ri + s * vi for ri, vi in zip(r_sym, v_eci, strict=True)},
             **{vi: vi + s * ai for vi, ai in zip(v_sym, a_eci, strict=True)}}
    moved = sp.Matrix(a_p).xreplace(shift)
    return moved.diff(s).xreplace({s: 0})


def true_anomaly(mu, r_eci, v_eci):
    """Osculating true anomaly [rad] of (r, v): atan2(h r_dot / mu, h^2 / (mu r) - 1), i.e.
    e sin(nu) over e cos(nu) (0 for a circular orbit)."""
    r = norm(r_eci)
    h = norm(cross(r_eci, v_eci))
    return sp.atan2(h * dot(r_eci, v_eci) / (mu * r), h**2 / (mu * r) - 1)


def dcm_to_quat(C: sp.Matrix) -> sp.Matrix:
    """Quaternion (scalar last, rpo's convention: v_A = q v_B q* for C = C_{A<-B}) of a rotation
    matrix, by Shepperd's method: of the four forms, the one whose component is largest
    (4 q_k^2 = 1 + 2 C_kk - tr C, 4 q_w^2 = 1 + tr C) is used, so no form divides by a small
    number.  The chosen component is positive (the sign of q is arbitrary)."""
    tr = C[0, 0] + C[1, 1] + C[2, 2]
    d = [C[0, 0], C[1, 1], C[2, 2]]
    sw = sp.sqrt(1 + tr) * 2  # 4 q_w
    qw = vec((C[2, 1] - C[1, 2]) / sw, (C[0, 2] - C[2, 0]) / sw, (C[1, 0] - C[0, 1]) / sw, sw / 4)
    sx = sp.sqrt(1 + 2 * d[0] - tr) * 2
    qx = vec(sx / 4, (C[0, 1] + C[1, 0]) / sx, (C[0, 2] + C[2, 0]) / sx, (C[2, 1] - C[1, 2]) / sx)
    sy = sp.sqrt(1 + 2 * d[1] - tr) * 2
    qy = vec((C[0, 1] + C[1, 0]) / sy, sy / 4, (C[1, 2] + C[2, 1]) / sy, (C[0, 2] - C[2, 0]) / sy)
    sz = sp.sqrt(1 + 2 * d[2] - tr) * 2
    qz = vec((C[0, 2] + C[2, 0]) / sz, (C[1, 2] + C[2, 1]) / sz, sz / 4, (C[1, 0] - C[0, 1]) / sz)
    # the largest of tr, C_00, C_11, C_22 picks the form (ties: the first)
    use_w = sp.And(tr >= d[0], tr >= d[1], tr >= d[2])
    use_x = sp.And(d[0] >= d[1], d[0] >= d[2])
    use_y = d[1] >= d[2]
    return sp.Matrix([sp.Piecewise((qw[i], use_w), (qx[i], use_x), (qy[i], use_y), (qz[i], True))
                      for i in range(4)])


def propagated_orbit(mu, r_eci, v_eci, a_p, a_p_rate):
    """The target-orbit quantities of :func:`.orbit.target_orbit` (same keys), from the propagated
    state, plus ``w_x`` and ``w_x_dot`` (the LVLH frame's rate about X_L and its derivative; 0 for
    a Keplerian orbit) and ``q_IL`` (the quaternion of ``C_IL``)."""
    C_IL = lvlh_basis(r_eci, v_eci)
    w, w_dot = lvlh_rates(r_eci, v_eci, a_p, a_p_rate)
    r = norm(r_eci)
    return {
        "nu": true_anomaly(mu, r_eci, v_eci),
        "r": r,
        "r_dot": dot(r_eci, v_eci) / r,
        "n": w[2],
        "n_dot": w_dot[2],
        "w_x": w[0],
        "w_x_dot": w_dot[0],
        "C_IL": C_IL,
        "r_eci": r_eci,
        "v_eci": v_eci,
    }
