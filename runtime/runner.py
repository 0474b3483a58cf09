"""One run from a scenario file to a results folder: the code path of ``rpo run`` and ``rpo report``.

:func:`execute_run` loads the scenario, applies the overrides (duration, seed, controller, plant,
gains), simulates, computes the metrics (:mod:`rpo.runtime.metrics`) and writes the folder
(:func:`rpo.runtime.output.write_run`, including ``metrics.json``).  It prints nothing itself;
``log`` receives the progress lines and ``progress(done, total)`` the step count.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import ModelError


@dataclass
class RunOutcome:
    """What :func:`execute_run` produced."""

    result: object          # RunResult
    out_dir: Path
    metrics: dict
    inputs: object          # RunInputs (after the overrides)
    scenario: object        # Scenario (after the overrides)
    write_time: float

    @property
    def diverged(self) -> bool:
        return self.result.divergence is not None


def apply_gain_overrides(model, controller: str, gains: dict, overrides: Mapping | None) -> dict:
    """``gains`` with ``overrides`` (name -> value) replaced, each checked against the layout of
    ``controller``'s gains (unknown names and wrong sizes are a :class:`ModelError`)."""
    if not overrides:
        return gains
    entry = model.manifest["controllers"][controller]
    layout = {f["name"]: f for f in model.layouts[entry["gains"]]}
    out = dict(gains)
    for name, value in overrides.items():
        if name not in layout:
            raise ModelError(f"gain override {name!r}: controller {controller} has no such gain; "
                             f"available: {', '.join(layout)}")
        v = np.atleast_1d(np.asarray(value, float)).ravel()
        if v.size != layout[name]["size"] or not np.all(np.isfinite(v)):
            raise ModelError(f"gain override {name} = {value!r}: needs {layout[name]['size']} finite value(s)")
        out[name] = v
    return out


def execute_run(scenario: str | Path, out_dir: str | Path, model, *, duration: float | None = None,
                seed: int | None = None, controller: str | None = None, plant: str | None = None,
                gains: Mapping | None = None, plots: bool = True, thresholds: Mapping | None = None,
                error_times: Iterable[float] = (), log: Callable[[str], None] | None = None,
                progress: Callable[[int, int], None] | None = None, extra_meta: dict | None = None) -> RunOutcome:
    """Simulate ``scenario`` with the overrides and write ``out_dir`` (must be absent or empty)."""
    import time

    from .metrics import compute_metrics, result_columns
    from .output import check_out_dir, write_run
    from .scenario import load_scenario
    from .simulate import Simulation

    sc = load_scenario(scenario).with_overrides(duration=duration, seed=seed, controller=controller, plant=plant)
    out = check_out_dir(out_dir)
    inputs = sc.to_run(model)
    inputs.gains = apply_gain_overrides(model, inputs.controller, inputs.gains, gains)
    sim = Simulation(model, inputs.controller, params=inputs.params, gains=inputs.gains)
    z0 = sim.initial_state(inputs.plant)
    n_steps = int(round(inputs.duration / sim.dt))
    if log:
        log(f"{sc.name}: {n_steps} steps of {sim.dt:g} s ({inputs.duration:g} s), controller "
            f"{inputs.controller}, seed {inputs.seed}, backend {model.backend}")
    result = sim.run(z0, inputs.duration, seed=inputs.seed, record_every=inputs.record_every, progress=progress)
    if log:
        log(f"simulated {result.steps_done} steps in {result.wall_time:.3g} s; writing {out} ...")

    goal = np.ravel(inputs.gains["r_goal"]) if "r_goal" in inputs.gains else None
    metrics = compute_metrics(result.t, result_columns(result), thresholds, goal=goal, error_times=error_times)
    metrics["status"] = "ok" if result.divergence is None else "diverged"
    overrides = {k: v for k, v in (("duration", duration), ("seed", seed), ("controller", controller),
                                   ("plant", plant)) if v is not None}
    if gains:
        overrides["gains"] = {k: np.ravel(np.asarray(v, float)).tolist() for k, v in gains.items()}
    extra = {"scenario": sc.name, "scenario_meta": sc.meta.model_dump(), "overrides": overrides,
             "inputs": inputs.to_json(), "z0": z0, **(extra_meta or {})}
    t_write = time.perf_counter()
    write_run(result, out, model, scenario_path=scenario, scenario_text=sc.text, extra_meta=extra,
              plots=plots, params=inputs.params, gains=inputs.gains, title=sc.name, metrics=metrics)
    return RunOutcome(result=result, out_dir=out, metrics=metrics, inputs=inputs, scenario=sc,
                      write_time=time.perf_counter() - t_write)
