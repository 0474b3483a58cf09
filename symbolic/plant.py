"""The full-fidelity plant of seed 000: two rigid bodies, wheels, thrusters, orbit and environment.

State x (25): chaser attitude q_c (ECI -> body, scalar last) and body rate w_c; wheel momenta
h_w; target q_t, w_t; relative position r and velocity v of the chaser in the target's LVLH
frame (000 eq. 30); propellant used.  Input u (20): wheel torques on the body T_w (after the
transport delay, before the speed limit) and the 16 thruster on-levels.  Exogenous w (6):
standard-normal samples for the random torques of eq. 5, held over a step.

Everything here is SymPy; :mod:`rpo.symbolic.codegen` translates these very expressions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from . import actuators as act
from . import environment as env
from . import orbit as orb
from .layout import XYZ, XYZW, Layout
from .mass_properties import chaser_mass_properties
from .relative_attitude import attitude_error, rate_error
from .relative_translation import chaser_inertial_state, relative_acceleration
from .rigid_body import chaser_angular_acceleration, target_angular_acceleration, wheel_momentum_rate
from .rotations import norm, quat_conj, quat_mul, quat_rate, quat_to_dcm, vec

INERTIA_COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
WHEELS = ("1", "2", "3", "4")
THRUSTERS = tuple(f"{j:02d}" for j in range(16))
DEG = math.pi / 180


def inertia_tensor(c) -> sp.Matrix:
    """Symmetric 3x3 tensor from (xx, yy, zz, xy, xz, yz) entries [kg m^2]."""
    xx, yy, zz, xy, xz, yz = c
    return sp.Matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _params() -> Layout:
    p = Layout("p")
    # constants (SPEC.md "Common constants")
    p.add("mu", 1, "m^3/s^2", "Earth gravitational parameter", default=3.986004418e14)
    p.add("j2", 1, "-", "Earth J2", default=1.08262668e-3)
    p.add("r_earth", 1, "m", "Earth equatorial radius", default=6378137.0)
    p.add("earth_flattening", 1, "-", "WGS-84 flattening, for the altitude of eq. 39", default=1 / 298.257223563)
    p.add("omega_earth", 1, "rad/s", "Earth rotation rate (atmosphere co-rotation)", default=7.292115e-5)
    p.add("mu_mag", 1, "T m^3", "Earth dipole strength (000 eq. 13)", default=8.1e15)
    p.add("g0", 1, "m/s^2", "standard gravity for Isp", default=9.80665)
    # target orbit (000 scenario III by default)
    p.add("orbit_a", 1, "m", "target semi-major axis", default=(6378137.0 + 400e3) / (1 - 0.138))
    p.add("orbit_e", 1, "-", "target eccentricity, 0 <= e < 1", default=0.138)
    p.add("orbit_inc", 1, "rad", "inclination", default=55 * DEG)
    p.add("orbit_raan", 1, "rad", "right ascension of the ascending node", default=0.0)
    p.add("orbit_argp", 1, "rad", "argument of perigee", default=270 * DEG)
    p.add("orbit_nu0", 1, "rad", "true anomaly at t = 0", default=0.0)
    # model switches (0 or 1)
    p.add("gg_on", 1, "-", "gravity-gradient torques on (1) or off (0)", default=1)
    p.add("mag_on", 1, "-", "magnetic torques on/off", default=1)
    p.add("j2_on", 1, "-", "differential J2 on/off", default=1)
    p.add("drag_on", 1, "-", "differential drag on/off", default=1)
    p.add("mass_profile_on", 1, "-", "000 time-varying chaser mass/inertia on/off", default=1)
    # chaser
    p.add("chaser_mass", 1, "kg", "chaser nominal mass m0", default=100.0)
    p.add("chaser_inertia", 6, "kg m^2", "chaser nominal inertia (no wheel axial inertia)",
          INERTIA_COMPONENTS, default=(11, 14, 13, -0.09, -0.4, -0.08))
    p.add("chaser_dipole", 3, "A m^2", "chaser residual dipole", XYZ, default=(0, 0, 0))
    p.add("chaser_rand_std", 1, "N m", "std of the chaser random torque (000 eq. 5)", default=0.3)
    p.add("chaser_cd", 1, "-", "chaser drag coefficient", default=2.2)
    p.add("chaser_area", 1, "m^2", "chaser drag area", default=1.0)
    # target
    p.add("target_mass", 1, "kg", "target mass", default=5425.0)
    p.add("target_inertia", 6, "kg m^2", "target inertia", INERTIA_COMPONENTS,
          default=(3336, 3184, 2423, -135, -154, -135))
    p.add("target_dipole", 3, "A m^2", "target residual dipole (000 eq. 12)", XYZ, default=(0.3, 0.3, 0.3))
    p.add("target_rand_std", 1, "N m", "std of the target random torque (000 eq. 5)", default=0.3)
    p.add("target_cd", 1, "-", "target drag coefficient", default=2.2)
    p.add("target_area", 1, "m^2", "target drag area", default=20.0)
    # reaction wheels (000 Table 3)
    p.add("wheel_beta", 1, "rad", "pyramid tilt (000 eq. 47)", default=30 * DEG)
    p.add("wheel_inertia", 1, "kg m^2", "wheel axial inertia", default=0.001364)
    p.add("wheel_torque_max", 1, "N m", "per-wheel torque limit", default=0.1)
    p.add("wheel_speed_max", 1, "rad/s", "per-wheel speed limit (7000 rpm)", default=7000 * 2 * math.pi / 60)
    p.add("wheel_delay", 1, "s", "wheel transport delay", default=0.002)
    # thrusters (000 Table 3)
    p.add("thruster_force", 1, "N", "thrust of one thruster", default=1.0)
    p.add("thruster_isp", 1, "s", "specific impulse", default=227.0)
    p.add("pwpf_km", 1, "-", "PWPF prefilter gain K_m", default=10.0)
    p.add("pwpf_tm", 1, "s", "PWPF prefilter time constant T_m", default=0.2)
    p.add("pwpf_uon", 1, "-", "Schmitt trigger on level U_on", default=0.25)
    p.add("pwpf_uoff", 1, "-", "Schmitt trigger off level U_off", default=0.15)
    # simulation
    p.add("dt", 1, "s", "control and integration step", default=0.01)
    return p


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
    return x


def _input() -> Layout:
    u = Layout("u")
    u.add("T_w", 4, "N m", "wheel torques on the body (delayed command)", WHEELS)
    u.add("thr_on", 16, "-", "thruster on-levels (0 or 1)", THRUSTERS)
    return u


def _noise() -> Layout:
    w = Layout("w")
    w.add("n_c", 3, "-", "standard-normal sample for the chaser random torque", XYZ)
    w.add("n_t", 3, "-", "standard-normal sample for the target random torque", XYZ)
    return w


def _measurement() -> Layout:
    m = Layout("meas")
    m.add("q_e", 4, "-", "chaser attitude relative to the interface frame (000 eq. 22)", XYZW)
    m.add("w_e", 3, "rad/s", "rate error, chaser axes (000 eq. 17)", XYZ)
    m.add("r", 3, "m", "relative position, LVLH", XYZ)
    m.add("v", 3, "m/s", "relative velocity, LVLH", XYZ)
    m.add("w_c", 3, "rad/s", "chaser body rate", XYZ)
    m.add("q_cL", 4, "-", "chaser attitude relative to the target's LVLH frame", XYZW)
    return m


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

    def mass_properties(self):
        p = self.p
        return chaser_mass_properties(self.t, p["chaser_mass"], inertia_tensor(p["chaser_inertia"]),
                                      p["mass_profile_on"])

    def _terms(self):
        """Every intermediate quantity of the right-hand side, by name."""
        p, x, u, w = self.p, self.x, self.u, self.w
        o = self.orbit()
        C_IL = o["C_IL"]
        m_c, I_c = self.mass_properties()
        I_t = inertia_tensor(p["target_inertia"])
        A = act.pyramid_matrix(p["wheel_beta"])
        q_c, w_c, h_w = x["q_c"], x["w_c"], x["h_w"]
        q_t = x["q_t"]
        r, v = x["r"], x["v"]

        Omega = act.wheel_speeds(h_w, p["wheel_inertia"], A, w_c)
        T_w = act.speed_limited_torques(u["T_w"], Omega, p["wheel_speed_max"])
        F_thr, tau_thr = act.thruster_wrench(u["thr_on"], p["thruster_force"])

        r_c_eci, v_c_eci = chaser_inertial_state(o["r_eci"], o["v_eci"], C_IL, o["n"], r, v)
        C_Ic, C_It = quat_to_dcm(q_c), quat_to_dcm(q_t)
        rc = norm(r_c_eci)
        rt = o["r"]
        M_gg_c = p["gg_on"] * env.gravity_gradient_torque(p["mu"], rc, C_Ic.T * r_c_eci / rc, I_c)
        M_gg_t = p["gg_on"] * env.gravity_gradient_torque(p["mu"], rt, C_It.T * o["r_eci"] / rt, I_t)
        m_hat = vec(0, 0, -1)  # untilted dipole, pointing to geographic south
        B_c = env.dipole_field(p["mu_mag"], r_c_eci, m_hat)
        B_t = env.dipole_field(p["mu_mag"], o["r_eci"], m_hat)
        M_mag_c = p["mag_on"] * env.magnetic_torque(p["chaser_dipole"], C_Ic.T * B_c)
        M_mag_t = p["mag_on"] * env.magnetic_torque(p["target_dipole"], C_It.T * B_t)
        M_r_c = env.random_torque(p["chaser_rand_std"], w["n_c"])
        M_r_t = env.random_torque(p["target_rand_std"], w["n_t"])

        def perturbation(r_eci, v_eci, mass, cd, area):
            a_j2 = env.j2_acceleration(p["mu"], p["j2"], p["r_earth"], r_eci)
            rho = env.atmosphere_density(env.altitude(r_eci, p["r_earth"], p["earth_flattening"]))
            a_drag = env.drag_acceleration(rho, cd, area, mass, r_eci, v_eci, p["omega_earth"])
            return p["j2_on"] * a_j2 + p["drag_on"] * a_drag

        a_c = perturbation(r_c_eci, v_c_eci, m_c, p["chaser_cd"], p["chaser_area"])
        a_t = perturbation(o["r_eci"], o["v_eci"], p["target_mass"], p["target_cd"], p["target_area"])
        a_d = C_IL.T * env.relative_disturbance(a_c, a_t)
        a_ctrl = C_IL.T * C_Ic * F_thr / m_c

        M_c = M_gg_c + M_mag_c + M_r_c + tau_thr
        M_t = M_gg_t + M_mag_t + M_r_t
        return {
            "orbit": o, "m_c": m_c, "I_c": I_c, "I_t": I_t, "A": A, "Omega": Omega, "T_w": T_w,
            "T_c": A * T_w, "F_thr": F_thr, "tau_thr": tau_thr, "M_c": M_c, "M_t": M_t,
            "M_gg_c": M_gg_c, "M_gg_t": M_gg_t, "M_mag_t": M_mag_t, "a_d": a_d, "a_ctrl": a_ctrl,
            "h_rw": A * h_w,
        }

    def rhs(self) -> sp.Matrix:
        """dx/dt as a SymPy column (25)."""
        p, x, u = self.p, self.x, self.u
        k = self._terms()
        o = k["orbit"]
        return self.x.pack({
            "q_c": quat_rate(x["q_c"], x["w_c"]),
            "w_c": chaser_angular_acceleration(k["I_c"], x["w_c"], k["h_rw"], k["T_c"], k["M_c"]),
            "h_w": wheel_momentum_rate(k["T_w"]),
            "q_t": quat_rate(x["q_t"], x["w_t"]),
            "w_t": target_angular_acceleration(k["I_t"], x["w_t"], k["M_t"]),
            "r": x["v"],
            "v": relative_acceleration(x["r"], x["v"], o["r"], o["n"], o["n_dot"], p["mu"],
                                       k["a_ctrl"], k["a_d"]),
            "m_prop": act.propellant_flow(u["thr_on"], p["thruster_force"], p["thruster_isp"], p["g0"]),
        })

    def torques(self) -> dict[str, sp.Matrix]:
        """Chaser and target external torques and the wheel torque on the body [N m]."""
        k = self._terms()
        return {"M_c": k["M_c"], "M_t": k["M_t"], "T_c": k["T_c"], "h_rw": k["h_rw"],
                "I_c": k["I_c"], "I_t": k["I_t"]}

    def measurement(self) -> sp.Matrix:
        """Truth -> the relative pose the 000-family controllers use."""
        x = self.x
        o = self.orbit()
        q_e = attitude_error(x["q_c"], x["q_t"])
        return self.meas.pack({
            "q_e": q_e,
            "w_e": rate_error(q_e, x["w_c"], x["w_t"]),
            "r": x["r"],
            "v": x["v"],
            "w_c": x["w_c"],
            "q_cL": quat_mul(quat_conj(self.lvlh_attitude(o)), x["q_c"]),
        })

    def env_outputs(self) -> sp.Matrix:
        """Logged environment and actuator quantities at the start of a step."""
        k = self._terms()
        o = k["orbit"]
        return self.env.pack({
            "nu": o["nu"], "r_t": o["r"], "n": o["n"], "m_c": k["m_c"],
            "I_c_diag": sp.Matrix([k["I_c"][i, i] for i in range(3)]),
            "wheel_speed": k["Omega"], "M_gg_c": k["M_gg_c"], "M_gg_t": k["M_gg_t"],
            "M_mag_t": k["M_mag_t"], "a_d": k["a_d"], "F_thr": k["F_thr"], "tau_thr": k["tau_thr"],
        })


def make_plant() -> Plant:
    """Fresh symbols and layouts of the 000 plant."""
    return Plant(_params(), _state(), _input(), _noise(), _measurement(), _env_outputs(),
                 sp.Symbol("t", real=True))
