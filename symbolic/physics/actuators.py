"""Actuators: reaction-wheel pyramid (000 eqs. 46-47, Fig. 6) and 16 PWPF thrusters (Fig. 7).

Values (000 Table 3, via SPEC.md) are parameters with defaults in :mod:`rpo.symbolic.physics.plant`.
The thruster geometry is not published; rpo's choice is defined here and documented in
``docs/actuators.md``.  Misalignment (rpo's model, not the papers'): the plant may rotate each wheel
axis and each thruster direction by a small rotation (:func:`rotation_offset`), while the
allocations keep the nominal geometry of this module.
"""

from __future__ import annotations

import sympy as sp

from .rotations import cross, dot
from .special import Fmax, fmax

# --------------------------------------------------------------------------- reaction wheels


def pyramid_matrix(beta):
    """A*: wheel axes in body axes as columns, tilt beta (000 eq. 47)."""
    c, s = sp.cos(beta), sp.sin(beta)
    return sp.Matrix([[c, 0, -c, 0], [0, c, 0, -c], [s, s, s, s]])


def rotation_offset(theta, v):
    """R(theta) v - v: how much a rotation by the rotation vector ``theta`` [rad] moves v.

    rpo's misalignment rotation is the Cayley transform R = (I - [g]x)^-1 (I + [g]x) of the Gibbs
    vector g = theta / 2, i.e. R = I + 2 / (1 + g.g) ([g]x + [g]x^2): an exact rotation about
    theta / |theta| by the angle 2 atan(|theta| / 2) = |theta| - |theta|^3 / 12 + ... (the same
    rotation as the unit quaternion [theta / 2, 1] / |[theta / 2, 1]|, the convention of the
    attitude bias of :meth:`rpo.symbolic.physics.plant.Plant.measurement`).  Rational in theta (no trig, no
    branch), smooth at 0, and exactly 0 at theta = 0 in floating point too (every term of the
    numerator has a factor theta_k; the denominator is then 4), so the true geometry is built as
    nominal + this offset and a zero misalignment adds exact zeros (x + 0 = x) to the nominal
    expressions, which keep their bits.

    With g = theta / 2: R v - v = (4 theta x v + 2 theta x (theta x v)) / (4 + theta.theta).
    """
    theta, v = sp.Matrix(theta), sp.Matrix(v)
    tv = cross(theta, v)
    return (4 * tv + 2 * cross(theta, tv)) / (4 + dot(theta, theta))


def wheel_axes_offset(beta, theta):
    """dA (3 x 4): true wheel axes minus the nominal ones A* (eq. 47); ``theta`` holds the 12
    components of the four wheels' rotation vectors (wheel 1 x, y, z, wheel 2 x, ...) [rad]."""
    A = pyramid_matrix(beta)
    return sp.Matrix.hstack(*[rotation_offset(theta[3 * i:3 * i + 3], A[:, i]) for i in range(4)])


def pyramid_pseudo_inverse(beta):
    """Minimum-norm allocation A*^T (A* A*^T)^{-1} = A*^T diag(1/(2c^2), 1/(2c^2), 1/(4s^2))."""
    c, s = sp.cos(beta), sp.sin(beta)
    return pyramid_matrix(beta).T * sp.diag(1 / (2 * c**2), 1 / (2 * c**2), 1 / (4 * s**2))


def _max_abs(values):
    return sp.Max(*[sp.Abs(v) for v in values])


def allocate_wheel_torques(beta, T_cmd, T_max):
    """Per-wheel torques [N m] realising the body torque command T_cmd (inverse of eq. 46).

    Minimum-norm solution, then scaled down uniformly when a wheel would exceed T_max, so the
    realised body torque keeps the commanded direction (A* T_w = s T_cmd, 0 < s <= 1).
    """
    T_w = pyramid_pseudo_inverse(beta) * T_cmd
    scale = sp.Max(1, _max_abs(T_w) / T_max)
    return T_w / scale


def wheel_speeds(h_w, I_w, A, omega, dA=None):
    """Wheel spin rates relative to the body, Omega_i = h_i / I_w - a_i . omega [rad/s] (the true
    axes A + dA when misaligned, :func:`wheel_axes_offset`; dA = 0 gives the nominal bits)."""
    out = h_w / I_w - A.T * omega
    return out if dA is None else out - dA.T * omega


def speed_limited_torques(T_w, Omega, Omega_max):
    """Fig. 6's momentum saturation: a wheel at |Omega| >= Omega_max cannot be driven further.

    dh_i/dt = -T_i, so a negative T_i spins wheel i up in the positive sense.
    """
    out = []
    for T, W in zip(T_w, Omega, strict=True):
        blocked = sp.Or(sp.And(W >= Omega_max, T < 0), sp.And(W <= -Omega_max, T > 0))
        out.append(sp.Piecewise((0, blocked), (T, True)))
    return sp.Matrix(out)


# --------------------------------------------------------------------------- thrusters
# rpo's 16-thruster layout (000 gives only "4 on each of the right, left, up and down faces").
# Body: 1 m cube centred on the CoM.  Right = +Y, left = -Y, down = +Z, up = -Z faces.  Each
# thruster is canted 36.87 deg (tan = 3/4) towards +X or -X so the set produces force along all
# three axes.  Thrusters come in coaxial pairs (2j, 2j+1) on opposite faces, sharing one line of
# action with opposite forces, so any wrench in the span of the 8 pair columns (rank 6) can be
# produced with non-negative thrusts.  Exact rationals keep the allocation matrix identical on
# every machine.
_R = sp.Rational


def thruster_layout():
    """(positions [m], unit force directions on the body) of the 16 thrusters, body axes."""
    pos, dirs = [], []
    for sigma in (1, -1):
        for off in (_R(3, 10), _R(-3, 10)):
            # right (+Y) and left (-Y) faces, pair on the same line of action
            pos += [sp.Matrix([-_R(3, 8) * sigma, _R(1, 2), off]), sp.Matrix([_R(3, 8) * sigma, -_R(1, 2), off])]
            dirs += [sp.Matrix([_R(3, 5) * sigma, -_R(4, 5), 0]), sp.Matrix([-_R(3, 5) * sigma, _R(4, 5), 0])]
    for sigma in (1, -1):
        for off in (_R(3, 10), _R(-3, 10)):
            # down (+Z) and up (-Z) faces
            pos += [sp.Matrix([-_R(3, 8) * sigma, off, _R(1, 2)]), sp.Matrix([_R(3, 8) * sigma, off, -_R(1, 2)])]
            dirs += [sp.Matrix([_R(3, 5) * sigma, 0, -_R(4, 5)]), sp.Matrix([-_R(3, 5) * sigma, 0, _R(4, 5)])]
    return pos, dirs


def thruster_wrench_matrix():
    """B (6 x 16): column j = [force; torque] of thruster j at unit thrust, body axes."""
    pos, dirs = thruster_layout()
    cols = [sp.Matrix.vstack(d, cross(p, d)) for p, d in zip(pos, dirs, strict=True)]
    return sp.Matrix.hstack(*cols)


def thruster_wrench_offset(theta):
    """dB (6 x 16): true minus nominal wrench columns of thrusters whose force directions are
    rotated by the rotation vectors ``theta`` (48: thruster 00 x, y, z, thruster 01 x, ...) [rad];
    column j = [dd_j; r_j x dd_j] with dd_j = :func:`rotation_offset` of direction j (the thruster
    stays where it is; its line of action turns about its mounting point)."""
    pos, dirs = thruster_layout()
    cols = []
    for j, (p, d) in enumerate(zip(pos, dirs, strict=True)):
        dd = rotation_offset(theta[3 * j:3 * j + 3], d)
        cols.append(sp.Matrix.vstack(dd, cross(p, dd)))
    return sp.Matrix.hstack(*cols)


def thruster_pair_matrix():
    """B8 (6 x 8): the wrench columns of the first thruster of each coaxial pair.

    Thrusters 2j and 2j+1 share a line of action with opposite forces, so B = [b_0, -b_0, b_1,
    -b_1, ...] and a signed pair level x_j fires thruster 2j (x_j > 0) or 2j+1 (x_j < 0).
    """
    B = thruster_wrench_matrix()
    for j in range(8):
        assert B[:, 2 * j] == -B[:, 2 * j + 1], "thrusters 2j, 2j+1 must be a coaxial opposed pair"
    return sp.Matrix.hstack(*[B[:, 2 * j] for j in range(8)])


def allocate_thrusters(F_cmd, tau_cmd, F_max):
    """Duty demands d in [0, 1]^16 for a body force [N] and torque [N m] command.

    Signed pair levels x = B8^+ w / F_max (exact rational pseudo-inverse, rank 6), then
    d_2j = max(x_j, 0), d_2j+1 = max(-x_j, 0): only one thruster of each opposed pair fires, and
    B d F_max = w exactly.  If any d exceeds 1 all are scaled by the same factor, keeping the
    wrench direction.  Closed form and continuous in the command; not L1 fuel-optimal (an LP
    would be), but no opposed pair ever fires together.
    """
    B8 = thruster_pair_matrix()
    x = B8.T * (B8 * B8.T).inv() * sp.Matrix.vstack(F_cmd, tau_cmd) / F_max
    d = []
    for j in range(8):
        d += [sp.Max(x[j], 0), sp.Max(-x[j], 0)]
    scale = sp.Max(1, *[sp.Abs(x[j]) for j in range(8)])
    return sp.Matrix(d) / scale


def thruster_wrench(on, F_max):
    """Body force [N] and torque [N m] of thrusters firing at levels ``on`` (0 or 1 each)."""
    w = thruster_wrench_matrix() * on * F_max
    return sp.Matrix(w[0:3]), sp.Matrix(w[3:6])


def thruster_wrench_misalignment(on, F_max, theta):
    """Force [N] and torque [N m] that misaligned thrusters (rotation vectors ``theta``, 48) add
    to :func:`thruster_wrench`: dB on F_max (:func:`thruster_wrench_offset`), exactly 0 at theta = 0."""
    w = thruster_wrench_offset(theta) * on * F_max
    return sp.Matrix(w[0:3]), sp.Matrix(w[3:6])


def propellant_flow(on, F_max, isp, g0):
    """Propellant mass flow sum_j F_j / (Isp g0) [kg/s]."""
    return sum(on) * F_max / (isp * g0)


# --------------------------------------------------------------------------- ideal actuators
# The papers 001, 002 and 004 command body force and torque directly, limited per axis.


def saturate(v, limit):
    """Per-axis saturation of a column to [-limit, limit] (limit >= 0, in the column's unit).

    The one saturation of rpo: the ideal actuators use it directly, the papers' own limits
    (001 sec. 7, 002 eq. 13) through wrappers that keep their equation numbers.
    """
    # evaluate=False: SymPy's Min/Max otherwise try to order the limit against the (large) command
    # expression symbolically, which takes minutes and cannot succeed
    return v.applyfunc(lambda c: sp.Max(-limit, sp.Min(limit, c, evaluate=False), evaluate=False))


def ideal_wrench(F_cmd, tau_cmd, F_max, tau_max):
    """Force [N] and torque [N m] the ideal actuators apply: the commands saturated per axis."""
    return saturate(F_cmd, F_max), saturate(tau_cmd, tau_max)


def ideal_propellant_flow(F, isp, g0):
    """Propellant flow of ideal thrust, as from one thruster pair per body axis: sum_i |F_i| / (Isp g0)."""
    return sum(sp.Abs(c) for c in F) / (isp * g0)


# --------------------------------------------------------------------------- PWPF modulator
# Fig. 7: prefilter K_m / (T_m s + 1) on (demand - output), Schmitt trigger (U_on, U_off).
# Discretised exactly for a demand and an output held over the step dt.


def schmitt_trigger(f, on_prev, u_on, u_off):
    """Trigger output (0 or 1): on when f >= U_on, off when f <= U_off, else hold."""
    return sp.Piecewise((1, f >= u_on), (0, f <= u_off), (on_prev, True))


def pwpf_filter_step(f, demand, on, k_m, t_m, dt):
    """Prefilter state after dt: f + (1 - exp(-dt/T_m)) (K_m (demand - on) - f)."""
    return f + (1 - sp.exp(-dt / t_m)) * (k_m * (demand - on) - f)


# --------------------------------------------------------------------------- fault-aware allocation
# rpo's FDIR model (not the papers'): with ``fdir_allocation`` = 1 these allocations replace the
# nominal ones, over the units the fault flags of :mod:`rpo.symbolic.physics.faults` leave healthy.  Both
# take the nominal minimum-norm solution and move it along the null space of the actuator matrix
# (which changes no body torque or wrench) until the failed units are at zero: exact, closed-form
# and as well conditioned as the nominal allocation, where a pseudo-inverse over the healthy
# units would be singular whenever they stop spanning the axes.


#: Smallest fraction of a unit's limit the fault-aware allocations divide by (the schema's range of
#: the weak faults' values is (0, 1]; this keeps a smaller value given directly finite).
FRACTION_MIN = sp.Rational(1, 10**9)


def null_space_redistribution(x, null_vectors, failed):
    """x moved along ``null_vectors`` so that the ``failed`` entries (0/1 flags) are zero.

    Each null vector has entries in {-1, 0, 1} and no two share an entry (true of the wheel
    pyramid and of the thruster pairs, :func:`pyramid_null_vector`, :func:`thruster_pair_null_vectors`),
    so each is moved on its own: by -n_j x_j for its one failed entry j, which zeroes it exactly.
    With two or more failed entries on one null vector no exact solution exists; the shift then
    averages theirs and the failed entries are set to zero (the command is not reproduced).
    """
    x = sp.Matrix(x)
    for n in null_vectors:
        members = [j for j in range(len(x)) if n[j] != 0]
        count = sum(failed[j] for j in members)
        c = -sum(failed[j] * n[j] * x[j] for j in members) / Fmax(count, 1)
        x = x + c * sp.Matrix(n)
    return sp.Matrix([(1 - failed[j]) * x[j] for j in range(len(x))])


def pyramid_null_vector():
    """The null space of A* (any beta): [1, -1, 1, -1] (opposite wheels' torques cancel)."""
    return [1, -1, 1, -1]


def allocate_wheel_torques_healthy(beta, T_cmd, T_max, avail, limit):
    """Per-wheel torques [N m] realising T_cmd without the unavailable wheels (``avail`` 0/1).

    The minimum-norm torques (eq. 46 inverted), moved along the pyramid's null space until an
    unavailable wheel's torque is zero: with one wheel lost the remaining three (which span the
    body axes) realise T_cmd exactly; then scaled down uniformly so that no wheel exceeds its own
    limit ``limit_i`` T_max (0 < limit_i <= 1, a weak wheel's), keeping the direction.
    """
    T_w = null_space_redistribution(pyramid_pseudo_inverse(beta) * T_cmd, [pyramid_null_vector()],
                                    [1 - a for a in avail])
    # Fmax: a limit fraction below 1e-9 (outside the schema's range) must not divide by zero; the
    # blend with the nominal allocation multiplies this result by 0, and 0 * inf would be NaN
    scale = fmax(1, *[sp.Abs(T_w[i], evaluate=False) / (Fmax(limit[i], FRACTION_MIN) * T_max) for i in range(4)])
    return T_w / scale


def thruster_pair_null_vectors():
    """A basis of the null space of B8 with entries in {-1, 0, 1} and disjoint supports."""
    B8 = thruster_pair_matrix()
    basis = [list(v) for v in B8.nullspace()]
    for v in basis:
        assert all(c in (-1, 0, 1) for c in v), "thruster layout: null vector not in {-1, 0, 1}"
    assert all(a * b == 0 for a, b in zip(*basis, strict=True)), "thruster layout: null vectors share pairs"
    return basis


def allocate_thrusters_healthy(F_cmd, tau_cmd, F_max, avail, thrust, stuck_on):
    """Duty demands in [0, 1]^16 without the unavailable thrusters (rpo's FDIR model).

    The known wrench of the stuck-on thrusters is subtracted from the command; the pair levels of
    :func:`allocate_thrusters` for the rest are moved along the two null vectors of B8 until the
    pairs with an unavailable thruster are at zero (exact for up to one such pair per null
    vector); a weak thruster's demand is divided by its thrust fraction ``thrust_j``
    (0 < thrust_j <= 1); all demands are scaled down together when one exceeds 1.  A pair with one
    failed thruster is not used (its partner alone could push one way only), so this is not the
    best allocation an optimiser (an LP) would find, but it is closed-form.
    """
    B8 = thruster_pair_matrix()
    pinv = B8.T * (B8 * B8.T).inv()
    x_nominal = pinv * sp.Matrix.vstack(F_cmd, tau_cmd) / F_max  # as allocate_thrusters (shared)
    # the stuck thrusters' wrench is B s F_max = B8 (s_2j - s_2j+1)_j F_max (opposed pairs), so its
    # pair levels are the projection B8^+ B8 of those differences, a constant 8 x 8 rational matrix
    s = [stuck_on[j] * thrust[j] for j in range(16)]
    x = x_nominal - (pinv * B8) * sp.Matrix([s[2 * j] - s[2 * j + 1] for j in range(8)])
    pair_failed = [1 - avail[2 * j] * avail[2 * j + 1] for j in range(8)]
    x = null_space_redistribution(x, thruster_pair_null_vectors(), pair_failed)
    d = []
    for j in range(8):
        d += [Fmax(x[j], 0) / Fmax(thrust[2 * j], FRACTION_MIN), Fmax(-x[j], 0) / Fmax(thrust[2 * j + 1], FRACTION_MIN)]
    scale = fmax(1, *d)
    return sp.Matrix(d) / scale
