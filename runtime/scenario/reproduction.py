"""The ``[reproduction]`` table of a scenario file: its runs in ``rpo report`` and its paper's
published values (read by :mod:`rpo.runtime.jobs.reproduction`).  A file declares only its own runs and
claims (the table is not inherited through ``extends``), so adding a scenario adds its runs to
the report without editing any list.  Layout::

    [reproduction]
    paper = "000"                     # the paper whose tables show these runs
    title = "..."                     # paper-level, given by one file of the paper: the section
                                      #   heading; that file's controller is the paper's controller
    thresholds = { pos_m = 0.3 }      # paper-level (one file): settling thresholds of its runs

    [[reproduction.run]]              # runs of this file, one per plant: label <paper>-<case>-<plant>
    case = "I"                        # the paper's case, matched by the claims
    plants = ["paper", "full"]        # default both
    gains = { acc_d_on = 0.0 }        # optional, as rpo run: also duration, seed, thresholds,
                                      #   error_times

    [[reproduction.claim]]            # one row "published | ours (paper plant) | ours (full plant)"
    case = "I"
    what = "attitude tracked"         # the row's text
    metric = "att_settling_time_s"    # a key of metrics.json
    unit = "s"                        # display unit (rad -> deg, rad/s -> deg/s are converted)
    published = 60.0                  # number, and/or
    published_text = "about 60 s"     # text (shown when given)

    [reproduction.table2]             # 001's Table 2 layout: errors at given times (see Table2)

    [reproduction.comparison]         # all controllers on this file's scenario
    case = "000-I"                    # labels cmp-<case>-<controller>-<plant>
    controllers = "all"               # default: every controller of the generated model
    plants = ["paper", "full"]
    gains = { c002 = { k1 = 0.5 } }   # optional gain overrides per controller
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, model_validator

Plant = Literal["paper", "full"]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Claim(_Strict):
    case: str
    what: str
    metric: str
    unit: str | None = None
    published: float | None = None
    published_text: str | None = None


class Table2(_Strict):
    case: str
    times: list[float]
    q: list[list[float]]
    pos: list[list[float]]
    rate_deg_s: list[list[float]]
    vel: list[list[float]]
    constraints_text: str = "> 0 throughout"
    #: the paper's attitude error as a difference q - q_ref of logged columns, in the published
    #: order (instead of the error quaternion): column labels and the reference, same order
    q_columns: list[str] | None = None
    q_reference: list[float] | None = None


class ReproductionRun(_Strict):
    case: str
    plants: list[Plant] = ["paper", "full"]
    duration: float | None = None
    seed: int | None = None
    gains: dict[str, float | list[float]] | None = None
    thresholds: dict[str, float] | None = None
    error_times: list[float] = []


class ReproductionComparison(_Strict):
    case: str
    controllers: list[str] | Literal["all"] = "all"
    plants: list[Plant] = ["paper", "full"]
    duration: float | None = None
    seed: int | None = None
    thresholds: dict[str, float] | None = None
    #: per controller, gain overrides for every run of this comparison
    gains: dict[str, dict[str, float | list[float]]] = {}


class Reproduction(_Strict):
    paper: str | None = None
    title: str | None = None
    thresholds: dict[str, float] | None = None
    run: list[ReproductionRun] = []
    claim: list[Claim] = []
    table2: Table2 | None = None
    comparison: ReproductionComparison | None = None

    @model_validator(mode="after")
    def _needs_paper(self):
        if self.paper is None and (self.title or self.thresholds or self.run or self.claim or self.table2):
            raise ValueError("runs, claims, title, thresholds and table2 belong to a paper: give paper = \"<id>\"")
        return self
