"""Everything a run checks before its first step, in the one function ``rpo run`` (through
:func:`rpo.runtime.jobs.runner.execute_run`) and ``rpo validate`` both call, so the two cannot disagree.

:func:`preflight` takes a validated :class:`~.schema.Scenario` (its schema checks: types, ranges,
cross-field and step-dependent checks) and the model, and does what the run does next:

1. the inputs (:func:`~.initial_state.run_inputs`: SI parameters, gains, the initial state with
   attitudes relative to ECI, wheel speeds to momenta);
2. the closed loop (:class:`~rpo.runtime.run.simulate.Simulation`) and its packed initial state,
   including the controller's own initial states (``xc0_<name>`` from the first measurement);
3. the run's argument checks (duration, record_every, seed, a finite initial state);
4. **step 0 on trial**: the generated step function once from that state, with the run's own
   noise for step 0.  A nan or inf in the next state or in the step's outputs is an input the
   model cannot integrate at this step (each parameter within its range, their combination not),
   refused here with one line naming the entry, instead of a run that "diverges" at t = 0.

A finite state beyond the run's divergence bounds is not refused: the run stops there and writes
what it has (exit 3), as for any divergence; :attr:`Preflight.notes` says so beforehand.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from rpo.runtime.errors import ScenarioError

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.run.simulate import Simulation
    from rpo.runtime.scenario.initial_state import RunInputs
    from rpo.runtime.scenario.schema import Scenario


@dataclass
class Preflight:
    """What :func:`preflight` built: the run's ``inputs``, its ``sim`` and initial state ``z0``,
    and ``notes`` (one line each: what the run will meet, e.g. a divergence at step 0)."""

    inputs: RunInputs
    sim: Simulation
    z0: np.ndarray
    notes: list[str] = field(default_factory=list)


def preflight(sc: Scenario, model: Model) -> Preflight:
    """Every check of a run before its first step; raises :class:`ScenarioError` (one line) or
    :class:`~rpo.runtime.errors.ModelError`."""
    from rpo.runtime.run import noise
    from rpo.runtime.run.simulate import Simulation
    from rpo.runtime.scenario.initial_state import packed_run_inputs

    inputs, p = packed_run_inputs(sc, model)  # = sc.to_run(model), and its parameter vector
    sim = Simulation(model, inputs.controller, params=inputs.params, gains=inputs.gains, packed_p=p)
    z0 = sim.initial_state(inputs.plant)
    rate = f"simulation.rate = {1.0 / sim.dt:g} Hz"
    labels = model.labels(sim.z_layout)
    bad = np.flatnonzero(~np.isfinite(z0))
    if bad.size:
        i = int(bad[0])
        origin = "the controller's initial state (xc0)" if labels[i].startswith("xc_") else "the initial state"
        raise ScenarioError(f"{sc.source}: {origin} has {labels[i]} = {float(z0[i])}: the parameters and gains "
                            "are each within their ranges, but not this combination")
    # the checks Simulation.run makes on its arguments, here so that validate makes them too
    sim._check_run_args(z0, inputs.duration, 0.0, inputs.record_every, 1)
    noise.check_seed(inputs.seed)

    w0 = noise.noise(inputs.seed, 0, 1, sim.nw)[0]
    z1, y0 = (np.ravel(np.asarray(a, float)) for a in sim.step_fn(z0, 0.0, sim.p, sim.k, w0))
    for values, layout in ((z1, sim.z_layout), (y0, sim.y_layout)):
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            i = int(bad[0])
            what = "state" if layout == sim.z_layout else "output"
            raise ScenarioError(
                f"{sc.source}: the first step gives {what} {model.labels(layout)[i]} = {float(values[i])} "
                f"({bad.size} non-finite): the parameters and gains are each within their ranges, but this "
                f"combination cannot be integrated at {rate}")
    notes = []
    for z, when in ((z0, "the initial state"), (z1, "the first step")):
        over = np.flatnonzero(np.abs(z) > sim.bound)
        if over.size:
            i = int(over[0])
            notes.append(f"{when} has {labels[i]} = {z[i]:.6g}, beyond the divergence bound {sim.bound[i]:g}: "
                         "the run will stop at step 0 (exit 3)")
            break
    last_start = inputs.duration - inputs.dt
    for n, f in enumerate(getattr(sc, "faults", [])):
        if f.time > last_start * (1 + 1e-12):
            notes.append(f"faults[{n}] ({f.kind} of {f.unit_name()}) starts at {f.time:g} s, after the last step "
                         f"starts ({last_start:g} s): it changes nothing in this run")
    return Preflight(inputs=inputs, sim=sim, z0=z0, notes=notes)
