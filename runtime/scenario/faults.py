"""The scenario's ``[[faults]]`` array: fault events of the wheels, thrusters and sensors.

Each entry is one fault of one unit over a window in time::

    [[faults]]
    kind = "wheel_off"      # see KINDS
    unit = 2                # wheel 1-4, thruster 0-15, or sensor "attitude"/"rate"/"position"/"velocity"
    time = 30.0             # s, when it starts
    end = 120.0             # s, optional: when it ends (default: never)
    value = 0.5             # only for the kinds that need one (see KINDS)

The faults become runtime parameters (``fault_<unit>_<kind>_start``/``_end`` and the values, of
``symbolic/physics/faults.py``), so a fault needs no rebuild.  Nothing here models a fault: this module
only maps the table to those parameters and refuses what cannot be flown, naming the entry.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationInfo, field_validator, model_validator
from pydantic_core import PydanticCustomError

#: Window edge meaning "never" (``symbolic/physics/faults.py`` NEVER, the manifest default of every window).
NEVER = 1e30
DEG = math.pi / 180.0

WHEELS = ("1", "2", "3", "4")
THRUSTERS = tuple(f"{j:02d}" for j in range(16))
#: sensor name -> (its name in the parameters, the unit a scenario writes its values in, SI scale)
SENSORS = {"attitude": ("att", "deg", DEG), "rate": ("rate", "deg/s", DEG), "position": ("pos", "m", 1.0),
           "velocity": ("vel", "m/s", 1.0)}

#: kind -> (unit family, parameter kind, what ``value`` is or None when the kind takes none)
KINDS: dict[str, tuple[str, str, str | None]] = {
    "wheel_off": ("wheel", "off", None),
    "wheel_weak": ("wheel", "weak", "the fraction of the torque limit left, 0 < value <= 1"),
    "wheel_stuck": ("wheel", "stuck", None),
    "thruster_off": ("thr", "off", None),
    "thruster_stuck_on": ("thr", "stuck_on", None),
    "thruster_weak": ("thr", "weak", "the fraction of the thrust left, 0 < value <= 1"),
    "sensor_bias": ("sensor", "bias", "the bias step [x, y, z] in the sensor's unit (deg, deg/s, m, m/s)"),
    "sensor_freeze": ("sensor", "freeze", None),
    "sensor_noise": ("sensor", "noise", "the noise standard deviation, >= 0, in the sensor's unit"),
}
FAMILY_UNITS = {"wheel": "a wheel 1-4", "thr": "a thruster 0-15",
                "sensor": "a sensor " + ", ".join(f'"{s}"' for s in SENSORS)}


def _err(kind: str, text: str) -> PydanticCustomError:
    return PydanticCustomError(kind, text)


class Fault(BaseModel):
    """One entry of ``[[faults]]`` (times in s, from the scenario's t = 0)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

    kind: Literal[tuple(KINDS)]  # type: ignore[valid-type]
    unit: int | str
    time: float
    end: float | None = None
    value: float | list[float] | None = None

    @field_validator("unit", mode="before")
    @classmethod
    def _unit_type(cls, u: Any, info: ValidationInfo) -> Any:
        # before the union is tried, so that a float or a boolean gets the family's message
        if isinstance(u, bool) or not isinstance(u, int | str):
            kind = info.data.get("kind")
            family = KINDS[kind][0] if kind in KINDS else None
            allowed = FAMILY_UNITS[family] if family else "a wheel 1-4, a thruster 0-15 or a sensor name"
            raise _err("unit", f"unit = {u!r}: must be {allowed}")
        return u

    @model_validator(mode="after")
    def _check(self) -> Fault:
        family, _k, value_doc = KINDS[self.kind]
        self.unit_index()  # raises for a unit of the wrong family
        if not 0.0 <= self.time < NEVER:
            raise _err("range", f"time = {self.time:g} s: must be >= 0 s (and < {NEVER:g} s)")
        if self.end is not None and not self.end < NEVER:
            raise _err("range", f"end = {self.end:g} s: must be < {NEVER:g} s (omit end for a fault that lasts)")
        if self.end is not None and not self.time < self.end:
            raise _err("range", f"end = {self.end:g} s: must be > time = {self.time:g} s")
        if value_doc is None:
            if self.value is not None:
                raise _err("value", f"kind {self.kind} takes no value (got {self.value!r})")
            return self
        if self.value is None:
            raise _err("value", f"kind {self.kind} needs a value: {value_doc}")
        if self.kind == "sensor_bias":
            if not (isinstance(self.value, list) and len(self.value) == 3):
                raise _err("value", f"value = {self.value!r}: must be {value_doc}")
        elif isinstance(self.value, list):
            raise _err("value", f"value = {self.value!r}: must be one number, {value_doc}")
        elif self.kind == "sensor_noise":
            if self.value < 0:
                raise _err("range", f"value = {self.value:g}: must be {value_doc}")
        elif not 0.0 < self.value <= 1.0:
            raise _err("range", f"value = {self.value:g}: must be {value_doc}"
                       + (f" (use kind {self.kind.replace('weak', 'off')} for none)" if self.value == 0 else ""))
        return self

    @property
    def family(self) -> str:
        return KINDS[self.kind][0]

    def unit_index(self) -> int:
        """Index of the unit within its family's parameter vector."""
        family = self.family
        u = self.unit
        if family == "sensor":
            if isinstance(u, str) and u in SENSORS:
                return list(SENSORS).index(u)
        elif isinstance(u, int) and not isinstance(u, bool):
            lo, hi = (1, 4) if family == "wheel" else (0, 15)
            if lo <= u <= hi:
                return u - lo
        raise _err("unit", f"unit = {u!r}: kind {self.kind} needs {FAMILY_UNITS[family]}")

    def unit_name(self) -> str:
        i = self.unit_index()
        return {"wheel": WHEELS, "thr": THRUSTERS, "sensor": tuple(SENSORS)}[self.family][i]


def fault_params(faults: list[Fault], defaults: dict[str, Any]) -> dict[str, list[float]]:
    """The p fields the faults set (SI), from the manifest ``defaults`` (p field -> array).

    Raises ValueError(index, message) for two faults of one kind on one unit (a window per kind
    and unit is what the model has).
    """
    out: dict[str, list[float]] = {}
    seen: dict[tuple[str, int], int] = {}

    def vec(name: str) -> list[float]:
        if name not in out:
            out[name] = [float(v) for v in defaults[name]]
        return out[name]

    for n, f in enumerate(faults):
        family, kind, _ = KINDS[f.kind]
        i = f.unit_index()
        if (f.kind, i) in seen:
            raise FaultConflict(n, f"a second {f.kind} fault of unit {f.unit!r} (faults[{seen[f.kind, i]}] is "
                                   "the first): one window per kind and unit")
        seen[f.kind, i] = n
        vec(f"fault_{family}_{kind}_start")[i] = float(f.time)
        vec(f"fault_{family}_{kind}_end")[i] = float(NEVER if f.end is None else f.end)
        if f.kind == "wheel_weak":
            vec("fault_wheel_weak_value")[i] = float(f.value)  # type: ignore[arg-type]
        elif f.kind == "thruster_weak":
            vec("fault_thr_weak_value")[i] = float(f.value)  # type: ignore[arg-type]
        elif f.kind in ("sensor_bias", "sensor_noise"):
            short, _unit, scale = SENSORS[str(f.unit)]
            if f.kind == "sensor_bias":
                out[f"fault_bias_{short}"] = [scale * float(v) for v in f.value]  # type: ignore[union-attr]
            else:
                out[f"fault_noise_{short}_std"] = [scale * float(f.value)]  # type: ignore[arg-type]
    return out


def fault_value_unit(f: Fault, si_unit: str) -> tuple[float, str]:
    """(scale, unit) of the value a scenario writes: SI value = scale x value (deg and deg/s for
    the attitude and rate sensors)."""
    if f.family == "sensor":
        _short, unit, scale = SENSORS[str(f.unit)]
        return scale, unit
    return 1.0, si_unit


class FaultConflict(ValueError):
    """Two faults the model cannot represent together: ``index`` of the second, ``message``."""

    def __init__(self, index: int, message: str):
        super().__init__(message)
        self.index = index
        self.message = message


def describe(faults: list[Fault]) -> list[dict[str, Any]]:
    """The faults as JSON-ready records (for run.json and the figures' markers)."""
    return [{"kind": f.kind, "unit": f.unit, "unit_name": f.unit_name(), "time": f.time,
             "end": f.end, "value": f.value} for f in faults]


def active_faults(params: Mapping[str, Any], t_end: float) -> list[tuple[float, str]]:
    """(start time, "kind unit") of every fault window in ``params`` (p fields, SI) that opens at
    a step starting before ``t_end`` (the last step starts at t_end - dt), sorted by time: what a
    run's figures mark and its verdict lists."""
    names = {"wheel": WHEELS, "thr": THRUSTERS, "sensor": tuple(SENSORS)}
    dt = float(np.ravel(params["dt"])[0]) if "dt" in params else 0.0
    t_end = t_end - dt * (1 - 1e-9)
    out = []
    for kind, (family, k, _v) in KINDS.items():
        start = params.get(f"fault_{family}_{k}_start")
        if start is None:
            continue
        for i, s in enumerate(np.ravel(np.asarray(start, float))):
            if s < NEVER and s <= t_end:
                out.append((float(s), f"{kind} {names[family][i]}"))
    return sorted(out)

