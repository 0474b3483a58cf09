"""Figures of one run (matplotlib, Agg; no pyplot, so no global backend state is touched).

The figures are drawn from a :class:`~rpo.runtime.outputs.plotdata.PlotData` (the time, the columns the
figures use at the rate of the in-memory record, the layouts and a few run facts: the parameters
of :data:`~rpo.runtime.outputs.plotdata.PLOT_PARAMS`, the metrics' thresholds and settling times),
so they can be rendered in another process (:mod:`rpo.runtime.outputs.writers` does, while it writes
the data files).  Each figure is built as a :class:`~matplotlib.figure.Figure` by a function of
:data:`FIGURES` (``build(name, data)``; None: nothing to draw), then saved by :func:`render`.

Every error the verdict judges is the metrics' own series
(:func:`rpo.runtime.outputs.plotdata.judged_errors`), drawn with its threshold and its settling time
(the verdict's "reached at").  Figures (``<name>.<format>``):

* ``attitude``     the attitude error the verdict judges [deg] (threshold, settling time), its
  error quaternion and the rate error [deg/s] (the same sources as the metrics: the controller's
  ``ctrl_*`` errors, else 000's interface-frame errors);
* ``translation``  relative position r in LVLH [m] with the goal (dotted, when known), the
  distance |r| with the goal distance and the keep-out radius, the position error the verdict
  judges (threshold, settling time), the relative velocity v [m/s];
* ``errors``       every error on a logarithmic scale (:mod:`rpo.runtime.outputs.views`);
* ``lvlh``         the LVLH projections: in-plane (V-bar/R-bar), cross-track (views);
* ``approach``     the 3D approach with the keep-out sphere and the camera cone (views);
* ``actuators``    the actuators the plant has: ideal force and torque with their limits, or the
  wheel speeds [rpm], torques [N m] and momenta [N m s] against their limits and capacity, and the
  torque and force applied to the chaser (body axes);
* ``thrusters``    firing raster (fraction of time each of the 16 thrusters is on, per time bin),
  the commanded duty (PWPF input) the same way, and the propellant used [kg]; not written for a
  plant with ideal actuators (it has no thrusters);
* ``controller``   the controller's standard errors (attitude, error quaternion, position,
  rate, velocity: those it logs; the judged ones with threshold and settling time) and commands;
* ``constraints``  001's field-of-view and collision margins (> 0 = satisfied);
* ``diagnostics``  every controller-specific diagnostic ``ctrl_*`` (sliding surfaces, adaptive or
  ESO estimates...), one panel each, titled by its manifest description.

A figure whose columns are all absent is not written.  A diverged run is plotted up to its last
good step and marked with a red line.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure

from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, FIGURE_FORMATS, unknown_figure_format
from rpo.runtime.outputs import geometry as geo
from rpo.runtime.outputs import views
from rpo.runtime.outputs.figkit import (
    AXES_COLORS,
    MARGIN,
    RAD2DEG,
    RADS2RPM,
    SETTLED_STYLE,
    THRESHOLD_STYLE,
    components,
    envelope,
    figure,
    finish,
    judged_panel,
    legend,
    limits,
    lines,
    norm,
    save,
)
from rpo.runtime.outputs.plotdata import STANDARD_DIAG, PlotData, judged_errors

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from rpo.runtime.model.manifest import LayoutField
    from rpo.runtime.run.result import RunResult

#: Time bins of the thruster rasters (a 10 ms pulse in a 300 s run stays visible as a grey level).
RASTER_BINS = 600
XYZ = ("x", "y", "z")
LVLH_AXES = ("x (radial, R-bar)", "y (along-track, V-bar)", "z (normal, cross-track)")


# --------------------------------------------------------------------------- the figures

Panel = tuple[str, str, float]  # (field, axis label with unit, scale)


def _field_panels(d: PlotData, title: str, panels: Sequence[Panel], ncols: int = 1,
                  limit: dict[str, tuple[float | None, str]] | None = None,
                  decorate: dict[str, Callable[[Axes], None]] | None = None) -> Figure | None:
    """One panel per logged field; None (nothing to draw) if none.  Absent ones are named.
    ``limit``: a field's +- limit (dotted) and its label; ``decorate``: more drawing on a field's panel."""
    present = [p for p in panels if d.has(p[0])]
    if not present:
        return None
    absent = [p[1].split(" [")[0] for p in panels if not d.has(p[0])]
    if absent:
        title = f"{title}\n(not logged by this controller: {', '.join(absent)})"
    fig, axes = figure(len(present), ncols=ncols, titled=bool(absent))
    for ax, (name, ylabel, scale) in zip(axes, present, strict=True):
        f = d.field(name)
        assert f is not None
        lines(ax, d.t, d.get(name) * scale, components(f), ylabel)
        if limit and name in limit:
            limits(ax, *limit[name])
            legend(ax)
        if name in ("env_beta_fov", "env_beta_ca"):
            ax.axhline(0.0, color="red", ls=":", lw=1.0)
        if decorate and name in decorate:
            decorate[name](ax)
    return finish(fig, axes, d, title)


def _source_of_q(d: PlotData) -> str:
    return "ctrl_q_err" if d.has("ctrl_q_err") else "meas_q_e, 000 interface frame"


def plot_attitude(d: PlotData) -> Figure | None:
    judged, comp = judged_errors(d)
    if "att" not in judged:
        return None
    rows = ["att"] + (["q"] if "q" in comp else []) + (["rate"] if "rate" in comp else [])
    fig, axes = figure(len(rows), titled=True)
    for ax, row in zip(axes, rows, strict=True):
        if row == "att":
            judged_panel(ax, d.t, judged["att"])
        elif row == "q":
            lines(ax, d.t, comp["q"], ["x", "y", "z", "w (scalar)"], f"error quaternion [-]\n({_source_of_q(d)})")
        else:
            lines(ax, d.t, comp["rate"], XYZ, f"rate error [deg/s]\n({judged['rate'].source})")
            norm(ax, d.t, comp["rate"], "|rate error|")
            legend(ax)
    return finish(fig, axes, d, "attitude error as the verdict judges it (log scale; threshold dashed, "
                                "reached dash-dotted)")


def pose(d: PlotData) -> dict[str, Any]:
    """``r``, both attitudes in LVLH (``C_Lc``, ``C_Lt``: body axes as columns) and the goal in LVLH
    (None where unknown), with how the LVLH frame and the goal were found."""
    r = d.get("r")
    C_IL, how = geo.lvlh_frame(d.t, d.columns, d.params)
    C_Lc = geo.attitude_in_lvlh(d.columns, "q_c", C_IL)
    C_Lt = geo.attitude_in_lvlh(d.columns, "q_t", C_IL)
    f = d.field("ctrl_pos_err")
    goal, goal_how = geo.goal_lvlh(d.columns, r, f.doc if f is not None else None, d.goal, C_Lc, C_Lt)
    return {"r": r, "C_Lc": C_Lc, "C_Lt": C_Lt, "goal": goal, "goal_how": goal_how, "frame_how": how}


def plot_translation(d: PlotData) -> Figure | None:
    if not (d.has("r") and d.has("v")):
        return None
    t, r, v = d.t, d.get("r"), d.get("v")
    where = pose(d)
    goal = where["goal"]
    judged, _ = judged_errors(d)
    rows = ["r", "dist"] + (["pos"] if "pos" in judged else []) + ["v"]
    fig, axes = figure(len(rows), titled=True)
    for ax, row in zip(axes, rows, strict=True):
        if row == "r":
            lines(ax, t, r, LVLH_AXES, "position, LVLH [m]")
            if goal is not None:
                for i in range(3):
                    ax.plot(*envelope(t, goal[:, i]), color=AXES_COLORS[i], ls=":", lw=1.2,
                            label="goal" if i == 0 else None)
                legend(ax)
        elif row == "dist":
            norm(ax, t, r, "|r|")
            if goal is not None:
                ax.plot(*envelope(t, np.linalg.norm(goal, axis=1)), color="tab:purple", ls=":", lw=1.2,
                        label="|goal|")
            keep_out = geo.keep_out_radius(d.params)
            if keep_out is not None:
                ax.axhline(keep_out, color="red", ls=":", lw=1.0, label=f"keep-out radius {keep_out:.3g} m")
            ax.set_ylabel("distance [m]", fontsize=9)
            ax.set_ylim(bottom=0)
            legend(ax)
        elif row == "pos":
            judged_panel(ax, t, judged["pos"])
        else:
            lines(ax, t, v, LVLH_AXES, "velocity, LVLH [m/s]")
            norm(ax, t, v, "|v|")
            legend(ax)
    what = "relative position and velocity" + (f" (goal dotted: {where['goal_how']})" if goal is not None else "")
    return finish(fig, axes, d, what)


def _wheel_capacity(d: PlotData) -> float | None:
    """A wheel's momentum at its speed limit [N m s]: wheel_inertia x wheel_speed_max."""
    i_w, s_max = d.param("wheel_inertia"), d.param("wheel_speed_max")
    return None if i_w is None or s_max is None else i_w * s_max


def plot_actuators(d: PlotData) -> Figure | None:
    f_max, t_max = d.param("force_max"), d.param("torque_max")
    if d.ideal_actuators:  # no wheel, no thruster: what the ideal actuators applied, against their limits
        return _field_panels(d, "actuators: ideal force and torque, per body axis (limits dotted)", [
            ("env_tau_applied", "torque applied, body [N m]", 1.0),
            ("env_F_applied", "force applied, body [N]", 1.0)],
            limit={"env_tau_applied": (t_max, "torque limit"), "env_F_applied": (f_max, "force limit")})
    torque = "wheel_applied" if d.has("wheel_applied") else "wheel_cmd"
    speed_max, torque_max = d.param("wheel_speed_max"), d.param("wheel_torque_max")
    capacity = _wheel_capacity(d)
    return _field_panels(d, "actuators: reaction wheels and the applied torque and force (limits dotted)", [
        ("env_wheel_speed", "wheel speed rel. body [rpm]", RADS2RPM),
        (torque, "wheel torque, after the delay [N m]", 1.0),
        ("h_w", "wheel momentum [N m s]", 1.0),
        ("env_tau_applied", "torque applied, body [N m]", 1.0),
        ("env_F_applied", "force applied, body [N]", 1.0)],
        limit={"env_wheel_speed": (None if speed_max is None else speed_max * RADS2RPM, "speed limit"),
               torque: (torque_max, "torque limit"),
               "h_w": (capacity, "capacity I_w x speed limit")})


def _binned(t: np.ndarray, data: np.ndarray, n_bins: int = RASTER_BINS):
    """Mean of each column over up to ``n_bins`` consecutive time bins (NaN rows ignored)."""
    ok = np.all(np.isfinite(data), axis=1)
    t, data = t[ok], data[ok]
    if len(t) == 0:
        return np.zeros((data.shape[1], 1)), (0.0, 1.0)
    n_bins = max(1, min(n_bins, len(t)))
    starts = np.unique(np.linspace(0, len(t), n_bins + 1).astype(int)[:-1])
    sums = np.add.reduceat(data, starts, axis=0)
    counts = np.diff(np.append(starts, len(t)))[:, None]
    dt = t[1] - t[0] if len(t) > 1 else 1.0
    return (sums / counts).T, (float(t[0]), float(t[-1] + dt))


def plot_thrusters(d: PlotData) -> Figure | None:
    if d.ideal_actuators or not (d.has("thr_on") and d.has("thr_duty") and d.has("m_prop")):
        return None
    t, on = d.t, d.get("thr_on")
    fig = Figure(figsize=(9, 8))
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True, height_ratios=(2, 2, 1.2))
    fig.subplots_adjust(left=MARGIN["left"] / 9, right=1 - MARGIN["right"] / 9, bottom=MARGIN["bottom"] / 8,
                        top=1 - MARGIN["top"] / 8, hspace=0.25)
    for ax, data, what in ((ax1, on, "firing (fraction of time on per bin)"),
                           (ax2, d.get("thr_duty"), "commanded duty (PWPF input)")):
        img, (t0, t1) = _binned(t, data)
        im = ax.imshow(img, aspect="auto", cmap="Greys", vmin=0, vmax=1, interpolation="nearest",
                       extent=(t0, t1, img.shape[0] - 0.5, -0.5))
        ax.set_ylabel("thruster #", fontsize=9)
        ax.set_yticks(range(0, img.shape[0], 3))
        ax.text(0.0, 1.02, what, transform=ax.transAxes, fontsize=9, va="bottom")
        fig.colorbar(im, cax=ax.inset_axes((1.01, 0.0, 0.015, 1.0)))
    total_on = np.nansum(on, axis=0) * (d.dt * d.record_every)
    m_prop = d.get("m_prop")[:, 0]
    ax3.plot(*envelope(t, m_prop), color="k", lw=1.2)
    ax3.set_ylabel("propellant used [kg]", fontsize=9)
    ax3.set_ylim(bottom=0)
    ax3.text(0.01, 0.95, f"total on-time {total_on.sum():.4g} s (busiest: thruster #{int(np.argmax(total_on))}, "
             f"{total_on.max():.4g} s); used {np.nanmax(m_prop):.4g} kg",
             transform=ax3.transAxes, va="top", fontsize=8)
    return finish(fig, (ax1, ax2, ax3), d, "thrusters")


def _mark(ax: Axes, j: Any) -> None:
    """The verdict's threshold and settling time of the error ``j`` on a controller panel."""
    ax.axhline(j.threshold, label=f"threshold {j.threshold:.4g} {j.unit}", **THRESHOLD_STYLE)
    if j.settling is not None:
        ax.axvline(j.settling, label=f"reached at {j.settling:.4g} s", **SETTLED_STYLE)
    legend(ax)


def plot_controller(d: PlotData) -> Figure | None:
    judged, _ = judged_errors(d)
    decorate: dict[str, Callable[[Axes], None]] = {}
    att, pos = judged.get("att"), judged.get("pos")
    if att is not None and att.source == "ctrl_att_err":
        decorate["ctrl_att_err"] = lambda ax: _mark(ax, att)
    if pos is not None and pos.source == "|ctrl_pos_err|":
        def pos_panel(ax: Axes) -> None:
            ax.plot(*envelope(d.t, pos.signal), lw=1.2, color="k", label="|pos error| (judged)")
            _mark(ax, pos)
        decorate["ctrl_pos_err"] = pos_panel
    return _field_panels(d, "controller errors (to its desired state; the verdict's thresholds dashed) and commands", [
        ("ctrl_att_err", "attitude error [deg]", RAD2DEG), ("ctrl_q_err", "error quaternion [-]", 1.0),
        ("ctrl_pos_err", "position error [m]", 1.0), ("ctrl_rate_err", "rate error [deg/s]", RAD2DEG),
        ("ctrl_vel_err", "velocity error [m/s]", 1.0),
        ("cmd_tau_w", "wheel torque command [N m]", 1.0), ("cmd_tau_thr", "thruster torque command [N m]", 1.0),
        ("cmd_F", "force command [N]", 1.0)], ncols=2, decorate=decorate)


def plot_constraints(d: PlotData) -> Figure | None:
    return _field_panels(d, "constraint margins (> 0 satisfied; 001 eqs. 41, 47)", [
        ("env_beta_fov", "field-of-view margin beta_FOV [m]", 1.0),
        ("env_beta_ca", "collision margin beta_CA [m^2]", 1.0)])


def diag_fields(d: PlotData) -> list[LayoutField]:
    """The controller-specific diagnostics: ``ctrl_*`` y fields beyond :data:`STANDARD_DIAG`."""
    return [f for f in d.y_layout if f.name.startswith("ctrl_") and f.name not in STANDARD_DIAG and d.has(f.name)]


def plot_diagnostics(d: PlotData) -> Figure | None:
    fields = diag_fields(d)
    if not fields:
        return None
    ncols = 1 if len(fields) <= 3 else 2
    fig, axes = figure(len(fields), height=1.8, ncols=ncols, titled=True)
    for ax, f in zip(axes, fields, strict=True):
        unit = f.unit or "-"
        lines(ax, d.t, d.get(f.name), components(f), f"{f.name[len('ctrl_'):]} [{unit}]")
        # a text, not set_title: a title makes matplotlib measure every axis again (a third of the time)
        ax.text(0.0, 1.03, f.doc or f.name, transform=ax.transAxes, fontsize=9, va="bottom")
    return finish(fig, axes, d, f"{d.controller} diagnostics")


def plot_lvlh(d: PlotData) -> Figure | None:
    return views.lvlh_figure(d, pose(d)) if d.has("r") else None


def plot_approach(d: PlotData) -> Figure | None:
    return views.approach_figure(d, pose(d)) if d.has("r") else None


#: The figures in drawing order: (file stem, function).  Stems are part of the output contract.
FIGURES: dict[str, Callable[[PlotData], Figure | None]] = {
    "attitude": plot_attitude, "translation": plot_translation, "errors": views.errors_figure,
    "lvlh": plot_lvlh, "approach": plot_approach, "actuators": plot_actuators,
    "thrusters": plot_thrusters, "controller": plot_controller, "constraints": plot_constraints,
    "diagnostics": plot_diagnostics,
}


def build(name: str, d: PlotData) -> Figure | None:
    """The figure ``name`` of ``d`` as a matplotlib Figure (not saved); None if it has nothing to draw."""
    return FIGURES[name](d)


def render(d: PlotData, out_dir: str | Path, fmt: str = DEFAULT_FIGURE_FORMAT,
           names: Sequence[str] | None = None) -> list[str]:
    """Write the figures ``names`` (default: all of :data:`FIGURES`) of ``d`` into ``out_dir`` as
    ``<name>.<fmt>``; returns the file names written (a figure with no logged column is skipped)."""
    if fmt not in FIGURE_FORMATS:
        raise ValueError(unknown_figure_format(fmt))
    out = Path(out_dir)
    written = []
    for name in names or list(FIGURES):
        fig = build(name, d)
        if fig is not None:
            save(fig, out / f"{name}.{fmt}")
            written.append(f"{name}.{fmt}")
    return written


def make_plots(result: RunResult, model: Any, out_dir: str | Path, params: dict | None = None,
               gains: dict | None = None, title: str = "", fmt: str = DEFAULT_FIGURE_FORMAT,
               metrics: dict | None = None) -> list[str]:
    """Write the figures of ``result`` into ``out_dir`` in this process; returns the file names.

    ``params`` (p fields, SI) gives the actuators, their limits and the constraints; ``gains`` the
    goal position ``r_goal``; ``metrics`` the thresholds and settling times the verdict used.
    """
    return render(PlotData.from_result(result, model, params, gains, title, metrics), out_dir, fmt)
