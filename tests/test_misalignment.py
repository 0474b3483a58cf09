"""Actuator misalignment (docs/actuators.md): the plant's true geometry, the allocations' nominal one.

The true wheel axes and thrust directions the generated plant applies are the nominal ones rotated
by scipy's rotation of the same rotation vector in rpo's convention (the Cayley / Gibbs form: the
quaternion [theta / 2, 1] normalised, angle 2 atan(|theta| / 2)); the wheel momentum coupling and
a locked wheel's inertia use the same axes (angular momentum balance); zero misalignment changes
no bit; a misaligned opposed pair gives the torque r x F of its rotated forces, which is exactly
what the applied wrench differs from the command by; the scenario keys refuse out-of-range values.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rpo.runtime.errors import ScenarioError
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import loads_scenario

from conftest import quiet_params, target_state

RNG = np.random.default_rng(20240612)
DEG = math.pi / 180
TOL = 1e-12
NEVER = 1e30


def rotation(theta) -> Rotation:
    """rpo's misalignment rotation of the rotation vector theta [rad] (actuators.rotation_offset)."""
    return Rotation.from_quat(np.r_[np.asarray(theta, float) / 2, 1.0])  # scipy normalises


def nominal_geometry(beta: float):
    """(wheel axes 3 x 4, thruster positions 16 x 3, thruster directions 16 x 3), body axes."""
    from rpo.symbolic.physics.actuators import thruster_layout

    c, s = math.cos(beta), math.sin(beta)
    A = np.array([[c, 0, -c, 0], [0, c, 0, -c], [s, s, s, s]])
    pos, dirs = thruster_layout()
    return A, np.array([[float(v) for v in p] for p in pos]), np.array([[float(v) for v in d] for d in dirs])


def small_rotations(n: int, max_deg: float = 5.0) -> np.ndarray:
    return RNG.uniform(-max_deg, max_deg, (n, 3)) * DEG


class Plant:
    """The generated plant functions at one state, with the given parameters."""

    def __init__(self, model, **params):
        self.m = model
        self.p = model.vector("p", quiet_params(**params))
        self.po = model.offsets("p")
        self.uo, self.xo, self.eo = model.offsets("u"), model.offsets("x"), model.offsets("env")
        x = np.zeros(model.layout_size("x"))
        x[self.xo["q_c"]] = x[self.xo["q_t"]] = [0, 0, 0, 1]
        x[self.xo["r"]] = [100.0, 0.0, 0.0]
        ts = target_state(model, self.p)
        x[self.xo["r_T"]], x[self.xo["v_T"]] = ts["r_T"], ts["v_T"]
        self.x = x
        self.w = np.zeros(model.layout_size("w"))

    def u(self, T_w=(0, 0, 0, 0), thr_on=None, locked=(0, 0, 0, 0)):
        u = np.zeros(self.m.layout_size("u"))
        u[self.uo["T_w"]] = T_w
        u[self.uo["thr_on"]] = np.zeros(16) if thr_on is None else thr_on
        u[self.uo["wheel_locked"]] = locked
        return u

    def env(self, u, x=None):
        e = np.ravel(self.m.env_outputs(self.x if x is None else x, u, 0.0, self.p, self.w)[0])
        return {k: e[sl] for k, sl in self.eo.items()}

    def xdot(self, u, x):
        d = np.ravel(self.m.plant_rhs(x, u, 0.0, self.p, self.w)[0])
        return {k: d[sl] for k, sl in self.xo.items()}

    def scalar(self, name):
        return float(self.p[self.po[name]][0])


# --------------------------------------------------------------------------- (1) the true geometry


def test_convention_is_an_exact_rotation_by_2_atan_half_theta():
    """The documented angle: the Cayley rotation of theta turns by 2 atan(|theta| / 2) about theta."""
    for theta in small_rotations(5, 10.0):
        t = np.linalg.norm(theta)
        ref = Rotation.from_rotvec(theta / t * 2 * math.atan(t / 2))
        assert rotation(theta).approx_equal(ref, atol=1e-15)


def test_wheel_axes_are_the_nominal_ones_rotated(model):
    """One wheel commanded at a time: the motors' body torque is T a_i with the rotated axis, and the
    wheel speeds relative to the body are h_i / I_w - a_i . omega with the same axes."""
    theta = small_rotations(4)
    P = Plant(model, wheel_misalign=theta.ravel())
    A, _, _ = nominal_geometry(P.scalar("wheel_beta"))
    true_axes = np.array([rotation(theta[i]).apply(A[:, i]) for i in range(4)])
    for i in range(4):
        T = np.zeros(4)
        T[i] = 0.05
        e = P.env(P.u(T_w=T))
        np.testing.assert_allclose(e["tau_applied"], 0.05 * true_axes[i], rtol=0, atol=TOL * 0.05)
        assert np.abs(e["tau_applied"] - 0.05 * A[:, i]).max() > 1e-4  # the misalignment is visible
    x = P.x.copy()
    x[P.xo["w_c"]] = omega = RNG.normal(0, 0.1, 3)
    x[P.xo["h_w"]] = h = RNG.normal(0, 0.3, 4)
    I_w = P.scalar("wheel_inertia")
    np.testing.assert_allclose(P.env(P.u(), x)["wheel_speed"], h / I_w - true_axes @ omega, rtol=TOL)


def test_thruster_directions_are_the_nominal_ones_rotated(model):
    """One thruster firing at a time: force F_max R d_j and torque r_j x F_max R d_j."""
    theta = small_rotations(16)
    P = Plant(model, thruster_misalign=theta.ravel())
    _, pos, dirs = nominal_geometry(P.scalar("wheel_beta"))
    F_max = P.scalar("thruster_force")
    for j in range(16):
        on = np.zeros(16)
        on[j] = 1.0
        e = P.env(P.u(thr_on=on))
        F = F_max * rotation(theta[j]).apply(dirs[j])
        np.testing.assert_allclose(e["F_thr"], F, rtol=0, atol=TOL)
        np.testing.assert_allclose(e["tau_thr"], np.cross(pos[j], F), rtol=0, atol=TOL)
        np.testing.assert_allclose(e["F_applied"], F, rtol=0, atol=TOL)


@pytest.mark.parametrize("locked", [(0, 0, 0, 0), (0, 1, 0, 0)], ids=["free", "wheel2_locked"])
def test_angular_momentum_balance_uses_the_true_axes(model, locked):
    """With no external torque, d/dt (I_c w + A_true h) = -w x (I_c w + A_true h) in body axes:
    the motor torques, the wheel momentum coupling (eq. 6), the wheel momentum rates and a locked
    wheel's inertia all use the same (true) axes."""
    theta = small_rotations(4, 8.0)
    P = Plant(model, wheel_misalign=theta.ravel(), thruster_misalign=small_rotations(16).ravel())
    A, _, _ = nominal_geometry(P.scalar("wheel_beta"))
    A_true = np.column_stack([rotation(theta[i]).apply(A[:, i]) for i in range(4)])
    x = P.x.copy()
    x[P.xo["w_c"]] = w = RNG.normal(0, 0.1, 3)
    x[P.xo["h_w"]] = h = RNG.normal(0, 0.3, 4)
    d = P.xdot(P.u(T_w=RNG.normal(0, 0.05, 4), locked=locked), x)
    c = P.p[P.po["chaser_inertia"]]
    I_c = np.array([[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]])
    H = I_c @ w + A_true @ h
    np.testing.assert_allclose(I_c @ d["w_c"] + A_true @ d["h_w"], -np.cross(w, H), rtol=0,
                               atol=1e-12 * np.abs(I_c @ d["w_c"]).max())


# --------------------------------------------------------------------------- (2) zero changes nothing


def _short_run(model, params, seconds=2.0):
    from rpo.runtime.scenario import load_scenario

    run = load_scenario("scenarios/000_scenario_III.toml").to_run(model)
    sim = Simulation(model, run.controller, params={**run.params, **params}, gains=run.gains)
    res = sim.run(sim.initial_state(run.plant), seconds, seed=5, record_every=20)
    return res.z.view(np.uint64), res.y.view(np.uint64)


def test_zero_misalignment_is_the_default_and_changes_no_bit(model):
    """The defaults are zero, and a run given explicit zeros equals one given nothing, bit for bit
    (that zero reproduces the model before misalignment existed is checked against that model's
    build in the change's report: the offsets are only ever added as exact zeros)."""
    for name, n in (("wheel_misalign", 12), ("thruster_misalign", 48)):
        assert np.array_equal(model.vector("p")[model.offsets("p")[name]], np.zeros(n))
    z0, y0 = _short_run(model, {})
    z1, y1 = _short_run(model, {"wheel_misalign": np.zeros(12), "thruster_misalign": np.zeros(48)})
    assert np.array_equal(z0, z1) and np.array_equal(y0, y1)


def test_a_misaligned_thruster_that_never_fires_changes_no_bit(model):
    """Thruster 06 failed off from t = 0 and misaligned: every state and output equal the run without
    the misalignment, bit for bit (its offset enters only as its level, 0, times its column)."""
    off = {"fault_thr_off_start": [NEVER] * 6 + [0.0] + [NEVER] * 9}
    theta = np.zeros((16, 3))
    theta[6] = [4 * DEG, -7 * DEG, 2 * DEG]
    z0, y0 = _short_run(model, off)
    z1, y1 = _short_run(model, {**off, "thruster_misalign": theta.ravel()})
    assert np.array_equal(z0, z1) and np.array_equal(y0, y1)
    z2, _ = _short_run(model, {"thruster_misalign": theta.ravel()})  # firing, it does change the run
    assert not np.array_equal(z0, z2)


# --------------------------------------------------------------------------- (3) parasitic wrench


def test_a_misaligned_opposed_pair_gives_the_parasitic_torque(model):
    """Thrusters 4 and 5 share a line of action with opposite forces: nominally they cancel; rotated,
    their force is F_max (R4 d4 - R5 d4) and their torque r4 x F4 + r5 x F5."""
    theta = small_rotations(16, 0.0)
    theta[4], theta[5] = [1 * DEG, -2 * DEG, 0.5 * DEG], [-0.5 * DEG, 1.5 * DEG, 3 * DEG]
    P = Plant(model, thruster_misalign=theta.ravel())
    _, pos, dirs = nominal_geometry(P.scalar("wheel_beta"))
    assert np.allclose(dirs[4], -dirs[5]) and np.allclose(np.cross(pos[4] - pos[5], dirs[4]), 0)
    F_max = P.scalar("thruster_force")
    on = np.zeros(16)
    on[4] = on[5] = 1.0
    e = P.env(P.u(thr_on=on))
    F4, F5 = F_max * rotation(theta[4]).apply(dirs[4]), F_max * rotation(theta[5]).apply(dirs[5])
    np.testing.assert_allclose(e["F_thr"], F4 + F5, rtol=0, atol=TOL)
    np.testing.assert_allclose(e["tau_thr"], np.cross(pos[4], F4) + np.cross(pos[5], F5), rtol=0, atol=TOL)
    assert np.linalg.norm(e["tau_thr"]) > 1e-2  # tens of mN m from a few degrees
    Pn = Plant(model)
    assert np.abs(Pn.env(Pn.u(thr_on=on))["tau_thr"]).max() < 1e-15  # nominally they cancel


def test_applied_minus_commanded_wrench_is_the_misalignment(model):
    """The allocations see the nominal geometry (their outputs do not change with the misalignment),
    so the applied wrench differs from the commanded one by exactly the misaligned units' offsets:
    sum_j d_j F_max [R d_j - d_j; r_j x (R d_j - d_j)] and (A_true - A) T_w."""
    th_thr, th_wheel = small_rotations(16), small_rotations(4)
    P = Plant(model, thruster_misalign=th_thr.ravel(), wheel_misalign=th_wheel.ravel())
    Pn = Plant(model)
    A, pos, dirs = nominal_geometry(P.scalar("wheel_beta"))
    F_max = P.scalar("thruster_force")
    F_cmd, tau_cmd = np.array([0.3, -0.2, 0.25]), np.array([0.05, 0.08, -0.04])
    duty = np.ravel(model.thruster_alloc(F_cmd, tau_cmd, 0.0, P.p)[0])
    assert np.array_equal(duty, np.ravel(model.thruster_alloc(F_cmd, tau_cmd, 0.0, Pn.p)[0]))
    assert 0 < duty.max() < 1  # within the limits: the nominal wrench is the command
    e = P.env(P.u(thr_on=duty))
    dd = np.array([rotation(th_thr[j]).apply(dirs[j]) - dirs[j] for j in range(16)])
    dF = F_max * duty @ dd
    dtau = F_max * sum(duty[j] * np.cross(pos[j], dd[j]) for j in range(16))
    np.testing.assert_allclose(e["F_applied"] - F_cmd, dF, rtol=0, atol=TOL)
    np.testing.assert_allclose(e["tau_applied"] - tau_cmd, dtau, rtol=0, atol=TOL)
    assert np.linalg.norm(dtau) > 1e-3
    T_w = np.ravel(model.wheel_alloc(tau_cmd, 0.0, P.p)[0])
    assert np.array_equal(T_w, np.ravel(model.wheel_alloc(tau_cmd, 0.0, Pn.p)[0]))
    A_true = np.column_stack([rotation(th_wheel[i]).apply(A[:, i]) for i in range(4)])
    e = P.env(P.u(T_w=T_w))
    np.testing.assert_allclose(e["tau_applied"] - tau_cmd, (A_true - A) @ T_w, rtol=0, atol=TOL)


# --------------------------------------------------------------------------- (4) scenario keys

MINIMAL = """
[simulation]
duration = 1.0
[chaser]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[target]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[relative]
position = [10.0, 0.0, 0.0]
velocity = [0.0, 0.0, 0.0]
"""


def _toml(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def test_scenario_keys_set_the_misalignment_in_degrees():
    wheels = RNG.uniform(-10, 10, 12)
    wheels[0] = 10.0  # a closed bound is accepted
    thr = RNG.uniform(-10, 10, 48)
    sc = loads_scenario(MINIMAL + f"[wheels]\nmisalignment_deg = {_toml(wheels)}\n"
                        f"[thrusters]\nmisalignment_deg = {_toml(thr)}\n", "s.toml")
    np.testing.assert_allclose(sc.params()["wheel_misalign"], wheels * DEG, rtol=1e-15)
    np.testing.assert_allclose(sc.params()["thruster_misalign"], thr * DEG, rtol=1e-15)


@pytest.mark.parametrize(("key", "n"), [("wheels", 12), ("thrusters", 48)])
def test_scenario_keys_refuse_out_of_range_values(key, n):
    bad = [0.0] * n
    bad[4] = -10.5
    # the value is shown shortened (``[0.0, ..., 0.0,...``) when long; one line with the key and the range
    with pytest.raises(ScenarioError, match=rf"^s\.toml: {key}\.misalignment_deg = \[[^\n]*: must be in "
                                            r"\[-10, 10\] deg$"):
        loads_scenario(MINIMAL + f"[{key}]\nmisalignment_deg = {_toml(bad)}\n", "s.toml")
    with pytest.raises(ScenarioError, match=rf"^s\.toml: {key}\.misalignment_deg = \[.*\]: must have {n} values, "
                                            "got 3$"):
        loads_scenario(MINIMAL + f"[{key}]\nmisalignment_deg = [1.0, 2.0, 3.0]\n", "s.toml")
