"""From a validated scenario to the inputs of a run: SI parameters, gains and the initial state.

Attitudes given relative to ``lvlh``/``orbit`` use the LVLH attitude ``q_IL`` and rate ``n`` of
the generated ``target_orbit`` function at t = 0, and wheel speeds become absolute momenta
through the generated ``env_outputs``: no orbit or actuator equation is retyped here.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime import frames
from rpo.runtime.errors import ModelError, ScenarioError
from rpo.runtime.scenario.units import RPM

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.scenario.schema import Scenario
    from rpo.runtime.scenario.sections import _Body


@dataclass
class RunInputs:
    """Everything a run needs, in SI: ``params`` (all p fields), ``gains``, the initial ``plant``
    state for :meth:`Simulation.initial_state` (attitudes relative to ECI, rates relative to ECI
    in body axes, r and v in LVLH, the target's ECI state r_T, v_T), the run settings, and ``goal``:
    the goal flown (:meth:`~rpo.runtime.scenario.goals.GoalFlown.record`: its ``text``, where the
    scenario states it, the controller's goal gains for it)."""

    params: dict[str, np.ndarray]
    gains: dict[str, np.ndarray]
    plant: dict[str, np.ndarray]
    duration: float
    seed: int
    controller: str
    record_every: int
    dt: float
    frame_info: dict[str, Any] = field(default_factory=dict)
    goal: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        """JSON-ready copy (arrays as lists, 1-element arrays as numbers)."""

        def conv(v: Any) -> Any:
            if isinstance(v, dict):
                return {k: conv(x) for k, x in v.items()}
            a = np.asarray(v)
            if a.dtype.kind == "f" or a.dtype.kind == "i":
                return a.item() if a.size == 1 else a.tolist()
            return v

        return {k: conv(v) for k, v in asdict(self).items()}


def run_inputs(sc: Scenario, model: Model) -> RunInputs:
    """Inputs of :class:`~rpo.runtime.run.simulate.Simulation` for ``model``: all parameters in SI,
    the gains, and the plant's initial state with attitudes relative to ECI."""
    return packed_run_inputs(sc, model)[0]


def packed_run_inputs(sc: Scenario, model: Model) -> tuple[RunInputs, np.ndarray]:
    """:func:`run_inputs` and its parameter vector ``model.vector("p", inputs.params)`` (packed on
    the way to the initial state; the pre-flight hands it to its Simulation instead of packing
    the same values again)."""
    params = sc.params(copy=False)  # read here; RunInputs gets copies
    gains = sc.gains()
    try:
        p = model.vector("p", params)
        # what the run will call, compiled together (one compile on every core, not one per call)
        ctrl = model.manifest.controllers.get(sc.simulation.controller)
        model.prepare(["target_orbit", "env_outputs", "measure", *((ctrl.step, ctrl.xc0 or "") if ctrl else ())], p)
        orbit = model.functions["target_orbit"](0.0, p)
    except KeyError as exc:
        raise ModelError(f"the generated model has no function {exc}: run `python build.py`") from exc
    _nu, _r, _r_dot, n_arr, _n_dot, _r_eci, _v_eci, q_IL_arr = orbit
    n = float(np.ravel(n_arr)[0])
    q_IL = np.ravel(q_IL_arr)
    if float(params["gravity_on"][0]) == 0.0:
        # free space: the frame of r, v ("lvlh") is fixed in ECI (symbolic/physics/plant.py reference_frame)
        n, q_IL = 0.0, np.array([0.0, 0.0, 0.0, 1.0])

    def body(b: _Body) -> tuple[np.ndarray, np.ndarray]:
        q_IB = frames.attitude_to_eci(b.quaternion, b.attitude_frame, q_IL)
        rel_frame = b.attitude_frame if b.angular_velocity_relative_to == "attitude_frame" else "eci"
        return q_IB, frames.body_rate_eci(b.rate_rad_s(), q_IB, rel_frame, q_IL, n)

    q_c, w_c = body(sc.chaser)
    q_t, w_t = body(sc.target)
    plant = {"q_c": q_c, "w_c": w_c, "q_t": q_t, "w_t": w_t,
             "r": np.array(sc.relative.position, float), "v": np.array(sc.relative.velocity, float)}
    if "r_T" in model.offsets("x"):
        # the target's own orbit (plant.target_orbit = "propagated") starts on the Keplerian orbit
        # of the elements at t = 0
        plant["r_T"], plant["v_T"] = np.ravel(_r_eci).copy(), np.ravel(_v_eci).copy()
    if sc.chaser.wheel_momentum is not None:
        plant["h_w"] = np.array(sc.chaser.wheel_momentum, float)
    else:
        speeds = np.array(sc.chaser.wheel_speed_rpm or [0.0] * 4, float) * RPM
        limit = float(params["wheel_speed_max"][0])
        if np.abs(speeds).max() > limit * (1 + 1e-12):
            key = sc.scenario_schema.param("wheel_speed_max")
            raise ScenarioError(f"{sc.source}: chaser.wheel_speed_rpm = {sc.chaser.wheel_speed_rpm}: each |speed| "
                                f"must be <= {key.key} = {key.to_scenario([limit]):g} {key.unit}")
        plant["h_w"] = _wheel_momentum(model, p, plant, speeds)
    sim = sc.simulation
    inputs = RunInputs(params={k: v.copy() for k, v in params.items()}, gains=gains, plant=plant,
                       duration=float(sim.duration), seed=int(sim.seed), controller=sim.controller,
                       record_every=int(sim.record_every), dt=float(params["dt"][0]),
                       frame_info={"q_IL0": q_IL, "n0": n}, goal=sc.goal_flown.record())
    return inputs, p


def _wheel_momentum(model: Model, p: np.ndarray, plant: dict[str, np.ndarray], speeds: np.ndarray) -> np.ndarray:
    """Absolute wheel momenta h_w [N m s] giving wheel ``speeds`` [rad/s] relative to the body.

    Uses the generated ``env_outputs`` (wheel speeds are affine in h_w with slope 1 / J_w):
    no actuator equation is retyped here; the result is checked by evaluating it again.
    """
    try:
        fn = model.functions["env_outputs"]
    except KeyError as exc:
        raise ModelError("the generated model has no function env_outputs: run `python build.py`") from exc
    offs = model.offsets("env")["wheel_speed"]
    J = float(p[model.offsets("p")["wheel_inertia"]][0])

    def omega(h: np.ndarray) -> np.ndarray:
        x = model.vector("x", {**plant, "h_w": h, "m_prop": 0.0})
        u = np.zeros(model.layout_size("u"))
        w = np.zeros(model.layout_size("w"))
        return np.asarray(np.ravel(fn(x, u, 0.0, p, w)[0])[offs])

    h = J * (speeds - omega(np.zeros(4)))
    check = omega(h)
    if not _close(check, speeds):
        raise ModelError(f"wheel speeds are not affine in h_w with slope 1/J_w (got {check}, wanted {speeds})")
    return np.asarray(h)


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.allclose(a, b, rtol=1e-9, atol=1e-9)``: its test on finite values (``|a - b| <= atol +
    rtol |b|``) first, np.allclose itself for the rest (nan, inf): the same answer, without
    np.allclose's ~10 us for the common case (a campaign checks every run's wheel momenta)."""
    finite = bool(np.isfinite(a).all() and np.isfinite(b).all())
    return (finite and bool(np.all(np.abs(a - b) <= 1e-9 + 1e-9 * np.abs(b)))) or \
        bool(np.allclose(a, b, rtol=1e-9, atol=1e-9))
