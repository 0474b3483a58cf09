"""Figures of one run (matplotlib, Agg; no pyplot, so no global backend state is touched).

The figures are drawn from a :class:`~rpo.runtime.outputs.plotdata.PlotData` (the time, the columns the
figures use at the rate of the in-memory record, the layouts and a few run facts), so they can be
rendered in another process (:mod:`rpo.runtime.outputs.writers` does, while it writes the data files).  Every figure
is a column of panels over time; titles, axis labels and legends use words and units ("wheel
speed [rpm]"), not layout ids.  Long series are drawn through a min/max envelope per horizontal
pixel (:func:`envelope`), which looks the same as every point and keeps vector files small.

* ``attitude``     angle of the chaser to the target's interface frame [deg], the error quaternion
  q_e (000 eq. 22, scalar last) and the rate error w_e (000 eq. 17) [deg/s];
* ``translation``  relative position r in LVLH [m], the distance (and to the goal), the relative
  velocity v [m/s];
* ``actuators``    wheel speeds relative to the body [rpm] and wheel torques after the delay
  [N m] with their limits (dotted), the torque and force applied to the chaser (body axes);
* ``thrusters``    firing raster (fraction of time each of the 16 thrusters is on, per time bin),
  the commanded duty (PWPF input) the same way, and the propellant used [kg];
* ``controller``   the controller's standard errors (attitude, error quaternion, position,
  rate, velocity: those it logs) and its commands (wheel torque, thruster torque, force);
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
from matplotlib.ticker import MaxNLocator

from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, FIGURE_FORMATS, figure_format_of, unknown_figure_format
from rpo.runtime.outputs.metrics import quat_angle
from rpo.runtime.outputs.plotdata import STANDARD_DIAG, PlotData

if TYPE_CHECKING:
    from rpo.runtime.model.manifest import LayoutField
    from rpo.runtime.run.result import RunResult

RAD2DEG = 180.0 / np.pi
RADS2RPM = 60.0 / (2.0 * np.pi)
#: Time bins of the thruster rasters (a 10 ms pulse in a 300 s run stays visible as a grey level).
RASTER_BINS = 600
#: Envelope bins per line: about one per horizontal pixel of a 9 inch figure at DPI.
ENVELOPE_BINS = 1000
DPI = 110
AXES_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red")
XYZ = ("x", "y", "z")


# --------------------------------------------------------------------------- drawing helpers


def envelope(t: np.ndarray, x: np.ndarray, n_bins: int = ENVELOPE_BINS) -> tuple[np.ndarray, np.ndarray]:
    """``(t, x)`` reduced to the first, minimum, maximum and last sample of each of ``n_bins``
    consecutive bins, in time order: the drawn line covers the same pixels as the full series."""
    n = len(t)
    k = n // n_bins
    if k < 4:
        return t, x
    m = n_bins * k
    b = x[:m].reshape(n_bins, k)
    lo = np.where(np.isnan(b), np.inf, b).argmin(axis=1)
    hi = np.where(np.isnan(b), -np.inf, b).argmax(axis=1)
    base = np.arange(n_bins) * k
    idx = np.concatenate([base, base + lo, base + hi, base + k - 1, np.arange(m, n)])
    idx = np.unique(idx)
    return t[idx], x[idx]


def _lines(ax, t, data, labels: Sequence[str], ylabel: str, colors: Sequence[str] | None = None) -> None:
    n = data.shape[1]
    for i in range(n):  # x, y, z, w in the usual colours; longer fields (estimates) in the tab10 cycle
        color = colors[i] if colors else (AXES_COLORS[i] if n <= 4 else f"C{i % 10}")
        ax.plot(*envelope(t, data[:, i]), lw=1.0, color=color, label=labels[i])
    ax.set_ylabel(ylabel, fontsize=9)
    ax.tick_params(labelsize=8)
    ax.yaxis.set_major_locator(MaxNLocator(4))  # every tick is five artists: fewer is faster
    if n > 1 or labels[0]:
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False,
                  ncol=1 if n <= 8 else 2)


def _norm(ax, t, data, label: str) -> None:
    ax.plot(*envelope(t, np.linalg.norm(data, axis=1)), lw=1.2, color="k", label=label)


def _limits(ax, value: float | None) -> None:
    if value:
        for s in (1, -1):
            ax.axhline(s * value, color="red", ls=":", lw=1.0)


def _components(f: LayoutField) -> list[str]:
    """Legend entries of a field: its component names (``x``, ``alpha_xx1``, ``wheel 1``...)."""
    if f.size == 1:
        return [""]
    out = []
    for lbl in f.labels:
        c = lbl[len(f.name) + 1:] if lbl.startswith(f.name + "_") else lbl
        what = "wheel" if "wheel" in f.name else "thruster" if f.name.startswith("thr_") else "#"
        out.append((f"{what} {int(c)}" if what != "#" else f"#{int(c)}") if c.isdigit() else c)
    return out


#: Fixed margins [inch] (no layout engine: constrained layout cost half of the drawing time).
MARGIN = {"left": 0.85, "right": 1.75, "bottom": 0.55, "top": 0.75, "hspace": 0.45}


def _figure(n_panels: int, height: float = 2.0, ncols: int = 1, titled: bool = False) -> tuple[Figure, list]:
    """A figure of ``n_panels`` panels over time in ``ncols`` columns (filled down each column),
    with room right of each panel for its legend."""
    rows = -(-n_panels // ncols)
    gap = MARGIN["hspace"] + (0.25 if titled else 0.0)
    width = 9.0 if ncols == 1 else 15.0
    h = MARGIN["top"] + MARGIN["bottom"] + (0.3 if titled else 0.0) + height * rows + gap * (rows - 1)
    fig = Figure(figsize=(width, h))
    axes = fig.subplots(rows, ncols, sharex=True, squeeze=False)
    axes[0, 0].xaxis.set_major_locator(MaxNLocator(6))  # shared by every panel
    ax_w = (width - MARGIN["left"] - ncols * MARGIN["right"] - (ncols - 1) * MARGIN["left"]) / ncols
    fig.subplots_adjust(left=MARGIN["left"] / width, right=1 - MARGIN["right"] / width,
                        bottom=MARGIN["bottom"] / h, top=1 - (MARGIN["top"] + (0.3 if titled else 0.0)) / h,
                        hspace=gap / height, wspace=(MARGIN["right"] + MARGIN["left"]) / ax_w)
    flat = list(axes.T.ravel())
    for ax in flat[n_panels:]:
        ax.set_visible(False)
    return fig, flat[:n_panels]


def _finish(fig: Figure, axes, d: PlotData, title: str, path: Path) -> None:
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if d.divergence is not None:
            ax.axvline(d.divergence[0], color="red", lw=1.0, ls="--")
        for t_f, _label in d.faults:
            ax.axvline(t_f, color="darkorange", lw=1.0, ls=":")
    bottom = {ax.get_subplotspec().colspan.start: ax for ax in axes}  # the lowest panel of each column
    for ax in bottom.values():
        ax.set_xlabel("time [s]")
        ax.xaxis.set_tick_params(labelbottom=True)
    if d.faults:
        shown = "; ".join(f"{label} at {t_f:g} s" for t_f, label in d.faults[:4])
        title = f"{title}\nfaults (dotted): {shown}{' ...' if len(d.faults) > 4 else ''}"
    if d.divergence is not None:
        title = f"{title}\nDIVERGED at t = {d.divergence[0]:.6g} s ({d.divergence[1]})"
    fig.suptitle(f"{d.title}: {title}", fontsize=11, y=1 - 0.12 / fig.get_figheight(), va="top")
    fmt = figure_format_of(path)  # its quick options (PNG: a fast zlib level)
    extra: dict[str, Any] = fmt.quick_options() if fmt is not None else {}
    fig.savefig(path, dpi=DPI, **extra)


# --------------------------------------------------------------------------- the figures

Panel = tuple[str, str, float]  # (field, axis label with unit, scale)


def _field_panels(d: PlotData, path: Path, title: str, panels: Sequence[Panel], ncols: int = 1,
                  limits: dict[str, float | None] | None = None) -> bool:
    """One panel per logged field; False (nothing written) if none.  Absent ones are named."""
    present = [p for p in panels if d.has(p[0])]
    if not present:
        return False
    absent = [p[1].split(" [")[0] for p in panels if not d.has(p[0])]
    if absent:
        title = f"{title}\n(not logged by this controller: {', '.join(absent)})"
    fig, axes = _figure(len(present), ncols=ncols, titled=bool(absent))
    for ax, (name, ylabel, scale) in zip(axes, present, strict=True):
        f = d.field(name)
        assert f is not None
        _lines(ax, d.t, d.get(name) * scale, _components(f), ylabel)
        if limits and name in limits:
            _limits(ax, limits[name])
        if name in ("env_beta_fov", "env_beta_ca"):
            ax.axhline(0.0, color="red", ls=":", lw=1.0)
    _finish(fig, axes, d, title, path)
    return True


def plot_attitude(d: PlotData, path: Path) -> bool:
    if not (d.has("meas_q_e") and d.has("meas_w_e")):
        return False
    t, q_e, w_e = d.t, d.get("meas_q_e"), d.get("meas_w_e") * RAD2DEG
    fig, (ax1, ax2, ax3) = _figure(3)
    ok = np.all(np.isfinite(q_e), axis=1)  # the last row has no output (NaN)
    angle = np.full(len(t), np.nan)
    angle[ok] = quat_angle(q_e[ok]) * RAD2DEG
    ax1.plot(*envelope(t, angle), lw=1.2, color="k")
    ax1.set_ylabel("angle to interface frame [deg]", fontsize=9)
    ax1.set_ylim(bottom=0)
    _lines(ax2, t, q_e, ["x", "y", "z", "w (scalar)"], "error quaternion q_e [-]")
    _lines(ax3, t, w_e, XYZ, "rate error w_e, chaser axes [deg/s]")
    _norm(ax3, t, w_e, "|w_e|")
    ax3.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    _finish(fig, (ax1, ax2, ax3), d, "attitude relative to the target's interface frame", path)
    return True


def plot_translation(d: PlotData, path: Path) -> bool:
    if not (d.has("r") and d.has("v")):
        return False
    t, r, v, goal = d.t, d.get("r"), d.get("v"), d.goal
    fig, (ax1, ax2, ax3) = _figure(3)
    _lines(ax1, t, r, ["x (radial)", "y (along-track)", "z (normal)"], "position, LVLH [m]")
    _norm(ax2, t, r, "|r|")
    if goal is not None and np.any(goal != 0):
        for i in range(3):
            ax1.axhline(goal[i], color=AXES_COLORS[i], ls=":", lw=1.0)
        ax2.plot(*envelope(t, np.linalg.norm(r - goal, axis=1)), color="tab:purple", lw=1.2, label="|r - r_goal|")
    ax2.set_ylabel("distance [m]", fontsize=9)
    ax2.set_ylim(bottom=0)
    ax2.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    _lines(ax3, t, v, ["x (radial)", "y (along-track)", "z (normal)"], "velocity, LVLH [m/s]")
    _norm(ax3, t, v, "|v|")
    ax3.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    _finish(fig, (ax1, ax2, ax3), d, "relative position and velocity (goal dotted)", path)
    return True


def plot_actuators(d: PlotData, path: Path) -> bool:
    torque = "wheel_applied" if d.has("wheel_applied") else "wheel_cmd"
    speed_max, torque_max = d.limits.get("wheel_speed_max"), d.limits.get("wheel_torque_max")
    return _field_panels(d, path, "actuators (limits dotted)", [
        ("env_wheel_speed", "wheel speed rel. body [rpm]", RADS2RPM),
        (torque, "wheel torque, after the delay [N m]", 1.0),
        ("env_tau_applied", "torque applied, body [N m]", 1.0),
        ("env_F_applied", "force applied, body [N]", 1.0)],
        limits={"env_wheel_speed": None if speed_max is None else speed_max * RADS2RPM, torque: torque_max})


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


def plot_thrusters(d: PlotData, path: Path) -> bool:
    if not (d.has("thr_on") and d.has("thr_duty") and d.has("m_prop")):
        return False
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
    _finish(fig, (ax1, ax2, ax3), d, "thrusters", path)
    return True


def plot_controller(d: PlotData, path: Path) -> bool:
    return _field_panels(d, path, "controller errors (to its desired state) and commands", [
        ("ctrl_att_err", "attitude error [deg]", RAD2DEG), ("ctrl_q_err", "error quaternion [-]", 1.0),
        ("ctrl_pos_err", "position error [m]", 1.0), ("ctrl_rate_err", "rate error [deg/s]", RAD2DEG),
        ("ctrl_vel_err", "velocity error [m/s]", 1.0),
        ("cmd_tau_w", "wheel torque command [N m]", 1.0), ("cmd_tau_thr", "thruster torque command [N m]", 1.0),
        ("cmd_F", "force command [N]", 1.0)], ncols=2)


def plot_constraints(d: PlotData, path: Path) -> bool:
    return _field_panels(d, path, "constraint margins (> 0 satisfied; 001 eqs. 41, 47)", [
        ("env_beta_fov", "field-of-view margin beta_FOV [m]", 1.0),
        ("env_beta_ca", "collision margin beta_CA [m^2]", 1.0)])


def diag_fields(d: PlotData) -> list[LayoutField]:
    """The controller-specific diagnostics: ``ctrl_*`` y fields beyond :data:`STANDARD_DIAG`."""
    return [f for f in d.y_layout if f.name.startswith("ctrl_") and f.name not in STANDARD_DIAG and d.has(f.name)]


def plot_diagnostics(d: PlotData, path: Path) -> bool:
    fields = diag_fields(d)
    if not fields:
        return False
    ncols = 1 if len(fields) <= 3 else 2
    fig, axes = _figure(len(fields), height=1.8, ncols=ncols, titled=True)
    for ax, f in zip(axes, fields, strict=True):
        unit = f.unit or "-"
        _lines(ax, d.t, d.get(f.name), _components(f), f"{f.name[len('ctrl_'):]} [{unit}]")
        # a text, not set_title: a title makes matplotlib measure every axis again (a third of the time)
        ax.text(0.0, 1.03, f.doc or f.name, transform=ax.transAxes, fontsize=9, va="bottom")
    _finish(fig, axes, d, f"{d.controller} diagnostics", path)
    return True


#: The figures in drawing order: (file stem, function).  Stems are part of the output contract.
FIGURES: dict[str, Callable[[PlotData, Path], bool]] = {
    "attitude": plot_attitude, "translation": plot_translation, "actuators": plot_actuators,
    "thrusters": plot_thrusters, "controller": plot_controller, "constraints": plot_constraints,
    "diagnostics": plot_diagnostics,
}


def render(d: PlotData, out_dir: str | Path, fmt: str = DEFAULT_FIGURE_FORMAT,
           names: Sequence[str] | None = None) -> list[str]:
    """Write the figures ``names`` (default: all of :data:`FIGURES`) of ``d`` into ``out_dir`` as
    ``<name>.<fmt>``; returns the file names written (a figure with no logged column is skipped)."""
    if fmt not in FIGURE_FORMATS:
        raise ValueError(unknown_figure_format(fmt))
    out = Path(out_dir)
    written = []
    for name in names or list(FIGURES):
        if FIGURES[name](d, out / f"{name}.{fmt}"):
            written.append(f"{name}.{fmt}")
    return written


def make_plots(result: RunResult, model: Any, out_dir: str | Path, params: dict | None = None,
               gains: dict | None = None, title: str = "", fmt: str = DEFAULT_FIGURE_FORMAT) -> list[str]:
    """Write the figures of ``result`` into ``out_dir`` in this process; returns the file names.

    ``params`` (p fields, SI) gives the wheel limits; ``gains`` the goal position ``r_goal``.
    """
    return render(PlotData.from_result(result, model, params, gains, title), out_dir, fmt)
