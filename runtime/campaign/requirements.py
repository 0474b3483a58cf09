"""Requirements of a campaign (``[requirements.<name>]``) and their verdicts with confidence.

::

    [requirements.position_final]
    metric = "pos_err_final_m"   # a metric column of summary.parquet (rpo.runtime.outputs.metrics.UNITS)
    max = 0.5                    # a run meets it when metric <= max (the metric's SI unit); or min = ...
    probability = 0.9973         # required probability that a run meets it
    confidence = 0.95            # one-sided confidence of the PASS / FAIL decision
    description = "final position error below 0.5 m"   # optional

A run meets a requirement when its status is ``ok`` and its metric is a number within the bound.
Every other done case fails it: a diverged run, a run in error, an invalid draw (the dispersion
produced a scenario that cannot be flown: counting it as a success would hide it), and a null
metric (e.g. a settling time of a run that never settled).

**Verdict** (k failures in n done cases, s = n - k successes, a = 1 - confidence): the one-sided
Clopper-Pearson bounds of the success probability,

    lower = B(a; s, k + 1)       (0 when s = 0)
    upper = B(1 - a; s + 1, k)   (1 when k = 0)

with B(q; x, y) the q-quantile of the beta distribution.  PASS when lower >= probability; FAIL when
upper < probability; otherwise UNDECIDED, with the runs still needed: the smallest n' such that
with the same k failures (none more) the lower bound at n' reaches the probability, minus n.
With k = 0 the lower bound is a^(1/n), so PASS needs n >= ln(a) / ln(p): 1109 runs for 0.9973 at
95 % (Hanson & Beard, NASA/TP-2010-216447; the order-statistics argument gives the same count).

A sequential campaign (:mod:`.sequential`) looks at its runs ``looks`` times; each look then judges
at the confidence ``1 - a / looks`` (Bonferroni), so that the chance of any wrong decision over all
the looks stays at most a.  :func:`judge` takes that number of looks.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats as sps

from rpo.runtime.errors import CampaignError
from rpo.runtime.outputs.metrics import UNITS
from rpo.runtime.scenario.messages import show

#: The metric columns a requirement may bound: every scalar metric of the summary.
METRIC_COLUMNS: tuple[str, ...] = tuple(UNITS)
#: summary.parquet's schema metadata key holding the verdicts (JSON).
SUMMARY_KEY = "rpo.requirements"
VERDICTS = ("PASS", "FAIL", "UNDECIDED")
_FIELDS = ("metric", "max", "min", "probability", "confidence", "description")
#: Largest run count :func:`runs_needed` searches (beyond it a requirement is not worth a campaign).
MAX_SEARCH = 10**9


@dataclass(frozen=True)
class Requirement:
    """One requirement: a run meets it when ``metric`` <= ``bound`` (``kind`` "max") or >= ``bound``
    (``kind`` "min"), in the metric's SI unit; it must hold with ``probability`` at ``confidence``."""

    name: str
    metric: str
    kind: str
    bound: float
    probability: float
    confidence: float
    description: str = ""

    @property
    def text(self) -> str:
        """``pos_err_final_m <= 0.5`` (SI)."""
        return f"{self.metric} {'<=' if self.kind == 'max' else '>='} {self.bound:g}"

    def to_json(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_json(cls, d: Mapping[str, Any]) -> Requirement:
        return cls(**{k: d[k] for k in ("name", "metric", "kind", "bound", "probability", "confidence")},
                   description=str(d.get("description", "")))


def _number(where: str, v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise CampaignError(f"{where} = {show(v)}: must be a finite number")
    return float(v)


def _fraction(where: str, v: Any) -> float:
    f = _number(where, v)
    if not 0.0 < f < 1.0:
        raise CampaignError(f"{where} = {show(v)}: must be in (0, 1), e.g. 0.9973")
    return f


def parse_requirements(table: Any, source: str) -> list[Requirement]:
    """``[requirements]`` of a campaign file -> the requirements, in the file's order.  Raises
    :class:`CampaignError` with one line naming the key, the value and what is allowed."""
    if not isinstance(table, dict):
        raise CampaignError(f"{source}: requirements = {show(table)}: must be a table of "
                            "[requirements.<name>] with metric, max or min, probability, confidence")
    out = []
    for name, spec in table.items():
        where = f"{source}: requirements.{name}"
        if not isinstance(spec, dict):
            raise CampaignError(f"{where} = {show(spec)}: must be a table with metric = ..., max = ... (or "
                                "min = ...), probability = ..., confidence = ...")
        unknown = [k for k in spec if k not in _FIELDS]
        if unknown:
            raise CampaignError(f"{where}.{unknown[0]}: unknown field; allowed: {', '.join(_FIELDS)}")
        for k in ("metric", "probability", "confidence"):
            if k not in spec:
                raise CampaignError(f"{where}.{k}: required field is missing")
        metric = spec["metric"]
        if not isinstance(metric, str) or metric not in METRIC_COLUMNS:
            raise CampaignError(f"{where}.metric = {show(metric)}: not a metric column of the summary; "
                                f"available: {', '.join(METRIC_COLUMNS)}")
        kinds = [k for k in ("max", "min") if k in spec]
        if len(kinds) != 1:
            raise CampaignError(f"{where}: give exactly one of max = ... (met when {metric} <= max) or min = ... "
                                f"(met when {metric} >= min), in {UNITS[metric] or 'its unit'}; "
                                f"got {' and '.join(kinds) if kinds else 'neither'}")
        kind = kinds[0]
        bound = _number(f"{where}.{kind}", spec[kind])
        description = spec.get("description", "")
        if not isinstance(description, str):
            raise CampaignError(f"{where}.description = {show(description)}: must be a string")
        out.append(Requirement(name=str(name), metric=metric, kind=kind, bound=bound,
                               probability=_fraction(f"{where}.probability", spec["probability"]),
                               confidence=_fraction(f"{where}.confidence", spec["confidence"]),
                               description=description))
    return out


# --------------------------------------------------------------------------- the statistics


def lower_bound(successes: int, n: int, confidence: float) -> float:
    """One-sided lower Clopper-Pearson bound of a success probability: B(1 - confidence; s, n - s + 1)."""
    if n <= 0 or successes <= 0:
        return 0.0
    if successes == n:  # the closed form, exact to the last bit (the beta quantile is iterative)
        return float((1.0 - confidence) ** (1.0 / n))
    return float(sps.beta.ppf(1.0 - confidence, successes, n - successes + 1))


def upper_bound(successes: int, n: int, confidence: float) -> float:
    """One-sided upper Clopper-Pearson bound of a success probability: B(confidence; s + 1, n - s)."""
    if n <= 0 or successes >= n:
        return 1.0
    if successes == 0:
        return float(1.0 - (1.0 - confidence) ** (1.0 / n))
    return float(sps.beta.ppf(confidence, successes + 1, n - successes))


def runs_needed(probability: float, confidence: float, failures: int = 0) -> int:
    """The fewest runs n such that ``failures`` failures in n runs give a lower bound >= ``probability``
    at ``confidence`` (a PASS).  0 failures: ceil(ln(1 - confidence) / ln(probability)), e.g. 1109 for
    0.9973 at 95 %.  Raises ValueError beyond :data:`MAX_SEARCH` runs."""
    if not (0.0 < probability < 1.0 and 0.0 < confidence < 1.0) or failures < 0:
        raise ValueError(f"runs_needed: probability {probability}, confidence {confidence} in (0, 1), "
                         f"failures {failures} >= 0")

    def ok(n: int) -> bool:
        return lower_bound(n - failures, n, confidence) >= probability

    if failures == 0:  # closed form; the check guards its rounding
        n = max(1, math.ceil(math.log(1.0 - confidence) / math.log(probability)))
        while n > 1 and ok(n - 1):
            n -= 1
        while not ok(n):
            n += 1
        return n
    lo, hi = failures, max(2 * failures + 2, runs_needed(probability, confidence, 0))  # ok(lo) is False
    while not ok(hi):
        lo, hi = hi, 2 * hi
        if hi > MAX_SEARCH:
            raise ValueError(f"runs_needed: more than {MAX_SEARCH} runs")
    while hi - lo > 1:  # the lower bound grows with n at fixed failures
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return hi


@dataclass(frozen=True)
class Verdict:
    """A requirement judged on a campaign: ``failures`` of ``n`` done cases failed it; the one-sided
    bounds of the success probability at ``confidence_used`` (the stated confidence, or the
    Bonferroni share of each look of a sequential campaign); PASS / FAIL / UNDECIDED and, when
    undecided, the runs still needed with no further failure (None when out of reach)."""

    requirement: Requirement
    n: int
    failures: int
    lower: float
    upper: float
    verdict: str
    runs_still_needed: int | None
    confidence_used: float

    @property
    def met(self) -> int:
        return self.n - self.failures

    def to_json(self) -> dict[str, Any]:
        return {"name": self.requirement.name, "metric": self.requirement.metric, "kind": self.requirement.kind,
                "bound": self.requirement.bound, "probability": self.requirement.probability,
                "confidence": self.requirement.confidence, "confidence_used": self.confidence_used,
                "n": self.n, "met": self.met, "failures": self.failures, "lower": self.lower,
                "upper": self.upper, "verdict": self.verdict, "runs_still_needed": self.runs_still_needed}


def decide(req: Requirement, n: int, failures: int, looks: int = 1) -> Verdict:
    """The verdict of ``req`` with ``failures`` failures in ``n`` runs, at the confidence of one of
    ``looks`` Bonferroni-split looks (1: a campaign judged once)."""
    conf = 1.0 - (1.0 - req.confidence) / looks
    s = n - failures
    lo, up = lower_bound(s, n, conf), upper_bound(s, n, conf)
    if lo >= req.probability:
        verdict, more = "PASS", 0
    elif up < req.probability:
        verdict, more = "FAIL", None
    else:
        verdict = "UNDECIDED"
        try:
            more = max(0, runs_needed(req.probability, conf, failures) - n)
        except ValueError:
            more = None
    return Verdict(req, n, failures, lo, up, verdict, more, conf)


def meets(req: Requirement, status: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Which runs meet ``req``: status ``ok`` and the metric a number within the bound."""
    v = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        within = v <= req.bound if req.kind == "max" else v >= req.bound
    return (np.asarray(status) == "ok") & np.isfinite(v) & within


def judge(reqs: Sequence[Requirement], status: np.ndarray, columns: Mapping[str, np.ndarray],
          looks: int = 1) -> list[Verdict]:
    """Every requirement judged over the done cases (``status`` and the metric ``columns``, one
    entry per case; a metric absent from ``columns`` is null in every run)."""
    n = int(np.asarray(status).size)
    out = []
    for r in reqs:
        values = columns.get(r.metric)
        if values is None:
            values = np.full(n, np.nan)
        failures = n - int(np.sum(meets(r, status, values)))
        out.append(decide(r, n, failures, looks))
    return out


def judge_rows(reqs: Sequence[Requirement], rows: Mapping[int, Mapping[str, Any]], looks: int = 1) -> list[Verdict]:
    """:func:`judge` over manifest rows (``{case: row}``, the runner's form)."""
    ordered = [rows[c] for c in sorted(rows)]
    status = np.array([str(r["status"]) for r in ordered], dtype=object)
    cols = {}
    for metric in {r.metric for r in reqs}:
        vals = [r.get("metrics", {}).get(metric) for r in ordered]
        cols[metric] = np.array([np.nan if v is None else float(v) for v in vals], dtype=float)
    return judge(reqs, status, cols, looks)


def of_resolved(resolved: Mapping[str, Any]) -> list[Requirement]:
    """The requirements recorded in a folder's ``resolved.json`` (none for older folders)."""
    return [Requirement.from_json(d) for d in resolved.get("requirements", []) or []]


def summary_metadata(resolved: Mapping[str, Any], rows: Mapping[int, Mapping[str, Any]]) -> dict[str, Any] | None:
    """The verdicts of the campaign's requirements over ``rows`` (JSON-ready, the value of the
    summary's :data:`SUMMARY_KEY`); None for a campaign without requirements."""
    reqs = of_resolved(resolved)
    if not reqs:
        return None
    looks = int((resolved.get("sequential") or {}).get("looks", 1))
    return {"looks": looks, "verdicts": [v.to_json() for v in judge_rows(reqs, rows, looks)]}


def write_summary(folder: Path, resolved: Mapping[str, Any], rows: Mapping[int, Mapping[str, Any]]) -> None:
    """:func:`~.storage.write_summary`, then the verdicts (:func:`summary_metadata`) added to the
    schema metadata of ``folder/summary.parquet`` beside ``rpo.units`` and ``rpo.campaign`` (rewritten
    atomically; a campaign without requirements keeps the bytes storage writes)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from rpo.runtime.campaign import storage

    path = storage.write_summary(folder, resolved, rows)
    meta = summary_metadata(resolved, rows)
    if meta is None:
        return
    table = pq.read_table(path)
    table = table.replace_schema_metadata({**(table.schema.metadata or {}),
                                           SUMMARY_KEY.encode(): json.dumps(meta, sort_keys=True).encode()})
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression="zstd")
    storage._atomic_write(path, sink.getvalue().to_pybytes())


def read_summary_verdicts(folder: Path) -> dict[str, Any] | None:
    """The verdicts recorded in ``folder/summary.parquet`` (None when it holds none)."""
    import pyarrow.parquet as pq

    from rpo.runtime.campaign.storage import SUMMARY
    raw = (pq.read_schema(Path(folder) / SUMMARY).metadata or {}).get(SUMMARY_KEY.encode())
    return None if raw is None else dict(json.loads(raw))
