"""RunResult: named access to fields and columns with units, pandas, and the final output row."""

from __future__ import annotations

import numpy as np
import pytest

from rpo.runtime.run.simulate import Simulation

from conftest import Q_C0_III, Q_T0_III, unit

Z0 = {"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "w_t": [0.10876, 0.009113, 0.05468],
      "r": [60, 0, 25], "v": [3, -0.5, 5]}


@pytest.fixture(scope="module")
def runs(model):
    sim = Simulation(model, "baseline")
    z0 = sim.initial_state(Z0)
    # 0.5 s recorded every 7th step, and 0.51 s recorded every step: the second run's row 50 is
    # the first run's final state
    return sim, z0, sim.run(z0, 0.5, seed=2, record_every=7), sim.run(z0, 0.51, seed=2)


def test_fields_and_columns_by_name_with_units(runs, model):
    _, _, res, _ = runs
    lay = model.layouts["z_baseline"]
    np.testing.assert_array_equal(res["r"], res.block("r", lay))
    assert res["r"].shape == (res.t.size, 3) and res["m_prop"].shape == (res.t.size, 1)
    np.testing.assert_array_equal(res["r_y"], res["r"][:, 1])
    np.testing.assert_array_equal(res["cmd_F"][:, 2], res.column("cmd_F_z"))
    assert res["t"] is res.t
    assert res.unit("r") == res.unit("r_x") == "m" and res.unit("w_c") == "rad/s"
    assert res.unit("cmd_tau_w_x") == "N m" and res.unit("t") == "s"
    assert "r" in res and "r_x" in res and "t" in res and "nope" not in res
    assert res.fields[0] == "q_c" and "env_beta_fov" in res.fields
    with pytest.raises(KeyError, match="neither a field nor a column"):
        res["nope"]
    with pytest.raises(KeyError):
        res.unit("nope")


def test_to_pandas_has_every_column_and_the_units(runs):
    _, _, res, _ = runs
    df = res.to_pandas()
    assert list(df.columns) == ["t", *res.z_labels, *res.y_labels]
    np.testing.assert_array_equal(df["t"].to_numpy(), res.t)
    np.testing.assert_array_equal(df["env_F_applied_x"].to_numpy(), res["env_F_applied_x"])
    assert df.attrs["units"]["r_x"] == "m" and df.attrs["units"]["t"] == "s"


def test_final_output_row_is_the_output_at_the_final_state(runs):
    _, _, res, longer = runs
    assert np.all(np.isfinite(res.y))
    assert res.t[-1] == pytest.approx(0.5) and longer.t[50] == res.t[-1]
    # the same state, and bit for bit the output the next step computes from it
    np.testing.assert_array_equal(res.z[-1], longer.z[50])
    np.testing.assert_array_equal(res.y[-1], longer.y[50])


def test_run_batch_final_row_bit_identical_to_run(runs):
    sim, z0, res, _ = runs
    other = {"chaser_mass": 120.0}
    batch = sim.run_batch(np.array([z0, z0]), 0.5, seeds=[2, 5], params=[None, other], record_every=7)
    np.testing.assert_array_equal(batch[0].y, res.y)
    alone = Simulation(sim.model, "baseline", params=other).run(z0, 0.5, seed=5, record_every=7)
    np.testing.assert_array_equal(batch[1].y, alone.y)
    assert np.all(np.isfinite(batch[1].y[-1])) and not np.array_equal(batch[1].y[-1], res.y[-1])
