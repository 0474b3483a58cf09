"""A campaign folder as the report reads it: ``resolved.json``, ``summary.parquet`` (one row per finished
case) and the histories, as NumPy arrays (pyarrow and NumPy only; no pandas); the statuses and metrics the
report is about.  The folder's format is in :mod:`.storage`; the report's conventions in :mod:`.reporting`."""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from rpo.runtime.campaign.records import json_kind
from rpo.runtime.campaign.storage import (  # noqa: F401  (the statuses and outcomes: declared once, there)
    OUTCOMES,
    STATUSES,
    history_path,
    read_histories,
    read_rows,
)
from rpo.runtime.errors import CampaignError

FLOWN = ("ok", "diverged")
#: The metrics with a tolerance bound and a worst-case list: (column, bound side, worst-case title).
MAIN_METRICS: tuple[tuple[str, str, str], ...] = (
    ("pos_err_final_m", "upper", "largest final position error"),
    ("att_err_final_rad", "upper", "largest final attitude error"),
    ("pos_settling_time_s", "upper", "longest position settling time"),
    ("att_settling_time_s", "upper", "longest attitude settling time"),
    ("propellant_kg", "upper", "most propellant"),
    ("delta_v_m_s", "upper", ""),
    ("pos_err_ss_rms_m", "upper", ""),
    ("att_err_ss_rms_rad", "upper", ""),
    ("wheel_momentum_peak_N_m_s", "upper", ""),
    ("beta_fov_min_m", "lower", ""),
    ("beta_ca_min_m2", "lower", ""),
)
#: The metrics drawn against the dispersed values (one scatter grid each).
SCATTER_METRICS = ("att_settling_time_s", "pos_settling_time_s", "att_err_final_rad", "pos_err_final_m",
                   "propellant_kg")
#: History channels of the envelope figure: (column, y label, scale to the displayed unit).
ENVELOPE_CHANNELS = (("err_att_rad", "attitude error [deg]", 180.0 / math.pi),
                     ("err_pos_m", "position error [m]", 1.0),
                     ("h_w_norm", "wheel momentum norm [N m s]", 1.0))
PERCENTILES = (5.0, 50.0, 95.0)


# --------------------------------------------------------------------------- reading


def _column_kind(t: pa.DataType) -> str:
    if pa.types.is_boolean(t):
        return "bool"
    if pa.types.is_integer(t):
        return "int"
    if pa.types.is_floating(t):
        return "float"
    return "string"


def _to_numpy(col: pa.ChunkedArray) -> np.ndarray:
    """A parquet column as NumPy: floats and bools as float64 with NaN for null (bools 1.0/0.0),
    integers as int64/uint64 (float64 with NaN if they have nulls), strings as ``str`` ("" for null)."""
    kind = _column_kind(col.type)
    if kind == "bool" or kind == "float" or (kind == "int" and col.null_count):
        return np.asarray(col.cast(pa.float64()).to_numpy(zero_copy_only=False), dtype=np.float64)
    if kind == "int":
        return np.asarray(col.to_numpy())
    if pa.types.is_dictionary(col.type):
        col = col.cast(pa.string())
    values = col.to_pylist()
    return np.array(["" if v is None else str(v) for v in values], dtype=str)


def _meta_json(schema: pa.Schema, key: bytes) -> dict:
    raw = (schema.metadata or {}).get(key)
    if not raw:
        return {}
    try:
        out = json.loads(raw)
    except ValueError:
        return {}
    return out if isinstance(out, dict) else {}


def summary_table(campaign_dir: str | Path) -> dict[str, np.ndarray]:
    """The columns of ``<campaign_dir>/summary.parquet`` as NumPy arrays, in file order.

    Floats and the nullable bool outcomes are float64 (NaN = null; bools as 1.0/0.0), integers
    keep their type (``case`` int64, ``seed`` uint64), strings are ``str`` arrays ("" = null).
    """
    table = pq.read_table(Path(campaign_dir) / "summary.parquet")
    return {name: _to_numpy(table.column(name)) for name in table.column_names}


def case_history(campaign_dir: str | Path, case: int, columns: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """The time history of one flown case as NumPy arrays (``t`` [s] and the channels, in their
    units; ``columns`` selects some, those absent from the file are left out).  Raises
    FileNotFoundError for a case that has no history (invalid draw, worker error, not done)."""
    folder = Path(campaign_dir)
    rows = read_rows(folder)
    cols = dict(read_histories(folder, [case], rows, columns)).get(case)
    if cols is None:
        path = history_path(folder, case, rows.get(case))
        raise FileNotFoundError(f"case {case} has no history (not in {path}: the case was not flown, "
                                f"or is not done yet)")
    return cols


@dataclass
class CampaignFolder:
    """A campaign folder read into memory: the resolved campaign, the summary columns, their kinds
    (``bool``, ``int``, ``float``, ``string``) and units, and the campaign metadata of the file."""

    path: Path
    resolved: dict
    columns: dict[str, np.ndarray]
    kinds: dict[str, str]
    units: dict[str, str]
    meta: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return str(self.resolved.get("name") or self.meta.get("name") or self.path.name)

    @property
    def requested(self) -> int:
        return int(self.resolved.get("runs", self.meta.get("runs", len(self.cases))))

    @property
    def cases(self) -> np.ndarray:
        return self.columns.get("case", np.empty(0, dtype=np.int64))

    @property
    def status(self) -> np.ndarray:
        return self.columns.get("status", np.empty(0, dtype=str))

    @property
    def draws(self) -> list[str]:
        return [c for c in self.columns if c.startswith("draw.")]

    @property
    def numeric_draws(self) -> list[str]:
        return [c for c in self.draws if self.kinds[c] != "string"]

    @property
    def metrics(self) -> list[str]:
        return [c for c, k in self.kinds.items() if k == "float" and c not in ("case", "seed")
                and not c.startswith("draw.")]

    def mask(self, statuses: Iterable[str]) -> np.ndarray:
        return np.isin(self.status, list(statuses))

    def unit(self, column: str) -> str:
        return self.units.get(column, "")


class MissingSummary(CampaignError, FileNotFoundError):
    """A campaign folder without ``summary.parquet``: a user error (one line, exit 2) that is still
    the FileNotFoundError the Python API raised before."""


#: The summary columns the report cannot do without (storage.write_summary writes them all).
SUMMARY_COLUMNS = ("case", "seed", "status")


def _read_summary(path: Path, runs: int | None) -> pa.Table:
    """``summary.parquet`` read and checked as one rpo wrote: readable Parquet with the columns of
    :data:`SUMMARY_COLUMNS`, each case once and in ``[0, runs)``; refused in one line naming what is
    wrong and how to write it again (resume rebuilds it from the manifest)."""
    fix = f"`rpo mc resume {path.parent}` writes it again from manifest.jsonl"
    try:
        table = pq.read_table(path)
    except FileNotFoundError:
        raise MissingSummary(f"{path} does not exist (no run has finished, or it was removed): {fix}") from None
    except (pa.ArrowException, OSError, ValueError) as exc:
        why = " ".join(str(exc).split())[:100]
        raise CampaignError(f"{path}: damaged, not a campaign summary ({why}): {fix}") from None
    lacking = [c for c in SUMMARY_COLUMNS if c not in table.column_names]
    if lacking:
        raise CampaignError(f"{path}: damaged, no column {lacking[0]!r}: {fix}")
    case = table.column("case")
    if not pa.types.is_integer(case.type) or case.null_count:
        raise CampaignError(f"{path}: damaged, its case column is not whole numbers: {fix}")
    cases = np.asarray(case.to_numpy())
    if cases.size != np.unique(cases).size:
        raise CampaignError(f"{path}: damaged, a case appears twice: {fix}")
    if cases.size and (cases.min() < 0 or (runs is not None and cases.max() >= runs)):
        raise CampaignError(f"{path}: damaged, case {int(cases.max() if cases.min() >= 0 else cases.min())} is "
                            f"outside [0, {runs - 1 if runs else 'runs - 1'}]: {fix}")
    return table


def read_folder(campaign_dir: str | Path) -> CampaignFolder:
    """Read ``resolved.json`` (optional) and ``summary.parquet`` (required, checked: :func:`_read_summary`)
    of a campaign folder."""
    path = Path(campaign_dir)
    resolved_path = path / "resolved.json"
    try:
        resolved = json.loads(resolved_path.read_bytes()) if resolved_path.is_file() else {}
    except (OSError, ValueError) as exc:
        raise CampaignError(f"{resolved_path}: damaged ({type(exc).__name__}): the campaign cannot be "
                            "reported; fly it again into a new folder") from None
    if not isinstance(resolved, dict):
        raise CampaignError(f"{resolved_path}: damaged: {json_kind(resolved)}, not the campaign's object")
    runs = resolved.get("runs")
    table = _read_summary(path / "summary.parquet", runs if type(runs) is int else None)
    columns = {name: _to_numpy(table.column(name)) for name in table.column_names}
    kinds = {name: _column_kind(table.schema.field(name).type) for name in table.column_names}
    units = {str(k): str(v) for k, v in _meta_json(table.schema, b"rpo.units").items()}
    return CampaignFolder(path, resolved, columns, kinds, units, _meta_json(table.schema, b"rpo.campaign"))


def first_difference(a: Any, b: Any, path: str = "") -> str:
    """The first difference between two resolved campaigns, as ``key: then -> now``."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if a.get(k) != b.get(k):
                return first_difference(a.get(k), b.get(k), f"{path}.{k}" if path else str(k))
        return "(no difference)"
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            if x != y:
                return first_difference(x, y, f"{path}[{i}]")
    from rpo.runtime.scenario.messages import show
    return f"{path}: {show(a)} then, {show(b)} now"
