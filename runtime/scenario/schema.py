"""The scenario schema: pydantic sections, half written here and half derived from the manifest.

Written here are the keys that are not model parameters: ``[meta]``, the run settings of
``[simulation]`` (duration, seed, controller, record_every), ``orbit.perigee_altitude`` (an
alternative to the semi-major axis), the initial state of ``[chaser]``, ``[target]`` and
``[relative]``, the gains tables ``[controller.<name>]`` (checked against the manifest's gains
layouts), ``[reproduction]`` and ``[output]`` (its channels checked against the layouts of the
controller flown).  Every other key is a parameter of layout ``p`` whose key, kind, unit, scale and
bounds the manifest records (:mod:`.params`): a :class:`ScenarioSchema`, made once per typed manifest
(:meth:`ScenarioSchema.of`, kept with the manifest), adds them to these sections or makes new sections
for them, so a parameter added or re-bounded in ``symbolic/plant.py`` is validated here after
``python build.py`` with no edit of ``runtime/``.

Every function here takes the manifest explicitly; a :class:`Scenario` holds the one it was validated
against (:attr:`Scenario.manifest`).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, cast

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PlainValidator,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    WrapValidator,
    create_model,
    model_validator,
)
from pydantic_core import PydanticCustomError

from rpo.runtime.errors import ModelError, ScenarioError
from rpo.runtime.model.manifest import Interval, Manifest
from rpo.runtime.scenario.faults import Fault, FaultConflict, fault_params, fault_value_unit
from rpo.runtime.scenario.messages import field_error, first_error, unknown_key
from rpo.runtime.scenario.params import ScenarioParam, finite
from rpo.runtime.scenario.reproduction import Reproduction
from rpo.runtime.scenario.units import DEG

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.scenario.initial_state import RunInputs


#: Tolerance on |q| - 1 for a quaternion typed in a scenario (4 printed digits).
QUAT_TOL = 1e-3
#: Largest time history a run may record (z and y, float64), so a typo cannot exhaust memory.
MAX_RECORD_BYTES = 2e9


# --------------------------------------------------------------------------- value types


def _range(lo: float, lo_open: bool = False, unit: str = "", what: str = "a number") -> WrapValidator:
    """A lower bound on a key that is not a manifest parameter; a wrong type, nan or inf is told the
    bound too (``must be a finite number > 0 s``)."""
    bound = f"{'>' if lo_open else '>='} {lo:g}" + (f" {unit}" if unit else "")

    def check(v, handler):
        if isinstance(v, float) and not math.isfinite(v):
            raise PydanticCustomError("range", f"must be a finite number {bound}")
        try:
            v = handler(v)
        except ValidationError:
            raise PydanticCustomError("range", f"must be {what} {bound}") from None
        if v <= lo if lo_open else v < lo:
            raise PydanticCustomError("range", f"must be {bound}")
        return v

    return WrapValidator(check)


Vec3 = Annotated[list[float], Field(min_length=3, max_length=3)]
Vec4 = Annotated[list[float], Field(min_length=4, max_length=4)]
Frame = Literal["eci", "lvlh", "orbit"]


def _unit_quaternion(q: list[float]) -> list[float]:
    n = math.sqrt(sum(c * c for c in q))
    if not abs(n - 1.0) <= QUAT_TOL:
        raise PydanticCustomError(
            "quaternion", f"must be a unit quaternion [x, y, z, w] (|q| = {n:.6g}; allowed ||q| - 1| <= {QUAT_TOL:g})")
    return [c / n for c in q]


Quaternion = Annotated[Vec4, AfterValidator(_unit_quaternion)]


def _physical_inertia(rows: list[list[float]]) -> list[list[float]]:
    return _physical_tensor(rows)[0]


def _physical_tensor(rows: list[list[float]]) -> tuple[list[list[float]], np.ndarray]:
    """A physical inertia tensor [kg m^2] (symmetric, positive definite, the triangle inequality of
    its principal moments) as nested lists, and the principal moments of the tensor as given
    (``np.linalg.eigvalsh`` of it, ascending: the parameter bounds check those)."""
    I = np.array(rows, dtype=float)
    scale = float(np.max(np.abs(I))) or 1.0
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if abs(I[i, j] - I[j, i]) > 1e-9 * scale:
            raise PydanticCustomError(
                "inertia", f"must be symmetric (row {i} column {j} is {I[i, j]:g}, row {j} column {i} is {I[j, i]:g})")
    sym = 0.5 * (I + I.T)
    lam = np.linalg.eigvalsh(sym)
    shown = ", ".join(f"{x:.6g}" for x in lam)
    if lam[0] <= 0:
        raise PydanticCustomError(
            "inertia", f"must be positive definite (principal moments {shown} kg m^2; all must be > 0)")
    if lam[0] + lam[1] < lam[2] * (1 - 1e-9):
        raise PydanticCustomError(
            "inertia", f"principal moments {shown} kg m^2 violate the triangle inequality I1 + I2 >= I3 "
                       "(not a physical body)")
    # an exactly symmetric tensor (every drawn one) is its own symmetric part: the same matrix,
    # the same moments, not decomposed twice
    moments = lam if sym.tobytes() == I.tobytes() else np.linalg.eigvalsh(I)
    return cast(list[list[float]], I.tolist()), moments


Inertia = Annotated[list[Vec3], Field(min_length=3, max_length=3), AfterValidator(_physical_inertia)]


def _inertia_check(prm: ScenarioParam):
    """An inertia parameter: a physical tensor (:func:`_physical_inertia`) whose principal moments
    are within the parameter's bounds."""
    iv = prm.bounds
    rng = f", principal moments {iv.text(prm.unit)}" if iv is not None else ""

    def check(v):
        rows = v if isinstance(v, list) and len(v) == 3 else None
        if rows is None or not all(isinstance(r, list) and len(r) == 3 and all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in r) for r in rows):
            raise PydanticCustomError("inertia", f"must be a symmetric 3x3 array of numbers ({prm.unit}){rng}")
        if not all(math.isfinite(float(x)) for r in rows for x in r):
            raise PydanticCustomError("inertia", f"must be finite numbers ({prm.unit}){rng}")
        tensor, moments = _physical_tensor([[float(x) for x in r] for r in rows])
        msg = prm.check_moments(moments.tolist())
        if msg is not None:
            raise PydanticCustomError("inertia", msg)
        return tensor

    return PlainValidator(check)


def param_type(prm: ScenarioParam) -> Any:
    """The pydantic type of the scenario value of a manifest parameter: its kind, finite, within its
    bounds (:meth:`ScenarioParam.check`: one message with the allowed values for every refusal)."""
    if prm.kind == "switch":
        return bool
    if prm.kind == "choice":
        return Literal[tuple(prm.choices)]  # type: ignore[valid-type]
    if prm.kind == "inertia":
        return Annotated[Any, _inertia_check(prm)]

    def check(v):
        msg = prm.check(v)
        if msg is not None:
            raise PydanticCustomError("range", msg)
        return v

    return Annotated[Any, PlainValidator(check)]


# --------------------------------------------------------------------------- static sections


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


class Meta(_Section):
    name: str | None = None
    description: str = ""
    source: str = ""


class SimulationSection(_Section):
    duration: Annotated[float, _range(0, lo_open=True, unit="s")]
    seed: Annotated[int, _range(0, what="an integer"), Field(le=2**64 - 1)] = 0
    controller: str = "baseline"
    record_every: Annotated[int, _range(1, what="an integer")] = 1




#: File formats of the time histories (``[output] formats``; ``rpo run --format``).
FORMATS = ("parquet", "mat", "csv", "npz")
#: Figure file formats (``[output] figure_format``; ``rpo run --figure-format``).
FIGURE_FORMATS = ("png", "svg", "pdf")


class OutputSection(_Section):
    """``[output]``: what a run writes (:mod:`rpo.runtime.scenario.channels`, :mod:`rpo.runtime.outputs.writers`).

    ``channels``: field names, column labels or glob patterns over the layouts ``z_<controller>``
    and ``y_<controller>`` (omitted: :data:`rpo.runtime.scenario.channels.DEFAULT_CHANNELS`; ``"default"``
    inside the list stands for that set).  ``every`` (steps of 1 / rate) or ``rate_hz``: the
    written rows, a multiple of ``simulation.record_every`` (omitted: every recorded row).  The
    metrics are always computed from the full in-memory record, never from the written rows.
    """

    channels: Annotated[list[str], Field(min_length=1)] | None = None
    every: Annotated[int, _range(1, what="an integer")] | None = None
    rate_hz: Annotated[float, _range(0, lo_open=True, unit="Hz")] | None = None
    formats: Annotated[list[Literal[FORMATS]], Field(min_length=1)] = ["parquet"]  # type: ignore[valid-type]
    figures: bool = True
    figure_format: Literal[FIGURE_FORMATS] = "png"  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _one_rate(self):
        if self.every is not None and self.rate_hz is not None:
            raise field_error("rate_hz", self.rate_hz, "give either every (steps) or rate_hz, not both")
        if len(set(self.formats)) != len(self.formats):
            raise field_error("formats", self.formats, "lists a format twice")
        return self

    def step(self, dt: float, record_every: int) -> int:
        """The written rows' spacing in steps (``every``, or ``rate_hz`` converted; validated)."""
        if self.every is not None:
            return self.every
        if self.rate_hz is not None:
            return int(round(1.0 / (self.rate_hz * dt)))
        return record_every


class Orbit(_Section):
    #: alternative to the semi-major axis: a = (R_E + perigee_altitude) / (1 - e)
    perigee_altitude: Annotated[float, _range(0, True, "m (a lower perigee is below the surface)")] | None = None


class _Body(_Section):
    attitude_frame: Frame
    quaternion: Quaternion
    angular_velocity: Vec3 | None = None
    angular_velocity_deg_s: Vec3 | None = None
    angular_velocity_relative_to: Literal["eci", "attitude_frame"] = "eci"

    @model_validator(mode="after")
    def _one_rate(self):
        if self.angular_velocity is not None and self.angular_velocity_deg_s is not None:
            raise field_error("angular_velocity_deg_s", self.angular_velocity_deg_s,
                              "give either angular_velocity (rad/s) or angular_velocity_deg_s, not both")
        return self

    def rate_rad_s(self) -> np.ndarray:
        """Angular velocity as given (relative to ``angular_velocity_relative_to``), rad/s, body axes."""
        if self.angular_velocity is not None:
            return np.array(self.angular_velocity, float)
        if self.angular_velocity_deg_s is not None:
            return np.array(self.angular_velocity_deg_s, float) * DEG
        return np.zeros(3)


class Chaser(_Body):
    wheel_momentum: Vec4 | None = None
    wheel_speed_rpm: Vec4 | None = None

    @model_validator(mode="after")
    def _one_wheel_state(self):
        if self.wheel_momentum is not None and self.wheel_speed_rpm is not None:
            raise field_error("wheel_speed_rpm", self.wheel_speed_rpm,
                              "give either wheel_momentum (N m s) or wheel_speed_rpm, not both")
        return self


class Target(_Body):
    pass


class Relative(_Section):
    position: Vec3
    velocity: Vec3



# --------------------------------------------------------------------------- the scenario


class Scenario(_Section):
    """A validated scenario.  Build it with :func:`~rpo.runtime.scenario.load_scenario` or
    :func:`validate_scenario`; turn it into the inputs of a :class:`~rpo.runtime.run.simulate.Simulation`
    with :meth:`to_run`.

    The class validated is the :class:`ScenarioSchema`'s of the manifest, a subclass that adds the
    parameter keys; read those with :meth:`get` (``sc.get("orbit.eccentricity")``).  A validated
    scenario is not edited in place (:meth:`with_overrides` makes a re-validated copy).
    """

    meta: Meta = Field(default_factory=Meta)
    simulation: SimulationSection
    orbit: Orbit = Field(default_factory=Orbit)
    chaser: Chaser
    target: Target
    relative: Relative
    controller: dict[str, dict[str, Any]] = Field(default_factory=dict)
    reproduction: Reproduction | None = None
    output: OutputSection = Field(default_factory=OutputSection)
    faults: list[Fault] = Field(default_factory=list)

    _source: str = PrivateAttr(default="scenario")
    _schema: ScenarioSchema | None = PrivateAttr(default=None)
    _data: dict = PrivateAttr(default_factory=dict)
    _text: str | None = PrivateAttr(default=None)
    _overrides: dict[str, Any] | None = PrivateAttr(default=None)

    # -- lookups -----------------------------------------------------------------------------

    def get(self, path: str) -> Any:
        """Value at a dotted path (``"orbit.eccentricity"``), None when omitted."""
        obj: Any = self
        for part in path.split("."):
            obj = getattr(obj, part, None)
            if obj is None:
                return None
        return obj

    @property
    def scenario_schema(self) -> ScenarioSchema:
        """The schema this scenario was validated with (its manifest's)."""
        if self._schema is None:
            raise TypeError("a Scenario is made by validate_scenario(data, source, manifest) or load_scenario")
        return self._schema

    @property
    def manifest(self) -> Manifest:
        """The typed manifest this scenario was validated against."""
        return self.scenario_schema.manifest

    @property
    def data(self) -> dict:
        """A copy of the table the scenario was validated from (``extends`` resolved)."""
        return copy.deepcopy(self._data)

    def param_overrides(self) -> dict[str, Any]:
        """The parameters this scenario sets, by p-field name, in SI (omitted ones are absent; a new
        dict, made once per scenario)."""
        if self._overrides is None:
            self._overrides = self._param_overrides()
        return dict(self._overrides)

    def _param_overrides(self) -> dict[str, Any]:
        schema = self.scenario_schema
        out: dict[str, Any] = {}
        sections: dict[str, Any] = {}  # the ~80 keys sit in a few tables: each table looked up once
        for table, leaf, prm in schema.paths:
            if table not in sections:
                sections[table] = self.get(table) if table else self
            node = sections[table]
            v = None if node is None else getattr(node, leaf, None)  # = self.get(prm.key)
            if v is not None:
                out[prm.name] = prm.to_si(v)
        if self.orbit.perigee_altitude is not None:
            d = schema.p_defaults
            e = out.get("orbit_e", float(d["orbit_e"][0]))
            r_e = out.get("r_earth", float(d["r_earth"][0]))
            out["orbit_a"] = (r_e + self.orbit.perigee_altitude) / (1.0 - e)  # perigee radius = a (1 - e)
        if self.faults:
            out.update(fault_params(self.faults, schema.p_defaults))
        return out

    def params(self, copy: bool = True) -> dict[str, np.ndarray]:
        """Every parameter (defaults overridden by the scenario), by p-field name, SI.  ``copy=False``:
        the defaults' own read-only arrays where the scenario sets nothing (for a caller that copies
        or only reads them: :func:`~.initial_state.run_inputs`)."""
        d = self.scenario_schema.p_defaults
        p = {k: v.copy() for k, v in d.items()} if copy else dict(d)
        for k, v in self.param_overrides().items():
            p[k] = np.atleast_1d(np.asarray(v, float))
        return p

    def gains(self) -> dict[str, np.ndarray]:
        """Gains of the selected controller (defaults overridden by ``[controller.<name>]``)."""
        ctrl = self.simulation.controller
        g = {k: v.copy() for k, v in self._gain_defaults().items()}
        for k, v in self.controller.get(ctrl, {}).items():
            g[k] = _gain_array(v)
        return g

    def gain(self, name: str) -> np.ndarray | None:
        """``self.gains().get(name)``, without making the others (for reading only: a default is the
        manifest's own read-only array)."""
        table = self.controller.get(self.simulation.controller, {})
        if name in table:
            return _gain_array(table[name])
        return self._gain_defaults().get(name)

    def _gain_defaults(self) -> Mapping[str, np.ndarray]:
        manifest = self.manifest
        return manifest.layouts[manifest.controllers[self.simulation.controller].gains].defaults

    # -- cross-field checks (need the manifest's defaults) ---------------------------------------

    @model_validator(mode="after")
    def _cross_checks(self, info: ValidationInfo):
        schema = (info.context or {}).get("schema")
        if not isinstance(schema, ScenarioSchema):
            raise TypeError("validate a scenario with validate_scenario(data, source, manifest)")
        self._schema = schema
        cross_checks(self, schema)
        return self


    @property
    def source(self) -> str:
        return self._source

    @property
    def text(self) -> str | None:
        """The TOML text the scenario was read from (None if built from a table)."""
        return self._text

    @property
    def name(self) -> str:
        return self.meta.name or Path(self._source).stem

    def with_overrides(self, duration: float | None = None, seed: int | None = None,
                       controller: str | None = None, plant: str | None = None,
                       gains: dict[str, Any] | None = None, faults: list[dict[str, Any]] | None = None) -> Scenario:
        """A re-validated copy with ``simulation.duration`` / ``seed`` / ``controller`` replaced,
        ``gains`` (name -> value) merged into the selected controller's gains table and, with
        ``plant="full"``, the paper's plant replaced by the manifest's preset ``full``: every p
        field with a ``presets.full`` value is set to it (removed from the scenario where that
        value is the manifest default); ``faults`` (entries as in ``[[faults]]``) are added to the
        scenario's own."""
        if (duration is None and seed is None and controller is None and plant in (None, "paper") and not gains
                and not faults):
            return self
        data = copy.deepcopy(self._data)
        if faults:
            data["faults"] = [*data.get("faults", []), *copy.deepcopy(faults)]
        sim = data.setdefault("simulation", {})
        if duration is not None:
            sim["duration"] = duration
        if seed is not None:
            sim["seed"] = seed
        if controller is not None:
            sim["controller"] = controller
        if gains:
            ctrl = sim.get("controller", self.simulation.controller)
            table = data.setdefault("controller", {}).setdefault(ctrl, {})
            entry = self.manifest.controllers.get(ctrl)
            sizes = {f.name: f.size for f in self.manifest.layouts[entry.gains]} if entry else {}
            for k, v in gains.items():
                arr = np.ravel(np.asarray(v, float))
                # as a scenario would write it: a number for a one-entry gain, else an array
                table[k] = float(arr[0]) if sizes.get(k, arr.size) == 1 and arr.size == 1 else arr.tolist()
        if plant not in (None, "paper"):
            apply_preset(data, self.manifest, plant)
        sc = validate_scenario(data, f"{self._source} (with command-line overrides)", self.manifest)
        sc._text = self._text
        return sc

    def to_run(self, model: Model) -> RunInputs:
        """Inputs of :class:`~rpo.runtime.run.simulate.Simulation` for ``model`` (see
        :func:`~rpo.runtime.scenario.initial_state.run_inputs`)."""
        from rpo.runtime.scenario.initial_state import run_inputs
        return run_inputs(self, model)



def _gain_array(value: Any) -> np.ndarray:
    """A gain as a scenario's ``[controller.<name>]`` writes it (a number or an array), as an array."""
    return np.atleast_1d(np.asarray(value, float))



# --------------------------------------------------------------------------- cross-field checks


class _ParamValues:
    """``p[name]``: a parameter of :meth:`Scenario.params` (the scenario's value, else the default)
    as a float when it has one entry, else its array; read on demand (the cross-field checks read a
    few of the ~200)."""

    def __init__(self, overrides: Mapping[str, Any], defaults: Mapping[str, np.ndarray]):
        self._overrides, self._defaults = overrides, defaults

    def __getitem__(self, name: str) -> Any:
        v = np.atleast_1d(np.asarray(self._overrides[name] if name in self._overrides else self._defaults[name], float))
        return float(v[0]) if v.size == 1 else v


def cross_checks(sc: Scenario, schema: ScenarioSchema) -> None:
    """Every cross-field check of a scenario whose sections are valid, against ``schema``'s manifest."""
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
    r_p = p["orbit_a"] * (1 - p["orbit_e"])
    if not r_p > p["r_earth"]:
        where = next((k for k in (key("orbit_a"), key("orbit_e"), key("r_earth")) if sc.get(k) is not None),
                     key("orbit_a"))
        raise field_error(where, sc.get(where),
                          f"perigee below the surface: perigee radius a (1 - e) = {r_p:.7g} m with "
                          f"a = {p['orbit_a']:.7g} m, e = {p['orbit_e']:g}; must be > R_E = {p['r_earth']:.7g} m")

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
                where = "time" if name.endswith(("_start", "_end")) else "value"
                scale, unit = fault_value_unit(f, entry.unit) if where == "value" else (1.0, "s")
                shown = Interval(None if b.lo is None else b.lo / scale, None if b.hi is None else b.hi / scale,
                                 b.lo_open, b.hi_open)
                raise field_error(f"faults[{n}].{where}", getattr(f, where),
                                  f"out of range for {f.kind} of {f.unit_name()}: must be {shown.text(unit)}")
    ideal = sc.param_overrides().get("actuators_ideal", defaults["actuators_ideal"])
    if float(np.ravel(ideal)[0]) == 1.0:
        for n, f in enumerate(sc.faults):
            if f.family != "sensor":
                raise field_error(f"faults[{n}].kind", f.kind,
                                  "wheel and thruster faults need plant.actuators = \"wheels_thrusters\" (this "
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


# --------------------------------------------------------------------------- derived from the manifest


class ScenarioSchema:
    """What validating a scenario against one manifest needs, derived from it once: the parameters a
    scenario sets (:class:`~.params.ScenarioParam`, layout order), where each sits in the file, those
    with a per-step bound, the defaults of ``p`` and :attr:`model`, the :class:`Scenario` subclass
    with the parameters' keys.  Made by :meth:`of` (kept with the manifest: ``Manifest.derived``)."""

    def __init__(self, manifest: Manifest):
        self.manifest = manifest
        p = manifest.layouts["p"]
        #: every field of p that a scenario sets, in layout order
        self.params: tuple[ScenarioParam, ...] = tuple(ScenarioParam.from_field(f) for f in p if f.scenario)
        self._by_name = {prm.name: prm for prm in self.params}
        #: (table, leaf, parameter) of every parameter: ``chaser.mass`` -> ("chaser", "mass", ...)
        self.paths: tuple[tuple[str, str, ScenarioParam], ...] = tuple(
            (*prm.key.rpartition(".")[::2], prm) for prm in self.params)
        #: the parameters with a ``per_step`` bound
        self.per_step: tuple[ScenarioParam, ...] = tuple(
            prm for prm in self.params if prm.bounds is not None and prm.bounds.per_step is not None)
        #: the defaults of p (SI, read-only arrays)
        self.p_defaults: Mapping[str, np.ndarray] = p.defaults
        #: :class:`Scenario` with the parameters' keys added
        self.model: type[Scenario] = _derive_model(self.params)

    @classmethod
    def of(cls, manifest: Manifest) -> ScenarioSchema:
        """The schema of ``manifest`` (made on first use, then kept with it)."""
        return manifest.derived(cls)

    def param(self, name: str) -> ScenarioParam:
        """The scenario entry of p field ``name`` (for messages naming its key and unit)."""
        try:
            return self._by_name[name]
        except KeyError:
            raise KeyError(f"the manifest's layout p has no field {name} with a scenario key: run `python build.py`") \
                from None

    def validate(self, data: dict, source: str, *, own: bool = False) -> Scenario:
        """Validate a parsed scenario table; raises :class:`ScenarioError` with a one-line message.
        ``own``: the caller hands ``data`` over (it will not change it), so it is kept without a copy."""
        cls = self.model
        try:
            sc = cls.model_validate(data, context={"schema": self})
        except ValidationError as exc:
            raise ScenarioError(first_error(exc.errors(include_url=False), source, cls)) from None
        sc._source = source
        sc._data = data if own else copy.deepcopy(data)
        return sc


def scenario_params(manifest: Manifest) -> list[ScenarioParam]:
    """Every field of layout p that a scenario sets, in layout order (a new list; the entries are frozen)."""
    return list(ScenarioSchema.of(manifest).params)


def scenario_model(manifest: Manifest) -> type[Scenario]:
    """:class:`Scenario` with the manifest's parameter keys added (made once per manifest)."""
    return ScenarioSchema.of(manifest).model


def validate_scenario(data: dict, source: str, manifest: Manifest, *, own: bool = False) -> Scenario:
    """Validate a parsed scenario table against ``manifest``; raises :class:`ScenarioError` with a
    one-line message.  ``own``: the caller hands ``data`` over (it will not change it), so it is kept
    without a copy."""
    return ScenarioSchema.of(manifest).validate(data, source, own=own)


def apply_preset(data: dict, manifest: Manifest, preset: str) -> None:
    """Set, in a scenario table, every parameter of the manifest's ``preset`` (in place)."""
    members = [prm for prm in ScenarioSchema.of(manifest).params if preset in prm.presets]
    if not members:
        raise ScenarioError(f"the generated model has no parameter preset {preset!r}")
    for prm in members:
        *sections, leaf = prm.key.split(".")
        table = data
        for s in sections:
            table = table.setdefault(s, {})
        value = prm.presets[preset]
        if prm.default is not None and tuple(value) == tuple(prm.default):
            table.pop(leaf, None)
        else:
            table[leaf] = prm.to_scenario(value)


def _derive_model(params: tuple[ScenarioParam, ...]) -> type[Scenario]:
    """:class:`Scenario` with the parameters' keys added to its sections, or in new ones."""
    tree: dict[str, Any] = {}
    for prm in params:
        *sections, leaf = prm.key.split(".")
        if not sections:
            raise ModelError(f"manifest: parameter {prm.name}: scenario key {prm.key!r} is not in a table")
        node = tree
        for s in sections:
            node = node.setdefault(s, {})
            if not isinstance(node, dict):
                raise ModelError(f"manifest: scenario key {prm.key!r} is inside the key of another parameter")
        if leaf in node:
            raise ModelError(f"manifest: two parameters have the scenario key {prm.key!r}")
        node[leaf] = prm
    return cast(type[Scenario], _build("Scenario", tree, Scenario))


def _build(name: str, node: dict[str, Any], base: type[BaseModel]) -> type[BaseModel]:
    fields: dict[str, Any] = {}
    for k, v in node.items():
        existing = base.model_fields.get(k)
        if isinstance(v, ScenarioParam):
            if existing is not None:
                raise ModelError(f"manifest: scenario key {v.key!r} is also a key written in runtime/scenario")
            fields[k] = (param_type(v) | None, None)
            continue
        sub_base: Any = _Section
        if existing is not None:
            ann = existing.annotation
            if not (isinstance(ann, type) and issubclass(ann, _Section)):
                raise ModelError(f"manifest: scenario keys under {name}.{k} clash with a key of runtime/scenario")
            sub_base = ann
        sub = _build(f"{name}.{k}", v, sub_base)
        required = existing is not None and existing.is_required()
        fields[k] = (sub, ... if required else Field(default_factory=sub))
    return create_model(name, __base__=base, **fields)

