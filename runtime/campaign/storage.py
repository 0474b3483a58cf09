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
resume: :func:`history_state`).  SIGKILL at any moment leaves at worst a last line cut in half
(ignored and cut off by ``resume``), a history file without its lines (its runs flown again: the
same batch rewrites it with identical bytes, another batch writes its own, and the orphan is
removed when the campaign completes) or a temporary file (removed).  ``summary.parquet`` is a pure function of the
lines (sorted by case; later lines for a case replace earlier ones), so a resumed campaign's
summary has the bytes of one never interrupted.  A machine crash loses at most the lines
written since the last fsync completed (flown again by resume; :class:`Syncer`).

**What is trusted.**  Every manifest line is checked as a run record of this campaign
(:func:`scan_manifest`: the schema, the case in ``[0, runs)``, its seed, the history's name and
sha256); a line that is not one is reported with its number and never counted.  Each line of a
flown run records the sha256 of its history file (``history_sha256``), checked by resume, the
report and replay (:func:`history_state`); lines written before rpo recorded it are read, their
histories reported as unverified.  ``.lock`` (:mod:`.lock`) keeps a second ``rpo mc run`` or
``resume`` out while one flies.
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

from rpo.runtime.campaign.records import STATUSES, ManifestScan, case_seeds, json_kind, row_problem  # noqa: F401
from rpo.runtime.errors import CampaignError
from rpo.runtime.outputs.metrics import UNITS

RESOLVED = "resolved.json"
MANIFEST = "manifest.jsonl"
SUMMARY = "summary.parquet"
HISTORIES = "histories"
CAMPAIGN_COPY = "campaign.toml"
#: The outcome flags of a flown run (``execute.run_row``): ``constraint_violated`` by the verdict's rule
#: (``rpo.runtime.outputs.verdict.violated_constraints``), ``failed`` counting the declared constraints only.
OUTCOMES = ("att_reached", "pos_reached", "diverged", "constraint_violated", "failed")
#: The summary's metric columns: the scalar metrics of rpo.runtime.outputs.metrics, in its order.
METRICS = tuple(UNITS)


def _atomic_write(path: Path, data: bytes, durable: bool = True) -> None:
    """Write a temporary file beside ``path`` and rename it over ``path``: a reader sees the old
    file or the new one, never a part.  ``durable``: fsync before the rename (survives a machine
    crash, not only a killed process; ~1-3 ms a file, so the histories skip it, see
    :func:`history_state`)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as fh:
            fh.write(data)
            if durable:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:  # a full disk, a kill: no temporary left behind (resume removes any other)
        tmp.unlink(missing_ok=True)
        raise


def write_json(path: Path, obj: Any) -> None:
    _atomic_write(path, (json.dumps(obj, indent=1, sort_keys=True) + "\n").encode())


#: The keys of ``resolved.json`` that rpo reads (spec.campaign_from_resolved, the folder's checks), with
#: their JSON types: a file without one of them is not a campaign's.
RESOLVED_KEYS: dict[str, tuple[type, ...]] = {
    "name": (str,), "runs": (int,), "seed": (int,), "sampling": (str,), "record_every": (int,),
    "channels": (list,), "scenario": (dict,), "dispersions": (list,), "controller": (str,),
    "campaign_file": (str,), "hash": (str,)}


def read_resolved(folder: Path) -> dict[str, Any]:
    """The folder's ``resolved.json``, checked to hold the keys rpo reads with their types (refused
    in one line naming the first that is not: a damaged or foreign file)."""
    path = Path(folder) / RESOLVED
    try:
        data = json.loads(path.read_bytes())
    except FileNotFoundError:
        raise CampaignError(f"{folder}: not a campaign folder (no {RESOLVED}; `rpo mc run` makes one)") from None
    except IsADirectoryError:
        raise CampaignError(f"{path}: is a folder, not the campaign's resolved file") from None
    except OSError as exc:
        raise CampaignError(f"{path}: cannot be read ({exc.strerror})") from None
    except ValueError as exc:
        raise CampaignError(f"{path}: damaged, not JSON ({exc}); the folder cannot be resumed or "
                            "reported: fly the campaign again into a new folder") from None
    if not isinstance(data, dict):
        raise CampaignError(f"{path}: damaged: {json_kind(data)}, not the campaign's object")
    for key, types in RESOLVED_KEYS.items():
        v = data.get(key)
        if not isinstance(v, types) or isinstance(v, bool):
            what = "missing" if key not in data else \
                f"{json.dumps(v)[:40]} is {json_kind(v)}, not {json_kind(types[0]())}"
            raise CampaignError(f"{path}: damaged: key {key!r} {what}; fly the campaign again into a new folder")
    if data["runs"] < 1:
        raise CampaignError(f"{path}: damaged: runs = {data['runs']}, must be at least 1")
    return dict(data)


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


def _resolved_if_any(folder: Path) -> dict[str, Any] | None:
    """The folder's resolved.json as far as it reads (the run count and seed the lines are checked
    against); None if absent or unreadable (the commands that need it refuse: read_resolved)."""
    try:
        data = json.loads((folder / RESOLVED).read_bytes())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def scan_manifest(folder: Path, repair: bool = False, resolved: Mapping[str, Any] | None = None) -> ManifestScan:
    """Read ``manifest.jsonl`` and keep the lines that are run records of the campaign: a JSON object
    with an integer ``case`` in ``[0, runs)``, a known status, fields of the right types, the case's
    own seed, a history named as rpo names them with its sha256.  A later line replaces an earlier
    one of its case when the earlier ended in an error (resume flew it again) or the later is an
    error (its history was found lost); any other second line of a case (a duplicate, two commands
    flying the same run) is not counted.  ``resolved``: the campaign (read from the folder when it
    has one; without it the range and the seeds are not checked).

    A last line without its newline (a write cut by a kill or a full disk) is ignored and, with
    ``repair``, cut off so that the next append starts on a line of its own."""
    path = Path(folder) / MANIFEST
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        return ManifestScan({}, [], [])
    if resolved is None:
        resolved = _resolved_if_any(Path(folder))
    runs, seed = (resolved or {}).get("runs"), (resolved or {}).get("seed")
    runs = runs if type(runs) is int and runs > 0 else None
    sampling, disps = (resolved or {}).get("sampling", "random"), (resolved or {}).get("dispersions", [])
    seeds = case_seeds(seed, runs, str(sampling), len(disps) if isinstance(disps, list) else 0) \
        if type(seed) is int and seed >= 0 and runs is not None else None
    end = raw.rfind(b"\n") + 1
    problems = []
    if end < len(raw):
        cut_line = raw.count(b"\n") + 1
        problems.append(f"line {cut_line}: cut short (a write stopped half-way)")
        if repair:
            with open(path, "r+b") as fh:
                fh.truncate(end)
                fh.flush()
                os.fsync(fh.fileno())
    rows: dict[int, dict[str, Any]] = {}
    for n, line in enumerate(raw[:end].split(b"\n")[:-1], start=1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except ValueError:
            problems.append(f"line {n}: not JSON")
            continue
        why = row_problem(row, runs, seeds)
        if not why:
            case = row["case"]
            before = rows.get(case)
            if before is None or before["status"] == "error" or row["status"] == "error":
                rows[case] = row
                continue
            why = f"case {case} again (a duplicate: its run is recorded by an earlier line)"
        problems.append(f"line {n}: {why}")
    unverified = sorted(c for c, r in rows.items() if r["status"] in ("ok", "diverged") and not r.get("history_sha256"))
    return ManifestScan(rows, problems, unverified)


def read_rows(folder: Path, repair: bool = False) -> dict[int, dict[str, Any]]:
    """case -> its latest row: the run records of ``manifest.jsonl`` (:func:`scan_manifest`; the
    lines that are not one are left out)."""
    return scan_manifest(folder, repair).rows


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
    """:func:`write_history_file`'s file name."""
    return write_history_file(folder, runs, units)[0]


def write_history_file(folder: Path, runs: Sequence[History], units: Mapping[str, str]) -> tuple[str, str]:
    """The histories of one batch's flown ``runs``, in one Parquet file written atomically (a
    temporary file renamed into place: a reader sees all of it or none); returns its name and the
    sha256 of its bytes (hex; the runs' manifest lines record it: :func:`history_state`).

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
    data = sink.getvalue().to_pybytes()
    _atomic_write(Path(folder) / HISTORIES / name, data, durable=False)
    return name, hashlib.sha256(data).hexdigest()


#: What :func:`history_state` finds: ``whole`` (its bytes have the sha256 its lines record),
#: ``unverified`` (no sha256 recorded, an older folder: only Parquet's magic at both ends is
#: checked), ``missing``, ``damaged`` (another sha256, no magic, or unreadable).
READABLE = ("whole", "unverified")


def _state_of(data: bytes | None, sha256: str | None) -> str:
    if data is None:
        return "missing"
    if sha256:
        return "whole" if hashlib.sha256(data).hexdigest() == sha256 else "damaged"
    if len(data) < 12 or not data[:4] == data[-4:] == b"PAR1":
        return "damaged"
    import pyarrow as pa
    import pyarrow.parquet as pq
    try:  # no hash to check: at least its footer must parse (a file cut but keeping its last bytes does not)
        pq.read_metadata(pa.BufferReader(data))
    except (pa.ArrowException, OSError, ValueError):
        return "damaged"
    return "unverified"


def _read_bytes(path: Path) -> bytes | None:
    """A history file's bytes; None if it is not there; b"" if it cannot be read (damaged)."""
    try:
        return path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError:  # a folder in its place, no permission: not a history rpo can use
        return b""


def history_state(path: Path, sha256: str | None = None) -> str:
    """Whether the history file ``path`` is the one its manifest lines name (``sha256``: what they
    record, None for lines written before rpo recorded it): one of ``whole``, ``unverified``,
    ``missing``, ``damaged`` (:data:`READABLE`).  A killed process cannot leave a part (the file
    is renamed into place whole), but a machine that crashed before the page cache reached the
    disk can, and so can a hand or a tool: resume re-flies the runs of a file not READABLE."""
    return _state_of(_read_bytes(path), sha256)


def mark_lost_histories(folder: Path, rows: dict[int, dict[str, Any]], fresh: Iterable[str] = ()) -> None:
    """A flown run whose history file is not the one its line names (missing: a remote worker that
    does not share the folder; another sha256: a machine crash before the page cache reached the
    disk, a file cut or edited) is an error, flown again by resume: its line appended, ``rows``
    updated.  Each file is checked once (:func:`damaged_histories`; ``fresh``: as there)."""
    lost = {c: (state, path) for path, (state, cases) in damaged_histories(folder, rows, fresh).items()
            for c in cases}
    fixed = [{**rows[c], "status": "error", "message": f"its history {lost[c][1].name} is {lost[c][0]} in the "
              "campaign folder (Dask workers must share the folder's filesystem)"} for c in sorted(lost)]
    for r in fixed:
        r.pop("history", None)
        r.pop("history_sha256", None)
    if fixed:
        append_rows(folder, fixed)
        rows.update({r["case"]: r for r in fixed})


def damaged_histories(folder: Path, rows: Mapping[int, Mapping[str, Any]],
                      fresh: Iterable[str] = ()) -> dict[Path, tuple[str, list[int]]]:
    """The files the flown runs of ``rows`` name that are not usable: path -> (state, its cases); each
    checked once; ``fresh``: names just written and hashed by this command's workers, checked to exist only."""
    fresh = set(fresh)
    by_file: dict[Path, tuple[str | None, list[int]]] = {}
    for c, r in sorted(rows.items()):
        if r.get("status") in ("ok", "diverged"):
            path = history_path(folder, c, r)
            by_file.setdefault(path, (r.get("history_sha256"), []))[1].append(c)
    out = {}
    for path, (sha, cases) in by_file.items():
        state = ("whole" if path.is_file() else "missing") if path.name in fresh else history_state(path, sha)
        if state not in READABLE:
            out[path] = (state, cases)
    return out


def read_histories(folder: Path, cases: Iterable[int], rows: Mapping[int, Mapping[str, Any]] | None = None,
                   columns: Sequence[str] | None = None) -> Iterator[tuple[int, dict[str, np.ndarray] | None]]:
    """(case, its history's columns) for each of ``cases``, in order; None for a case with no
    history (not flown, invalid, an error, or its file missing).  Each file is read once, for all
    of its cases that are asked for, and only if it is the file its lines name (its sha256:
    :func:`history_state`; a damaged file gives None).  ``rows``: the manifest's rows (read here
    when not given); ``columns``: only these (``t`` and those present; default all but ``case``)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder = Path(folder)
    rows = read_rows(folder) if rows is None else rows
    cases = [int(c) for c in cases]
    by_file: dict[Path, list[int]] = {}
    for c in cases:
        by_file.setdefault(history_path(folder, c, rows.get(c)), []).append(c)
    found: dict[int, dict[str, np.ndarray]] = {}
    for path, wanted in by_file.items():
        data = _read_bytes(path)
        if _state_of(data, rows.get(wanted[0], {}).get("history_sha256")) not in READABLE:
            continue  # missing, or not the bytes its lines name: no history (the caller says so)
        assert data is not None
        try:
            buf = pa.BufferReader(data)
            names = pq.read_schema(buf).names
            pick = [n for n in names if n != "case"] if columns is None else [n for n in columns if n in names]
            table = pq.read_table(pa.BufferReader(data), columns=(["case"] if "case" in names else []) + pick)
        except (pa.ArrowException, OSError, ValueError):  # an older folder's unverified file, damaged inside
            continue
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
        row = rows.get(case)
        if row is None or row.get("status") not in ("ok", "diverged"):
            raise CampaignError(f"{path}: no history for case {case} (not flown: invalid, an error or not done)")
        state = history_state(path, row.get("history_sha256"))
        raise CampaignError(f"{path}: the history of case {case} is {state if state != 'whole' else 'not in it'}; "
                            f"`rpo mc resume {folder}` flies its runs again")
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
