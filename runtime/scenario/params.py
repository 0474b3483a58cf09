"""The parameters a scenario sets, as ``generated/manifest.json`` describes them.

Each field of layout ``p`` (and of a controller's gains ``k_<name>``) may carry, from
``symbolic/physics/layout.py`` ``Layout.add``:

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
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Interval:
    """``lo``/``hi`` (None: unbounded), open or closed, in one unit; ``per_step``: a limit on
    ``|value| * dt`` (a rate the fixed step must resolve), checked once the step is known."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    per_step: float | None = None

    @classmethod
    def from_manifest(cls, d: dict | None) -> Interval | None:
        if not d:
            return None
        per_step = d.get("per_step")
        return cls(d.get("lo"), d.get("hi"), bool(d.get("lo_open")), bool(d.get("hi_open")),
                   None if per_step is None else float(per_step))

    def contains(self, v: float) -> bool:
        """Whether ``v`` is inside (never for nan or +-inf)."""
        if not math.isfinite(v):
            return False
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

    def refusal(self, v: float, unit: str = "") -> str:
        """Why ``v`` is refused (it is not inside): ``must be in [0.01, 1e+07] kg``; a value of the
        wrong sign is told its sign first (``must be > 0 kg (allowed range [0.01, 1e+07] kg)``)."""
        full = self.text(unit)
        if self.lo is not None and self.lo > 0 and math.isfinite(v) and v <= 0:
            # the range starts above 0 (a magnitude): the sign is the first thing wrong
            return f"must be > 0{f' {unit}' if unit and unit != '-' else ''} (allowed range {full.removeprefix('in ')})"
        return f"must be {full}"

    def step_limit(self, dt: float) -> float | None:
        """The largest |value| the step ``dt`` [s] resolves (None: no such limit)."""
        return None if self.per_step is None else self.per_step / dt


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


#: Manifests declared unchanging (:func:`unchanging`): id -> (the manifest, its parsed entries).
_FROZEN: dict[int, tuple[dict, dict]] = {}


@contextmanager
def unchanging(manifest: dict) -> Iterator[None]:
    """Within this block ``manifest`` is not edited, so what is read from it is parsed once: a
    campaign validates thousands of scenarios against its model's manifest.  Outside such a block
    every call reads the manifest afresh (a test may edit one in place and validate again)."""
    key = id(manifest)
    outer = key in _FROZEN
    if not outer:
        _FROZEN[key] = (manifest, {})
    try:
        yield
    finally:
        if not outer:
            _FROZEN.pop(key, None)


def frozen_cache(manifest: dict) -> dict | None:
    """The parse cache of a manifest inside :func:`unchanging`, else None."""
    hit = _FROZEN.get(id(manifest))
    return hit[1] if hit is not None and hit[0] is manifest else None


def _cached(manifest: dict, what: tuple, make):
    cache = frozen_cache(manifest)
    if cache is None:
        return make()
    if what not in cache:
        cache[what] = make()
    return cache[what]


def scenario_params(manifest: dict, layout: str = "p") -> list[ScenarioParam]:
    """Every field of ``layout`` that a scenario sets, in layout order (a new list; the entries
    are frozen)."""
    fields = manifest["layouts"][layout]
    return list(_cached(manifest, ("params", layout),
                        lambda: [ScenarioParam.from_manifest(f) for f in fields if "scenario" in f]))


def param(manifest: dict, name: str) -> ScenarioParam:
    """The scenario entry of p field ``name`` (for messages naming its key and unit)."""
    hit = _cached(manifest, ("param", name), lambda: _find_param(manifest, name))
    if hit is None:
        raise KeyError(f"the manifest's layout p has no field {name} with a scenario key: run `python build.py`")
    return hit


def _find_param(manifest: dict, name: str) -> ScenarioParam | None:
    for f in manifest["layouts"]["p"]:
        if f["name"] == name and "scenario" in f:
            return ScenarioParam.from_manifest(f)
    return None


def manifest_defaults(manifest: dict, layout: str, copy: bool = True) -> dict[str, np.ndarray]:
    """Default values of a manifest layout by field name (as :meth:`Model.defaults`).

    ``copy=True``: a new dict of new arrays, the caller may change them.  ``copy=False``: the
    parsed defaults themselves, read-only arrays (for readers: a campaign reads them a few times
    per run)."""
    fields = manifest["layouts"][layout]

    def make() -> dict[str, np.ndarray]:
        out = {f["name"]: np.array(f["default"], float) for f in fields if "default" in f}
        for v in out.values():
            v.flags.writeable = False
        return out

    d = _cached(manifest, ("defaults", layout), make)
    return {k: v.copy() for k, v in d.items()} if copy else d


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def gain_bounds(entry: dict) -> Interval | None:
    """The bounds a controller module declared for one gain (SI, the gain's unit), if any."""
    return Interval.from_manifest(entry.get("bounds"))


def layout_fields(manifest: dict, layout: str) -> dict[str, tuple[dict, Interval | None]]:
    """field name -> (its manifest entry, its bounds (SI) or None), in layout order (parsed once
    inside :func:`unchanging`; a read-only mapping for the validators)."""
    fields = manifest["layouts"][layout]
    return _cached(manifest, ("fields", layout),
                   lambda: {f["name"]: (f, Interval.from_manifest(f.get("bounds"))) for f in fields})


def finite(values: Sequence[float]) -> bool:
    return all(math.isfinite(float(v)) for v in values)

