"""The full-fidelity plant of seed 000: two rigid bodies, wheels, thrusters, orbit and environment.

State x (25): chaser attitude q_c (ECI -> body, scalar last) and body rate w_c; wheel momenta
h_w; target q_t, w_t; relative position r and velocity v of the chaser in the target's LVLH
frame (000 eq. 30); propellant used.  Input u (26): wheel torques on the body T_w (after the
transport delay, before the speed limit), the 16 thruster on-levels, and the force and torque of
the papers' ideal actuators (001, 002, 004).  Exogenous w (18): standard-normal samples for the
random torques of eq. 5 and for the sensor noise, held over a step.

Switches for the papers' own models (0/1 parameters): ``gravity_on`` (0: free space, 004),
``actuators_ideal``, the environment terms, the mass profile; plus the papers' disturbance
models (:meth:`Plant.scenario_disturbance`) and sensor noise/bias (:meth:`Plant.measurement`).

Everything here is SymPy; :mod:`rpo.symbolic.codegen` translates these very expressions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from . import actuators as act
from . import environment as env
from . import faults as flt
from . import orbit as orb
from . import target_orbit_state as tos
from .constraints import beta_ca, beta_fov
from .layout import NON_NEGATIVE, POSITIVE, XYZ, XYZW, Bounds, Layout, ScenarioKey
from .mass_properties import chaser_mass_properties, spacecraft_inertia_with_wheels
from .relative_attitude import attitude_error, rate_error
from .relative_translation import chaser_inertial_state, frame_tilt_acceleration, relative_acceleration
from .rigid_body import (
    angular_acceleration_offset,
    chaser_angular_acceleration,
    locked_wheel_inertia,
    locked_wheel_inertia_offset,
    locked_wheel_momentum_rate,
    target_angular_acceleration,
)
from .rotations import cross, norm, quat_conj, quat_mul, quat_rate, quat_to_dcm, vec

INERTIA_COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
WHEELS = flt.WHEEL.units
THRUSTERS = flt.THRUSTER.units
DEG = math.pi / 180
RPM = 2 * math.pi / 60


def inertia_tensor(c) -> sp.Matrix:
    """Symmetric 3x3 tensor from (xx, yy, zz, xy, xz, yz) entries [kg m^2]."""
    xx, yy, zz, xy, xz, yz = c
    return sp.Matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _params() -> Layout:
    """Layout p: every plant parameter, SI, with its bounds and its key in a scenario file.

    ``presets={"full": ...}`` marks the fields that ``rpo run --plant full`` sets: orbit on, every
    environment term at 000's values, 000's wheels, PWPF thrusters and mass profile, the papers'
    synthetic disturbance tables off (``"default"``: the manifest default).
    """
    p = Layout("p")
    S, pos, nonneg = ScenarioKey, POSITIVE, NON_NEGATIVE  # noqa: F841 (the ranges below say more than > 0)
    full_default = {"full": "default"}

    def switch(key):
        return S(key, kind="switch")

    # constants (SPEC.md "Common constants")
    const = "environment.constants."
    p.add("mu", 1, "m^3/s^2", "Earth gravitational parameter", default=3.986004418e14,
          bounds=Bounds(1e5, 1e21, why="any central body from a small moon (Phobos 7e5) to the Sun (1.3e20)"),
          scenario=S(const + "mu"))
    p.add("j2", 1, "-", "Earth J2", default=1.08262668e-3,
          bounds=Bounds(-0.1, 0.1, why="oblate or prolate bodies; Earth 1.1e-3, Jupiter 1.5e-2"),
          scenario=S(const + "j2"))
    p.add("r_earth", 1, "m", "Earth equatorial radius", default=6378137.0,
          bounds=Bounds(1e3, 1e9, why="a 1 km asteroid to the Sun (7e8 m)"), scenario=S(const + "r_earth"))
    p.add("earth_flattening", 1, "-", "WGS-84 flattening, for the altitude of eq. 39", default=1 / 298.257223563,
          bounds=Bounds(0.0, 0.5, why="the altitude of eq. 39 needs a body far from a disc; Earth 3.4e-3, Saturn 0.1"),
          scenario=S(const + "earth_flattening"))
    p.add("omega_earth", 1, "rad/s", "Earth rotation rate (atmosphere co-rotation)", default=7.292115e-5,
          bounds=Bounds(-1e-2, 1e-2, why="either sense; Earth 7.3e-5, a fast asteroid (10 min day) 1e-2"),
          scenario=S(const + "omega_earth"))
    p.add("mu_mag", 1, "T m^3", "Earth dipole strength (000 eq. 13)", default=8.1e15,
          bounds=Bounds(0.0, 1e21, why="none to Jupiter's dipole (1.6e20)"),
          scenario=S(const + "mu_mag"))
    p.add("g0", 1, "m/s^2", "standard gravity for Isp", default=9.80665,
          bounds=Bounds(1.0, 100.0, why="a definition constant (9.80665); a typo by a factor 10 stays visible"),
          scenario=S(const + "g0"))
    # target orbit (000 scenario III by default); a scenario may give the perigee altitude instead of a
    p.add("orbit_a", 1, "m", "target semi-major axis", default=(6378137.0 + 400e3) / (1 - 0.138),
          bounds=Bounds(1e3, 1e10, why="beyond the Moon (3.8e8) and Sun-Earth L2 (1.5e9); the perigee must "
                        "also clear the body (checked by the runtime)"),
          scenario=S("orbit.semi_major_axis"))
    p.add("orbit_e", 1, "-", "target eccentricity, 0 <= e < 1", default=0.138,
          bounds=Bounds(0.0, 1.0, hi_open=True, why="a closed orbit; the perigee check with a <= 1e10 m keeps "
                        "1 - e >= 6e-4"),
          scenario=S("orbit.eccentricity"))
    p.add("orbit_inc", 1, "rad", "inclination", default=55 * DEG,
          bounds=Bounds(0.0, 180 * DEG, why="the definition of an inclination"),
          scenario=S("orbit.inclination_deg", "deg", DEG))
    p.add("orbit_raan", 1, "rad", "right ascension of the ascending node", default=0.0,
          bounds=Bounds(-360 * DEG, 360 * DEG, why="one turn either way"), scenario=S("orbit.raan_deg", "deg", DEG))
    p.add("orbit_argp", 1, "rad", "argument of perigee", default=270 * DEG,
          bounds=Bounds(-360 * DEG, 360 * DEG, why="one turn either way"),
          scenario=S("orbit.arg_perigee_deg", "deg", DEG))
    p.add("orbit_nu0", 1, "rad", "true anomaly at t = 0", default=0.0,
          bounds=Bounds(-360 * DEG, 360 * DEG, why="one turn either way"),
          scenario=S("orbit.true_anomaly_deg", "deg", DEG))
    # model switches (0 or 1)
    p.add("gg_on", 1, "-", "gravity-gradient torques on (1) or off (0)", default=1,
          scenario=switch("environment.gravity_gradient"), presets={"full": 1})
    p.add("mag_on", 1, "-", "magnetic torques on/off", default=1, scenario=switch("environment.magnetic"),
          presets={"full": 1})
    p.add("j2_on", 1, "-", "differential J2 on/off", default=1, scenario=switch("environment.j2"), presets={"full": 1})
    p.add("drag_on", 1, "-", "differential drag on/off", default=1, scenario=switch("environment.drag"),
          presets={"full": 1})
    p.add("mass_profile_on", 1, "-", "000 time-varying chaser mass/inertia on/off", default=1,
          scenario=S("chaser.mass_profile", kind="choice", choices=(("seed000", 1.0), ("constant", 0.0))),
          presets={"full": 1})
    p.add("gravity_on", 1, "-", "orbit on (1) or free space (0, 004's model: LVLH frozen to ECI, no gravity)",
          default=1, scenario=switch("plant.gravity"), presets={"full": 1})
    p.add("orbit_propagated", 1, "-", "target orbit: Keplerian with 000's differential J2 and drag (0, eqs. 30, "
          "45) or the target's own orbit propagated with J2 and drag, its LVLH frame from that state (1)",
          default=0, scenario=S("plant.target_orbit", kind="choice", choices=(("kepler", 0.0), ("propagated", 1.0))),
          presets={"full": 1})
    p.add("actuators_ideal", 1, "-", "ideal force/torque actuators (1) or wheels and thrusters (0)", default=0,
          scenario=S("plant.actuators", kind="choice", choices=(("ideal", 1.0), ("wheels_thrusters", 0.0))),
          presets={"full": 0})
    p.add("force_max", 1, "N", "ideal actuators: per-axis force limit, chaser body", default=1.0,
          bounds=Bounds(0.0, 1e4, lo_open=True, why="up to a main engine (RCS thrusters are 1-500 N)"),
          scenario=S("plant.max_force"), presets=full_default)
    p.add("torque_max", 1, "N m", "ideal actuators: per-axis torque limit, chaser body", default=0.1,
          bounds=Bounds(0.0, 1e4, lo_open=True, why="up to a station's CMGs (ISS about 260 N m)"),
          scenario=S("plant.max_torque"), presets=full_default)
    # Papers' own disturbance models (002, 004 eqs.; 001 sec. 7), in chaser body axes; per axis
    # d = c0 + a1 sin(w1 t) + b1 cos(w1 t) + a2 sin(w2 t) + b2 cos(w2 t) + s_nu sin(nu) + c_nu cos(nu)
    for q, unit in (("force", "N"), ("torque", "N m")):
        for name, key, u_, doc in (("c0", "constant", unit, "constant term"),
                                   ("a1", "sin1", unit, "sin(w1 t) amplitude"),
                                   ("b1", "cos1", unit, "cos(w1 t) amplitude"),
                                   ("w1", "omega1", "rad/s", "first angular frequency"),
                                   ("a2", "sin2", unit, "sin(w2 t) amplitude"),
                                   ("b2", "cos2", unit, "cos(w2 t) amplitude"),
                                   ("w2", "omega2", "rad/s", "second angular frequency"),
                                   ("s_nu", "sin_nu", unit, "sin(true anomaly) amplitude"),
                                   ("c_nu", "cos_nu", unit, "cos(true anomaly) amplitude")):
            p.add(f"dist_{q}_{name}", 3, u_, f"scenario disturbance {q} on the chaser, body: {doc}", XYZ,
                  default=(0, 0, 0),
                  bounds=(Bounds(0.0, 1e4, per_step=math.pi, why="a frequency the step samples (Nyquist: "
                                 "|w| dt <= pi)") if u_ == "rad/s" else
                          Bounds(-1e3, 1e3, why="either sign; far beyond any environmental disturbance (mN)")),
                  scenario=S(f"disturbance.{q}.{key}"), presets=full_default)
    p.add("meas_att_std", 1, "rad", "attitude measurement noise std (per axis, chaser)", default=0.0,
          bounds=Bounds(0.0, math.pi, why="up to a half turn (a star tracker is arcseconds)"),
          scenario=S("sensors.attitude_noise_deg", "deg", DEG))
    p.add("meas_rate_std", 1, "rad/s", "rate measurement noise std (per axis, chaser)", default=0.0,
          bounds=Bounds(0.0, 1.0, why="up to 57 deg/s (a gyro is 1e-5 rad/s)"),
          scenario=S("sensors.rate_noise_deg_s", "deg/s", DEG))
    p.add("meas_pos_std", 1, "m", "relative position noise std (per axis, LVLH)", default=0.0,
          bounds=Bounds(0.0, 1e4, why="up to 10 km (GNSS or lidar are cm to m)"),
          scenario=S("sensors.position_noise"))
    p.add("meas_vel_std", 1, "m/s", "relative velocity noise std (per axis, LVLH)", default=0.0,
          bounds=Bounds(0.0, 100.0, why="up to 100 m/s"),
          scenario=S("sensors.velocity_noise"))
    p.add("meas_att_bias", 3, "rad", "attitude measurement bias (small rotation, chaser body)", XYZ, default=(0, 0, 0),
          bounds=Bounds(-math.pi, math.pi, why="up to a half turn per axis"),
          scenario=S("sensors.attitude_bias_deg", "deg", DEG))
    p.add("meas_rate_bias", 3, "rad/s", "rate measurement bias, chaser body", XYZ, default=(0, 0, 0),
          bounds=Bounds(-1.0, 1.0, why="up to 57 deg/s per axis"),
          scenario=S("sensors.rate_bias_deg_s", "deg/s", DEG))
    p.add("meas_pos_bias", 3, "m", "relative position bias, LVLH", XYZ, default=(0, 0, 0),
          bounds=Bounds(-1e4, 1e4, why="up to 10 km per axis"),
          scenario=S("sensors.position_bias"))
    p.add("meas_vel_bias", 3, "m/s", "relative velocity bias, LVLH", XYZ, default=(0, 0, 0),
          bounds=Bounds(-100.0, 100.0, why="up to 100 m/s per axis"),
          scenario=S("sensors.velocity_bias"))
    p.add("camera_half_angle", 1, "rad", "camera half field of view (001: 45 deg), camera on body +z",
          default=45 * DEG,
          bounds=Bounds(0.0, 90 * DEG, lo_open=True, hi_open=True, why="a cone (001 eq. 41 needs tan < inf)"),
          scenario=S("constraints.camera_half_angle_deg", "deg", DEG))
    p.add("camera_zn", 1, "m", "camera lens vertex on body +z (001 z_N)", default=1.2,
          bounds=Bounds(-100.0, 100.0, why="on the body, either side of its centre"),
          scenario=S("constraints.camera_zn"))
    p.add("chaser_radius", 1, "m", "chaser envelope sphere radius (001 R_S)", default=2.1,
          bounds=Bounds(0.0, 1e3, why="up to a 1 km envelope"),
          scenario=S("constraints.chaser_radius"))
    p.add("target_radius", 1, "m", "target envelope sphere radius (001 R_T)", default=1.5,
          bounds=Bounds(0.0, 1e3, why="up to a 1 km envelope"),
          scenario=S("constraints.target_radius"))
    # chaser and target
    for body, mass, inertia, dipole, cd, area in (
            ("chaser", 100.0, (11, 14, 13, -0.09, -0.4, -0.08), (0, 0, 0), 2.2, 1.0),
            ("target", 5425.0, (3336, 3184, 2423, -135, -154, -135), (0.3, 0.3, 0.3), 2.2, 20.0)):
        doc = {"chaser": ("chaser nominal mass m0", "chaser nominal inertia (no wheel axial inertia)",
                          "chaser residual dipole", "std of the chaser random torque (000 eq. 5)"),
               "target": ("target mass", "target inertia", "target residual dipole (000 eq. 12)",
                          "std of the target random torque (000 eq. 5)")}[body]
        p.add(f"{body}_mass", 1, "kg", doc[0], default=mass,
              bounds=Bounds(1e-2, 1e7, why="a 10 g chip satellite to beyond the ISS (4.2e5 kg)"),
              scenario=S(f"{body}.mass"))
        p.add(f"{body}_inertia", 6, "kg m^2", doc[1], INERTIA_COMPONENTS, default=inertia,
              bounds=Bounds(1e-6, 1e10, why="principal moments, a chip satellite to beyond the ISS (1e8)"),
              scenario=S(f"{body}.inertia", kind="inertia"))
        p.add(f"{body}_dipole", 3, "A m^2", doc[2], XYZ, default=dipole,
              bounds=Bounds(-1e4, 1e4, why="either sign; magnetorquers are 1-400 A m^2"),
              scenario=S(f"{body}.dipole"))
        p.add(f"{body}_rand_std", 1, "N m", doc[3], default=0.3,
              bounds=Bounds(0.0, 100.0, why="000's 0.3 N m is already large; 100 N m keeps a typo visible"),
              scenario=S(f"environment.random_torque_std_{body}"), presets=full_default)
        p.add(f"{body}_cd", 1, "-", f"{body} drag coefficient", default=cd,
              bounds=Bounds(0.0, 10.0, lo_open=True, why="free-molecular C_D is 2-4"),
              scenario=S(f"{body}.drag_cd"))
        p.add(f"{body}_area", 1, "m^2", f"{body} drag area", default=area,
              bounds=Bounds(0.0, 1e4, lo_open=True, why="up to the ISS's arrays (2500 m^2)"),
              scenario=S(f"{body}.drag_area"))
    # reaction wheels (000 Table 3)
    p.add("wheel_beta", 1, "rad", "pyramid tilt (000 eq. 47)", default=30 * DEG,
          bounds=Bounds(0.0, 90 * DEG, lo_open=True, hi_open=True, why="a pyramid that spans 3 axes"),
          scenario=S("wheels.tilt_deg", "deg", DEG),
          presets=full_default)
    p.add("wheel_inertia", 1, "kg m^2", "wheel axial inertia", default=0.001364,
          bounds=Bounds(1e-6, 10.0, why="a CubeSat wheel (1e-6) to a CMG rotor; smaller makes h_w / J_w overflow"),
          scenario=S("wheels.inertia"), presets=full_default)
    p.add("wheel_torque_max", 1, "N m", "per-wheel torque limit", default=0.1,
          bounds=Bounds(0.0, 100.0, lo_open=True, why="a CubeSat wheel (1e-4 N m) to a large CMG"),
          scenario=S("wheels.max_torque"), presets=full_default)
    p.add("wheel_speed_max", 1, "rad/s", "per-wheel speed limit (7000 rpm)", default=7000 * 2 * math.pi / 60,
          bounds=Bounds(0.0, 50000 * RPM, lo_open=True, why="up to 50000 rpm (wheels run at 2000-10000 rpm)"),
          scenario=S("wheels.max_speed_rpm", "rpm", RPM), presets=full_default)
    # upper limit: the delay line (manifest delay_slots steps), checked with the step by the runtime
    p.add("wheel_delay", 1, "s", "wheel transport delay", default=0.002,
          bounds=Bounds(0.0, 10.0, why="below the delay line, checked with the step"), scenario=S("wheels.delay"),
          presets=full_default)
    # misalignment (rpo's model, not 000's): the true wheel axes and thruster directions are the
    # nominal ones rotated by these rotation vectors (actuators.rotation_offset); the allocations
    # keep the nominal geometry.  Not in the "full" preset: 000 has none, and --plant full must not
    # erase a dispersion the scenario sets.
    misalign = Bounds(-10 * DEG, 10 * DEG, why="a mounting error, not a different layout (real ones are 0.01-1 "
                      "deg); up to 10 deg per axis the rotation angle, 2 atan(t/2) for t the norm of theta, is "
                      "within 0.8 % of t")
    p.add("wheel_misalign", 12, "rad", "wheel spin-axis misalignment: rotation vector of each wheel's true axis "
          "from its nominal one (Cayley form, actuators.rotation_offset), body axes",
          tuple(f"{w}_{a}" for w in WHEELS for a in XYZ), default=(0.0,) * 12, bounds=misalign,
          scenario=S("wheels.misalignment_deg", "deg", DEG))
    # thrusters (000 Table 3)
    p.add("thruster_force", 1, "N", "thrust of one thruster", default=1.0,
          bounds=Bounds(0.0, 1e4, lo_open=True, why="a micro-thruster (mN) to a main engine"),
          scenario=S("thrusters.max_force"), presets=full_default)
    p.add("thruster_isp", 1, "s", "specific impulse", default=227.0,
          bounds=Bounds(1.0, 1e5, why="cold gas (60 s) to ion engines (1e4 s); m_dot = F / (Isp g0)"),
          scenario=S("thrusters.isp"),
          presets=full_default)
    p.add("thruster_misalign", 48, "rad", "thruster force-direction misalignment: rotation vector of each "
          "thruster's true direction from its nominal one (Cayley form, about its mounting point), body axes",
          tuple(f"{j}_{a}" for j in THRUSTERS for a in XYZ), default=(0.0,) * 48, bounds=misalign,
          scenario=S("thrusters.misalignment_deg", "deg", DEG))
    # u_off < u_on is checked by the runtime (a relation between two fields)
    pwpf_bounds = {"pwpf_km": Bounds(0.0, 1e4, lo_open=True, why="a prefilter gain; 000 uses 10"),
                   "pwpf_tm": Bounds(1e-6, 1e4, why="a time constant (the filter step is exact)"),
                   "pwpf_uon": Bounds(0.0, 1e4, lo_open=True, why="a trigger level in filter units"),
                   "pwpf_uoff": Bounds(0.0, 1e4, lo_open=True, why="a trigger level in filter units")}
    for name, key, unit, doc, default in (("pwpf_km", "k_m", "-", "PWPF prefilter gain K_m", 10.0),
                                          ("pwpf_tm", "t_m", "s", "PWPF prefilter time constant T_m", 0.2),
                                          ("pwpf_uon", "u_on", "-", "Schmitt trigger on level U_on", 0.25),
                                          ("pwpf_uoff", "u_off", "-", "Schmitt trigger off level U_off", 0.15)):
        p.add(name, 1, unit, doc, default=default, bounds=pwpf_bounds[name], scenario=S(f"thrusters.pwpf.{key}"),
              presets=full_default)
    # simulation
    p.add("dt", 1, "s", "control and integration step", default=0.01,
          bounds=Bounds(1e-5, 10.0, why="0.1 Hz to 100 kHz; the papers use 100-200 Hz"),
          scenario=S("simulation.rate", "Hz", kind="reciprocal"))
    _fault_params(p)
    return p


def _fault_params(p: Layout) -> None:
    """The fault windows and values of :mod:`rpo.symbolic.physics.faults`, set by the scenario's
    ``[[faults]]`` array (``runtime/scenario/faults.py``), and the FDIR switch."""
    never = flt.NEVER
    window = Bounds(0.0, never, why=f"a time from t = 0; the default {never:g} s means never")
    for family in flt.FAMILIES:
        names = family.units
        for kind in flt.kinds_of(family):
            for edge in ("start", "end"):
                p.add(kind.window(edge), len(names), "s", f"{family.prefix} {kind.param} fault: window {edge} time "
                      f"(never: {never:g})", names, default=(never,) * len(names), bounds=window)
    fraction = Bounds(0.0, 1.0, lo_open=True, why="the fraction left of the nominal value; none left is the _off kind")
    p.add(flt.value_of("wheel_weak").param, 4, "-", "weak wheel: fraction of the torque limit left", WHEELS,
          default=(1.0,) * 4, bounds=fraction)
    p.add(flt.value_of("thruster_weak").param, 16, "-", "weak thruster: fraction of the thrust left", THRUSTERS,
          default=(1.0,) * 16, bounds=fraction)
    # the units and ranges of the nominal sensor noise and bias (declared once, above)
    nominal = {f.name: f for f in p.fields}
    step, noise = flt.value_of("sensor_bias"), flt.value_of("sensor_noise")
    for s in (s.short for s in flt.SENSORS):
        bias, std = nominal[f"meas_{s}_bias"], nominal[f"meas_{s}_std"]
        p.add(step.param_of(s), 3, bias.unit, f"{s} sensor bias step (added to meas_{s}_bias)", XYZ,
              default=(0.0,) * 3, bounds=bias.bounds)
        p.add(noise.param_of(s), 1, std.unit, f"{s} sensor noise std during a noise fault", default=0.0,
              bounds=std.bounds)
    p.add("fdir_allocation", 1, "-", "fault-aware allocation over the healthy units (1, rpo's FDIR model) "
          "or the nominal allocation (0)", default=0,
          scenario=ScenarioKey("fdir.allocation", kind="choice", choices=(("nominal", 0.0), ("healthy", 1.0))))


def _state() -> Layout:
    x = Layout("x")
    x.add("q_c", 4, "-", "chaser attitude relative to ECI (scalar last)", XYZW)
    x.add("w_c", 3, "rad/s", "chaser body rate relative to ECI, body axes", XYZ)
    x.add("h_w", 4, "N m s", "wheel axial angular momenta (absolute)", WHEELS)
    x.add("q_t", 4, "-", "target attitude relative to ECI (scalar last)", XYZW)
    x.add("w_t", 3, "rad/s", "target body rate relative to ECI, body axes", XYZ)
    x.add("r", 3, "m", "chaser position relative to target, LVLH", XYZ)
    x.add("v", 3, "m/s", "chaser velocity relative to target, LVLH-frame derivative", XYZ)
    x.add("m_prop", 1, "kg", "propellant used")
    # the target's own orbit (rpo's full plant, plant.target_orbit = "propagated"; with "kepler",
    # 000's formulation, these are integrated but nothing reads them)
    x.add("r_T", 3, "m", "target position, ECI (propagated target orbit)", XYZ)
    x.add("v_T", 3, "m/s", "target velocity, ECI (propagated target orbit)", XYZ)
    return x


def _input() -> Layout:
    u = Layout("u")
    u.add("T_w", 4, "N m", "wheel torques on the body (delayed command)", WHEELS)
    u.add("thr_on", 16, "-", "thruster thrust levels (PWPF on-level 0 or 1, after faults: a fraction)", THRUSTERS)
    u.add("F_ideal", 3, "N", "force of the ideal actuators, chaser body", XYZ)
    u.add("tau_ideal", 3, "N m", "torque of the ideal actuators, chaser body", XYZ)
    u.add("wheel_locked", 4, "-", "wheels locked to the body (1; the wheel_stuck fault) or free (0)", WHEELS,
          default=(0, 0, 0, 0))
    return u


def _noise() -> Layout:
    w = Layout("w")
    w.add("n_c", 3, "-", "standard-normal sample for the chaser random torque", XYZ)
    w.add("n_t", 3, "-", "standard-normal sample for the target random torque", XYZ)
    w.add("n_att", 3, "-", "standard-normal sample for the attitude measurement noise", XYZ)
    w.add("n_rate", 3, "-", "standard-normal sample for the rate measurement noise", XYZ)
    w.add("n_pos", 3, "-", "standard-normal sample for the position measurement noise", XYZ)
    w.add("n_vel", 3, "-", "standard-normal sample for the velocity measurement noise", XYZ)
    return w


def _measurement() -> Layout:
    m = Layout("meas")
    m.add("q_c", 4, "-", "chaser attitude relative to ECI", XYZW)
    m.add("w_c", 3, "rad/s", "chaser body rate relative to ECI, body axes", XYZ)
    m.add("q_t", 4, "-", "target attitude relative to ECI", XYZW)
    m.add("w_t", 3, "rad/s", "target body rate relative to ECI, body axes", XYZ)
    m.add("r", 3, "m", "relative position, LVLH", XYZ)
    m.add("v", 3, "m/s", "relative velocity, LVLH", XYZ)
    m.add("q_L", 4, "-", "LVLH frame relative to ECI (identity in free space)", XYZW)
    m.add("n", 1, "rad/s", "LVLH rate (true-anomaly rate; 0 in free space)")
    m.add("n_dot", 1, "rad/s^2", "LVLH angular acceleration (0 in free space)")
    m.add("r_t", 1, "m", "target orbit radius")
    m.add("r_t_dot", 1, "m/s", "target orbit radius rate")
    m.add("nu", 1, "rad", "target true anomaly")
    m.add("h_rw", 3, "N m s", "wheel angular momentum, chaser body", XYZ)
    m.add("q_e", 4, "-", "chaser attitude relative to the interface frame (000 eq. 22)", XYZW)
    m.add("w_e", 3, "rad/s", "rate error, chaser axes (000 eq. 17)", XYZ)
    m.add("q_cL", 4, "-", "chaser attitude relative to the LVLH frame", XYZW)
    return m


#: The measurement fields of the sensors a fault can name (faults.SENSORS, in order).
SENSOR_FIELDS = tuple(s.field for s in flt.SENSORS)


def _sensor_hold() -> Layout:
    """The last value each sensor gave (a frozen sensor repeats it; rpo's sensor_freeze fault)."""
    h = Layout("hold")
    h.add("sensor_q_c", 4, "-", "last chaser attitude the attitude sensor gave", XYZW)
    h.add("sensor_w_c", 3, "rad/s", "last chaser rate the rate sensor gave", XYZ)
    h.add("sensor_r", 3, "m", "last relative position the position sensor gave", XYZ)
    h.add("sensor_v", 3, "m/s", "last relative velocity the velocity sensor gave", XYZ)
    return h


def _env_outputs() -> Layout:
    y = Layout("env")
    y.add("nu", 1, "rad", "target true anomaly")
    y.add("r_t", 1, "m", "target orbit radius")
    y.add("n", 1, "rad/s", "LVLH rate")
    y.add("m_c", 1, "kg", "chaser mass")
    y.add("I_c_diag", 3, "kg m^2", "chaser inertia diagonal", XYZ)
    y.add("wheel_speed", 4, "rad/s", "wheel speeds relative to the body", WHEELS)
    y.add("M_gg_c", 3, "N m", "gravity-gradient torque on the chaser, body", XYZ)
    y.add("M_gg_t", 3, "N m", "gravity-gradient torque on the target, body", XYZ)
    y.add("M_mag_t", 3, "N m", "magnetic torque on the target, body", XYZ)
    y.add("a_d", 3, "m/s^2", "differential disturbance acceleration, LVLH (000 eq. 45)", XYZ)
    y.add("F_thr", 3, "N", "thruster force, chaser body", XYZ)
    y.add("tau_thr", 3, "N m", "thruster torque, chaser body", XYZ)
    y.add("F_applied", 3, "N", "control force on the chaser (thrusters or ideal), body", XYZ)
    y.add("tau_applied", 3, "N m", "control torque on the chaser (wheel motors, thrusters or ideal; not a locked "
          "wheel's reaction), body", XYZ)
    y.add("F_dist", 3, "N", "scenario disturbance force, chaser body", XYZ)
    y.add("tau_dist", 3, "N m", "scenario disturbance torque, chaser body", XYZ)
    y.add("beta_fov", 1, "m", "001 eq. 41 field-of-view margin (camera on body +z; > 0 in view)")
    y.add("beta_ca", 1, "m^2", "001 eq. 47 collision margin (> 0 clear)")
    return y


@dataclass
class Plant:
    """Symbols and expressions of the 000 plant."""

    p: Layout
    x: Layout
    u: Layout
    w: Layout
    meas: Layout
    env: Layout
    t: sp.Symbol
    hold: Layout

    def orbit(self, t=None):
        """Target orbit quantities at t (default: the time symbol)."""
        p = self.p
        return orb.target_orbit(self.t if t is None else t, p["mu"], p["orbit_a"], p["orbit_e"],
                                p["orbit_inc"], p["orbit_raan"], p["orbit_argp"], p["orbit_nu0"])

    def lvlh_attitude(self, o):
        """q_{L/ECI}: quaternion of C_{ECI<-LVLH} = R3(raan) R1(inc) R3(u) (exact, no DCM->quat)."""
        p = self.p

        def axis(k, ang):
            e = [0, 0, 0]
            e[k] = sp.sin(ang / 2)
            return sp.Matrix([*e, sp.cos(ang / 2)])

        u_lat = p["orbit_argp"] + o["nu"]
        return quat_mul(quat_mul(axis(2, p["orbit_raan"]), axis(0, p["orbit_inc"])), axis(2, u_lat))

    def target_perturbation(self, r_eci, v_eci):
        """The target's perturbing acceleration [m/s^2], ECI: J2 and drag (its mass, C_D, area)."""
        p = self.p
        return self._perturbation(r_eci, v_eci, p["target_mass"], p["target_cd"], p["target_area"])

    def _perturbation(self, r_eci, v_eci, mass, cd, area):
        """J2 (000 eq. 37 corrected) and drag (eqs. 38-44 corrected) on one body [m/s^2], ECI."""
        p = self.p
        a_j2 = env.j2_acceleration(p["mu"], p["j2"], p["r_earth"], r_eci)
        rho = env.atmosphere_density(env.altitude(r_eci, p["r_earth"], p["earth_flattening"]))
        a_drag = env.drag_acceleration(rho, cd, area, mass, r_eci, v_eci, p["omega_earth"])
        return p["j2_on"] * a_j2 + p["drag_on"] * a_drag

    def target_frame(self):
        """The target's orbit and LVLH frame at t (the keys of :func:`.orbit.target_orbit`, plus
        ``w_x``, ``w_x_dot``, ``q_IL`` and ``a_p``, the target's perturbing acceleration).

        ``orbit_propagated`` (0 or 1, validated) picks 000's Keplerian target (Kepler's equation
        at t; the perturbations act on r, v only through their difference, eq. 45) or the target's
        own propagated state r_T, v_T (:mod:`.target_orbit_state`); the blend is exact for 0 and 1.
        """
        p, x = self.p, self.x
        g = p["orbit_propagated"]
        kep = self.orbit()
        kep["q_IL"] = self.lvlh_attitude(kep)
        kep["a_p"] = self.target_perturbation(kep["r_eci"], kep["v_eci"])
        r_T, v_T = x["r_T"], x["v_T"]
        a_p = self.target_perturbation(r_T, v_T)
        a_T = -p["mu"] * r_T / norm(r_T) ** 3 + a_p
        prop = tos.propagated_orbit(p["mu"], r_T, v_T, a_p, tos.perturbation_rate(a_p, r_T, v_T, v_T, a_T))
        prop["q_IL"] = tos.dcm_to_quat(prop["C_IL"])
        prop["a_p"] = a_p
        kep["w_x"] = kep["w_x_dot"] = sp.S.Zero
        out = {k: g * prop[k] + (1 - g) * kep[k] for k in kep}
        out["a_T"] = a_T  # the propagated target's acceleration (its state's derivative)
        return out

    def reference_frame(self, o):
        """The frame of r, v: the target's LVLH frame, or in free space (gravity_on = 0) a frame
        fixed in ECI.  Returns (q_L/ECI, C_ECI<-L, its rate w_L and angular acceleration
        w_L_dot relative to ECI, LVLH components: [w_x, 0, n], w_x = 0 for a Keplerian target).

        ``gravity_on`` is 0 or 1 (validated by the scenario), so the blends below are exact.
        """
        g = self.p["gravity_on"]
        q_L = g * o["q_IL"] + (1 - g) * vec(0, 0, 0, 1)
        C_IL = g * o["C_IL"] + (1 - g) * sp.eye(3)
        return q_L, C_IL, vec(g * o["w_x"], 0, g * o["n"]), vec(g * o["w_x_dot"], 0, g * o["n_dot"])

    def scenario_disturbance(self, kind: str, nu) -> sp.Matrix:
        """The papers' disturbance models (002 sec. 4, 004 sec. 5, 001 sec. 7) in chaser body axes.

        Per axis: c0 + a1 sin(w1 t) + b1 cos(w1 t) + a2 sin(w2 t) + b2 cos(w2 t) + s_nu sin(nu) + c_nu cos(nu).
        """
        p, t = self.p, self.t

        def c(name):
            return p[f"dist_{kind}_{name}"]

        return sp.Matrix([
            c("c0")[i] + c("a1")[i] * sp.sin(c("w1")[i] * t) + c("b1")[i] * sp.cos(c("w1")[i] * t)
            + c("a2")[i] * sp.sin(c("w2")[i] * t) + c("b2")[i] * sp.cos(c("w2")[i] * t)
            + c("s_nu")[i] * sp.sin(nu) + c("c_nu")[i] * sp.cos(nu)
            for i in range(3)])

    def mass_properties(self):
        p = self.p
        return chaser_mass_properties(self.t, p["chaser_mass"], inertia_tensor(p["chaser_inertia"]),
                                      p["mass_profile_on"])

    def _terms(self):
        """Every intermediate quantity of the right-hand side, by name."""
        p, x, u, w = self.p, self.x, self.u, self.w
        o = self.target_frame()
        _q_L, C_IL, w_L, w_L_dot = self.reference_frame(o)
        n_L, n_dot_L = w_L[2], w_L_dot[2]
        m_c, I_c = self.mass_properties()
        I_t = inertia_tensor(p["target_inertia"])
        # the TRUE wheel axes A + dA and thruster directions (misalignment, docs/actuators.md): every
        # use below is the plant's physics; the allocations (closed_loop.plant_pieces) and the
        # measured wheel momentum (measurement) keep the nominal A.  Bit-identity at zero: the
        # nominal expressions are built exactly as without misalignment and the offsets (exactly
        # 0 at zero) are only ever ADDED to them, never substituted inside a product or a solve,
        # where SymPy could reorder a sum (a different rounding) or expand it (eq. 6's adjugate).
        A = act.pyramid_matrix(p["wheel_beta"])
        dA = act.wheel_axes_offset(p["wheel_beta"], p["wheel_misalign"])
        q_c, w_c, h_w = x["q_c"], x["w_c"], x["h_w"]
        q_t = x["q_t"]
        r, v = x["r"], x["v"]

        Omega = act.wheel_speeds(h_w, p["wheel_inertia"], A, w_c, dA)
        # motor torques; a locked wheel (u wheel_locked = 1) exerts none of its own but turns with the body
        locked = u["wheel_locked"]
        T_w = act.speed_limited_torques(u["T_w"], Omega, p["wheel_speed_max"])
        T_free = sp.Matrix([(1 - locked[i]) * T_w[i] for i in range(4)])
        T_motor = A * T_free + dA * T_free  # the motors' torque on the body (eq. 46, true axes)
        I_locked0 = locked_wheel_inertia(p["wheel_inertia"], A, locked)
        dI_locked = locked_wheel_inertia_offset(p["wheel_inertia"], A, dA, locked)
        F_thr0, tau_thr0 = act.thruster_wrench(u["thr_on"], p["thruster_force"])
        dF_thr, dtau_thr = act.thruster_wrench_misalignment(u["thr_on"], p["thruster_force"], p["thruster_misalign"])
        F_thr, tau_thr = F_thr0 + dF_thr, tau_thr0 + dtau_thr

        r_c_eci, v_c_eci = chaser_inertial_state(o["r_eci"], o["v_eci"], o["C_IL"], vec(o["w_x"], 0, o["n"]), r, v)
        C_Ic, C_It = quat_to_dcm(q_c), quat_to_dcm(q_t)
        rc = norm(r_c_eci)
        rt = o["r"]
        # the whole spacecraft, rotors included (mass_properties.spacecraft_inertia_with_wheels)
        I_gg = spacecraft_inertia_with_wheels(I_c, p["wheel_inertia"], A + dA, 1 - p["actuators_ideal"])
        M_gg_c = p["gg_on"] * env.gravity_gradient_torque(p["mu"], rc, C_Ic.T * r_c_eci / rc, I_gg)
        M_gg_t = p["gg_on"] * env.gravity_gradient_torque(p["mu"], rt, C_It.T * o["r_eci"] / rt, I_t)
        m_hat = vec(0, 0, -1)  # untilted dipole, pointing to geographic south
        B_c = env.dipole_field(p["mu_mag"], r_c_eci, m_hat)
        B_t = env.dipole_field(p["mu_mag"], o["r_eci"], m_hat)
        M_mag_c = p["mag_on"] * env.magnetic_torque(p["chaser_dipole"], C_Ic.T * B_c)
        M_mag_t = p["mag_on"] * env.magnetic_torque(p["target_dipole"], C_It.T * B_t)
        M_r_c = env.random_torque(p["chaser_rand_std"], w["n_c"])
        M_r_t = env.random_torque(p["target_rand_std"], w["n_t"])

        a_c = self._perturbation(r_c_eci, v_c_eci, m_c, p["chaser_cd"], p["chaser_area"])
        a_t = o["a_p"]
        a_d = o["C_IL"].T * env.relative_disturbance(a_c, a_t)
        F_dist = self.scenario_disturbance("force", o["nu"])
        tau_dist = self.scenario_disturbance("torque", o["nu"])
        F_ctrl = F_thr + u["F_ideal"]
        a_ctrl = (C_IL.T * C_Ic * (F_thr0 + u["F_ideal"] + F_dist) / m_c  # nominal thrusters, then their offset
                  + C_IL.T * C_Ic * dF_thr / m_c)

        M_c0 = M_gg_c + M_mag_c + M_r_c + tau_thr0 + u["tau_ideal"] + tau_dist
        M_c = M_c0 + dtau_thr
        M_t = M_gg_t + M_mag_t + M_r_t
        # eq. 6 with the nominal geometry, then the exact change for the true one (rigid_body.py):
        # right-hand side + db (wheel momentum coupling, motor torques, thruster torques), inertia
        # + dI_locked
        w_dot0 = chaser_angular_acceleration(I_c, w_c, A * h_w, A * T_free, M_c0, I_locked0)
        db = -cross(w_c, dA * h_w) + dA * T_free + dtau_thr
        w_dot = w_dot0 + angular_acceleration_offset(I_c + I_locked0, dI_locked, db, w_dot0)
        h_rw = A * h_w + dA * h_w
        I_locked = I_locked0 + dI_locked
        T_c = T_motor - I_locked * w_dot  # the wheels' torque on the body, locked ones included
        return {
            "orbit": o, "m_c": m_c, "I_c": I_c, "I_t": I_t, "A": A, "dA": dA, "Omega": Omega, "T_w": T_w,
            "w_dot": w_dot, "h_w_dot": locked_wheel_momentum_rate(T_w, p["wheel_inertia"], A, locked, w_dot, dA),
            "T_c": T_c, "F_thr": F_thr, "tau_thr": tau_thr, "M_c": M_c, "M_t": M_t,
            "M_gg_c": M_gg_c, "M_gg_t": M_gg_t, "M_mag_t": M_mag_t, "a_d": a_d, "a_ctrl": a_ctrl,
            "h_rw": h_rw, "n_L": n_L, "n_dot_L": n_dot_L, "w_L": w_L, "w_L_dot": w_L_dot, "C_IL": C_IL, "C_Ic": C_Ic,
            "F_ctrl": F_ctrl, "tau_ctrl": T_motor + tau_thr + u["tau_ideal"], "F_dist": F_dist, "tau_dist": tau_dist,
        }

    def rhs(self) -> sp.Matrix:
        """dx/dt as a SymPy column (25)."""
        p, x, u = self.p, self.x, self.u
        k = self._terms()
        o = k["orbit"]
        return self.x.pack({
            "q_c": quat_rate(x["q_c"], x["w_c"]),
            "w_c": k["w_dot"],
            "h_w": k["h_w_dot"],
            "q_t": quat_rate(x["q_t"], x["w_t"]),
            "w_t": target_angular_acceleration(k["I_t"], x["w_t"], k["M_t"]),
            "r": x["v"],
            "v": relative_acceleration(x["r"], x["v"], o["r"], k["n_L"], k["n_dot_L"], p["gravity_on"] * p["mu"],
                                       k["a_ctrl"], k["a_d"])
            + frame_tilt_acceleration(x["r"], x["v"], k["w_L"][0], k["w_L_dot"][0], k["n_L"]),
            "m_prop": act.propellant_flow(u["thr_on"], p["thruster_force"], p["thruster_isp"], p["g0"])
            + act.ideal_propellant_flow(u["F_ideal"], p["thruster_isp"], p["g0"]),
            "r_T": x["v_T"],
            "v_T": o["a_T"],
        })

    def torques(self) -> dict[str, sp.Matrix]:
        """Chaser and target external torques and the wheel torque on the body [N m]."""
        k = self._terms()
        return {"M_c": k["M_c"], "M_t": k["M_t"], "T_c": k["T_c"], "h_rw": k["h_rw"],
                "I_c": k["I_c"], "I_t": k["I_t"]}

    def measurement(self) -> sp.Matrix:
        """Truth plus sensor noise and bias -> what every controller reads (its own variables
        are formed from these in its module).

        Noise (std * standard normal, drawn per step by the runtime) and bias act on the chaser's
        attitude (a small rotation in body axes), its rate, and the relative position and
        velocity.  The target's attitude and rate are passed exactly.
        """
        x, p, w, t = self.x, self.p, self.w, self.t
        o = self.target_frame()
        q_L, _C_IL, w_L, w_L_dot = self.reference_frame(o)
        n_L, n_dot_L = w_L[2], w_L_dot[2]
        # noise and bias, with the sensor faults' windows (faults.py); then a frozen sensor repeats
        # the last value it gave (the step state's sensor hold, self.hold)
        nb = flt.sensor_noise_and_bias(t, p)
        dtheta = nb["att"][0] * w["n_att"] + nb["att"][1]
        dq = vec(dtheta[0] / 2, dtheta[1] / 2, dtheta[2] / 2, 1)
        live = {"att": quat_mul(x["q_c"], dq / norm(dq)),
                "rate": x["w_c"] + nb["rate"][0] * w["n_rate"] + nb["rate"][1],
                "pos": x["r"] + nb["pos"][0] * w["n_pos"] + nb["pos"][1],
                "vel": x["v"] + nb["vel"][0] * w["n_vel"] + nb["vel"][1]}
        held = {s.short: self.hold[f"sensor_{s.field}"] for s in flt.SENSORS}
        out = flt.frozen(t, p, held, live)
        q_c, w_c = out["att"], out["rate"]
        q_e = attitude_error(q_c, x["q_t"])
        g = p["gravity_on"]
        return self.meas.pack({
            "q_c": q_c, "w_c": w_c, "q_t": x["q_t"], "w_t": x["w_t"],
            "r": out["pos"], "v": out["vel"],
            "q_L": q_L, "n": n_L, "n_dot": n_dot_L, "r_t": o["r"], "r_t_dot": g * o["r_dot"], "nu": o["nu"],
            # what the flight software computes from the wheels' momenta: the NOMINAL axes (it does
            # not know the misalignment; the plant's h_rw uses the true ones)
            "h_rw": act.pyramid_matrix(p["wheel_beta"]) * x["h_w"],
            "q_e": q_e,
            "w_e": rate_error(q_e, w_c, x["w_t"]),
            "q_cL": quat_mul(quat_conj(q_L), q_c),
        })

    def sensor_hold_next(self, meas: sp.Matrix) -> sp.Matrix:
        """The sensor hold after a step: the values the sensors gave (``meas``'s q_c, w_c, r, v)."""
        offs = self.meas.offsets()
        return sp.Matrix([meas[i] for f in SENSOR_FIELDS for i in range(*offs[f][:2])])

    def env_outputs(self) -> sp.Matrix:
        """Logged environment and actuator quantities at the start of a step."""
        k = self._terms()
        o = k["orbit"]
        p = self.p
        # target centroid relative to the chaser, chaser body axes (001 sec. 5)
        p_TS = -(k["C_Ic"].T * k["C_IL"] * self.x["r"])
        return self.env.pack({
            "nu": o["nu"], "r_t": o["r"], "n": o["n"], "m_c": k["m_c"],
            "I_c_diag": sp.Matrix([k["I_c"][i, i] for i in range(3)]),
            "wheel_speed": k["Omega"], "M_gg_c": k["M_gg_c"], "M_gg_t": k["M_gg_t"],
            "M_mag_t": k["M_mag_t"], "a_d": k["a_d"], "F_thr": k["F_thr"], "tau_thr": k["tau_thr"],
            "F_applied": k["F_ctrl"], "tau_applied": k["tau_ctrl"], "F_dist": k["F_dist"], "tau_dist": k["tau_dist"],
            "beta_fov": beta_fov(p_TS, p["camera_half_angle"], p["camera_zn"], p["target_radius"]),
            "beta_ca": beta_ca(p_TS, p["chaser_radius"], p["target_radius"]),
        })


def make_plant() -> Plant:
    """Fresh symbols and layouts of the 000 plant."""
    return Plant(_params(), _state(), _input(), _noise(), _measurement(), _env_outputs(),
                 sp.Symbol("t", real=True), _sensor_hold())
