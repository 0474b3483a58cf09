"""Rotation algebra: skew matrix, quaternions, MRPs (with shadow set) and dual quaternions.

All functions take and return :class:`sympy.Matrix` column vectors and work on symbols and
numbers alike.  Convention (one, used everywhere inside rpo):

* quaternion ``q = [x, y, z, w]`` (scalar last), Hamilton product ``⊗``;
* ``q`` = attitude of frame B relative to frame A, ``v_A = q ⊗ [v_B, 0] ⊗ q*``;
* ``quat_to_dcm(q) = C_{A<-B}``; the papers' attitude matrix (000 eq. 20) is ``C_{B<-A}``,
  i.e. ``quat_to_dcm(q).T`` with the same four numbers;
* ``omega`` = angular velocity of B relative to A, expressed in B.
"""

from __future__ import annotations

import sympy as sp

Matrix = sp.Matrix


def vec(*entries) -> Matrix:
    """Column vector from entries."""
    return sp.Matrix(entries)


def skew(v: Matrix) -> Matrix:
    """Cross-product matrix S(v) with S(v) u = v x u (000 eq. 7)."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def cross(a: Matrix, b: Matrix) -> Matrix:
    """a x b."""
    return skew(a) * b


def dot(a: Matrix, b: Matrix):
    """Scalar product a . b."""
    return (a.T * b)[0, 0]


def norm(v: Matrix):
    """Euclidean norm."""
    return sp.sqrt(dot(v, v))


# --------------------------------------------------------------------------- quaternions

def quat(v: Matrix, w) -> Matrix:
    """Quaternion from vector part ``v`` and scalar ``w``."""
    return sp.Matrix([v[0], v[1], v[2], w])


def quat_vec(q: Matrix) -> Matrix:
    """Vector part of a scalar-last quaternion."""
    return sp.Matrix(q[0:3])


def quat_mul(p: Matrix, q: Matrix) -> Matrix:
    """Hamilton product p ⊗ q (scalar last).

    ``(p ⊗ q)_v = p_w q_v + q_w p_v + p_v x q_v``, ``(p ⊗ q)_w = p_w q_w - p_v . q_v``.
    Composition: ``q_C_A = q_B_A ⊗ q_C_B``.
    """
    pv, pw = quat_vec(p), p[3]
    qv, qw = quat_vec(q), q[3]
    v = pw * qv + qw * pv + cross(pv, qv)
    return quat(v, pw * qw - dot(pv, qv))


def quat_conj(q: Matrix) -> Matrix:
    """Conjugate (the inverse for a unit quaternion): ``q_A_B = quat_conj(q_B_A)``."""
    return sp.Matrix([-q[0], -q[1], -q[2], q[3]])


def quat_to_dcm(q: Matrix) -> Matrix:
    """``C_{A<-B}`` for ``q = q_B_A`` (unit quaternion).

    ``(w^2 - |v|^2) I + 2 v v^T + 2 w S(v)``; its transpose is the attitude matrix printed
    as 000 eq. 20 (``C_t^c`` for ``q_r``).
    """
    v, w = quat_vec(q), q[3]
    return (w**2 - dot(v, v)) * sp.eye(3) + 2 * v * v.T + 2 * w * skew(v)


def quat_rotate(q: Matrix, v_B: Matrix) -> Matrix:
    """Express in A a vector given in B: ``v_A = C_{A<-B}(q) v_B``."""
    return quat_to_dcm(q) * v_B


def quat_rate(q: Matrix, omega: Matrix) -> Matrix:
    """Quaternion kinematics ``q_dot = 1/2 q ⊗ [omega, 0]`` (000 eqs. 24 and 29).

    ``omega`` is the rate of B relative to A in B.  In component form this is
    ``q_v_dot = 1/2 (w omega - omega x q_v)``, ``w_dot = -1/2 omega . q_v``, the matrix of
    000 eq. 24.  (000 eqs. 8 and 11 add orbit-rate terms because there the attitude is
    taken relative to the rotating orbit frame; rpo integrates attitude relative to ECI.)
    """
    return quat_mul(q, quat(omega, 0)) / 2


# --------------------------------------------------------------------------- MRPs

def mrp_from_quat(q: Matrix) -> Matrix:
    """Modified Rodrigues parameters ``sigma = q_v / (1 + w)`` (004 convention)."""
    return quat_vec(q) / (1 + q[3])


def quat_from_mrp(s: Matrix) -> Matrix:
    """Unit quaternion from MRPs: ``q_v = 2 s / (1 + s^2)``, ``w = (1 - s^2) / (1 + s^2)``."""
    s2 = dot(s, s)
    return quat(2 * s / (1 + s2), (1 - s2) / (1 + s2))


def mrp_shadow(s: Matrix) -> Matrix:
    """Shadow set ``sigma^S = -sigma / |sigma|^2``: the same attitude, |sigma^S| = 1/|sigma|."""
    return -s / dot(s, s)


def mrp_to_dcm(s: Matrix) -> Matrix:
    """``C_{A<-B}`` from the MRPs of ``q_B_A``.

    ``I + (8 S^2 + 4 (1 - s^2) S) / (1 + s^2)^2`` with ``S = S(sigma)``; equals
    ``quat_to_dcm(quat_from_mrp(s))``.
    """
    s2 = dot(s, s)
    S = skew(s)
    return sp.eye(3) + (8 * S * S + 4 * (1 - s2) * S) / (1 + s2) ** 2


def mrp_b_matrix(s: Matrix) -> Matrix:
    """``B(sigma) = (1 - s^2) I + 2 S(sigma) + 2 sigma sigma^T`` (004 eq. 2 form)."""
    return (1 - dot(s, s)) * sp.eye(3) + 2 * skew(s) + 2 * s * s.T


def mrp_rate(s: Matrix, omega: Matrix) -> Matrix:
    """MRP kinematics ``sigma_dot = 1/4 B(sigma) omega``."""
    return mrp_b_matrix(s) * omega / 4


def mrp_switch(s: Matrix) -> Matrix:
    """Shadow-set switching: return the set with |sigma| <= 1 (the non-singular one).

    Expressed with a Piecewise so that it can be generated to C.
    """
    s2 = dot(s, s)
    sh = mrp_shadow(s)
    return sp.Matrix([sp.Piecewise((sh[i], s2 > 1), (s[i], True)) for i in range(3)])


# --------------------------------------------------------------------------- dual quaternions
# A dual quaternion is stored as an 8-vector [real (4); dual (4)], each part scalar last.

def dq(real: Matrix, dual: Matrix) -> Matrix:
    """Dual quaternion ``real + eps dual`` as an 8-vector."""
    return sp.Matrix.vstack(real, dual)


def dq_real(d: Matrix) -> Matrix:
    """Real (rotation) part."""
    return sp.Matrix(d[0:4])


def dq_dual(d: Matrix) -> Matrix:
    """Dual part."""
    return sp.Matrix(d[4:8])


def dq_mul(a: Matrix, b: Matrix) -> Matrix:
    """Dual-quaternion product ``(a_r + eps a_d)(b_r + eps b_d) = a_r b_r + eps (a_r b_d + a_d b_r)``."""
    ar, ad = dq_real(a), dq_dual(a)
    br, bd = dq_real(b), dq_dual(b)
    return dq(quat_mul(ar, br), quat_mul(ar, bd) + quat_mul(ad, br))


def dq_conj(d: Matrix) -> Matrix:
    """Quaternion conjugate of both parts (the inverse of a unit dual quaternion)."""
    return dq(quat_conj(dq_real(d)), quat_conj(dq_dual(d)))


def dq_from_pose(q: Matrix, t: Matrix, frame: str = "A") -> Matrix:
    """Unit dual quaternion of the pose (attitude ``q = q_B_A``, position ``t`` of B's origin).

    ``frame="A"``: ``t`` expressed in A, dual part ``1/2 [t, 0] ⊗ q``.
    ``frame="B"``: ``t`` expressed in B, dual part ``1/2 q ⊗ [t, 0]`` (the form of 001).
    Both give the same dual quaternion for the same pose.
    """
    tq = quat(t, 0)
    if frame == "A":
        return dq(q, quat_mul(tq, q) / 2)
    if frame == "B":
        return dq(q, quat_mul(q, tq) / 2)
    raise ValueError(f"frame must be 'A' or 'B', got {frame!r}")


def dq_to_pose(d: Matrix, frame: str = "A") -> tuple[Matrix, Matrix]:
    """Inverse of :func:`dq_from_pose`: ``(q, t)`` with ``t`` in frame A or B."""
    q, qd = dq_real(d), dq_dual(d)
    if frame == "A":
        return q, quat_vec(2 * quat_mul(qd, quat_conj(q)))
    if frame == "B":
        return q, quat_vec(2 * quat_mul(quat_conj(q), qd))
    raise ValueError(f"frame must be 'A' or 'B', got {frame!r}")
