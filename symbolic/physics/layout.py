"""Named, unit-carrying layouts of the vectors that cross the generated-code boundary.

A :class:`Layout` is an ordered list of fields (state, input, output or parameter blocks).  It
creates the SymPy symbols for its fields and describes itself for ``generated/manifest.json``,
from which the runtime learns names, sizes, units and parameter defaults without importing
anything from ``rpo.symbolic``.

A field may also declare its admissible values (:class:`Bounds`, SI), how a scenario file sets it
(:class:`ScenarioKey`: dotted TOML key, unit and scale) and the values it takes in named parameter
presets (``presets={"full": ...}``, the ``--plant full`` plant).  The runtime's scenario validation,
its error messages and the presets are derived from these entries; nothing about a parameter is
typed a second time in ``runtime/``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

XYZ = ("x", "y", "z")
XYZW = ("x", "y", "z", "w")


#: Kinds of scenario value (:attr:`ScenarioKey.kind`) and how each maps to the SI entries of a field.
SCENARIO_KINDS = {
    "number": "a number (size 1) or an array of `size` numbers; SI = scale * value",
    "switch": "true or false; SI = 1 or 0",
    "choice": "one of the strings of `choices`; SI = its number",
    "reciprocal": "a positive number; SI = scale / value (e.g. a rate in Hz for a step in s)",
    "inertia": "a symmetric, positive-definite 3x3 tensor; SI = its entries in the order of the labels",
}


@dataclass(frozen=True)
class Bounds:
    """Admissible values of every entry of a field, in the field's (SI) unit; None = unbounded.

    For a field set by a scenario value of kind ``"inertia"`` the bounds apply to the tensor's
    principal moments (its off-diagonal entries are bounded by them).  ``per_step``: a limit on
    ``|value| * dt`` (dt the step, s), for a rate or frequency the fixed step must resolve; checked
    by the runtime once the step is known.  ``why``: the reason for the range, one sentence (the
    manifest's ``bounds_why``; ``docs/parameters.md`` shows it).
    """

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    per_step: float | None = None
    why: str = ""

    def __post_init__(self):
        if self.lo is not None and self.hi is not None and not self.lo < self.hi:
            raise ValueError(f"bounds: lo = {self.lo} must be < hi = {self.hi}")
        if self.per_step is not None and not (math.isfinite(self.per_step) and self.per_step > 0):
            raise ValueError(f"bounds: per_step = {self.per_step} must be finite and > 0")

    def contains(self, v: float) -> bool:
        if not math.isfinite(v):
            return False
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return not (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi))

    def describe(self) -> dict:
        d: dict[str, Any] = {"lo": self.lo, "hi": self.hi, "lo_open": self.lo_open, "hi_open": self.hi_open}
        if self.per_step is not None:
            d["per_step"] = self.per_step
        return d


def principal_moments(entries: tuple[float, ...]) -> tuple[float, ...]:
    """Eigenvalues (ascending) of the symmetric tensor with entries (xx, yy, zz, xy, xz, yz) [kg m^2]."""
    xx, yy, zz, xy, xz, yz = entries
    lam = sp.Matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]).evalf().eigenvals(multiple=True)
    return tuple(sorted(float(sp.re(v)) for v in lam))


#: > 0 and >= 0, the two most common bounds.
POSITIVE = Bounds(0.0, lo_open=True)
NON_NEGATIVE = Bounds(0.0)


@dataclass(frozen=True)
class ScenarioKey:
    """How a scenario file sets a parameter field: ``key`` (dotted TOML path, e.g.
    ``"orbit.inclination_deg"``), the ``unit`` the value is written in (default: the field's SI
    unit), ``scale`` (SI value = scale * scenario value; e.g. pi / 180 for deg) and ``kind``
    (:data:`SCENARIO_KINDS`; ``choices`` maps the strings of a ``"choice"`` to their SI numbers)."""

    key: str
    unit: str | None = None
    scale: float = 1.0
    kind: str = "number"
    choices: tuple[tuple[str, float], ...] = ()

    def __post_init__(self):
        if self.kind not in SCENARIO_KINDS:
            raise ValueError(f"scenario key {self.key}: kind {self.kind!r} not in {sorted(SCENARIO_KINDS)}")
        if (self.kind == "choice") != bool(self.choices):
            raise ValueError(f"scenario key {self.key}: choices go with kind 'choice' (and only with it)")
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise ValueError(f"scenario key {self.key}: scale must be finite and > 0")

    def describe(self, si_unit: str) -> dict:
        d: dict[str, Any] = {"key": self.key, "kind": self.kind, "unit": self.unit or si_unit, "scale": self.scale}
        if self.choices:
            d["choices"] = {name: float(v) for name, v in self.choices}
        return d


@dataclass(frozen=True)
class Field:
    """One block of a vector: ``size`` entries named ``name_<component>``, in ``unit``.

    Optional: ``bounds`` (admissible values of each entry, SI), ``scenario`` (how a scenario file
    sets it) and ``presets`` (preset name -> the SI values the field takes in that preset).
    """

    name: str
    size: int
    unit: str
    doc: str
    components: tuple[str, ...] = ()
    default: tuple[float, ...] | None = None
    bounds: Bounds | None = None
    scenario: ScenarioKey | None = None
    presets: tuple[tuple[str, tuple[float, ...]], ...] = ()

    def labels(self) -> list[str]:
        if self.size == 1:
            return [self.name]
        comps = self.components or tuple(str(i) for i in range(self.size))
        if len(comps) != self.size:
            raise ValueError(f"{self.name}: {len(comps)} component names for size {self.size}")
        return [f"{self.name}_{c}" for c in comps]


@dataclass
class Layout:
    """Ordered fields with SymPy symbols for each entry."""

    name: str
    fields: list[Field] = field(default_factory=list)
    _symbols: dict[str, sp.Matrix] = field(default_factory=dict, repr=False)

    def add(self, name: str, size: int, unit: str, doc: str, components: tuple[str, ...] = (),
            default=None, *, bounds: Bounds | None = None, scenario: ScenarioKey | None = None,
            presets: dict[str, Any] | None = None) -> sp.Matrix | sp.Symbol:
        """Append a field and return its symbols (a Symbol when ``size == 1``).

        ``presets`` maps a preset name to the field's value in it (SI; ``"default"``: the default).
        """
        if name in self._symbols:
            raise ValueError(f"{self.name}: field {name} defined twice")

        def entries(v, what):
            out = tuple(float(x) for x in (v if hasattr(v, "__len__") else [v]))
            if len(out) != size:
                raise ValueError(f"{self.name}.{name}: {what} has {len(out)} entries, not {size}")
            return out

        if default is not None:
            default = entries(default, "default")
        preset_values = []
        for preset, value in (presets or {}).items():
            if isinstance(value, str) and value == "default":
                if default is None:
                    raise ValueError(f"{self.name}.{name}: preset {preset} = 'default' but no default")
                value = default
            preset_values.append((preset, entries(value, f"preset {preset}")))
        for what, values in [("default", default or ()), *preset_values]:
            if scenario is not None and scenario.kind == "inertia" and values:
                values = principal_moments(values)  # the bounds of an inertia are on its principal moments
            if bounds is not None and not all(bounds.contains(v) for v in values):
                raise ValueError(f"{self.name}.{name}: {what} {values} outside its bounds {bounds}")
        f = Field(name, size, unit, doc, components, default, bounds, scenario, tuple(preset_values))
        self.fields.append(f)
        syms = sp.Matrix([sp.Symbol(lbl, real=True) for lbl in f.labels()])
        self._symbols[name] = syms
        return syms[0] if size == 1 else syms

    def __getitem__(self, name: str):
        s = self._symbols[name]
        return s[0] if s.shape[0] == 1 else s

    @property
    def size(self) -> int:
        return sum(f.size for f in self.fields)

    def vector(self) -> sp.Matrix:
        """All symbols, in order, as one column."""
        if not self.fields:
            return sp.zeros(0, 1)
        return sp.Matrix.vstack(*[self._symbols[f.name] for f in self.fields])

    def pack(self, values: dict[str, sp.Matrix | sp.Basic]) -> sp.Matrix:
        """Stack expressions given per field name, in layout order."""
        blocks = []
        for f in self.fields:
            v = values[f.name]
            v = v if isinstance(v, sp.MatrixBase) else sp.Matrix([v])
            if v.shape != (f.size, 1):
                raise ValueError(f"{self.name}.{f.name}: shape {v.shape}, expected ({f.size}, 1)")
            blocks.append(v)
        missing = set(values) - {f.name for f in self.fields}
        if missing:
            raise ValueError(f"{self.name}: unknown fields {sorted(missing)}")
        return sp.Matrix.vstack(*blocks) if blocks else sp.zeros(0, 1)

    def offsets(self) -> dict[str, tuple[int, int]]:
        out, i = {}, 0
        for f in self.fields:
            out[f.name] = (i, i + f.size)
            i += f.size
        return out

    def describe(self) -> list[dict]:
        """JSON-ready description for the manifest."""
        out = []
        for f in self.fields:
            d = {"name": f.name, "size": f.size, "unit": f.unit, "doc": f.doc, "labels": f.labels()}
            if f.default is not None:
                d["default"] = list(f.default)
            if f.bounds is not None:
                d["bounds"] = f.bounds.describe()
                if f.bounds.why:
                    d["bounds_why"] = f.bounds.why
            if f.scenario is not None:
                d["scenario"] = f.scenario.describe(f.unit)
            if f.presets:
                d["presets"] = {preset: list(v) for preset, v in f.presets}
            out.append(d)
        return out
