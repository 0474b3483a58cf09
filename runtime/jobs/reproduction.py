"""``rpo report``: run the reproduction runs and render the report from their metrics.

Inputs are data, not code:

* the runs and the papers' published values.  By default they are **discovered**: every scenario
  file of a folder (default ``scenarios/``) may carry a ``[reproduction]`` table with its own runs,
  claims and published tables (format: :mod:`rpo.runtime.scenario.reproduction`), so adding a
  controller and its scenario adds its runs to the report without editing a central list.  The
  comparison of all controllers on a common scenario (``[reproduction.comparison]``) takes every
  controller of the generated model unless it names them.  :func:`discover` turns the tables into
  a :class:`RunList`;

* or, given a TOML file instead of a folder, an explicit run list of the same content (for ad-hoc
  reports; paths are relative to the file)::

      [[run]]                           # one simulation
      label = "000-I-paper"             # required, unique: the run's folder name
      scenario = "000_scenario_I.toml"  # required
      controller = "baseline"           # default: the scenario's
      plant = "paper"                   # "paper" (the scenario's own plant) or "full"
      paper = "000"                     # the paper whose tables show this run (optional)
      case = "I"                        # the paper's case (scenario) name, matched by the claims
      duration = 300.0                  # optional overrides, as rpo run: duration, seed,
      seed = 0                          #   gains = { name = value }  (the controller's gain names)
      thresholds = { att_deg = 1.0, pos_m = 0.5 }   # settling thresholds (rpo.runtime.outputs.metrics)
      error_times = [3000.0, 4000.0]    # errors_at these times go into metrics.json (the paper's
                                        #   table2 times are added to the runs of its case)

      [[comparison]]                    # all controllers on one common scenario: expands to runs
      case = "000-III"                  # (one per controller and plant, labels cmp-<case>-<ctrl>-<plant>)
      scenario = "000_scenario_III.toml"
      controllers = ["baseline", "c000", "c001", "c002", "c004"]
      plants = ["paper", "full"]
      duration = 300.0                  # optional, as above; also seed, thresholds
      gains = { c002 = { k1 = 0.5 } }   # optional gain overrides per controller

      [paper."000"]
      title = "..."                     # the section heading
      controller = "c000"               # the paper's controller: its runs fill the paper's table
      thresholds = { pos_m = 0.3 }      # defaults for this paper's runs
      [[paper."000".claim]]             # as [[reproduction.claim]]
      [paper."001".table2]              # as [reproduction.table2]

* free text per paper, ``docs/reproduction_notes.toml``: ``intro``, ``comparison`` and a table
  ``[paper]`` with one string per paper id, written by hand and copied into the report.

Round-off: every run that flies is flown again ``copies`` times (default 16) from initial states
perturbed at round-off level, and the report gives, per goal, how many of the copies reach it
(:mod:`.reproduction_roundoff`): an outcome that some copies share and others do not depends on
round-off, and the report says so.

Outputs: one folder per run under ``<out>/<UTC time>/`` (a fresh folder per invocation), the
markdown report (default ``docs/reproduction.md``) and its JSON twin (``docs/reproduction.json``).
The markdown is a function of the JSON twin and the notes alone (:func:`rerender`): every number
and every outcome it states comes from the twin, the notes add only explanations.
Every run goes through :func:`rpo.runtime.jobs.runner.execute_run`, the path of ``rpo run``.  A run
whose controller is not in the generated model, or whose scenario file does not exist, is listed
as "not run" with the reason; a run that fails is listed with its error; neither stops the report.
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Callable, Iterable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from rpo.runtime.errors import RpoError, ScenarioError
from rpo.runtime.jobs.reproduction_roundoff import COPIES, fly_copies
from rpo.runtime.jobs.reproduction_runs import (  # noqa: F401  (re-exported: the report's API)
    FAULT_CASES,
    FAULT_SCENARIOS,
    RAD2DEG,
    Comparison,
    Notes,
    Paper,
    PlannedRun,
    ReportError,
    RunList,
    RunSpec,
    _load_toml,
    discover,
    fault_runs,
    plan,
)
from rpo.runtime.jobs.reproduction_tables import build_tables, render_markdown, summary_line  # noqa: F401
from rpo.runtime.scenario import ScenarioSource, load_scenario, read_scenario


def fresh_folder(base: Path) -> Path:
    """A new folder ``base/<UTC time>[-k]`` (never an existing one)."""
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    k = 1
    while True:
        out = base / (stamp if k == 1 else f"{stamp}-{k}")
        try:
            out.mkdir(parents=True, exist_ok=False)
            return out
        except FileExistsError:
            k += 1


def scenario_controller(src: ScenarioSource) -> str:
    """The controller a scenario file selects (``extends`` resolved; default ``baseline``)."""
    return str((src.data.get("simulation") or {}).get("controller", "baseline"))


def execute(runs: list[PlannedRun], model: Any, out: Path, *, plots: bool = True, copies: int = 0,
            on_run: Callable[[PlannedRun], None] | None = None) -> None:
    """Run each planned run through :func:`rpo.runtime.jobs.runner.execute_run` into ``out/<label>``,
    and each run that flew ``copies`` more times from perturbed initial states
    (:func:`~.reproduction_roundoff.fly_copies`, into ``r.roundoff``)."""
    from rpo.runtime.jobs.runner import execute_run

    available = set(model.manifest.controllers)
    for r in runs:
        r.controller_used = r.controller
        try:
            if not r.scenario.is_file():
                r.status, r.reason = "not run", f"scenario file {r.scenario.name} does not exist"
                continue
            src = read_scenario(r.scenario)  # the one loader: extends resolved, read once
            ctrl = r.controller or scenario_controller(src)
            r.controller_used = ctrl
            if ctrl not in available:
                r.status, r.reason = "not run", f"controller {ctrl} not generated yet"
                continue
            sc = load_scenario(src, model.manifest)
            if r.faults is not None:
                entries = [{k: v for k, v in f.items() if k != "fdir"} for f in r.faults if "kind" in f]
                sc = sc.with_overrides(plant=r.plant, faults=entries or None)
                if any(f.get("fdir") for f in r.faults):
                    sc = _with_fdir(sc)
            o = execute_run(sc, out / r.label, model, duration=r.duration,
                            seed=r.seed, controller=r.controller, plant=r.plant, gains=r.gains, plots=plots,
                            thresholds=r.thresholds, error_times=r.error_times,
                            extra_meta={"report_label": r.label})
            r.metrics, r.folder = o.metrics, str(o.out_dir)
            r.status = "diverged" if o.diverged else "ok"
            if o.result.divergence is not None:
                r.reason = o.result.divergence.message()
            if copies > 0:
                r.roundoff = fly_copies(o, model, copies)
        except RpoError as exc:  # a scenario the run refuses up front (e.g. step 0 not integrable) is "refused"
            r.status, r.reason = ("refused" if isinstance(exc, ScenarioError) else "error"), str(exc)
        except Exception as exc:  # noqa: BLE001 - one broken run must not lose the others' results
            r.status, r.reason = "error", f"{type(exc).__name__}: {exc}"
            warnings.warn(f"run {r.label} failed: {r.reason}", RuntimeWarning, stacklevel=2)
        finally:
            if on_run:
                on_run(r)


def _with_fdir(sc: Any) -> Any:
    """``sc`` with ``[fdir] allocation = "healthy"`` (the fault-aware allocation)."""
    from rpo.runtime.scenario.schema import validate_scenario

    data = sc.data
    data.setdefault("fdir", {})["allocation"] = "healthy"
    out = validate_scenario(data, f"{sc.source} (fault study)", sc.manifest)
    out._text = sc.text
    return out


def _atomic_write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def load_runs(source: Path, controllers: Iterable[str]) -> tuple[RunList, Path, str]:
    """The run list of ``source``: discovered in a folder of scenarios, or read from a TOML run
    list; with the folder its paths are relative to and how the report names where it came from."""
    source = Path(source)
    if source.is_dir():
        return discover(source, controllers), source, f"the `[reproduction]` tables of `{source / '*.toml'}`"
    return _load_toml(source, RunList, "run list"), source.parent, f"`{source}`"


def make_report(run_list_path: Path, model: Any, *, out_base: Path, md_path: Path, json_path: Path,
                notes_path: Path | None, plots: bool = True, only: list[str] | None = None, copies: int = COPIES,
                on_run: Callable[[PlannedRun], None] | None = None,
                on_plan: Callable[[list[PlannedRun]], None] | None = None) -> dict[str, Any]:
    """Plan, run and render; returns the JSON twin (also written to ``json_path``).  ``run_list_path``
    is a folder of scenario files (their runs are discovered) or a TOML run list; ``copies``: the
    perturbed copies of each run (0: none)."""
    from rpo.runtime.outputs.writers import _jsonable

    run_list_path = Path(run_list_path)
    run_list, base, origin = load_runs(run_list_path, model.manifest.controllers)
    notes = Notes()
    if notes_path is not None and Path(notes_path).exists():
        notes = _load_toml(Path(notes_path), Notes, "notes file")
    runs = plan(run_list, base)
    if run_list_path.is_dir():
        runs += fault_runs(base, model.manifest.controllers)
    if only:
        unknown = set(only) - {r.label for r in runs}
        if unknown:
            raise ReportError(f"--only: no run labelled {', '.join(sorted(unknown))}")
        runs = [r for r in runs if r.label in only]
    if on_plan:
        on_plan(runs)
    out = fresh_folder(Path(out_base))
    execute(runs, model, out, plots=plots, copies=copies, on_run=on_run)
    tables = build_tables(runs, run_list)
    info = {"created_utc": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "model_source_hash": model.manifest.source_hash, "runs_dir": str(out),
            "run_list": str(run_list_path), "origin": origin, "notes": str(notes_path) if notes_path else "-"}
    twin = {**info, "tables": tables,
            "runs": [{"label": r.label, "scenario": str(r.scenario), "controller": r.controller_used or r.controller,
                      "plant": r.plant, "paper": r.paper, "case": r.case, "status": r.status, "reason": r.reason,
                      "folder": r.folder, "metrics": r.metrics, "roundoff": r.roundoff} for r in runs]}
    twin = _jsonable(twin)
    md = rerender(twin, notes)  # the markdown from the twin alone, as the test of the committed copy renders it
    _atomic_write(Path(md_path), md)
    _atomic_write(Path(json_path), json.dumps(twin, indent=2, allow_nan=False) + "\n")
    return twin


#: the twin's fields that the markdown shows (its header)
INFO_KEYS = ("created_utc", "model_source_hash", "runs_dir", "run_list", "origin", "notes")


def rerender(twin: dict[str, Any], notes: Notes) -> str:
    """The markdown report of a JSON twin (``docs/reproduction.json``) and the notes: what
    :func:`make_report` writes, so the committed report can be checked against its data."""
    runs = [PlannedRun(label=r["label"], scenario=Path(r["scenario"]), controller=r["controller"], plant=r["plant"],
                       paper=r["paper"], case=r["case"], duration=None, seed=None, gains=None, thresholds=None,
                       error_times=[], status=r["status"], reason=r["reason"], folder=r["folder"],
                       metrics=r["metrics"], controller_used=r["controller"], roundoff=r.get("roundoff"))
            for r in twin["runs"]]
    return render_markdown(twin["tables"], runs, notes, {k: twin[k] for k in INFO_KEYS})


def rerender_files(json_path: Path = Path("docs/reproduction.json"),
                   notes_path: Path = Path("docs/reproduction_notes.toml"),
                   md_path: Path = Path("docs/reproduction.md")) -> None:
    """Rewrite the markdown report from its JSON twin and the notes, without running anything: after
    editing the notes only (``python -c "from rpo.runtime.jobs.reproduction import rerender_files;
    rerender_files()"`` from the repository's root)."""
    twin = json.loads(Path(json_path).read_text(encoding="utf-8"))
    _atomic_write(Path(md_path), rerender(twin, _load_toml(Path(notes_path), Notes, "notes file")))
