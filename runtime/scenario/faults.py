"""The scenario's ``[[faults]]`` array: fault events of the wheels, thrusters and sensors.

Each entry is one fault of one unit over a window in time::

    [[faults]]
    kind = "wheel_off"      # a kind of the manifest's fault vocabulary
    unit = 2                # a unit of the kind's family: a number, or a sensor's name
    time = 30.0             # s, when it starts
    end = 120.0             # s, optional: when it ends (default: never)
    value = 0.5             # only for the kinds that take one

The faults become runtime parameters (the window's ``start``/``end`` and the value's parameter of
each kind), so a fault needs no rebuild.  What a scenario may say is the manifest's fault vocabulary
(:class:`~rpo.runtime.model.manifest.FaultVocabulary`, declared once in ``symbolic/physics/faults.py``):
the kinds, their unit families, values, ranges, units and parameters, the sensors and ``never``.
Nothing here names a kind, a family or a sensor: the entry's class is made per manifest
(:func:`fault_model`), and the mapping to parameters and every message come from the vocabulary.
Nothing here models a fault either: this module only maps the table to those parameters and refuses
what cannot be flown, naming the entry.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, create_model, field_validator, model_validator
from pydantic_core import PydanticCustomError

from rpo.runtime.model.manifest import FaultFamily, FaultKind, FaultVocabulary, Manifest


def _err(kind: str, text: str) -> PydanticCustomError:
    return PydanticCustomError(kind, text)


def any_unit(vocabulary: FaultVocabulary) -> str:
    """Every family's units as a message names them: ``a wheel 1-4, a thruster 0-15 or a sensor name``."""
    parts = [f.what if f.first is not None else f"a {f.noun} name" for f in vocabulary.families.values()]
    return " or ".join([", ".join(parts[:-1]), parts[-1]]) if len(parts) > 1 else "".join(parts)


def actuator_families(vocabulary: FaultVocabulary) -> tuple[FaultFamily, ...]:
    """The families of actuators (the ideal actuators of 001/002/004 have no such units to fail)."""
    return tuple(f for f in vocabulary.families.values() if f.actuator)


class Fault(BaseModel):
    """One entry of ``[[faults]]`` (times in s, from the scenario's t = 0).

    The class validated is the manifest's (:func:`fault_model`): it carries the vocabulary and
    restricts ``kind`` to its kinds."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

    #: the manifest's fault vocabulary (set on the class :func:`fault_model` makes)
    vocabulary: ClassVar[FaultVocabulary] = FaultVocabulary()

    kind: str
    unit: int | str
    time: float
    end: float | None = None
    value: float | list[float] | None = None

    @field_validator("kind")
    @classmethod
    def _known_kind(cls, k: str) -> str:
        if k not in cls.vocabulary.kinds:  # only when the manifest declares no kind at all
            raise _err("kind", f"kind {k!r}: the generated model has no fault kinds")
        return k

    @field_validator("unit", mode="before")
    @classmethod
    def _unit_type(cls, u: Any, info: ValidationInfo) -> Any:
        # before the union is tried, so that a float or a boolean gets the family's message
        if isinstance(u, bool) or not isinstance(u, int | str):
            kind = info.data.get("kind")
            vocab = cls.vocabulary
            allowed = vocab.family(kind).what if kind in vocab.kinds else any_unit(vocab)
            raise _err("unit", f"unit = {u!r}: must be {allowed}")
        return u

    @model_validator(mode="after")
    def _check(self) -> Fault:
        never = self.vocabulary.never
        v = self.spec.value
        self.unit_index()  # raises for a unit of the wrong family
        if not 0.0 <= self.time < never:
            raise _err("range", f"time = {self.time:g} s: must be >= 0 s (and < {never:g} s)")
        if self.end is not None and not self.end < never:
            raise _err("range", f"end = {self.end:g} s: must be < {never:g} s (omit end for a fault that lasts)")
        if self.end is not None and not self.time < self.end:
            raise _err("range", f"end = {self.end:g} s: must be > time = {self.time:g} s")
        if v is None:
            if self.value is not None:
                raise _err("value", f"kind {self.kind} takes no value (got {self.value!r})")
            return self
        if self.value is None:
            raise _err("value", f"kind {self.kind} needs a value: {v.what}")
        if v.shape != 1:
            if not (isinstance(self.value, list) and len(self.value) == v.shape) or (
                    v.range is not None and not all(v.range.contains(x) for x in self.value)):
                raise _err("value", f"value = {self.value!r}: must be {v.what}")
        elif isinstance(self.value, list):
            raise _err("value", f"value = {self.value!r}: must be one number, {v.what}")
        elif v.range is not None and not v.range.contains(self.value):
            raise _err("range", f"value = {self.value:g}: must be {v.what}"
                       + (f" (use kind {v.none} for none)" if v.none is not None and self.value == 0 else ""))
        return self

    @property
    def spec(self) -> FaultKind:
        """The kind's declaration."""
        return self.vocabulary.kinds[self.kind]

    @property
    def family(self) -> FaultFamily:
        """The unit family of the kind."""
        return self.vocabulary.family(self.kind)

    def unit_index(self) -> int:
        """Index of the unit within its family's parameter vector."""
        family = self.family
        i = family.index(self.unit)
        if i is None:
            raise _err("unit", f"unit = {self.unit!r}: kind {self.kind} needs {family.what}")
        return i

    def unit_name(self) -> str:
        return self.family.units[self.unit_index()]

    def value_unit(self) -> tuple[float, str]:
        """(scale, unit) of the value a scenario writes: SI value = scale x value (a fixed unit, or the
        sensor's own, e.g. deg for the attitude sensor)."""
        v = self.spec.value
        if v is not None and v.unit is None:
            sensor = self.vocabulary.sensors[self.unit_name()]
            return sensor.scale, sensor.unit
        return 1.0, "" if v is None or v.unit is None else v.unit


def _fault_model(manifest: Manifest) -> type[Fault]:
    vocab = manifest.faults
    kinds = tuple(vocab.kinds)
    fields: dict[str, Any] = {"kind": (Literal[kinds], ...)} if kinds else {}
    model = create_model("Fault", __base__=Fault, __module__=__name__, **fields)
    model.vocabulary = vocab
    return model


def fault_model(manifest: Manifest) -> type[Fault]:
    """The ``[[faults]]`` entry of ``manifest`` (its kinds and vocabulary; made once, kept with it)."""
    return manifest.derived(_fault_model)


def faults_field(manifest: Manifest) -> tuple[Any, Any]:
    """The ``faults`` field of a scenario validated against ``manifest`` (pydantic's field definition)."""
    entry: Any = fault_model(manifest)
    return list[entry], Field(default_factory=list)


class FaultConflict(ValueError):
    """Two faults the model cannot represent together: ``index`` of the second, ``message``."""

    def __init__(self, index: int, message: str):
        super().__init__(message)
        self.index = index
        self.message = message


def fault_params(faults: list[Fault], defaults: Mapping[str, Any]) -> dict[str, list[float]]:
    """The p fields the faults set (SI), from the manifest ``defaults`` (p field -> array).

    Raises FaultConflict(index, message) for two faults of one kind on one unit (a window per kind
    and unit is what the model has).
    """
    out: dict[str, list[float]] = {}
    seen: dict[tuple[str, int], int] = {}

    def vec(name: str) -> list[float]:
        if name not in out:
            out[name] = [float(v) for v in defaults[name]]
        return out[name]

    for n, f in enumerate(faults):
        spec = f.spec
        i = f.unit_index()
        if (f.kind, i) in seen:
            raise FaultConflict(n, f"a second {f.kind} fault of unit {f.unit!r} (faults[{seen[f.kind, i]}] is "
                                   "the first): one window per kind and unit")
        seen[f.kind, i] = n
        vec(spec.start)[i] = float(f.time)
        vec(spec.end)[i] = float(f.vocabulary.never if f.end is None else f.end)
        v = spec.value
        if v is None or f.value is None:
            continue
        scale = f.value_unit()[0]
        values = f.value if isinstance(f.value, list) else [f.value]
        if v.vector is not None:  # one parameter over the family's units: this unit's entry
            vec(v.vector)[i] = scale * float(values[0])
        else:  # a parameter of the unit's own, set whole
            out[v.fields[f.unit_name()]] = [scale * float(x) for x in values]
    return out


def fault_value_unit(f: Fault) -> tuple[float, str]:
    """(scale, unit) of the value a scenario writes: SI value = scale x value (:meth:`Fault.value_unit`)."""
    return f.value_unit()


def describe(faults: list[Fault]) -> list[dict[str, Any]]:
    """The faults as JSON-ready records (for run.json and the figures' markers)."""
    return [{"kind": f.kind, "unit": f.unit, "unit_name": f.unit_name(), "time": f.time,
             "end": f.end, "value": f.value} for f in faults]


def active_faults(vocabulary: FaultVocabulary, params: Mapping[str, Any], t_end: float) -> list[tuple[float, str]]:
    """(start time, "kind unit") of every fault window in ``params`` (p fields, SI) that opens at
    a step starting before ``t_end`` (the last step starts at t_end - dt), sorted by time: what a
    run's figures mark and its verdict lists.  ``vocabulary``: the manifest's (``Manifest.faults``)."""
    dt = float(np.ravel(params["dt"])[0]) if "dt" in params else 0.0
    t_end = t_end - dt * (1 - 1e-9)
    out = []
    for kind, spec in vocabulary.kinds.items():
        start = params.get(spec.start)
        if start is None:
            continue
        units = vocabulary.families[spec.family].units
        for i, s in enumerate(np.ravel(np.asarray(start, float))):
            if s < vocabulary.never and s <= t_end:
                out.append((float(s), f"{kind} {units[i]}"))
    return sorted(out)
