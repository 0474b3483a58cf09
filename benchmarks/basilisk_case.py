"""Basilisk's speed on the single-spacecraft case it shares with rpo (for benchmarks/bench_step.py).

    python benchmarks/basilisk_case.py [--duration 300] [--dt 0.01] [--repeat 3]

Needs the optional extra ``bench`` (``pip install -e '.[bench]'``, which installs Basilisk as the
PyPI package ``bsk``).  One spacecraft with the mass and inertia of rpo's chaser (scenario III and
the manifest defaults, read through rpo's scenario reader; nothing else of rpo is used) on
scenario III's target orbit:

* ``spacecraft.Spacecraft`` hub: rpo's ``chaser_mass`` and full ``chaser_inertia`` tensor I_c plus the
  wheels' spin inertia J_s sum a a^T (Basilisk's balanced wheels belong to the hub's inertia:
  tests/basilisk_map.py; constant: Basilisk has no counterpart of rpo's time-varying mass
  profile), centre of mass at the body origin;
* Earth gravity: point mass plus J2, as Basilisk's spherical-harmonics model of degree 2 with the
  only non-zero coefficients C00 = 1 and the normalised C20 = -J2 / sqrt(5) (rpo's ``mu``, ``j2``,
  ``r_earth``; no coefficient file, so no data download);
* ``GravityGradientEffector`` about the Earth;
* four reaction wheels (``reactionWheelStateEffector``, balanced wheels) along the columns of rpo's
  pyramid matrix A* (000 eq. 47, tilt ``wheel_beta``), spin inertia ``wheel_inertia`` and no
  transverse inertia (the mapping of tests/basilisk_map.py), torque limit
  ``wheel_torque_max``, speed limit ``wheel_speed_max``, at rest at t = 0, driven by a constant
  motor-torque command (``WHEEL_TORQUE`` per wheel, signs +, -, +, -) written once to a stand-alone
  message: no flight software in the loop.  That command lies in the null space of A* (opposite
  wheels cancel), so the wheels spin up while the net wheel torque on the hub is zero and the hub's
  rate comes from the gravity gradient alone (which the test uses as a check);
* ``svIntegratorRK4`` at ``dt``; one task holding the wheels, the gravity-gradient module and the
  spacecraft; no recorders, no Vizard, no SPICE.

Only ``ExecuteSimulation()`` is timed (building and ``InitializeSimulation()`` are not); each of the
``repeat`` runs builds a fresh simulation and the median is returned.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
# rpo <-> Basilisk conventions (quaternions/MRPs, wheel speeds/momenta, inertias, LVLH): one module
sys.path.insert(0, str(ROOT / "tests"))
import basilisk_map as bmap  # noqa: E402

SCENARIO = ROOT / "scenarios" / "000_scenario_III.toml"

#: Constant motor torque per wheel [N m], signs (+, -, +, -): 0.6 N m s after 300 s, below the
#: 1.0 N m s of a wheel at rpo's 7000 rpm limit, so the speed limit never acts.
WHEEL_TORQUE = 0.002

INSTALL_HINT = "pip install -e '.[bench]'"


def _import_basilisk():
    """The Basilisk modules this case uses, and the seconds their import took."""
    t0 = time.perf_counter()
    try:
        import Basilisk
        from Basilisk.architecture import messaging
        from Basilisk.simulation import (
            GravityGradientEffector,
            reactionWheelStateEffector,
            spacecraft,
            sphericalHarmonicsGravityModel,
            svIntegrators,
        )
        from Basilisk.utilities import (
            RigidBodyKinematics,
            SimulationBaseClass,
            macros,
            simIncludeGravBody,
            simIncludeRW,
        )
    except ImportError as exc:
        raise ImportError(f"Basilisk (PyPI package bsk) is not installed: {INSTALL_HINT} ({exc})") from exc
    mods = dict(Basilisk=Basilisk, messaging=messaging, GravityGradientEffector=GravityGradientEffector,
                reactionWheelStateEffector=reactionWheelStateEffector, spacecraft=spacecraft,
                sphericalHarmonicsGravityModel=sphericalHarmonicsGravityModel, svIntegrators=svIntegrators,
                RigidBodyKinematics=RigidBodyKinematics, SimulationBaseClass=SimulationBaseClass, macros=macros,
                simIncludeGravBody=simIncludeGravBody, simIncludeRW=simIncludeRW)
    return mods, time.perf_counter() - t0


def chaser_parameters(scenario: str | Path = SCENARIO) -> dict:
    """rpo's parameters of the case, SI: the scenario's values over the manifest defaults.

    Read through rpo's scenario reader (``load_scenario(...).params()``: the TOML file and
    ``generated/manifest.json``, no compiled model).
    """
    from rpo.runtime.scenario import load_scenario

    sc = load_scenario(scenario)
    p = {k: (float(v[0]) if v.size == 1 else np.asarray(v, float)) for k, v in sc.params().items()}
    p["chaser_quaternion"] = np.asarray(sc.chaser.quaternion, float)  # scalar last, relative to the frame below
    p["chaser_attitude_frame"] = sc.chaser.attitude_frame
    p["chaser_rate"] = np.asarray(sc.chaser.rate_rad_s(), float)  # body axes
    p["chaser_rate_relative_to"] = sc.chaser.angular_velocity_relative_to  # "eci" or "attitude_frame"
    p["scenario"] = Path(str(scenario)).name
    return p


def kepler_state(mu: float, a: float, e: float, inc: float, raan: float, argp: float, nu: float):
    """ECI position [m] and velocity [m/s] from classical elements."""
    pr = a * (1 - e * e)
    r = pr / (1 + e * math.cos(nu))
    r_pf = np.array([r * math.cos(nu), r * math.sin(nu), 0.0])
    v_pf = math.sqrt(mu / pr) * np.array([-math.sin(nu), e + math.cos(nu), 0.0])

    def r3(x):
        c, s = math.cos(x), math.sin(x)
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])

    def r1(x):
        c, s = math.cos(x), math.sin(x)
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])

    C = r3(raan) @ r1(inc) @ r3(argp)
    return C @ r_pf, C @ v_pf


def initial_attitude(p: dict, r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """C_{ECI<-B} of the chaser at t = 0 (rpo's frames: "orbit" = X along-track, Z nadir)."""
    return bmap.frame_dcm(p["chaser_attitude_frame"], r, v) @ bmap.dcm_from_quat(p["chaser_quaternion"])


def initial_rate(p: dict, r: np.ndarray, v: np.ndarray, C_IB: np.ndarray) -> np.ndarray:
    """omega_BN in body axes at t = 0 [rad/s]: the scenario's rate, plus the frame's own rate
    (the orbit rate about the orbit normal) when it is given relative to an LVLH-fixed frame."""
    w = np.asarray(p["chaser_rate"], float)
    if p["chaser_rate_relative_to"] == "attitude_frame" and p["chaser_attitude_frame"] != "eci":
        w = w + C_IB.T @ bmap.lvlh_dcm(r, v) @ bmap.lvlh_rate(r, v)
    return w


pyramid_axes = bmap.pyramid_axes
inertia_tensor = bmap.inertia_tensor


# --------------------------------------------------------------------------- building blocks
# (also used by tests/test_xcheck_basilisk.py; every rpo <-> Basilisk conversion is in tests/basilisk_map.py)


def set_hub(sc, p: dict, r: np.ndarray, v: np.ndarray, q_IB: np.ndarray, omega: np.ndarray,
            wheels: bool = True) -> None:
    """The hub of ``sc``: rpo's chaser mass, and its inertia as basilisk_map.basilisk_inertias maps it
    (I_c + J_s A A^T with ``wheels``: Basilisk's balanced wheels belong to the hub's inertia; I_c
    without), centre of mass at the body origin, ECI position/velocity [m, m/s], attitude of rpo's
    q_B/ECI, body rate [rad/s]."""
    inert = bmap.basilisk_inertias(inertia_tensor(p["chaser_inertia"]), p["wheel_inertia"] if wheels else 0.0,
                                   pyramid_axes(p["wheel_beta"]))
    sc.hub.mHub = p["chaser_mass"]
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = inert["hub"].tolist()
    sc.hub.r_CN_NInit = [[x] for x in r]
    sc.hub.v_CN_NInit = [[x] for x in v]
    sc.hub.sigma_BNInit = [[x] for x in bmap.quat_to_mrp(q_IB)]
    sc.hub.omega_BN_BInit = [[x] for x in omega]


def add_earth(p: dict, bsk: dict, spacecraft: list, j2: bool = True) -> dict:
    """Earth as the central body of every spacecraft in ``spacecraft``: point mass (rpo's ``mu``),
    plus J2 as a degree-2 spherical-harmonics field (normalised C20 = -J2 / sqrt(5)) when ``j2``."""
    grav = bsk["simIncludeGravBody"].gravBodyFactory()
    earth = grav.createEarth()
    earth.isCentralBody = True
    earth.mu = p["mu"]
    earth.radEquator = p["r_earth"]
    sh = None
    if j2:
        sh = bsk["sphericalHarmonicsGravityModel"].SphericalHarmonicsGravityModel()
        sh.muBody = p["mu"]
        sh.radEquator = p["r_earth"]
        sh.maxDeg = 2
        sh.cBar = [[1.0], [0.0, 0.0], [-p["j2"] / math.sqrt(5.0), 0.0, 0.0]]
        sh.sBar = [[0.0], [0.0, 0.0], [0.0, 0.0, 0.0]]
        earth.gravityModel = sh
    for sc in spacecraft:
        grav.addBodiesTo(sc)
    return dict(grav=grav, earth=earth, sh=sh)


def add_wheels(sc, p: dict, bsk: dict, omega_rpm, torques) -> dict:
    """rpo's four pyramid wheels on ``sc`` (balanced, Js = wheel_inertia, Jt = Jg = 0: the mapping of
    basilisk_map.basilisk_inertias, with the hub of ``set_hub(..., wheels=True)``), initial speeds
    relative to the body [rpm], and a constant motor-torque command [N m] written once to a
    stand-alone message."""
    messaging = bsk["messaging"]
    A = pyramid_axes(p["wheel_beta"])
    inert = bmap.basilisk_inertias(inertia_tensor(p["chaser_inertia"]), p["wheel_inertia"], A)
    rw_factory = bsk["simIncludeRW"].rwFactory()
    for axis, om in zip(A.T, omega_rpm, strict=True):
        w = rw_factory.create("custom", list(axis), Js=inert["Js"], u_max=float(p["wheel_torque_max"]),
                              Omega_max=float(p["wheel_speed_max"] / bmap.RPM), Omega=float(om),
                              RWModel=messaging.BalancedWheels)
        w.Jt, w.Jg = inert["Jt"], inert["Jg"]  # the factory's default is Js / 2
    rw = bsk["reactionWheelStateEffector"].ReactionWheelStateEffector()
    rw_factory.addToSpacecraft("wheels", rw, sc)
    cmd = messaging.ArrayMotorTorqueMsgPayload()
    cmd.motorTorque = [float(t) for t in torques]
    cmd_msg = messaging.ArrayMotorTorqueMsg().write(cmd)
    rw.rwMotorCmdInMsg.subscribeTo(cmd_msg)
    return dict(rw=rw, rw_factory=rw_factory, cmd_msg=cmd_msg)


def add_gravity_gradient(sc, bsk: dict, earth):
    """Basilisk's gravity-gradient torque about ``earth`` on ``sc`` (it uses the whole spacecraft's inertia)."""
    gg = bsk["GravityGradientEffector"].GravityGradientEffector()
    gg.ModelTag = "gravityGradient"
    gg.addPlanetName(earth.planetName)
    sc.addDynamicEffector(gg)
    return gg


def build(p: dict, dt: float, duration: float, bsk: dict):
    """A Basilisk simulation of the case, initialised; returns (sim, handles)."""
    sbc, macros = bsk["SimulationBaseClass"], bsk["macros"]
    sim = sbc.SimBaseClass()
    sim.SetProgressBar(False)
    proc = sim.CreateNewProcess("dynamics")
    task = "dyn"
    proc.addTask(sim.CreateNewTask(task, macros.sec2nano(dt)))

    r0, v0 = kepler_state(p["mu"], p["orbit_a"], p["orbit_e"], p["orbit_inc"], p["orbit_raan"],
                          p["orbit_argp"], p["orbit_nu0"])
    C_IB = initial_attitude(p, r0, v0)

    sc = bsk["spacecraft"].Spacecraft()
    sc.ModelTag = "chaser"
    set_hub(sc, p, r0, v0, bmap.quat_from_dcm(C_IB), initial_rate(p, r0, v0, C_IB))
    integrator = bsk["svIntegrators"].svIntegratorRK4(sc)
    sc.setIntegrator(integrator)
    earth = add_earth(p, bsk, [sc], j2=True)
    gg = add_gravity_gradient(sc, bsk, earth["earth"])
    wheels = add_wheels(sc, p, bsk, [0.0] * 4, [WHEEL_TORQUE, -WHEEL_TORQUE, WHEEL_TORQUE, -WHEEL_TORQUE])

    # higher priority runs first: wheel commands, then the gravity-gradient module, then the hub
    sim.AddModelToTask(task, wheels["rw"], None, 3)
    sim.AddModelToTask(task, gg, None, 2)
    sim.AddModelToTask(task, sc, None, 1)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(duration))
    # keep every SWIG object alive as long as the simulation
    return sim, dict(sc=sc, integrator=integrator, **earth, gg=gg, **wheels, r0=r0, v0=v0, C_IB0=C_IB)


def describe(p: dict, dt: float, duration: float) -> str:
    I = bmap.basilisk_inertias(inertia_tensor(p["chaser_inertia"]), p["wheel_inertia"],
                               pyramid_axes(p["wheel_beta"]))["hub"]
    return (f"Basilisk: 1 spacecraft (hub m = {p['chaser_mass']:g} kg, I = I_c + J_s A A^T = "
            f"{np.round(I, 6).tolist()} kg m^2, constant), "
            f"Earth point mass + J2 (spherical harmonics degree 2, mu = {p['mu']:.10g}, J2 = {p['j2']:.9g}, "
            f"R = {p['r_earth']:g} m), gravity-gradient torque, 4 balanced reaction wheels in rpo's pyramid "
            f"(tilt {math.degrees(p['wheel_beta']):g} deg, Js = {p['wheel_inertia']:g} kg m^2, "
            f"u_max = {p['wheel_torque_max']:g} N m, Omega_max = {p['wheel_speed_max'] * 60 / (2 * math.pi):g} rpm) "
            f"with a constant command of +-{WHEEL_TORQUE:g} N m, svIntegratorRK4 at dt = {dt:g} s, {duration:g} s "
            f"({int(round(duration / dt))} steps), orbit of {p['scenario']} (a = {p['orbit_a']:.7g} m, "
            f"e = {p['orbit_e']:g}, i = {math.degrees(p['orbit_inc']):g} deg), no recorders")


def basilisk_us_per_step(duration: float = 300.0, dt: float = 0.01, repeat: int = 3,
                         scenario: str | Path = SCENARIO) -> dict:
    """Median wall-clock microseconds per step of Basilisk's ``ExecuteSimulation()`` on the case.

    Returns ``us_per_step``, ``steps``, ``run_s`` (the median run), ``runs_s`` (every run),
    ``setup_s`` (median of building + ``InitializeSimulation()``, not timed in ``us_per_step``),
    ``import_s`` (importing Basilisk's modules; near 0 when already imported in this process),
    ``basilisk_version``, ``configuration`` (text), ``params`` (rpo's values used), and the
    spacecraft's state: ``r0_N``, ``v0_N`` (ECI, m and m/s) and ``dcm_NB0`` (C_{ECI<-B}) at t = 0, and
    after the last run ``r_N``, ``v_N``, ``omega_BN_B`` (rad/s, body), ``sigma_BN`` (MRP) and
    ``wheel_speeds`` (rad/s, relative to the hub).
    """
    bsk, import_s = _import_basilisk()
    p = chaser_parameters(scenario)
    steps = int(round(duration / dt))
    runs, setups = [], []
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        sim, h = build(p, dt, duration, bsk)
        t1 = time.perf_counter()
        sim.ExecuteSimulation()
        t2 = time.perf_counter()
        setups.append(t1 - t0)
        runs.append(t2 - t1)
    state = h["sc"].scStateOutMsg.read()
    rw_speeds = h["rw"].rwSpeedOutMsg.read().wheelSpeeds[:4]
    run_s = statistics.median(runs)
    return {
        "us_per_step": run_s / steps * 1e6,
        "steps": steps,
        "run_s": run_s,
        "runs_s": runs,
        "setup_s": statistics.median(setups),
        "import_s": import_s,
        "basilisk_version": bsk["Basilisk"].__version__,
        "configuration": describe(p, dt, duration),
        "params": {k: p[k] for k in ("mu", "j2", "r_earth", "chaser_mass", "chaser_inertia", "wheel_beta",
                                     "wheel_inertia", "wheel_torque_max", "wheel_speed_max", "orbit_a", "orbit_e",
                                     "orbit_inc", "orbit_raan", "orbit_argp", "orbit_nu0")},
        "r0_N": h["r0"], "v0_N": h["v0"], "dcm_NB0": h["C_IB0"],
        "r_N": np.array(state.r_BN_N, float), "v_N": np.array(state.v_BN_N, float),
        "omega_BN_B": np.array(state.omega_BN_B, float), "sigma_BN": np.array(state.sigma_BN, float),
        "wheel_speeds": np.array(rw_speeds, float),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenario", default=str(SCENARIO))
    args = ap.parse_args(argv)
    res = basilisk_us_per_step(args.duration, args.dt, args.repeat, args.scenario)
    print(f"Basilisk {res['basilisk_version']}: {res['configuration']}")
    print(f"  import {res['import_s']:.2f} s, setup {res['setup_s']:.3f} s (median, not timed); "
          f"ExecuteSimulation {res['run_s']:.3f} s median of {len(res['runs_s'])} "
          f"({', '.join(f'{t:.3f}' for t in res['runs_s'])}) = {res['us_per_step']:.2f} us/step")
    return 0


if __name__ == "__main__":
    sys.exit(main())
