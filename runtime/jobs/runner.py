"""One run from a scenario file to a results folder: the code path of ``rpo run`` and ``rpo report``.

:func:`execute_run` goes once through the stages in the order the data flows:

1. **scenario**: read and validate the file (or take a validated :class:`Scenario`), apply the
   overrides (duration, seed, controller, plant, gains) and validate again;
2. **output folder**: checked completely (:func:`rpo.runtime.outputs.writers.check_out_dir`: not empty,
   writable, parent writable, symlinks resolved) before anything slow happens;
3. **inputs**: load the model (``model`` may be a callable, so a bad scenario or folder never
   waits for a compile), map the scenario to SI parameters, gains and the initial state;
4. **simulation** (every ``simulation.record_every``-th step kept in memory, default every
   step); 5. **metrics** (:mod:`rpo.runtime.outputs.metrics`) and the **verdict**
   (:mod:`rpo.runtime.outputs.verdict`, in metrics.json and run.json) from that full in-memory record;
   6. **outputs** (:func:`rpo.runtime.outputs.writers.write_run`, atomic, never over existing files): the
   scenario's ``[output]`` (channels, rows, formats, figures) with the command-line overrides.
   The figure workers are started at stage 2, so matplotlib is imported while the run simulates.

It prints nothing itself; ``log`` receives the progress lines and ``progress(done, total)`` the
step count.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.model.loader import Model
from rpo.runtime.model.manifest import read_manifest
from rpo.runtime.outputs.metrics import compute_metrics, result_columns
from rpo.runtime.outputs.verdict import verdict
from rpo.runtime.outputs.writers import OutputSpec, check_out_dir, warm_figures, write_run
from rpo.runtime.run import interrupts
from rpo.runtime.run.interrupts import Interrupted
from rpo.runtime.run.preflight import preflight
from rpo.runtime.run.result import RunResult
from rpo.runtime.scenario import RunInputs, Scenario, load_scenario


@dataclass
class RunOutcome:
    """What :func:`execute_run` produced."""

    result: RunResult
    out_dir: Path
    metrics: dict[str, Any]
    inputs: RunInputs          # after the overrides
    scenario: Scenario         # after the overrides
    model: Model
    write_time: float          # s spent writing the folder
    #: s per stage: scenario, model, simulation, metrics, write (write.data_files, write.figures_wait)
    timings: dict[str, float] | None = None

    @property
    def diverged(self) -> bool:
        return self.result.divergence is not None


def default_out_dir(scenario_path: str | Path, base: Path = Path("runs")) -> Path:
    """``runs/<scenario stem>-<UTC time>[-k]``: a folder name not taken yet."""
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    first = base / f"{Path(scenario_path).stem}-{stamp}"
    out, k = first, 1
    while out.exists():
        k += 1
        out = first.with_name(f"{first.name}-{k}")
    return out


def run_metrics(result: RunResult, inputs: RunInputs, model: Model, *, thresholds: Mapping[str, float] | None = None,
                error_times: Iterable[float] = (), interrupted: bool = False) -> dict[str, Any]:
    """The metrics of a run (rpo.runtime.outputs.metrics), its ``status`` and its ``verdict``
    (rpo.runtime.outputs.verdict): what ``metrics.json`` holds, for a folder or for ``rpo.run``."""
    goal = np.ravel(inputs.gains["r_goal"]) if "r_goal" in inputs.gains else None
    columns = result_columns(result)
    metrics = compute_metrics(result.t, columns, thresholds, goal=goal, error_times=error_times, params=inputs.params)
    metrics["status"] = "diverged" if result.divergence is not None else "interrupted" if interrupted else "ok"
    metrics["verdict"] = verdict(metrics, result.t, columns, inputs.params, result.divergence,  # also in run.json
                                 model.manifest.faults)
    return metrics


def execute_run(scenario: str | Path | Scenario, out_dir: str | Path | None, model: Model | Callable[[str], Model], *,
                duration: float | None = None, seed: int | None = None, controller: str | None = None,
                plant: str | None = None, gains: Mapping[str, Any] | None = None, plots: bool = True,
                thresholds: Mapping[str, float] | None = None, error_times: Iterable[float] = (),
                log: Callable[[str], None] | None = None, progress: Callable[[int, int], None] | None = None,
                extra_meta: dict[str, Any] | None = None, formats: Iterable[str] | None = None,
                figure_format: str | None = None) -> RunOutcome:
    """Simulate ``scenario`` with the overrides and write ``out_dir`` (must be absent or empty;
    None: :func:`default_out_dir`).  ``model`` is the model or a function loading it for the
    controller the run flies (``model(name)``, so a first run compiles only what it needs), called
    once the scenario and the folder are known to be good.  ``formats`` and ``figure_format``
    replace the scenario's ``[output] formats`` / ``figure_format``; ``plots=False`` writes no
    figure.

    SIGINT and SIGTERM (:mod:`rpo.runtime.run.interrupts`): before the simulation, nothing is written;
    during it, the run stops at its next chunk and the folder is written with what was computed,
    ``status = "interrupted"`` in ``run.json`` and ``metrics.json``, then :class:`Interrupted` is
    raised (naming the folder); while the folder is written (or a second signal), the temporary
    folder is removed and nothing is left.  The exception's ``exit_code`` is 130 or 143."""
    with interrupts.handling():
        return _execute_run(scenario, out_dir, model, duration=duration, seed=seed, controller=controller, plant=plant,
                            gains=gains, plots=plots, thresholds=thresholds, error_times=error_times, log=log,
                            progress=progress, extra_meta=extra_meta, formats=formats, figure_format=figure_format)


def _execute_run(scenario: str | Path | Scenario, out_dir: str | Path | None, model: Model | Callable[[str], Model],
                 *, duration: float | None, seed: int | None, controller: str | None, plant: str | None,
                 gains: Mapping[str, Any] | None, plots: bool, thresholds: Mapping[str, float] | None,
                 error_times: Iterable[float], log: Callable[[str], None] | None,
                 progress: Callable[[int, int], None] | None, extra_meta: dict[str, Any] | None,
                 formats: Iterable[str] | None, figure_format: str | None) -> RunOutcome:
    clock = time.perf_counter()
    timings: dict[str, float] = {}

    def lap(stage: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        timings[stage] = now - clock
        clock = now

    # 1. scenario (validated once, then once more with the overrides)
    # the model's manifest, or (the model loaded later, for the controller flown) the generated one
    manifest = model.manifest if isinstance(model, Model) else read_manifest()
    base = scenario if isinstance(scenario, Scenario) else load_scenario(scenario, manifest)
    sc = base.with_overrides(duration=duration, seed=seed, controller=controller, plant=plant,
                             gains=dict(gains) if gains else None)
    spec = output_spec(sc, formats=formats, figure_format=figure_format, plots=plots)
    # 2. output folder
    out = check_out_dir(out_dir if out_dir is not None else default_out_dir(base.source))
    if spec.figures:
        warm_figures()
    lap("scenario")
    # 3. inputs
    model = model if isinstance(model, Model) else model(sc.simulation.controller)
    lap("model")
    pre = preflight(sc, model)  # every check before the first step, the same as `rpo validate`
    inputs, sim, z0 = pre.inputs, pre.sim, pre.z0
    n_steps = int(round(inputs.duration / sim.dt))
    if log:
        log(f"{sc.name}: {n_steps} steps of {sim.dt:g} s ({inputs.duration:g} s), controller "
            f"{inputs.controller}, seed {inputs.seed}, backend {model.backend}")
    # 4. simulation (a first signal ends it at the next chunk, with what it has)
    with interrupts.stop_request() as stop:
        result = sim.run(z0, inputs.duration, seed=inputs.seed, record_every=inputs.record_every, progress=progress,
                         stop=stop.requested)
    lap("simulation")
    # a signal that came during the last chunk still counts: the folder says so and the exit code too
    stopped_by = stop.signum
    if stopped_by is not None:
        result.meta["interrupted"] = True
    if log:
        how = f" (stopped by {interrupts.signal_name(stopped_by)})" if stopped_by is not None else ""
        log(f"simulated {result.steps_done} steps in {result.wall_time:.3g} s{how}; writing {out} ...")
    # 5. metrics
    metrics = run_metrics(result, inputs, model, thresholds=thresholds, error_times=error_times,
                          interrupted=stopped_by is not None)
    lap("metrics")
    # 6. outputs
    overrides: dict[str, Any] = {k: v for k, v in (("duration", duration), ("seed", seed),
                                                    ("controller", controller), ("plant", plant)) if v is not None}
    if gains:
        overrides["gains"] = {k: np.ravel(np.asarray(v, float)).tolist() for k, v in gains.items()}
    extra = {"scenario": sc.name, "scenario_meta": sc.meta.model_dump(), "overrides": overrides,
             "plant": plant_summary(inputs.params, plant),
             "inputs": inputs.to_json(), "z0": z0, "verdict": metrics["verdict"], **(extra_meta or {})}
    if stopped_by is not None:
        extra["interrupted"] = {"signal": interrupts.signal_name(stopped_by), "step": int(result.steps_done),
                                "time": float(result.t[-1]), "steps_requested": int(result.steps_requested)}
    parts: dict[str, float] = {}
    write_run(result, out, model, scenario_path=base.source, scenario_text=sc.text, extra_meta=extra,
              plots=plots, params=inputs.params, gains=inputs.gains, title=sc.name, metrics=metrics, output=spec,
              timings=parts)
    lap("write")
    timings.update({f"write.{k}": v for k, v in parts.items()})
    if stopped_by is not None:  # written; now the interrupt goes on (never swallowed)
        raise Interrupted(stopped_by, f"interrupted by {interrupts.signal_name(stopped_by)} in step "
                                      f"{result.steps_done} of {result.steps_requested} (t = {result.t[-1]:.6g} s); "
                                      f"the results so far were written to {out}")
    return RunOutcome(result=result, out_dir=out, metrics=metrics, inputs=inputs, scenario=sc, model=model,
                      write_time=timings["write"], timings=timings)


#: plant_summary's words for the two target-orbit models
PROPAGATED = "propagated (the target's own orbit with J2 and drag, its LVLH frame)"
KEPLER = "kepler (000's Keplerian target; J2 and drag as chaser-minus-target differences, eqs. 30, 45)"


def ideal_actuators(params: Mapping[str, Any]) -> bool:
    """True when the run flies the ideal force and torque actuators (no wheel, no thruster)."""
    return float(np.ravel(params["actuators_ideal"])[0]) == 1.0


def plant_summary(params: Mapping[str, Any], plant: str | None) -> dict[str, str]:
    """Which plant a run flew (``run.json``'s ``plant``, ``rpo validate``): the --plant choice and
    the model choices a reader most needs, from the run's parameters."""
    def on(name: str) -> bool:
        return float(np.ravel(params[name])[0]) == 1.0

    return {
        "selected": plant or "paper",
        "target_orbit": (PROPAGATED if on("orbit_propagated") else KEPLER),
        "actuators": "ideal force and torque" if ideal_actuators(params) else "reaction wheels and PWPF thrusters",
    }


def output_spec(sc: Scenario, *, formats: Iterable[str] | None = None, figure_format: str | None = None,
                plots: bool = True) -> OutputSpec:
    """The :class:`~rpo.runtime.outputs.writers.OutputSpec` of a validated scenario's ``[output]`` table,
    with the command-line ``formats`` / ``figure_format`` and ``plots=False`` applied."""
    o = sc.output
    dt = float(sc.params()["dt"][0])
    every = o.step(dt, sc.simulation.record_every)
    return OutputSpec(channels=None if o.channels is None else tuple(o.channels),
                      every=None if every == sc.simulation.record_every else every,
                      formats=tuple(formats) if formats else tuple(o.formats),
                      figures=bool(plots and o.figures), figure_format=figure_format or o.figure_format)
