"""What a simulation returns: the recorded run (:class:`RunResult`) and, when it stopped early, where it
diverged (:class:`Divergence`)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.manifest import LayoutField

#: The run record's entries a DataFrame's ``attrs["run"]`` keeps: small, because pandas copies
#: ``attrs`` into every frame and column derived from it (the whole record is ``run.json``).
RUN_ATTRS = ("scenario", "controller", "seed", "status", "dt", "t_end", "steps_done", "steps_requested",
             "record_every", "backend", "model_source_hash", "rpo_version", "created_utc")


def frame_attrs(labels: Sequence[str], units: Sequence[str], fields: Sequence[str],
                run: Mapping[str, Any]) -> dict[str, Any]:
    """The ``DataFrame.attrs`` of a run's table (JSON-ready), the same for :meth:`RunResult.to_pandas`
    and the Parquet file (``pandas.read_parquet`` restores them): ``units`` (column -> unit),
    ``fields`` (layout field -> its columns, in order: ``"r": ["r_x", "r_y", "r_z"]``) and ``run``
    (the entries :data:`RUN_ATTRS` of the run record ``run``, with a ``units`` object for its times,
    the JSON rule of :mod:`rpo.runtime.outputs.jsonunits`)."""
    by_field: dict[str, list[str]] = {}
    for label, name in zip(labels, fields, strict=True):
        by_field.setdefault(name or label, []).append(label)
    rec = {k: run[k] for k in RUN_ATTRS if run.get(k) is not None}
    rec["units"] = {k: "s" for k in ("dt", "t_end") if k in rec}
    return {"units": dict(zip(labels, units, strict=True)), "fields": by_field, "run": rec}


@dataclass
class Divergence:
    """Where a run stopped: the step, its end time [s], the offending entry and both states.

    ``where`` is ``"state"`` (an entry of the next state, non-finite or above its bound),
    ``"output"`` (an entry of the step's outputs y, non-finite; ``label`` is its y label) or
    ``"step"`` (the step function reported an error).  ``output`` is the failing step's y.
    """

    step: int
    time: float
    label: str
    value: float
    bound: float
    state: np.ndarray
    last_good_state: np.ndarray
    where: str = "state"
    output: np.ndarray | None = None

    def message(self) -> str:
        what = "non-finite" if not np.isfinite(self.value) else f"|{self.value:.6g}| > {self.bound:.6g}"
        entry = f"output {self.label}" if self.where == "output" else self.label
        return (f"simulation diverged in step {self.step} (ending at t = {self.time:.6g} s): {entry} is "
                f"{what}; the results up to the step's start were kept")


@dataclass
class RunResult:
    """Time histories of one run.  ``z[i]`` is the state at ``t[i]`` [s]; ``y[i]`` the outputs over
    the step starting at ``t[i]``.  The final row of a completed run holds the outputs at the final
    state (one more evaluation of the step, its next state discarded), so no row is NaN.

    Named access: ``res["r"]`` is the (N, 3) array of the layout field ``r`` (state or outputs),
    ``res["r_x"]`` one column, ``res["t"]`` the time; ``res.unit("r")`` its unit (``"m"``);
    ``res.fields`` the field names; ``res.to_pandas()`` a DataFrame (needs pandas) with the units in
    ``df.attrs["units"]``.  :func:`rpo.runtime.outputs.reading.read_run` reads one back from a results folder.
    """

    t: np.ndarray
    z: np.ndarray
    y: np.ndarray
    z_labels: list[str]
    z_units: list[str]
    y_labels: list[str]
    y_units: list[str]
    steps_done: int
    steps_requested: int
    dt: float
    wall_time: float
    divergence: Divergence | None = None
    meta: dict = field(default_factory=dict)
    #: layout field name -> its column labels, state fields first (the model's layouts)
    field_labels: Mapping[str, Sequence[str]] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.divergence is None

    @property
    def fields(self) -> list[str]:
        """The layout field names, state first, then outputs (``q_c``, ``r``, ..., ``cmd_F``, ...)."""
        return list(self.field_labels)

    def column(self, label: str) -> np.ndarray:
        """One column by label, from the state z or the outputs y."""
        if label in self.z_labels:
            return self.z[:, self.z_labels.index(label)]
        if label in self.y_labels:
            return self.y[:, self.y_labels.index(label)]
        raise KeyError(label)

    def block(self, name: str, layout: Iterable[LayoutField]) -> np.ndarray:
        """All columns of a layout field, e.g. ``block('r', model.layouts['z_baseline'])``."""
        labels = next((f.labels for f in layout if f.name == name), None)
        if labels is None:
            raise KeyError(name)
        return np.column_stack([self.column(lbl) for lbl in labels])

    def __getitem__(self, name: str) -> np.ndarray:
        """``"t"`` [s]; a layout field (2-D, one column per component, also for a 1-value field);
        else a column label (1-D).  A view where possible: copy before editing."""
        if name == "t":
            return self.t
        if name in self.field_labels:
            return np.column_stack([self.column(lbl) for lbl in self.field_labels[name]])
        try:
            return self.column(name)
        except KeyError:
            raise KeyError(f"{name!r} is neither a field nor a column of this run; fields: "
                           f"{', '.join(self.fields)}") from None

    def __contains__(self, name: object) -> bool:
        return name == "t" or name in self.field_labels or name in self.z_labels or name in self.y_labels

    def unit(self, name: str) -> str:
        """The unit of a field or column label (``"s"`` for ``"t"``; ``"-"`` when dimensionless)."""
        if name == "t":
            return "s"
        if name in self.field_labels:
            name = self.field_labels[name][0]
        if name in self.z_labels:
            return self.z_units[self.z_labels.index(name)]
        if name in self.y_labels:
            return self.y_units[self.y_labels.index(name)]
        raise KeyError(f"{name!r} is neither a field nor a column of this run")

    def frame_attrs(self) -> dict[str, Any]:
        """What :meth:`to_pandas` puts in ``df.attrs``: :func:`frame_attrs` of every column."""
        field_of = {lbl: name for name, labels in self.field_labels.items() for lbl in labels}
        labels = ["t", *self.z_labels, *self.y_labels]
        status = "diverged" if self.divergence is not None else "interrupted" if self.meta.get("interrupted") else "ok"
        run = {"status": status, "dt": float(self.dt), "t_end": float(self.t[-1]) if len(self.t) else 0.0,
               "steps_done": int(self.steps_done), "steps_requested": int(self.steps_requested), **self.meta}
        return frame_attrs(labels, ["s", *self.z_units, *self.y_units], [field_of.get(lbl, lbl) for lbl in labels],
                           run)

    def to_pandas(self) -> Any:
        """A ``pandas.DataFrame``: column ``t`` [s], then every state and output column by label, float64.

        ``df.attrs`` (:func:`frame_attrs`): ``units`` (column -> unit: ``df.attrs["units"]["r_x"]``
        is ``"m"``), ``fields`` (layout field -> its columns) and ``run`` (the run's controller, seed,
        status, step [s]...).  pandas has no per-column metadata: a column taken from the frame
        (``df["r_x"]``) carries the frame's ``attrs``.  The same ``attrs`` as ``pd.read_parquet`` of
        the run's ``timeseries.parquet``.  pandas is imported here (optional: ``pip install pandas``)."""
        try:
            import pandas as pd
        except ImportError:
            raise ModelError("RunResult.to_pandas needs pandas (optional, not installed with rpo): "
                             "pip install pandas") from None
        data = {"t": self.t, **{lbl: self.z[:, i] for i, lbl in enumerate(self.z_labels)},
                **{lbl: self.y[:, i] for i, lbl in enumerate(self.y_labels)}}
        df = pd.DataFrame(data)
        df.attrs.update(self.frame_attrs())
        return df
