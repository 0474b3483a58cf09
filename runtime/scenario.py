"""Scenario files: a TOML description of one run, validated into the inputs of a simulation.

Every table and key is optional unless marked *required*; an omitted value falls back to the
default recorded in ``generated/manifest.json`` (``rpo info`` prints them), so no parameter is
typed twice.  Units are SI unless the key says otherwise (``_deg``, ``_deg_s``, ``_rpm``).
Unknown keys are errors.  Layout::

    [meta]                     # free text, recorded in run.json
    name = "..."               # default: the file's stem
    description = "..."
    source = "..."

    [simulation]               # required
    duration = 300.0           # required, s, > 0
    rate = 100.0               # Hz, > 0; step dt = 1 / rate            (p.dt)
    seed = 0                   # integer >= 0: random torques (000 eq. 5)
    controller = "baseline"    # a controller of the manifest
    record_every = 1           # integer >= 1: keep every n-th step

    [orbit]                    # the target's Keplerian orbit at t = 0
    perigee_altitude = 400e3   # m above R_E, > 0 ... or semi_major_axis (m); not both (p.orbit_a)
    eccentricity = 0.138       # [0, 1)                                   (p.orbit_e)
    inclination_deg = 55.0     # [0, 180]                                 (p.orbit_inc)
    raan_deg = 0.0             #                                          (p.orbit_raan)
    arg_perigee_deg = 270.0    #                                          (p.orbit_argp)
    true_anomaly_deg = 0.0     #                                          (p.orbit_nu0)

    [environment]
    gravity_gradient = true    # torques on/off                (p.gg_on)
    magnetic = true            #                               (p.mag_on)
    j2 = true                  # differential accelerations    (p.j2_on)
    drag = true                #                               (p.drag_on)
    random_torque_std_chaser = 0.3   # N m, >= 0 (000 eq. 5)      (p.chaser_rand_std)
    random_torque_std_target = 0.3   # N m, >= 0                  (p.target_rand_std)
    [environment.constants]    # mu, j2, r_earth, earth_flattening, omega_earth, mu_mag, g0
                               # (the p fields of the same name, SI)

    [chaser]                   # required
    mass = 100.0               # kg, > 0 (nominal m0 of the mass profile)   (p.chaser_mass)
    inertia = [[11, -0.09, -0.4], [-0.09, 14, -0.08], [-0.4, -0.08, 13]]  # kg m^2, symmetric,
                               # positive definite, triangle inequalities   (p.chaser_inertia)
    mass_profile = "seed000"   # "seed000" (000 Figs. 9-10) or "constant"  (p.mass_profile_on)
    dipole = [0, 0, 0]         # A m^2                                     (p.chaser_dipole)
    drag_area = 1.0            # m^2, > 0       drag_cd = 2.2   # > 0     (p.chaser_area, chaser_cd)
    attitude_frame = "orbit"   # required: "eci", "lvlh" or "orbit" (000's R: X along-track,
                               # Z nadir); see rpo.runtime.frames
    quaternion = [0, 0, 0, 1]  # required, [x, y, z, w] of the body relative to attitude_frame;
                               # |q| within 1e-3 of 1 (then normalised)
    angular_velocity_deg_s = [0, 0, 0]  # body axes, deg/s ... or angular_velocity (rad/s); default 0
    angular_velocity_relative_to = "eci"  # "eci" (default) or "attitude_frame": the frame's own
                               # rotation (n about the orbit normal) is then added
    wheel_speed_rpm = [0, 0, 0, 0]  # relative to the body (default: at rest) ... or
                               # wheel_momentum (N m s, absolute axial momenta h_w)

    [target]                   # required: mass, inertia, dipole, drag_area, drag_cd,
                               # attitude_frame, quaternion, angular velocity as for the chaser

    [relative]                 # required: the chaser relative to the target, LVLH
    position = [60, 0, 25]     # m
    velocity = [3, -0.5, 5]    # m/s (derivative in the rotating LVLH frame)

    [wheels]
    tilt_deg = 30.0            # (0, 90)                       (p.wheel_beta)
    inertia = 0.001364         # kg m^2, > 0                   (p.wheel_inertia)
    max_torque = 0.1           # N m, > 0                      (p.wheel_torque_max)
    max_speed_rpm = 7000.0     # > 0                           (p.wheel_speed_max)
    delay = 0.002              # s, 0 <= delay < 4 / rate (the model's delay line)  (p.wheel_delay)

    [thrusters]
    max_force = 1.0            # N, > 0                        (p.thruster_force)
    isp = 227.0                # s, > 0                        (p.thruster_isp)
    pwpf = { k_m = 10.0, t_m = 0.2, u_on = 0.25, u_off = 0.15 }  # k_m, t_m > 0; 0 < u_off < u_on

    [controller.baseline]      # gains by the names of the manifest layout k_baseline
    kp_att = 0.28              # (kp_att, kd_att, kp_pos, kd_pos, r_goal = [x, y, z] m LVLH)

Every error is reported as ONE line naming the file, the dotted key, the offending value and
the allowed range, e.g. ``scenario.toml: orbit.eccentricity = 1.2: must be in [0, 1)``, and
raised as :class:`~rpo.runtime.errors.ScenarioError`.
"""

from __future__ import annotations

import copy
import difflib
import json
import math
import tomllib
import typing
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    model_validator,
)
from pydantic_core import PydanticCustomError

from . import frames
from .errors import ModelError, ScenarioError

DEG = math.pi / 180.0
RPM = 2.0 * math.pi / 60.0
#: Tolerance on |q| - 1 for a quaternion typed in a scenario (4 printed digits).
QUAT_TOL = 1e-3
#: Largest time history a run may record (z and y, float64), so a typo cannot exhaust memory.
MAX_RECORD_BYTES = 2e9


# --------------------------------------------------------------------------- field types


def _interval(lo, hi, lo_open, hi_open, unit) -> str:
    u = f" {unit}" if unit else ""
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}{u}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}{u}"
    return f"{'<' if hi_open else '<='} {hi:g}{u}"


def _range(lo=None, hi=None, lo_open=False, hi_open=False, unit="") -> AfterValidator:
    text = "must be " + _interval(lo, hi, lo_open, hi_open, unit)

    def check(v):
        bad = ((lo is not None and (v <= lo if lo_open else v < lo))
               or (hi is not None and (v >= hi if hi_open else v > hi)))
        if bad:
            raise PydanticCustomError("range", text)
        return v

    return AfterValidator(check)


def Num(lo=None, hi=None, lo_open=False, hi_open=False, unit=""):
    """A finite float, optionally restricted to an interval (strict: ints accepted, strings not)."""
    if lo is None and hi is None:
        return float
    return Annotated[float, _range(lo, hi, lo_open, hi_open, unit)]


def Vec(n: int, item=float):
    """A TOML array of exactly n numbers."""
    return Annotated[list[item], Field(min_length=n, max_length=n)]


Positive = Num(0, lo_open=True)
NonNegative = Num(0)
Vec3 = Vec(3)
Vec4 = Vec(4)
Frame = Literal["eci", "lvlh", "orbit"]


def _unit_quaternion(q: list[float]) -> list[float]:
    n = math.sqrt(sum(c * c for c in q))
    if not abs(n - 1.0) <= QUAT_TOL:
        raise PydanticCustomError(
            "quaternion", f"must be a unit quaternion [x, y, z, w] (|q| = {n:.6g}; allowed ||q| - 1| <= {QUAT_TOL:g})")
    return [c / n for c in q]


Quaternion = Annotated[Vec4, AfterValidator(_unit_quaternion)]


def _physical_inertia(rows: list[list[float]]) -> list[list[float]]:
    I = np.array(rows, dtype=float)
    scale = float(np.max(np.abs(I))) or 1.0
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if abs(I[i, j] - I[j, i]) > 1e-9 * scale:
            raise PydanticCustomError(
                "inertia", f"must be symmetric (row {i} column {j} is {I[i, j]:g}, row {j} column {i} is {I[j, i]:g})")
    lam = np.linalg.eigvalsh(0.5 * (I + I.T))
    shown = ", ".join(f"{x:.6g}" for x in lam)
    if lam[0] <= 0:
        raise PydanticCustomError(
            "inertia", f"must be positive definite (principal moments {shown} kg m^2; all must be > 0)")
    if lam[0] + lam[1] < lam[2] * (1 - 1e-9):
        raise PydanticCustomError(
            "inertia", f"principal moments {shown} kg m^2 violate the triangle inequality I1 + I2 >= I3 "
                       "(not a physical body)")
    return I.tolist()


Inertia = Annotated[list[Vec3], Field(min_length=3, max_length=3), AfterValidator(_physical_inertia)]


def _field_error(field_name: str, value: Any, message: str) -> PydanticCustomError:
    """An error on ``field_name`` (dotted, relative to the model raising it) with its value."""
    return PydanticCustomError("scenario", message, {"field": field_name, "value": value})


# --------------------------------------------------------------------------- sections


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


class Meta(_Section):
    name: str | None = None
    description: str = ""
    source: str = ""


class SimulationSection(_Section):
    duration: Positive  # s
    rate: Positive | None = None  # Hz
    seed: Annotated[int, _range(0)] = 0
    controller: str = "baseline"
    record_every: Annotated[int, _range(1)] = 1


class Orbit(_Section):
    perigee_altitude: Num(0, lo_open=True, unit="m (a lower perigee is below the surface)") | None = None
    semi_major_axis: Positive | None = None
    eccentricity: Num(0, 1, hi_open=True) | None = None
    inclination_deg: Num(0, 180) | None = None
    raan_deg: float | None = None
    arg_perigee_deg: float | None = None
    true_anomaly_deg: float | None = None

    @model_validator(mode="after")
    def _one_size(self):
        if self.perigee_altitude is not None and self.semi_major_axis is not None:
            raise _field_error("semi_major_axis", self.semi_major_axis,
                               "give either perigee_altitude or semi_major_axis, not both")
        return self


class Constants(_Section):
    mu: Positive | None = None
    j2: float | None = None
    r_earth: Positive | None = None
    earth_flattening: Num(0, 1, hi_open=True) | None = None
    omega_earth: float | None = None
    mu_mag: NonNegative | None = None
    g0: Positive | None = None


class Environment(_Section):
    gravity_gradient: bool | None = None
    magnetic: bool | None = None
    j2: bool | None = None
    drag: bool | None = None
    random_torque_std_chaser: Num(0, unit="N m") | None = None
    random_torque_std_target: Num(0, unit="N m") | None = None
    constants: Constants = Field(default_factory=Constants)


class _Body(_Section):
    mass: Num(0, lo_open=True, unit="kg") | None = None
    inertia: Inertia | None = None
    dipole: Vec3 | None = None
    drag_area: Num(0, lo_open=True, unit="m^2") | None = None
    drag_cd: Positive | None = None
    attitude_frame: Frame
    quaternion: Quaternion
    angular_velocity: Vec3 | None = None
    angular_velocity_deg_s: Vec3 | None = None
    angular_velocity_relative_to: Literal["eci", "attitude_frame"] = "eci"

    @model_validator(mode="after")
    def _one_rate(self):
        if self.angular_velocity is not None and self.angular_velocity_deg_s is not None:
            raise _field_error("angular_velocity_deg_s", self.angular_velocity_deg_s,
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
    mass_profile: Literal["seed000", "constant"] | None = None
    wheel_momentum: Vec4 | None = None
    wheel_speed_rpm: Vec4 | None = None

    @model_validator(mode="after")
    def _one_wheel_state(self):
        if self.wheel_momentum is not None and self.wheel_speed_rpm is not None:
            raise _field_error("wheel_speed_rpm", self.wheel_speed_rpm,
                               "give either wheel_momentum (N m s) or wheel_speed_rpm, not both")
        return self


class Target(_Body):
    pass


class Relative(_Section):
    position: Vec3
    velocity: Vec3


class Wheels(_Section):
    tilt_deg: Num(0, 90, lo_open=True, hi_open=True, unit="deg") | None = None
    inertia: Num(0, lo_open=True, unit="kg m^2") | None = None
    max_torque: Num(0, lo_open=True, unit="N m") | None = None
    max_speed_rpm: Num(0, lo_open=True, unit="rpm") | None = None
    delay: Num(0, unit="s") | None = None


class Pwpf(_Section):
    k_m: Positive | None = None
    t_m: Num(0, lo_open=True, unit="s") | None = None
    u_on: Positive | None = None
    u_off: Positive | None = None


class Thrusters(_Section):
    max_force: Num(0, lo_open=True, unit="N") | None = None
    isp: Num(0, lo_open=True, unit="s") | None = None
    pwpf: Pwpf = Field(default_factory=Pwpf)


class PlantSection(_Section):
    """Which plant model: the orbit or free space, and the actuator model."""

    gravity: bool | None = None  # false: free space (004's model), the LVLH frame is frozen to ECI
    actuators: Literal["ideal", "wheels_thrusters"] | None = None
    max_force: Num(0, lo_open=True, unit="N") | None = None    # per axis, ideal actuators
    max_torque: Num(0, lo_open=True, unit="N m") | None = None  # per axis, ideal actuators


class DisturbanceAxes(_Section):
    """Per axis, chaser body: constant + sin1 sin(omega1 t) + cos1 cos(omega1 t) + sin2 sin(omega2 t)
    + cos2 cos(omega2 t) + sin_nu sin(nu) + cos_nu cos(nu), nu the target's true anomaly."""

    constant: Vec3 | None = None
    sin1: Vec3 | None = None
    cos1: Vec3 | None = None
    omega1: Vec3 | None = None
    sin2: Vec3 | None = None
    cos2: Vec3 | None = None
    omega2: Vec3 | None = None
    sin_nu: Vec3 | None = None
    cos_nu: Vec3 | None = None


class Disturbance(_Section):
    force: DisturbanceAxes = Field(default_factory=DisturbanceAxes)   # N
    torque: DisturbanceAxes = Field(default_factory=DisturbanceAxes)  # N m


class Sensors(_Section):
    """Measurement noise (std per axis, a new sample each step from the run's seed) and bias."""

    attitude_noise_deg: Num(0, unit="deg") | None = None
    rate_noise_deg_s: Num(0, unit="deg/s") | None = None
    position_noise: Num(0, unit="m") | None = None
    velocity_noise: Num(0, unit="m/s") | None = None
    attitude_bias_deg: Vec3 | None = None
    rate_bias_deg_s: Vec3 | None = None
    position_bias: Vec3 | None = None
    velocity_bias: Vec3 | None = None


class Constraints(_Section):
    """001's camera cone and envelope spheres (logged for every controller)."""

    camera_half_angle_deg: Num(0, 90, lo_open=True, hi_open=True, unit="deg") | None = None
    camera_zn: float | None = None
    chaser_radius: Num(0, unit="m") | None = None
    target_radius: Num(0, unit="m") | None = None


_DIST_KEYS = {"constant": "c0", "sin1": "a1", "cos1": "b1", "omega1": "w1", "sin2": "a2", "cos2": "b2",
              "omega2": "w2", "sin_nu": "s_nu", "cos_nu": "c_nu"}

# (scenario path, p field, conversion to SI) for the keys that map one-to-one onto a parameter.
_SCALE = {"deg": lambda v: v * DEG, "rpm": lambda v: v * RPM, "bool": lambda v: 1.0 if v else 0.0,
          "hz": lambda v: 1.0 / v, "profile": lambda v: 1.0 if v == "seed000" else 0.0,
          "ideal": lambda v: 1.0 if v == "ideal" else 0.0, "degvec": lambda v: np.array(v, float) * DEG}
PARAM_MAP: tuple[tuple[str, str, str | None], ...] = (
    ("simulation.rate", "dt", "hz"),
    ("orbit.semi_major_axis", "orbit_a", None),
    ("orbit.eccentricity", "orbit_e", None),
    ("orbit.inclination_deg", "orbit_inc", "deg"),
    ("orbit.raan_deg", "orbit_raan", "deg"),
    ("orbit.arg_perigee_deg", "orbit_argp", "deg"),
    ("orbit.true_anomaly_deg", "orbit_nu0", "deg"),
    ("environment.gravity_gradient", "gg_on", "bool"),
    ("environment.magnetic", "mag_on", "bool"),
    ("environment.j2", "j2_on", "bool"),
    ("environment.drag", "drag_on", "bool"),
    ("environment.random_torque_std_chaser", "chaser_rand_std", None),
    ("environment.random_torque_std_target", "target_rand_std", None),
    *((f"environment.constants.{c}", c, None) for c in Constants.model_fields),
    ("chaser.mass", "chaser_mass", None),
    ("chaser.inertia", "chaser_inertia", "inertia"),
    ("chaser.dipole", "chaser_dipole", None),
    ("chaser.drag_area", "chaser_area", None),
    ("chaser.drag_cd", "chaser_cd", None),
    ("chaser.mass_profile", "mass_profile_on", "profile"),
    ("target.mass", "target_mass", None),
    ("target.inertia", "target_inertia", "inertia"),
    ("target.dipole", "target_dipole", None),
    ("target.drag_area", "target_area", None),
    ("target.drag_cd", "target_cd", None),
    ("wheels.tilt_deg", "wheel_beta", "deg"),
    ("wheels.inertia", "wheel_inertia", None),
    ("wheels.max_torque", "wheel_torque_max", None),
    ("wheels.max_speed_rpm", "wheel_speed_max", "rpm"),
    ("wheels.delay", "wheel_delay", None),
    ("thrusters.max_force", "thruster_force", None),
    ("thrusters.isp", "thruster_isp", None),
    ("thrusters.pwpf.k_m", "pwpf_km", None),
    ("thrusters.pwpf.t_m", "pwpf_tm", None),
    ("thrusters.pwpf.u_on", "pwpf_uon", None),
    ("thrusters.pwpf.u_off", "pwpf_uoff", None),
    ("plant.gravity", "gravity_on", "bool"),
    ("plant.actuators", "actuators_ideal", "ideal"),
    ("plant.max_force", "force_max", None),
    ("plant.max_torque", "torque_max", None),
    *((f"disturbance.{kind}.{key}", f"dist_{kind}_{p}", None)
      for kind in ("force", "torque") for key, p in _DIST_KEYS.items()),
    ("sensors.attitude_noise_deg", "meas_att_std", "deg"),
    ("sensors.rate_noise_deg_s", "meas_rate_std", "deg"),
    ("sensors.position_noise", "meas_pos_std", None),
    ("sensors.velocity_noise", "meas_vel_std", None),
    ("sensors.attitude_bias_deg", "meas_att_bias", "degvec"),
    ("sensors.rate_bias_deg_s", "meas_rate_bias", "degvec"),
    ("sensors.position_bias", "meas_pos_bias", None),
    ("sensors.velocity_bias", "meas_vel_bias", None),
    ("constraints.camera_half_angle_deg", "camera_half_angle", "deg"),
    ("constraints.camera_zn", "camera_zn", None),
    ("constraints.chaser_radius", "chaser_radius", None),
    ("constraints.target_radius", "target_radius", None),
)

#: ``--plant full``: the common full-fidelity plant of seed 000 for the scenario's initial
#: conditions, bodies and orbit: orbit on, every environment disturbance at 000's values, the
#: 000 wheel pyramid and PWPF thrusters (Table 3), 000's mass/inertia profile; the papers'
#: synthetic disturbance models off (the environment replaces them).
FULL_PLANT = {
    "plant": {"gravity": True, "actuators": "wheels_thrusters"},
    "environment": {"gravity_gradient": True, "magnetic": True, "j2": True, "drag": True},
    "chaser": {"mass_profile": "seed000"},
    "disturbance": {},
    "wheels": {},
    "thrusters": {},
}



def _inertia_components(I: list[list[float]], labels: list[str]) -> np.ndarray:
    """3x3 tensor -> the manifest's component order, read from the label suffixes (``_xx``, ``_xy``...)."""
    ax = {"x": 0, "y": 1, "z": 2}
    return np.array([I[ax[lbl[-2]]][ax[lbl[-1]]] for lbl in labels], float)


def manifest_defaults(manifest: dict, layout: str) -> dict[str, np.ndarray]:
    """Default values of a manifest layout by field name (as :meth:`Model.defaults`)."""
    return {f["name"]: np.array(f["default"], float) for f in manifest["layouts"][layout] if "default" in f}


class Scenario(_Section):
    """A validated scenario.  Build it with :func:`load_scenario`; turn it into the inputs of a
    :class:`~rpo.runtime.simulate.Simulation` with :meth:`to_run`."""

    meta: Meta = Field(default_factory=Meta)
    simulation: SimulationSection
    orbit: Orbit = Field(default_factory=Orbit)
    environment: Environment = Field(default_factory=Environment)
    chaser: Chaser
    target: Target
    relative: Relative
    wheels: Wheels = Field(default_factory=Wheels)
    thrusters: Thrusters = Field(default_factory=Thrusters)
    plant: PlantSection = Field(default_factory=PlantSection)
    disturbance: Disturbance = Field(default_factory=Disturbance)
    sensors: Sensors = Field(default_factory=Sensors)
    constraints: Constraints = Field(default_factory=Constraints)
    controller: dict[str, dict[str, Any]] = Field(default_factory=dict)

    _source: str = PrivateAttr(default="scenario")
    _manifest: dict = PrivateAttr(default_factory=dict)
    _data: dict = PrivateAttr(default_factory=dict)
    _text: str | None = PrivateAttr(default=None)

    # -- lookups -----------------------------------------------------------------------------

    def get(self, path: str) -> Any:
        """Value at a dotted path (``"orbit.eccentricity"``), None when omitted."""
        obj: Any = self
        for part in path.split("."):
            obj = getattr(obj, part, None)
            if obj is None:
                return None
        return obj

    def param_overrides(self, manifest: dict | None = None) -> dict[str, Any]:
        """The parameters this scenario sets, by p-field name, in SI (omitted ones are absent)."""
        manifest = manifest or self._manifest
        labels = {f["name"]: f["labels"] for f in manifest["layouts"]["p"]}
        out: dict[str, Any] = {}
        for path, name, conv in PARAM_MAP:
            v = self.get(path)
            if v is None:
                continue
            if conv == "inertia":
                out[name] = _inertia_components(v, labels[name])
            elif conv:
                out[name] = _SCALE[conv](v)
            else:
                out[name] = np.array(v, float) if isinstance(v, list) else float(v)
        if self.orbit.perigee_altitude is not None:
            d = manifest_defaults(manifest, "p")
            e = out.get("orbit_e", float(d["orbit_e"][0]))
            r_e = out.get("r_earth", float(d["r_earth"][0]))
            out["orbit_a"] = (r_e + self.orbit.perigee_altitude) / (1.0 - e)  # perigee radius = a (1 - e)
        return out

    def params(self, manifest: dict | None = None) -> dict[str, np.ndarray]:
        """Every parameter (defaults overridden by the scenario), by p-field name, SI."""
        manifest = manifest or self._manifest
        p = manifest_defaults(manifest, "p")
        for k, v in self.param_overrides(manifest).items():
            p[k] = np.atleast_1d(np.asarray(v, float))
        return p

    def gains(self, manifest: dict | None = None) -> dict[str, np.ndarray]:
        """Gains of the selected controller (defaults overridden by ``[controller.<name>]``)."""
        manifest = manifest or self._manifest
        ctrl = self.simulation.controller
        g = manifest_defaults(manifest, manifest["controllers"][ctrl]["gains"])
        for k, v in self.controller.get(ctrl, {}).items():
            g[k] = np.atleast_1d(np.asarray(v, float))
        return g

    # -- cross-field checks (need the manifest's defaults) ---------------------------------------

    @model_validator(mode="after")
    def _cross_checks(self, info: ValidationInfo):
        manifest = (info.context or {}).get("manifest")
        if manifest is None:
            from .compiled import read_manifest
            manifest = read_manifest()
        self._manifest = manifest
        self._check_controller(manifest)
        p = {k: float(v[0]) if v.size == 1 else v for k, v in self.params(manifest).items()}
        sim = self.simulation

        # orbit: the perigee must be above the surface
        r_p = p["orbit_a"] * (1 - p["orbit_e"])
        if not r_p > p["r_earth"]:
            where = next((k for k in ("orbit.semi_major_axis", "orbit.eccentricity", "environment.constants.r_earth")
                          if self.get(k) is not None), "orbit.semi_major_axis")
            raise _field_error(where, self.get(where),
                               f"perigee below the surface: perigee radius a (1 - e) = {r_p:.7g} m with "
                               f"a = {p['orbit_a']:.7g} m, e = {p['orbit_e']:g}; must be > R_E = {p['r_earth']:.7g} m")

        # time: at least one step; the wheel delay fits the delay line
        dt = p["dt"]
        if sim.duration < dt * (1 - 1e-9):
            raise _field_error("simulation.duration", sim.duration,
                               f"must be at least one step (1 / rate = {dt:g} s)")
        steps = sim.duration / dt
        if abs(steps - round(steps)) > 1e-9 * max(1.0, steps):
            # a fixed-step run covers whole steps; rounding silently would misreport the end time
            raise _field_error("simulation.duration", sim.duration,
                               f"must be a whole number of steps of 1 / rate = {dt:g} s")
        slots = int(manifest.get("delay_slots", 4))
        if not p["wheel_delay"] < slots * dt:
            where = "wheels.delay" if self.wheels.delay is not None else "simulation.rate"
            raise _field_error(where, self.get(where),
                               f"the wheel delay {p['wheel_delay']:g} s must be in [0, {slots * dt:g}) s: the model's "
                               f"delay line holds {slots} steps of 1 / rate = {dt:g} s")
        n_rows = int(round(sim.duration / dt)) // sim.record_every + 1
        ctrl = manifest["controllers"][sim.controller]["step"]
        width = sum(math.prod(o["shape"]) for o in manifest["functions"][ctrl]["outputs"])
        size = n_rows * width * 8
        if size > MAX_RECORD_BYTES:
            raise _field_error("simulation.duration", sim.duration,
                               f"would record {n_rows} rows ({size / 1e9:.3g} GB, limit "
                               f"{MAX_RECORD_BYTES / 1e9:g} GB): raise simulation.record_every or shorten the run")

        # ideal actuators need their limits
        if self.plant.actuators == "ideal" and (self.plant.max_force is None or self.plant.max_torque is None):
            raise _field_error("plant.actuators", "ideal",
                               "ideal actuators need plant.max_force [N] and plant.max_torque [N m] (per axis)")

        # thrusters: Schmitt trigger levels
        if not p["pwpf_uoff"] < p["pwpf_uon"]:
            where = "thrusters.pwpf.u_off" if self.thrusters.pwpf.u_off is not None else "thrusters.pwpf.u_on"
            raise _field_error(where, self.get(where),
                               f"must satisfy 0 < u_off < u_on (u_off = {p['pwpf_uoff']:g}, u_on = {p['pwpf_uon']:g})")
        return self

    def _check_controller(self, manifest: dict) -> None:
        ctrls = manifest["controllers"]
        if self.simulation.controller not in ctrls:
            raise _field_error("simulation.controller", self.simulation.controller,
                               f"unknown controller; available: {', '.join(sorted(ctrls))}")
        for name, table in self.controller.items():
            if name not in ctrls:
                raise _field_error(f"controller.{name}", table,
                                   f"unknown controller; available: {', '.join(sorted(ctrls))}")
            layout = {f["name"]: f for f in manifest["layouts"][ctrls[name]["gains"]]}
            for key, value in table.items():
                path = f"controller.{name}.{key}"
                if key not in layout:
                    raise _field_error(path, value, _unknown_key(key, list(layout)))
                size, unit = layout[key]["size"], layout[key]["unit"]
                items = value if isinstance(value, list) else [value]
                numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in items)
                if (size == 1) == isinstance(value, list) or not numeric:
                    want = "a number" if size == 1 else f"an array of {size} numbers"
                    raise _field_error(path, value, f"must be {want} ({unit})")
                if len(items) != size:
                    raise _field_error(path, value, f"must have {size} values, got {len(items)}")
                if not all(math.isfinite(x) for x in items):
                    raise _field_error(path, value, "must be finite")

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
                       controller: str | None = None, plant: str | None = None) -> Scenario:
        """A re-validated copy with ``simulation.duration`` / ``seed`` / ``controller`` replaced and,
        with ``plant="full"``, the paper's plant replaced by the common full plant (:data:`FULL_PLANT`)."""
        if duration is None and seed is None and controller is None and plant in (None, "paper"):
            return self
        data = copy.deepcopy(self._data)
        sim = data.setdefault("simulation", {})
        if duration is not None:
            sim["duration"] = duration
        if seed is not None:
            sim["seed"] = seed
        if controller is not None:
            sim["controller"] = controller
        if plant == "full":
            for section, values in FULL_PLANT.items():
                if not values:
                    data.pop(section, None)
                    continue
                table = data.setdefault(section, {})
                if section == "plant":
                    table.pop("max_force", None)
                    table.pop("max_torque", None)
                if section == "environment":
                    table.pop("random_torque_std_chaser", None)
                    table.pop("random_torque_std_target", None)
                table.update(values)
        sc = validate_scenario(data, f"{self._source} (with command-line overrides)", self._manifest)
        sc._text = self._text
        return sc

    def to_run(self, model) -> RunInputs:
        """Inputs of :class:`~rpo.runtime.simulate.Simulation` for ``model``: all parameters in SI,
        the gains, and the plant's initial state with attitudes relative to ECI.

        Attitudes given relative to ``lvlh``/``orbit`` use the LVLH attitude ``q_IL`` and rate
        ``n`` of the generated ``target_orbit`` function at t = 0 (no orbit equation is retyped).
        """
        manifest = model.manifest
        params = self.params(manifest)
        gains = self.gains(manifest)
        try:
            p = model.vector("p", params)
            orbit = model.functions["target_orbit"](0.0, p)
        except KeyError as exc:
            raise ModelError(f"the generated model has no function {exc}: run `python build.py`") from exc
        _nu, _r, _r_dot, n, _n_dot, _r_eci, _v_eci, q_IL = orbit
        n = float(np.ravel(n)[0])
        q_IL = np.ravel(q_IL)
        if float(params["gravity_on"][0]) == 0.0:
            # free space: the frame of r, v ("lvlh") is fixed in ECI (symbolic/plant.py reference_frame)
            n, q_IL = 0.0, np.array([0.0, 0.0, 0.0, 1.0])

        def body(b: _Body) -> tuple[np.ndarray, np.ndarray]:
            q_IB = frames.attitude_to_eci(b.quaternion, b.attitude_frame, q_IL)
            rel_frame = b.attitude_frame if b.angular_velocity_relative_to == "attitude_frame" else "eci"
            return q_IB, frames.body_rate_eci(b.rate_rad_s(), q_IB, rel_frame, q_IL, n)

        q_c, w_c = body(self.chaser)
        q_t, w_t = body(self.target)
        plant = {"q_c": q_c, "w_c": w_c, "q_t": q_t, "w_t": w_t,
                 "r": np.array(self.relative.position, float), "v": np.array(self.relative.velocity, float)}
        if self.chaser.wheel_momentum is not None:
            plant["h_w"] = np.array(self.chaser.wheel_momentum, float)
        else:
            speeds = np.array(self.chaser.wheel_speed_rpm or [0.0] * 4, float) * RPM
            limit = float(params["wheel_speed_max"][0])
            if np.abs(speeds).max() > limit * (1 + 1e-12):
                raise ScenarioError(f"{self._source}: chaser.wheel_speed_rpm = {self.chaser.wheel_speed_rpm}: "
                                    f"each |speed| must be <= wheels.max_speed_rpm = {limit / RPM:g} rpm")
            plant["h_w"] = _wheel_momentum(model, p, plant, speeds)
        sim = self.simulation
        return RunInputs(params={k: v.copy() for k, v in params.items()}, gains=gains, plant=plant,
                         duration=float(sim.duration), seed=int(sim.seed), controller=sim.controller,
                         record_every=int(sim.record_every), dt=float(params["dt"][0]),
                         frame_info={"q_IL0": q_IL, "n0": n})


def _wheel_momentum(model, p: np.ndarray, plant: dict, speeds: np.ndarray) -> np.ndarray:
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

    def omega(h):
        x = model.vector("x", {**plant, "h_w": h, "m_prop": 0.0})
        u = np.zeros(model.layout_size("u"))
        w = np.zeros(model.layout_size("w"))
        return np.ravel(fn(x, u, 0.0, p, w)[0])[offs]

    h = J * (speeds - omega(np.zeros(4)))
    check = omega(h)
    if not np.allclose(check, speeds, rtol=1e-9, atol=1e-9):
        raise ModelError(f"wheel speeds are not affine in h_w with slope 1/J_w (got {check}, wanted {speeds})")
    return h


@dataclass
class RunInputs:
    """Everything a run needs, in SI: ``params`` (all p fields), ``gains``, the initial ``plant``
    state for :meth:`Simulation.initial_state` (attitudes relative to ECI, rates relative to ECI
    in body axes, r and v in LVLH), and the run settings."""

    params: dict[str, np.ndarray]
    gains: dict[str, np.ndarray]
    plant: dict[str, np.ndarray]
    duration: float
    seed: int
    controller: str
    record_every: int
    dt: float
    frame_info: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        """JSON-ready copy (arrays as lists, 1-element arrays as numbers)."""

        def conv(v):
            if isinstance(v, dict):
                return {k: conv(x) for k, x in v.items()}
            a = np.asarray(v)
            if a.dtype.kind == "f" or a.dtype.kind == "i":
                return a.item() if a.size == 1 else a.tolist()
            return v

        return {k: conv(v) for k, v in asdict(self).items()}


# --------------------------------------------------------------------------- loading and errors


def _show(v: Any, limit: int = 70) -> str:
    """A value as it would be typed in TOML, shortened."""
    if isinstance(v, bool):
        s = "true" if v else "false"
    elif isinstance(v, str):
        s = json.dumps(v)
    elif isinstance(v, float):
        s = repr(v)
    elif isinstance(v, (list, tuple)):
        s = "[" + ", ".join(_show(x, limit) for x in v) + "]"
    elif isinstance(v, dict):
        s = "{ " + ", ".join(f"{k} = {_show(x, limit)}" for k, x in v.items()) + " }"
    else:
        s = str(v)
    return s if len(s) <= limit else s[: limit - 3] + "..."


def _dotted(loc) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


def _unknown_key(key: str, allowed: list[str]) -> str:
    close = difflib.get_close_matches(key, allowed, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return f"unknown key ({hint}allowed: {', '.join(allowed)})"


def _section_class(loc) -> type[BaseModel] | None:
    """The model class of the table at ``loc`` (for listing the allowed keys)."""
    cls: Any = Scenario
    for part in loc:
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)) or part not in cls.model_fields:
            return None
        ann = cls.model_fields[part].annotation
        cands = [ann, *typing.get_args(ann)]
        cls = next((c for c in cands if isinstance(c, type) and issubclass(c, BaseModel)), None)
    return cls


def _message(err: dict) -> str:
    t, ctx = err["type"], err.get("ctx") or {}
    inp = err.get("input")
    simple = {
        "float_type": "must be a number", "float_parsing": "must be a number",
        "int_type": "must be an integer", "int_from_float": "must be an integer",
        "bool_type": "must be true or false", "string_type": "must be a string",
        "list_type": "must be an array", "model_type": "must be a table", "model_attributes_type": "must be a table",
        "dict_type": "must be a table", "finite_number": "must be a finite number",
        "missing": "required key is missing",
    }
    if t in simple:
        return simple[t]
    if t == "literal_error":
        return f"must be one of {ctx.get('expected', '')}"
    if t in ("too_short", "too_long"):
        n = ctx.get("min_length", ctx.get("max_length"))
        got = len(inp) if isinstance(inp, (list, tuple)) else ctx.get("actual_length")
        return f"must have {n} values, got {got}"
    if t == "extra_forbidden":
        cls = _section_class(err["loc"][:-1])
        return _unknown_key(str(err["loc"][-1]), list(cls.model_fields) if cls else [])
    return err["msg"][0].lower() + err["msg"][1:] if err["msg"] else t


def format_error(err: dict, source: str) -> str:
    """One line: ``source: dotted.key = value: message``."""
    ctx = err.get("ctx") or {}
    loc = tuple(err["loc"])
    value = err.get("input")
    if "field" in ctx:
        loc = loc + tuple(ctx["field"].split("."))
        value = ctx.get("value")
    path = _dotted(loc) or "(top level)"
    msg = _message(err) if "field" not in ctx else err["msg"]
    msg = " ".join(msg.split())  # never more than one line
    if err["type"] == "missing":
        what = "table" if _section_class(loc) is not None else "key"
        return f"{source}: {path}: required {what} is missing"
    if value is None:
        return f"{source}: {path}: {msg}"
    return f"{source}: {path} = {_show(value)}: {msg}"


def validate_scenario(data: dict, source: str = "scenario", manifest: dict | None = None) -> Scenario:
    """Validate a parsed scenario table; raises :class:`ScenarioError` with a one-line message."""
    if manifest is None:
        from .compiled import read_manifest
        manifest = read_manifest()
    try:
        sc = Scenario.model_validate(data, context={"manifest": manifest})
    except ValidationError as exc:
        errs = exc.errors(include_url=False)
        more = f" (and {len(errs) - 1} more error{'s' if len(errs) > 2 else ''})" if len(errs) > 1 else ""
        raise ScenarioError(format_error(errs[0], source) + more) from None
    sc._source = source
    sc._manifest = manifest
    sc._data = copy.deepcopy(data)
    return sc


def _read_toml(path: Path, chain: tuple[Path, ...] = ()) -> tuple[str, dict]:
    """Text and table of a scenario file, with ``extends = "<base>.toml"`` resolved.

    A variant names its base file (relative to itself) and gives only what differs: tables are
    merged key by key, any other value replaces the base's.  Bases may extend further bases.
    """
    src = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ScenarioError(f"{src}: cannot read the scenario: {reason}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{src}: invalid TOML: {' '.join(str(exc).split())}") from None
    base_name = data.pop("extends", None)
    if base_name is None:
        return text, data
    if not isinstance(base_name, str):
        raise ScenarioError(f"{src}: extends = {base_name!r}: must be the file name of a base scenario")
    base_path = (path.parent / base_name).resolve()
    if base_path in chain or base_path == path.resolve():
        raise ScenarioError(f"{src}: extends = {base_name!r}: the scenarios extend each other in a cycle")
    _base_text, base = _read_toml(base_path, (*chain, path.resolve()))
    return text, _merge(base, data)


def _merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else copy.deepcopy(v)
    return out


def load_scenario(path: str | Path, manifest: dict | None = None) -> Scenario:
    """Read and validate a scenario file (TOML, optionally ``extends`` a base file).  ``manifest``
    defaults to the generated one."""
    text, data = _read_toml(Path(path))
    sc = validate_scenario(data, str(path), manifest)
    sc._text = text
    return sc


def loads_scenario(text: str, source: str = "scenario", manifest: dict | None = None) -> Scenario:
    """Validate a scenario given as TOML text (``source`` names it in error messages)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: invalid TOML: {' '.join(str(exc).split())}") from None
    sc = validate_scenario(data, source, manifest)
    sc._text = text
    return sc

