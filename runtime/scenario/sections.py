"""The scenario's value types and static sections: the keys written here, not derived from the manifest.

Value types: a lower bound on a key that is not a manifest parameter (:func:`_range`), 3- and
4-vectors, unit quaternions (:data:`QUAT_TOL`), physical inertia tensors, and :func:`param_type`, the
pydantic type of a manifest parameter's scenario value (its kind and bounds, :mod:`.params`).
Sections: ``[meta]``, the run settings of ``[simulation]``, ``orbit.perigee_altitude``, the initial
state of ``[chaser]``, ``[target]`` and ``[relative]``, and ``[goal]`` (:mod:`.goals`).  ``[output]``
is in :mod:`.schema`; the sections of the parameters are made from the manifest there
(:class:`~.schema.ScenarioSchema`).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, cast

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PlainValidator,
    ValidationError,
    WrapValidator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from rpo.runtime.scenario.goals import GOAL_FRAMES, POSITION_LIMIT
from rpo.runtime.scenario.messages import field_error
from rpo.runtime.scenario.params import ScenarioParam
from rpo.runtime.scenario.units import DEG

#: Tolerance on |q| - 1 for a quaternion typed in a scenario (4 printed digits).
QUAT_TOL = 1e-3

# --------------------------------------------------------------------------- value types


def _range(lo: float, lo_open: bool = False, unit: str = "", what: str = "a number") -> WrapValidator:
    """A lower bound on a key that is not a manifest parameter; a wrong type, nan or inf is told the
    bound too (``must be a finite number > 0 s``)."""
    bound = f"{'>' if lo_open else '>='} {lo:g}" + (f" {unit}" if unit else "")

    def check(v, handler):
        if isinstance(v, float) and not math.isfinite(v):
            raise PydanticCustomError("range", f"must be a finite number {bound}")
        try:
            v = handler(v)
        except ValidationError:
            raise PydanticCustomError("range", f"must be {what} {bound}") from None
        if v <= lo if lo_open else v < lo:
            raise PydanticCustomError("range", f"must be {bound}")
        return v

    return WrapValidator(check)


Vec3 = Annotated[list[float], Field(min_length=3, max_length=3)]
Vec4 = Annotated[list[float], Field(min_length=4, max_length=4)]
Frame = Literal["eci", "lvlh", "orbit"]


def _unit_quaternion(q: list[float]) -> list[float]:
    n = math.sqrt(sum(c * c for c in q))
    if not abs(n - 1.0) <= QUAT_TOL:
        raise PydanticCustomError(
            "quaternion", f"must be a unit quaternion [x, y, z, w] (|q| = {n:.6g}; allowed ||q| - 1| <= {QUAT_TOL:g})")
    return [c / n for c in q]


Quaternion = Annotated[Vec4, AfterValidator(_unit_quaternion)]


def _physical_inertia(rows: list[list[float]]) -> list[list[float]]:
    return _physical_tensor(rows)[0]


def _physical_tensor(rows: list[list[float]]) -> tuple[list[list[float]], np.ndarray]:
    """A physical inertia tensor [kg m^2] (symmetric, positive definite, the triangle inequality of
    its principal moments) as nested lists, and the principal moments of the tensor as given
    (``np.linalg.eigvalsh`` of it, ascending: the parameter bounds check those)."""
    I = np.array(rows, dtype=float)
    scale = float(np.max(np.abs(I))) or 1.0
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if abs(I[i, j] - I[j, i]) > 1e-9 * scale:
            raise PydanticCustomError(
                "inertia", f"must be symmetric (row {i} column {j} is {I[i, j]:g}, row {j} column {i} is {I[j, i]:g})")
    sym = 0.5 * (I + I.T)
    lam = np.linalg.eigvalsh(sym)
    shown = ", ".join(f"{x:.6g}" for x in lam)
    if lam[0] <= 0:
        raise PydanticCustomError(
            "inertia", f"must be positive definite (principal moments {shown} kg m^2; all must be > 0)")
    if lam[0] + lam[1] < lam[2] * (1 - 1e-9):
        raise PydanticCustomError(
            "inertia", f"principal moments {shown} kg m^2 violate the triangle inequality I1 + I2 >= I3 "
                       "(not a physical body)")
    # an exactly symmetric tensor (every drawn one) is its own symmetric part: the same matrix,
    # the same moments, not decomposed twice
    moments = lam if sym.tobytes() == I.tobytes() else np.linalg.eigvalsh(I)
    return cast(list[list[float]], I.tolist()), moments


Inertia = Annotated[list[Vec3], Field(min_length=3, max_length=3), AfterValidator(_physical_inertia)]


def _inertia_check(prm: ScenarioParam):
    """An inertia parameter: a physical tensor (:func:`_physical_inertia`) whose principal moments
    are within the parameter's bounds."""
    iv = prm.bounds
    rng = f", principal moments {iv.text(prm.unit)}" if iv is not None else ""

    def check(v):
        rows = v if isinstance(v, list) and len(v) == 3 else None
        if rows is None or not all(isinstance(r, list) and len(r) == 3 and all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in r) for r in rows):
            raise PydanticCustomError("inertia", f"must be a symmetric 3x3 array of numbers ({prm.unit}){rng}")
        if not all(math.isfinite(float(x)) for r in rows for x in r):
            raise PydanticCustomError("inertia", f"must be finite numbers ({prm.unit}){rng}")
        tensor, moments = _physical_tensor([[float(x) for x in r] for r in rows])
        msg = prm.check_moments(moments.tolist())
        if msg is not None:
            raise PydanticCustomError("inertia", msg)
        return tensor

    return PlainValidator(check)


def param_type(prm: ScenarioParam) -> Any:
    """The pydantic type of the scenario value of a manifest parameter: its kind, finite, within its
    bounds (:meth:`ScenarioParam.check`: one message with the allowed values for every refusal)."""
    if prm.kind == "switch":
        return bool
    if prm.kind == "choice":
        return Literal[tuple(prm.choices)]  # type: ignore[valid-type]
    if prm.kind == "inertia":
        return Annotated[Any, _inertia_check(prm)]

    def check(v):
        msg = prm.check(v)
        if msg is not None:
            raise PydanticCustomError("range", msg)
        return v

    return Annotated[Any, PlainValidator(check)]


# --------------------------------------------------------------------------- static sections


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


class Meta(_Section):
    name: str | None = None
    description: str = ""
    source: str = ""


class SimulationSection(_Section):
    duration: Annotated[float, _range(0, lo_open=True, unit="s")]
    seed: Annotated[int, _range(0, what="an integer"), Field(le=2**64 - 1)] = 0
    controller: str = "baseline"
    record_every: Annotated[int, _range(1, what="an integer")] = 1


#: File formats of the time histories (``[output] formats``; ``rpo run --format``).


class Orbit(_Section):
    #: alternative to the semi-major axis: a = (R_E + perigee_altitude) / (1 - e)
    perigee_altitude: Annotated[float, _range(0, True, "m (a lower perigee is below the surface)")] | None = None


class _Body(_Section):
    attitude_frame: Frame
    quaternion: Quaternion
    angular_velocity: Vec3 | None = None
    angular_velocity_deg_s: Vec3 | None = None
    angular_velocity_relative_to: Literal["eci", "attitude_frame"] = "eci"

    @model_validator(mode="after")
    def _one_rate(self):
        if self.angular_velocity is not None and self.angular_velocity_deg_s is not None:
            raise field_error("angular_velocity_deg_s", self.angular_velocity_deg_s,
                              "give either angular_velocity (rad/s) or angular_velocity_deg_s, not both")
        return self

    def rate_rad_s(self) -> np.ndarray:
        """Angular velocity as given (relative to ``angular_velocity_relative_to``), rad/s, body axes."""
        if self.angular_velocity is not None:
            return np.array(self.angular_velocity, float)
        if self.angular_velocity_deg_s is not None:
            return np.array(self.angular_velocity_deg_s, float) * DEG
        return np.zeros(3)


class Chaser(_Body):
    wheel_momentum: Vec4 | None = None
    wheel_speed_rpm: Vec4 | None = None

    @model_validator(mode="after")
    def _one_wheel_state(self):
        if self.wheel_momentum is not None and self.wheel_speed_rpm is not None:
            raise field_error("wheel_speed_rpm", self.wheel_speed_rpm,
                              "give either wheel_momentum (N m s) or wheel_speed_rpm, not both")
        return self


class Target(_Body):
    pass


class Relative(_Section):
    position: Vec3
    velocity: Vec3



def _goal_position(v: list[float]) -> list[float]:
    if not all(abs(x) <= POSITION_LIMIT for x in v):
        raise PydanticCustomError("range", f"each component must be in [-{POSITION_LIMIT:g}, {POSITION_LIMIT:g}] m "
                                           "(the controllers' goal positions)")
    return v


class GoalSection(_Section):
    """``[goal]``: the pose the chaser is to reach and hold relative to the target (:mod:`.goals`).

    ``position`` [m]: the chaser's centre relative to the target's, in ``frame`` (``"target"``: the
    target's body axes; ``"lvlh"``: the target's LVLH frame); ``attitude``: the chaser's attitude
    relative to the target's body, [x, y, z, w]; ``camera_at_target``: require the camera (body +z)
    to point at the target there; ``contact``: a docking or capture goal, which may be inside the
    keep-out sphere (``[constraints]`` chaser_radius + target_radius)."""

    position: Annotated[Vec3, AfterValidator(_goal_position)]
    frame: Literal[tuple(GOAL_FRAMES)]  # type: ignore[valid-type]
    attitude: Quaternion
    camera_at_target: bool = False
    contact: bool = False
