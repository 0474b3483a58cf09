"""A results folder read back: :func:`read_run` gives the :class:`~rpo.runtime.run.result.RunResult` of
the rows and columns ``rpo run`` wrote, with the same named access (``res["r"]`` an (N, 3) array,
``res.unit("r")``, ``res.fields``) and ``to_pandas()`` (units in ``df.attrs["units"]``).

```python
from rpo.runtime.outputs.reading import read_run
res = read_run("runs/001_scenario-20260101-120000")
res["r"], res.unit("r")          # (N, 3) [m]
res.meta["verdict"]["line"]      # run.json; res.meta["metrics"] is metrics.json
df = res.to_pandas()             # df.attrs["units"]["r_x"] == "m", df.attrs["run"]["controller"]
```

The time histories are read from ``timeseries.parquet`` (else ``.mat``, else ``.npz``: the first
the folder has; each format's reader is declared with it in :mod:`rpo.runtime.formats`), with
the units, layouts and fields the file carries; ``run.json`` becomes
``res.meta`` (and ``res.divergence`` when the run diverged), ``metrics.json`` ``res.meta["metrics"]``.
The rows are those written (``[output] every``), the columns those chosen (``[output] channels``).
pyarrow and NumPy only (SciPy for a ``.mat`` file); pandas only in ``to_pandas()``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.errors import OutputError
from rpo.runtime.formats import OUTPUT_FORMATS, Column, Table
from rpo.runtime.run.result import Divergence, RunResult


def read_table(folder: str | Path) -> Table:
    """The time histories of a results folder as the writer's :class:`~rpo.runtime.formats.Table`,
    from the first file of :data:`~rpo.runtime.formats.OUTPUT_FORMATS` (in their order) that the
    folder has and that keeps the units and layouts (a format with a ``read``)."""
    path = Path(folder)
    fmt = next((f for f in OUTPUT_FORMATS.values() if f.read is not None and (path / f.file).is_file()), None)
    if fmt is None or fmt.read is None:
        have = ", ".join(sorted(p.name for p in path.glob("timeseries.*"))) or "none"
        readable = ", ".join(f.file for f in OUTPUT_FORMATS.values() if f.read is not None)
        raise OutputError(f"{path}: no time histories read_run can read ({readable}; the folder has {have})")
    table = fmt.read(path / fmt.file)
    if not table.columns or table.columns[0].label != "t":
        raise OutputError(f"{path / fmt.file}: its first column is not t")
    return table


def _number(v: Any) -> float:
    """A JSON number, or a non-finite one written as text (``"nan"``, ``"inf"``)."""
    return float(v)


def _divergence(d: dict | None) -> Divergence | None:
    if not d:
        return None
    state, last = d.get("state") or {}, d.get("last_good_state") or {}
    output = d.get("output")
    return Divergence(step=int(d["step"]), time=_number(d["time"]), label=str(d["label"]), value=_number(d["value"]),
                      bound=_number(d["bound"]), state=np.array([_number(v) for v in state.values()]),
                      last_good_state=np.array([_number(v) for v in last.values()]), where=d.get("where", "state"),
                      output=None if output is None else np.array([_number(v) for v in output.values()]))


def read_run(folder: str | Path) -> RunResult:
    """The run written to ``folder`` by ``rpo run`` (or :func:`rpo.runtime.outputs.writers.write_run`).

    ``res.t``, ``res.z``, ``res.y`` and their labels and units are the written table (the state
    columns, then the outputs; ``res.fields`` their layout fields); ``res.meta`` is ``run.json``
    with ``metrics.json`` under ``"metrics"``; ``res.divergence`` is rebuilt from ``run.json`` (its
    ``state`` over every state label of the model, not only the written ones).  Raises
    :class:`~rpo.runtime.errors.OutputError` (one line) when the folder has no ``run.json`` or no
    time-history file it can read."""
    path = Path(folder)
    record_path = path / "run.json"
    if not record_path.is_file():
        raise OutputError(f"{path}: no run.json: not a results folder of rpo run")
    record = json.loads(record_path.read_text(encoding="utf-8"))
    table = read_table(path)
    t = table.columns[0].data
    z, y = table.columns[1:1 + table.z_count], table.columns[1 + table.z_count:]

    def block(cs: Sequence[Column]) -> np.ndarray:
        return np.column_stack([c.data for c in cs]) if cs else np.empty((t.size, 0))

    fields: dict[str, list[str]] = {}
    for c in (*z, *y):
        fields.setdefault(c.field or c.label, []).append(c.label)
    meta = dict(record)
    metrics_path = path / "metrics.json"
    if metrics_path.is_file():
        meta["metrics"] = json.loads(metrics_path.read_text(encoding="utf-8"))
    return RunResult(
        t=t, z=block(z), y=block(y), z_labels=[c.label for c in z], z_units=[c.unit for c in z],
        y_labels=[c.label for c in y], y_units=[c.unit for c in y],
        steps_done=int(record.get("steps_done", max(t.size - 1, 0))),
        steps_requested=int(record.get("steps_requested", max(t.size - 1, 0))),
        dt=float(record.get("dt", t[1] - t[0] if t.size > 1 else 0.0)), wall_time=float(record.get("wall_time", 0.0)),
        divergence=_divergence(record.get("divergence")), meta=meta, field_labels=fields)
