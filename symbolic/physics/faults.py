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

import sympy as sp

from .special import Step

#: Start and end time of a window that never opens [s] (a finite stand-in for +inf: the
#: manifest is JSON, and 1e30 s is 3e22 years).
NEVER = 1e30

WHEEL_KINDS = ("off", "weak", "stuck")
THRUSTER_KINDS = ("off", "stuck_on", "weak")
SENSOR_KINDS = ("bias", "freeze", "noise")
#: The sensors a fault can name, with their measurement fields and the bias/noise parameters.
SENSORS = ("att", "rate", "pos", "vel")


def window(t, start, end):
    """1 on [start, end), 0 elsewhere (exactly 0 or 1)."""
    return Step(t - start) * (1 - Step(t - end))


def windows(t, start, end) -> sp.Matrix:
    """:func:`window` per unit of the columns ``start``, ``end``."""
    return sp.Matrix([window(t, a, b) for a, b in zip(start, end, strict=True)])


def _blend(a, faulty, nominal):
    """a * faulty + (1 - a) * nominal: the nominal value exactly when a = 0."""
    return a * faulty + (1 - a) * nominal


def wheel_flags(t, p) -> dict[str, sp.Matrix]:
    """Per wheel: ``off``, ``stuck`` (0/1) and ``limit`` (the fraction of the torque limit left;
    1 when healthy) at t."""
    a = {k: windows(t, p[f"fault_wheel_{k}_start"], p[f"fault_wheel_{k}_end"]) for k in WHEEL_KINDS}
    limit = sp.Matrix([_blend(a["weak"][i], p["fault_wheel_weak_value"][i], 1) for i in range(4)])
    # off beats stuck: a wheel both failed and stuck coasts
    stuck = sp.Matrix([a["stuck"][i] * (1 - a["off"][i]) for i in range(4)])
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
    a = {k: windows(t, p[f"fault_thr_{k}_start"], p[f"fault_thr_{k}_end"]) for k in THRUSTER_KINDS}
    thrust = sp.Matrix([_blend(a["weak"][j], p["fault_thr_weak_value"][j], 1) for j in range(16)])
    # off beats stuck on: a thruster both failed and stuck does not fire
    stuck_on = sp.Matrix([a["stuck_on"][j] * (1 - a["off"][j]) for j in range(16)])
    return {"off": a["off"], "stuck_on": stuck_on, "thrust": thrust}


def faulty_thruster_levels(on, t, p) -> sp.Matrix:
    """Thrust levels (fraction of the nominal thrust) the thrusters deliver for the on-levels
    ``on`` of the PWPF modulators."""
    f = thruster_flags(t, p)
    return sp.Matrix([(1 - f["off"][j]) * _blend(f["stuck_on"][j], 1, on[j]) * f["thrust"][j]
                      for j in range(16)])


def sensor_flags(t, p) -> dict[str, sp.Matrix]:
    """Per sensor (attitude, rate, position, velocity): ``bias``, ``freeze``, ``noise`` (0/1) at t."""
    return {k: windows(t, p[f"fault_sensor_{k}_start"], p[f"fault_sensor_{k}_end"]) for k in SENSOR_KINDS}


def sensor_noise_and_bias(t, p) -> dict[str, tuple]:
    """(noise std, bias) of each sensor at t, the fault's values blended over the nominal ones."""
    f = sensor_flags(t, p)
    out = {}
    for i, s in enumerate(SENSORS):
        std = _blend(f["noise"][i], p[f"fault_noise_{s}_std"], p[f"meas_{s}_std"])
        bias = p[f"meas_{s}_bias"] + f["bias"][i] * p[f"fault_bias_{s}"]
        out[s] = (std, bias)
    return out


def frozen(t, p, held, live) -> dict[str, sp.Matrix]:
    """Each sensor's output: its held last value while it is frozen, else the live one."""
    f = sensor_flags(t, p)
    return {s: _blend(f["freeze"][i], held[s], live[s]) for i, s in enumerate(SENSORS)}
