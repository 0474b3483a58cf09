"""Fault events of the wheels, the thrusters and the sensors (rpo's model; the papers have none).

Every fault is a window [start, end) in time, per unit, set by runtime parameters (the scenario's
``[[faults]]`` array), so failing a unit needs no rebuild and a campaign can disperse fault times
like any other parameter.  A window is evaluated at the start t_k of each step and held over the
step (the actuators' zero-order hold): a fault at ``time`` acts from the first step starting at
or after it.  Units with no fault keep their nominal values *exactly*: every fault enters as a
blend ``a * faulty + (1 - a) * nominal`` with a flag a in {0, 1}, so a fault after the end of a
run changes nothing, bit for bit.

Kinds (unit, value):

* wheels 1-4: ``wheel_off`` (no motor torque; the wheel coasts, its momentum constant),
  ``wheel_weak`` (its torque limit becomes ``value`` times the nominal one, 0 <= value <= 1),
  ``wheel_stuck`` (locked at its speed relative to the body: it turns with the body and adds
  ``I_w a a^T`` to the chaser's inertia, :func:`rpo.symbolic.physics.rigid_body.locked_wheel_inertia`);
* thrusters 00-15: ``thruster_off`` (never fires), ``thruster_stuck_on`` (fires at full
  thrust, using propellant at F / (Isp g0)), ``thruster_weak`` (delivers ``value`` times its
  thrust, and uses propellant in proportion: a partly blocked feed);
* sensors ``attitude``, ``rate``, ``position``, ``velocity``: ``sensor_bias`` (``value`` added
  to the sensor's bias), ``sensor_freeze`` (the sensor repeats the last value it gave),
  ``sensor_noise`` (its noise standard deviation becomes ``value``).

If several kinds overlap on one actuator the precedence is off > stuck > weak.

The controller is not told.  The fault-aware allocation (``fdir_allocation`` = 1) is rpo's model
of an ideal FDIR layer that isolates a faulty unit the moment it fails: the wheel
pseudo-inverse and the thruster allocation are taken over the healthy units
(:mod:`rpo.symbolic.physics.actuators`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from .layout import Bounds
from .special import Step

# --------------------------------------------------------------------------- the vocabulary, declared once
#
# What a scenario's ``[[faults]]`` entry may say, as data: the unit families, the sensors, the fault
# kinds and NEVER.  The functions below and the plant's fault parameters use it; the code generator
# writes it into the manifest (``faults``), from which the runtime builds the ``[[faults]]`` schema,
# the mapping to parameters and every message.  Adding a kind is an entry of KINDS (and its effect
# below, and docs/faults.md).

#: Start and end time of a window that never opens [s] (a finite stand-in for +inf: the
#: manifest is JSON, and 1e30 s is 3e22 years).
NEVER = 1e30


@dataclass(frozen=True)
class Sensor:
    """A sensor a fault can name: ``name`` as a scenario writes it, ``short`` its name in the
    parameters (``meas_<short>_std``, ``fault_bias_<short>``), the ``unit`` a scenario writes its fault
    values in and their ``scale`` to SI (SI = scale x value), and the measurement ``field`` it gives."""

    name: str
    short: str
    unit: str
    scale: float
    field: str

    def describe(self) -> dict:
        return {"name": self.name, "short": self.short, "unit": self.unit, "scale": self.scale}


SENSORS = (Sensor("attitude", "att", "deg", math.pi / 180, "q_c"),
           Sensor("rate", "rate", "deg/s", math.pi / 180, "w_c"),
           Sensor("position", "pos", "m", 1.0, "r"),
           Sensor("velocity", "vel", "m/s", 1.0, "v"))


@dataclass(frozen=True)
class Family:
    """The units of one kind of equipment: ``prefix`` of its parameters (``fault_<prefix>_<kind>_start``),
    the ``noun`` of the messages, the ``units`` as the parameters label them, and ``first``: the number
    a scenario writes for the first unit (``unit = first + index``), or None for units a scenario
    names (``unit = "<label>"``); ``actuator``: whether its units are actuators (the ideal actuators
    of 001, 002 and 004 have none to fail); ``shorts``: each unit's name in a parameter of its own
    (default: its label)."""

    prefix: str
    noun: str
    units: tuple[str, ...]
    first: int | None
    actuator: bool
    shorts: tuple[str, ...] = ()

    def short(self, i: int) -> str:
        return (self.shorts or self.units)[i]

    @property
    def what(self) -> str:
        """The units as a message names them: ``a wheel 1-4``, ``a sensor "attitude", "rate", ...``."""
        if self.first is None:
            return f"a {self.noun} " + ", ".join(f'"{u}"' for u in self.units)
        return f"a {self.noun} {self.first}-{self.first + len(self.units) - 1}"

    def describe(self) -> dict:
        return {"prefix": self.prefix, "noun": self.noun, "units": list(self.units), "first": self.first,
                "what": self.what, "actuator": self.actuator}


WHEEL = Family("wheel", "wheel", ("1", "2", "3", "4"), first=1, actuator=True)
THRUSTER = Family("thr", "thruster", tuple(f"{j:02d}" for j in range(16)), first=0, actuator=True)
SENSOR = Family("sensor", "sensor", tuple(s.name for s in SENSORS), first=None, actuator=False,
                shorts=tuple(s.short for s in SENSORS))
FAMILIES = (WHEEL, THRUSTER, SENSOR)

#: ``Value.param``'s placeholder for the faulted unit's short name (a parameter per sensor)
UNIT = "{unit}"


@dataclass(frozen=True)
class Value:
    """The ``value`` a fault kind takes: ``what`` it is (the messages' text), its ``shape`` (1: a
    number, 3: [x, y, z]), the ``range`` a scenario's value must be in (None: only the parameter's
    bounds), its ``unit`` (None: the sensor's own, :attr:`Sensor.unit`) and the parameter it goes
    to: ``param`` is one vector over the family's units (``fault_wheel_weak_value``), or, with
    :data:`UNIT` in it, one field per unit (``fault_bias_{unit}`` -> ``fault_bias_att``), set whole.
    ``none``: the kind a value of 0 would mean (the messages point to it)."""

    what: str
    param: str
    shape: int = 1
    range: Bounds | None = None
    unit: str | None = "-"
    none: str | None = None

    def param_of(self, short: str) -> str:
        """The parameter of the unit with short name ``short`` (the vector's own name if not per unit)."""
        return self.param.replace(UNIT, short)

    def describe(self, family: Family) -> dict:
        """As the manifest records it: ``vector`` (the one parameter over the units) or ``fields``
        (unit -> its own parameter), so that the runtime need not know :data:`UNIT`."""
        per_unit = UNIT in self.param
        return {"what": self.what, "shape": self.shape, "unit": self.unit, "none": self.none,
                "range": None if self.range is None else self.range.describe(),
                "vector": None if per_unit else self.param,
                "fields": {u: self.param_of(family.short(i)) for i, u in enumerate(family.units)} if per_unit else None}


@dataclass(frozen=True)
class Kind:
    """A fault kind: its ``name`` in a scenario, its unit ``family``, ``param`` its name in the
    parameters (``fault_<family prefix>_<param>_start``/``_end``) and the ``value`` it takes (None:
    none)."""

    name: str
    family: Family
    param: str
    value: Value | None = None

    def window(self, edge: str) -> str:
        """The parameter of the window's ``start`` or ``end``."""
        return f"fault_{self.family.prefix}_{self.param}_{edge}"

    def describe(self) -> dict:
        return {"name": self.name, "family": self.family.prefix, "param": self.param,
                "start": self.window("start"), "end": self.window("end"),
                "value": None if self.value is None else self.value.describe(self.family)}


_FRACTION = Bounds(0.0, 1.0, lo_open=True)
KINDS = (
    Kind("wheel_off", WHEEL, "off"),
    Kind("wheel_weak", WHEEL, "weak", Value("the fraction of the torque limit left, 0 < value <= 1",
                                            "fault_wheel_weak_value", range=_FRACTION, none="wheel_off")),
    Kind("wheel_stuck", WHEEL, "stuck"),
    Kind("thruster_off", THRUSTER, "off"),
    Kind("thruster_stuck_on", THRUSTER, "stuck_on"),
    Kind("thruster_weak", THRUSTER, "weak", Value("the fraction of the thrust left, 0 < value <= 1",
                                                  "fault_thr_weak_value", range=_FRACTION, none="thruster_off")),
    Kind("sensor_bias", SENSOR, "bias", Value(
        "the bias step [x, y, z] in the sensor's unit (" + ", ".join(s.unit for s in SENSORS) + ")",
        f"fault_bias_{UNIT}", shape=3, unit=None)),
    Kind("sensor_freeze", SENSOR, "freeze"),
    Kind("sensor_noise", SENSOR, "noise", Value("the noise standard deviation, >= 0, in the sensor's unit",
                                                f"fault_noise_{UNIT}_std", range=Bounds(0.0), unit=None)),
)
KIND = {k.name: k for k in KINDS}


def kinds_of(family: Family) -> tuple[Kind, ...]:
    """The kinds of ``family``, in declaration order."""
    return tuple(k for k in KINDS if k.family is family)


def value_of(kind: str) -> Value:
    """The value of the kind named ``kind`` (one that takes a value)."""
    v = KIND[kind].value
    if v is None:
        raise ValueError(f"fault kind {kind} takes no value")
    return v


def vocabulary() -> dict:
    """The vocabulary as the manifest records it (``faults``; lists, so that the order stays)."""
    return {"never": NEVER, "families": [f.describe() for f in FAMILIES],
            "sensors": [s.describe() for s in SENSORS], "kinds": [k.describe() for k in KINDS]}


def window(t, start, end):
    """1 on [start, end), 0 elsewhere (exactly 0 or 1)."""
    return Step(t - start) * (1 - Step(t - end))


def windows(t, start, end) -> sp.Matrix:
    """:func:`window` per unit of the columns ``start``, ``end``."""
    return sp.Matrix([window(t, a, b) for a, b in zip(start, end, strict=True)])


def _blend(a, faulty, nominal):
    """a * faulty + (1 - a) * nominal: the nominal value exactly when a = 0."""
    return a * faulty + (1 - a) * nominal


def _flags(family: Family, t, p) -> dict[str, sp.Matrix]:
    """The window of each kind of ``family`` per unit at t, by the kind's parameter name."""
    return {k.param: windows(t, p[k.window("start")], p[k.window("end")]) for k in kinds_of(family)}


def wheel_flags(t, p) -> dict[str, sp.Matrix]:
    """Per wheel: ``off``, ``stuck`` (0/1) and ``limit`` (the fraction of the torque limit left;
    1 when healthy) at t."""
    a = _flags(WHEEL, t, p)
    weak = value_of("wheel_weak")
    n = range(len(WHEEL.units))
    limit = sp.Matrix([_blend(a["weak"][i], p[weak.param][i], 1) for i in n])
    # off beats stuck: a wheel both failed and stuck coasts
    stuck = sp.Matrix([a["stuck"][i] * (1 - a["off"][i]) for i in n])
    return {"off": a["off"], "stuck": stuck, "weak": a["weak"], "limit": limit}


def faulty_wheel_torques(T_w, t, p, T_max) -> sp.Matrix:
    """The motor torques the wheels deliver for the commands T_w [N m]: 0 for a failed or locked
    wheel, clipped at the reduced limit for a weak one."""
    f = wheel_flags(t, p)
    out = []
    for i, T in enumerate(T_w):
        L = f["limit"][i] * T_max
        clipped = sp.Max(-L, sp.Min(L, T, evaluate=False), evaluate=False)
        out.append((1 - f["off"][i]) * (1 - f["stuck"][i]) * _blend(f["weak"][i], clipped, T))
    return sp.Matrix(out)


def thruster_flags(t, p) -> dict[str, sp.Matrix]:
    """Per thruster: ``off``, ``stuck_on`` (0/1) and ``thrust`` (the fraction of its thrust it
    delivers; 1 when healthy) at t."""
    a = _flags(THRUSTER, t, p)
    weak = value_of("thruster_weak")
    n = range(len(THRUSTER.units))
    thrust = sp.Matrix([_blend(a["weak"][j], p[weak.param][j], 1) for j in n])
    # off beats stuck on: a thruster both failed and stuck does not fire
    stuck_on = sp.Matrix([a["stuck_on"][j] * (1 - a["off"][j]) for j in n])
    return {"off": a["off"], "stuck_on": stuck_on, "thrust": thrust}


def faulty_thruster_levels(on, t, p) -> sp.Matrix:
    """Thrust levels (fraction of the nominal thrust) the thrusters deliver for the on-levels
    ``on`` of the PWPF modulators."""
    f = thruster_flags(t, p)
    return sp.Matrix([(1 - f["off"][j]) * _blend(f["stuck_on"][j], 1, on[j]) * f["thrust"][j]
                      for j in range(len(THRUSTER.units))])


def sensor_flags(t, p) -> dict[str, sp.Matrix]:
    """Per sensor (attitude, rate, position, velocity): ``bias``, ``freeze``, ``noise`` (0/1) at t."""
    return _flags(SENSOR, t, p)


def sensor_noise_and_bias(t, p) -> dict[str, tuple]:
    """(noise std, bias) of each sensor at t, the fault's values blended over the nominal ones."""
    f = sensor_flags(t, p)
    noise, step = value_of("sensor_noise"), value_of("sensor_bias")
    out = {}
    for i, s in enumerate(SENSORS):
        std = _blend(f["noise"][i], p[noise.param_of(s.short)], p[f"meas_{s.short}_std"])
        bias = p[f"meas_{s.short}_bias"] + f["bias"][i] * p[step.param_of(s.short)]
        out[s.short] = (std, bias)
    return out


def frozen(t, p, held, live) -> dict[str, sp.Matrix]:
    """Each sensor's output: its held last value while it is frozen, else the live one."""
    f = sensor_flags(t, p)
    return {s.short: _blend(f["freeze"][i], held[s.short], live[s.short]) for i, s in enumerate(SENSORS)}
