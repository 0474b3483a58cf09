"""The reproduction runs: the run list (discovered in the scenario files' ``[reproduction]`` tables, or
read from a TOML file), the papers' published values it carries, and the planned runs.  The format is in
:mod:`.reproduction`."""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, TypeVar

from pydantic import BaseModel, ConfigDict, ValidationError

from rpo.runtime.errors import RpoError, ScenarioError
from rpo.runtime.scenario import Reproduction, ScenarioSource, read_scenario
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
    #: the run's perturbed copies (:mod:`.reproduction_roundoff`): how many reached each goal
    roundoff: dict | None = None

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


