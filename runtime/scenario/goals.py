"""A scenario's goal, and how each controller flies it (or why it cannot).

**The goal** (:class:`Goal`) is the pose of the chaser relative to the target that a run is to
reach and hold: the position of the chaser's centre relative to the target's, fixed in a named
frame (``"target"``: the target's body axes, so the point turns with the target; ``"lvlh"``: the
target's LVLH frame), and the chaser's attitude relative to the target's body (``q_S/T``, scalar
last, docs/conventions.md), held with no relative motion.  It is the scenario's: a ``[goal]``
table states it (:class:`~.sections.GoalSection`); a scenario without one states it through the
goal gains of its own controller (``[controller.<name>]`` and that controller's defaults), as
before the table existed.  ``rpo run --controller X`` keeps the scenario's goal and maps it into
X's goal gains (:func:`fly`), or refuses in one line when X's design cannot hold it.

**The designs** (:data:`DESIGNS`, one entry per controller): which gains hold the goal, in which
frame, and what the design fixes.  The papers' designs differ:

* ``baseline``, ``c000``: a point fixed in LVLH (``r_goal``); the attitude is always 000's
  interface frame, the target's axes turned 180 deg about x (their attitude error is 000's q_e,
  eq. 22), so any other attitude is refused;
* ``c001``: any pose fixed in the target's axes (``r_D``, ``q_D``), provided its potential
  (001 eq. 53) has its minimum there: the target in the camera's cone and the envelope spheres
  apart at the goal (``beta_FOV > 0``, ``beta_CA > 0`` with its own gains, 001 eqs. 41, 47);
* ``c002``, ``c004``: a point fixed in the target's axes (``sigma_t``, ``p_t``); the attitude is
  always the target's own axes (their attitude errors are the chaser's attitude relative to the
  target: 002 eq. 1, 004 eqs. 10, 12).

A position goal in the other frame is refused (a point fixed in LVLH is not fixed in the axes of
a rotating target), except the origin, which is the same point in both.  A controller with no
entry here (a new module, docs/architecture.md "Adding a controller") flies its own goal gains,
and the goal it flies says so.  ``tests/test_goal.py`` checks each entry against the generated
model: after :func:`fly`, the controller's own errors are zero at the scenario's goal pose.

Pure NumPy over the manifest's gain names.  The checks of a goal against the scenario are in
:func:`.checks.check_goal`: a ``[goal]`` inside the keep-out sphere (``[constraints]``
chaser_radius + target_radius) is refused unless ``contact = true``; a goal stated by gains there
(c000's and the baseline's default ``r_goal`` is the target's centre) is flown as before and
flagged (:attr:`GoalFlown.warning`); ``camera_at_target`` is checked.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rpo.runtime import frames

#: The frames a goal's position may be fixed in, and how a message names each.
GOAL_FRAMES = {"target": "target axes", "lvlh": "LVLH"}
#: Largest |component| of a goal position [m]: the controllers' goal gains' range (100 km).
POSITION_LIMIT = 1e5
#: Two attitudes closer than this [rad] are the same goal (a design's fixed attitude; a gain that
#: restates the goal).
ANGLE_TOL = 1e-6
#: "Camera at the target": the camera axis (chaser body +z) within this angle [rad] of the
#: direction to the target's centre (a quaternion typed with 4 digits is within 1e-4 rad).
CAMERA_TOL = 1e-3
#: Two positions closer than this [m] (plus 1e-12 relative) are the same goal.
POSITION_TOL = 1e-9

Q_IDENTITY = (0.0, 0.0, 0.0, 1.0)
#: 000's interface frame relative to the target's body: 180 deg about x_T (000 eqs. 15-16).
Q_INTERFACE = (1.0, 0.0, 0.0, 0.0)
#: The names of the attitudes some designs fix.
ATTITUDE_NAMES = {Q_IDENTITY: "the chaser's axes along the target's",
                  Q_INTERFACE: "the chaser's axes on 000's interface frame (the target's turned 180 deg about x)"}


class GoalRefusal(Exception):
    """A controller cannot fly a goal; the message says why (one line, no key)."""


# --------------------------------------------------------------------------- geometry


def attitude_angle(a: Any, b: Any) -> float:
    """Angle of the rotation between two attitudes [rad], in [0, pi] (q and -q alike)."""
    d = frames.quat_multiply(frames.quat_conjugate(frames.quat_normalize(a)), frames.quat_normalize(b))
    return 2.0 * math.atan2(float(np.linalg.norm(d[:3])), abs(float(d[3])))


def target_in_chaser_axes(position_T: Any, attitude: Any) -> np.ndarray:
    """The target's centre seen from the chaser, in chaser axes [m]: ``-C_{S<-T} r^T`` for the
    chaser at ``position_T`` (target axes) with ``attitude`` = q_S/T (001's p_TS = -r^S)."""
    return -(frames.dcm_from_quat(attitude).T @ np.asarray(position_T, float))


def camera_angle(position_T: Any, attitude: Any) -> float | None:
    """Angle between the camera axis (chaser body +z) and the direction to the target's centre
    [rad]; None at the target's centre."""
    p = target_in_chaser_axes(position_T, attitude)
    n = float(np.linalg.norm(p))
    return None if n == 0.0 else math.atan2(math.hypot(p[0], p[1]), p[2])


def camera_margin(p_TS: np.ndarray, half_angle: float, z_N: float, R_T: float) -> float:
    """001 eq. 41 (the plant's ``beta_fov``, symbolic/physics/constraints.py) [m]: > 0 when the
    target's envelope sphere is inside the camera's cone."""
    return float(p_TS[2] - math.hypot(p_TS[0], p_TS[1]) / math.tan(half_angle) - (z_N + R_T / math.sin(half_angle)))


def keep_out_margin(p_TS: np.ndarray, R_S: float, R_T: float) -> float:
    """001 eq. 47 (the plant's ``beta_ca``) [m^2]: > 0 when the envelope spheres are apart."""
    return float(p_TS @ p_TS - (R_S + R_T) ** 2)


def _vec(v: Any, fmt: str = "g") -> str:
    return "(" + ", ".join(format(float(x) + 0.0, fmt) for x in np.ravel(v)) + ")"


# --------------------------------------------------------------------------- the goal


@dataclass(frozen=True)
class Goal:
    """A scenario's goal: ``position`` [m] of the chaser relative to the target in ``frame``
    (:data:`GOAL_FRAMES`), ``attitude`` q_S/T (scalar last), ``contact`` (a docking or capture
    goal, allowed inside the keep-out sphere), ``camera_at_target`` (the scenario requires the
    camera on the target there), ``source``: where the scenario states it, and ``stated``: True
    for a ``[goal]`` table, False for a goal stated by a controller's goal gains (as before the
    table existed: not refused inside the keep-out sphere, only flagged)."""

    position: tuple[float, float, float]
    frame: str
    attitude: tuple[float, float, float, float]
    contact: bool = False
    camera_at_target: bool = False
    source: str = ""
    stated: bool = True

    def camera_on_target(self) -> bool:
        """The camera (body +z) points at the target's centre at the goal (target-axes goals only:
        in LVLH where the camera points turns with the target)."""
        if self.frame != "target":
            return False
        a = camera_angle(self.position, self.attitude)
        return a is not None and a <= CAMERA_TOL

    def attitude_text(self) -> str:
        named = next((name for q, name in ATTITUDE_NAMES.items() if attitude_angle(q, self.attitude) <= ANGLE_TOL),
                     None)
        q = f"q_S/T = {_vec(self.attitude, '.6g')} (x, y, z, w)"
        if self.camera_on_target():
            return f"camera at the target, {q}"
        return f"{named}, {q}" if named else f"chaser attitude {q}"

    def text(self) -> str:
        """``hold r = (50, 0, 0) m in target axes, camera at the target (q_S/T = ...), from ...``."""
        what = "contact at" if self.contact else "hold"
        src = f", from {self.source}" if self.source else ""
        return f"{what} r = {_vec(self.position)} m in {GOAL_FRAMES[self.frame]}, {self.attitude_text()}{src}"

    def table(self) -> dict[str, Any]:
        """The goal as a scenario's ``[goal]`` table writes it."""
        out: dict[str, Any] = dict(position=[float(x) for x in self.position], frame=self.frame,
                                   attitude=[float(x) for x in self.attitude])
        flags = (("contact", self.contact), ("camera_at_target", self.camera_at_target))
        out.update({k: True for k, on in flags if on})
        return out


# --------------------------------------------------------------------------- the designs


@dataclass(frozen=True)
class GoalDesign:
    """How one controller holds a goal: the gain of its position goal (``position_gain``, a point
    fixed in ``frame``), the gain of its attitude goal (``attitude_gain``, q_S/T) or the attitude
    its design always drives to (``fixed_attitude``, with ``fixed_why``), and ``check``: a
    further condition of the design on a goal and its gains (``gain(name)``; a refusal's text, or None)."""

    frame: str
    position_gain: str
    attitude_gain: str | None = None
    fixed_attitude: tuple[float, float, float, float] | None = None
    fixed_why: str = ""
    check: Callable[[Goal, Callable[[str], Any]], str | None] | None = field(default=None, compare=False)

    @property
    def gains(self) -> tuple[str, ...]:
        """The goal gains, position first."""
        return (self.position_gain,) + ((self.attitude_gain,) if self.attitude_gain else ())


def _c001_potential_minimum(goal: Goal, k: Callable[[str], Any]) -> str | None:
    """001's potential (eq. 53) has an admissible minimum only where both of its constraints hold
    with its own geometry gains (the camera cone and the envelope spheres, eqs. 41, 47)."""
    def g(name: str) -> float:
        return float(np.ravel(k(name))[0])

    p = target_in_chaser_axes(goal.position, goal.attitude)
    fov = camera_margin(p, g("theta"), g("z_N"), g("R_T"))
    ca = keep_out_margin(p, g("R_S"), g("R_T"))
    if fov > 0 and ca > 0:
        return None
    bad = [f"beta_FOV = {fov:.4g} m" if fov <= 0 else "", f"beta_CA = {ca:.4g} m^2" if ca <= 0 else ""]
    return ("its potential (001 eq. 53) has its minimum only where the target is in its camera's cone and the "
            "envelope spheres are apart (beta_FOV > 0, beta_CA > 0 with its gains theta, z_N, R_S, R_T), and at "
            f"this goal {' and '.join(b for b in bad if b)}")


_INTERFACE_WHY = "its attitude error, 000's q_e of eq. 22, is to 000's interface frame"
_C002_WHY = "its attitude error, 002's Q~ of eq. 1, is the chaser's attitude relative to the target's axes"
_C004_WHY = ("its attitude error, the MRPs sigma_e of 004 eqs. 10 and 12, is the chaser's attitude relative to the "
             "target's axes")

#: The controllers' goal coordinates (module docstring); checked against the manifest by tests/test_goal.py.
DESIGNS: dict[str, GoalDesign] = {
    "baseline": GoalDesign("lvlh", "r_goal", fixed_attitude=Q_INTERFACE, fixed_why=_INTERFACE_WHY),
    "c000": GoalDesign("lvlh", "r_goal", fixed_attitude=Q_INTERFACE, fixed_why=_INTERFACE_WHY),
    "c001": GoalDesign("target", "r_D", attitude_gain="q_D", check=_c001_potential_minimum),
    "c002": GoalDesign("target", "sigma_t", fixed_attitude=Q_IDENTITY, fixed_why=_C002_WHY),
    "c004": GoalDesign("target", "p_t", fixed_attitude=Q_IDENTITY, fixed_why=_C004_WHY),
}


def derive(controller: str, gain: Callable[[str], Any], source: str = "") -> Goal | None:
    """The goal that ``controller``'s goal gains (``gain(name)``) state (a scenario without
    ``[goal]``); None for a controller with no entry in :data:`DESIGNS`."""
    d = DESIGNS.get(controller)
    if d is None:
        return None
    pos = tuple(float(x) for x in np.ravel(gain(d.position_gain)))
    att = d.fixed_attitude if d.attitude_gain is None else tuple(float(x) for x in np.ravel(gain(d.attitude_gain)))
    return Goal(position=pos, frame=d.frame, attitude=att, source=source, stated=False)  # type: ignore[arg-type]


def fly(goal: Goal, controller: str, gain: Callable[[str], Any]) -> dict[str, np.ndarray]:
    """``controller``'s goal gains for ``goal`` (``gain(name)``: its other gains, for the design's
    own check); raises :class:`GoalRefusal` with the reason when its design cannot hold the goal.
    A controller with no entry in :data:`DESIGNS` gets no goal gains ({}): it flies its own."""
    d = DESIGNS.get(controller)
    if d is None:
        return {}
    pos = np.array(goal.position, float)
    why = []
    if goal.frame != d.frame and np.any(pos != 0.0):
        why.append(f"its position goal ({d.position_gain}) is a point fixed in {GOAL_FRAMES[d.frame]}, and this "
                   f"goal's is fixed in {GOAL_FRAMES[goal.frame]} (the two frames turn relative to each other)")
    out = {d.position_gain: pos}
    if d.attitude_gain is not None:
        out[d.attitude_gain] = np.array(goal.attitude, float)
    elif d.fixed_attitude is not None:
        off = attitude_angle(d.fixed_attitude, goal.attitude)
        if off > ANGLE_TOL:
            why.append(f"its design always holds {ATTITUDE_NAMES[d.fixed_attitude]} ({d.fixed_why}), and this "
                       f"goal's attitude is {math.degrees(off):.4g} deg from that")
    if not why and d.check is not None:
        reason = d.check(goal, lambda name: out[name] if name in out else gain(name))
        if reason is not None:
            why.append(reason)
    if why:
        raise GoalRefusal("; and ".join(why))
    return out


def same_gain(name: str, a: Any, b: Any) -> bool:
    """Whether two values of a goal gain state the same goal (an attitude: the same rotation, same sign)."""
    a, b = np.ravel(np.asarray(a, float)), np.ravel(np.asarray(b, float))
    if a.shape != b.shape:
        return False
    if a.size == 4 and any(name == d.attitude_gain for d in DESIGNS.values()):
        return float(np.dot(a, b)) > 0 and attitude_angle(a, b) <= ANGLE_TOL
    return bool(np.all(np.abs(a - b) <= POSITION_TOL + 1e-12 * np.abs(b)))


# --------------------------------------------------------------------------- the goal flown


@dataclass(frozen=True)
class GoalFlown:
    """What a run flies: the scenario's ``goal`` (None: rpo cannot tell it), the ``controller``
    flown, its goal ``gains`` for that goal, ``mapped`` (False: a controller with no entry in
    :data:`DESIGNS`, flying its own goal gains) and ``warning`` (a goal stated by gains inside the
    keep-out sphere: :func:`~.checks.check_goal`)."""

    controller: str
    goal: Goal | None
    gains: Mapping[str, np.ndarray]
    mapped: bool
    warning: str = ""

    def text(self) -> str:
        """One line naming the goal flown (``rpo run``, ``rpo validate``, the verdict)."""
        if self.mapped and self.goal is not None:
            return self.goal.text() + (f" (WARNING: {self.warning})" if self.warning else "")
        where = "runtime/scenario/goals.py"
        if self.goal is None:
            return (f"{self.controller}'s own goal gains (rpo has no goal description of {self.controller} ({where}) "
                    "and the scenario no [goal] table)")
        return (f"{self.controller}'s own goal gains, NOT mapped from the scenario's goal ({self.goal.text()}): "
                f"rpo has no goal mapping for {self.controller} ({where})")

    def record(self) -> dict[str, Any]:
        """JSON-ready (``run.json``: ``inputs.goal``)."""
        g = self.goal
        return {"text": self.text(), "controller": self.controller, "mapped": self.mapped, "warning": self.warning,
                "gains": {k: np.ravel(v).tolist() for k, v in self.gains.items()},
                **({} if g is None else {**g.table(), "contact": g.contact, "camera_at_target": g.camera_at_target,
                                         "camera_on_target": g.camera_on_target(), "source": g.source})}
