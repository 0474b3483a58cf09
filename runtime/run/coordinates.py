"""The reduced coordinates of a closed-loop step state, in which :mod:`.linearize` states its Jacobians.

Reduced coordinates (``docs/linearization.md``).  Each unit quaternion of z (``q_c``, ``q_t``,
both relative to ECI) is replaced by its body-axes rotation vector relative to the point of
linearisation ``q0``::

    q = q0 ⊗ exp(dth),    exp(dth) = [sin(|dth|/2) dth/|dth|, cos(|dth|/2)]   (scalar last, Hamilton)
    dth = log(q0* ⊗ q),   log([v, w]) = 2 atan2(|v|, w) v/|v| after the sign makes w >= 0

(``dth`` is scipy's ``(R0.inv() * R).as_rotvec()``).  Their tangent maps at dth = 0 are
``E(q0) = d q / d dth = 1/2 L(q0) [I3; 0]`` (4x3) and ``E+(q0) = d dth / d q = 2 [I3 0] L(q0*)``
(3x4), with ``L(a)`` the left-multiplication matrix ``a ⊗ b = L(a) b``; ``E+ E = I3`` and
``E+ q0 = 0``.  The step Jacobian in reduced coordinates is the chain rule (exact, at the
point)::

    A = P_out(z_next0) @ dF/dz(z0) @ P_in(z0),     z_next0 = F(z0)

with ``P_in`` holding ``E(q0)`` and ``P_out`` holding ``E+(q_next0)`` on the quaternion blocks,
identities elsewhere, and the permutation into the groups below.  Perturbations after the step are
taken relative to the nominal next state, so A is the one-step variational map also where z0 is
not a fixed point (a tumbling target).

Groups (contiguous, in this order): ``chaser`` (dth_c, w_c), ``target`` (dth_t, w_t),
``translation`` (r, v), ``actuators`` (wheel momenta h_w, propellant m_prop, the wheel-command
delay line, the PWPF prefilters and the thruster on-levels), ``controller`` (the design's states).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.frames import quat_conjugate, quat_multiply
from rpo.runtime.model.manifest import LayoutField

#: The attitude fields of z replaced by rotation vectors (the controllers' own layouts keep none).
QUATERNIONS = ("q_c", "q_t")
#: Reduced-coordinate groups: name -> z fields (``dth_c``/``dth_t`` for the quaternions); every
#: field not named here belongs to ``actuators`` (plant) or ``controller`` (``xc_*``).
RIGID_GROUPS = {"chaser": ("q_c", "w_c"), "target": ("q_t", "w_t"), "translation": ("r", "v")}
GROUP_ORDER = ("chaser", "target", "translation", "actuators", "controller")

# --------------------------------------------------------------------------- quaternion maps


def left_matrix(a: np.ndarray) -> np.ndarray:
    """L(a) with a ⊗ b = L(a) b (scalar last)."""
    x, y, z, w = a
    return np.array([[w, -z, y, x],
                     [z, w, -x, y],
                     [-y, x, w, z],
                     [-x, -y, -z, w]])


def quat_exp(dth: np.ndarray) -> np.ndarray:
    """The unit quaternion of the rotation vector ``dth`` (angle |dth| about dth/|dth|)."""
    dth = np.asarray(dth, float)
    a = float(np.linalg.norm(dth))
    s = 0.5 - a * a / 48 if a < 1e-6 else math.sin(a / 2) / a   # sin(a/2)/a, series near 0
    return np.concatenate([s * dth, [math.cos(a / 2)]])


def quat_log(q: np.ndarray) -> np.ndarray:
    """The rotation vector of ``q`` (any norm > 0; the sign of q is chosen so that w >= 0, the
    shorter rotation, angle in [0, pi])."""
    q = np.asarray(q, float)
    v, w = (q[:3], q[3]) if q[3] >= 0 else (-q[:3], -q[3])
    s = float(np.linalg.norm(v))
    if s == 0.0:
        return np.zeros(3)
    return 2.0 * math.atan2(s, w) * v / s


def retract(q0: np.ndarray, dth: np.ndarray) -> np.ndarray:
    """q = q0 ⊗ exp(dth): the attitude rotated by dth in the body axes of q0."""
    return quat_multiply(q0, quat_exp(dth))


def local(q0: np.ndarray, q: np.ndarray) -> np.ndarray:
    """dth = log(q0* ⊗ q), the inverse of :func:`retract` (for |dth| < pi)."""
    return quat_log(quat_multiply(quat_conjugate(q0), q))


def retract_tangent(q0: np.ndarray) -> np.ndarray:
    """E(q0) = d retract(q0, dth) / d dth at dth = 0 (4x3): 1/2 L(q0) [I3; 0]."""
    return 0.5 * left_matrix(np.asarray(q0, float))[:, :3]


def local_tangent(q0: np.ndarray) -> np.ndarray:
    """E+(q0) = d local(q0, q) / d q at q = q0 (3x4): 2 [I3 0] L(q0*) (unit q0)."""
    return 2.0 * left_matrix(quat_conjugate(q0))[:3, :]


# --------------------------------------------------------------------------- reduced coordinates


@dataclass
class Coordinates:
    """The map between the packed step state z of one controller and the reduced coordinates.

    ``order``: for each reduced coordinate, the z field it comes from and its index there;
    ``labels``/``units``: of the reduced coordinates; ``groups``: name -> slice (contiguous).
    """

    z_fields: Sequence[LayoutField]
    labels: list[str] = field(default_factory=list)
    units: list[str] = field(default_factory=list)
    groups: dict[str, slice] = field(default_factory=dict)
    blocks: list[tuple[str, slice, slice]] = field(default_factory=list)  # (field, z slice, xi slice)

    def __post_init__(self):
        offs, i = {}, 0
        for f in self.z_fields:
            offs[f.name] = slice(i, i + f.size)
            i += f.size
        self.nz = i
        self.z_labels = [lbl for f in self.z_fields for lbl in f.labels]
        by_group: dict[str, list[LayoutField]] = {g: [] for g in GROUP_ORDER}
        owner = {name: g for g, names in RIGID_GROUPS.items() for name in names}
        for f in self.z_fields:
            g = owner.get(f.name, "controller" if f.name.startswith("xc_") else "actuators")
            by_group[g].append(f)
        missing = [q for q in QUATERNIONS if q not in offs]
        if missing:
            raise ModelError(f"state layout has no {', '.join(missing)}")
        j = 0
        for g in GROUP_ORDER:
            start = j
            for f in by_group[g]:
                if f.name in QUATERNIONS:
                    body = f.name.split("_", 1)[1]
                    lbl, unit, n = [f"dth_{body}_{a}" for a in "xyz"], ["rad"] * 3, 3
                else:
                    lbl, unit, n = list(f.labels), [f.unit] * f.size, f.size
                self.blocks.append((f.name, offs[f.name], slice(j, j + n)))
                self.labels += lbl
                self.units += unit
                j += n
            self.groups[g] = slice(start, j)
        self.n = j

    def tangent_in(self, z0: np.ndarray) -> np.ndarray:
        """P_in = dz/dxi at xi = 0 around z0 (nz x n)."""
        P = np.zeros((self.nz, self.n))
        for name, zs, xs in self.blocks:
            P[zs, xs] = retract_tangent(z0[zs]) if name in QUATERNIONS else np.eye(zs.stop - zs.start)
        return P

    def tangent_out(self, z0: np.ndarray) -> np.ndarray:
        """P_out = dxi/dz at z = z0 (n x nz); P_out @ P_in = I."""
        P = np.zeros((self.n, self.nz))
        for name, zs, xs in self.blocks:
            P[xs, zs] = local_tangent(z0[zs]) if name in QUATERNIONS else np.eye(zs.stop - zs.start)
        return P

    def to_z(self, z0: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """The state z at reduced coordinates xi around z0 (the exact map, not its tangent)."""
        z = np.array(z0, float)
        for name, zs, xs in self.blocks:
            z[zs] = retract(z0[zs], xi[xs]) if name in QUATERNIONS else z0[zs] + xi[xs]
        return z

    def to_xi(self, z0: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The reduced coordinates of z around z0 (inverse of :meth:`to_z`)."""
        xi = np.zeros(self.n)
        for name, zs, xs in self.blocks:
            xi[xs] = local(z0[zs], z[zs]) if name in QUATERNIONS else z[zs] - z0[zs]
        return xi

    def indices(self, *names: str) -> list[int]:
        """Reduced indices of z fields (a quaternion field gives its rotation vector)."""
        out: list[int] = []
        for name, _zs, xs in self.blocks:
            if name in names:
                out += list(range(xs.start, xs.stop))
        return out

    def group_of(self, i: int) -> str:
        return next(g for g, s in self.groups.items() if s.start <= i < s.stop)
