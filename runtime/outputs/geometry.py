"""The geometry the approach views draw (NumPy only): both bodies' attitudes in the LVLH frame, the
goal the controller steers to, in LVLH, and the target's keep-out sphere and the chaser's camera
cone, all from a run's columns (label -> 1-D array) and its parameters (name -> SI value).

Used by the figures (:mod:`rpo.runtime.outputs.views`, from the in-memory record) and by the run
page (:mod:`rpo.runtime.outputs.page`, from a results folder), so both draw the same thing.

Frames (:mod:`rpo.runtime.frames`): ``r`` is the chaser's centre relative to the target's, in the
target's LVLH frame L (x radial = R-bar, y along-track = V-bar, z orbit normal = cross-track);
``q_c``, ``q_t`` are the bodies' attitudes relative to ECI, ``meas_q_L`` the LVLH frame's.  The
constraints are 001's (``symbolic/physics/constraints.py``): the keep-out sphere is where the
envelope spheres touch, ``|r| = chaser_radius + target_radius`` (``beta_ca = 0``); the camera
looks along chaser body +z from the lens vertex ``(0, 0, camera_zn)`` with the half angle
``camera_half_angle``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from rpo.runtime.frames import dcm_from_quat

XYZ = ("x", "y", "z")
QUAT = ("x", "y", "z", "w")
#: which frame a controller's ``ctrl_pos_err`` is in, from its manifest description (the goal in
#: LVLH is ``r - C_{L<-F} pos_err``); an unknown frame gives no goal line
POS_ERR_FRAMES = (("LVLH", "lvlh"), ("target axes", "target"), ("chaser body axes", "chaser"))


def series(columns: Mapping[str, Any], name: str, comps: tuple[str, ...] = XYZ) -> np.ndarray | None:
    """The field ``name`` as an (N, len(comps)) array (``name_x``... or ``name_0``...), None if absent."""
    for labels in ([f"{name}_{c}" for c in comps], [f"{name}_{i}" for i in range(len(comps))]):
        if all(lbl in columns for lbl in labels):
            return np.column_stack([np.asarray(columns[lbl], float) for lbl in labels])
    return None


def param(params: Mapping[str, Any] | None, name: str) -> float | None:
    """A scalar parameter (the first entry of a vector one), None if not given."""
    if not params or name not in params:
        return None
    v = np.ravel(np.asarray(params[name], float))
    return float(v[0]) if v.size else None


def dcm(q: np.ndarray) -> np.ndarray:
    """``C_{A<-B}`` (N, 3, 3) of the quaternions ``q_B_A`` (N, 4, scalar last); NaN where a row is not
    a finite, non-zero quaternion (the final output row of a run has none)."""
    q = np.atleast_2d(np.asarray(q, float))
    out = np.full((len(q), 3, 3), np.nan)
    ok = np.all(np.isfinite(q), axis=1) & (np.linalg.norm(q, axis=1) > 0)
    if ok.any():
        out[ok] = dcm_from_quat(q[ok])
    return out


def _hold(x: np.ndarray) -> np.ndarray:
    """Rows that are not finite replaced by the previous finite row (a run's last output row)."""
    bad = ~np.all(np.isfinite(x.reshape(len(x), -1)), axis=1)
    if not bad.any() or bad.all():
        return x
    idx = np.where(~bad, np.arange(len(x)), 0)
    np.maximum.accumulate(idx, out=idx)
    first = int(np.argmax(~bad))
    idx[:first] = first
    return x[idx]


def _rot(axis: int, angle: np.ndarray) -> np.ndarray:
    """Active rotations about body axis ``axis`` (N, 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out = np.zeros((len(angle), 3, 3))
    out[:, axis, axis] = 1.0
    out[:, i, i], out[:, i, j], out[:, j, i], out[:, j, j] = c, -s, s, c
    return out


def kepler_lvlh(t: np.ndarray, params: Mapping[str, Any]) -> np.ndarray:
    """``C_{ECI<-LVLH}`` (N, 3, 3) on the Keplerian target orbit of ``params`` (``mu``, ``orbit_a``,
    ``orbit_e``, ``orbit_inc``, ``orbit_raan``, ``orbit_argp``, ``orbit_nu0``): R3(raan) R1(inc)
    R3(argp + nu(t)), as the plant (``symbolic/physics/orbit.py``)."""
    t = np.asarray(t, float)
    mu, a, e, inc, raan, argp, nu0 = (param(params, k) or 0.0 for k in (
        "mu", "orbit_a", "orbit_e", "orbit_inc", "orbit_raan", "orbit_argp", "orbit_nu0"))
    n_bar = np.sqrt(mu / a ** 3)
    E0 = 2.0 * np.arctan2(np.sqrt(1 - e) * np.sin(nu0 / 2), np.sqrt(1 + e) * np.cos(nu0 / 2))
    M = E0 - e * np.sin(E0) + n_bar * t
    E = M.copy()
    for _ in range(30):  # Newton; e < 1 converges in a few steps
        E = E - (E - e * np.sin(E) - M) / (1 - e * np.cos(E))
    beta = e / (1 + np.sqrt(1 - e * e))
    nu = E + 2 * np.arctan2(beta * np.sin(E), 1 - beta * np.cos(E))
    one = np.ones_like(t)
    return _rot(2, raan * one) @ _rot(0, inc * one) @ _rot(2, argp + nu)


def _frame_from_state(r_T: np.ndarray, v_T: np.ndarray) -> np.ndarray:
    """``C_{ECI<-LVLH}`` from the target's ECI position and velocity (x = r_hat, z = h_hat)."""
    x = r_T / np.linalg.norm(r_T, axis=1, keepdims=True)
    h = np.cross(r_T, v_T)
    z = h / np.linalg.norm(h, axis=1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=2)


def lvlh_frame(t: np.ndarray, columns: Mapping[str, Any], params: Mapping[str, Any] | None
               ) -> tuple[np.ndarray | None, str]:
    """(``C_{ECI<-LVLH}`` (N, 3, 3) or None, how it was found): the logged ``meas_q_L``, else (a
    propagated target orbit) the target state ``r_T``, ``v_T``, else identity in free space (``gravity_on = 0``), else
    the Keplerian orbit of the parameters (exact for the Keplerian target; for a propagated one
    whose state was not written, off by its J2 and drag drift: a fraction of a degree per orbit)."""
    q_L = series(columns, "meas_q_L", QUAT)
    if q_L is not None:
        return _hold(dcm(q_L)), "meas_q_L"
    if params is None:
        return None, "no LVLH attitude: meas_q_L not recorded and no parameters"
    r_T, v_T = series(columns, "r_T"), series(columns, "v_T")
    if param(params, "orbit_propagated") == 1.0 and r_T is not None and v_T is not None \
            and np.all(np.isfinite(r_T)) and np.all(np.linalg.norm(r_T, axis=1) > 0):
        return _frame_from_state(r_T, v_T), "r_T, v_T (the propagated target orbit)"
    if param(params, "gravity_on") == 0.0:
        return np.broadcast_to(np.eye(3), (len(t), 3, 3)).copy(), "free space: LVLH fixed in ECI"
    if param(params, "orbit_a") is None:
        return None, "no LVLH attitude: meas_q_L not recorded and no orbit parameters"
    how = "Keplerian orbit of the parameters"
    if param(params, "orbit_propagated") == 1.0:
        how += " (the run propagated J2 and drag: approximate)"
    return kepler_lvlh(t, params), how


def attitude_in_lvlh(columns: Mapping[str, Any], name: str, C_IL: np.ndarray | None) -> np.ndarray | None:
    """``C_{L<-B}`` (N, 3, 3) of the body whose ECI attitude is the field ``name`` (``q_c``, ``q_t``):
    its body axes, written in LVLH, as columns."""
    q = series(columns, name, QUAT)
    if q is None or C_IL is None:
        return None
    return np.swapaxes(C_IL, 1, 2) @ _hold(dcm(q))


def pos_err_frame(doc: str) -> str | None:
    """The frame of a ``ctrl_pos_err`` field from its description (:data:`POS_ERR_FRAMES`)."""
    return next((f for key, f in POS_ERR_FRAMES if key in doc), None)


def goal_lvlh(columns: Mapping[str, Any], r: np.ndarray, pos_err_doc: str | None, goal: np.ndarray | None,
              C_Lc: np.ndarray | None, C_Lt: np.ndarray | None) -> tuple[np.ndarray | None, str]:
    """(the goal position in LVLH over time (N, 3) or None, what it is).

    The goal is where the controller's position error vanishes: ``r - C_{L<-F} pos_err`` with F the
    frame of its ``ctrl_pos_err`` (:func:`pos_err_frame`); a constant LVLH goal (``r_goal``) is used
    as given.  Without a logged error, ``goal`` (LVLH) is used; else there is none."""
    e = series(columns, "ctrl_pos_err")
    frame = pos_err_frame(pos_err_doc or "") if e is not None else None
    if goal is not None and (e is None or frame == "lvlh"):
        return np.broadcast_to(np.ravel(goal)[:3], r.shape).copy(), "r_goal (LVLH)"
    if e is None or frame is None:
        return None, ""
    C = {"lvlh": None, "target": C_Lt, "chaser": C_Lc}[frame]
    if frame != "lvlh" and C is None:
        return None, ""
    e = _hold(e)
    g = r - (e if C is None else np.einsum("nij,nj->ni", C, e))
    return g, f"r - ctrl_pos_err ({'LVLH' if frame == 'lvlh' else frame + ' axes'})"


def keep_out_radius(params: Mapping[str, Any] | None) -> float | None:
    """The collision constraint's radius [m]: chaser_radius + target_radius (``beta_ca = 0``)."""
    rs, rt = param(params, "chaser_radius"), param(params, "target_radius")
    return None if rs is None or rt is None else rs + rt


def camera(params: Mapping[str, Any] | None) -> tuple[float, float] | None:
    """(half angle [rad], lens vertex on body +z [m]) of the chaser's camera, None if not given."""
    th, zn = param(params, "camera_half_angle"), param(params, "camera_zn")
    return None if th is None else (th, zn or 0.0)


def cone_lines(apex: np.ndarray, axis: np.ndarray, half_angle: float, length: float,
               n: int = 24, spokes: int = 8) -> np.ndarray:
    """A cone's outline as one polyline with NaN breaks (M, 3): the rim circle at ``length`` along
    the unit ``axis`` from ``apex`` and ``spokes`` lines from the apex to it."""
    axis = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    w = np.cross(axis, u)
    rho = length * np.tan(half_angle)
    a = np.linspace(0, 2 * np.pi, n + 1)
    rim = apex + length * axis + rho * (np.outer(np.cos(a), u) + np.outer(np.sin(a), w))
    gap = np.full((1, 3), np.nan)
    parts = [rim, gap]
    for k in range(spokes):
        parts += [apex[None, :], rim[(k * n) // spokes][None, :], gap]
    return np.concatenate(parts)


def sphere_mesh(radius: float, n: int = 16) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, z) (n, 2n) grids of a sphere of ``radius`` at the origin."""
    u = np.linspace(0, 2 * np.pi, 2 * n)
    v = np.linspace(0, np.pi, n)
    return (radius * np.outer(np.sin(v), np.cos(u)), radius * np.outer(np.sin(v), np.sin(u)),
            radius * np.outer(np.cos(v), np.ones_like(u)))


def sample_indices(n: int, k: int) -> np.ndarray:
    """Up to ``k`` row indices spread evenly over ``n`` rows, the first and the last included."""
    return np.unique(np.linspace(0, n - 1, min(n, k)).round().astype(int)) if n else np.zeros(0, int)
