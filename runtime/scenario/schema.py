"""The scenario schema: pydantic sections, half written here and half derived from the manifest.

Written here are the keys that are not model parameters: ``[meta]``, the run settings of
``[simulation]`` (duration, seed, controller, record_every), ``orbit.perigee_altitude`` (an
alternative to the semi-major axis), the initial state of ``[chaser]``, ``[target]`` and
``[relative]``, the gains tables ``[controller.<name>]`` (checked against the manifest's gains
layouts), ``[reproduction]`` and ``[output]`` (its channels checked against the layouts of the
controller flown).  Every other key is a parameter of layout ``p`` whose key, kind,
unit, scale and bounds the manifest records (:mod:`.params`): :func:`scenario_model` adds them
to these sections, or makes new sections for them, so a parameter added or re-bounded in
``symbolic/physics/plant.py`` is validated here after ``python build.py`` with no edit of ``runtime/``.
"""

from __future__ import annotations

import copy
import json
import math
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
from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, DEFAULT_FORMATS, FIGURE_FORMAT_NAMES, FORMAT_NAMES
from rpo.runtime.scenario.faults import Fault, FaultConflict, fault_params, fault_value_unit
from rpo.runtime.scenario.messages import field_error, first_error, unknown_key
from rpo.runtime.scenario.params import (
    Interval,
    ScenarioParam,
    _cached,
    finite,
    frozen_cache,
    layout_fields,
    manifest_defaults,
    param,
    scenario_params,
)
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


class OutputSection(_Section):
    """``[output]``: what a run writes (:mod:`rpo.runtime.scenario.channels`, :mod:`rpo.runtime.outputs.writers`).

    ``channels``: field names, column labels or glob patterns over the layouts ``z_<controller>``
    and ``y_<controller>`` (omitted: :data:`rpo.runtime.scenario.channels.DEFAULT_CHANNELS`; ``"default"``
    inside the list stands for that set).  ``every`` (steps of 1 / rate) or ``rate_hz``: the
    written rows, a multiple of ``simulation.record_every`` (omitted: every recorded row).  The
    metrics are always computed from the full in-memory record, never from the written rows.
    ``formats`` and ``figure_format``: the names of :mod:`rpo.runtime.formats`.
    """

    channels: Annotated[list[str], Field(min_length=1)] | None = None
    every: Annotated[int, _range(1, what="an integer")] | None = None
    rate_hz: Annotated[float, _range(0, lo_open=True, unit="Hz")] | None = None
    formats: Annotated[list[Literal[FORMAT_NAMES]], Field(min_length=1)] = list(DEFAULT_FORMATS)  # type: ignore[valid-type]
    figures: bool = True
    figure_format: Literal[FIGURE_FORMAT_NAMES] = DEFAULT_FIGURE_FORMAT  # type: ignore[valid-type]

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
    """A validated scenario.  Build it with :func:`~rpo.runtime.scenario.load_scenario`; turn it
    into the inputs of a :class:`~rpo.runtime.run.simulate.Simulation` with :meth:`to_run`.

    The class validated is :func:`scenario_model` of the manifest, a subclass that adds the
    parameter keys; read those with :meth:`get` (``sc.get("orbit.eccentricity")``).
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
    _manifest: dict = PrivateAttr(default_factory=dict)
    _data: dict = PrivateAttr(default_factory=dict)
    _text: str | None = PrivateAttr(default=None)
    _overrides: tuple[dict, dict] | None = PrivateAttr(default=None)

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
    def manifest(self) -> dict:
        return self._manifest

    @property
    def data(self) -> dict:
        """A copy of the table the scenario was validated from (``extends`` resolved)."""
        return copy.deepcopy(self._data)

    def param_overrides(self, manifest: dict | None = None) -> dict[str, Any]:
        """The parameters this scenario sets, by p-field name, in SI (omitted ones are absent)."""
        manifest = manifest or self._manifest
        if frozen_cache(manifest) is not None:  # an unchanging manifest (a campaign): once per scenario
            hit = self._overrides
            if hit is not None and hit[0] is manifest:
                return dict(hit[1])
            out = self._param_overrides(manifest)
            self._overrides = (manifest, out)
            return dict(out)
        return self._param_overrides(manifest)

    def _param_overrides(self, manifest: dict) -> dict[str, Any]:
        out: dict[str, Any] = {}
        sections: dict[str, Any] = {}  # the ~80 keys sit in a few tables: each table looked up once
        for table, leaf, prm in _param_paths(manifest):
            if table not in sections:
                sections[table] = self.get(table) if table else self
            node = sections[table]
            v = None if node is None else getattr(node, leaf, None)  # = self.get(prm.key)
            if v is not None:
                out[prm.name] = prm.to_si(v)
        if self.orbit.perigee_altitude is not None:
            d = manifest_defaults(manifest, "p", copy=False)
            e = out.get("orbit_e", float(d["orbit_e"][0]))
            r_e = out.get("r_earth", float(d["r_earth"][0]))
            out["orbit_a"] = (r_e + self.orbit.perigee_altitude) / (1.0 - e)  # perigee radius = a (1 - e)
        if self.faults:
            out.update(fault_params(self.faults, manifest_defaults(manifest, "p", copy=False)))
        return out

    def params(self, manifest: dict | None = None, copy: bool = True) -> dict[str, np.ndarray]:
        """Every parameter (defaults overridden by the scenario), by p-field name, SI.  ``copy=False``:
        the defaults' own read-only arrays where the scenario sets nothing (for a caller that copies
        or only reads them: :func:`~.initial_state.run_inputs`)."""
        manifest = manifest or self._manifest
        p = manifest_defaults(manifest, "p") if copy else dict(manifest_defaults(manifest, "p", copy=False))
        for k, v in self.param_overrides(manifest).items():
            p[k] = np.atleast_1d(np.asarray(v, float))
        return p

    def gains(self, manifest: dict | None = None) -> dict[str, np.ndarray]:
        """Gains of the selected controller (defaults overridden by ``[controller.<name>]``)."""
        manifest = manifest or self._manifest
        ctrl = self.simulation.controller
        g = manifest_defaults(manifest, manifest["controllers"][ctrl]["gains"])
        for k, v in self.controller.get(ctrl, {}).items():
            g[k] = _gain_array(v)
        return g

    def _gain(self, manifest: dict, name: str) -> np.ndarray | None:
        """``self.gains(manifest).get(name)``, without making the others (for reading only: a
        default is the manifest's own read-only array)."""
        ctrl = self.simulation.controller
        table = self.controller.get(ctrl, {})
        if name in table:
            return _gain_array(table[name])
        return manifest_defaults(manifest, manifest["controllers"][ctrl]["gains"], copy=False).get(name)

    # -- cross-field checks (need the manifest's defaults) ---------------------------------------

    @model_validator(mode="after")
    def _cross_checks(self, info: ValidationInfo):
        manifest = (info.context or {}).get("manifest")
        if manifest is None:
            from rpo.runtime.model.manifest import read_manifest
            manifest = read_manifest()
        self._manifest = manifest
        self._check_controller(manifest)

        def key(name: str) -> str:
            return param(manifest, name).key

        if self.orbit.perigee_altitude is not None and self.get(key("orbit_a")) is not None:
            raise field_error(key("orbit_a"), self.get(key("orbit_a")),
                              f"give either perigee_altitude or {key('orbit_a').rsplit('.', 1)[-1]}, not both")
        self._check_faults(manifest)
        p = _ParamValues(self.param_overrides(manifest), manifest_defaults(manifest, "p", copy=False))
        sim = self.simulation

        # orbit: the perigee must be above the surface
        r_p = p["orbit_a"] * (1 - p["orbit_e"])
        if not r_p > p["r_earth"]:
            where = next((k for k in (key("orbit_a"), key("orbit_e"), key("r_earth")) if self.get(k) is not None),
                         key("orbit_a"))
            raise field_error(where, self.get(where),
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
        slots = int(manifest.get("delay_slots", 4))
        if not p["wheel_delay"] < slots * dt:
            where = key("wheel_delay") if self.get(key("wheel_delay")) is not None else key("dt")
            raise field_error(where, self.get(where),
                              f"the wheel delay {p['wheel_delay']:g} s must be in [0, {slots * dt:g}) s: the model's "
                              f"delay line holds {slots} steps of 1 / rate = {dt:g} s")
        n_rows = int(round(sim.duration / dt)) // sim.record_every + 1
        ctrl = manifest["controllers"][sim.controller]["step"]
        width = sum(math.prod(o["shape"]) for o in manifest["functions"][ctrl]["outputs"])
        size = n_rows * width * 8
        if size > MAX_RECORD_BYTES:
            raise field_error("simulation.duration", sim.duration,
                              f"would record {n_rows} rows ({size / 1e9:.3g} GB, limit "
                              f"{MAX_RECORD_BYTES / 1e9:g} GB): raise simulation.record_every or shorten the run")

        self._check_output(manifest, dt)
        self._check_per_step(manifest, dt)

        # ideal actuators need their limits (the defaults are placeholders, not a paper's values)
        ideal, f_max, t_max = (param(manifest, n) for n in ("actuators_ideal", "force_max", "torque_max"))
        if p["actuators_ideal"] == 1.0 and (self.get(f_max.key) is None or self.get(t_max.key) is None):
            raise field_error(ideal.key, self.get(ideal.key),
                              f"ideal actuators need {f_max.key} [{f_max.unit}] and {t_max.key} [{t_max.unit}] "
                              "(per axis)")

        # thrusters: Schmitt trigger levels
        if not p["pwpf_uoff"] < p["pwpf_uon"]:
            on, off = key("pwpf_uon"), key("pwpf_uoff")
            where = off if self.get(off) is not None else on
            a, b = off.rsplit(".", 1)[-1], on.rsplit(".", 1)[-1]
            raise field_error(where, self.get(where),
                              f"must satisfy 0 < {a} < {b} ({a} = {p['pwpf_uoff']:g}, {b} = {p['pwpf_uon']:g})")
        return self

    def _check_faults(self, manifest: dict) -> None:
        """Faults the model can fly: one window per kind and unit; actuator faults need the
        wheels and thrusters (the ideal actuators of 001/002/004 have no units to fail)."""
        defaults = manifest_defaults(manifest, "p", copy=False)
        try:
            fault_params(self.faults, defaults)
        except FaultConflict as exc:
            raise field_error(f"faults[{exc.index}]", self.faults[exc.index].kind, exc.message) from None
        fields = layout_fields(manifest, "p")
        for n, f in enumerate(self.faults):  # the values against the ranges of the parameters they set
            for name, values in fault_params([f], defaults).items():
                entry, b = fields[name]
                if b is not None and not all(b.contains(v) for v in values):
                    where = "time" if name.endswith(("_start", "_end")) else "value"
                    scale, unit = fault_value_unit(f, entry["unit"]) if where == "value" else (1.0, "s")
                    shown = Interval(None if b.lo is None else b.lo / scale, None if b.hi is None else b.hi / scale,
                                     b.lo_open, b.hi_open)
                    raise field_error(f"faults[{n}].{where}", getattr(f, where),
                                      f"out of range for {f.kind} of {f.unit_name()}: must be {shown.text(unit)}")
        ideal = self.param_overrides(manifest).get("actuators_ideal",
                                                   manifest_defaults(manifest, "p", copy=False)["actuators_ideal"])
        if float(np.ravel(ideal)[0]) == 1.0:
            for n, f in enumerate(self.faults):
                if f.family != "sensor":
                    raise field_error(f"faults[{n}].kind", f.kind,
                                      "wheel and thruster faults need plant.actuators = \"wheels_thrusters\" (this "
                                      "scenario flies the ideal actuators, which have no units to fail; "
                                      "try --plant full)")

    def _check_controller(self, manifest: dict) -> None:
        ctrls = manifest["controllers"]
        if self.simulation.controller not in ctrls:
            raise field_error("simulation.controller", self.simulation.controller,
                              f"unknown controller; available: {', '.join(sorted(ctrls))}")
        for name, table in self.controller.items():
            if name not in ctrls:
                raise field_error(f"controller.{name}", table,
                                  f"unknown controller; available: {', '.join(sorted(ctrls))}")
            layout = layout_fields(manifest, ctrls[name]["gains"])
            for k, value in table.items():
                if k not in layout:
                    raise field_error(f"controller.{name}.{k}", value, unknown_key(k, list(layout)))
                entry, bounds = layout[k]
                path = f"controller.{name}.{k}"
                size, unit = entry["size"], entry["unit"]
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

    def _check_per_step(self, manifest: dict, dt: float) -> None:
        """The rates a fixed step must resolve (``per_step`` bounds: |value| * dt <= limit), for the
        parameters this scenario sets and the gains of the controller it flies."""
        rate = f"simulation.rate = {1.0 / dt:g} Hz"
        for prm in _per_step_params(manifest):  # the others have no such limit
            v = self.get(prm.key)
            limit = None if prm.bounds is None else prm.bounds.step_limit(dt)
            if v is None or limit is None or prm.bounds is None:
                continue
            si = np.abs(np.ravel(prm.to_si(v)))
            if si.max() > limit * (1 + 1e-12):
                raise field_error(prm.key, v, f"|value| must be <= {prm.bounds.per_step:g} / dt = "
                                              f"{limit / prm.scale:g} {prm.unit} at {rate} (the step must resolve it)")
        ctrl = self.simulation.controller
        fields = [(f, b) for f, b in layout_fields(manifest, manifest["controllers"][ctrl]["gains"]).values()
                  if b is not None and b.per_step is not None]
        for f, b in fields:
            limit = b.step_limit(dt)
            gain = None if limit is None else self._gain(manifest, f["name"])
            if limit is None or gain is None:
                continue
            g = np.abs(np.ravel(gain))
            if g.max() > limit * (1 + 1e-12):
                given = self.controller.get(ctrl, {}).get(f["name"])
                key = f"controller.{ctrl}.{f['name']}"
                raise field_error(key, given if given is not None else g.tolist(),
                                  f"|value| must be <= {b.per_step:g} / dt = {limit:g} {f['unit']} at {rate} "
                                  "(the step must resolve it)" + ("" if given is not None else "; this is the default"))

    def _check_output(self, manifest: dict, dt: float) -> None:
        from rpo.runtime.scenario.channels import ChannelError, select

        out, rec = self.output, self.simulation.record_every
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
        ctrl = self.simulation.controller
        z_name, y_name = f"z_{ctrl}", f"y_{ctrl}"
        layouts = manifest["layouts"]
        if out.channels is not None and z_name in layouts and y_name in layouts:
            try:
                select(out.channels, layouts[z_name], layouts[y_name], where=f"{z_name}/{y_name}")
            except ChannelError as exc:
                raise field_error(f"output.channels[{out.channels.index(exc.entry)}]", exc.entry, str(exc)) from None

    # -- to a run ----------------------------------------------------------------------------

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
            entry = self._manifest["controllers"].get(ctrl)
            sizes = {f["name"]: f["size"] for f in self._manifest["layouts"][entry["gains"]]} if entry else {}
            for k, v in gains.items():
                arr = np.ravel(np.asarray(v, float))
                # as a scenario would write it: a number for a one-entry gain, else an array
                table[k] = float(arr[0]) if sizes.get(k, arr.size) == 1 and arr.size == 1 else arr.tolist()
        if plant not in (None, "paper"):
            apply_preset(data, self._manifest, plant)
        sc = validate_scenario(data, f"{self._source} (with command-line overrides)", self._manifest)
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


class _ParamValues:
    """``p[name]``: a parameter of :meth:`Scenario.params` (the scenario's value, else the default)
    as a float when it has one entry, else its array; read on demand (the cross-field checks read a
    few of the ~200)."""

    def __init__(self, overrides: dict[str, Any], defaults: dict[str, np.ndarray]):
        self._overrides, self._defaults = overrides, defaults

    def __getitem__(self, name: str) -> Any:
        v = np.atleast_1d(np.asarray(self._overrides[name] if name in self._overrides else self._defaults[name], float))
        return float(v[0]) if v.size == 1 else v


def _param_paths(manifest: dict) -> list[tuple[str, str, ScenarioParam]]:
    """(table, leaf, parameter) of every scenario parameter, in layout order: ``chaser.mass`` ->
    ("chaser", "mass", ...) (once per unchanging manifest)."""
    def path(prm: ScenarioParam) -> tuple[str, str, ScenarioParam]:
        table, _, leaf = prm.key.rpartition(".")
        return table, leaf, prm

    return _cached(manifest, ("param_paths", "p"), lambda: [path(prm) for prm in scenario_params(manifest)])


def _per_step_params(manifest: dict) -> list[ScenarioParam]:
    """The parameters with a ``per_step`` bound, in layout order (once per unchanging manifest)."""
    return _cached(manifest, ("per_step", "p"), lambda: [
        prm for prm in scenario_params(manifest) if prm.bounds is not None and prm.bounds.per_step is not None])


def apply_preset(data: dict, manifest: dict, preset: str) -> None:
    """Set, in a scenario table, every parameter of the manifest's ``preset`` (in place)."""
    members = [prm for prm in scenario_params(manifest) if preset in prm.presets]
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


# --------------------------------------------------------------------------- derived model

_MODELS: dict[str, type[Scenario]] = {}


def scenario_model(manifest: dict) -> type[Scenario]:
    """:class:`Scenario` with the manifest's parameter keys added (cached per parameter schema)."""
    fields = manifest["layouts"]["p"]
    frozen = frozen_cache(manifest)
    if frozen is not None and "scenario_model" in frozen:  # an unchanging manifest: not serialised again
        return cast(type[Scenario], frozen["scenario_model"])
    params = scenario_params(manifest)
    cache_key = json.dumps([f for f in fields if "scenario" in f], sort_keys=True)
    if cache_key in _MODELS:
        if frozen is not None:
            frozen["scenario_model"] = _MODELS[cache_key]
        return _MODELS[cache_key]
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
    cls = cast(type[Scenario], _build("Scenario", tree, Scenario))
    _MODELS[cache_key] = cls
    if frozen is not None:
        frozen["scenario_model"] = cls
    return cls


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


def validate_scenario(data: dict, source: str = "scenario", manifest: dict | None = None, *,
                      own: bool = False) -> Scenario:
    """Validate a parsed scenario table; raises :class:`ScenarioError` with a one-line message.
    ``own``: the caller hands ``data`` over (it will not change it), so it is kept without a copy."""
    if manifest is None:
        from rpo.runtime.model.manifest import read_manifest
        manifest = read_manifest()
    cls = scenario_model(manifest)
    try:
        sc = cls.model_validate(data, context={"manifest": manifest})
    except ValidationError as exc:
        raise ScenarioError(first_error(exc.errors(include_url=False), source, cls)) from None
    sc._source = source
    sc._manifest = manifest
    sc._data = data if own else copy.deepcopy(data)
    return sc
