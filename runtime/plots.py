"""PNG figures of one run (matplotlib, Agg; no pyplot, so no global backend state is touched).

Each figure is a function of the :class:`~rpo.runtime.simulate.RunResult` and the model's
layouts; all quantities are read by label from the recorded state ``z`` and outputs ``y``:

* ``attitude.png``  rotation angle of the chaser to the target's interface frame (deg) and the
  error quaternion q_e (000 eq. 22, scalar last);
* ``rates.png``     rate error w_e (000 eq. 17) in chaser axes, deg/s;
* ``position.png``  relative position r in LVLH (m), distance |r| and distance to the goal;
* ``velocity.png``  relative velocity v in LVLH (m/s) and its norm;
* ``wheels.png``    wheel speeds relative to the body (rpm, with the limit) and the wheel torque
  commands after the transport delay (N m, with the limit; the plant blocks a wheel at its
  speed limit from being driven further);
* ``thrusters.png`` firing raster (fraction of time each of the 16 thrusters is on, per time bin),
  the commanded duty (PWPF input) the same way, and the propellant used (kg);
* ``ctrl_errors.png`` the controller's standard errors (``ctrl_att_err`` in deg, ``ctrl_q_err``,
  ``ctrl_pos_err`` m, ``ctrl_rate_err`` deg/s, ``ctrl_vel_err`` m/s): the panels that are logged;
* ``commands.png``  the controller's commands (wheel torque, thruster torque, force);
* ``actuators.png`` the torque and force the actuators applied to the chaser (body axes);
* ``constraints.png`` 001's field-of-view and collision margins (> 0 = satisfied);
* ``diag_<field>.png`` one per controller-specific diagnostic ``ctrl_<field>`` (sliding surfaces,
  adaptive estimates, ESO estimates...), one line per component.

A figure whose columns are all absent is not written.

A diverged run is plotted up to its last good step and marked with a red line.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure

from . import frames

if TYPE_CHECKING:
    from .simulate import RunResult

RAD2DEG = 180.0 / np.pi
RADS2RPM = 60.0 / (2.0 * np.pi)
#: Time bins of the thruster rasters (a 10 ms pulse in a 300 s run stays visible as a grey level).
RASTER_BINS = 600
DPI = 110
AXES_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red")


class _Data:
    """Blocks of a run by layout field name (``z`` fields and ``y`` fields)."""

    def __init__(self, result, model):
        self.r = result
        ctrl = result.meta.get("controller", "baseline")
        self.z_layout = model.layouts.get(f"z_{ctrl}", [])
        self.y_layout = model.layouts.get(f"y_{ctrl}", [])

    def has(self, name: str, source: str) -> bool:
        return any(f["name"] == name for f in (self.z_layout if source == "z" else self.y_layout))

    def get(self, name: str, source: str) -> np.ndarray:
        return self.r.block(name, self.z_layout if source == "z" else self.y_layout)

    def field(self, name: str, source: str = "y") -> dict | None:
        return next((f for f in (self.z_layout if source == "z" else self.y_layout) if f["name"] == name), None)


def _finish(fig: Figure, axes, result, title: str, path: Path) -> None:
    div = result.divergence
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if div is not None:
            ax.axvline(div.time, color="red", lw=1.0, ls="--")
    axes[-1].set_xlabel("t [s]")
    if div is not None:
        title = f"{title}\nDIVERGED at t = {div.time:.6g} s ({div.label})"
    fig.suptitle(title, fontsize=11)
    fig.savefig(path, dpi=DPI)


def _lines(ax, t, data, labels, unit: str, ylabel: str) -> None:
    n = data.shape[1]
    for i in range(n):  # x, y, z, w in the usual colours; longer fields (estimates) in the tab10 cycle
        ax.plot(t, data[:, i], lw=1.0, color=AXES_COLORS[i] if n <= 4 else f"C{i % 10}", label=labels[i])
    ax.set_ylabel(f"{ylabel} [{unit}]")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)


def _binned(t: np.ndarray, data: np.ndarray, n_bins: int = RASTER_BINS):
    """Mean of each column over up to ``n_bins`` consecutive time bins (NaN rows ignored)."""
    ok = np.all(np.isfinite(data), axis=1)
    t, data = t[ok], data[ok]
    if len(t) == 0:
        return np.zeros((data.shape[1], 1)), (0.0, 1.0)
    n_bins = max(1, min(n_bins, len(t)))
    starts = np.linspace(0, len(t), n_bins + 1).astype(int)[:-1]
    starts = np.unique(starts)
    sums = np.add.reduceat(data, starts, axis=0)
    counts = np.diff(np.append(starts, len(t)))[:, None]
    dt = t[1] - t[0] if len(t) > 1 else 1.0
    return (sums / counts).T, (float(t[0]), float(t[-1] + dt))


def plot_attitude(d: _Data, path: Path, title: str) -> None:
    t = d.r.t
    q_e = d.get("meas_q_e", "y")
    fig = Figure(figsize=(9, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ok = np.all(np.isfinite(q_e), axis=1)  # the last row has no output (NaN)
    angle = np.full(len(t), np.nan)
    angle[ok] = frames.rotation_angle(q_e[ok]) * RAD2DEG
    ax1.plot(t, angle, lw=1.2, color="k")
    ax1.set_ylabel("angle to interface frame [deg]")
    ax1.set_ylim(bottom=0)
    _lines(ax2, t, q_e, ["q_e x", "q_e y", "q_e z", "q_e w"], "-", "error quaternion")
    _finish(fig, (ax1, ax2), d.r, f"{title}: relative attitude (chaser to target interface frame)", path)


def plot_rates(d: _Data, path: Path, title: str) -> None:
    t = d.r.t
    w_e = d.get("meas_w_e", "y") * RAD2DEG
    fig = Figure(figsize=(9, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    _lines(ax1, t, w_e, ["w_e x", "w_e y", "w_e z"], "deg/s", "rate error, chaser axes")
    ax2.plot(t, np.linalg.norm(w_e, axis=1), color="k", lw=1.2)
    ax2.set_ylabel("|w_e| [deg/s]")
    ax2.set_ylim(bottom=0)
    _finish(fig, (ax1, ax2), d.r, f"{title}: rate error", path)


def plot_position(d: _Data, path: Path, title: str, goal: np.ndarray | None) -> None:
    t = d.r.t
    r = d.get("r", "z")
    fig = Figure(figsize=(9, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    _lines(ax1, t, r, ["x (radial)", "y (along-track)", "z (normal)"], "m", "position, LVLH")
    ax2.plot(t, np.linalg.norm(r, axis=1), color="k", lw=1.2, label="|r|")
    if goal is not None and np.any(goal != 0):
        for i in range(3):
            ax1.axhline(goal[i], color=AXES_COLORS[i], ls=":", lw=1.0)
        ax2.plot(t, np.linalg.norm(r - goal, axis=1), color="tab:purple", lw=1.2, label="|r - r_goal|")
    ax2.set_ylabel("distance [m]")
    ax2.set_ylim(bottom=0)
    ax2.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False)
    _finish(fig, (ax1, ax2), d.r, f"{title}: relative position", path)


def plot_velocity(d: _Data, path: Path, title: str) -> None:
    t = d.r.t
    v = d.get("v", "z")
    fig = Figure(figsize=(9, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    _lines(ax1, t, v, ["v x", "v y", "v z"], "m/s", "velocity, LVLH")
    ax2.plot(t, np.linalg.norm(v, axis=1), color="k", lw=1.2)
    ax2.set_ylabel("|v| [m/s]")
    ax2.set_ylim(bottom=0)
    _finish(fig, (ax1, ax2), d.r, f"{title}: relative velocity", path)


def plot_wheels(d: _Data, path: Path, title: str, speed_max: float | None, torque_max: float | None) -> None:
    t = d.r.t
    fig = Figure(figsize=(9, 6.5), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    names = [f"wheel {i + 1}" for i in range(4)]
    _lines(ax1, t, d.get("env_wheel_speed", "y") * RADS2RPM, names, "rpm", "speed rel. body")
    if speed_max:
        for s in (1, -1):
            ax1.axhline(s * speed_max * RADS2RPM, color="red", ls=":", lw=1.0)
    torque = d.get("wheel_applied", "y") if d.has("wheel_applied", "y") else d.get("wheel_cmd", "y")
    _lines(ax2, t, torque, names, "N m", "delayed command")
    if torque_max:
        for s in (1, -1):
            ax2.axhline(s * torque_max, color="red", ls=":", lw=1.0)
    _finish(fig, (ax1, ax2), d.r, f"{title}: reaction wheels (limits dotted)", path)


def plot_thrusters(d: _Data, path: Path, title: str) -> None:
    t = d.r.t
    on = d.get("thr_on", "y")
    fig = Figure(figsize=(9, 8), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True, height_ratios=(2, 2, 1.2))
    for ax, data, what in ((ax1, on, "firing (fraction of time on)"),
                           (ax2, d.get("thr_duty", "y"), "commanded duty (PWPF input)")):
        img, (t0, t1) = _binned(t, data)
        im = ax.imshow(img, aspect="auto", cmap="Greys", vmin=0, vmax=1, interpolation="nearest",
                       extent=(t0, t1, img.shape[0] - 0.5, -0.5))
        ax.set_ylabel("thruster")
        ax.set_yticks(range(0, img.shape[0], 3))
        ax.set_title(what, fontsize=9)
        fig.colorbar(im, ax=ax, pad=0.01, fraction=0.04)
    total_on = np.nansum(on, axis=0) * (d.r.dt * d.r.meta.get("record_every", 1))
    m_prop = d.get("m_prop", "z")[:, 0]
    ax3.plot(t, m_prop, color="k", lw=1.2)
    ax3.set_ylabel("propellant [kg]")
    ax3.set_ylim(bottom=0)
    ax3.text(0.01, 0.95, f"total on-time {total_on.sum():.4g} s (busiest: thruster {int(np.argmax(total_on))}, "
             f"{total_on.max():.4g} s); used {np.nanmax(m_prop):.4g} kg",
             transform=ax3.transAxes, va="top", fontsize=8)
    _finish(fig, (ax1, ax2, ax3), d.r, f"{title}: thrusters", path)


#: Standard diagnostic fields every paper controller logs first (plotted together in ctrl_errors.png).
STANDARD_DIAG = ("ctrl_att_err", "ctrl_q_err", "ctrl_pos_err", "ctrl_rate_err", "ctrl_vel_err")


def _components(f: dict) -> list[str]:
    return [lbl[len(f["name"]) + 1:] or f["name"] for lbl in f["labels"]] if f["size"] > 1 else [f["name"]]


def _panels(d: _Data, path: Path, title: str, panels: list[tuple[str, str, float, str]], height=2.2) -> bool:
    """One panel per present y field: (field, y label, scale, unit); False (nothing written) if none.
    The absent fields are named in the title."""
    present = [p for p in panels if d.has(p[0], "y")]
    if not present:
        return False
    absent = [p[0] for p in panels if not d.has(p[0], "y")]
    if absent:
        title = f"{title}\n(not logged by this controller: {', '.join(absent)})"
    fig = Figure(figsize=(9, 1.5 + height * len(present)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(present), 1, sharex=True, squeeze=False)[:, 0])
    for ax, (name, ylabel, scale, unit) in zip(axes, present, strict=True):
        f = d.field(name)
        if f is None:  # not reached: present holds the logged fields only
            continue
        data = d.get(name, "y") * scale
        _lines(ax, d.r.t, data, _components(f), unit, ylabel)
        if name in ("env_beta_fov", "env_beta_ca"):
            ax.axhline(0.0, color="red", ls=":", lw=1.0)
    _finish(fig, axes, d.r, title, path)
    return True


def plot_ctrl_errors(d: _Data, path: Path, title: str) -> bool:
    return _panels(d, path, f"{title}: controller errors (to its desired state)", [
        ("ctrl_att_err", "attitude error", RAD2DEG, "deg"), ("ctrl_q_err", "error quaternion", 1.0, "-"),
        ("ctrl_pos_err", "position error", 1.0, "m"), ("ctrl_rate_err", "rate error", RAD2DEG, "deg/s"),
        ("ctrl_vel_err", "velocity error", 1.0, "m/s")])


def plot_commands(d: _Data, path: Path, title: str) -> bool:
    return _panels(d, path, f"{title}: controller commands", [
        ("cmd_tau_w", "wheel torque cmd", 1.0, "N m"), ("cmd_tau_thr", "thruster torque cmd", 1.0, "N m"),
        ("cmd_F", "force cmd", 1.0, "N")])


def plot_actuators(d: _Data, path: Path, title: str) -> bool:
    return _panels(d, path, f"{title}: applied control torque and force (body)", [
        ("env_tau_applied", "applied torque", 1.0, "N m"), ("env_F_applied", "applied force", 1.0, "N")])


def plot_constraints(d: _Data, path: Path, title: str) -> bool:
    return _panels(d, path, f"{title}: constraint margins (> 0 satisfied; 001 eqs. 41, 47)", [
        ("env_beta_fov", "beta_FOV", 1.0, "m"), ("env_beta_ca", "beta_CA", 1.0, "m^2")])


def diag_fields(d: _Data) -> list[dict]:
    """The controller-specific diagnostics: ``ctrl_*`` y fields beyond :data:`STANDARD_DIAG`."""
    return [f for f in d.y_layout if f["name"].startswith("ctrl_") and f["name"] not in STANDARD_DIAG]


def plot_diag(d: _Data, f: dict, path: Path, title: str) -> bool:
    unit = f.get("unit") or "-"
    doc = f.get("doc", "")
    return _panels(d, path, f"{title}: {f['name']}" + (f" ({doc})" if doc else ""),
                   [(f["name"], f["name"][len("ctrl_"):], 1.0, unit)], height=4.0)


def make_plots(result: RunResult, model: Any, out_dir: str | Path, params: dict | None = None,
               gains: dict | None = None, title: str = "") -> list[str]:
    """Write the figures of ``result`` into ``out_dir``; returns the file names written.

    ``params`` (p fields, SI) gives the wheel limits; ``gains`` the goal position ``r_goal``.
    """
    out = Path(out_dir)
    d = _Data(result, model)
    params = params or {}

    def scalar(name):
        v = params.get(name)
        return None if v is None else float(np.ravel(v)[0])

    goal = None if not gains or "r_goal" not in gains else np.ravel(np.asarray(gains["r_goal"], float))
    title = title or result.meta.get("controller", "run")
    jobs: list[tuple[str, Callable[[Path], object]]] = [
        ("attitude.png", lambda p: plot_attitude(d, p, title)),
        ("rates.png", lambda p: plot_rates(d, p, title)),
        ("position.png", lambda p: plot_position(d, p, title, goal)),
        ("velocity.png", lambda p: plot_velocity(d, p, title)),
        ("wheels.png", lambda p: plot_wheels(d, p, title, scalar("wheel_speed_max"), scalar("wheel_torque_max"))),
        ("thrusters.png", lambda p: plot_thrusters(d, p, title)),
    ]
    optional: list[tuple[str, Callable[[Path], bool]]] = [
        ("ctrl_errors.png", lambda p: plot_ctrl_errors(d, p, title)),
        ("commands.png", lambda p: plot_commands(d, p, title)),
        ("actuators.png", lambda p: plot_actuators(d, p, title)),
        ("constraints.png", lambda p: plot_constraints(d, p, title)),
    ]

    def diag_job(f: dict) -> Callable[[Path], bool]:
        return lambda p: plot_diag(d, f, p, title)

    optional += [(f"diag_{f['name'][len('ctrl_'):]}.png", diag_job(f)) for f in diag_fields(d)]
    written = []
    for name, job in jobs:
        job(out / name)
        written.append(name)
    for name, job in optional:
        if job(out / name):
            written.append(name)
    return written
