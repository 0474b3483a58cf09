"""Named, unit-carrying layouts of the vectors that cross the generated-code boundary.

A :class:`Layout` is an ordered list of fields (state, input, output or parameter blocks).  It
creates the SymPy symbols for its fields and describes itself for ``generated/manifest.json``,
from which the runtime learns names, sizes, units and parameter defaults without importing
anything from ``rpo.symbolic``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

XYZ = ("x", "y", "z")
XYZW = ("x", "y", "z", "w")


@dataclass(frozen=True)
class Field:
    """One block of a vector: ``size`` entries named ``name_<component>``, in ``unit``."""

    name: str
    size: int
    unit: str
    doc: str
    components: tuple[str, ...] = ()
    default: tuple[float, ...] | None = None

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
            default=None) -> sp.Matrix | sp.Symbol:
        """Append a field and return its symbols (a Symbol when ``size == 1``)."""
        if name in self._symbols:
            raise ValueError(f"{self.name}: field {name} defined twice")
        if default is not None:
            default = tuple(float(v) for v in (default if hasattr(default, "__len__") else [default]))
            if len(default) != size:
                raise ValueError(f"{self.name}.{name}: default has {len(default)} entries, not {size}")
        f = Field(name, size, unit, doc, components, default)
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
            out.append(d)
        return out
