"""The scenario's cross-field checks: what its sections cannot check alone, because it needs the
manifest's defaults, controllers and functions or several keys at once (the perigee above the surface,
whole steps, the wheel delay within the delay line, the record's size, the ``[output]`` rows and
channels, the rates a step must resolve, ideal actuators with their limits, the Schmitt trigger
levels, the faults, the gains tables and the goal: :func:`check_goal`).

:func:`cross_checks` runs once the sections are valid (:meth:`~.schema.Scenario._cross_checks`);
each refusal is a :func:`~.messages.field_error` on the key to change.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.model.manifest import Interval
from rpo.runtime.scenario import goals
from rpo.runtime.scenario.faults import FaultConflict, actuator_families, fault_params, fault_value_unit
from rpo.runtime.scenario.messages import field_error, unknown_key
from rpo.runtime.scenario.params import finite
from rpo.runtime.scenario.physical import check_physical

if TYPE_CHECKING:
    from rpo.runtime.scenario.schema import Scenario, ScenarioSchema

#: Largest time history a run may record (z and y, float64), so a typo cannot exhaust memory.
MAX_RECORD_BYTES = 2e9


class _ParamValues:
    """``p[name]``: a parameter of :meth:`Scenario.params` (the scenario's value, else the default)
    as a float when it has one entry, else its array; read on demand (the cross-field checks read a
    few of the ~200)."""

    def __init__(self, overrides: Mapping[str, Any], defaults: Mapping[str, np.ndarray]):
        self._overrides, self._defaults = overrides, defaults

    def __getitem__(self, name: str) -> Any:
        v = np.atleast_1d(np.asarray(self._overrides[name] if name in self._overrides else self._defaults[name], float))
        return float(v[0]) if v.size == 1 else v


def cross_checks(sc: Scenario, schema: ScenarioSchema, source: str = "scenario", goal_from: str | None = None,
                 carried: goals.Goal | None = None) -> goals.GoalFlown:
    """Every cross-field check of a scenario whose sections are valid, against ``schema``'s manifest;
    returns the goal flown (:func:`check_goal`: ``source``, ``goal_from``, ``carried``)."""
    manifest = schema.manifest
    check_controller(sc, schema)

    def key(name: str) -> str:
        return schema.param(name).key

    if sc.orbit.perigee_altitude is not None and sc.get(key("orbit_a")) is not None:
        raise field_error(key("orbit_a"), sc.get(key("orbit_a")),
                          f"give either perigee_altitude or {key('orbit_a').rsplit('.', 1)[-1]}, not both")
    check_faults(sc, schema)
    p = _ParamValues(sc.param_overrides(), schema.p_defaults)
    sim = sc.simulation

    # orbit: the perigee must be above the surface
    def orbit_key() -> str:  # the orbit key the scenario sets, named in a refusal of its orbit
        keys = ("orbit.perigee_altitude", key("orbit_a"), key("orbit_e"), key("r_earth"))
        return next((k for k in keys if sc.get(k) is not None), key("orbit_a"))

    r_p = p["orbit_a"] * (1 - p["orbit_e"])
    if not r_p > p["r_earth"]:
        where = orbit_key()
        raise field_error(where, sc.get(where),
                          f"perigee below the surface: perigee radius a (1 - e) = {r_p:.7g} m with "
                          f"a = {p['orbit_a']:.7g} m, e = {p['orbit_e']:g}; must be > R_E = {p['r_earth']:.7g} m")
    check_physical(sc, schema, p, orbit_key)  # a perigee in the atmosphere, bodies inside each other

    # time: at least one step; the wheel delay fits the delay line
    dt = p["dt"]
    if sim.duration < dt * (1 - 1e-9):
        raise field_error("simulation.duration", sim.duration,
                          f"must be at least one step (1 / rate = {dt:g} s)")
    steps = sim.duration / dt
    if abs(steps - round(steps)) > 1e-9 * max(1.0, steps):
        # a fixed-step run covers whole steps; rounding silently would misreport the end time
        raise field_error("simulation.duration", sim.duration,
                          f"must be a whole number of steps of 1 / rate = {dt:g} s")
    slots = manifest.delay_slots
    if not p["wheel_delay"] < slots * dt:
        where = key("wheel_delay") if sc.get(key("wheel_delay")) is not None else key("dt")
        raise field_error(where, sc.get(where),
                          f"the wheel delay {p['wheel_delay']:g} s must be in [0, {slots * dt:g}) s: the model's "
                          f"delay line holds {slots} steps of 1 / rate = {dt:g} s")
    n_rows = int(round(sim.duration / dt)) // sim.record_every + 1
    step = manifest.controllers[sim.controller].step
    width = sum(o.size for o in manifest.functions[step].outputs)
    size = n_rows * width * 8
    if size > MAX_RECORD_BYTES:
        raise field_error("simulation.duration", sim.duration,
                          f"would record {n_rows} rows ({size / 1e9:.3g} GB, limit "
                          f"{MAX_RECORD_BYTES / 1e9:g} GB): raise simulation.record_every or shorten the run")

    check_output(sc, schema, dt)
    check_per_step(sc, schema, dt)

    # ideal actuators need their limits (the defaults are placeholders, not a paper's values)
    ideal, f_max, t_max = (schema.param(n) for n in ("actuators_ideal", "force_max", "torque_max"))
    if p["actuators_ideal"] == 1.0 and (sc.get(f_max.key) is None or sc.get(t_max.key) is None):
        raise field_error(ideal.key, sc.get(ideal.key),
                          f"ideal actuators need {f_max.key} [{f_max.unit}] and {t_max.key} [{t_max.unit}] "
                          "(per axis)")

    # thrusters: Schmitt trigger levels
    if not p["pwpf_uoff"] < p["pwpf_uon"]:
        on, off = key("pwpf_uon"), key("pwpf_uoff")
        where = off if sc.get(off) is not None else on
        a, b = off.rsplit(".", 1)[-1], on.rsplit(".", 1)[-1]
        raise field_error(where, sc.get(where),
                          f"must satisfy 0 < {a} < {b} ({a} = {p['pwpf_uoff']:g}, {b} = {p['pwpf_uon']:g})")
    return check_goal(sc, schema, p, source, goal_from, carried)


def check_goal(sc: Scenario, schema: ScenarioSchema, p: _ParamValues, source: str, goal_from: str | None,
               carried: goals.Goal | None = None) -> goals.GoalFlown:
    """The scenario's goal (its ``[goal]`` table, else the goal gains of its controller, defaults
    included), with the camera on the target where ``camera_at_target`` asks it and outside the
    keep-out sphere unless ``contact`` (a goal stated by gains, as before ``[goal]`` existed, is
    flagged there, not refused), and the goal gains of the controller flown for it
    (:func:`~.goals.fly`; a gain its table sets must restate the goal).  ``goal_from`` names where
    the goal is stated when not in this table (``rpo run --controller``: the file's); ``carried``:
    the goal of the scenario overridden (:meth:`~.schema.Scenario.with_overrides`), when its
    ``[goal]`` table was made from a goal stated by gains."""
    ctrl = sc.simulation.controller
    table = sc.controller.get(ctrl, {})
    defaults = schema.manifest.layouts[schema.manifest.controllers[ctrl].gains].defaults

    def own(name: str) -> Any:  # the controller's own gain: its table's, else its default
        return table[name] if name in table else defaults[name]

    design = goals.DESIGNS.get(ctrl)
    if sc.goal is not None:
        g = sc.goal
        goal: goals.Goal | None = carried or goals.Goal(
            position=(g.position[0], g.position[1], g.position[2]), frame=g.frame,
            attitude=(g.attitude[0], g.attitude[1], g.attitude[2], g.attitude[3]), contact=g.contact,
            camera_at_target=g.camera_at_target, source=goal_from or f"{source} [goal]")
    elif design is not None:
        names = ", ".join(n if n in table else f"{n} (default)" for n in design.gains)
        goal = goals.derive(ctrl, own, goal_from or f"{source} [controller.{ctrl}] {names}")
    else:
        return goals.GoalFlown(ctrl, None, {}, mapped=False)
    assert goal is not None
    radii = [schema.param(n).key for n in ("chaser_radius", "target_radius")]
    keep_out = p["chaser_radius"] + p["target_radius"]
    dist = float(np.linalg.norm(goal.position))
    inside = "" if goal.contact or dist >= keep_out else \
        f"inside the keep-out sphere: |r| = {dist:.4g} m < {' + '.join(radii)} = {keep_out:.4g} m"
    if inside and goal.stated:
        raise field_error("goal.position", list(goal.position), f"the goal is {inside}; give a goal outside it, or "
                                                                "contact = true for a docking or capture goal")
    if goal.camera_at_target:
        if goal.frame != "target":
            raise field_error("goal.camera_at_target", True, 'needs frame = "target" (with a position fixed in LVLH, '
                                                             "where the camera points turns with the target)")
        angle = goals.camera_angle(goal.position, goal.attitude)
        if angle is None or angle > goals.CAMERA_TOL:
            off = "undefined at the target's centre" if angle is None else f"{np.degrees(angle):.4g} deg off"
            raise field_error("goal.attitude", list(goal.attitude),
                              f"camera_at_target = true: the camera (body +z) must point at the target's centre at "
                              f"the goal (within {np.degrees(goals.CAMERA_TOL):.2g} deg); it is {off}")
    warning = inside and f"the goal is {inside}"
    if sc.goal is None and design is not None:  # stated by this controller's own goal gains: flown as they are
        return goals.GoalFlown(ctrl, goal, {n: np.ravel(np.asarray(own(n), float)) for n in design.gains},
                               mapped=True, warning=warning)
    try:
        mapped = goals.fly(goal, ctrl, own)
    except goals.GoalRefusal as exc:
        raise field_error("simulation.controller", ctrl,
                          f"{ctrl} cannot fly the scenario's goal ({goal.text()}): {exc}") from None
    for name, v in mapped.items():
        if name in table and not goals.same_gain(name, table[name], v):
            raise field_error(f"controller.{ctrl}.{name}", table[name],
                              f"differs from the scenario's goal ({goal.text()}): a scenario states its goal once; "
                              "remove this gain or make it equal")
    return goals.GoalFlown(ctrl, goal, {n: np.ravel(np.asarray(own(n) if n in table else v, float))
                                        for n, v in mapped.items()}, mapped=design is not None, warning=warning)


def check_faults(sc: Scenario, schema: ScenarioSchema) -> None:
    """Faults the model can fly: one window per kind and unit; actuator faults need the
    wheels and thrusters (the ideal actuators of 001/002/004 have no units to fail)."""
    defaults = schema.p_defaults
    try:
        fault_params(sc.faults, defaults)
    except FaultConflict as exc:
        raise field_error(f"faults[{exc.index}]", sc.faults[exc.index].kind, exc.message) from None
    fields = schema.manifest.layouts["p"]
    for n, f in enumerate(sc.faults):  # the values against the ranges of the parameters they set
        for name, values in fault_params([f], defaults).items():
            entry = fields.field(name)
            b = entry.bounds
            if b is not None and not all(b.contains(v) for v in values):
                where = "time" if name in (f.spec.start, f.spec.end) else "value"
                scale, unit = fault_value_unit(f) if where == "value" else (1.0, "s")
                shown = Interval(None if b.lo is None else b.lo / scale, None if b.hi is None else b.hi / scale,
                                 b.lo_open, b.hi_open)
                raise field_error(f"faults[{n}].{where}", getattr(f, where),
                                  f"out of range for {f.kind} of {f.unit_name()}: must be {shown.text(unit)}")
    ideal = sc.param_overrides().get("actuators_ideal", defaults["actuators_ideal"])
    actuators = actuator_families(schema.manifest.faults)
    if float(np.ravel(ideal)[0]) == 1.0:
        for n, f in enumerate(sc.faults):
            if f.family in actuators:
                raise field_error(f"faults[{n}].kind", f.kind,
                                  " and ".join(a.noun for a in actuators) + " faults need plant.actuators = "
                                  "\"wheels_thrusters\" (this "
                                  "scenario flies the ideal actuators, which have no units to fail; "
                                  "try --plant full)")


def check_controller(sc: Scenario, schema: ScenarioSchema) -> None:
    """The controller flown exists; every ``[controller.<name>]`` table names a controller and its
    gains, each of the right size, finite and within its bounds."""
    manifest = schema.manifest
    ctrls = manifest.controllers
    if sc.simulation.controller not in ctrls:
        raise field_error("simulation.controller", sc.simulation.controller,
                          f"unknown controller; available: {', '.join(sorted(ctrls))}")
    for name, table in sc.controller.items():
        if name not in ctrls:
            raise field_error(f"controller.{name}", table,
                              f"unknown controller; available: {', '.join(sorted(ctrls))}")
        layout = manifest.layouts[ctrls[name].gains]
        for k, value in table.items():
            if k not in layout.by_name:
                raise field_error(f"controller.{name}.{k}", value, unknown_key(k, list(layout.names)))
            entry = layout.field(k)
            bounds = entry.bounds
            path = f"controller.{name}.{k}"
            size, unit = entry.size, entry.unit
            items = value if isinstance(value, list) else [value]
            numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in items)
            if (size == 1) == isinstance(value, list) or not numeric:
                want = "a number" if size == 1 else f"an array of {size} numbers"
                raise field_error(path, value, f"must be {want} ({unit})")
            if len(items) != size:
                raise field_error(path, value, f"must have {size} values, got {len(items)}")
            if not finite(items):
                rng = f" {bounds.text(unit)}" if bounds is not None else f" ({unit})"
                raise field_error(path, value, f"must be {'a finite number' if size == 1 else 'finite numbers'}"
                                               f"{rng}")
            bad = [float(x) for x in items if bounds is not None and not bounds.contains(float(x))]
            if bounds is not None and bad:
                raise field_error(path, value, bounds.refusal(bad[0], unit))


def check_per_step(sc: Scenario, schema: ScenarioSchema, dt: float) -> None:
    """The rates a fixed step must resolve (``per_step`` bounds: |value| * dt <= limit), for the
    parameters this scenario sets and the gains of the controller it flies."""
    rate = f"simulation.rate = {1.0 / dt:g} Hz"
    for prm in schema.per_step:  # the others have no such limit
        v = sc.get(prm.key)
        limit = None if prm.bounds is None else prm.bounds.step_limit(dt)
        if v is None or limit is None or prm.bounds is None:
            continue
        si = np.abs(np.ravel(prm.to_si(v)))
        if si.max() > limit * (1 + 1e-12):
            raise field_error(prm.key, v, f"|value| must be <= {prm.bounds.per_step:g} / dt = "
                                          f"{limit / prm.scale:g} {prm.unit} at {rate} (the step must resolve it)")
    ctrl = sc.simulation.controller
    layout = schema.manifest.layouts[schema.manifest.controllers[ctrl].gains]
    for f in layout:
        b = f.bounds
        if b is None or b.per_step is None:
            continue
        limit = b.step_limit(dt)
        gain = None if limit is None else sc.gain(f.name)
        if limit is None or gain is None:
            continue
        g = np.abs(np.ravel(gain))
        if g.max() > limit * (1 + 1e-12):
            given = sc.controller.get(ctrl, {}).get(f.name)
            key = f"controller.{ctrl}.{f.name}"
            raise field_error(key, given if given is not None else g.tolist(),
                              f"|value| must be <= {b.per_step:g} / dt = {limit:g} {f.unit} at {rate} "
                              "(the step must resolve it)" + ("" if given is not None else "; this is the default"))


def check_output(sc: Scenario, schema: ScenarioSchema, dt: float) -> None:
    """``[output]``: the written rows a whole number of steps and a multiple of the record; the channels
    among the columns of the controller flown."""
    from rpo.runtime.scenario.channels import ChannelError, select

    out, rec = sc.output, sc.simulation.record_every
    if out.rate_hz is not None:
        n = 1.0 / (out.rate_hz * dt)
        if not (abs(n - round(n)) <= 1e-9 * max(1.0, n) and round(n) >= 1):
            step_hz = 1.0 / dt
            ok = [step_hz / (rec * m) for m in (1, 2, 5, 10, 20, 100)]
            raise field_error("output.rate_hz", out.rate_hz,
                              f"must divide the step rate {step_hz:g} Hz by a whole number (allowed e.g. "
                              f"{', '.join(f'{x:g}' for x in ok)} Hz), or give output.every in steps")
    step = out.step(dt, rec)
    if step % rec:
        key = "output.every" if out.every is not None else "output.rate_hz"
        raise field_error(key, out.every if out.every is not None else out.rate_hz,
                          f"the written rows ({step} steps apart) must be a multiple of simulation.record_every "
                          f"= {rec} steps (the in-memory record)")
    ctrl = schema.manifest.controllers[sc.simulation.controller]
    layouts = schema.manifest.layouts
    if out.channels is not None and ctrl.z_layout in layouts and ctrl.y_layout in layouts:
        try:
            select(out.channels, layouts[ctrl.z_layout], layouts[ctrl.y_layout],
                   where=f"{ctrl.z_layout}/{ctrl.y_layout}")
        except ChannelError as exc:
            raise field_error(f"output.channels[{out.channels.index(exc.entry)}]", exc.entry, str(exc)) from None
