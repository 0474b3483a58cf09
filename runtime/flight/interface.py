"""What an exported controller reads and writes: its structs, named from the manifest's layouts.

A controller's generated step ``control_<name>(meas, xc, t, p, k) -> (cmd, xc_next, diag)`` is the
export's algorithm.  Its flat vectors become named C structs:

* inputs: ``t`` (the sample time, s) and the fields of the measurement (layout ``meas``) the law reads;
* params: ``gains`` (every field of layout ``k_<name>``) and ``model`` (the fields of the plant's
  parameters, layout ``p``, the law reads: e.g. the sample period ``dt`` its own integration uses);
* state: the controller's own states (layout ``xc_<name>``) and a step counter;
* outputs: the command (``tau_w``, ``F``, ``tau_thr``: the fields of the closed loop's ``cmd_*``
  outputs) and the diagnostics ``diag`` (layout ``diag_<name>``).

:class:`Interface` also says how each struct maps to the simulation's vectors (``offset`` of a member
in its source vector), which the test vectors and the processor-in-the-loop use; the flat order of a
struct (``<prefix>_<struct>_from_array`` / ``_to_array``) is its members' order.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.manifest import Layout, Manifest

_C_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_RESERVED = {"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum",
             "extern", "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return",
             "short", "signed", "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void",
             "volatile", "while", "steps"}


@dataclass(frozen=True)
class Member:
    """One named member of a struct: ``size`` values (an array when > 1) in ``unit``, taken from
    ``source`` (a vector of the simulation) at ``offset``."""

    name: str
    size: int
    unit: str
    doc: str
    labels: tuple[str, ...]
    source: str
    offset: int


@dataclass(frozen=True)
class Group:
    """Members that travel together (one flat array); ``path`` is their C access prefix (``"gains."``)."""

    name: str
    path: str
    members: tuple[Member, ...]

    @property
    def size(self) -> int:
        return sum(m.size for m in self.members)


@dataclass(frozen=True)
class Interface:
    """The four structs of one export (each a tuple of groups, in flat order)."""

    controller: str
    prefix: str
    inputs: tuple[Group, ...]
    params: tuple[Group, ...]
    state: tuple[Group, ...]
    outputs: tuple[Group, ...]
    has_start: bool
    function: str
    start_function: str | None
    sources: dict[str, int] = field(default_factory=dict)   # simulation vector -> its size

    def size(self, struct: str) -> int:
        return sum(g.size for g in getattr(self, struct))

    def members(self, struct: str) -> Iterator[tuple[Group, Member]]:
        for g in getattr(self, struct):
            for m in g.members:
                yield g, m

    def gather(self, struct: str, vectors: dict[str, np.ndarray]) -> np.ndarray:
        """The flat array of ``struct`` from the simulation's vectors (name -> array, last axis)."""
        parts = []
        for _, m in self.members(struct):
            v = np.asarray(vectors[m.source], float)
            parts.append(v[..., m.offset:m.offset + m.size])
        if not parts:
            lead = next(iter(vectors.values())).shape[:-1] if vectors else ()
            return np.zeros((*lead, 0))
        return np.concatenate(parts, axis=-1)

    def json(self) -> dict[str, Any]:
        """The interface as data (written into the package as ``<prefix>.json``)."""
        def groups(gs: tuple[Group, ...]) -> list[dict[str, Any]]:
            return [{"name": g.name, "path": g.path, "members": [
                {"name": m.name, "size": m.size, "unit": m.unit, "doc": m.doc, "labels": list(m.labels),
                 "source": m.source, "offset": m.offset} for m in g.members]} for g in gs]

        return {"controller": self.controller, "prefix": self.prefix, "function": self.function,
                "start_function": self.start_function, "inputs": groups(self.inputs),
                "params": groups(self.params), "state": groups(self.state), "outputs": groups(self.outputs),
                "sizes": {s: self.size(s) for s in ("inputs", "params", "state", "outputs")}}


def _members(layout: Layout, source: str, keep: set[int] | None = None) -> tuple[Member, ...]:
    """The fields of ``layout`` (those with an element in ``keep`` when given), as members."""
    out = []
    off = 0
    for f in layout:
        if keep is None or any(off + i in keep for i in range(f.size)):
            if not _C_NAME.match(f.name) or f.name in _RESERVED:
                raise ModelError(f"layout {layout.name}: field {f.name!r} is not usable as a C member name")
            out.append(Member(f.name, f.size, f.unit, f.doc, tuple(f.labels), source, off))
        off += f.size
    return tuple(out)


def controller_interface(manifest: Manifest, controller: str, control_fn: Any, start_fn: Any | None) -> Interface:
    """The interface of ``controller``'s export, from its manifest layouts and what ``control_fn`` (the
    CasADi function ``control_<name>``) reads."""
    from rpo.runtime.flight.emit import inputs_read

    spec = manifest.controller(controller)
    fn = manifest.functions[spec.control]
    names = [p.name for p in fn.inputs]
    if names != ["meas", "xc", "t", "p", "k"] or [p.name for p in fn.outputs] != ["cmd", "xc_next", "diag"]:
        raise ModelError(f"{spec.control}: unexpected ports {names} -> {[p.name for p in fn.outputs]}; this "
                         "exporter knows (meas, xc, t, p, k) -> (cmd, xc_next, diag)")
    read = inputs_read(control_fn)
    if start_fn is not None:
        for i, idx in inputs_read(start_fn).items():   # xc0(meas, p, k): meas, p and k
            read.setdefault({0: 0, 1: 3, 2: 4}[i], set()).update(idx)
    lay = manifest.layouts
    gains_layout, xc_layout = fn.inputs[4].layout, fn.inputs[1].layout
    diag_layout = fn.outputs[2].layout
    if gains_layout is None or xc_layout is None or diag_layout is None:
        raise ModelError(f"{spec.control}: the manifest gives no layout for its gains, state or diagnostics")
    y = lay[spec.y_layout]
    cmd_fields = [f for f in y if f.name.startswith("cmd_")]
    cmd = []
    off = 0
    for f in cmd_fields:
        cmd.append(Member(f.name.removeprefix("cmd_"), f.size, f.unit, f.doc,
                          tuple(lbl.removeprefix("cmd_") for lbl in f.labels), "cmd", off))
        off += f.size
    if off != fn.outputs[0].size:
        raise ModelError(f"{spec.control}: the cmd_* outputs of {spec.y_layout} ({off}) do not cover cmd "
                         f"({fn.outputs[0].size})")
    t = Member("t", 1, "s", "time of the sample the inputs were measured at", ("t",), "t", 0)
    inputs = (Group("inputs", "", (t, *_members(lay["meas"], "meas", read.get(0, set())))),)
    params = (Group("gains", "gains.", _members(lay[gains_layout], "k")),
              Group("model", "model.", _members(lay["p"], "p", read.get(3, set()))))
    state = (Group("state", "", _members(lay[xc_layout], "xc")),)
    outputs = (Group("cmd", "", tuple(cmd)), Group("diag", "diag.", _members(lay[diag_layout], "diag")))
    sizes = {"meas": lay["meas"].size, "xc": lay[xc_layout].size, "t": 1, "p": lay["p"].size,
             "k": lay[gains_layout].size, "cmd": fn.outputs[0].size, "diag": lay[diag_layout].size}
    return Interface(controller, f"rpo_{controller}", inputs, params, state, outputs, start_fn is not None,
                     spec.control, spec.xc0, sizes)
