"""rpo.runtime.run.linearize: quaternion charts, AD step Jacobian against central differences of the
compiled step, plant A/B against plant_jac, and `rpo linearize` on the command line."""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rpo.runtime.run import linearize as lz
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import load_scenario

from conftest import target_state

ROOT = Path(__file__).resolve().parents[1]
III = ROOT / "scenarios" / "000_scenario_III.toml"
RNG = np.random.default_rng(20261201)


def rpo(*args, timeout=120) -> subprocess.CompletedProcess:
    """``python -m rpo.runtime.cli.main ARGS``, as tests/test_cli.py runs it."""
    env = {**os.environ, "PYTHONWARNINGS": "default", "COLUMNS": "100"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], env=env,
                          capture_output=True, text=True, timeout=timeout)


def assert_user_error(res: subprocess.CompletedProcess, *needles: str) -> None:
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert "Traceback" not in res.stderr + res.stdout
    last = res.stderr.strip().splitlines()[-1]  # after any compile progress lines
    assert last.startswith("error: ")
    for n in needles:
        assert n in last, (n, last)


def _random_quats(n):
    return Rotation.random(n, random_state=7).as_quat()


# --------------------------------------------------------------------------- charts


def test_exp_log_match_scipy_and_round_trip():
    q0s = _random_quats(20)
    for q0 in q0s:
        axis = RNG.normal(size=3)
        dth = axis / np.linalg.norm(axis) * RNG.uniform(1e-9, 3.1)  # the chart covers |dth| < pi
        q = lz.retract(q0, dth)
        ref = (Rotation.from_quat(q0) * Rotation.from_rotvec(dth)).as_quat()
        assert min(np.abs(q - ref).max(), np.abs(q + ref).max()) < 1e-14
        np.testing.assert_allclose(lz.local(q0, q), dth, atol=1e-12)
        # the inverse map against scipy: dth = rotvec(R0^-1 R), for any second attitude
        q1 = _random_quats(1)[0] if np.linalg.norm(dth) > 1 else q
        ref_dth = (Rotation.from_quat(q0).inv() * Rotation.from_quat(q1)).as_rotvec()
        np.testing.assert_allclose(lz.local(q0, q1), ref_dth, atol=1e-12)
        # sign and scale of q do not matter (the shorter rotation, a ray in R^4)
        np.testing.assert_allclose(lz.local(q0, -2.5 * q1), ref_dth, atol=1e-12)


def test_tangent_maps_round_trip_and_match_differences():
    h = 1e-6  # central differences of smooth maps: error ~ h^2 ~ 1e-12, round-off ~ 1e-16 / h ~ 1e-10
    for q0 in _random_quats(10):
        E, Ep = lz.retract_tangent(q0), lz.local_tangent(q0)
        np.testing.assert_allclose(Ep @ E, np.eye(3), atol=1e-15)
        np.testing.assert_allclose(Ep @ q0, 0.0, atol=1e-15)      # the norm direction is not a rotation
        np.testing.assert_allclose(E.T @ q0, 0.0, atol=1e-15)     # E spans the sphere's tangent space
        E_fd = np.column_stack([(lz.retract(q0, h * e) - lz.retract(q0, -h * e)) / (2 * h) for e in np.eye(3)])
        np.testing.assert_allclose(E, E_fd, atol=1e-9)
        Ep_fd = np.column_stack([(lz.local(q0, q0 + h * e) - lz.local(q0, q0 - h * e)) / (2 * h) for e in np.eye(4)])
        np.testing.assert_allclose(Ep, Ep_fd, atol=1e-9)


def test_reduced_coordinates_round_trip(model):
    c = lz.coordinates(model, "c000")
    assert c.n == c.nz - 2 and sorted(c.labels) == sorted(set(c.labels))
    assert list(c.groups) == list(lz.GROUP_ORDER)
    assert [c.labels[i] for i in range(c.groups["chaser"].start, c.groups["chaser"].stop)] == \
        ["dth_c_x", "dth_c_y", "dth_c_z", "w_c_x", "w_c_y", "w_c_z"]
    for name in ("h_w", "m_prop", "wheel_cmd_1", "pwpf_f", "pwpf_on"):
        assert all(c.group_of(i) == "actuators" for i in c.indices(name)), name
    z0 = RNG.normal(size=c.nz)
    offs = model.offsets("z_c000")
    for q in ("q_c", "q_t"):
        z0[offs[q]] = _random_quats(1)[0]
    xi = RNG.normal(size=c.n) * 0.3  # |dth| < pi
    np.testing.assert_allclose(c.to_xi(z0, c.to_z(z0, xi)), xi, atol=1e-12)
    np.testing.assert_allclose(c.tangent_out(z0) @ c.tangent_in(z0), np.eye(c.n), atol=1e-15)
    # the rotation vector of q_c is scipy's rotvec of R0^-1 R
    z1 = c.to_z(z0, xi)
    ref = (Rotation.from_quat(z0[offs["q_c"]]).inv() * Rotation.from_quat(z1[offs["q_c"]])).as_rotvec()
    np.testing.assert_allclose(xi[c.indices("q_c")], ref, atol=1e-12)


# --------------------------------------------------------------------------- the step


@functools.cache
def _setup(scenario: str, controller: str):
    from rpo.runtime import load_model

    model = load_model(controllers=[controller])
    sc = load_scenario(ROOT / "scenarios" / scenario).with_overrides(controller=controller)
    inputs = sc.to_run(model)
    sim = Simulation(model, controller, params=inputs.params, gains=inputs.gains)
    return model, sim, sim.initial_state(inputs.plant)


def _off_goal(model, controller, sim, z0):
    """The goal moved by a fixed small offset, so that no sign(s) or |s| sits at s = 0 (where the
    step has no derivative; AD then takes one branch and central differences average two)."""
    goal = lz.goal_state(model, controller, z0, 0.0, sim.p, sim.k).z
    c = lz.coordinates(model, controller)
    xi = np.zeros(c.n)
    off = {"q_c": 2e-3, "w_c": 1e-3, "r": 0.3, "v": 0.02}
    for name, size in off.items():
        idx = c.indices(name)
        xi[idx] = size * np.array([1.0, -0.7, 0.4])[: len(idx)]
    return c.to_z(goal, xi)


@pytest.mark.parametrize(("scenario", "controller"), [("000_III_ideal.toml", "c000"),
                                                      ("002_scenario.toml", "c002"),
                                                      ("004_scenario.toml", "c004"),
                                                      ("000_scenario_III.toml", "c000")])
def test_ad_jacobian_matches_central_differences(scenario, controller):
    """AD of the serialised step against central differences of the compiled C step, in the same
    reduced coordinates.  Step h = 1e-6 max(1, |z_j|) (the field's norm for the plant's vectors):
    truncation ~ h^2 |f'''| ~ 1e-12 (relative) and round-off ~ 1e-16 |z_next| / h ~ 1e-10 |z_next|
    (measured: 3e-10 to 3e-8 of 1 + |A|); the tolerance 1e-6 (1 + |A|) leaves a factor 20 or more
    and is still 1e-3 of the smallest loop gain that matters (~1e-3 per step)."""
    model, sim, z0 = _setup(scenario, controller)
    z = _off_goal(model, controller, sim, z0)
    lin = lz.linearize(model, controller, z, 0.0, sim.p, sim.k)
    J = lz.central_differences(model, lin, sim.p, sim.k)
    err = np.abs(J - lin.A)
    assert np.all(err <= 1e-6 * (1 + np.abs(lin.A))), (err.max(), np.unravel_index(err.argmax(), err.shape))
    # and the Jacobian is not trivial: the loop acts on the chaser
    assert np.abs(lin.block("chaser") - np.eye(6)).max() > 1e-4


def test_plant_jacobians_match_plant_jac(model):
    q_c, q_t = _random_quats(2)
    x = model.vector("x", {"q_c": q_c, "w_c": [0.01, -0.02, 0.005], "h_w": [0.1, -0.05, 0.0, 0.02], "q_t": q_t,
                           "w_t": [0.1, 0.01, 0.05], "r": [5, 1, 0], "v": [0, 0.1, 0], "m_prop": 0.5,
                           **target_state(model)})
    u = RNG.normal(size=model.layout_size("u")) * 0.1
    p = model.vector("p")
    pj = lz.plant_jacobians(model, x, u, 3.0, p)
    A, B = model.plant_jac(x, u, 3.0, p, np.zeros(model.layout_size("w")))
    np.testing.assert_array_equal(pj.A, A)
    np.testing.assert_array_equal(pj.B, B)
    assert pj.A.shape == (len(pj.x_labels),) * 2 and pj.B.shape == (len(pj.x_labels), len(pj.u_labels))
    # and they are the derivatives of plant_rhs (central differences; h = 1e-6 relative)
    f = model.plant_rhs
    w = np.zeros(model.layout_size("w"))
    for j in range(x.size):
        h = 1e-6 * max(1.0, abs(x[j]))
        e = np.zeros(x.size)
        e[j] = h
        col = (f(x + e, u, 3.0, p, w)[0] - f(x - e, u, 3.0, p, w)[0]) / (2 * h)
        np.testing.assert_allclose(col, A[:, j], rtol=1e-5, atol=1e-8)


def test_goal_zeroes_the_controllers_errors():
    model, sim, z0 = _setup("000_scenario_III.toml", "c000")
    goal = lz.goal_state(model, "c000", z0, 0.0, sim.p, sim.k)
    assert goal.residual < 1e-10 and goal.iterations < 15
    y = model.function("step_c000")(goal.z, 0.0, sim.p, sim.k, np.zeros(model.layout_size("w")))[1]
    yo, ko = model.offsets("y_c000"), model.offsets("k_c000")
    np.testing.assert_allclose(y[yo["ctrl_pos_err"]], 0.0, atol=1e-10)
    np.testing.assert_allclose(goal.z[model.offsets("z_c000")["r"]], sim.k[ko["r_goal"]], atol=1e-10)


# --------------------------------------------------------------------------- CLI


def test_cli_prints_eigenvalues():
    res = rpo("linearize", III, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "eigenvalues of A" in res.stdout and "goal" in res.stdout
    assert "chaser+actuators" in res.stdout and "target: w_t_x" in res.stdout
    # another controller flies the scenario's goal (002's docking point; c004 cannot hold III's, below)
    res = rpo("linearize", III.with_name("002_scenario.toml"), "--controller", "c004", "--at", "initial", "--json",
              timeout=300)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    n = len(out["labels"])
    assert np.array(out["A"]).shape == (n, n) and len(out["modes"]) == n
    assert set(out["groups"]) == set(lz.GROUP_ORDER)


def test_cli_bad_input(tmp_path):
    assert_user_error(rpo("linearize", tmp_path / "missing.toml"), "cannot read the scenario")
    assert_user_error(rpo("linearize", III, "--controller", "nope"), "unknown controller")
    assert_user_error(rpo("linearize", III, "--controller", "baseline"), "--at initial")
    assert_user_error(rpo("linearize", III, "--controller", "c004", "--at", "initial"),
                      "c004 cannot fly the scenario's goal")
    bad = tmp_path / "bad.toml"
    bad.write_text(III.read_text().replace("eccentricity = 0.138", "eccentricity = 1.5"))
    assert_user_error(rpo("linearize", bad), "eccentricity")
    res = rpo("linearize", III, "--at", "middle")
    assert res.returncode == 2 and "Traceback" not in res.stderr
