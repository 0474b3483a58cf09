"""What a campaign folder's manifest line must be to count: a run record of the folder's campaign
(:func:`row_problem`), and what reading the manifest found (:class:`ManifestScan`).  The manifest
itself is read by ``storage.scan_manifest``; the rules are in docs/campaigns.md ("What the folder
trusts")."""

from __future__ import annotations

import functools
import json
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

STATUSES = ("ok", "diverged", "invalid", "error")
#: JSON's names of the Python types json.loads gives
_JSON = {dict: "an object", list: "an array", str: "a string", int: "a number", float: "a number",
         bool: "a boolean", type(None): "null"}


#: A history file's name as rpo writes it (storage.history_name): nothing else is opened from a line
_HISTORY_NAME = re.compile(r"batch_\d{6}_[0-9a-f]{12}\.parquet")
_SHA256 = re.compile(r"[0-9a-f]{64}")


def json_kind(value: Any) -> str:
    """What ``value`` (parsed JSON) is, in JSON's words ("an object", "a number", ...)."""
    return _JSON.get(type(value), type(value).__name__)


@dataclass
class ManifestScan:
    """``manifest.jsonl`` read and checked (``storage.scan_manifest``): ``rows`` case -> its latest valid
    line; ``problems`` one text per line that is not counted (``line N: why``); ``unverified`` the
    flown cases whose line records no sha256 of their history (written before rpo recorded it)."""

    rows: dict[int, dict[str, Any]]
    problems: list[str]
    unverified: list[int]


@functools.lru_cache(maxsize=8)
def case_seeds(seed: int, runs: int, sampling: str = "random", dispersions: int = 0) -> tuple[int, ...]:
    """The noise seed of every case of a campaign (master ``seed``, ``runs`` runs, its ``sampling``
    and number of ``dispersions``: :func:`~.sampling.noise_case`), computed at once: one by one
    they cost ~0.2 ms a line, more than reading it."""
    from rpo.runtime.campaign.sampling import noise_case, run_seeds
    return tuple(run_seeds(seed, [noise_case(sampling, dispersions, c) for c in range(runs)]))


def row_problem(row: Any, runs: int | None, seeds: tuple[int, ...] | None) -> str:
    """Why ``row`` (a manifest line, parsed) is not a run record of the campaign (``runs`` runs,
    ``seeds`` its cases' noise seeds: :func:`case_seeds`; None: unknown, not checked); empty if it
    is one."""
    if not isinstance(row, dict):
        return f"{json_kind(row)}, not a run record"
    case = row.get("case")
    if type(case) is not int:
        return "no case number" if case is None else f"case {json.dumps(case)[:30]} is not an integer"
    if case < 0 or (runs is not None and case >= runs):
        return f"case {case} is outside [0, {runs - 1 if runs is not None else 'runs - 1'}]"
    if row.get("status") not in STATUSES:
        return f"case {case}: status {json.dumps(row.get('status'))[:30]} is not one of {', '.join(STATUSES)}"
    for key, typ in (("draws", dict), ("outcome", dict), ("metrics", dict), ("message", str), ("history", str),
                     ("history_sha256", str)):
        if key in row and row[key] is not None and not isinstance(row[key], typ):
            return f"case {case}: {key} is {json_kind(row[key])}, not {_JSON[typ]}"
    bad = [k for k, v in (row.get("metrics") or {}).items()
           if v is not None and (type(v) not in (int, float) or not np.isfinite(v))]
    if bad:
        return f"case {case}: metric {bad[0]} is not a finite number"
    if row.get("history") and not _HISTORY_NAME.fullmatch(row["history"]):
        return f"case {case}: history {json.dumps(row['history'])[:60]} is not a history file's name"
    if row.get("history_sha256") and not _SHA256.fullmatch(row["history_sha256"]):
        return f"case {case}: history_sha256 is not a sha256 digest"
    if seeds is not None and row.get("seed") != seeds[case]:
        return f"case {case}: seed {json.dumps(row.get('seed'))[:30]} is not this campaign's seed of the case"
    return ""
