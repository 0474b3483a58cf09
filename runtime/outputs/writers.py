"""Write the results of one run into a fresh folder, atomically, never overwriting anything.

``out_dir`` must not exist or be an empty folder.  Everything is written into a hidden
temporary sibling (``.<name>.<random>.tmp``) and renamed into place at the end, so a folder
with the final name is always complete, figures included; on any error the temporary folder is
removed.

Contents (:class:`OutputSpec` chooses the columns, the rows, the formats and the figures):

* ``timeseries.<suffix>``, one file per chosen format (Parquet by default): ``t`` [s], the chosen z
  columns, then the chosen y columns, float64, with their units and the run record (Parquet: also
  the pandas ``df.attrs`` of :func:`rpo.runtime.run.result.frame_attrs`, which ``pd.read_parquet``
  restores; MATLAB: one N x k array per layout field).  The formats,
  their files, what each holds and its writer are declared once, in
  :data:`rpo.runtime.formats.OUTPUT_FORMATS` (``docs/scenarios.md`` lists them).  ``y`` at row i
  is the output over the step starting at ``t[i]``: the final row has none (NaN).  Written rows
  are the recorded rows whose step is a multiple of :attr:`OutputSpec.every`, and always the
  final row;
* ``scenario.toml``   the scenario as read (when given);
* ``metrics.json``    the metrics of :mod:`rpo.runtime.outputs.metrics` (computed by the caller from the
  full in-memory record, not from the written rows);  in both JSON files every number has its unit
  beside it, by the rule of :mod:`rpo.runtime.outputs.jsonunits`;
* ``run.json``        status (``ok``/``diverged`` with the divergence message, step, time and
  state label), steps, wall time, backend, seed, controller, model source hash, versions, what
  was written (``output``) and the figure files;
* the figures of :mod:`rpo.runtime.outputs.plots` (``<name>.<figure_format>``, of
  :data:`rpo.runtime.formats.FIGURE_FORMATS`; unless disabled).

Figures are rendered by worker processes (:mod:`rpo.runtime.outputs.figure_workers`; :func:`warm_figures`
starts them early, so matplotlib is imported off the data path while the simulation runs), from
the full-rate in-memory columns, while this process writes the data files; :func:`write_run`
waits for them before the rename, so the folder appears complete or not at all.
A plotting failure is a warning (``plot_error`` in ``run.json``): the data are still written.

A diverged run is written the same way, with the data up to its last good step.
"""

from __future__ import annotations

import ctypes
import errno
import json
import os
import platform
import secrets
import shutil
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.errors import OutputError
from rpo.runtime.formats import (
    DEFAULT_FIGURE_FORMAT,
    DEFAULT_FORMATS,
    FIGURE_FORMATS,
    OUTPUT_FORMATS,
    Column,
    Table,
    unknown_figure_format,
    unknown_format,
)
from rpo.runtime.outputs import figure_workers
from rpo.runtime.outputs.jsonunits import annotate_metrics, annotate_run
from rpo.runtime.outputs.plotdata import FIGURE_FIELDS, FIGURE_ORDER, PlotData
from rpo.runtime.outputs.verdict import name_goal
from rpo.runtime.run import interrupts
from rpo.runtime.run.result import frame_attrs
from rpo.runtime.scenario.channels import Selection, select

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.run.result import RunResult


@dataclass(frozen=True)
class OutputSpec:
    """What :func:`write_run` writes: ``channels`` (entries of :func:`rpo.runtime.scenario.channels.select`;
    None: the default set), ``every`` (steps between written rows; None: every recorded row),
    ``formats`` (of :data:`rpo.runtime.formats.OUTPUT_FORMATS`), ``figures`` and their ``figure_format``
    (of :data:`rpo.runtime.formats.FIGURE_FORMATS`)."""

    channels: tuple[str, ...] | None = None
    every: int | None = None
    formats: tuple[str, ...] = DEFAULT_FORMATS
    figures: bool = True
    figure_format: str = DEFAULT_FIGURE_FORMAT

    def __post_init__(self):
        bad = [f for f in self.formats if f not in OUTPUT_FORMATS]
        if bad or not self.formats:
            raise OutputError(unknown_format(bad))
        if self.figure_format not in FIGURE_FORMATS:
            raise OutputError(unknown_figure_format(self.figure_format))
        if self.every is not None and (int(self.every) != self.every or self.every < 1):
            raise OutputError(f"output every = {self.every}: must be an integer >= 1 (steps)")

    def to_json(self) -> dict[str, Any]:
        return {"channels": None if self.channels is None else list(self.channels), "every": self.every,
                "formats": list(self.formats), "figures": self.figures, "figure_format": self.figure_format}


def rpo_version() -> str:
    try:
        return metadata.version("rpo")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare checkout
        return "unknown"


def _may_write(path: Path) -> bool:
    """True if this process may create entries in the folder ``path``.

    ``os.access`` decides (it sees ACLs and read-only mounts); for root, which may write anywhere,
    the folder must also have a write bit for someone: a folder made read-only for everyone is
    respected even by root."""
    try:
        st = path.stat()
    except OSError:
        return False
    if not os.access(path, os.W_OK | os.X_OK):
        return False
    return os.geteuid() != 0 or bool(st.st_mode & 0o222)


def check_out_dir(out_dir: str | Path) -> Path:
    """Check the results folder completely before anything is computed; return where the results go.

    Refused with :class:`OutputError` (one line, nothing touched): ``.``, ``..``, ``/`` or the
    current folder; a path that exists and is not a folder, or a folder that is not empty; an
    empty folder this user may not write into (its permissions are respected: it is never
    replaced by a writable one); an absent folder whose nearest existing parent is not a folder
    or not writable.  A symlink (in any component) is resolved and the target checked the same
    way; the resolved path is returned then (the results are written there, the link is left as
    it is), else ``out_dir`` as given.
    """
    given = Path(out_dir)
    if given.name in ("", ".", ".."):
        raise OutputError(f"output folder {str(out_dir)!r}: must name a folder of its own (not ., .. or /)")
    real = Path(os.path.realpath(given))
    out = given if real == Path(os.path.abspath(given)) else real
    shown = str(given) if out is given else f"{given} (-> {real})"
    try:
        is_cwd = real == Path.cwd().resolve()
    except OSError:  # the current folder was removed: it cannot be the target
        is_cwd = False
    if is_cwd:
        raise OutputError(f"output folder {shown} is the current folder: choose a new folder (--out)")
    if real.exists():
        if not real.is_dir():
            raise OutputError(f"output folder {shown} exists and is not a folder: refusing to overwrite it")
        try:
            with os.scandir(real) as it:
                entries = next(it, None) is not None
        except OSError as exc:
            raise OutputError(f"output folder {shown} cannot be read ({exc.strerror}): choose another --out") from None
        if entries:
            raise OutputError(f"output folder {shown} exists and is not empty: refusing to overwrite it "
                              "(choose another --out)")
        if not _may_write(real):
            mode = oct(real.stat().st_mode & 0o777)
            raise OutputError(f"output folder {shown} is empty but not writable (mode {mode}): refusing to "
                              "write into it or replace it (make it writable or choose another --out)")
        return out
    parent = real.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        raise OutputError(f"output folder {shown}: {parent} is not a folder")
    if not _may_write(parent):
        raise OutputError(f"output folder {shown}: its parent {parent} is not writable "
                          "(choose another --out)")
    return out


def _jsonable(v: Any) -> Any:
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return _jsonable(v.item()) if v.size == 1 else _jsonable(v.tolist())
    if isinstance(v, np.generic):
        return _jsonable(v.item())
    if isinstance(v, float) and not np.isfinite(v):
        return str(v)
    return v


def _by_label(labels: Sequence[str], values: np.ndarray | None) -> dict[str, float] | None:
    """``{label: value}``, or None when the values are missing or do not match the labels."""
    if values is None or len(values) != len(labels):
        return None
    return dict(zip(labels, np.asarray(values, float).tolist(), strict=True))


def run_record(result: RunResult, model: Model, scenario_path: str | Path | None = None,
               extra_meta: dict | None = None) -> dict[str, Any]:
    """The content of ``run.json`` (also stored in the data files' metadata)."""
    div = result.divergence
    rec = {
        "status": "diverged" if div is not None else "interrupted" if result.meta.get("interrupted") else "ok",
        "divergence": None if div is None else {
            "message": div.message(), "step": int(div.step), "time": float(div.time), "label": div.label,
            "value": float(div.value), "bound": float(div.bound), "where": getattr(div, "where", "state"),
            # both states by label: the one that failed the check and the last good one
            "state": dict(zip(result.z_labels, div.state.tolist(), strict=True)),
            "last_good_state": dict(zip(result.z_labels, div.last_good_state.tolist(), strict=True)),
            # the failing step's outputs by label (non-finite values as text)
            "output": _by_label(result.y_labels, getattr(div, "output", None)),
        },
        "steps_done": int(result.steps_done),
        "steps_requested": int(result.steps_requested),
        "dt": float(result.dt),
        "t_end": float(result.t[-1]) if len(result.t) else 0.0,
        "rows": int(len(result.t)),
        "wall_time": float(result.wall_time),
        "backend": result.meta.get("backend", getattr(model, "backend", None)),
        "seed": result.meta.get("seed"),
        "controller": result.meta.get("controller"),
        "record_every": result.meta.get("record_every"),
        "model_source_hash": model.manifest.source_hash,
        "codegen_tools": dict(model.manifest.tools),
        "rpo_version": rpo_version(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scenario_path": None if scenario_path is None else str(scenario_path),
        "created_utc": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }
    rec.update(extra_meta or {})
    return _jsonable(annotate_run(rec, result, model))  # every number with its unit (jsonunits)


# --------------------------------------------------------------------------- the table written


def written_rows(t: np.ndarray, dt: float, every: int | None) -> np.ndarray:
    """Indices of the recorded rows written: step a multiple of ``every``, and the final row."""
    n = len(t)
    if every is None or every == 1 or n == 0:
        return np.arange(n)
    steps = np.rint((np.asarray(t) - t[0]) / dt).astype(np.int64)
    keep = steps % int(every) == 0
    keep[-1] = True
    return np.flatnonzero(keep)


def columns(result: RunResult, model: Model, spec: OutputSpec) -> tuple[list[Column], Selection]:
    """The columns :func:`write_run` writes (``t`` first), decimated to :func:`written_rows`."""
    ctrl = result.meta.get("controller", "baseline")
    z_name, y_name = f"z_{ctrl}", f"y_{ctrl}"
    z_lay, y_lay = model.layouts.get(z_name, []), model.layouts.get(y_name, [])
    if z_lay or y_lay:
        sel = select(spec.channels, z_lay, y_lay, where=f"{z_name}/{y_name}")
    else:  # no layouts (a bare result): every column
        sel = Selection(tuple(result.z_labels), tuple(result.y_labels))
    rows = written_rows(result.t, result.dt, spec.every)
    info = {lbl: (f.name, f.doc) for f in (*z_lay, *y_lay) for lbl in f.labels}
    out = [Column("t", "s", "", "t", "time", np.ascontiguousarray(result.t[rows]))]
    for labels, units, data, lay, chosen in ((result.z_labels, result.z_units, result.z, z_name, sel.z),
                                            (result.y_labels, result.y_units, result.y, y_name, sel.y)):
        idx = {lbl: i for i, lbl in enumerate(labels)}
        for lbl in chosen:
            i = idx[lbl]
            name, doc = info.get(lbl, (lbl, ""))
            out.append(Column(lbl, units[i], lay, name, doc, np.ascontiguousarray(data[rows, i])))
    return out, sel


# --------------------------------------------------------------------------- figures


def warm_figures() -> None:
    """Start the figure workers now (they import matplotlib while the caller simulates)."""
    from rpo.runtime.outputs import figure_workers
    figure_workers.start()


# --------------------------------------------------------------------------- the folder


def write_run(result: RunResult, out_dir: str | Path, model: Model, scenario_path: str | Path | None = None,
              scenario_text: str | None = None, extra_meta: dict | None = None, *, plots: bool = True,
              params: dict | None = None, gains: dict | None = None, title: str = "",
              metrics: dict | None = None, output: OutputSpec | None = None,
              timings: dict[str, float] | None = None) -> Path:
    """Write ``result`` (a :class:`~rpo.runtime.run.result.RunResult`) into the new folder ``out_dir``.

    ``scenario_text`` (else the file ``scenario_path``) is copied as ``scenario.toml``;
    ``extra_meta`` is merged into ``run.json``; ``params``/``gains`` give the plots their limits
    and goal; ``metrics`` is written as ``metrics.json``; ``output`` chooses columns, rows, formats
    and figures (``plots=False`` also disables the figures); ``timings`` (if given) receives the
    seconds spent on ``data_files`` and then ``figures_wait`` (after the data).  Raises :class:`OutputError` if
    ``out_dir`` exists and is not empty (nothing is touched then) or cannot be written.  Returns
    the folder.
    """
    spec = output or OutputSpec()
    out = check_out_dir(out_dir)  # again: the folder may have changed while the run simulated
    goal = ((extra_meta or {}).get("inputs") or {}).get("goal")  # the goal flown: run.json and its verdict name it
    if goal:
        extra_meta = {**(extra_meta or {}), "goal": goal}
        if isinstance(extra_meta.get("verdict"), dict):
            extra_meta["verdict"] = name_goal(extra_meta["verdict"], goal)
    # an existing (empty, writable) folder is filled in place, so it keeps its permissions, owner
    # and identity; an absent one is made from a temporary sibling by one rename
    in_place = out.is_dir()
    # os.mkdir (not mkdtemp, which makes it 0700): the results get the user's usual permissions
    tmp = (out if in_place else out.parent) / f".{out.name}.{secrets.token_hex(6)}.tmp"
    with interrupts.deferred():  # a signal here cannot leave the hidden folder behind
        try:
            if not in_place:
                out.parent.mkdir(parents=True, exist_ok=True)
            os.mkdir(tmp)
        except OSError as exc:
            raise OutputError(f"cannot create the output folder {out}: {exc.strerror or exc}") from None
    drawing = None
    clock = time.perf_counter()
    try:
        if plots and spec.figures:  # drawn by the workers while the data are written
            data = PlotData.from_result(result, model, params, gains, title, metrics)
            drawing = figure_workers.draw([(data.subset(name), str(tmp), spec.figure_format, name)
                                           for name in FIGURE_FIELDS])

        if scenario_text is None and scenario_path is not None:
            scenario_text = Path(scenario_path).read_text(encoding="utf-8")
        if scenario_text is not None:
            (tmp / "scenario.toml").write_text(scenario_text, encoding="utf-8")
        if metrics is not None:
            (tmp / "metrics.json").write_text(json.dumps(_jsonable(annotate_metrics(metrics, result)), indent=2,
                                                         allow_nan=False) + "\n", encoding="utf-8")
        cols, sel = columns(result, model, spec)
        meta = run_record(result, model, scenario_path, extra_meta)
        meta["output"] = {**spec.to_json(), "rows_written": len(cols[0].data), "columns_written": len(cols),
                          "files": [OUTPUT_FORMATS[f].file for f in spec.formats]}
        attrs = frame_attrs([c.label for c in cols], [c.unit for c in cols], [c.field for c in cols], meta)
        table = Table(cols, json.dumps(meta, sort_keys=False, allow_nan=False), len(sel.z),
                      json.dumps(attrs, allow_nan=False))
        for fmt in spec.formats:
            OUTPUT_FORMATS[fmt].write(tmp / OUTPUT_FORMATS[fmt].file, table)

        if timings is not None:
            timings["data_files"] = time.perf_counter() - clock
            clock = time.perf_counter()
        done, plot_error = drawing.wait() if drawing is not None else ({}, "")
        if timings is not None:
            timings["figures_wait"] = time.perf_counter() - clock
        drawing = None
        names = [f for n in FIGURE_ORDER for f in done.get(n, [])]
        if plot_error:
            warnings.warn(f"some figures were not written: {plot_error}", RuntimeWarning, stacklevel=2)
            meta["plot_error"] = plot_error
        meta["figures"] = names
        (tmp / "run.json").write_text(json.dumps(meta, indent=2, sort_keys=False, allow_nan=False) + "\n",
                                      encoding="utf-8")
    except OSError as exc:
        _abandon(drawing, tmp)
        raise OutputError(f"cannot write the results into {out}: {exc}") from None
    except BaseException:
        _abandon(drawing, tmp)
        raise
    with interrupts.deferred():  # the move is never cut in half; a signal is raised after it
        _move_into_place(tmp, out, in_place)
    return out


def _rename_noreplace(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst``, failing (FileExistsError) if ``dst`` exists, even an empty folder:
    renameat2(RENAME_NOREPLACE) where the C library and file system have it, else a check and rename."""
    fn = getattr(_libc(), "renameat2", None)
    if fn is not None:
        at_fdcwd, noreplace = -100, 1
        if fn(at_fdcwd, os.fsencode(src), at_fdcwd, os.fsencode(dst), noreplace) == 0:
            return
        err = ctypes.get_errno()
        if err not in (errno.ENOSYS, errno.EINVAL):  # EINVAL: this file system has no RENAME_NOREPLACE
            raise OSError(err, os.strerror(err), str(dst))
    if os.path.lexists(dst):
        raise FileExistsError(errno.EEXIST, os.strerror(errno.EEXIST), str(dst))
    os.rename(src, dst)


_LIBC: list[Any] = []


def _libc() -> Any:
    if not _LIBC:
        try:
            _LIBC.append(ctypes.CDLL(None, use_errno=True))
        except OSError:  # pragma: no cover - no C library to ask
            _LIBC.append(None)
    return _LIBC[0]


def _move_into_place(tmp: Path, out: Path, in_place: bool) -> None:
    """The final move of a complete results folder ``tmp`` to ``out``.

    ``in_place``: ``tmp`` is inside the existing empty folder ``out``; its entries are moved up
    (run.json last), then it is removed.  Else ``tmp`` is renamed to ``out`` (atomic, never over an
    existing folder).  If the move fails, what was moved goes back and the results stay in ``tmp``:
    the :class:`OutputError` gives that path.
    """
    moved: list[str] = []
    try:
        if not in_place:
            _rename_noreplace(tmp, out)
            return
        others = sorted(set(os.listdir(out)) - {tmp.name})
        if others:
            raise FileExistsError(errno.ENOTEMPTY, f"it is not empty any more ({', '.join(others[:3])})")
        names = sorted(os.listdir(tmp), key=lambda n: n == "run.json")  # run.json last: the folder is done
        for name in names:
            _rename_noreplace(tmp / name, out / name)
            moved.append(name)
        os.rmdir(tmp)
    except OSError as exc:
        for name in reversed(moved):
            try:
                os.rename(out / name, tmp / name)
            except OSError:
                pass
        raise OutputError(f"cannot move the results into {out} ({exc.strerror or exc}); they are complete "
                          f"in {tmp}") from None


def _abandon(drawing: figure_workers.Drawing | None, tmp: Path) -> None:
    """Remove ``tmp`` without waiting for the figures being drawn into it (a signal in between
    waits: the hidden folder is never left half removed).

    ``tmp`` is renamed first: a worker still drawing opens ``tmp/<figure>`` by name, which then
    fails, so nothing can be created in the folder while it is removed."""
    with interrupts.deferred():
        if drawing is not None:
            drawing.abandon()
        gone = tmp.with_name(f"{tmp.name}.gone")
        try:
            os.rename(tmp, gone)
        except OSError:
            gone = tmp
        shutil.rmtree(gone, ignore_errors=True)
