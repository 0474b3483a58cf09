"""Attitude conventions at the edges of the runtime (scenario input, summaries, plots).

Conventions (the same as the generated model, see ``generated/manifest.json``):

* quaternions are **scalar last** ``[x, y, z, w]``, multiplied with the **Hamilton** product;
* ``q_B_A`` (the attitude of frame B relative to frame A) maps B components to A components,
  ``v_A = q v_B q*``; its matrix ``dcm_from_quat(q) = C_{A<-B}`` has the B axes, written in A,
  as columns.  This is SciPy's convention: ``Rotation.from_quat(q).as_matrix() = C_{A<-B}``;
* composition: ``q_C_A = q_B_A ⊗ q_C_B``;
* body rates are rates of the body relative to ECI, in body axes [rad/s].

Frames (000 §"Essential coordinate systems"):

* ``"eci"``: Earth-centred inertial, X to the vernal equinox, Z to the north pole;
* ``"lvlh"``: the target's local-vertical local-horizontal frame L: X_L radial (Earth centre to
  target), Y_L along-track in the orbit plane, Z_L orbit normal.  Its attitude relative to ECI
  at time t is ``q_IL`` from the generated function ``target_orbit``; it rotates at the rate
  ``n`` (true-anomaly rate) about Z_L;
* ``"orbit"``: 000's orbit reference frame R: X_R along-track, Z_R nadir (toward the Earth's
  centre), Y_R = Z_R x X_R (minus the orbit normal).  Here it is taken at the target and built
  from the LVLH axes: X_R = Y_L, Y_R = -Z_L, Z_R = -X_L, a constant rotation from L.  For an
  elliptic orbit X_R is the local horizontal, which differs from the velocity direction by the
  flight-path angle (zero at perigee and apogee, at most asin(e)).  The chaser's own orbit frame
  differs from the target's by less than |r| / r_t (about 1e-5 rad at 100 m in LEO).

Paper 000 prints its quaternions scalar last; for the same attitude they have the same four
numbers in Shuster's convention and in ours, so they are used as printed.

Only numpy, math and :class:`scipy.spatial.transform.Rotation` are used here (one quaternion at a
time in Python floats, with the same arithmetic as numpy and SciPy: the same bits).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

#: Frames an initial attitude can be given in.
FRAMES = ("eci", "lvlh", "orbit")

#: C_{L<-R}: the orbit-reference-frame axes (X_R = Y_L, Y_R = -Z_L, Z_R = -X_L) as columns in LVLH.
DCM_LVLH_FROM_ORBIT = np.array([[0.0, 0.0, -1.0],
                                [1.0, 0.0, 0.0],
                                [0.0, -1.0, 0.0]])

#: q_R_L: attitude of the orbit frame R relative to LVLH, scalar last (= [-1, -1, 1, 1] / 2).
Q_LVLH_ORBIT = np.array([-0.5, -0.5, 0.5, 0.5])


# --------------------------------------------------------------------------- quaternion algebra


def _q(q: ArrayLike) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    if q.shape[-1] != 4:
        raise ValueError(f"a quaternion needs 4 components, got shape {q.shape}")
    return q


def scalar_first_to_last(q_wxyz: ArrayLike) -> np.ndarray:
    """``[w, x, y, z]`` -> ``[x, y, z, w]`` (works on (..., 4) arrays)."""
    return np.roll(_q(q_wxyz), -1, axis=-1)


def scalar_last_to_first(q_xyzw: ArrayLike) -> np.ndarray:
    """``[x, y, z, w]`` -> ``[w, x, y, z]`` (works on (..., 4) arrays)."""
    return np.roll(_q(q_xyzw), 1, axis=-1)


def quat_normalize(q: ArrayLike) -> np.ndarray:
    """Unit quaternion along ``q`` (scalar last); raises ValueError for a zero quaternion."""
    q = _q(q)
    if q.ndim == 1:  # one quaternion: its norm without np.linalg's overhead (a campaign: ~10 per run)
        x, y, z, w = q.tolist()
        n1 = math.sqrt(x * x + y * y + z * z + w * w)  # np.linalg.norm's sum, in its order: the same bits
        if n1 == 0:
            raise ValueError("cannot normalise a zero quaternion")
        return q / n1
    n = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ValueError("cannot normalise a zero quaternion")
    return q / n


def quat_conjugate(q: ArrayLike) -> np.ndarray:
    """Conjugate (inverse of a unit quaternion), scalar last."""
    q = _q(q).copy()
    q[..., :3] *= -1
    return q


def quat_multiply(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """Hamilton product ``a ⊗ b`` of scalar-last quaternions (broadcasts over leading axes)."""
    a, b = _q(a), _q(b)
    if a.ndim == 1 and b.ndim == 1:
        return _quat_multiply_one(a, b)
    av, aw = a[..., :3], a[..., 3:]
    bv, bw = b[..., :3], b[..., 3:]
    cross = np.cross(av, bv)
    v = aw * bv + bw * av + cross
    w = aw * bw - np.sum(av * bv, axis=-1, keepdims=True)
    return np.concatenate([v, w], axis=-1)


def _quat_multiply_one(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`quat_multiply` of two single quaternions in Python floats: numpy's operations in
    numpy's order (np.cross's products and differences; the dot product summed from +0.0, as
    np.sum does), so the same bits, signed zeros included (tests/test_frames.py), without the
    cost of a dozen numpy calls on 3-vectors (a campaign multiplies ~6 quaternions per run)."""
    (a0, a1, a2, aw), (b0, b1, b2, bw) = a.tolist(), b.tolist()
    c0, c1, c2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
    return np.array([aw * b0 + bw * a0 + c0, aw * b1 + bw * a1 + c1, aw * b2 + bw * a2 + c2,
                     aw * bw - (0.0 + a0 * b0 + a1 * b1 + a2 * b2)])


def dcm_from_quat(q: ArrayLike) -> np.ndarray:
    """``C_{A<-B}`` for ``q = q_B_A`` (scalar last, normalised first); (..., 3, 3)."""
    q = _q(q)
    if q.ndim == 1:
        x, y, z, w = q.tolist()
        n = math.sqrt(x * x + y * y + z * z + w * w)
        if n > 0 and math.isfinite(n):
            return _dcm_of_one(x / n, y / n, z / n, w / n)
    return Rotation.from_quat(q).as_matrix()


def _dcm_of_one(x: float, y: float, z: float, w: float) -> np.ndarray:
    """``C_{A<-B}`` of one unit quaternion [x, y, z, w]: SciPy's own arithmetic (its normalisation
    and ``as_matrix``, in the same order: the same bits, tests/test_frames.py), without the cost of
    a Rotation object for one quaternion (a campaign converts a few per run)."""
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
    return np.array([[x2 - y2 - z2 + w2, 2 * (xy - zw), 2 * (xz + yw)],
                     [2 * (xy + zw), -x2 + y2 - z2 + w2, 2 * (yz - xw)],
                     [2 * (xz - yw), 2 * (yz + xw), -x2 - y2 + z2 + w2]])


def quat_from_dcm(C: ArrayLike) -> np.ndarray:
    """``q_B_A`` (scalar last, w >= 0) from ``C_{A<-B}``."""
    q = Rotation.from_matrix(np.asarray(C, dtype=float)).as_quat()
    return np.where(q[..., 3:] < 0, -q, q)


def rotation_angle(q: ArrayLike) -> np.ndarray:
    """Angle of the rotation ``q`` in [0, pi] [rad] (sign-invariant: q and -q give the same angle)."""
    q = quat_normalize(q)
    return 2.0 * np.arccos(np.clip(np.abs(q[..., 3]), 0.0, 1.0))


def quat_from_euler(seq: str, angles: Sequence[float], degrees: bool = True) -> np.ndarray:
    """``q_B_A`` from Euler angles: uppercase ``seq`` = intrinsic (e.g. ``"ZYX"`` = yaw, pitch, roll
    about the rotating axes), lowercase = extrinsic; SciPy's convention."""
    return Rotation.from_euler(seq, angles, degrees=degrees).as_quat()


def euler_from_quat(q: ArrayLike, seq: str = "ZYX", degrees: bool = True) -> np.ndarray:
    """Euler angles of ``q_B_A`` in the sequence ``seq`` (see :func:`quat_from_euler`)."""
    return Rotation.from_quat(_q(q)).as_euler(seq, degrees=degrees)


# --------------------------------------------------------------------------- frames


def _check_frame(frame: str) -> None:
    if frame not in FRAMES:
        raise ValueError(f"frame must be one of {', '.join(FRAMES)}; got {frame!r}")


def frame_attitude(frame: str, q_IL: ArrayLike) -> np.ndarray:
    """Attitude of ``frame`` relative to ECI (scalar last), given ``q_IL`` = q_LVLH_ECI."""
    _check_frame(frame)
    if frame == "eci":
        return np.array([0.0, 0.0, 0.0, 1.0])
    q_IL = quat_normalize(q_IL)
    if frame == "lvlh":
        return q_IL
    return quat_multiply(q_IL, Q_LVLH_ORBIT)


def attitude_to_eci(q_FB: ArrayLike, frame: str, q_IL: ArrayLike) -> np.ndarray:
    """Body attitude relative to ECI from the attitude ``q_FB`` relative to ``frame``.

    ``q_B_ECI = q_F_ECI ⊗ q_B_F``; ``q_IL`` is the LVLH attitude at the same instant (unused for
    ``frame == "eci"``).  All quaternions scalar last.
    """
    return quat_normalize(quat_multiply(frame_attitude(frame, q_IL), quat_normalize(q_FB)))


def attitude_from_eci(q_IB: ArrayLike, frame: str, q_IL: ArrayLike) -> np.ndarray:
    """Inverse of :func:`attitude_to_eci`: ``q_B_F = q_F_ECI* ⊗ q_B_ECI``."""
    return quat_normalize(quat_multiply(quat_conjugate(frame_attitude(frame, q_IL)), quat_normalize(q_IB)))


def frame_rate_eci(frame: str, q_IL: ArrayLike, n: float) -> np.ndarray:
    """Angular velocity of ``frame`` relative to ECI, in ECI axes [rad/s].

    LVLH (and R, fixed to it) turns at the true-anomaly rate ``n`` (``target_orbit`` output)
    about the orbit normal Z_L; ECI does not turn.
    """
    _check_frame(frame)
    if frame == "eci":
        return np.zeros(3)
    return float(n) * dcm_from_quat(quat_normalize(q_IL))[:, 2]


def body_rate_eci(omega_rel: ArrayLike, q_IB: ArrayLike, frame: str, q_IL: ArrayLike, n: float) -> np.ndarray:
    """Body rate relative to ECI [rad/s, body axes] from the rate ``omega_rel`` relative to ``frame``.

    ``w_B/I = w_B/F + C_{B<-I} w_F/I``, both in body axes.
    """
    C_IB = dcm_from_quat(quat_normalize(q_IB))
    return np.asarray(omega_rel, dtype=float) + C_IB.T @ frame_rate_eci(frame, q_IL, n)
