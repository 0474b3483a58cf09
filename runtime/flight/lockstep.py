"""A scenario flown with the controller outside the simulation: the exported package, on this machine
(:class:`~rpo.runtime.flight.host.HostController`) or on an emulated flight processor (the PIL target),
against rpo's plant, one step at a time.

Each step is the composition the generated ``step_<name>`` makes (symbolic/physics/closed_loop.py:
measure -> control -> plant_advance), with the control half sent to the endpoint: the measurement at
t_k goes out, the command and diagnostics come back, the plant advances under the held command.  The
plant copies, the noise and the time grid are the simulation's own (the specialised copy the step's
dispatch picks, :func:`rpo.runtime.run.noise.noise`, t_k = t0 + k dt), so a controller that computes
what ``control_<name>`` computes gives the simulation's run bit for bit.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.interface import Interface
from rpo.runtime.model.loader import Model
from rpo.runtime.model.selection import variant_choice
from rpo.runtime.run import noise
from rpo.runtime.run.result import Divergence, RunResult
from rpo.runtime.run.simulate import Simulation


class Endpoint(Protocol):
    """Where the controller runs: :meth:`init` with the flat params (and start inputs), then :meth:`step`."""

    def init(self, params: np.ndarray, start: np.ndarray | None = None) -> np.ndarray: ...

    def step(self, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...


@dataclass
class LockstepStats:
    """What the lockstep measured besides the run: per-step instructions and stack (PIL), wall time."""

    steps: int = 0
    wall_s: float = 0.0
    instructions: list[int] = field(default_factory=list)
    stack_bytes: list[int] = field(default_factory=list)


def start_inputs(iface: Interface, model: Model, sim: Simulation, z0: np.ndarray) -> np.ndarray | None:
    """The inputs a design with a start is started from: the noise-free measurement at t0, as
    :meth:`Simulation.initial_state` starts the simulation's copy."""
    if not iface.has_start:
        return None
    z_offs = model.offsets(sim.z_layout)
    hold = np.concatenate([z0[z_offs[name]] for name in model.offsets("hold")])
    nx = model.layout_size("x")
    meas0 = np.ravel(model.functions["measure"](z0[:nx], hold, 0.0, sim.p, np.zeros(sim.nw))[0])
    return iface.gather("inputs", {"meas": meas0, "t": np.zeros(1)})


def fly(iface: Interface, model: Model, sim: Simulation, z0: np.ndarray, duration: float, seed: int,
        endpoint: Endpoint, t0: float = 0.0, progress: Callable[[int, int], None] | None = None,
        stats: LockstepStats | None = None) -> RunResult:
    """Fly ``duration`` seconds from ``z0`` with the controller at ``endpoint``; every step recorded."""
    n_total, _, _ = sim._check_run_args(z0, duration, t0, 1, 1)
    seed = noise.check_seed(seed)
    man = model.manifest
    p_offs = model.offsets("p")
    P = np.atleast_2d(sim.p)
    measure = model.function(variant_choice(man, p_offs, "measure", P)[0], p=sim.p)
    advance = model.function(variant_choice(man, p_offs, "plant_advance", P)[0], p=sim.p)
    nx, nzp, nh = model.layout_size("x"), model.layout_size("zp"), model.layout_size("hold")
    ncmd = iface.outputs[0].size
    nz, ny = sim.nz, sim.ny
    stats = stats if stats is not None else LockstepStats()
    params = iface.gather("params", {"p": sim.p, "k": sim.k})
    state = endpoint.init(params, start_inputs(iface, model, sim, z0))
    Z = np.full((n_total + 1, nz), np.nan)
    Y = np.full((n_total + 1, ny), np.nan)
    Z[0] = z0
    Z[0, nzp + nh:] = state     # the controller's own start (equal to the simulation's in double precision)
    # the C loop's own draws (NumPy's log and cos agree with rpo_math.h's only to rounding)
    W = model.loop_noise(noise.key(seed), 0, n_total + 1)
    if W is None:
        W = noise.noise(seed, 0, n_total + 1, sim.nw)
    wall0 = time.perf_counter()
    divergence = None
    done = 0

    def half(z: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t = t0 + float(k) * sim.dt
        w = W[k]
        meas, hold_next = measure(z[:nx], z[nzp:nzp + nh], t, sim.p, w)
        meas = np.ravel(meas)
        out, st = endpoint.step(iface.gather("inputs", {"meas": meas, "t": np.array([t])}))
        zp_next, y_plant = advance(z[:nzp], t, sim.p, w, out[:ncmd])
        z_next = np.concatenate([np.ravel(zp_next), np.ravel(hold_next), st])
        y = np.concatenate([meas, out[:ncmd], np.ravel(y_plant), out[ncmd:]])
        return z_next, y, out, st

    for k in range(n_total):
        z_next, y, _, _ = half(Z[k], k)
        Y[k] = y
        bad = np.flatnonzero(~np.isfinite(z_next) | (np.abs(z_next) > sim.bound))
        bad_y = np.flatnonzero(~np.isfinite(y))
        if bad.size or bad_y.size:
            j = int(bad[0]) if bad.size else nz + int(bad_y[0])
            divergence = sim._divergence(k, t0, j, z_next, Z[k].copy(), y)
            break
        Z[k + 1] = z_next
        done = k + 1
        if progress is not None and (done % 1000 == 0 or done == n_total):
            progress(done, n_total)
    if divergence is None:   # the outputs at the final state: one more step, its next state discarded
        Y[done] = half(Z[done], done)[1]
    stats.steps += done
    stats.wall_s += time.perf_counter() - wall0
    keep = done + 1
    return RunResult(
        t=t0 + np.arange(keep) * sim.dt, z=Z[:keep], y=Y[:keep],
        z_labels=model.labels(sim.z_layout), z_units=model.units(sim.z_layout),
        y_labels=model.labels(sim.y_layout), y_units=model.units(sim.y_layout),
        steps_done=done, steps_requested=n_total, dt=sim.dt, wall_time=stats.wall_s, divergence=divergence,
        meta={"controller": sim.controller, "seed": seed, "record_every": 1, "backend": "lockstep"},
        field_labels=sim._field_labels())


def bits_equal(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal bit for bit where neither is NaN, and NaN at the same places (a NaN's sign and payload are
    the machine's: x86 makes 0xfff8..., ARM 0x7ff8...; IEEE 754 leaves them open)."""
    na, nb = np.isnan(a), np.isnan(b)
    if not np.array_equal(na, nb):
        return False
    keep = ~na
    return bool(np.array_equal(a[keep].view(np.uint64), b[keep].view(np.uint64)))


def compare(a: RunResult, b: RunResult) -> dict[str, float | int | bool]:
    """How two runs of the same scenario differ: the largest absolute difference over every state and
    output entry of the rows both have, whether they are equal bit for bit (NaN: at the same places), and
    the rows compared."""
    n = min(a.z.shape[0], b.z.shape[0])
    if a.z.shape[1] != b.z.shape[1] or a.y.shape[1] != b.y.shape[1]:
        raise ModelError("the two runs have different layouts")
    dz = np.abs(a.z[:n] - b.z[:n])
    dy = np.abs(a.y[:n] - b.y[:n])
    same = bits_equal(a.z[:n], b.z[:n]) and bits_equal(a.y[:n], b.y[:n])
    return {"rows": n, "max_abs_diff": float(max(np.nanmax(dz, initial=0.0), np.nanmax(dy, initial=0.0))),
            "bit_identical": same and a.z.shape == b.z.shape}


__all__ = ["Divergence", "Endpoint", "LockstepStats", "bits_equal", "compare", "fly", "start_inputs"]
