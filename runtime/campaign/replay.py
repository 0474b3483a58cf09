"""One case of a campaign flown alone: ``rpo run --campaign DIR --case 17``.

The case's scenario is made again from the folder's ``resolved.json`` (the same draws and noise
seed: :mod:`.sampling` needs nothing of the other runs), flown by the scalar runner with every
step recorded ("full logging"), and written as any ``rpo run``.  Lockstep lanes and the scalar
loop give the same bits, and the campaign's record is every ``record_every``-th step of this one,
so :func:`compare` takes those rows, computes the campaign's row from them and checks it against
the folder's (manifest line and history) bit for bit.  :func:`compared` says what was compared: the
history only when its file is the one the manifest line names (sha256), never a file missing or damaged.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.campaign import storage
from rpo.runtime.campaign.fingerprint import model_changes
from rpo.runtime.campaign.spec import Campaign, campaign_from_resolved
from rpo.runtime.errors import CampaignError, ScenarioError


def toml_text(data: dict[str, Any], header: str = "") -> str:
    """A scenario table as TOML text (what ``tomllib.loads`` reads back as ``data``): the case's
    scenario.toml, so that the folder of a case flown alone holds the file that flies it."""
    import json
    import re

    bare = re.compile(r"^[A-Za-z0-9_-]+$")

    def key(k: str) -> str:
        return k if bare.match(k) else json.dumps(k)

    def value(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }"
        raise TypeError(f"cannot write {type(v).__name__} as TOML")

    lines = [header] if header else []

    def table(d: dict[str, Any], path: list[str]) -> None:
        plain = {k: v for k, v in d.items() if not isinstance(v, dict) and not _tables(v)}
        if path and (plain or not d):
            lines.append(f"\n[{'.'.join(key(p) for p in path)}]")
        lines.extend(f"{key(k)} = {value(v)}" for k, v in plain.items())
        for k, v in d.items():
            if isinstance(v, dict):
                table(v, [*path, k])
            elif _tables(v):
                for entry in v:
                    lines.append(f"\n[[{'.'.join(key(p) for p in [*path, k])}]]")
                    lines.extend(f"{key(a)} = {value(b)}" for a, b in entry.items())

    table(data, [])
    return "\n".join(lines) + "\n"


def _tables(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def case_scenario(folder: Path, case: int, model: Any, full_logging: bool = True) -> tuple[Any, Campaign]:
    """(the validated scenario of ``case``, the campaign); refused when the model changed."""
    from rpo.runtime.scenario import validate_scenario

    resolved = storage.read_resolved(folder)
    changed = model_changes(resolved, model)
    if changed:
        raise CampaignError(f"{folder}: the model changed since the campaign ran ({changed}): case {case} would "
                            "not be the campaign's run")
    try:
        camp = campaign_from_resolved(resolved, model.manifest)
    except (KeyError, TypeError, ValueError) as exc:
        raise CampaignError(f"{folder}/{storage.RESOLVED}: damaged ({type(exc).__name__}: "
                            f"{' '.join(str(exc).split())[:120]}): case {case} cannot be made again") from None
    if not 0 <= case < camp.runs:
        raise CampaignError(f"--case {case}: must be in [0, {camp.runs - 1}] (the campaign has {camp.runs} runs)")
    data = camp.case_data(case)
    if full_logging:
        data["simulation"]["record_every"] = 1
    try:
        sc = validate_scenario(data, camp.case_source(case), model.manifest)
    except ScenarioError as exc:
        raise ScenarioError(f"{exc} (the campaign recorded this draw as invalid)") from None
    sc._text = toml_text(data, f"# case {case} of the campaign {camp.name} ({folder}), every step recorded:\n"
                               f"# its draws and noise seed applied to the campaign's scenario")
    return sc, camp


def _subsample(res: Any, every: int) -> Any:
    """The record the campaign keeps of a run recorded at every step: every ``every``-th step and
    the last (Simulation.run's grid)."""
    from rpo.runtime.run.simulate import RunResult, record_grid

    steps = np.rint((res.t - res.t[0]) / res.dt).astype(np.int64)
    last = int(steps[-1])
    idx = np.searchsorted(steps, record_grid(last, every))
    return RunResult(t=res.t[idx], z=res.z[idx], y=res.y[idx], z_labels=res.z_labels, z_units=res.z_units,
                     y_labels=res.y_labels, y_units=res.y_units, steps_done=res.steps_done,
                     steps_requested=res.steps_requested, dt=res.dt, wall_time=res.wall_time,
                     divergence=res.divergence, meta=res.meta, field_labels=res.field_labels)


def _history(folder: Path, case: int, rows: dict[int, dict[str, Any]]) -> tuple[str, Path]:
    """(the state of ``case``'s history file, storage.history_state; its path)."""
    row = rows.get(case, {})
    path = storage.history_path(folder, case, row)
    return storage.history_state(path, row.get("history_sha256")), path


def compared(folder: Path, case: int) -> str:
    """What :func:`compare` compares for ``case``, said as it is: the history only when its file is
    the one the manifest names (its sha256), or an older folder's file that reads (unverified)."""
    rows = storage.read_rows(folder)
    if case not in rows:
        return f"nothing: case {case} is not in {folder / storage.MANIFEST}"
    state, path = _history(folder, case, rows)
    shown = f"{storage.HISTORIES}/{path.name}"
    if state == "whole":
        return f"status, metrics, history; {shown} has the sha256 its manifest line records"
    if state == "unverified":
        return (f"status, metrics, history; {shown} has no recorded sha256 (a folder written before rpo "
                "recorded them): the history compared is not verified to be the campaign's")
    return (f"status and metrics; its history file is {state} ({shown}), so the history was not compared; "
            f"`rpo mc resume {folder}` flies its runs again")


def compare(folder: Path, camp: Campaign, model: Any, case: int, result: Any, inputs: Any) -> list[str]:
    """What differs between the case flown alone and the campaign's record of it (empty: the same
    bits: status, every metric, and every history value when the history file is readable:
    :func:`compared` says which)."""
    from rpo.runtime.campaign.execute import run_row

    rows = storage.read_rows(folder)
    if case not in rows:
        return [f"case {case} is not in {folder / storage.MANIFEST} yet (not flown by the campaign)"]
    stored = rows[case]
    row, hist, _ = run_row(camp, model, inputs, _subsample(result, camp.scenario_data["simulation"]["record_every"]))
    out = []
    if stored["status"] != row["status"]:
        out.append(f"status: {stored['status']} in the campaign, {row['status']} alone")
    for k, v in row["metrics"].items():
        w = stored.get("metrics", {}).get(k)
        if not (v == w or (v is None and w is None)):
            out.append(f"metric {k}: {w!r} in the campaign, {v!r} alone")
    state, path = _history(folder, case, rows)
    if state in storage.READABLE:
        cols = dict(storage.read_histories(folder, [case], rows)).get(case)
        if cols is None:  # an older folder's file that does not read as Parquet, or without the case
            out.append(f"history: {path} does not hold case {case} readably")
            return out
        for k, v in hist.items():
            a = np.asarray(v, np.float32)
            b = cols.get(k)
            if b is None or b.shape != a.shape or not np.array_equal(a, b, equal_nan=True):
                out.append(f"history column {k} differs")
    return out
