"""What the figures of one run need, without matplotlib: :class:`PlotData` and which fields each
figure of :mod:`rpo.runtime.outputs.plots` reads (:data:`FIGURE_FIELDS`), so the data path can hand each
figure only its columns (to another process) without importing matplotlib itself."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from fnmatch import fnmatchcase
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.outputs.metrics import DEFAULT_THRESHOLDS, error_signals, settling_time
from rpo.runtime.scenario.channels import select
from rpo.runtime.scenario.faults import active_faults

if TYPE_CHECKING:
    from rpo.runtime.model.manifest import LayoutField
    from rpo.runtime.run.result import RunResult

#: Standard diagnostic fields every paper controller logs first (in the ``controller`` figure).
STANDARD_DIAG = ("ctrl_att_err", "ctrl_q_err", "ctrl_pos_err", "ctrl_rate_err", "ctrl_vel_err")
#: What the metrics' error signals are computed from (:func:`rpo.runtime.outputs.metrics.error_signals`:
#: the controller's own errors, else 000's interface-frame errors, else ``r``/``v`` and the goal).
ERROR_SOURCES = (*STANDARD_DIAG, "meas_q_e", "meas_w_e", "r", "v")
#: The pose of both bodies in the target's LVLH frame (:mod:`rpo.runtime.outputs.geometry`).
POSE = ("r", "q_c", "q_t", "meas_q_L", "r_T", "v_T", "ctrl_pos_err")
#: The fields (names or glob patterns) each figure reads, heaviest figure first (the order the
#: figures are handed to the workers).
FIGURE_FIELDS: dict[str, tuple[str, ...]] = {
    "diagnostics": ("ctrl_*",),
    "controller": (*STANDARD_DIAG, "cmd_*"),
    "approach": POSE,
    "actuators": ("env_wheel_speed", "wheel_applied", "wheel_cmd", "h_w", "env_tau_applied", "env_F_applied"),
    "errors": ERROR_SOURCES,
    "translation": (*ERROR_SOURCES, *POSE),
    "attitude": ERROR_SOURCES,
    "lvlh": (*POSE, "env_beta_ca"),
    "thrusters": ("thr_on", "thr_duty", "m_prop"),
    "constraints": ("env_beta_fov", "env_beta_ca"),
}
#: The figures in reading order (``run.json`` lists them so; :data:`rpo.runtime.outputs.plots.FIGURES`).
FIGURE_ORDER = ("attitude", "translation", "errors", "lvlh", "approach", "actuators", "thrusters", "controller",
                "constraints", "diagnostics")
FIGURE_CHANNELS = tuple(dict.fromkeys(p for ps in FIGURE_FIELDS.values() for p in ps))
#: The parameters the figures use (SI; scalars): which actuators the plant has and their limits,
#: the constraints' geometry, the orbit (the LVLH frame when ``meas_q_L`` is not at hand).
PLOT_PARAMS = ("actuators_ideal", "wheel_speed_max", "wheel_torque_max", "wheel_inertia", "force_max", "torque_max",
               "camera_half_angle", "camera_zn", "chaser_radius", "target_radius", "gravity_on", "orbit_propagated",
               "mu", "orbit_a", "orbit_e", "orbit_inc", "orbit_raan", "orbit_argp", "orbit_nu0")
#: What the figures take from the metrics: the thresholds, the settling times (the verdict's
#: "reached at"), the sources of the errors and the verdict's line.
JUDGED_KEYS = ("thresholds", "att_settling_time_s", "pos_settling_time_s", "sources")


@dataclass
class PlotData:
    """What the figures need, picklable: ``columns`` by label (rows at ``t``), the layouts of the
    controller's z and y (the manifest's fields), and the run facts shown."""

    t: np.ndarray
    dt: float
    columns: dict[str, np.ndarray]
    z_layout: list[LayoutField]
    y_layout: list[LayoutField]
    controller: str = "run"
    record_every: int = 1
    divergence: tuple[float, str] | None = None  # (time, label)
    title: str = ""
    params: dict[str, float] = field(default_factory=dict)  # PLOT_PARAMS given (SI)
    goal: np.ndarray | None = None
    faults: list[tuple[float, str]] = field(default_factory=list)  # (start time, label) of each fault
    #: JUDGED_KEYS of the run's metrics and ``verdict`` (its line); empty: computed by judged_errors
    judged: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def from_result(cls, result: RunResult, model: Any, params: dict | None = None, gains: dict | None = None,
                    title: str = "", metrics: Mapping[str, Any] | None = None) -> PlotData:
        """The figures' columns of ``result`` (full in-memory rate) and the run facts; ``metrics``
        (:func:`rpo.runtime.outputs.metrics.compute_metrics`, with its ``verdict``) gives the
        thresholds and settling times the error figures mark, so they show what the verdict judged."""
        ctrl = result.meta.get("controller", "baseline")
        z_lay = list(model.layouts.get(f"z_{ctrl}", []))
        y_lay = list(model.layouts.get(f"y_{ctrl}", []))
        sel = select(FIGURE_CHANNELS, z_lay, y_lay, strict=False)
        zi = {lbl: i for i, lbl in enumerate(result.z_labels)}
        yi = {lbl: i for i, lbl in enumerate(result.y_labels)}
        cols = {lbl: np.ascontiguousarray(result.z[:, zi[lbl]]) for lbl in sel.z if lbl in zi}
        cols.update({lbl: np.ascontiguousarray(result.y[:, yi[lbl]]) for lbl in sel.y if lbl in yi})
        plot_params = {}
        for name in PLOT_PARAMS:
            v = (params or {}).get(name)
            if v is not None and np.size(v):
                plot_params[name] = float(np.ravel(v)[0])
        judged = {k: metrics[k] for k in JUDGED_KEYS if k in metrics} if metrics else {}
        if metrics and isinstance(metrics.get("verdict"), Mapping):
            judged["verdict"] = metrics["verdict"].get("line", "")
        goal = None if not gains or "r_goal" not in gains else np.ravel(np.asarray(gains["r_goal"], float))
        div = result.divergence
        return cls(t=np.asarray(result.t), dt=float(result.dt), columns=cols, z_layout=z_lay, y_layout=y_lay,
                   controller=ctrl, record_every=int(result.meta.get("record_every", 1)),
                   divergence=None if div is None else (float(div.time), str(div.label)),
                   title=title or ctrl, params=plot_params, goal=goal, judged=judged,
                   faults=active_faults(model.manifest.faults, params, float(np.asarray(result.t)[-1]))
                   if params else [])

    def subset(self, figure: str) -> PlotData:
        """A copy with only the columns of ``figure`` (what a worker process is sent)."""
        pats = FIGURE_FIELDS[figure]
        keep = {lbl for f in (*self.z_layout, *self.y_layout) if any(fnmatchcase(f.name, p) for p in pats)
                for lbl in f.labels}
        return replace(self, columns={k: v for k, v in self.columns.items() if k in keep})

    def field(self, name: str) -> LayoutField | None:
        f = next((f for f in (*self.z_layout, *self.y_layout) if f.name == name), None)
        return f if f is not None and all(lbl in self.columns for lbl in f.labels) else None

    def has(self, name: str) -> bool:
        return self.field(name) is not None

    def get(self, name: str) -> np.ndarray:
        f = self.field(name)
        if f is None:
            raise KeyError(name)
        return np.column_stack([self.columns[lbl] for lbl in f.labels])

    def param(self, name: str) -> float | None:
        return self.params.get(name)

    @property
    def ideal_actuators(self) -> bool | None:
        """True: the plant flies ideal force and torque actuators (no wheel, no thruster); None: not known."""
        v = self.params.get("actuators_ideal")
        return None if v is None else v == 1.0


RAD2DEG = 180.0 / np.pi


@dataclass
class Judged:
    """One error as the metrics and the verdict see it, in the unit drawn: ``signal`` (the metrics'
    own series, :func:`~rpo.runtime.outputs.metrics.error_signals`), its ``threshold`` and
    ``settling`` time (the verdict's "reached at"; None: not reached, or no goal for this error)."""

    quantity: str            # att, pos, rate, vel
    label: str               # "attitude error"
    unit: str                # deg, m, deg/s, m/s
    signal: np.ndarray
    source: str              # the columns it is computed from
    threshold: float | None = None
    settling: float | None = None

    @property
    def judged(self) -> bool:
        """Whether the verdict judges this error (it has a threshold)."""
        return self.threshold is not None


ERROR_TEXT = {"att": ("attitude error", "deg", RAD2DEG), "pos": ("position error", "m", 1.0),
              "rate": ("rate error", "deg/s", RAD2DEG), "vel": ("velocity error", "m/s", 1.0)}


def judged_errors(d: PlotData) -> tuple[dict[str, Judged], dict[str, np.ndarray]]:
    """(the errors by quantity, their components in the unit drawn), computed by the metrics' own
    :func:`~rpo.runtime.outputs.metrics.error_signals` from the same columns; the thresholds and
    settling times are the run's metrics' (``d.judged``), else computed the metrics' way."""
    sig, comp, src = error_signals(d.columns, d.goal)
    th = {**DEFAULT_THRESHOLDS, **d.judged.get("thresholds", {})}
    limits = {"att": np.radians(th["att_deg"]), "pos": th["pos_m"]}
    out: dict[str, Judged] = {}
    for q, x in sig.items():
        label, unit, scale = ERROR_TEXT[q]
        j = Judged(q, label, unit, x * scale, d.judged.get("sources", {}).get(q, src[q]))
        if q in limits:
            key = f"{q}_settling_time_s"
            j.threshold = float(limits[q] * scale)
            j.settling = d.judged[key] if key in d.judged else settling_time(d.t, x, limits[q])
        out[q] = j
    scales = {"q": 1.0, "pos": 1.0, "rate": RAD2DEG, "vel": 1.0}
    return out, {k: v * scales[k] for k, v in comp.items()}
