"""Test vectors of an export, recorded from a closed-loop run of the simulation.

A run records, per step k, the measurement the controller read (``meas_*`` outputs), the command and
diagnostics it gave (``cmd_*``, ``ctrl_*``) and its states after the step (``xc_*`` of z[k+1]): the
export, driven by the recorded inputs, must give the recorded outputs and states bit for bit (double)
or within the measured tolerance (single).  Values are written as the 16 hexadecimal digits of their
IEEE-754 bits, so nothing is lost in printing and the C reader needs no decimal conversion.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rpo.runtime.flight.interface import Interface
from rpo.runtime.model.loader import Model
from rpo.runtime.run.result import RunResult
from rpo.runtime.run.simulate import Simulation


@dataclass(frozen=True)
class Vectors:
    """The recorded run: params (n_p,), initial state (n_s,), start inputs (n_i,) or None, and per step
    inputs (N, n_i), outputs (N, n_o), states after (N, n_s)."""

    params: np.ndarray
    state0: np.ndarray
    start: np.ndarray | None
    inputs: np.ndarray
    outputs: np.ndarray
    states: np.ndarray
    source: str

    @property
    def steps(self) -> int:
        return int(self.inputs.shape[0])


def _hex(a: np.ndarray) -> str:
    return " ".join(f"{int(b):016x}" for b in np.ascontiguousarray(a, dtype="<f8").view("<u8"))


def from_run(iface: Interface, model: Model, sim: Simulation, result: RunResult, source: str) -> Vectors:
    """The vectors of ``result`` (a :class:`~rpo.runtime.run.result.RunResult` recorded at every step)
    of the simulation ``sim`` (its p, k, layouts) on ``model``."""
    m = model
    z_offs = m.offsets(sim.z_layout)
    y_offs = m.offsets(sim.y_layout)
    y, z, t = np.asarray(result.y), np.asarray(result.z), np.asarray(result.t)
    n = int(result.steps_done)

    def cols(offs: dict[str, slice], prefix: str, layout: str) -> np.ndarray:
        idx = [np.arange(offs[prefix + f.name].start, offs[prefix + f.name].stop)
               for f in m.manifest.layouts[layout]]
        return np.concatenate(idx) if idx else np.zeros(0, int)

    ctrl = m.manifest.controller(iface.controller)
    fn = m.manifest.functions[ctrl.control]
    xc_l, diag_l = fn.inputs[1].layout, fn.outputs[2].layout
    meas_c = cols(y_offs, "meas_", "meas")
    cmd_c = np.concatenate([np.arange(y_offs[f.name].start, y_offs[f.name].stop)
                            for f in m.manifest.layouts[ctrl.y_layout] if f.name.startswith("cmd_")])
    diag_c, xc_c = cols(y_offs, "ctrl_", diag_l), cols(z_offs, "xc_", xc_l)
    vec = {"p": np.asarray(sim.p), "k": np.asarray(sim.k)}
    params = iface.gather("params", vec)
    steps = {"meas": y[:n][:, meas_c], "t": t[:n, None], "cmd": y[:n][:, cmd_c], "diag": y[:n][:, diag_c],
             "xc": z[1:n + 1][:, xc_c]}
    start = None
    if iface.has_start:
        # the simulation starts the states from the noise-free measurement at t0 (Simulation.initial_state)
        hold_offs = m.offsets("hold")
        nx = m.layout_size("x")
        hold = np.concatenate([z[0, z_offs[name]] for name in hold_offs])
        meas0 = np.ravel(m.functions["measure"](z[0, :nx], hold, 0.0, sim.p, np.zeros(sim.nw))[0])
        start = iface.gather("inputs", {"meas": meas0, "t": np.zeros(1)})
    return Vectors(params=params, state0=z[0, xc_c], start=start, inputs=iface.gather("inputs", steps),
                   outputs=iface.gather("outputs", steps), states=iface.gather("state", steps), source=source)


def write(path: Path, iface: Interface, v: Vectors, tolerance: float | None) -> None:
    """The vector file: ``P`` params, ``S`` the initial state, ``I`` the start inputs (designs with a
    start), ``C`` each output's scale (max |value| over the run), ``T`` the single-precision tolerance
    (relative to the scale), then one ``V`` line per step: inputs, outputs, states after."""
    scale = np.max(np.abs(v.outputs), axis=0) if v.steps else np.zeros(v.outputs.shape[1])
    lines = [f"# rpo test vectors for {iface.prefix}: {v.steps} steps recorded from {v.source}",
             "# values: the 16 hex digits of each IEEE-754 double (big-endian digit order)",
             f"# sizes: params {v.params.size} inputs {v.inputs.shape[1]} outputs {v.outputs.shape[1]} "
             f"state {v.states.shape[1]} steps {v.steps}",
             f"N {v.steps}", f"P {_hex(v.params)}", f"S {_hex(v.state0)}"]
    if v.start is not None:
        lines.append(f"I {_hex(v.start)}")
    lines.append(f"C {_hex(scale)}")
    lines.append(f"T {_hex(np.array([tolerance if tolerance is not None else 0.0]))}")
    for i in range(v.steps):
        lines.append(f"V {_hex(v.inputs[i])} {_hex(v.outputs[i])} {_hex(v.states[i])}")
    path.write_text("\n".join(lines) + "\n")


def read(path: Path) -> dict[str, np.ndarray]:
    """The arrays of a vector file (tag -> values; ``V`` rows stacked)."""
    out: dict[str, list[np.ndarray]] = {}
    for line in path.read_text().splitlines():
        if not line or line.startswith("#"):
            continue
        tag, *vals = line.split()
        if tag == "N":
            continue
        a = np.array([int(x, 16) for x in vals], dtype="<u8").view("<f8")
        out.setdefault(tag, []).append(a)
    return {k: (np.vstack(v) if k == "V" else v[0]) for k, v in out.items()}
