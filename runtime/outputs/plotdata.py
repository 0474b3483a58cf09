"""What the figures of one run need, without matplotlib: :class:`PlotData` and which fields each
figure of :mod:`rpo.runtime.outputs.plots` reads (:data:`FIGURE_FIELDS`), so the data path can hand each
figure only its columns (to another process) without importing matplotlib itself."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from fnmatch import fnmatchcase
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.scenario.channels import select
from rpo.runtime.scenario.faults import active_faults

if TYPE_CHECKING:
    from rpo.runtime.model.manifest import LayoutField
    from rpo.runtime.run.result import RunResult

#: Standard diagnostic fields every paper controller logs first (in the ``controller`` figure).
STANDARD_DIAG = ("ctrl_att_err", "ctrl_q_err", "ctrl_pos_err", "ctrl_rate_err", "ctrl_vel_err")
#: The fields (names or glob patterns) each figure reads, heaviest figure first (the order the
#: figures are handed to the workers).
FIGURE_FIELDS: dict[str, tuple[str, ...]] = {
    "diagnostics": ("ctrl_*",),
    "controller": (*STANDARD_DIAG, "cmd_*"),
    "actuators": ("env_wheel_speed", "wheel_applied", "wheel_cmd", "env_tau_applied", "env_F_applied"),
    "attitude": ("meas_q_e", "meas_w_e"),
    "translation": ("r", "v"),
    "thrusters": ("thr_on", "thr_duty", "m_prop"),
    "constraints": ("env_beta_fov", "env_beta_ca"),
}
#: The figures in reading order (``run.json`` lists them so; :data:`rpo.runtime.outputs.plots.FIGURES`).
FIGURE_ORDER = ("attitude", "translation", "actuators", "thrusters", "controller", "constraints", "diagnostics")
FIGURE_CHANNELS = tuple(dict.fromkeys(p for ps in FIGURE_FIELDS.values() for p in ps))


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
    limits: dict[str, float] = field(default_factory=dict)  # wheel_speed_max, wheel_torque_max (SI)
    goal: np.ndarray | None = None
    faults: list[tuple[float, str]] = field(default_factory=list)  # (start time, label) of each fault

    @classmethod
    def from_result(cls, result: RunResult, model: Any, params: dict | None = None, gains: dict | None = None,
                    title: str = "") -> PlotData:
        """The figures' columns of ``result`` (full in-memory rate) and the run facts."""
        ctrl = result.meta.get("controller", "baseline")
        z_lay = list(model.layouts.get(f"z_{ctrl}", []))
        y_lay = list(model.layouts.get(f"y_{ctrl}", []))
        sel = select(FIGURE_CHANNELS, z_lay, y_lay, strict=False)
        zi = {lbl: i for i, lbl in enumerate(result.z_labels)}
        yi = {lbl: i for i, lbl in enumerate(result.y_labels)}
        cols = {lbl: np.ascontiguousarray(result.z[:, zi[lbl]]) for lbl in sel.z if lbl in zi}
        cols.update({lbl: np.ascontiguousarray(result.y[:, yi[lbl]]) for lbl in sel.y if lbl in yi})
        limits = {}
        for name in ("wheel_speed_max", "wheel_torque_max"):
            v = (params or {}).get(name)
            if v is not None:
                limits[name] = float(np.ravel(v)[0])
        goal = None if not gains or "r_goal" not in gains else np.ravel(np.asarray(gains["r_goal"], float))
        div = result.divergence
        return cls(t=np.asarray(result.t), dt=float(result.dt), columns=cols, z_layout=z_lay, y_layout=y_lay,
                   controller=ctrl, record_every=int(result.meta.get("record_every", 1)),
                   divergence=None if div is None else (float(div.time), str(div.label)),
                   title=title or ctrl, limits=limits, goal=goal,
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
