"""rpo's Python API, installed as the package ``rpo`` itself (setup.py maps ``rpo`` to this folder):

    import rpo
    result = rpo.run("scenarios/001_scenario.toml", duration=600, overrides={"chaser.mass": 90.0})
    result.meta["verdict"]["line"]          # the verdict, as `rpo run` prints it
    df = result.to_pandas()                 # units in df.attrs["units"]
    again = rpo.read_run("runs/001_scenario-...")   # a folder written by `rpo run` or rpo.run(out=...)

Everything here is a thin call of the runtime's own functions (the same as the CLI's), so a run from
Python and from the command line are the same run.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from rpo.runtime.errors import ModelError, OutputError, RpoError, ScenarioError
from rpo.runtime.model.loader import Model, load_model
from rpo.runtime.outputs.reading import read_run
from rpo.runtime.run.result import RunResult
from rpo.runtime.scenario import Scenario, load_scenario, read_scenario
from rpo.runtime.scenario.overrides import with_sets

__all__ = ["Model", "ModelError", "OutputError", "RpoError", "RunResult", "Scenario", "ScenarioError", "load_model",
           "load_scenario", "read_run", "run", "scenario"]


def scenario(path: str | Path, overrides: Mapping[str, Any] | None = None) -> Scenario:
    """The scenario file ``path`` (a path, or a shipped scenario's name: ``"001_scenario"``), validated,
    with ``overrides`` (dotted key -> value, as ``--set``: ``{"chaser.mass": 90.0}``) applied first."""
    from rpo.runtime.scenario import SCENARIO_DIR

    p = Path(path)
    if not p.suffix and not p.exists():
        p = SCENARIO_DIR / f"{path}.toml"
    return load_scenario(with_sets(read_scenario(p), dict(overrides or {})))


def run(path: str | Path, *, controller: str | None = None, plant: str | None = None, duration: float | None = None,
        seed: int | None = None, overrides: Mapping[str, Any] | None = None, out: str | Path | None = None,
        plots: bool = True, log: Callable[[str], None] | bool = True) -> RunResult:
    """Fly the scenario file ``path`` in one call and return its :class:`RunResult`.

    ``controller``, ``plant``, ``duration`` [s], ``seed``: as ``rpo run``'s options; ``overrides``: dotted
    scenario keys -> values (``--set``), validated exactly as if written in the file.  ``out``: also write
    the results folder ``rpo run --out`` writes (figures unless ``plots=False``).  The result's
    ``meta["metrics"]`` holds metrics.json's content and ``meta["verdict"]`` the verdict.  ``log``:
    compile progress to stderr (True), to a function, or none (False).
    """
    from rpo.runtime.jobs.runner import execute_run, run_metrics
    from rpo.runtime.run.preflight import preflight

    sc = scenario(path, overrides)
    logger = None if log is False else log

    def model(name: str) -> Model:
        return load_model(log=logger if logger is not None else False, controllers=[name])

    if out is not None:
        outcome = execute_run(sc, out, model, duration=duration, seed=seed, controller=controller, plant=plant,
                              plots=plots)
        result, metrics = outcome.result, outcome.metrics
    else:
        sc = sc.with_overrides(duration=duration, seed=seed, controller=controller, plant=plant)
        m = model(sc.simulation.controller)
        pre = preflight(sc, m)
        result = pre.sim.run(pre.z0, pre.inputs.duration, seed=pre.inputs.seed, record_every=pre.inputs.record_every)
        metrics = run_metrics(result, pre.inputs, m)
    result.meta["metrics"] = metrics
    result.meta["verdict"] = metrics["verdict"]
    return result
