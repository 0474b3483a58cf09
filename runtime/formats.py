"""The file formats rpo writes, each declared once: the time histories' formats with their writers,
and the figures' formats with what matplotlib needs for each.

:data:`OUTPUT_FORMATS` (``[output] formats``, ``rpo run --format``) maps each name to an
:class:`OutputFormat`: its file suffix, what its file holds and the function that writes it.
:data:`FIGURE_FORMATS` (``[output] figure_format``, ``rpo run --figure-format``, the campaign report)
maps each name to a :class:`FigureFormat`: the ``savefig`` options of a run's figures and the
metadata that keeps a campaign figure's bytes free of dates and versions.  Everything else derives
from these two tables: the scenario schema's allowed values (:mod:`rpo.runtime.scenario.schema`),
the writer of the results folder (:mod:`rpo.runtime.outputs.writers`), the figures
(:mod:`rpo.runtime.outputs.plots`, :mod:`rpo.runtime.campaign.figures`), the command's choices and
help (:mod:`rpo.runtime.cli.main`), the error messages (:func:`unknown_format`,
:func:`unknown_figure_format`) and the reference in ``docs/scenarios.md``
(:mod:`rpo.runtime.docgen.choices`).  ``tests/test_vocabularies.py`` shows that no other module
spells the names.  **Adding a format is one entry here** (and, for a time-history format, its
writer function beside it).

Why this module sits in the lowest layer, beside :mod:`rpo.runtime.errors`, and holds the writers
too: the scenario layer needs the names (to validate ``[output]``) and may not import the outputs
layer that writes the files; the command line needs them when its options are declared, and
``rpo --help`` should not import pydantic (the scenario package) for them.  A list of names down
here with the writers registered from the outputs layer would be a second list (and a test to keep
the two equal); the writers need nothing of rpo (a table of named float64 columns in, a file out;
pyarrow and SciPy are imported when one is called), so they live with their names and a format is
declared in one place.
"""

from __future__ import annotations

import copy
import json
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

#: Every double written as text with this format reads back bit for bit (17 significant digits).
CSV_FORMAT = "%.17g"
MATLAB_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,62}$")


# --------------------------------------------------------------------------- the table written


@dataclass
class Column:
    """One written column: its label, unit, layout (``z_<ctrl>`` or ``y_<ctrl>``; "" for ``t``),
    the layout field it belongs to, that field's doc, and its values (float64)."""

    label: str
    unit: str
    layout: str
    field: str
    doc: str
    data: np.ndarray


@dataclass
class Table:
    """What a writer writes: ``columns`` (``t`` first, then ``z_count`` state columns, then the
    outputs) and the run record as JSON (``metadata``), stored in the file where the format can;
    ``frame_attrs``: the pandas ``DataFrame.attrs`` of the table as JSON (units, fields, the run),
    which the Parquet file carries where ``pandas.read_parquet`` restores them from."""

    columns: Sequence[Column]
    metadata: str
    z_count: int
    frame_attrs: str = ""


#: The Parquet schema metadata key pandas (>= 2.1) writes ``df.attrs`` to and restores them from.
PANDAS_ATTRS = "PANDAS_ATTRS"


# --------------------------------------------------------------------------- writers


def write_parquet(path: Path, table: Table) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    cols = table.columns
    fields = [pa.field(c.label, pa.float64(), nullable=False, metadata={
        "unit": c.unit, "layout": c.layout, "field": c.field, "doc": c.doc}) for c in cols]
    units = json.dumps({c.label: c.unit for c in cols})
    meta = {"rpo.run": table.metadata, "rpo.units": units}
    if table.frame_attrs:
        meta[PANDAS_ATTRS] = table.frame_attrs
    schema = pa.schema(fields, metadata=meta)
    arrow = pa.Table.from_arrays([pa.array(c.data, pa.float64()) for c in cols], schema=schema)
    pq.write_table(arrow, path, compression="zstd", use_dictionary=False,
                   column_encoding={c.label: "BYTE_STREAM_SPLIT" for c in cols})


def matlab_names(labels: Sequence[str], reserved: Sequence[str] = ("units", "metadata", "columns")) -> list[str]:
    """Valid, distinct MATLAB variable names for ``labels`` (unchanged where already valid)."""
    out: list[str] = []
    taken = set(reserved)
    for lbl in labels:
        name = lbl if MATLAB_NAME.match(lbl) else re.sub(r"\W", "_", lbl)
        if not name[:1].isalpha():
            name = f"v_{name}"
        name = name[:63]
        base, k = name, 1
        while name in taken:
            k += 1
            name = f"{base[:60]}_{k}"
        taken.add(name)
        out.append(name)
    return out


#: The members of a ``.mat`` file's ``history`` struct that describe its fields (no field takes these names).
MAT_INFO = ("units", "labels", "layouts", "docs")


def mat_struct(table: Table) -> dict[str, Any]:
    """The ``history`` struct of :func:`write_mat`: per layout field (``t`` first, then the state,
    then the outputs, in column order) its N x k array of the written columns, and the structs
    ``units`` (field -> unit), ``labels`` (field -> 1 x k cell array of the column labels),
    ``layouts`` and ``docs``; a field's name is made a valid MATLAB name where it is not one."""
    groups: dict[tuple[str, str], list[Column]] = {}
    for c in table.columns:  # by layout and field (a state field and an output field never merge)
        groups.setdefault((c.layout, c.field or c.label), []).append(c)
    names = matlab_names([f for _, f in groups], reserved=MAT_INFO)
    out: dict[str, Any] = {}
    info: dict[str, dict[str, Any]] = {k: {} for k in MAT_INFO}
    for name, cs in zip(names, groups.values(), strict=True):
        out[name] = np.column_stack([c.data for c in cs])
        info["units"][name] = cs[0].unit
        info["labels"][name] = np.array([c.label for c in cs], dtype=object).reshape(1, -1)
        info["layouts"][name] = cs[0].layout
        info["docs"][name] = cs[0].doc
    return {**out, **info}


def write_mat(path: Path, table: Table) -> None:
    from scipy.io import savemat

    savemat(path, {"history": mat_struct(table), "metadata": table.metadata}, do_compression=True,
            oned_as="column", long_field_names=True)


def write_csv(path: Path, table: Table) -> None:
    cols = table.columns
    np.savetxt(path, np.column_stack([c.data for c in cols]), fmt=CSV_FORMAT, delimiter=",",
               header=",".join(f"{c.label} [{c.unit}]" for c in cols), comments="")


def write_npz(path: Path, table: Table) -> None:
    cols = table.columns
    z, y = cols[1:1 + table.z_count], cols[1 + table.z_count:]
    n = len(cols[0].data)

    def block(cs):
        return np.column_stack([c.data for c in cs]) if cs else np.empty((n, 0))

    def text(cs, what):
        return np.array([getattr(c, what) for c in cs], dtype=str)

    np.savez_compressed(path, t=cols[0].data, z=block(z), y=block(y), z_labels=text(z, "label"),
                        z_units=text(z, "unit"), y_labels=text(y, "label"), y_units=text(y, "unit"),
                        z_fields=text(z, "field"), y_fields=text(y, "field"), metadata=np.array(table.metadata))


# --------------------------------------------------------------------------- readers (rpo.runtime.outputs.reading)


def read_parquet(path: Path) -> Table:
    import pyarrow.parquet as pq

    arrow = pq.read_table(path)
    cols = []
    for name in arrow.column_names:
        meta = {k.decode(): v.decode() for k, v in (arrow.schema.field(name).metadata or {}).items()}
        cols.append(Column(name, meta.get("unit", ""), meta.get("layout", ""), meta.get("field", name),
                           meta.get("doc", ""), np.asarray(arrow.column(name).to_numpy(), dtype=np.float64)))
    raw = arrow.schema.metadata or {}
    return Table(cols, raw.get(b"rpo.run", b"{}").decode(), sum(c.layout.startswith("z") for c in cols),
                 raw.get(PANDAS_ATTRS.encode(), b"").decode())


def read_mat(path: Path) -> Table:
    from scipy.io import loadmat

    mat = loadmat(path)
    h = mat["history"][0, 0]
    info = {k: h[k][0, 0] for k in MAT_INFO}

    def text(a: np.ndarray) -> str:
        return str(a[0]) if a.size else ""

    cols = []
    for name in h.dtype.names:
        if name in MAT_INFO:
            continue
        block = np.asarray(h[name], np.float64)
        labels = [text(x) for x in info["labels"][name].ravel()]
        cols += [Column(lbl, text(info["units"][name]), text(info["layouts"][name]), name, text(info["docs"][name]),
                        np.ascontiguousarray(block[:, i])) for i, lbl in enumerate(labels)]
    return Table(cols, text(mat["metadata"]), sum(c.layout.startswith("z") for c in cols))


def read_npz(path: Path) -> Table:
    with np.load(path) as f:
        cols = [Column("t", "s", "", "t", "time", np.asarray(f["t"], np.float64))]
        for b in ("z", "y"):
            fields = f[f"{b}_fields"] if f"{b}_fields" in f else f[f"{b}_labels"]  # older files: no fields
            cols += [Column(str(lbl), str(u), b, str(fld), "", np.ascontiguousarray(f[b][:, i], np.float64))
                     for i, (lbl, u, fld) in enumerate(zip(f[f"{b}_labels"], f[f"{b}_units"], fields, strict=True))]
        return Table(cols, str(f["metadata"]), len(f["z_labels"]))


# --------------------------------------------------------------------------- the time histories' formats


@dataclass(frozen=True)
class OutputFormat:
    """A time-history format: ``name`` (as ``[output] formats`` and ``--format`` spell it), the file
    ``suffix`` (``timeseries.<suffix>``), ``note`` (a word for lists: "MATLAB"), ``holds`` (what
    the file holds, for the reference), ``write(path, table)``, whether it is written by default,
    and ``read(path)``, the :class:`Table` back with its units, layouts and fields (None: the file
    does not keep them; :func:`rpo.runtime.outputs.reading.read_run` reads the first format with one)."""

    name: str
    suffix: str
    holds: str
    write: Callable[[Path, Table], None]
    note: str = ""
    default: bool = False
    read: Callable[[Path], Table] | None = None

    @property
    def file(self) -> str:
        return f"timeseries.{self.suffix}"


#: The time-history formats, in the order the messages, the help and the docs list them.
OUTPUT_FORMATS: dict[str, OutputFormat] = {f.name: f for f in (
    OutputFormat("parquet", "parquet", default=True, write=write_parquet, read=read_parquet, holds=(
        "one table: `t` [s], the chosen z columns, then the chosen y columns, float64, zstd-compressed "
        "(byte-stream-split encoding: lossless); each field's metadata holds `unit`, `layout` "
        "(`z_<ctrl>`/`y_<ctrl>`), `field` and `doc`, the file's metadata `rpo.run` (the run record), "
        "`rpo.units` (label -> unit) and `PANDAS_ATTRS` (what `pandas.read_parquet` restores as `df.attrs`: "
        "`units`, `fields`, `run`). pandas, polars, pyarrow, DuckDB, R's arrow and MATLAB's "
        "`parquetread` open it")),
    OutputFormat("mat", "mat", note="MATLAB", write=write_mat, read=read_mat, holds=(
        "MATLAB v5 (`scipy.io.savemat`): a struct `history` with one N x k array per layout field "
        "(`history.t` N x 1, `history.r` N x 3, ...: the field's written columns) and the structs "
        "`history.units` (field -> unit), `history.labels` (field -> cell array of its column labels), "
        "`history.layouts`, `history.docs`; the char array `metadata` (the run record as JSON)")),
    OutputFormat("csv", "csv", write=write_csv, holds=(
        "the same table as text, header `name [unit]`, every double with 17 significant digits "
        "(reads back bit for bit)")),
    OutputFormat("npz", "npz", write=write_npz, read=read_npz, holds=(
        "NumPy: `t`, `z`, `y`, `z_labels`, `z_units`, `y_labels`, `y_units`, `z_fields`, `y_fields` (each "
        "column's layout field), `metadata`")),
)}
#: The names, in order (what ``[output] formats`` accepts).
FORMAT_NAMES: tuple[str, ...] = tuple(OUTPUT_FORMATS)
#: What a run writes when nothing chooses.
DEFAULT_FORMATS: tuple[str, ...] = tuple(f.name for f in OUTPUT_FORMATS.values() if f.default)


def unknown_format(bad: Sequence[str]) -> str:
    """The message for unknown time-history formats (or none)."""
    return f"output format {', '.join(bad) or '(none)'}: allowed {', '.join(FORMAT_NAMES)}"


# --------------------------------------------------------------------------- the figures' formats


@dataclass(frozen=True)
class FigureFormat:
    """A figure format matplotlib's ``savefig`` writes (chosen by the suffix, which is the name):
    ``quick`` its extra ``savefig`` options for a run's figures (drawn on every run: speed first),
    ``fixed`` the ``savefig`` metadata that leaves no date, software version or random id in the
    file (the campaign report: the same folder gives the same bytes)."""

    name: str
    quick: Mapping[str, Any] = field(default_factory=dict)
    fixed: Mapping[str, Any] = field(default_factory=dict)
    default: bool = False

    @property
    def suffix(self) -> str:
        return self.name

    def quick_options(self) -> dict[str, Any]:
        return copy.deepcopy(dict(self.quick))

    def fixed_metadata(self) -> dict[str, Any]:
        return dict(self.fixed)


#: The figure formats, in the order the messages and the docs list them.
FIGURE_FORMATS: dict[str, FigureFormat] = {f.name: f for f in (
    # zlib level 1: a third of the PNG encoding time for files about 20 % larger
    FigureFormat("png", default=True, quick={"pil_kwargs": {"compress_level": 1}}, fixed={"Software": None}),
    FigureFormat("svg", fixed={"Date": None, "Creator": None}),
    FigureFormat("pdf", fixed={"CreationDate": None, "Creator": None, "Producer": None}),
)}
#: The names, in order (what ``[output] figure_format`` accepts).
FIGURE_FORMAT_NAMES: tuple[str, ...] = tuple(FIGURE_FORMATS)
DEFAULT_FIGURE_FORMAT: str = next(f.name for f in FIGURE_FORMATS.values() if f.default)


def unknown_figure_format(fmt: object) -> str:
    """The message for an unknown figure format."""
    return f"figure format {fmt!r}: allowed {', '.join(FIGURE_FORMAT_NAMES)}"


def figure_format_of(path: str | Path) -> FigureFormat | None:
    """The figure format of a file name (by its suffix), None for another suffix."""
    return FIGURE_FORMATS.get(Path(path).suffix.lstrip(".").lower())
