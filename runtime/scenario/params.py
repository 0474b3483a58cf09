"""The parameters a scenario sets, as ``generated/manifest.json`` describes them.

Each field of layout ``p`` (and of a controller's gains ``k_<name>``) may carry, from
``symbolic/layout.py`` ``Layout.add``:

* ``bounds``: ``{"lo", "hi", "lo_open", "hi_open"}``, the admissible values of every entry, SI;
* ``scenario``: ``{"key", "kind", "unit", "scale"[, "choices"]}``, the dotted TOML key that sets
  it, the kind of value (``number``, ``switch``, ``choice``, ``reciprocal``, ``inertia``), the
  unit it is written in and the factor to SI (SI = scale * value; ``reciprocal``: scale / value);
* ``presets``: ``{"<preset>": [SI values]}``, the values it takes in a named preset
  (``full``: ``rpo run --plant full``).

:class:`ScenarioParam` turns one such entry into the conversion to SI, its inverse (for the
presets) and the check and error text of its bounds in the scenario's units.  Nothing here
knows a parameter by name.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Interval:
    """``lo``/``hi`` (None: unbounded), open or closed, in one unit."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False

    @classmethod
    def from_manifest(cls, d: dict | None) -> Interval | None:
        if not d:
            return None
        return cls(d.get("lo"), d.get("hi"), bool(d.get("lo_open")), bool(d.get("hi_open")))

    def contains(self, v: float) -> bool:
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return not (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi))

    def text(self, unit: str = "") -> str:
        """``in [0, 1)``, ``> 0 kg``, ``<= 5 m``: what an error message says is allowed."""
        u = f" {unit}" if unit and unit != "-" else ""
        if self.lo is not None and self.hi is not None:
            return f"in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}{')' if self.hi_open else ']'}{u}"
        if self.lo is not None:
            return f"{'>' if self.lo_open else '>='} {self.lo:g}{u}"
        if self.hi is not None:
            return f"{'<' if self.hi_open else '<='} {self.hi:g}{u}"
        return "any number"


@dataclass(frozen=True)
class ScenarioParam:
    """One manifest field with a ``scenario`` entry: how its scenario key maps to SI."""

    name: str                       # field of the layout (p)
    key: str                        # dotted scenario key
    kind: str                       # number | switch | choice | reciprocal | inertia
    unit: str                       # unit of the scenario value
    scale: float                    # SI = scale * value (reciprocal: scale / value)
    size: int
    labels: tuple[str, ...]
    default: tuple[float, ...] | None
    bounds: Interval | None         # SI
    choices: dict[str, float] = field(default_factory=dict)
    presets: dict[str, tuple[float, ...]] = field(default_factory=dict)

    @classmethod
    def from_manifest(cls, entry: dict) -> ScenarioParam:
        s = entry["scenario"]
        return cls(name=entry["name"], key=s["key"], kind=s.get("kind", "number"), unit=s.get("unit", entry["unit"]),
                   scale=float(s.get("scale", 1.0)), size=int(entry["size"]), labels=tuple(entry["labels"]),
                   default=tuple(entry["default"]) if "default" in entry else None,
                   bounds=Interval.from_manifest(entry.get("bounds")),
                   choices={k: float(v) for k, v in (s.get("choices") or {}).items()},
                   presets={k: tuple(float(x) for x in v) for k, v in (entry.get("presets") or {}).items()})

    # -- values ------------------------------------------------------------------------------

    def to_si(self, value: Any) -> float | np.ndarray:
        """The SI value(s) of a validated scenario value (a float when the field has one entry)."""
        if self.kind == "switch":
            return 1.0 if value else 0.0
        if self.kind == "choice":
            return self.choices[value]
        if self.kind == "reciprocal":
            return self.scale / float(value)
        if self.kind == "inertia":
            ax = {"x": 0, "y": 1, "z": 2}  # the component order is the labels' suffixes (_xx, _xy, ...)
            return np.array([value[ax[lbl[-2]]][ax[lbl[-1]]] for lbl in self.labels], float)
        if isinstance(value, list):
            return np.array(value, float) * self.scale
        return float(value) * self.scale

    def to_scenario(self, si: Sequence[float]) -> Any:
        """The scenario value giving the SI values ``si`` (the inverse of :meth:`to_si`)."""
        if self.kind == "switch":
            return bool(si[0])
        if self.kind == "choice":
            return next(k for k, v in self.choices.items() if v == si[0])
        if self.kind == "reciprocal":
            return self.scale / si[0]
        if self.kind == "inertia":
            ax = {"x": 0, "y": 1, "z": 2}
            tensor = [[0.0] * 3 for _ in range(3)]
            for lbl, v in zip(self.labels, si, strict=True):
                i, j = ax[lbl[-2]], ax[lbl[-1]]
                tensor[i][j] = tensor[j][i] = float(v)
            return tensor
        vals = [float(v) / self.scale for v in si]
        return vals[0] if self.size == 1 else vals

    # -- bounds ------------------------------------------------------------------------------

    def scenario_interval(self) -> Interval | None:
        """The bounds in the scenario's unit (for the error text)."""
        b = self.bounds
        if b is None:
            return None
        if self.kind == "reciprocal":  # value = scale / SI: the ends swap; SI > 0 keeps value > 0
            lo = self.scale / b.hi if b.hi is not None else 0.0
            hi = self.scale / b.lo if b.lo is not None and b.lo > 0 else None
            return Interval(lo, hi, b.hi_open if b.hi is not None else True, b.lo_open)
        return Interval(None if b.lo is None else b.lo / self.scale, None if b.hi is None else b.hi / self.scale,
                        b.lo_open, b.hi_open)

    def allowed(self) -> str:
        """``must be in [0, 180] deg``: the bound as an error message (empty if unbounded)."""
        iv = self.scenario_interval()
        return "" if iv is None else f"must be {iv.text(self.unit)}"

    def in_bounds(self, value: Any) -> bool:
        """Whether a scenario value of kind number/reciprocal is within the bounds.

        Compared in SI: the bound was computed in symbolic/ as ``value * scale`` with the same
        scale, so a value exactly at a closed bound (180 deg) is accepted.
        """
        if self.bounds is None:
            return True
        items = value if isinstance(value, list) else [value]
        if self.kind == "reciprocal" and not all(float(v) > 0 for v in items):
            return False
        si = np.ravel(self.to_si(value))
        return all(self.bounds.contains(float(v)) for v in si)


def scenario_params(manifest: dict, layout: str = "p") -> list[ScenarioParam]:
    """Every field of ``layout`` that a scenario sets, in layout order."""
    return [ScenarioParam.from_manifest(f) for f in manifest["layouts"][layout] if "scenario" in f]


def param(manifest: dict, name: str) -> ScenarioParam:
    """The scenario entry of p field ``name`` (for messages naming its key and unit)."""
    for f in manifest["layouts"]["p"]:
        if f["name"] == name and "scenario" in f:
            return ScenarioParam.from_manifest(f)
    raise KeyError(f"the manifest's layout p has no field {name} with a scenario key: run `python build.py`")


def manifest_defaults(manifest: dict, layout: str) -> dict[str, np.ndarray]:
    """Default values of a manifest layout by field name (as :meth:`Model.defaults`)."""
    return {f["name"]: np.array(f["default"], float) for f in manifest["layouts"][layout] if "default" in f}


def gain_bounds(entry: dict) -> Interval | None:
    """The bounds a controller module declared for one gain (SI, the gain's unit), if any."""
    return Interval.from_manifest(entry.get("bounds"))


def finite(values: Sequence[float]) -> bool:
    return all(math.isfinite(float(v)) for v in values)
