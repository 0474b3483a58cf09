"""The campaign folder: what is written, when, and how nothing is lost.

::

    DIR/
      campaign.toml        the campaign file's text, as given
      resolved.json        everything that decides the runs (the resolved scenario, the dispersions,
                           the design) with its hash and the model's manifest hash
      manifest.jsonl       one line per finished run (its row: case, seed, status, draws, outcomes,
                           metrics, and the file of its history), appended as each batch of runs
                           comes back and fsynced on a background thread (all of it before the
                           command returns)
      histories/batch_000032_<digest>.parquet   the decimated time histories (float32) of one
                           batch's flown runs, with a ``case`` column, written atomically
                           (temporary file, then rename) by the worker that flew the batch
      summary.parquet      one row per run, sorted by case, rebuilt from manifest.jsonl (atomically)
                           at the end of every `rpo mc run` / `rpo mc resume`

**Loss and resumption.**  A run counts as done when its line is in ``manifest.jsonl``; its
batch's history file was renamed into place before the line is written (and is checked whole by
resume: :func:`history_ok`).  SIGKILL at any moment leaves at worst a last line cut in half
(ignored and cut off by ``resume``), a history file without its lines (its runs flown again: the
same batch rewrites it with identical bytes, another batch writes its own, and the orphan is
removed when the campaign completes) or a temporary file (removed).  ``summary.parquet`` is a pure function of the
lines (sorted by case; later lines for a case replace earlier ones), so a resumed campaign's
summary has the bytes of one never interrupted.  A machine crash loses at most the lines
written since the last fsync completed (flown again by resume; :class:`Syncer`).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import orjson

from rpo.runtime.errors import CampaignError
from rpo.runtime.outputs.metrics import UNITS

RESOLVED = "resolved.json"
MANIFEST = "manifest.jsonl"
SUMMARY = "summary.parquet"
HISTORIES = "histories"
CAMPAIGN_COPY = "campaign.toml"
STATUSES = ("ok", "diverged", "invalid", "error")
#: The outcome flags of a flown run (``execute.run_row``): ``constraint_violated`` by the verdict's rule
#: (``rpo.runtime.outputs.verdict.violated_constraints``), ``failed`` counting the declared constraints only.
OUTCOMES = ("att_reached", "pos_reached", "diverged", "constraint_violated", "failed")
#: The summary's metric columns: the scalar metrics of rpo.runtime.outputs.metrics, in its order.
METRICS = tuple(UNITS)


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


#: A manifest line: one JSON object, keys sorted, NumPy scalars as numbers, a newline.  orjson
#: rather than json: a row is ~11 kB (the draws and the applied vectors, ~250 floats) and json took
#: 0.13 ms to write one, orjson 0.014 ms.  orjson writes a NaN or inf as null where json raised; a
#: row holds none: metrics are finite or None, a refused draw's non-finite cells are null
#: (execute._json_draws), the applied vectors are checked finite (execute.applied).  Lines are read
#: back with json (read_rows), which gives the same floats.
_LINE = orjson.OPT_SORT_KEYS | orjson.OPT_APPEND_NEWLINE | orjson.OPT_SERIALIZE_NUMPY


def append_rows(folder: Path, rows: Iterable[Mapping[str, Any]], sync: bool = True) -> bool:
    """Append one line per row (whole lines, in one write) and, with ``sync``, fsync: each line is
    on disk when this returns.  ``sync=False`` leaves the fsync to the caller (:class:`Syncer`);
    the lines are in the page cache either way, so a killed process loses none.  Returns whether
    anything was written."""
    lines = b"".join(orjson.dumps(r, option=_LINE) for r in rows)
    if not lines:
        return False
    with open(Path(folder) / MANIFEST, "ab") as fh:
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
#: Parquet codec of the histories: lz4, the fastest writer of these files (zstd saves ~10 % of the
#: bytes of such noisy float32 columns at twice the time)
HISTORY_COMPRESSION = "lz4"
#: The histories of a batch: one file, named by :func:`history_name`.
HISTORY_GLOB = "batch_*.parquet"


@dataclass(frozen=True)
class History:
    """One flown run's decimated time history, as a batch hands it to :func:`write_histories`:
    ``t`` [s] and the chosen ``columns`` (SI, the record's units), and the run's ``meta`` (case,
    seed, status)."""

    case: int
    t: np.ndarray
    columns: Mapping[str, np.ndarray]
    meta: Mapping[str, Any]


def history_name(cases: Sequence[int]) -> str:
    """The file of the histories of a batch flying ``cases`` (in that order): its first case and a
    digest of the whole list.  The same batch flown again (resume) rewrites its own file with the
    same bytes; two different batches never share a name."""
    digest = hashlib.sha256(",".join(str(int(c)) for c in cases).encode()).hexdigest()[:12]
    return f"batch_{int(cases[0]):06d}_{digest}.parquet"


def legacy_history_path(folder: Path, case: int) -> Path:
    """Where rpo before batch files kept a run's history (one file per run, no manifest entry):
    read for folders made then."""
    return Path(folder) / HISTORIES / f"case_{case:06d}.parquet"


def history_path(folder: Path, case: int, row: Mapping[str, Any] | None) -> Path:
    """The file holding ``case``'s history: the batch file its manifest ``row`` names (the row's
    ``history``), else the per-run file of older campaign folders."""
    name = (row or {}).get("history")
    return Path(folder) / HISTORIES / str(name) if name else legacy_history_path(folder, case)


def write_histories(folder: Path, runs: Sequence[History], units: Mapping[str, str]) -> str:
    """The histories of one batch's flown ``runs``, in one Parquet file written atomically (a
    temporary file renamed into place: a reader sees all of it or none); returns its name.

    Columns: ``case`` (int64), ``t`` (float64, s) and each channel as float32 (7 digits: ample for
    envelopes and figures; the metrics come from the full-precision record), the rows of each run
    together, in the order of ``runs``.  Units in the schema metadata ``rpo.units``; the runs'
    ``meta`` in ``rpo.runs`` (a JSON list).  One file per batch, not per run: creating a file costs
    more than encoding a run's few kB (0.6-1.2 ms a file against 0.14 ms a run in one batch file,
    docs/campaigns.md)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    names = tuple(runs[0].columns)
    if any(tuple(r.columns) != names for r in runs):
        raise ValueError("write_histories: the runs of a batch must record the same channels")
    key = (names, tuple(units.get(n, "") for n in names))
    schema = _SCHEMAS.get(key)
    if schema is None:  # one schema per campaign: building it is a good part of a small file's cost
        fields = [pa.field("case", pa.int64(), nullable=False), pa.field("t", pa.float64(), nullable=False)]
        fields += [pa.field(n, pa.float32(), nullable=False) for n in names]
        schema = _SCHEMAS[key] = pa.schema(fields, metadata={
            "rpo.units": json.dumps({"case": "-", "t": "s", **{n: units.get(n, "") for n in names}},
                                    sort_keys=True)})
    sizes = [len(r.t) for r in runs]
    n = sum(sizes)
    # one float32 block, channel-major, so that each channel is a contiguous slice of one Arrow
    # array (the record's columns are strided views of each run's state and output arrays)
    block = np.empty((len(names), n), np.float32)
    start = 0
    for r, size in zip(runs, sizes, strict=True):
        for i, v in enumerate(r.columns.values()):
            block[i, start:start + size] = v
        start += size
    flat = pa.array(block.reshape(-1), type=pa.float32())
    case = np.repeat(np.array([r.case for r in runs], np.int64), sizes)
    t = np.concatenate([np.asarray(r.t, np.float64) for r in runs])
    arrays = [pa.array(case, type=pa.int64()), pa.array(t, type=pa.float64())]
    arrays += [flat.slice(i * n, n) for i in range(len(names))]
    meta = json.dumps([dict(r.meta) for r in runs], sort_keys=True).encode()
    table = pa.Table.from_arrays(arrays, schema=schema.with_metadata({**schema.metadata, b"rpo.runs": meta}))
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression=HISTORY_COMPRESSION, use_dictionary=False, write_statistics=False)
    name = history_name([r.case for r in runs])
    _atomic_write(Path(folder) / HISTORIES / name, sink.getvalue().to_pybytes(), durable=False)
    return name


def history_ok(path: Path) -> bool:
    """Whether a history file is whole: present and ending with Parquet's footer magic.  A killed
    process cannot leave a part (the file is renamed into place whole), but a machine that crashed
    before the page cache reached the disk can: resume re-flies the runs of such a file."""
    try:
        if path.stat().st_size < 12:
            return False
        with open(path, "rb") as fh:
            fh.seek(-4, os.SEEK_END)
            return fh.read(4) == b"PAR1"
    except OSError:
        return False


def read_histories(folder: Path, cases: Iterable[int], rows: Mapping[int, Mapping[str, Any]] | None = None,
                   columns: Sequence[str] | None = None) -> Iterator[tuple[int, dict[str, np.ndarray] | None]]:
    """(case, its history's columns) for each of ``cases``, in order; None for a case with no
    history (not flown, invalid, an error, or its file missing).  Each file is read once, for all
    of its cases that are asked for.  ``rows``: the manifest's rows (read here when not given);
    ``columns``: only these (``t`` and those present; default all but ``case``)."""
    import pyarrow.parquet as pq

    folder = Path(folder)
    rows = read_rows(folder) if rows is None else rows
    cases = [int(c) for c in cases]
    by_file: dict[Path, list[int]] = {}
    for c in cases:
        by_file.setdefault(history_path(folder, c, rows.get(c)), []).append(c)
    found: dict[int, dict[str, np.ndarray]] = {}
    for path, wanted in by_file.items():
        if not path.is_file():
            continue
        names = pq.read_schema(path).names
        pick = [n for n in names if n != "case"] if columns is None else [n for n in columns if n in names]
        table = pq.read_table(path, columns=(["case"] if "case" in names else []) + pick)
        cols = {n: table.column(n).to_numpy() for n in pick}
        if "case" not in names:  # a per-run file of an older folder: the whole file is the run
            found[wanted[0]] = cols
            continue
        case_col = table.column("case").to_numpy()
        for c in wanted:
            idx = np.flatnonzero(case_col == c)
            if idx.size:  # a batch's runs are contiguous in its file
                found[c] = {n: v[idx[0]: idx[-1] + 1] for n, v in cols.items()}
    for c in cases:
        yield c, found.get(c)


def read_history(folder: Path, case: int, rows: Mapping[int, Mapping[str, Any]] | None = None
                 ) -> tuple[dict[str, np.ndarray], dict[str, str], dict[str, Any]]:
    """(columns, units, meta) of one run's history (``rows``: the manifest's, read when not given)."""
    import pyarrow.parquet as pq

    folder = Path(folder)
    rows = read_rows(folder) if rows is None else rows
    path = history_path(folder, case, rows.get(case))
    cols = dict(read_histories(folder, [case], rows)).get(case)
    if cols is None:
        raise CampaignError(f"{path}: no history for case {case} (not flown: invalid or missing)")
    md = pq.read_schema(path).metadata or {}
    units = json.loads(md.get(b"rpo.units", b"{}"))
    units.pop("case", None)
    if b"rpo.runs" in md:
        meta: dict[str, Any] = next((m for m in json.loads(md[b"rpo.runs"]) if m.get("case") == case), {})
    else:
        meta = json.loads(md.get(b"rpo.case", b"{}"))
    return cols, units, meta


def remove_orphans(folder: Path, rows: Mapping[int, Mapping[str, Any]]) -> int:
    """Remove the batch history files no manifest row names (a batch written, then killed before
    its lines: its runs were flown again into another file); how many.  Only when no batch is in
    flight: at the end of a campaign whose batches all came back."""
    named = {str(r["history"]) for r in rows.values() if r.get("history")}
    n = 0
    for p in (Path(folder) / HISTORIES).glob(HISTORY_GLOB):
        if p.name not in named:
            p.unlink(missing_ok=True)
            n += 1
    return n


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
    """The draw columns in dispersion order, and within a dispersion the value itself, then its
    named parts (``.angle_deg``), then its components in index order (``[2]`` before ``[10]``,
    ``[0][2]`` before ``[1][1]``): an order of the names alone, whatever the order of the rows'
    keys (the manifest's lines sort them as text)."""
    seen: dict[str, None] = {}
    for r in rows:
        for c in r.get("draws", {}):
            seen.setdefault(c, None)
    order = {d["key"]: i for i, d in enumerate(dispersions)}
    longest_first = sorted(order, key=len, reverse=True)

    def rank(col: str) -> tuple[int, int, str, tuple[int, ...]]:
        key = next((k for k in longest_first if col == f"draw.{k}" or col.startswith(f"draw.{k}[")
                    or col.startswith(f"draw.{k}.")), None)
        if key is None:  # a column of no dispersion (an older folder's): last, by name
            return (len(order), 3, col, ())
        rest = col[len(f"draw.{key}"):]
        if rest.startswith("["):
            return (order[key], 2, "", tuple(int(i) for i in re.findall(r"\[(\d+)\]", rest)))
        return (order[key], 1 if rest else 0, rest, ())

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
