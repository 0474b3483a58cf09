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
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from rpo.runtime.campaign import storage
from rpo.runtime.campaign.requirements import Requirement, judge_rows


def look_points(runs: int, looks: int) -> list[int]:
    """The planned looks' run counts: ceil(j runs / looks), j = 1 .. looks (distinct, the last = runs)."""
    return sorted({math.ceil(j * runs / looks) for j in range(1, looks + 1)})


def fly_in_looks(requirements: Sequence[Requirement], runs: int, looks: int, folder: Path,
                 fly: Callable[[Sequence[int]], Any]) -> Any:
    """Fly look after look with ``fly(cases)`` (a :func:`~.execute.run_campaign` of those cases:
    it returns a ``CampaignOutcome``) until every requirement is decided at the Bonferroni
    confidence of ``looks`` looks; returns the last outcome with ``sequential`` set to what happened
    (``looks``, ``look``, ``runs_judged``, ``decided``, ``verdicts``)."""
    t0 = time.perf_counter()
    points = look_points(runs, looks)
    flown = 0
    out: Any = None
    info: dict[str, Any] = {}
    for j, n in enumerate(points, 1):
        out = fly(range(n))
        flown += out.flown_now
        if out.interrupted is not None:
            break
        rows = storage.read_rows(folder)
        seen = {c: rows[c] for c in range(n) if c in rows}
        verdicts = judge_rows(requirements, seen, len(points))
        decided = all(v.verdict != "UNDECIDED" for v in verdicts)
        errors = any(r["status"] == "error" for r in seen.values())
        info = {"looks": len(points), "look": j, "runs_judged": len(seen), "decided": decided and not errors,
                "verdicts": [v.to_json() for v in verdicts]}
        if decided or errors or len(seen) < n:
            break
    return dataclasses.replace(out, flown_now=flown, wall_s=time.perf_counter() - t0, sequential=info)
