"""Write the results of one run into a fresh folder, atomically, never overwriting anything.

``out_dir`` must not exist or be an empty folder.  Everything is written into a hidden
temporary sibling (``.<name>.<random>.tmp``) and renamed into place at the end, so a folder
with the final name is always complete; on any error the temporary folder is removed.

Contents:

* ``timeseries.npz``  ``t`` [s], ``z`` (state), ``y`` (outputs), ``z_labels``, ``z_units``,
  ``y_labels``, ``y_units`` and ``metadata`` (the JSON of ``run.json``, as a string);
* ``timeseries.csv``  the same table, header ``name [unit]``: ``t [s]``, the z columns, then the
  y columns.  ``y`` at row i is the output over the step starting at ``t[i]``: the last row has
  none (``nan``);
* ``scenario.toml``   the scenario as read (when given);
* ``metrics.json``    the metrics of :mod:`rpo.runtime.metrics` (when given);
* ``run.json``        status (``ok``/``diverged`` with the divergence message, step, time and
  state label), steps, wall time, backend, seed, controller, model source hash, versions;
* the figures of :mod:`rpo.runtime.plots` (unless ``plots=False``).

A diverged run is written the same way, with the data up to its last good step.
"""

from __future__ import annotations

import json
import os
import platform
import secrets
import shutil
import warnings
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import OutputError

if TYPE_CHECKING:
    from .compiled import Model
    from .simulate import RunResult

CSV_FORMAT = "%.17g"  # round-trips every double: the CSV equals the NPZ


def rpo_version() -> str:
    try:
        return metadata.version("rpo")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a bare checkout
        return "unknown"


def check_out_dir(out_dir: str | Path) -> Path:
    """Raise :class:`OutputError` unless ``out_dir`` is absent or an empty folder; returns it as a Path."""
    out = Path(out_dir)
    if out.exists() or out.is_symlink():
        if not out.is_dir():
            raise OutputError(f"output folder {out} exists and is not a folder: refusing to overwrite it")
        if any(out.iterdir()):
            raise OutputError(f"output folder {out} exists and is not empty: refusing to overwrite it "
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


def run_record(result: RunResult, model: Model, scenario_path: str | Path | None = None,
               extra_meta: dict | None = None) -> dict[str, Any]:
    """The content of ``run.json`` (also stored in the npz as ``metadata``)."""
    div = result.divergence
    rec = {
        "status": "ok" if div is None else "diverged",
        "divergence": None if div is None else {
            "message": div.message(), "step": int(div.step), "time": float(div.time), "label": div.label,
            "value": float(div.value), "bound": float(div.bound),
            # both states by label: the one that failed the check and the last good one
            "state": dict(zip(result.z_labels, div.state.tolist(), strict=True)),
            "last_good_state": dict(zip(result.z_labels, div.last_good_state.tolist(), strict=True)),
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
        "model_source_hash": model.manifest.get("source_hash"),
        "codegen_tools": model.manifest.get("tools"),
        "rpo_version": rpo_version(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scenario_path": None if scenario_path is None else str(scenario_path),
        "created_utc": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }
    rec.update(extra_meta or {})
    return _jsonable(rec)


def _header(result) -> list[str]:
    return (["t [s]"] + [f"{n} [{u}]" for n, u in zip(result.z_labels, result.z_units, strict=True)]
            + [f"{n} [{u}]" for n, u in zip(result.y_labels, result.y_units, strict=True)])


def write_run(result: RunResult, out_dir: str | Path, model: Model, scenario_path: str | Path | None = None,
              scenario_text: str | None = None, extra_meta: dict | None = None, *, plots: bool = True,
              params: dict | None = None, gains: dict | None = None, title: str = "",
              metrics: dict | None = None) -> Path:
    """Write ``result`` (a :class:`~rpo.runtime.simulate.RunResult`) into the new folder ``out_dir``.

    ``scenario_text`` (else the file ``scenario_path``) is copied as ``scenario.toml``;
    ``extra_meta`` is merged into ``run.json``; ``params``/``gains`` give the plots their limits
    and goal; ``metrics`` is written as ``metrics.json``.  Raises :class:`OutputError` if ``out_dir``
    exists and is not empty (nothing is touched then) or cannot be written.  Returns the folder.
    """
    out = check_out_dir(out_dir)
    parent = out.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        # os.mkdir (not mkdtemp, which makes it 0700): the results get the user's usual permissions
        tmp = parent / f".{out.name}.{secrets.token_hex(6)}.tmp"
        os.mkdir(tmp)
    except OSError as exc:
        raise OutputError(f"cannot create the output folder {out}: {exc.strerror or exc}") from None
    try:
        if scenario_text is None and scenario_path is not None:
            scenario_text = Path(scenario_path).read_text(encoding="utf-8")
        if scenario_text is not None:
            (tmp / "scenario.toml").write_text(scenario_text, encoding="utf-8")

        figures, plot_error = [], None
        if plots:
            from .plots import make_plots  # matplotlib only when figures are wanted
            try:
                figures = make_plots(result, model, tmp, params=params, gains=gains, title=title)
            except Exception as exc:  # the data must survive a plotting bug
                plot_error = f"{type(exc).__name__}: {exc}"
                warnings.warn(f"plots were not written: {plot_error}", RuntimeWarning, stacklevel=2)

        meta = run_record(result, model, scenario_path, extra_meta)
        meta["figures"] = figures
        if plot_error:
            meta["plot_error"] = plot_error
        meta_json = json.dumps(meta, indent=2, sort_keys=False, allow_nan=False)

        np.savez_compressed(
            tmp / "timeseries.npz", t=result.t, z=result.z, y=result.y,
            z_labels=np.array(result.z_labels), z_units=np.array(result.z_units),
            y_labels=np.array(result.y_labels), y_units=np.array(result.y_units),
            metadata=np.array(meta_json),
        )
        table = np.column_stack([result.t, result.z, result.y])
        np.savetxt(tmp / "timeseries.csv", table, fmt=CSV_FORMAT, delimiter=",",
                   header=",".join(_header(result)), comments="")
        (tmp / "run.json").write_text(meta_json + "\n", encoding="utf-8")
        if metrics is not None:
            (tmp / "metrics.json").write_text(json.dumps(_jsonable(metrics), indent=2, allow_nan=False) + "\n",
                                              encoding="utf-8")
        try:
            # rename(2) replaces an empty folder atomically and fails on a non-empty one: an
            # existing result is never overwritten, even if it appeared while we were writing.
            os.rename(tmp, out)
        except OSError as exc:
            raise OutputError(f"cannot move the results into {out}: {exc.strerror or exc} "
                              f"(is it non-empty now?)") from None
    except OSError as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        raise OutputError(f"cannot write the results into {out}: {exc}") from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out
