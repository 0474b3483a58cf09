"""rpo's Python API, the names of the package ``rpo`` itself (runtime/api/ is that package: it forwards
here on first use, so that importing any ``rpo.runtime`` module stays cheap):

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

__all__ = ["Model", "ModelError", "OutputError", "RpoError", "RunResult", "Scenario", "ScenarioError", "campaign",
           "linearize", "load_model", "load_scenario", "load_summary", "read_run", "run", "scenario"]


def _path(path: str | Path) -> Path:
    """A file, or the shipped scenario of that name (``"001_scenario"``, ``"campaigns/000_III_mc"``)."""
    from rpo.runtime.scenario import SCENARIO_DIR

    p = Path(path)
    return SCENARIO_DIR / f"{path}.toml" if not p.suffix and not p.exists() else p


def scenario(path: str | Path, overrides: Mapping[str, Any] | None = None) -> Scenario:
    """The scenario file ``path`` (a path, or a shipped scenario's name: ``"001_scenario"``), validated,
    with ``overrides`` (dotted key -> value, as ``--set``: ``{"chaser.mass": 90.0}``) applied first."""
    return load_scenario(with_sets(read_scenario(_path(path)), dict(overrides or {})))


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


def campaign(path: str | Path, out: str | Path, *, runs: int | None = None, duration: float | None = None,
             overrides: Mapping[str, Any] | None = None, workers: int | None = None, report: bool = True,
             log: Callable[[str], None] | bool = True) -> Path:
    """Fly the campaign file ``path`` into the new folder ``out`` (``rpo mc run``; ``runs``, ``duration`` [s]
    and ``overrides`` as its --runs, --duration and --set), write its ``report.md`` unless
    ``report=False`` (``rpo mc report``), and return the folder (:func:`load_summary` reads its runs)."""
    from rpo.runtime.campaign import load_campaign, run_campaign, start_folder
    from rpo.runtime.campaign.reporting import write_report
    from rpo.runtime.model.manifest import read_manifest
    from rpo.runtime.outputs.writers import check_out_dir

    camp = load_campaign(with_sets(read_scenario(_path(path)), dict(overrides or {})), read_manifest(), runs=runs,
                         duration=duration)
    check_out_dir(out)
    ctrl = camp.scenario_data.get("simulation", {}).get("controller", "baseline")
    model = load_model(log=False if log is False else log, controllers=[ctrl])
    folder = start_folder(camp, model, out, command="rpo.campaign")
    run_campaign(camp, model, folder, workers=workers)
    if report:
        write_report(folder)
    return folder


def load_summary(folder: str | Path) -> Any:
    """A campaign folder's ``summary.parquet`` as a pandas DataFrame, one row per run (units in
    ``df.attrs["units"]``)."""
    from rpo.runtime.campaign import load_summary as summary

    return summary(folder)


def linearize(path: str | Path, *, controller: str | None = None, plant: str | None = None, at: str = "goal",
              overrides: Mapping[str, Any] | None = None, log: Callable[[str], None] | bool = True) -> Any:
    """The closed loop of a scenario file linearised at its goal (or ``at="initial"``): ``rpo linearize``'s
    result (``.lin`` the eigen-analysis; ``rpo.runtime.run.linearize.format_report(res)`` its printed report)."""
    from rpo.runtime.run.linearize import linearize_scenario

    src = with_sets(read_scenario(_path(path)), dict(overrides or {}))
    return linearize_scenario(src, controller=controller, plant=plant, at=at, log=None if log is False else log)
