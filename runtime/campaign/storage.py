"""The campaign folder: what is written, when, and how nothing is lost.

::

    DIR/
      campaign.toml        the campaign file's text, as given
      resolved.json        everything that decides the runs (the resolved scenario, the dispersions,
                           the design) with its hash and the model's manifest hash
      manifest.jsonl       one line per finished run (its row: case, seed, status, draws, outcomes,
                           metrics), appended as each batch of runs comes back and fsynced on a
                           background thread (all of it before the command returns)
      histories/case_000017.parquet   each flown run's decimated time history (float32), written
                           atomically (temporary file, then rename) by the worker that flew it
      summary.parquet      one row per run, sorted by case, rebuilt from manifest.jsonl (atomically)
                           at the end of every `rpo mc run` / `rpo mc resume`

**Loss and resumption.**  A run counts as done when its line is in ``manifest.jsonl``; its history
was renamed into place before the line is written (and is checked whole by resume:
:func:`history_ok`).  SIGKILL at any moment leaves at worst a last line cut in
half (ignored and cut off by ``resume``), a history without its line (flown again, replaced by
identical bytes) or a temporary file (removed).  ``summary.parquet`` is a pure function of the
lines (sorted by case; later lines for a case replace earlier ones), so a resumed campaign's
summary has the bytes of one never interrupted.  A machine crash loses at most the lines
written since the last fsync completed (flown again by resume; :class:`Syncer`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import CampaignError
from ..metrics import UNITS

RESOLVED = "resolved.json"
MANIFEST = "manifest.jsonl"
SUMMARY = "summary.parquet"
HISTORIES = "histories"
CAMPAIGN_COPY = "campaign.toml"
STATUSES = ("ok", "diverged", "invalid", "error")
OUTCOMES = ("att_reached", "pos_reached", "diverged", "constraint_violated", "failed")
#: The summary's metric columns: the scalar metrics of rpo.runtime.metrics, in its order.
METRICS = tuple(UNITS)


def history_path(folder: Path, case: int) -> Path:
    return Path(folder) / HISTORIES / f"case_{case:06d}.parquet"


def _atomic_write(path: Path, data: bytes, durable: bool = True) -> None:
    """Write a temporary file beside ``path`` and rename it over ``path``: a reader sees the old
    file or the new one, never a part.  ``durable``: fsync before the rename (survives a machine
    crash, not only a killed process; ~1-3 ms a file, so the histories skip it, see
    :func:`history_ok`)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as fh:
        fh.write(data)
        if durable:
            fh.flush()
            os.fsync(fh.fileno())
    os.replace(tmp, path)


def write_json(path: Path, obj: Any) -> None:
    _atomic_write(path, (json.dumps(obj, indent=1, sort_keys=True) + "\n").encode())


def read_resolved(folder: Path) -> dict[str, Any]:
    path = Path(folder) / RESOLVED
    try:
        return dict(json.loads(path.read_text()))
    except FileNotFoundError:
        raise CampaignError(f"{folder}: not a campaign folder (no {RESOLVED}; `rpo mc run` makes one)") from None
    except (OSError, ValueError) as exc:
        raise CampaignError(f"{path}: cannot be read ({exc})") from None


# --------------------------------------------------------------------------- manifest


def append_rows(folder: Path, rows: Iterable[Mapping[str, Any]], sync: bool = True) -> bool:
    """Append one line per row (whole lines, in one write) and, with ``sync``, fsync: each line is
    on disk when this returns.  ``sync=False`` leaves the fsync to the caller (:class:`Syncer`);
    the lines are in the page cache either way, so a killed process loses none.  Returns whether
    anything was written."""
    lines = "".join(json.dumps(r, sort_keys=True, allow_nan=False) + "\n" for r in rows)
    if not lines:
        return False
    with open(Path(folder) / MANIFEST, "a", encoding="utf-8") as fh:
        fh.write(lines)
        fh.flush()
        if sync:
            os.fsync(fh.fileno())
    return True


class Syncer:
    """fsyncs of the manifest on a background thread, while the next batch flies: an fsync waits
    for the disk (~15 ms here) and needs no CPU, so a campaign should not wait for it between
    batches.  :meth:`close` waits for the last one (``rpo mc run`` and ``resume`` return only then).
    A machine that crashes mid-campaign loses at most the lines written since the last completed
    fsync: those runs are flown again by resume (a killed process loses nothing: the lines are in
    the page cache)."""

    def __init__(self, folder: Path) -> None:
        from concurrent.futures import ThreadPoolExecutor
        self.path = Path(folder) / MANIFEST
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="rpo-fsync")
        self.pending: list[Any] = []

    def _sync(self) -> None:
        fd = os.open(self.path, os.O_RDONLY)
        try:
            os.fsync(fd)  # the file's dirty pages, whichever descriptor wrote them
        finally:
            os.close(fd)

    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        if append_rows(self.path.parent, rows, sync=False):
            self.pending = [f for f in self.pending if not f.done()]
            self.pending.append(self.pool.submit(self._sync))

    def close(self) -> None:
        """Wait for every fsync; an fsync's error (a full or failing disk) is raised here."""
        try:
            for f in self.pending:
                f.result()
        finally:
            self.pool.shutdown(wait=True)


def read_rows(folder: Path, repair: bool = False) -> dict[int, dict[str, Any]]:
    """case -> its latest row.  A last line without its newline (a write cut by a kill) is
    ignored and, with ``repair``, cut off so that the next append starts on a line of its own."""
    path = Path(folder) / MANIFEST
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        return {}
    end = raw.rfind(b"\n") + 1
    if repair and end < len(raw):
        with open(path, "r+b") as fh:
            fh.truncate(end)
            fh.flush()
            os.fsync(fh.fileno())
    rows: dict[int, dict[str, Any]] = {}
    for n, line in enumerate(raw[:end].splitlines()):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except ValueError:
            raise CampaignError(f"{path}: line {n + 1} is not JSON (edited by hand?): refusing to guess; "
                                "remove the line to fly that run again") from None
        rows[int(row["case"])] = row
    return rows


# --------------------------------------------------------------------------- histories


_SCHEMAS: dict[tuple, Any] = {}
#: Parquet codec of the histories: lz4, the fastest writer of these few-kB files (zstd saves ~10 %
#: of the bytes of such noisy float32 columns at twice the time)
HISTORY_COMPRESSION = "lz4"


def write_history(folder: Path, case: int, t: np.ndarray, columns: Mapping[str, np.ndarray],
                  units: Mapping[str, str], meta: Mapping[str, Any]) -> Path:
    """One run's time history: ``t`` (float64, s) and the columns as float32 (7 digits: ample for
    envelopes and figures; the metrics come from the full-precision record), atomically.  Units
    in the schema metadata ``rpo.units``, the case in ``rpo.case``."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    key = (tuple(columns), tuple(units.get(n, "") for n in columns))
    schema = _SCHEMAS.get(key)
    if schema is None:  # one schema per campaign: building it is most of a small file's cost
        fields = [pa.field("t", pa.float64(), nullable=False)] + [pa.field(n, pa.float32(), nullable=False)
                                                                  for n in columns]
        schema = _SCHEMAS[key] = pa.schema(fields, metadata={
            "rpo.units": json.dumps({"t": "s", **{n: units.get(n, "") for n in columns}}, sort_keys=True)})
    # one float32 block, column-major, so that each column is a contiguous slice (the record's
    # columns are strided views of the run's state and output arrays)
    n = len(t)
    block = np.empty((len(columns), n), np.float32)
    for i, v in enumerate(columns.values()):
        block[i] = v
    # one Arrow array, each column a slice of it (the same file bytes); typed, because pyarrow's
    # type inference from an untyped NumPy array took 0.65 ms of a run's 5 ms of Python
    flat = pa.array(block.reshape(-1), type=pa.float32())
    arrays = [pa.array(np.asarray(t, np.float64), type=pa.float64())] + [flat.slice(i * n, n)
                                                                         for i in range(len(columns))]
    table = pa.Table.from_arrays(arrays, schema=schema.with_metadata(
        {**schema.metadata, b"rpo.case": json.dumps(dict(meta), sort_keys=True).encode()}))
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression=HISTORY_COMPRESSION, use_dictionary=False, write_statistics=False)
    path = history_path(folder, case)
    _atomic_write(path, sink.getvalue().to_pybytes(), durable=False)
    return path


def history_ok(folder: Path, case: int) -> bool:
    """Whether a run's history is whole: present and ending with Parquet's footer magic.  A killed
    process cannot leave a part (the file is renamed into place whole), but a machine that crashed
    before the page cache reached the disk can: resume re-flies such a run."""
    path = history_path(folder, case)
    try:
        size = path.stat().st_size
        if size < 12:
            return False
        with open(path, "rb") as fh:
            fh.seek(-4, os.SEEK_END)
            return fh.read(4) == b"PAR1"
    except OSError:
        return False


def read_history(folder: Path, case: int) -> tuple[dict[str, np.ndarray], dict[str, str], dict[str, Any]]:
    """(columns, units, meta) of one run's history."""
    import pyarrow.parquet as pq

    path = history_path(folder, case)
    if not path.exists():
        raise CampaignError(f"{path}: no history for case {case} (not flown: invalid or missing)")
    table = pq.read_table(path)
    md = table.schema.metadata or {}
    cols = {name: table.column(name).to_numpy() for name in table.column_names}
    return cols, json.loads(md.get(b"rpo.units", b"{}")), json.loads(md.get(b"rpo.case", b"{}"))


def remove_temporaries(folder: Path) -> int:
    """Remove the temporary files a killed writer left (``.<name>.<pid>.tmp``); how many."""
    n = 0
    for sub in (Path(folder), Path(folder) / HISTORIES):
        if sub.is_dir():
            for p in sub.glob(".*.tmp"):
                p.unlink(missing_ok=True)
                n += 1
    return n


# --------------------------------------------------------------------------- summary


def draw_columns(dispersions: Sequence[Mapping[str, Any]], rows: Iterable[Mapping[str, Any]]) -> list[str]:
    """The draw columns in dispersion order (each dispersion's columns as its rows name them)."""
    seen: dict[str, None] = {}
    for r in rows:
        for c in r.get("draws", {}):
            seen.setdefault(c, None)
    order = {d["key"]: i for i, d in enumerate(dispersions)}

    def rank(col: str) -> tuple[int, int]:
        key = next((k for k in sorted(order, key=len, reverse=True) if col == f"draw.{k}"
                    or col.startswith(f"draw.{k}[") or col.startswith(f"draw.{k}.")), None)
        return (order.get(key, len(order)) if key is not None else len(order), list(seen).index(col))

    return sorted(seen, key=rank)


def write_summary(folder: Path, resolved: Mapping[str, Any], rows: Mapping[int, Mapping[str, Any]]) -> Path:
    """``summary.parquet`` from the rows (one per case, sorted), atomically; its bytes depend only
    on the rows and the resolved campaign."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    cases = sorted(rows)
    ordered = [rows[c] for c in cases]
    dcols = draw_columns(resolved["dispersions"], ordered)
    units: dict[str, str] = {"case": "-", "seed": "-"}
    unit_of = {d["key"]: d.get("unit", "") for d in resolved["dispersions"]}
    arrays: list[Any] = []
    fields: list[Any] = []

    def add(name: str, values: list, typ: Any, unit: str = "") -> None:
        fields.append(pa.field(name, typ, metadata={"unit": unit}))
        arrays.append(pa.array(values, typ))
        units[name] = unit

    add("case", [int(r["case"]) for r in ordered], pa.int64(), "-")
    add("seed", [int(r["seed"]) for r in ordered], pa.uint64(), "-")
    add("status", [str(r["status"]) for r in ordered], pa.string())
    add("message", [str(r.get("message") or "") for r in ordered], pa.string())
    for col in dcols:
        vals = [r.get("draws", {}).get(col) for r in ordered]
        is_str = any(isinstance(v, str) for v in vals)
        key = col.removeprefix("draw.").split("[")[0]
        key = next((k for k in unit_of if key == k or key.startswith(f"{k}.")), key)
        unit = "deg" if col.endswith(".angle_deg") else unit_of.get(key, "")
        add(col, [None if v is None else (str(v) if is_str else float(v)) for v in vals],
            pa.string() if is_str else pa.float64(), unit)
    for col in OUTCOMES:
        add(col, [r.get("outcome", {}).get(col) for r in ordered], pa.bool_())
    for col in METRICS:
        add(col, [r.get("metrics", {}).get(col) for r in ordered], pa.float64(), UNITS[col])
    meta = {"name": resolved["name"], "runs": resolved["runs"], "rows": len(ordered),
            "complete": len(ordered) == resolved["runs"] and all(r["status"] != "error" for r in ordered)}
    schema = pa.schema(fields, metadata={"rpo.units": json.dumps(units, sort_keys=True),
                                         "rpo.campaign": json.dumps(meta, sort_keys=True)})
    sink = pa.BufferOutputStream()
    pq.write_table(pa.Table.from_arrays(arrays, schema=schema), sink, compression="zstd")
    path = Path(folder) / SUMMARY
    _atomic_write(path, sink.getvalue().to_pybytes())
    return path
