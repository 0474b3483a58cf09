"""The parameters a scenario sets, as ``generated/manifest.json`` describes them.

Each field of layout ``p`` (and of a controller's gains ``k_<name>``) may carry, from
``symbolic/physics/layout.py`` ``Layout.add`` (typed in :mod:`rpo.runtime.model.manifest`,
:class:`~rpo.runtime.model.manifest.LayoutField`):

* ``bounds``: an :class:`Interval`, the admissible values of every entry, SI;
* ``scenario``: a :class:`~rpo.runtime.model.manifest.ScenarioKey`, the dotted TOML key that sets
  it, the kind of value (``number``, ``switch``, ``choice``, ``reciprocal``, ``inertia``), the
  unit it is written in and the factor to SI (SI = scale * value; ``reciprocal``: scale / value);
* ``presets``: preset name -> the SI values it takes in that preset (``full``: ``rpo run --plant full``).

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

from rpo.runtime.model.manifest import Interval, LayoutField, Manifest

__all__ = ["Interval", "ScenarioParam", "finite", "manifest_defaults"]


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
    def from_field(cls, f: LayoutField) -> ScenarioParam:
        """The parameter of a layout field that has a scenario key."""
        s = f.scenario
        if s is None:
            raise ValueError(f"layout field {f.name} has no scenario key")
        return cls(name=f.name, key=s.key, kind=s.kind, unit=s.unit, scale=s.scale, size=f.size, labels=f.labels,
                   default=f.default, bounds=f.bounds, choices=dict(s.choices), presets=dict(f.presets))

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
        if iv is None:
            return ""
        return f"must be {iv.text(self.unit)}" + (" (principal moments)" if self.kind == "inertia" else "")

    def value_text(self) -> str:
        """What a value of this parameter is: ``a number``, ``an array of 3 numbers``."""
        if self.kind == "inertia":
            return "a symmetric 3x3 array of numbers"
        return "a number" if self.size == 1 else f"an array of {self.size} numbers"

    def check(self, value: Any) -> str | None:
        """None if ``value`` (as typed in a scenario) is admissible, else why not: ONE message with the
        allowed values, for a wrong type, a wrong length, nan or inf, or a value out of bounds.
        Kinds ``number`` and ``reciprocal`` (``inertia``: see :meth:`check_moments`)."""
        items = value if isinstance(value, list) else [value]
        if (self.size == 1) == isinstance(value, list) or not all(_is_number(x) for x in items):
            return f"must be {self.value_text()}{self._allowed_text()}"
        if len(items) != self.size:
            return f"must have {self.size} values, got {len(items)}"
        if not finite(items):
            return f"must be {'a finite number' if self.size == 1 else 'finite numbers'}{self._allowed_text()}"
        if not self.in_bounds(value):
            iv = self.scenario_interval()
            assert iv is not None
            bad = next(float(x) for x in items if not self.in_bounds(float(x)))
            return iv.refusal(bad, self.unit)
        return None

    def _allowed_text(self) -> str:
        """`` in [0, 180] deg`` (the bounds), or `` (deg)`` (the unit of an unbounded value)."""
        iv = self.scenario_interval()
        if iv is not None:
            return f" {iv.text(self.unit)}"
        return f" ({self.unit})" if self.unit not in ("", "-") else ""

    def check_moments(self, moments: Sequence[float]) -> str | None:
        """For kind ``inertia``: None if the principal moments [kg m^2] are within the bounds."""
        if self.bounds is None or all(self.bounds.contains(float(m)) for m in moments):
            return None
        shown = ", ".join(f"{m:.6g}" for m in moments)
        return f"principal moments {shown} {self.unit}: each must be {self.bounds.text(self.unit)}"

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
        if not isinstance(value, list):  # one number: to_si gives a float (np.ravel of it: the same)
            return self.bounds.contains(float(self.to_si(value)))
        si = np.ravel(self.to_si(value))
        return all(self.bounds.contains(float(v)) for v in si)


def manifest_defaults(manifest: Manifest, layout: str, copy: bool = True) -> dict[str, np.ndarray]:
    """Default values of a manifest layout by field name (as :meth:`Model.defaults`), a new dict.

    ``copy=True``: new arrays, the caller may change them.  ``copy=False``: the parsed defaults
    themselves, read-only arrays (``manifest.layouts[layout].defaults``), for readers."""
    d = manifest.layouts[layout].defaults
    return {k: v.copy() for k, v in d.items()} if copy else dict(d)


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def finite(values: Sequence[float]) -> bool:
    return all(math.isfinite(float(v)) for v in values)

