"""Divergence covers the outputs y as well as the state: a non-finite output stops the run in the
scalar C loop, in the lane loop (per lane) and in the Python fallback, and the report names it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rpo.runtime.outputs.writers import run_record
from rpo.runtime.run.simulate import Simulation

from conftest import Q_C0_III, Q_T0_III, unit

Z0 = {"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "w_t": [0.10876, 0.009113, 0.05468],
      "r": [60, 0, 25], "v": [3, -0.5, 5]}
#: a near-zero wheel inertia and no speed limit: the wheel speeds h / J (outputs only) overflow to
#: inf once the controller drives |h_w| past 1.797e308 * 1e-307 = 17.98 N m s, while the state
#: stays finite (~0.3 s in from 17.95 N m s)
TINY_WHEEL = {"wheel_inertia": 1e-307, "wheel_speed_max": np.inf}


def _h(model, h: float) -> list[float]:
    """Every wheel at momentum ``h`` [N m s] (as many as the model's layout has)."""
    sl = model.offsets("z_baseline")["h_w"]
    return [h] * (sl.stop - sl.start)


def _sim(model) -> tuple[Simulation, np.ndarray]:
    sim = Simulation(model, params=TINY_WHEEL)
    return sim, sim.initial_state({**Z0, "h_w": _h(model, 17.95)})


def _check_output_divergence(res, sim, every: int) -> None:
    d = res.divergence
    assert d is not None and d.where == "output"
    assert d.label.startswith("env_wheel_speed_") and not np.isfinite(d.value)
    assert 0 < d.step < 100 and d.time == pytest.approx((d.step + 1) * sim.dt)
    assert np.all(np.isfinite(d.state)) and np.all(np.isfinite(d.last_good_state))  # the state was fine
    assert not np.isfinite(d.output[res.y_labels.index(d.label)])
    assert f"output {d.label} is non-finite" in d.message() and f"step {d.step}" in d.message()
    # everything computed so far is kept: the rows before the failing step have finite outputs
    assert res.steps_done == d.step and res.t[-1] == pytest.approx(d.step * sim.dt)
    assert np.array_equal(res.z[-1], d.last_good_state)
    assert np.all(np.isfinite(res.y[:-1])) and not np.all(np.isfinite(res.y[-1]))
    assert res.t.size == d.step // every + 1 + (d.step % every != 0)


@pytest.mark.parametrize("every", [1, 3])
def test_a_non_finite_output_stops_the_scalar_loop_and_is_named(model, every):
    sim, z0 = _sim(model)
    res = sim.run(z0, 1.0, record_every=every, chunk=10)  # several chunks before the failure
    _check_output_divergence(res, sim, every)
    rec = json.loads(json.dumps(run_record(res, model)))
    div = rec["divergence"]
    assert rec["status"] == "diverged" and div["where"] == "output" and div["label"] == res.divergence.label
    assert div["output"][div["label"]] in ("inf", "-inf", "nan") and set(div["state"]) == set(res.z_labels)


def test_a_healthy_run_with_finite_outputs_is_unchanged(model):
    sim = Simulation(model, params=TINY_WHEEL)
    res = sim.run(sim.initial_state({**Z0, "h_w": _h(model, -17.95)}), 1.0)  # |h_w| falls: speeds stay finite
    assert res.divergence is None and res.steps_done == 100


def test_the_python_fallback_checks_the_outputs_too(model, monkeypatch):
    sim, z0 = _sim(model)
    ref = sim.run(z0, 1.0, record_every=3)
    monkeypatch.setattr(sim, "_c_runner", lambda: None)  # the per-step loop of the CasADi backend
    res = sim.run(z0, 1.0, record_every=3)
    _check_output_divergence(res, sim, 3)
    assert res.divergence.step == ref.divergence.step and res.divergence.label == ref.divergence.label
    # (the per-step Python call of the compiled step differs from the C loop by round-off, as before)
    assert res.t.size == ref.t.size and np.allclose(res.z, ref.z, rtol=1e-12, atol=1e-15)


def test_lanes_stop_per_lane_on_an_output_and_stay_bit_identical_to_run(model):
    sim, z_bad = _sim(model)
    z_ok = sim.initial_state({**Z0, "h_w": _h(model, -17.95)})
    cases = [z_ok, z_bad, z_ok, z_bad, z_ok]
    seeds = [1, 2, 3, 4, 5]
    batch = sim.run_batch(np.array(cases), 1.0, seeds=seeds, record_every=3, chunk=30)
    for z0, seed, b in zip(cases, seeds, batch, strict=True):
        r = sim.run(z0, 1.0, seed=seed, record_every=3, chunk=30)
        assert np.array_equal(b.t, r.t) and np.array_equal(b.z, r.z) and np.array_equal(b.y, r.y, equal_nan=True)
        assert (b.divergence is None) == (r.divergence is None) == (z0 is z_ok)
        if r.divergence is not None:
            _check_output_divergence(b, sim, 3)
            assert (b.divergence.step, b.divergence.label) == (r.divergence.step, r.divergence.label)
            assert np.array_equal(b.divergence.output, r.divergence.output, equal_nan=True)


def test_an_output_divergence_is_written_with_its_metrics(model, tmp_path):
    """The folder of a run stopped by a non-finite output: status diverged, the entry by name, the
    metrics (computed over the record, whose last output row is the non-finite one) valid JSON."""
    from rpo.runtime.outputs.metrics import compute_metrics, result_columns
    from rpo.runtime.outputs.writers import OutputSpec, write_run

    sim, z0 = _sim(model)
    res = sim.run(z0, 1.0)
    metrics = compute_metrics(res.t, result_columns(res), None)
    out = write_run(res, tmp_path / "out", model, metrics=metrics, output=OutputSpec(figures=False))
    rec = json.loads((out / "run.json").read_text())
    assert rec["status"] == "diverged" and rec["divergence"]["where"] == "output"
    assert rec["divergence"]["label"] in rec["divergence"]["message"] and rec["rows"] == res.steps_done + 1
    json.loads((out / "metrics.json").read_text())  # strict JSON (non-finite values as text)
