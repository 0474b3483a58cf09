"""Simulation loop behaviour: divergence handling, reproducibility, parameter validation."""

from __future__ import annotations

import numpy as np
import pytest

from rpo.runtime.errors import ModelError
from rpo.runtime.run.simulate import Simulation

from conftest import Q_C0_III, Q_T0_III, unit

Z0 = {"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "w_t": [0.10876, 0.009113, 0.05468],
      "r": [60, 0, 25], "v": [3, -0.5, 5]}


def test_divergence_stops_with_step_time_and_state_and_keeps_the_data(model):
    sim = Simulation(model, params={"chaser_mass": 0.0})  # 1/m -> inf: NaN in the first step
    res = sim.run(sim.initial_state(Z0), 10.0)
    d = res.divergence
    assert d is not None and d.step == 0 and d.time == pytest.approx(0.01)
    assert not np.all(np.isfinite(d.state)) and np.all(np.isfinite(d.last_good_state))
    assert "diverged" in d.message() and "t = 0.01" in d.message()
    assert res.t.size == 1 and np.all(res.z[0] == sim.initial_state(Z0))


def test_divergence_bound_reports_the_offending_entry_after_partial_progress(model):
    sim = Simulation(model, bounds={"r": 100.0})  # the chaser drifts past 100 m after ~10 s
    res = sim.run(sim.initial_state(Z0), 300.0)
    d = res.divergence
    assert d is not None and 100 < d.step < 30000
    assert d.label.startswith("r_") and abs(d.value) > 100
    assert res.steps_done == d.step and res.t[-1] == pytest.approx(d.step * 0.01)
    assert np.all(np.abs(res.z[:, 18:21]) <= 100)  # everything kept is within the bound


def test_same_seed_same_run_different_seed_different_run(model):
    sim = Simulation(model)
    z0 = sim.initial_state(Z0)
    a = sim.run(z0, 2.0, seed=4, chunk=64)
    b = sim.run(z0, 2.0, seed=4, chunk=1000)
    c = sim.run(z0, 2.0, seed=5)
    assert np.array_equal(a.z, b.z) and np.array_equal(a.y, b.y, equal_nan=True)  # last y row: NaN
    assert not np.array_equal(a.z, c.z)


def test_record_every_decimates_without_changing_the_trajectory(model):
    sim = Simulation(model)
    z0 = sim.initial_state(Z0)
    full = sim.run(z0, 1.0, seed=1)
    dec = sim.run(z0, 1.0, seed=1, record_every=7, chunk=10)
    # every 7th state, and always the final one (100 steps is not a multiple of 7)
    assert np.array_equal(dec.z[:-1], full.z[::7]) and np.allclose(dec.t[:-1], full.t[::7])
    assert np.array_equal(dec.z[-1], full.z[-1]) and dec.t[-1] == pytest.approx(1.0)


def test_divergence_keeps_the_last_good_state_off_the_recording_grid(model):
    sim = Simulation(model, bounds={"r": 100.0})
    res = sim.run(sim.initial_state(Z0), 300.0, record_every=50)
    d = res.divergence
    assert d is not None and d.step % 50 != 0
    assert res.t[-1] == pytest.approx(d.step * 0.01) and np.array_equal(res.z[-1], d.last_good_state)
    assert np.all(np.isfinite(res.y[-1]))  # the failing step's output, computed at the last good state


@pytest.mark.parametrize("delay", [-0.001, 0.04, 0.1])
def test_wheel_delay_outside_the_delay_line_is_refused(model, delay):
    with pytest.raises(ModelError, match="wheel_delay"):
        Simulation(model, params={"wheel_delay": delay})


def test_unknown_parameter_and_non_unit_quaternion_are_refused(model):
    with pytest.raises(ModelError, match="unknown p fields: chaser_mas"):
        Simulation(model, params={"chaser_mas": 3})
    sim = Simulation(model)
    with pytest.raises(ModelError, match="unit quaternion"):
        sim.initial_state({**Z0, "q_c": [0, 0, 0, 2]})
