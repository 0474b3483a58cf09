"""rpo <-> Basilisk conventions, in one place (tests/test_xcheck_basilisk.py, benchmarks/basilisk_case.py).

Pure numpy: nothing of rpo or Basilisk is imported, so every conversion here can be checked
against an independent route (tests/test_basilisk_map.py: SciPy's ``Rotation``, round trips;
tests/test_xcheck_basilisk.py: Basilisk's own ``RigidBodyKinematics`` and momentum).  The page
docs/basilisk_xcheck.md explains the choices.

Attitude
    rpo: quaternion ``q_B/ECI`` **scalar last** ``[x, y, z, w]``, **Hamilton** product,
    ``v_ECI = q v_B q*``, so ``dcm_from_quat(q) = C_{ECI<-B}`` (the body axes in ECI as columns;
    SciPy's ``Rotation.from_quat(q).as_matrix()``; runtime/frames.py, generated/manifest.json).

    Basilisk: modified Rodrigues parameters ``sigma_BN`` (its hub state) and Euler parameters
    ``beta_BN`` **scalar first** (``RigidBodyKinematics.EP2C``, ``MRP2C``, ``C2MRP``), both of the
    DCM ``[BN] = C_{B<-N}`` = ``C_{ECI<-B}^T`` (Schaub's passive convention).  For the same attitude
    the principal axis and angle are the same, so ``beta_BN = [q_w, q_x, q_y, q_z]`` (same numbers,
    reordered) and ``sigma_BN = q_vec / (1 + q_w)``.  ``sigma`` and its shadow set
    ``-sigma / |sigma|^2`` are the same attitude; Basilisk switches to the shadow set when
    ``|sigma| > 1`` after each integration step, so comparisons go through :func:`attitude_error`,
    which is blind to the set and to the quaternion's sign.

Body rates
    Both: ``omega_B/N`` relative to ECI in body axes [rad/s] (Basilisk ``omega_BN_B``).

Reaction wheels
    rpo's state is the **axial absolute angular momentum** ``h_i`` [N m s] of each wheel
    (symbolic/physics/actuators.py ``wheel_speeds``); Basilisk's is the wheel speed ``Omega_i`` **relative to
    the body** [rad/s] (``rwSpeedOutMsg.wheelSpeeds``; its factory takes rpm).  With spin axis
    ``a_i`` (column i of rpo's pyramid matrix, Basilisk ``gsHat_B``) and spin inertia ``J_s``:
    ``Omega_i = h_i / J_s - a_i . omega``, ``h_i = J_s (Omega_i + a_i . omega)``.

Inertia
    rpo's chaser inertia ``I_c`` (``chaser_inertia``, about the centre of mass) **excludes** the
    wheels' spin-axis inertia: the whole spacecraft's inertia is ``I_c + J_s sum_i a_i a_i^T`` and its
    angular momentum ``I_c omega + A h`` (symbolic/physics/rigid_body.py: ``I_c omega_dot = -omega x (I_c omega
    + A h) + ...``, ``dh/dt = -T``).  Basilisk's **balanced** wheels (``BalancedWheels``, 2.12.1) add
    neither mass nor inertia to the spacecraft (their ``updateEffectorMassProps`` is empty for that
    model; ``Jt``, ``Jg`` and the wheel mass are unused) but take ``Js gs gs^T`` OUT of the hub's
    inertia in the rotational equation, ``(I_hub - sum Js gs gs^T) omega_dot = ...``, with momentum
    ``I_hub omega + sum Js Omega_i gs_i``: Basilisk's hub inertia is the WHOLE spacecraft's,
    wheels included.  The mapping (:func:`basilisk_inertias`): **hub = I_c + J_s sum_i a_i a_i^T**,
    ``Js`` = rpo's ``wheel_inertia``, ``Jt = Jg = 0`` (rpo has no transverse rotor inertia; set so
    that a model that did use them would see rpo's wheel), hub mass = rpo's ``chaser_mass``.  Then
    Basilisk's momentum ``(I_c + J_s A A^T) omega + J_s A Omega`` is rpo's ``I_c omega + A h`` term by
    term, and Basilisk's gravity-gradient torque (which uses the spacecraft's inertia) is the one of
    the whole spacecraft.  tests/test_xcheck_basilisk.py checks this on Basilisk's own
    ``totRotAngMomPntC_N``; the mapping "hub = I_c" is off there by ``J_s A A^T omega``.

Relative translation
    rpo: ``r``, ``v`` of the chaser relative to the target in the target's LVLH frame L
    (X radial, Z orbit normal, Y = Z x X), ``v`` the L-frame derivative.  ECI:
    ``r_c = r_t + C_IL r``, ``v_c = v_t + C_IL (v + omega_L x r)``, with ``omega_L`` the frame's
    angular velocity in L axes (:func:`lvlh_rate`: ``h / r^2`` about Z, plus ``r a_h / h`` about X
    when a perturbing acceleration has a component ``a_h`` along the orbit normal).  Basilisk's
    two spacecraft are ECI states.

Units: SI everywhere except :data:`RPM` (Basilisk's RW factory and the issue's wheel targets).
"""

from __future__ import annotations

import math

import numpy as np

#: rad/s per rpm
RPM = 2.0 * math.pi / 60.0


# --------------------------------------------------------------------------- attitude


def _unit(q) -> np.ndarray:
    q = np.asarray(q, float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def dcm_from_quat(q) -> np.ndarray:
    """``C_{A<-B}`` of rpo's ``q_B_A`` (scalar last, Hamilton, ``v_A = q v_B q*``); normalises q."""
    x, y, z, w = _unit(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def quat_from_dcm(C) -> np.ndarray:
    """rpo's ``q_B_A`` (scalar last, ``w >= 0``) of ``C_{A<-B}`` (Shepperd: the largest component first)."""
    C = np.asarray(C, float)
    tr = np.trace(C)
    d = np.array([C[0, 0], C[1, 1], C[2, 2], tr])
    k = int(np.argmax(d))
    if k == 3:
        w = 0.5 * math.sqrt(1 + tr)
        q = np.array([(C[2, 1] - C[1, 2]) / (4 * w), (C[0, 2] - C[2, 0]) / (4 * w), (C[1, 0] - C[0, 1]) / (4 * w), w])
    else:
        i, j, m = k, (k + 1) % 3, (k + 2) % 3
        s = 0.5 * math.sqrt(1 + C[i, i] - C[j, j] - C[m, m])
        q = np.zeros(4)
        q[i] = s
        q[j] = (C[j, i] + C[i, j]) / (4 * s)
        q[m] = (C[m, i] + C[i, m]) / (4 * s)
        q[3] = (C[m, j] - C[j, m]) / (4 * s)
    return q if q[3] >= 0 else -q


def quat_to_ep(q) -> np.ndarray:
    """Basilisk's Euler parameters ``beta_BN`` (scalar first) of rpo's ``q_B/N`` (scalar last)."""
    x, y, z, w = _unit(q)
    return np.array([w, x, y, z])


def ep_to_quat(beta) -> np.ndarray:
    """rpo's ``q_B/N`` (scalar last) of Basilisk's ``beta_BN`` (scalar first)."""
    w, x, y, z = _unit(beta)
    return np.array([x, y, z, w])


def quat_to_mrp(q) -> np.ndarray:
    """Basilisk's ``sigma_BN`` (the set with ``|sigma| <= 1``) of rpo's ``q_B/N``."""
    q = _unit(q)
    if q[3] < 0:
        q = -q
    return q[:3] / (1.0 + q[3])


def mrp_to_quat(sigma) -> np.ndarray:
    """rpo's ``q_B/N`` (scalar last) of Basilisk's ``sigma_BN`` (either set: the shadow set gives -q)."""
    s = np.asarray(sigma, float)
    s2 = float(s @ s)
    return np.concatenate([2.0 * s, [1.0 - s2]]) / (1.0 + s2)


def mrp_shadow(sigma) -> np.ndarray:
    """The other MRP set of the same attitude, ``-sigma / |sigma|^2``."""
    s = np.asarray(sigma, float)
    return -s / float(s @ s)


def attitude_error(q_a, q_b) -> np.ndarray:
    """Angle [rad] of the rotation between two rpo quaternions (..., 4): ``2 atan2(|v|, |w|)`` of
    ``q_a* q_b``; blind to the sign of either (accurate near 0, unlike ``2 acos |w|``)."""
    a, b = _unit(q_a), _unit(q_b)
    av, aw, bv, bw = a[..., :3], a[..., 3:], b[..., :3], b[..., 3:]
    v = aw * bv - bw * av - np.cross(av, bv)
    w = np.sum(av * bv, axis=-1) + aw[..., 0] * bw[..., 0]
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=-1), np.abs(w))


# --------------------------------------------------------------------------- wheels and inertia


def pyramid_axes(beta: float) -> np.ndarray:
    """rpo's wheel axes A* (000 eq. 47, tilt ``wheel_beta``) as columns, body axes (Basilisk ``gsHat_B``)."""
    c, s = math.cos(beta), math.sin(beta)
    return np.array([[c, 0, -c, 0], [0, c, 0, -c], [s, s, s, s]])


def inertia_tensor(c) -> np.ndarray:
    """3 x 3 tensor of rpo's six-number inertia ``[xx, yy, zz, xy, xz, yz]`` (products as signed entries)."""
    xx, yy, zz, xy, xz, yz = np.asarray(c, float)
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], float)


def wheel_speeds(h, J_s: float, A, omega) -> np.ndarray:
    """Basilisk's ``Omega`` [rad/s, relative to the body] of rpo's absolute axial momenta ``h``."""
    return np.asarray(h, float) / J_s - np.asarray(A, float).T @ np.asarray(omega, float)


def wheel_momenta(Omega, J_s: float, A, omega) -> np.ndarray:
    """rpo's ``h`` [N m s] of Basilisk's relative wheel speeds ``Omega`` [rad/s]."""
    return J_s * (np.asarray(Omega, float) + np.asarray(A, float).T @ np.asarray(omega, float))


def basilisk_inertias(I_c, J_s: float, A) -> dict:
    """Basilisk's inertias for rpo's chaser with spin inertia ``J_s`` on the axes ``A`` (columns):
    ``hub`` (IHubPntBc_B) = I_c + J_s A A^T (the whole spacecraft), each balanced wheel ``Js`` = J_s,
    ``Jt = Jg = 0`` (see the module docstring).  ``J_s = 0``: no wheels, hub = I_c."""
    return {"hub": total_inertia(I_c, J_s, A), "Js": float(J_s), "Jt": 0.0, "Jg": 0.0}


def total_inertia(I_c, J_s: float, A) -> np.ndarray:
    """The whole chaser's inertia ``I_c + J_s sum_i a_i a_i^T`` (Basilisk's hub inertia, :func:`basilisk_inertias`)."""
    A = np.asarray(A, float)
    return np.asarray(I_c, float) + J_s * A @ A.T


def angular_momentum(I_c, A, h, omega) -> np.ndarray:
    """rpo's total angular momentum about the centre of mass, body axes: ``I_c omega + A h``."""
    return np.asarray(I_c, float) @ np.asarray(omega, float) + np.asarray(A, float) @ np.asarray(h, float)


# --------------------------------------------------------------------------- frames and relative state


def lvlh_dcm(r, v) -> np.ndarray:
    """``C_{ECI<-L}`` of the LVLH frame of the orbit state (r, v): columns X radial, Y = Z x X, Z normal."""
    r, v = np.asarray(r, float), np.asarray(v, float)
    x = r / np.linalg.norm(r)
    z = np.cross(r, v)
    z /= np.linalg.norm(z)
    return np.column_stack([x, np.cross(z, x), z])


#: ``C_{L<-R}`` of rpo's orbit reference frame R (000: X_R along-track = Y_L, Y_R = -Z_L, Z_R nadir = -X_L)
DCM_LVLH_FROM_ORBIT = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


def frame_dcm(frame: str, r, v) -> np.ndarray:
    """``C_{ECI<-F}`` of rpo's attitude frames ``"eci"``, ``"lvlh"``, ``"orbit"`` at the orbit state (r, v)."""
    if frame == "eci":
        return np.eye(3)
    C_IL = lvlh_dcm(r, v)
    if frame == "lvlh":
        return C_IL
    if frame == "orbit":
        return C_IL @ DCM_LVLH_FROM_ORBIT
    raise ValueError(f"unknown frame {frame!r}")


def lvlh_rate(r, v, a_perturb=None) -> np.ndarray:
    """Angular velocity of the LVLH frame relative to ECI, in L axes [rad/s].

    ``[r a_h / h, 0, h / r^2]``: the orbit normal turns about the radial axis when the perturbing
    acceleration ``a_perturb`` (ECI, not the central term) has a normal component ``a_h``.
    """
    r, v = np.asarray(r, float), np.asarray(v, float)
    hv = np.cross(r, v)
    h, rn = np.linalg.norm(hv), np.linalg.norm(r)
    a_h = 0.0 if a_perturb is None else float(np.asarray(a_perturb, float) @ hv) / h
    return np.array([rn * a_h / h, 0.0, h / rn**2])


def relative_to_inertial(r_t, v_t, r_rel, v_rel, a_perturb=None) -> tuple[np.ndarray, np.ndarray]:
    """The chaser's ECI (r_c, v_c) from rpo's LVLH (r, v) relative to the target at ECI (r_t, v_t)."""
    C = lvlh_dcm(r_t, v_t)
    w = lvlh_rate(r_t, v_t, a_perturb)
    r_rel, v_rel = np.asarray(r_rel, float), np.asarray(v_rel, float)
    return np.asarray(r_t, float) + C @ r_rel, np.asarray(v_t, float) + C @ (v_rel + np.cross(w, r_rel))


def inertial_to_relative(r_t, v_t, r_c, v_c, a_perturb=None) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`relative_to_inertial`: rpo's LVLH (r, v) of two ECI states."""
    C = lvlh_dcm(r_t, v_t)
    w = lvlh_rate(r_t, v_t, a_perturb)
    r_rel = C.T @ (np.asarray(r_c, float) - np.asarray(r_t, float))
    v_rel = C.T @ (np.asarray(v_c, float) - np.asarray(v_t, float)) - np.cross(w, r_rel)
    return r_rel, v_rel
