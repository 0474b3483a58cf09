"""Rigid-body attitude dynamics of the chaser (with reaction wheels) and the target (000 eqs. 1-3, 6, 10).

Wheel convention (see ``docs/conventions.md``): ``h_w`` holds each wheel's absolute axial
angular momentum I_w (a_i . omega + Omega_i) [N m s]; ``I_c`` is the chaser inertia without
the wheels' axial inertia; ``T_w`` is the reaction torque each wheel motor exerts on the body
about its axis [N m].  Then the body torque is T_c = A T_w (eq. 46) and dh_w/dt = -T_w, which is
eq. 6 with T_c = -dh_rw/dt, and total angular momentum and energy are exactly conserved when
no external torque acts (``tests/test_attitude.py``).
"""

from __future__ import annotations

import sympy as sp

from .rotations import cross, dot, quat_to_dcm


def solve3(M, b):
    """M^{-1} b for a 3x3 matrix via its adjugate (closed form, no pivoting branches)."""
    adj = M.adjugate()
    # det by the first row's cofactors (already in adj): M.det() (Bareiss) re-derives them and,
    # with a locked wheel's terms in M, builds a much larger expression
    det = M[0, 0] * adj[0, 0] + M[0, 1] * adj[1, 0] + M[0, 2] * adj[2, 0]
    return adj * b / det


def chaser_angular_acceleration(I_c, omega, h_rw, T_c, M_ext, I_locked=None):
    """omega_dot [rad/s^2] from I_c omega_dot = -S(omega) I_c omega - S(omega) h_rw + T_c + M (000 eq. 6).

    ``h_rw`` = A h_w is the wheels' momentum in body axes, ``T_c`` the wheel torque on the body,
    ``M_ext`` every other torque (gravity gradient, magnetic, random, thrusters) [N m].
    I_c is taken at the current time; like the paper, no dI/dt term (see docs/errata.md).
    ``I_locked`` (:func:`locked_wheel_inertia`) adds the reaction of locked wheels, whose torque is
    then not in ``T_c``: (I_c + I_locked) omega_dot = the same right-hand side.
    """
    J = I_c if I_locked is None else I_c + I_locked
    return solve3(J, -cross(omega, I_c * omega) - cross(omega, h_rw) + T_c + M_ext)


def locked_wheel_inertia(I_w, A, locked):
    """I_w sum_i locked_i a_i a_i^T [kg m^2]: what locked wheels (``locked`` 0/1 each) add to the
    chaser's inertia (rpo's ``wheel_stuck`` fault, :mod:`rpo.symbolic.physics.faults`).

    A wheel held at a constant speed relative to the body has dh_i/dt = I_w a_i . omega_dot, i.e.
    it exerts T_i = -I_w a_i . omega_dot on the body; moved to the left of eq. 6 this is the added
    inertia.  Zero, exactly, when no wheel is locked.
    """
    return I_w * A * sp.diag(*locked) * A.T


def locked_wheel_inertia_offset(I_w, A, dA, locked):
    """:func:`locked_wheel_inertia` of the true axes A + dA minus that of the nominal A [kg m^2]
    (misalignment): I_w (A L dA^T + dA L A^T + dA L dA^T), L = diag(locked); exactly 0 when dA = 0."""
    L = sp.diag(*locked)
    return I_w * (A * L * dA.T + dA * L * A.T + dA * L * dA.T)


def solve3_explicit(M, b):
    """M^{-1} b by the cofactor formulas written out (a d - b c per minor).

    For a matrix whose entries are long sums: SymPy's adjugate (:func:`solve3`) simplifies each
    minor with ``cancel``, which expands such entries into very large polynomials.
    """
    def cof(i, j):
        r = [k for k in range(3) if k != i]
        c = [k for k in range(3) if k != j]
        return (-1) ** (i + j) * (M[r[0], c[0]] * M[r[1], c[1]] - M[r[0], c[1]] * M[r[1], c[0]])

    adj = sp.Matrix(3, 3, lambda i, j: cof(j, i))
    det = M[0, 0] * adj[0, 0] + M[0, 1] * adj[1, 0] + M[0, 2] * adj[2, 0]
    return adj * b / det


def angular_acceleration_offset(J, dJ, db, omega_dot0):
    """delta with (J + dJ)(omega_dot0 + delta) = J omega_dot0 + db, exactly: the change of
    omega_dot [rad/s^2] when the inertia of eq. 6 changes by dJ and its right-hand side by db
    (misaligned wheels and thrusters), from the nominal solution omega_dot0 of J omega_dot0 = b.

    delta = (J + dJ)^{-1} (db - dJ omega_dot0), which is exactly 0 (bit for bit) when dJ and db
    are, so omega_dot0 + delta keeps the nominal bits at zero misalignment.
    """
    return solve3_explicit(J + dJ, db - dJ * omega_dot0)


def locked_wheel_momentum_rate(T_w, I_w, A, locked, omega_dot, dA=None):
    """dh_w/dt [N m]: -T_w for a free wheel (eq. 6), I_w a_i . omega_dot for a locked one (true
    axes A + dA, as :func:`locked_wheel_inertia`)."""
    turn = A.T * omega_dot
    if dA is not None:
        turn = turn + dA.T * omega_dot
    return sp.Matrix([-(1 - locked[i]) * T_w[i] + locked[i] * I_w * turn[i] for i in range(len(T_w))])


def target_angular_acceleration(I_t, omega, M_ext):
    """omega_dot [rad/s^2] from I_t omega_dot = -S(omega) I_t omega + M_tot_t (000 eq. 10)."""
    return solve3(I_t, -cross(omega, I_t * omega) + M_ext)


def wheel_momentum_rate(T_w):
    """dh_w/dt = -T_w [N m] (000 eq. 6, T_c = -dh_rw/dt, per wheel)."""
    return -T_w


def angular_momentum_inertial(q, I_c, omega, h_rw):
    """Total angular momentum in ECI, C_{I<-B}(q) (I_c omega + h_rw) [N m s] (000 eq. 2)."""
    return quat_to_dcm(q) * (I_c * omega + h_rw)


def kinetic_energy(I_c, omega, h_w, I_w):
    """Rotational kinetic energy 1/2 omega^T I_c omega + sum h_i^2 / (2 I_w) [J]."""
    return dot(omega, I_c * omega) / 2 + dot(h_w, h_w) / (2 * I_w)
