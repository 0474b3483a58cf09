"""Sequential campaigns: fly in planned looks, stop once every requirement is decided.

``[campaign] sequential = true`` (and optionally ``looks = L``, default 10) flies cases 0 .. n_1 - 1,
judges every requirement, flies on to n_2, judges again, ... up to ``runs``, and stops at the first
look where every requirement is PASS or FAIL.  The looks are planned before the first run:
n_j = ceil(j runs / L), j = 1 .. L.

**Why the confidence holds.**  Looking at the data L times and stopping at the first decision gives
L chances of a wrong decision.  Each look therefore judges at the confidence 1 - a / L (a = 1 -
confidence, Bonferroni): for a requirement whose true success probability is below the required
one, P(PASS at some look) <= sum_j P(PASS at look j) <= L (a / L) = a, whatever the dependence
between the looks (they share runs); the same for a false FAIL.  The price is more runs for a PASS
than a single look needs (0.9973 at 95 %: 1109 runs once, 1704 with L = 5, 1960 with L = 10); the
gain is an early stop, mostly on an early FAIL or a requirement with margin.

The runs are those of a campaign of the same seed: case i's draws depend only on the seed and i
(``random`` or ``sobol`` sampling; ``lhs`` and ``sobol-indices`` designs depend on ``runs`` and are
refused), so the summary of a campaign stopped after n runs holds the rows of a campaign of n runs.
A look whose cases include a run in error stops the campaign undecided (``rpo mc resume`` flies the
errors again and continues the looks).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.campaign import execute, storage
from rpo.runtime.campaign.execute import CampaignOutcome
from rpo.runtime.campaign.requirements import Requirement, judge, judge_rows, of_resolved
from rpo.runtime.campaign.spec import Campaign


def look_points(runs: int, looks: int) -> list[int]:
    """The planned looks' run counts: ceil(j runs / looks), j = 1 .. looks (distinct, the last = runs)."""
    return sorted({math.ceil(j * runs / looks) for j in range(1, looks + 1)})


@dataclass
class SequentialOutcome(CampaignOutcome):
    """:class:`~.execute.CampaignOutcome` of a sequential campaign, with its last look: its number
    (1-based) of ``looks``, the runs judged there, whether every requirement was decided, and the
    verdicts (JSON-ready, :meth:`~.requirements.Verdict.to_json`)."""

    looks: int = 0
    look: int = 0
    runs_judged: int = 0
    decided: bool = False
    verdicts: list[dict[str, Any]] = dataclasses.field(default_factory=list)


def run_campaign(camp: Campaign, model: Any, folder: Path, *, cases: Iterable[int] | None = None,
                 workers: int | None = None, dask: str | None = None, batch: int | None = None,
                 on_rows: Callable[[list[dict]], None] | None = None) -> CampaignOutcome:
    """:func:`.execute.run_campaign`; a sequential campaign (``[campaign] sequential = true``, all
    of its cases asked for) flies look after look until decided (:func:`fly_in_looks`)."""
    def fly(some: Iterable[int] | None) -> CampaignOutcome:
        return execute.run_campaign(camp, model, folder, cases=some, workers=workers, dask=dask, batch=batch,
                                    on_rows=on_rows)

    if cases is not None or not camp.settings.sequential:
        return fly(cases)
    return fly_in_looks(camp.requirements, camp.runs, camp.looks, folder, fly)


def fly_in_looks(requirements: list[Requirement], runs: int, looks: int, folder: Path,
                 fly: Callable[[Iterable[int]], CampaignOutcome]) -> SequentialOutcome:
    """Fly look after look with ``fly(cases)`` (:func:`.execute.run_campaign` of those cases) until
    every requirement is decided at the Bonferroni confidence of ``looks`` looks, a run ends in an
    error, or a signal stops it; the last outcome with the last look's figures."""
    t0 = time.perf_counter()
    points = look_points(runs, looks)
    flown = 0
    extra: dict[str, Any] = {"looks": len(points)}
    for j, n in enumerate(points, 1):
        out = fly(range(n))
        flown += out.flown_now
        if out.interrupted is not None:
            break
        rows = storage.read_rows(folder)
        seen = {c: rows[c] for c in range(n) if c in rows}
        verdicts = judge_rows(requirements, seen, len(points))
        errors = any(r["status"] == "error" for r in seen.values())
        decided = all(v.verdict != "UNDECIDED" for v in verdicts) and not errors
        extra.update(look=j, runs_judged=len(seen), decided=decided, verdicts=[v.to_json() for v in verdicts])
        if decided or errors or len(seen) < n:
            break
    base = {f.name: getattr(out, f.name) for f in dataclasses.fields(CampaignOutcome)}
    base.update(flown_now=flown, wall_s=time.perf_counter() - t0)
    return SequentialOutcome(**base, **extra)


def stopped_at(resolved: Mapping[str, Any], cases: np.ndarray, status: np.ndarray,
               columns: Mapping[str, np.ndarray]) -> tuple[int, int, int] | None:
    """(runs, look, looks) when a sequential campaign's done cases are 0 .. n - 1 with n a planned look
    and every requirement decided there (it stopped as planned); None otherwise (the report then says
    which cases are missing)."""
    seq, reqs = resolved.get("sequential"), of_resolved(resolved)
    if not seq or not reqs:
        return None
    points = look_points(int(resolved["runs"]), int(seq["looks"]))
    n = int(np.asarray(cases).size)
    if n not in points or sorted(int(k) for k in cases) != list(range(n)):
        return None
    if any(v.verdict == "UNDECIDED" for v in judge(reqs, status, columns, len(points))):
        return None
    return n, points.index(n) + 1, len(points)
