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

Outputs: one folder per run under ``<out>/<UTC time>/`` (a fresh folder per invocation), the
markdown report (default ``docs/reproduction.md``) and its JSON twin (``docs/reproduction.json``).
Every run goes through :func:`rpo.runtime.jobs.runner.execute_run`, the path of ``rpo run``.  A run
whose controller is not in the generated model, or whose scenario file does not exist, is listed
as "not run" with the reason; a run that fails is listed with its error; neither stops the report.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal, TypeVar

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError

from rpo.runtime.errors import RpoError, ScenarioError
from rpo.runtime.scenario import Reproduction, ScenarioSource, load_scenario, read_scenario
from rpo.runtime.scenario.loader import parse_toml, read_text
from rpo.runtime.scenario.messages import first_error
from rpo.runtime.scenario.reproduction import Claim, Table2

_M = TypeVar("_M", bound=BaseModel)

RAD2DEG = 180.0 / math.pi


class ReportError(RpoError):
    """The run list or the notes file is invalid."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class RunSpec(_Strict):
    label: str
    scenario: str
    controller: str | None = None
    plant: Literal["paper", "full"] = "paper"
    paper: str | None = None
    case: str | None = None
    duration: float | None = None
    seed: int | None = None
    gains: dict[str, float | list[float]] | None = None
    thresholds: dict[str, float] | None = None
    error_times: list[float] = []


class Comparison(_Strict):
    case: str
    scenario: str
    controllers: list[str]
    plants: list[Literal["paper", "full"]] = ["paper", "full"]
    duration: float | None = None
    seed: int | None = None
    thresholds: dict[str, float] | None = None
    #: per controller, gain overrides for every run of this comparison
    gains: dict[str, dict[str, float | list[float]]] = {}


class Paper(_Strict):
    title: str = ""
    controller: str | None = None
    thresholds: dict[str, float] | None = None
    claim: list[Claim] = []
    table2: Table2 | None = None


class RunList(_Strict):
    run: list[RunSpec] = []
    comparison: list[Comparison] = []
    paper: dict[str, Paper] = {}


class Notes(_Strict):
    intro: str = ""
    comparison: str = ""
    faults: str = ""
    paper: dict[str, str] = {}


def _load_toml(path: Path, cls: type[_M], what: str) -> _M:
    """A run list or notes file, read by the scenario loader's TOML reader (one error format)."""
    path = Path(path)
    if not path.is_file():
        raise ReportError(f"{what} {path} not found")
    data = parse_toml(read_text(path, what, ReportError), str(path), ReportError)
    try:
        return cls.model_validate(data)
    except ValidationError as exc:
        # run.0.plant: the position in an array of tables ([[run]]) as in the run list's own dotted keys
        raise ReportError(first_error(exc.errors(include_url=False), str(path), cls, index=".{}")) from None


def _order(src: ScenarioSource, rep: Reproduction) -> tuple[str, int, str]:
    """Discovery order: by paper, a base file before the variants that extend it, then by name."""
    return (rep.paper or "~", len(src.bases), Path(src.source).name)


def discover(folder: Path, controllers: Iterable[str]) -> RunList:
    """The :class:`RunList` declared by the ``[reproduction]`` tables of ``folder/*.toml``.

    Each run is labelled ``<paper>-<case>-<plant>`` and flies the file's own controller; a paper's
    title, thresholds and Table 2 come from the one file of that paper that gives them, and the
    paper's controller is that file's.  ``controllers`` (the generated ones) fill a comparison
    that names none.
    """
    found: list[tuple[ScenarioSource, Reproduction]] = []
    for path in sorted(Path(folder).glob("*.toml")):
        src = read_scenario(path)
        table = src.data.get("reproduction")
        if table is None:
            continue
        try:
            found.append((src, Reproduction.model_validate(table)))
        except ValidationError as exc:
            raise ScenarioError(first_error(exc.errors(include_url=False), src.source, Reproduction,
                                            ("reproduction",))) from None
    found.sort(key=lambda item: _order(*item))
    runs: list[RunSpec] = []
    comparisons: list[Comparison] = []
    papers: dict[str, Paper] = {}
    given: dict[tuple[str, str], str] = {}  # (paper, paper-level field) -> the file giving it
    for src, rep in found:
        name = Path(src.source).name
        controller = str((src.data.get("simulation") or {}).get("controller", "baseline"))
        if rep.paper is not None:
            paper = papers.setdefault(rep.paper, Paper())
            for attr in ("title", "thresholds", "table2"):
                value = getattr(rep, attr)
                if value is None:
                    continue
                other = given.setdefault((rep.paper, attr), src.source)
                if other != src.source:
                    raise ReportError(f"{src.source}: reproduction.{attr}: paper {rep.paper}'s {attr} is "
                                      f"given in {other} already (one file per paper gives it)")
                setattr(paper, attr, value)
                if attr == "title":
                    paper.controller = controller
            paper.claim.extend(rep.claim)
            for r in rep.run:
                for plant in r.plants:
                    runs.append(RunSpec(label=f"{rep.paper}-{r.case}-{plant}", scenario=name, controller=controller,
                                        plant=plant, paper=rep.paper, case=r.case, duration=r.duration, seed=r.seed,
                                        gains=r.gains, thresholds=r.thresholds, error_times=list(r.error_times)))
        c = rep.comparison
        if c is not None:
            ctrls = sorted(controllers) if c.controllers == "all" else list(c.controllers)
            comparisons.append(Comparison(case=c.case, scenario=name, controllers=ctrls, plants=list(c.plants),
                                          duration=c.duration, seed=c.seed, thresholds=c.thresholds,
                                          gains=c.gains))
    return RunList(run=runs, comparison=comparisons, paper=papers)


@dataclass
class PlannedRun:
    """One run to do (from ``[[run]]`` or expanded from ``[[comparison]]``)."""

    label: str
    scenario: Path
    controller: str | None
    plant: str
    paper: str | None
    case: str | None
    duration: float | None
    seed: int | None
    gains: dict | None
    thresholds: dict | None
    error_times: list[float]
    compare: bool = False
    status: str = "pending"          # ok | diverged | not run | error
    reason: str = ""
    folder: str | None = None
    metrics: dict | None = None
    controller_used: str | None = None
    extra: dict = field(default_factory=dict)
    faults: list[dict] | None = None  # [[faults]] entries added to the scenario's (the fault study)

    def key(self) -> str:
        return json.dumps([str(self.scenario), self.controller, self.plant, self.duration, self.seed, self.gains,
                           self.thresholds, sorted(self.error_times), self.faults], sort_keys=True)


#: The fault study of the report (issue 11): every controller on these scenarios (file, plant) in
#: each of these cases (label, [[faults]] entries), with the nominal and the fault-aware allocation.
#: Wheels and thrusters need the full plant for 001 (its own model has ideal actuators).
FAULT_SCENARIOS = (("001_scenario.toml", "full"), ("000_scenario_III.toml", "paper"))
FAULT_CASES: tuple[tuple[str, list[dict]], ...] = (
    ("nominal", []),
    ("wheel 1 off at 30 s", [{"kind": "wheel_off", "unit": 1, "time": 30.0}]),
    ("wheel 1 off at 30 s, FDIR", [{"kind": "wheel_off", "unit": 1, "time": 30.0}]),
    ("thruster 00 stuck on at 30 s", [{"kind": "thruster_stuck_on", "unit": 0, "time": 30.0}]),
    ("thruster 00 stuck on at 30 s, FDIR", [{"kind": "thruster_stuck_on", "unit": 0, "time": 30.0}]),
)


def fault_runs(base: Path, controllers: Iterable[str]) -> list[PlannedRun]:
    """The runs of the fault study (:data:`FAULT_SCENARIOS` x :data:`FAULT_CASES` x controllers)."""
    runs = []
    for scen, plant in FAULT_SCENARIOS:
        if not (base / scen).is_file():
            continue
        for case, faults in FAULT_CASES:
            for ctrl in sorted(controllers):
                label = f"fault-{Path(scen).stem}-{ctrl}-" + "-".join(case.replace(",", "").split())
                runs.append(PlannedRun(label=label, scenario=base / scen, controller=ctrl, plant=plant, paper=None,
                                       case=case, duration=None, seed=None, gains=None, thresholds=None,
                                       error_times=[], faults=[dict(f, fdir=case.endswith("FDIR")) for f in faults]
                                       if faults else [{"fdir": False}]))
    return runs


def plan(run_list: RunList, base: Path) -> list[PlannedRun]:
    """The runs of ``run_list`` (paths relative to ``base``); a comparison run that equals an
    explicit run is not run twice (the explicit run is marked as part of the comparison)."""
    runs: list[PlannedRun] = []
    for r in run_list.run:
        pth = run_list.paper.get(r.paper) if r.paper else None
        th = {**((pth.thresholds if pth else None) or {}), **(r.thresholds or {})} or None
        times = list(r.error_times)
        if pth and pth.table2 and pth.table2.case == r.case:  # the paper's Table 2 needs these times
            times += [t for t in pth.table2.times if t not in times]
        runs.append(PlannedRun(label=r.label, scenario=base / r.scenario, controller=r.controller, plant=r.plant,
                               paper=r.paper, case=r.case, duration=r.duration, seed=r.seed, gains=r.gains,
                               thresholds=th, error_times=times))
    labels = [r.label for r in runs]
    dup = {x for x in labels if labels.count(x) > 1}
    if dup:
        raise ReportError(f"run labels must be unique; repeated: {', '.join(sorted(dup))}")
    by_key = {r.key(): r for r in runs}
    for c in run_list.comparison:
        for ctrl in c.controllers:
            for plant in c.plants:
                p = PlannedRun(label=f"cmp-{c.case}-{ctrl}-{plant}", scenario=base / c.scenario, controller=ctrl,
                               plant=plant, paper=None, case=c.case, duration=c.duration, seed=c.seed,
                               gains=c.gains.get(ctrl) or None,
                               thresholds=c.thresholds, error_times=[], compare=True)
                same = by_key.get(p.key())
                if same is not None:
                    same.compare = True
                    same.extra.setdefault("comparison_cases", []).append(c.case)
                    continue
                if p.label in labels:
                    raise ReportError(f"comparison run label {p.label} is also a [[run]] label")
                runs.append(p)
                labels.append(p.label)
                by_key[p.key()] = p
    return runs


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


def execute(runs: list[PlannedRun], model: Any, out: Path, *, plots: bool = True,
            on_run: Callable[[PlannedRun], None] | None = None) -> None:
    """Run each planned run through :func:`rpo.runtime.jobs.runner.execute_run` into ``out/<label>``."""
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


# --------------------------------------------------------------------------- rendering

_CONVERT = {("rad", "deg"): RAD2DEG, ("rad/s", "deg/s"): RAD2DEG, ("rad/s", "rpm"): 60 / (2 * math.pi)}


def _num(v: float | None, fmt: str = ".4g") -> str:
    return "-" if v is None else format(v, fmt)


def metric_cell(r: PlannedRun | None, metric: str, unit: str | None = None, with_unit: bool = False) -> str:
    """A run's metric as table text: the value, or why there is none."""
    from rpo.runtime.outputs.metrics import UNITS

    if r is None:
        return "not run (no run declared)"
    if r.status in ("not run", "error", "refused"):
        return f"{r.status} ({r.reason})" if r.status == "not run" else f"{r.status} (see run list)"
    m = r.metrics or {}
    if metric not in m:
        return f"unknown metric {metric}"
    v = m[metric]
    if v is None:
        if metric in m.get("unavailable", {}):
            return "n/a (not logged)"
        return "not settled" if metric.endswith("settling_time_s") else "-"
    if isinstance(v, bool):
        text = "yes" if v else "no"
    else:
        base = UNITS.get(metric)
        scale = _CONVERT.get((base or "", unit), 1.0) if unit else 1.0
        text = _num(float(v) * scale) + (f" {unit or base}" if with_unit and (unit or base) else "")
    return text + (" (diverged)" if r.status == "diverged" else "")


def _find(runs: list[PlannedRun], paper: str, case: str, plant: str, controller: str | None) -> PlannedRun | None:
    cands = [r for r in runs if r.paper == paper and r.case == case and r.plant == plant]
    if controller:
        cands = [r for r in cands if (r.controller_used or r.controller) == controller]
    return cands[0] if cands else None


def _published(c: Claim) -> str:
    if c.published_text:
        return c.published_text
    return "-" if c.published is None else f"{c.published:g}" + (f" {c.unit}" if c.unit else "")


def paper_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    rows = []
    for c in paper.claim:
        cells: dict[str, str | None] = {}
        for plant in ("paper", "full"):
            r = _find(runs, pid, c.case, plant, paper.controller)
            cells[plant] = metric_cell(r, c.metric, c.unit, with_unit=True)
            cells[f"{plant}_label"] = None if r is None else r.label
        rows.append({"case": c.case, "what": c.what, "metric": c.metric, "published": _published(c),
                     "published_value": c.published, "ours_paper": cells["paper"], "ours_full": cells["full"],
                     "run_paper": cells["paper_label"], "run_full": cells["full_label"]})
    return rows


def _vec(v, scale=1.0) -> str:
    return "-" if v is None else "(" + ", ".join(f"{x * scale:.3g}" for x in v) + ")"


def table2_rows(runs: list[PlannedRun], pid: str, paper: Paper) -> list[dict]:
    t2 = paper.table2
    if t2 is None:
        return []
    rows = []
    ours = {}
    for plant in ("paper", "full"):
        r = _find(runs, pid, t2.case, plant, paper.controller)
        at = {}
        if r is not None and r.metrics:
            at = {round(e["t"], 6): e for e in r.metrics.get("errors_at", [])}
        ours[plant] = (r, at)

    def cell(plant, t, key, scale=1.0):
        r, at = ours[plant]
        if r is None:
            return "not run (no run declared)"
        if r.status in ("not run", "error", "refused"):
            return f"{r.status} ({r.reason})"
        e = at.get(round(t, 6))
        if e is None:
            return "n/a (time not recorded)"
        v = e.get(key)
        if v is None:
            return "n/a (not logged or run ended)"
        if key == "q" and t2.q_columns:  # the paper's difference of quaternions, sign-aligned to the reference
            d = e.get("diag") or {}
            if not all(c in d for c in t2.q_columns):
                return "n/a (not logged)"
            q = np.array([d[c] for c in t2.q_columns])
            ref = np.array(t2.q_reference)
            q = q if q @ ref >= 0 else -q
            return _vec(list(q - ref), scale)
        if key == "q":  # ours as (scalar, x, y, z), the published order
            v = [v[3], v[0], v[1], v[2]]
        return _vec(v, scale)

    q_name = "attitude quaternion " + ("q - q_D " if t2.q_columns else "") + "(scalar, x, y, z)"
    for name, key, pub, scale, unit in ((q_name, "q", t2.q, 1.0, "-"),
                                        ("position", "pos_m", t2.pos, 1.0, "m"),
                                        ("angular rate", "rate_rad_s", t2.rate_deg_s, RAD2DEG, "deg/s"),
                                        ("velocity", "vel_m_s", t2.vel, 1.0, "m/s")):
        for i, t in enumerate(t2.times):
            rows.append({"quantity": f"{name} [{unit}]", "t": t, "published": _vec(pub[i] if i < len(pub) else None),
                         "ours_paper": cell("paper", t, key, scale), "ours_full": cell("full", t, key, scale)})
    for name, metric, unit in (("min beta_FOV", "beta_fov_min_m", "m"), ("min beta_CA", "beta_ca_min_m2", "m^2")):
        rows.append({"quantity": f"{name} [{unit}]", "t": None, "published": t2.constraints_text,
                     "ours_paper": metric_cell(ours["paper"][0], metric),
                     "ours_full": metric_cell(ours["full"][0], metric)})
    return rows


COMPARISON_COLUMNS = (("converged", None, "converges"), ("att_settling_time_s", None, "att. settling [s]"),
                      ("pos_settling_time_s", None, "pos. settling [s]"), ("propellant_kg", None, "propellant [kg]"),
                      ("wheel_momentum_peak_N_m_s", None, "peak wheel momentum [N m s]"),
                      ("beta_fov_min_m", None, "min beta_FOV [m]"), ("beta_ca_min_m2", None, "min beta_CA [m^2]"))


def comparison_rows(runs: list[PlannedRun]) -> list[dict]:
    rows = []
    for r in runs:
        if not r.compare:
            continue
        cases = r.extra.get("comparison_cases") or [r.case]
        for case in cases:
            row = {"case": case, "plant": r.plant, "controller": r.controller_used or r.controller, "run": r.label,
                   "status": r.status if r.status != "not run" else f"not run ({r.reason})"}
            for metric, unit, _head in COMPARISON_COLUMNS:
                row[metric] = metric_cell(r, metric, unit) if r.status in ("ok", "diverged") else "-"
            rows.append(row)
    rows.sort(key=lambda x: (x["case"], x["plant"] != "paper", x["plant"], x["controller"] or ""))
    return rows


def _md_table(head: list[str], rows: list[list[str]]) -> str:
    esc = [[str(c).replace("|", "\\|").replace("\n", " ") for c in row] for row in rows]
    lines = ["| " + " | ".join(head) + " |", "| " + " | ".join("---" for _ in head) + " |"]
    lines += ["| " + " | ".join(row) + " |" for row in esc]
    return "\n".join(lines)


def build_tables(runs: list[PlannedRun], run_list: RunList) -> dict:
    papers = {}
    for pid, paper in run_list.paper.items():
        papers[pid] = {"title": paper.title, "controller": paper.controller, "claims": paper_rows(runs, pid, paper),
                       "table2": table2_rows(runs, pid, paper) if paper.table2 else None}
    return {"papers": papers, "comparison": comparison_rows(runs), "faults": fault_rows(runs)}


def _fault_cell(r: PlannedRun | None) -> str:
    """Attitude and position settling (or final errors), the propellant; or why there is none."""
    if r is None:
        return "-"
    if r.status not in ("ok", "diverged"):
        return r.status
    m = r.metrics or {}

    def goal(q: str, unit: str, scale: float) -> str:
        st, fin = m.get(f"{q}_settling_time_s"), m.get(f"{q}_err_final_{'rad' if q == 'att' else 'm'}")
        if fin is None:
            return f"{q} n/a"
        return f"{q} {st:.0f} s" if st is not None else f"{q} off {fin * scale:.3g} {unit}"

    text = f"{goal('att', 'deg', RAD2DEG)}, {goal('pos', 'm', 1.0)}, {_num(m.get('propellant_kg'), '.3g')} kg"
    return ("DIVERGED; " + text) if r.status == "diverged" else text


def fault_rows(runs: list[PlannedRun]) -> list[dict]:
    """The fault study: one row per (scenario, plant, controller), one cell per case."""
    rows: dict[tuple, dict] = {}
    for r in runs:
        if r.faults is None:
            continue
        key = (r.scenario.name, r.plant, r.controller_used or r.controller)
        row = rows.setdefault(key, {"scenario": key[0], "plant": key[1], "controller": key[2], "cells": {}})
        row["cells"][r.case] = _fault_cell(r)
    return list(rows.values())


def render_markdown(tables: dict, runs: list[PlannedRun], notes: Notes, info: dict) -> str:
    from rpo.runtime.outputs.metrics import DEFAULT_THRESHOLDS

    out = ["# Reproduction of the papers' results", "",
           f"Generated by `rpo report` on {info['created_utc']} (model source hash {info['model_source_hash']}); "
           f"run folders under `{info['runs_dir']}`. Do not edit: the numbers come from the runs, the published "
           f"values and runs from {info['origin']}, the text from `{info['notes']}`.", "",
           "Metric definitions: `rpo.runtime.outputs.metrics` (module docstring). Settling time: the first time after "
           f"which the error stays below its threshold (default {DEFAULT_THRESHOLDS['att_deg']:g} deg, "
           f"{DEFAULT_THRESHOLDS['pos_m']:g} m) until the end of the run; \"not settled\" if it ends above. "
           "\"n/a (not logged)\": the controller does not log that error.", ""]
    if notes.intro.strip():
        out += [notes.intro.strip(), ""]
    for pid, p in tables["papers"].items():
        out += [f"## {pid}" + (f": {p['title']}" if p["title"] else ""), ""]
        if p["controller"]:
            out += [f"Controller: `{p['controller']}`.", ""]
        if p["claims"]:
            out += [_md_table(["case", "claim", "published", "ours (paper plant)", "ours (full plant)"],
                              [[c["case"], c["what"], c["published"], c["ours_paper"], c["ours_full"]]
                               for c in p["claims"]]), ""]
        if p["table2"]:
            out += ["Errors at given times (Table 2 layout):", "",
                    _md_table(["quantity", "t [s]", "published", "ours (paper plant)", "ours (full plant)"],
                              [[row["quantity"], "-" if row["t"] is None else f"{row['t']:g}", row["published"],
                                row["ours_paper"], row["ours_full"]] for row in p["table2"]]), ""]
        text = notes.paper.get(pid, "").strip()
        if text:
            out += [text, ""]
    if tables["comparison"]:
        out += ["## All controllers on common scenarios", ""]
        head = ["case", "plant", "controller", "status"] + [h for _m, _u, h in COMPARISON_COLUMNS]
        out += [_md_table(head, [[row["case"], row["plant"], row["controller"], row["status"]]
                                 + [row[m] for m, _u, _h in COMPARISON_COLUMNS] for row in tables["comparison"]]), ""]
        if notes.comparison.strip():
            out += [notes.comparison.strip(), ""]
    if tables.get("faults"):
        cases = [c for c, _f in FAULT_CASES]
        out += ["## Faults", "",
                "Every controller with one reaction wheel failed (no torque) and with one thruster stuck on, "
                "both from 30 s (`runtime/jobs/reproduction.py` FAULT_CASES; the fault model and the fault-aware "
                "allocation (\"FDIR\", rpo's, not the papers') in `docs/faults.md`). Scenario 001 flies the "
                "full plant here: its own model has ideal actuators, which have no units to fail. Each cell: "
                "attitude and position settling time (or the final error), propellant used.", "",
                _md_table(["scenario", "plant", "controller", *cases],
                          [[row["scenario"], row["plant"], row["controller"],
                            *[row["cells"].get(c, "-") for c in cases]] for row in tables["faults"]]), ""]
        if notes.faults.strip():
            out += [notes.faults.strip(), ""]
    out += ["## Runs", "",
            _md_table(["label", "scenario", "controller", "plant", "ran to [s]", "status", "folder"],
                      [[r.label, r.scenario.name, r.controller_used or r.controller or "-", r.plant,
                        "-" if r.metrics is None else _num(r.metrics.get("t_end_s")),
                        r.status + (f": {r.reason}" if r.reason else ""), r.folder or "-"] for r in runs]), ""]
    return "\n".join(out)


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
                notes_path: Path | None, plots: bool = True, only: list[str] | None = None,
                on_run: Callable[[PlannedRun], None] | None = None,
                on_plan: Callable[[list[PlannedRun]], None] | None = None) -> dict[str, Any]:
    """Plan, run and render; returns the JSON twin (also written to ``json_path``).  ``run_list_path``
    is a folder of scenario files (their runs are discovered) or a TOML run list."""
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
    execute(runs, model, out, plots=plots, on_run=on_run)
    tables = build_tables(runs, run_list)
    info = {"created_utc": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "model_source_hash": model.manifest.source_hash, "runs_dir": str(out),
            "run_list": str(run_list_path), "origin": origin, "notes": str(notes_path) if notes_path else "-"}
    md = render_markdown(tables, runs, notes, info)
    twin = {**info, "tables": tables,
            "runs": [{"label": r.label, "scenario": str(r.scenario), "controller": r.controller_used or r.controller,
                      "plant": r.plant, "paper": r.paper, "case": r.case, "status": r.status, "reason": r.reason,
                      "folder": r.folder, "metrics": r.metrics} for r in runs]}
    twin = _jsonable(twin)
    _atomic_write(Path(md_path), md)
    _atomic_write(Path(json_path), json.dumps(twin, indent=2, allow_nan=False) + "\n")
    return twin


def summary_line(r: PlannedRun) -> str:
    """One line per finished run for the console."""
    m = r.metrics or {}
    if r.status in ("not run", "error", "refused"):
        return f"{r.label}: {r.status}: {r.reason}"
    def st(key):
        return metric_cell(r, key, with_unit=True)
    return f"{r.label}: {r.status}, attitude {st('att_settling_time_s')}, position {st('pos_settling_time_s')}, " \
           f"propellant {_num(m.get('propellant_kg'))} kg"

