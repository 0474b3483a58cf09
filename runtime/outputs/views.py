"""The standard rendezvous views of one run (matplotlib, Agg): the errors on a logarithmic scale,
the LVLH projections and the 3D approach.  Built as Figures from a
:class:`~rpo.runtime.outputs.plotdata.PlotData` (and, for the geometric views, the pose
:func:`rpo.runtime.outputs.plots.pose` derives with :mod:`rpo.runtime.outputs.geometry`);
:mod:`rpo.runtime.outputs.plots` registers and saves them.

* ``errors``    every error the metrics compute (attitude, position, rate, velocity), the metrics'
  own series on a log scale; the judged ones with the verdict's threshold and settling time; the
  verdict's line in the title;
* ``lvlh``      the trajectory of the chaser relative to the target in the target's LVLH frame:
  in-plane (V-bar = along-track horizontal, R-bar = radial vertical), cross-track against
  along-track, cross-track against radial; the target's keep-out circle (radius chaser_radius +
  target_radius: 001's collision constraint), start, end, the goal and a dot every tenth of the run;
* ``approach``  the same trajectory in 3D (V-bar, cross-track, R-bar), whole and near the target,
  with the keep-out sphere, the camera cone (chaser body +z from the lens vertex, its half angle)
  and both bodies' axes (x red, y green, z blue) at the start, at the settling time and at the end.
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from rpo.runtime.outputs import geometry as geo
from rpo.runtime.outputs.figkit import figure, finish, judged_panel
from rpo.runtime.outputs.plotdata import PlotData, judged_errors

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: body axes colours (x, y, z)
TRIAD_COLORS = ("tab:red", "tab:green", "tab:blue")
#: LVLH components on the views' axes: (index in r, label)
RBAR, VBAR, HBAR = (0, "R-bar: radial x_L [m]"), (1, "V-bar: along-track y_L [m]"), (2, "cross-track z_L [m]")
#: the three projections of :func:`lvlh_figure`: (horizontal, vertical, title)
PROJECTIONS = ((VBAR, RBAR, "in-plane (V-bar / R-bar)"), (VBAR, HBAR, "cross-track against along-track"),
               (HBAR, RBAR, "cross-track against radial (seen along V-bar)"))
TIME_DOTS = 10
#: the colours of the camera cones at :func:`_instants`
INSTANT_COLORS = {"start": "tab:green", "attitude reached": "tab:orange", "end": "tab:red"}


def errors_figure(d: PlotData) -> Figure | None:
    judged, _ = judged_errors(d)
    order = [q for q in ("att", "pos", "rate", "vel") if q in judged]
    if not order:
        return None
    verdict = textwrap.wrap(d.judged.get("verdict", ""), 100)
    fig, axes = figure(len(order), height=1.9, titled=True, title_lines=len(verdict))
    for ax, q in zip(axes, order, strict=True):
        judged_panel(ax, d.t, judged[q], log=True)
    title = "errors on a log scale (the metrics' series; the verdict's thresholds dashed, reached dash-dotted)"
    return finish(fig, axes, d, "\n".join([title, *verdict]))


def _ends(ax: Axes, h: np.ndarray, v: np.ndarray, t: np.ndarray, legend: bool) -> None:
    """Start, end and a dot every tenth of the run along the path (h, v)."""
    ok = np.flatnonzero(np.isfinite(h) & np.isfinite(v))
    if not ok.size:
        return
    idx = ok[geo.sample_indices(ok.size, TIME_DOTS + 1)]
    step = (t[ok[-1]] - t[ok[0]]) / TIME_DOTS
    ax.plot(h[idx], v[idx], ".", color="0.3", ms=4, label=f"every {step:.4g} s" if legend else None)
    ax.plot(h[ok[0]], v[ok[0]], "o", color="tab:green", ms=6, label="start" if legend else None)
    ax.plot(h[ok[-1]], v[ok[-1]], "s", color="tab:red", ms=6, label="end" if legend else None)


def lvlh_figure(d: PlotData, pose: dict[str, Any]) -> Figure:
    """The LVLH projections (see the module docstring)."""
    r, goal = pose["r"], pose["goal"]
    keep_out = geo.keep_out_radius(d.params)
    fig = Figure(figsize=(15.0, 5.6))
    axes = fig.subplots(1, 3)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.24, top=0.83, wspace=0.3)
    for k, (ax, (h, v, what)) in enumerate(zip(axes, PROJECTIONS, strict=True)):
        first = k == 0
        ax.plot(r[:, h[0]], r[:, v[0]], color="k", lw=1.2, label="chaser (relative to the target)" if first else None)
        _ends(ax, r[:, h[0]], r[:, v[0]], d.t, first)
        if goal is not None:
            ax.plot(goal[:, h[0]], goal[:, v[0]], color="tab:purple", ls=":", lw=1.2, label="goal" if first else None)
            ax.plot(goal[-1, h[0]], goal[-1, v[0]], "*", color="tab:purple", ms=10)
        ax.plot(0, 0, "+", color="k", ms=10, mew=1.5, label="target" if first else None)
        if keep_out is not None:
            ax.add_patch(Circle((0, 0), keep_out, facecolor="red", alpha=0.25, edgecolor="red", ls="--",
                                label=f"keep-out radius {keep_out:.3g} m" if first else None))
        ax.set_xlabel(h[1], fontsize=9)
        ax.set_ylabel(v[1], fontsize=9)
        ax.set_title(what, fontsize=10)
        ax.set_aspect("equal", adjustable="datalim")
        ax.tick_params(labelsize=8)
        ax.grid(True, alpha=0.3)
    fig.legend(loc="lower center", ncol=7, fontsize=8, frameon=False)
    return finish(fig, list(axes), d, "trajectory in the target's LVLH frame", time_axes=False)


def _p(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """LVLH components on the 3D axes: (V-bar, cross-track, R-bar), R-bar up."""
    x = np.asarray(x)
    return x[..., 1], x[..., 2], x[..., 0]


def _instants(d: PlotData, r: np.ndarray) -> list[tuple[int, str]]:
    """(row, what) at which the bodies are drawn: the start, the attitude settling time, the end."""
    ok = np.flatnonzero(np.all(np.isfinite(r), axis=1))
    if not ok.size:
        return []
    out = [(int(ok[0]), "start")]
    t_set = d.judged.get("att_settling_time_s")
    if t_set is not None and d.t[ok[0]] < t_set < d.t[ok[-1]]:
        out.append((int(np.searchsorted(d.t, t_set)), "attitude reached"))
    out.append((int(ok[-1]), "end"))
    return out


def _inside(x: np.ndarray, center: np.ndarray, half: float) -> np.ndarray:
    """Rows of ``x`` (LVLH) outside the cube around ``center`` set to NaN (mplot3d does not clip)."""
    x = np.array(x, float)
    x[np.any(np.abs(x - center) > half * 1.0001, axis=-1)] = np.nan
    return x


def _bodies(ax: Any, d: PlotData, pose: dict[str, Any], box: tuple[np.ndarray, float], legend: bool) -> None:
    """Camera cones and body axes at :func:`_instants` inside the cube ``box`` (centre, half side),
    the target's axes at the end."""
    r, C_Lc, C_Lt = pose["r"], pose["C_Lc"], pose["C_Lt"]
    center, half = box
    scale = 0.12 * half
    cam = geo.camera(d.params)
    instants = _instants(d, r)
    for i, what in instants:
        if C_Lc is None or not np.all(np.isfinite(C_Lc[i])) or np.any(np.abs(r[i] - center) > half):
            continue
        for a in range(3):
            ax.plot(*_p(np.array([r[i], r[i] + scale * C_Lc[i][:, a]])), color=TRIAD_COLORS[a], lw=1.5)
        if cam is not None:
            half_angle, zn = cam
            apex = r[i] + zn * C_Lc[i][:, 2]
            # the cone drawn up to the target's range, shortened until it fits in the box
            length = 1.05 * float(np.linalg.norm(r[i]))
            for _ in range(8):
                cone = geo.cone_lines(apex, C_Lc[i][:, 2], half_angle, length, n=20, spokes=6)
                if np.all(np.abs(cone[np.isfinite(cone[:, 0])] - center) <= half):
                    break
                length *= 0.6
            ax.plot(*_p(_inside(cone, center, half)), color=INSTANT_COLORS[what], lw=0.8, alpha=0.8,
                    label=f"camera cone at {d.t[i]:.4g} s ({what})" if legend else None)
    if C_Lt is not None and instants:
        end = instants[-1][0]
        if np.all(np.isfinite(C_Lt[end])):
            for a in range(3):
                ax.plot(*_p(np.array([np.zeros(3), scale * C_Lt[end][:, a]])), color=TRIAD_COLORS[a], lw=1.5,
                        label=("body axes x, y, z" if a == 0 else None) if legend else None)


def _box(ax: Any, center: np.ndarray, half: float) -> None:
    c = _p(center)
    ax.set_xlim(c[0] - half, c[0] + half)
    ax.set_ylim(c[1] - half, c[1] + half)
    ax.set_zlim(c[2] - half, c[2] + half)
    ax.set_box_aspect((1, 1, 1))


def approach_figure(d: PlotData, pose: dict[str, Any]) -> Figure:
    """The 3D approach, whole and near the target (see the module docstring)."""
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401 - registers the 3d projection

    r, goal = pose["r"], pose["goal"]
    ok = np.all(np.isfinite(r), axis=1)
    keep_out = geo.keep_out_radius(d.params)
    fig = Figure(figsize=(14.0, 7.2))
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.12, top=0.88, wspace=0.0)
    rr = r[ok]
    lo, hi = np.minimum(rr.min(axis=0), 0.0), np.maximum(rr.max(axis=0), 0.0)
    whole = (0.5 * (lo + hi), 0.55 * float(np.max(hi - lo)) or 1.0)
    near_r = max(1.3 * float(np.linalg.norm(rr[-1])), 4.0 * (keep_out or 1.0))
    near = (0.5 * rr[-1], 0.6 * near_r)
    for k, (center, half, what) in enumerate(((*whole, "the whole approach"),
                                              (*near, "near the target: the final pose"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        first = k == 0
        ax.plot(*_p(_inside(rr, center, half)), color="k", lw=1.2, label="chaser" if first else None)
        for row, style in ((rr[:1], {"color": "tab:green", "label": "start"}),
                           (rr[-1:], {"color": "tab:red", "marker": "s", "label": "end"})):
            if np.all(np.abs(row - center) <= half):
                ax.scatter(*_p(row), s=20, **{**style, "label": style["label"] if first else None})
        if goal is not None:
            ax.plot(*_p(_inside(goal[ok], center, half)), color="tab:purple", ls=":", lw=1.2,
                    label="goal" if first else None)
        if keep_out is not None:
            ax.plot_wireframe(*_p(np.stack(geo.sphere_mesh(keep_out, 8), axis=-1)), color="red", lw=0.5, alpha=0.6,
                              label=f"keep-out sphere, radius {keep_out:.3g} m" if first else None)
        _bodies(ax, d, pose, (center, half), first)
        ax.set_xlabel("V-bar y_L [m]", fontsize=8)
        ax.set_ylabel("cross-track z_L [m]", fontsize=8)
        ax.set_zlabel("R-bar x_L [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.set_title(what, fontsize=10)
        _box(ax, center, half)
    fig.legend(loc="lower center", ncol=5, fontsize=8, frameon=False)
    cam = geo.camera(d.params)
    extra = f"; camera on body +z, half angle {np.degrees(cam[0]):.3g} deg" if cam else ""
    return finish(fig, [], d, f"approach in the target's LVLH frame{extra}", time_axes=False)
