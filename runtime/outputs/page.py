"""The interactive run page: one self-contained, offline HTML file of a results folder (``rpo view
RUN_FOLDER [--out FILE]``), drawn with plotly, its JavaScript inlined (no network at all).

Left, the 3D approach in the target's LVLH frame (V-bar, cross-track, R-bar: as the ``approach``
figure): the chaser's path, the goal, the target's keep-out sphere (radius chaser_radius +
target_radius), and, animated, both bodies' axes (x red, y green, z blue) and the chaser's camera
cone (body +z from the lens vertex, its half angle).  Right, the main time histories: the errors
the verdict judges (log scale, the threshold dashed and the settling time dash-dotted, from
``metrics.json``), the distance with the keep-out radius, and the camera and collision margins.
A slider (and a play button) moves one time through every panel: the 3D bodies and a cursor in
each time history.  The verdict's line is the page's title.

Everything is read from the folder :func:`read_run_folder` (``run.json``: the parameters and gains;
``metrics.json``: the thresholds, settling times and verdict; the Parquet time histories with their
field descriptions), the geometry from :mod:`rpo.runtime.outputs.geometry` and the errors from the
metrics' own :func:`~rpo.runtime.outputs.metrics.error_signals`, so the page and the figures agree.
"""

from __future__ import annotations

import json
import os
import textwrap
from dataclasses import dataclass, field
from html import escape
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.errors import RpoError
from rpo.runtime.formats import DEFAULT_FORMATS, OUTPUT_FORMATS
from rpo.runtime.outputs import geometry as geo
from rpo.runtime.outputs.plotdata import PlotData, judged_errors

#: animation frames at most (evenly spread over the run, the first and last rows included)
FRAMES = 150
#: the page's file in the run folder when ``--out`` is not given
PAGE_NAME = "view.html"
#: marks a page this module wrote (an existing file is replaced only if it carries it)
GENERATOR = '<meta name="generator" content="rpo view">'
TRIAD_COLORS = ("red", "green", "blue")
#: one line of a time-history panel: (name, values, line style)
Series = tuple[str, np.ndarray, dict[str, Any]]
#: the columns the page reads (field names; a field's columns are ``<name>_<component>``)
FIELDS = ("r", "v", "q_c", "q_t", "meas_q_L", "r_T", "v_T", "ctrl_att_err", "ctrl_q_err", "ctrl_pos_err",
          "ctrl_rate_err", "ctrl_vel_err", "meas_q_e", "meas_w_e", "env_beta_fov", "env_beta_ca")


class ViewError(RpoError):
    """A folder ``rpo view`` cannot show (missing, not a run folder, unreadable), or a page it may not write."""


@dataclass
class RunFolder:
    """What the page needs of a results folder: ``run.json``, ``metrics.json``, the time ``t`` and
    the columns by label, and each field's description (by field name)."""

    path: Path
    run: dict[str, Any]
    metrics: dict[str, Any]
    t: np.ndarray
    columns: dict[str, np.ndarray]
    docs: dict[str, str] = field(default_factory=dict)

    @property
    def params(self) -> dict[str, Any]:
        return (self.run.get("inputs") or {}).get("params") or {}

    @property
    def gains(self) -> dict[str, Any]:
        return (self.run.get("inputs") or {}).get("gains") or {}


def _json(path: Path) -> dict[str, Any]:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ViewError(f"{path}: cannot be read ({getattr(exc, 'strerror', None) or exc})") from None


def read_run_folder(folder: str | Path) -> RunFolder:
    """Read a folder written by ``rpo run`` (a small reader of its own, to be replaced by the
    outputs' ``read_run``); :class:`ViewError` (one line) if it is not one."""
    path = Path(folder)
    if not path.exists():
        raise ViewError(f"run folder {folder}: no such folder")
    if not path.is_dir():
        raise ViewError(f"run folder {folder}: not a folder")
    if not (path / "run.json").is_file():
        raise ViewError(f"{folder} is not a run folder: it has no run.json (`rpo run` writes one)")
    run = _json(path / "run.json")
    metrics = _json(path / "metrics.json") if (path / "metrics.json").is_file() else {}
    ts = OUTPUT_FORMATS[DEFAULT_FORMATS[0]].file
    if not (path / ts).is_file():
        wrote = ", ".join((run.get("output") or {}).get("files") or []) or "none"
        raise ViewError(f"{folder} has no {ts}: rpo view reads the Parquet time histories (this run wrote: {wrote}; "
                        "run it again with its default --format)")
    import pyarrow.parquet as pq

    try:
        schema = pq.read_schema(path / ts)
        wanted = ["t"] + [n for n in schema.names if n in FIELDS or n.rsplit("_", 1)[0] in FIELDS]
        table = pq.read_table(path / ts, columns=wanted)
    except (OSError, ValueError) as exc:
        raise ViewError(f"{path / ts}: cannot be read ({exc})") from None
    if "t" not in table.column_names or table.num_rows == 0:
        raise ViewError(f"{path / ts}: no rows (or no column t)")
    docs: dict[str, str] = {}
    for f in schema:
        meta = f.metadata or {}
        name = meta.get(b"field", b"").decode()
        if name and b"doc" in meta:
            docs[name] = meta[b"doc"].decode()
    cols = {n: table[n].to_numpy() for n in table.column_names}
    return RunFolder(path, run, metrics, cols.pop("t"), cols, docs)


# --------------------------------------------------------------------------- the page


def _plot_data(rf: RunFolder) -> PlotData:
    """The folder as the figures' PlotData (columns, the metrics' thresholds and settling times)."""
    goal = rf.gains.get("r_goal")
    judged = {k: rf.metrics[k] for k in ("thresholds", "att_settling_time_s", "pos_settling_time_s", "sources")
              if k in rf.metrics}
    params = {k: float(np.ravel(v)[0]) for k, v in rf.params.items() if np.size(v) and _numeric(v)}
    return PlotData(t=rf.t, dt=float(rf.run.get("dt") or 0.0), columns=rf.columns, z_layout=[], y_layout=[],
                    params=params, goal=None if goal is None else np.ravel(np.asarray(goal, float)), judged=judged,
                    title=str(rf.run.get("scenario") or rf.path.name))


def _numeric(v: Any) -> bool:
    try:
        np.asarray(v, float)
    except (TypeError, ValueError):
        return False
    return True


def _xyz(v: np.ndarray) -> dict[str, Any]:
    """LVLH points on the scene's axes: x = V-bar, y = cross-track, z = R-bar (R-bar up)."""
    v = np.atleast_2d(v)
    return {"x": v[:, 1], "y": v[:, 2], "z": v[:, 0]}


def _triad(origin: np.ndarray, C: np.ndarray | None, scale: float, axis: int) -> dict[str, Any]:
    if C is None or not np.all(np.isfinite(C)):
        return _xyz(np.full((2, 3), np.nan))
    return _xyz(np.array([origin, origin + scale * C[:, axis]]))


def _cone(r: np.ndarray, C: np.ndarray | None, cam: tuple[float, float] | None, reach: float) -> dict[str, Any]:
    """The camera cone up to the target's range, at most ``reach`` long (it stays in the scene)."""
    if cam is None or C is None or not np.all(np.isfinite(C)) or not np.all(np.isfinite(r)):
        return _xyz(np.full((1, 3), np.nan))
    half, zn = cam
    length = min(1.05 * float(np.linalg.norm(r)), reach / max(1.0, float(np.tan(half))))
    return _xyz(geo.cone_lines(r + zn * C[:, 2], C[:, 2], half, length, n=24, spokes=8))


def page_figure(rf: RunFolder, frames: int = FRAMES) -> Any:
    """The page as a plotly Figure: the 3D scene, the time histories, the frames and the slider."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    d = _plot_data(rf)
    if "r_x" not in rf.columns:
        raise ViewError(f"{rf.path}: the relative position r (r_x, r_y, r_z) was not written: nothing to show")
    r = geo.series(rf.columns, "r")
    assert r is not None
    C_IL, frame_how = geo.lvlh_frame(rf.t, rf.columns, rf.params)
    C_Lc = geo.attitude_in_lvlh(rf.columns, "q_c", C_IL)
    C_Lt = geo.attitude_in_lvlh(rf.columns, "q_t", C_IL)
    goal, goal_how = geo.goal_lvlh(rf.columns, r, rf.docs.get("ctrl_pos_err"), d.goal, C_Lc, C_Lt)
    keep_out, cam = geo.keep_out_radius(rf.params), geo.camera(rf.params)
    judged, _ = judged_errors(d)
    t = rf.t

    # the time-history panels: (y label, [(name, series, line style)], axis type, [(h|v, value, label)])
    rows: list[tuple[str, list[Series], str, list[tuple[str, float, str]]]] = []
    for q in ("att", "pos"):
        if q in judged:
            j = judged[q]
            marks = [] if j.threshold is None else [("h", j.threshold, f"threshold {j.threshold:.4g} {j.unit}")]
            if j.settling is not None:
                marks.append(("v", j.settling, f"reached at {j.settling:.4g} s"))
            rows.append((f"{j.label} [{j.unit}]", [(f"{j.label} ({j.source})", j.signal, {})], "log", marks))
    dist: list[Series] = [("|r|", np.linalg.norm(r, axis=1), {})]
    if goal is not None:
        dist.append(("|goal|", np.linalg.norm(goal, axis=1), {"dash": "dot"}))
    rows.append(("distance [m]", dist, "linear", [] if keep_out is None else
                 [("h", keep_out, f"keep-out radius {keep_out:.3g} m")]))
    margins: list[Series] = [(lbl, rf.columns[c], {}) for c, lbl in (("env_beta_fov", "camera margin beta_FOV [m]"),)
               if c in rf.columns]
    if margins:
        rows.append(("camera margin [m]", margins, "linear", [("h", 0.0, "constraint (> 0 held)")]))

    n_rows = len(rows)
    specs: list[list[dict | None]] = [[{"type": "scene", "rowspan": n_rows}, {"type": "xy"}]]
    specs += [[None, {"type": "xy"}] for _ in range(n_rows - 1)]
    fig = make_subplots(rows=n_rows, cols=2, column_widths=[0.55, 0.45], specs=specs, shared_xaxes=True,
                        vertical_spacing=0.06, horizontal_spacing=0.06)

    # static 3D: path, goal, target, keep-out sphere
    fig.add_trace(go.Scatter3d(**_xyz(r), mode="lines", line={"color": "black", "width": 3}, name="chaser path"),
                  row=1, col=1)
    if goal is not None:
        fig.add_trace(go.Scatter3d(**_xyz(goal), mode="lines", line={"color": "purple", "dash": "dot", "width": 3},
                                   name=f"goal ({goal_how})"), row=1, col=1)
    fig.add_trace(go.Scatter3d(x=[0], y=[0], z=[0], mode="markers", marker={"size": 3, "color": "black"},
                               name="target centre"), row=1, col=1)
    if keep_out is not None:
        sx, sy, sz = geo.sphere_mesh(keep_out, 12)
        s = _xyz(np.stack([sx, sy, sz], axis=-1).reshape(-1, 3))
        fig.add_trace(go.Surface(x=s["x"].reshape(sx.shape), y=s["y"].reshape(sx.shape), z=s["z"].reshape(sx.shape),
                                 opacity=0.35, showscale=False, colorscale=[[0, "red"], [1, "red"]],
                                 name=f"keep-out sphere {keep_out:.3g} m", showlegend=True), row=1, col=1)
    # static time histories
    for k, (ylabel, series, axis_type, marks) in enumerate(rows):
        for name, y, dash in series:
            y = np.where(y > 0, y, np.nan) if axis_type == "log" else y
            fig.add_trace(go.Scattergl(x=t, y=y, mode="lines", name=name, line={"width": 1.5, **dash}),
                          row=k + 1, col=2)
        lo_hi = _range(series, axis_type)
        for kind, value, label in marks:  # traces, not shapes: plotly's add_hline fails beside a 3D scene
            horizontal = kind == "h"
            fig.add_trace(go.Scatter(x=[t[0], t[-1]] if horizontal else [value, value],
                                     y=[value, value] if horizontal else list(lo_hi), mode="lines", name=label,
                                     line={"color": "red" if horizontal else "green", "width": 1,
                                           "dash": "dash" if horizontal else "dashdot"}), row=k + 1, col=2)
        fig.update_yaxes(title_text=ylabel, type=axis_type, row=k + 1, col=2)
    fig.update_xaxes(title_text="time [s]", row=n_rows, col=2)

    # animated: chaser marker, both triads, the camera cone, a cursor per time history
    ok = np.all(np.isfinite(r), axis=1)
    box = np.vstack([r[ok], np.zeros((1, 3))])
    center, extent = 0.5 * (box.min(axis=0) + box.max(axis=0)), float(np.max(np.ptp(box, axis=0))) or 1.0
    triad = 0.08 * extent
    rows_i = geo.sample_indices(len(t), frames)
    ranges = [_range(series, scale_kind) for _, series, scale_kind, _ in rows]

    def moving(i: int) -> list[dict[str, Any]]:
        out = [{"type": "scatter3d", **_xyz(r[i]), "mode": "markers", "marker": {"size": 4, "color": "black"}}]
        out += [{"type": "scatter3d", **_triad(r[i], None if C_Lc is None else C_Lc[i], triad, a)} for a in range(3)]
        out += [{"type": "scatter3d", **_triad(np.zeros(3), None if C_Lt is None else C_Lt[i], triad, a)}
                for a in range(3)]
        out += [{"type": "scatter3d", **_cone(r[i], None if C_Lc is None else C_Lc[i], cam, 0.35 * extent)}]
        out += [{"type": "scatter", "x": [t[i], t[i]], "y": list(lo_hi)} for lo_hi in ranges]
        return out

    first = len(fig.data)
    start = moving(int(rows_i[0]))
    names = ["chaser", *(f"chaser {a}" for a in "xyz"), *(f"target {a}" for a in "xyz"), "camera cone",
             *(f"time cursor {k}" for k in range(len(rows)))]
    for k, (tr, name) in enumerate(zip(start, names, strict=True)):
        kind = tr.pop("type")
        if kind == "scatter3d":
            color = "black" if k == 0 else TRIAD_COLORS[(k - 1) % 3] if k <= 6 else "orange"
            style = {} if k == 0 else {"mode": "lines", "line": {"color": color, "width": 5 if k <= 6 else 2}}
            fig.add_trace(go.Scatter3d(**{**tr, **style}, name=name, showlegend=k in (0, 7)), row=1, col=1)
        else:
            fig.add_trace(go.Scatter(**tr, mode="lines", line={"color": "gray", "width": 1}, name=name,
                                     showlegend=False, hoverinfo="skip"), row=k - 8 + 1, col=2)
    moving_idx = list(range(first, len(fig.data)))
    fig.frames = [go.Frame(name=f"{t[i]:.6g}", data=moving(int(i)), traces=moving_idx) for i in rows_i]
    steps = [{"method": "animate", "label": f"{t[i]:.4g}",
              "args": [[f"{t[i]:.6g}"], {"mode": "immediate", "frame": {"duration": 0, "redraw": True},
                                         "transition": {"duration": 0}}]} for i in rows_i]
    verdict = (rf.metrics.get("verdict") or {}).get("line") or (rf.run.get("verdict") or {}).get("line") or ""
    title = f"{d.title}: {rf.run.get('controller') or ''}, {t[-1]:.6g} s"
    fig.update_layout(
        title={"text": "<br>".join([title, *textwrap.wrap(verdict, 160)]), "font": {"size": 14}},
        height=max(820, 200 * n_rows + 300), template="plotly_white",
        legend={"orientation": "h", "y": -0.2, "yanchor": "top", "font": {"size": 11}},
        margin={"t": 110, "b": 210},
        scene={"xaxis": {"title": {"text": "V-bar y_L [m]"}, "range": _span(center[1], extent)},
               "yaxis": {"title": {"text": "cross-track z_L [m]"}, "range": _span(center[2], extent)},
               "zaxis": {"title": {"text": "R-bar x_L [m]"}, "range": _span(center[0], extent)},
               "aspectmode": "cube", "camera": {"eye": {"x": 1.7, "y": 1.7, "z": 1.1}}},
        # the steps' own labels would crowd the slider: only the current time is shown
        sliders=[{"active": 0, "currentvalue": {"prefix": "t [s] = ", "font": {"color": "black"}},
                  "font": {"color": "rgba(0,0,0,0)"}, "x": 0.12, "len": 0.88, "y": -0.04, "pad": {"t": 10},
                  "steps": steps}],
        updatemenus=[{"type": "buttons", "showactive": False, "x": 0.0, "y": -0.04, "xanchor": "left",
                      "yanchor": "top", "direction": "left",
                      "buttons": [{"label": "play", "method": "animate",
                                   "args": [None, {"frame": {"duration": 60, "redraw": True}, "fromcurrent": True,
                                                   "transition": {"duration": 0}}]},
                                  {"label": "pause", "method": "animate",
                                   "args": [[None], {"mode": "immediate",
                                                     "frame": {"duration": 0, "redraw": False}}]}]}],
        annotations=[*fig.layout.annotations, {"text": f"LVLH attitude: {frame_how}", "showarrow": False,
                                               "xref": "paper", "yref": "paper", "x": 0.0, "y": 1.02,
                                               "font": {"size": 10}}],
    )
    return fig


def _span(center: float, extent: float) -> list[float]:
    return [center - 0.6 * extent, center + 0.6 * extent]


def _range(series: list[Series], scale: str) -> tuple[float, float]:
    """The y span of a time-history panel's cursor (positive on a log axis)."""
    ys = np.concatenate([np.asarray(y, float) for _, y, _ in series])
    ys = ys[np.isfinite(ys) & ((ys > 0) if scale == "log" else True)]
    if not ys.size:
        return (1.0, 10.0) if scale == "log" else (0.0, 1.0)
    return float(ys.min()), float(ys.max())


def page_html(rf: RunFolder, frames: int = FRAMES) -> str:
    """The page as one HTML document, plotly's JavaScript inlined (opens offline)."""
    fig = page_figure(rf, frames)
    html = fig.to_html(full_html=True, include_plotlyjs=True, include_mathjax=False, auto_play=False,
                       config={"displaylogo": False, "responsive": True},
                       post_script="console.log('rpo view: ready, ' + document.getElementById('{plot_id}')"
                                   "._transitionData._frames.length + ' frames');")
    title = escape(f"rpo view: {rf.run.get('scenario') or rf.path.name}")
    return html.replace("<head>", f"<head>\n{GENERATOR}\n<title>{title}</title>", 1)


def write_page(folder: str | Path, out: str | Path | None = None, frames: int = FRAMES) -> Path:
    """Write the page of the run ``folder`` to ``out`` (default ``<folder>/view.html``); returns it.

    An existing file is replaced only if it is a page this command wrote; the new one is written
    beside it and renamed over it, so a reader never sees half of it."""
    rf = read_run_folder(folder)
    target = Path(out) if out is not None else rf.path / PAGE_NAME
    if target.is_dir():
        raise ViewError(f"--out {target}: is a folder (give a file name)")
    if target.exists():
        try:
            with open(target, encoding="utf-8", errors="replace") as f:
                head = f.read(400)
        except OSError as exc:
            raise ViewError(f"--out {target}: cannot be read ({exc.strerror})") from None
        if GENERATOR not in head:
            raise ViewError(f"--out {target}: exists and is not an rpo view page: refusing to overwrite it")
    html = page_html(rf, frames)
    tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(html, encoding="utf-8")
        os.replace(tmp, target)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise ViewError(f"cannot write {target}: {exc.strerror or exc}") from None
    return target
