"""``rpo pil``: a scenario flown with the exported controller in the loop, compared with the simulation.

The reference is the simulation's own run of the same scenario (every step recorded).  The double-
precision package must give it bit for bit (``max_abs_diff`` 0 over every state and output); the
single-precision package is judged by how far its closed loop strays (:func:`single_error`) and by
whether it reaches what the double-precision loop reaches (the verdict's status).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rpo.runtime.errors import ModelError, ScenarioError
from rpo.runtime.flight.lockstep import LockstepStats, compare, fly
from rpo.runtime.run.result import RunResult

#: the single-precision closed loop's bound: the largest position deviation from the double-precision
#: run, relative to the run's largest distance (measured by benchmarks/bench_export.py on the M4F: 2.3e-4
#: at most, c000's chattering sliding mode on 000 scenario I; 2e-4 for c001 over the whole 001 scenario on
#: the host; 1.3e-7 or less for the others), so 1e-3 leaves a factor 4
SINGLE_RUN_BOUND = 1e-3


#: the memory the two recorded runs of ``rpo pil`` may take [bytes]
MAX_RECORD_BYTES = 4e9


def single_error(ref: RunResult, run: RunResult) -> dict[str, float]:
    """How far a run strays from the reference: the largest position deviation relative to the largest
    distance (``position_rel``), the largest attitude deviation (``attitude_rad``, angle between the
    chasers' attitudes) and the commands' deviation relative to each command's scale (median and
    99th percentile over the steps of the worst component; sliding-mode laws chatter, so the
    maximum says little)."""
    n = min(ref.z.shape[0], run.z.shape[0])
    r_cols = [ref.z_labels.index(f"r_{a}") for a in "xyz"]
    q_cols = [ref.z_labels.index(f"q_c_{a}") for a in "xyzw"]
    r_d, r_s = ref.z[:n, r_cols], run.z[:n, r_cols]
    pos = float(np.max(np.linalg.norm(r_s - r_d, axis=1)) / max(np.max(np.linalg.norm(r_d, axis=1)), 1e-300))
    dots = np.clip(np.abs(np.sum(ref.z[:n, q_cols] * run.z[:n, q_cols], axis=1)), 0.0, 1.0)
    att = float(np.max(2.0 * np.arccos(dots)))
    cmd = [i for i, lbl in enumerate(ref.y_labels) if lbl.startswith("cmd_")]
    scale = np.max(np.abs(ref.y[:n, cmd]), axis=0)
    scale[scale == 0] = 1.0
    worst = np.max(np.abs(run.y[:n, cmd] - ref.y[:n, cmd]) / scale, axis=1)
    return {"position_rel": pos, "attitude_rad": att, "command_rel_median": float(np.median(worst)),
            "command_rel_p99": float(np.quantile(worst, 0.99))}


@dataclass
class PilReport:
    """The outcome of one in-the-loop flight."""

    scenario: str
    controller: str
    precision: str
    where: str
    steps: int
    steps_reference: int
    comparison: dict[str, Any]
    verdict: str
    verdict_reference: str
    wall_s: float
    instructions: list[int] = field(default_factory=list)
    stack_bytes: list[int] = field(default_factory=list)
    single: dict[str, float] | None = None
    core: str = ""

    @property
    def passed(self) -> bool:
        if self.steps != self.steps_reference:
            return False
        if self.precision == "double":
            return bool(self.comparison["bit_identical"])
        assert self.single is not None
        return self.single["position_rel"] <= SINGLE_RUN_BOUND and self.verdict == self.verdict_reference

    def json(self) -> dict[str, Any]:
        ins = np.asarray(self.instructions, float)
        out: dict[str, Any] = {
            "scenario": self.scenario, "controller": self.controller, "precision": self.precision,
            "on": self.where, "core": self.core, "steps": self.steps, "passed": self.passed,
            "pil_max_abs_diff": self.comparison["max_abs_diff"], "bit_identical": self.comparison["bit_identical"],
            "verdict": self.verdict, "verdict_simulation": self.verdict_reference,
            "wall_s": round(self.wall_s, 3), "wall_us_per_step": round(1e6 * self.wall_s / max(self.steps, 1), 1)}
        if ins.size:
            out |= {"instructions_per_step_median": int(np.median(ins)), "instructions_per_step_max": int(ins.max())}
        if self.stack_bytes:
            out["stack_bytes_measured_max"] = int(max(self.stack_bytes))
        if self.single is not None:
            out |= {"pil_single_rel_err": self.single["position_rel"], "single_bound": SINGLE_RUN_BOUND,
                    **{f"single_{k}": v for k, v in self.single.items()}}
        return out

    def text(self) -> str:
        j = self.json()
        where = f"{self.where} ({self.core})" if self.core else self.where
        lines = [f"{self.controller} ({self.precision}) on {where}: {self.steps} steps of {self.scenario} in "
                 f"{self.wall_s:.1f} s ({j['wall_us_per_step']} us per step)"]
        if self.precision == "double":
            lines.append("equal to the simulation's run bit for bit (every state and output)"
                         if self.comparison["bit_identical"] else
                         f"DIFFERS from the simulation's run: max |difference| {self.comparison['max_abs_diff']:.3g}")
        else:
            s = self.single or {}
            lines.append(f"single precision: position deviation {s.get('position_rel', float('nan')):.3g} of the "
                         f"largest distance (bound {SINGLE_RUN_BOUND:g}), attitude deviation "
                         f"{s.get('attitude_rad', float('nan')):.3g} rad, commands {s.get('command_rel_median', 0):.3g}"
                         f" (median) / {s.get('command_rel_p99', 0):.3g} (99 %) of their scale")
        if "instructions_per_step_median" in j:
            lines.append(f"instructions per step: {j['instructions_per_step_median']} (median), "
                         f"{j['instructions_per_step_max']} (max)")
        if "stack_bytes_measured_max" in j:
            lines.append(f"stack used by a step (painted): {j['stack_bytes_measured_max']} bytes")
        lines.append(f"verdict: {self.verdict} (simulation: {self.verdict_reference})")
        lines.append("PASS" if self.passed else "FAIL")
        return "\n".join(lines)


def check_package_matches(folder: Path, controller: str, precision: str, manifest_hash: str) -> None:
    """Refuse, in one line, a package of another controller or precision, or one exported from another
    model than the one flown (a stale export would be compared with a plant it was not made for)."""
    from rpo.runtime.flight.host import package_info

    info = package_info(folder)
    if info.get("controller") != controller:
        raise ScenarioError(f"--package {folder} holds controller {info.get('controller')!r}, not {controller!r}")
    if info.get("precision") != precision:
        raise ScenarioError(f"--package {folder} is in {info.get('precision')} precision: give --precision "
                            f"{info.get('precision')}")
    if info.get("manifest_hash") != manifest_hash:
        raise ModelError(f"--package {folder} was exported from another model (manifest "
                         f"{str(info.get('manifest_hash'))[:12]}, now {manifest_hash[:12]}): export it again")


class TargetEndpoint:
    """The package on the emulated flight processor (:class:`~rpo.runtime.flight.target.PilTarget`) as a
    lockstep endpoint, keeping each step's instructions and stack bytes."""

    def __init__(self, folder: Path, log: Callable[[str], None] | None = None) -> None:
        from rpo.runtime.flight.target import PilTarget, build_firmware

        self.target = PilTarget(build_firmware(folder, log=log))
        self.core = self.target.core
        self.instructions: list[int] = []
        self.stack_bytes: list[int] = []

    def init(self, params: np.ndarray, start: np.ndarray | None = None) -> np.ndarray:
        state = self.target.init(params)
        return self.target.start(start) if start is not None else state

    def step(self, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = self.target.step(inputs)
        self.instructions.append(int(r.instructions))
        self.stack_bytes.append(int(r.stack_bytes))
        return r.outputs, r.state

    def __enter__(self) -> TargetEndpoint:
        return self

    def __exit__(self, *exc: object) -> None:
        self.target.close()


def fly_in_the_loop(scenario: str, controller: str, precision: str = "double", where: str = "qemu",
                    duration: float | None = None, package: Path | None = None,
                    log: Callable[[str], None] | None = None) -> PilReport:
    """Export ``controller`` (or use ``package``), fly ``scenario`` with it at ``where`` ("qemu" or
    "host") and compare with the simulation's run."""
    from rpo.runtime.flight.interface import controller_interface
    from rpo.runtime.flight.package import functions, write_package
    from rpo.runtime.jobs.api import scenario as load
    from rpo.runtime.jobs.runner import run_metrics
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.run.preflight import preflight

    sc = load(scenario, {"simulation.controller": controller})
    model = load_model(log=log if log is not None else False, controllers=[controller])
    pre = preflight(sc, model)
    sim = pre.sim
    dur = duration if duration is not None else pre.inputs.duration
    # both runs keep every step (the comparison is step by step): say so before asking for the memory
    steps = int(round(dur / sim.dt))
    need = 2 * (steps + 1) * (sim.nz + sim.ny + sim.nw) * 8
    if need > MAX_RECORD_BYTES:
        raise ScenarioError(f"--duration {dur:g} s is {steps} steps of {sim.dt:g} s; the simulation's run and the "
                            f"in-the-loop run, every step kept, would need {need / 1e9:.3g} GB (at most "
                            f"{MAX_RECORD_BYTES / 1e9:g}): give a shorter --duration")
    control, start = functions(model.manifest, controller)
    iface = controller_interface(model.manifest, controller, control, start)
    with tempfile.TemporaryDirectory(prefix="rpo-pil-") as tmp:
        folder = package
        if folder is not None:
            check_package_matches(folder, controller, precision, model.manifest.manifest_hash)
        else:
            folder = Path(tmp) / iface.prefix
            write_package(controller, folder, precision=precision, scenario=scenario, steps=1, log=log)
        ref = sim.run(pre.z0, dur, seed=pre.inputs.seed, record_every=1)
        stats = LockstepStats()
        if where == "host":
            from rpo.runtime.flight.host import HostController

            endpoint: Any = HostController(folder, log=log)
            core = ""
        else:
            endpoint = TargetEndpoint(folder, log=log)
            core = endpoint.core
        with endpoint:
            run = fly(iface, model, sim, pre.z0, dur, pre.inputs.seed, endpoint, stats=stats)
        instructions = list(getattr(endpoint, "instructions", []))
        stack = list(getattr(endpoint, "stack_bytes", []))
    if run.steps_done != ref.steps_done and run.divergence is None:
        raise ModelError(f"the in-the-loop run stopped after {run.steps_done} of {ref.steps_done} steps")
    verdict = run_metrics(run, pre.inputs, model)["verdict"]["status"]
    verdict_ref = run_metrics(ref, pre.inputs, model)["verdict"]["status"]
    return PilReport(scenario, controller, precision, where, run.steps_done, ref.steps_done, compare(ref, run),
                     verdict, verdict_ref, stats.wall_s, instructions, stack,
                     single_error(ref, run) if precision == "single" else None, core)
