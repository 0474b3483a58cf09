"""``import rpo``: one call flies a scenario file, the same run as ``rpo run``."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import rpo
from tests.test_cli import III
from tests.test_cli import rpo as rpo_cli


def test_rpo_run_is_the_command_line_run(tmp_path):
    res = rpo.run(III, duration=2.0, seed=3, overrides={"chaser.mass": 90.0}, log=False)
    cli = rpo_cli("run", III, "--duration", "2", "--seed", "3", "--set", "chaser.mass=90.0", "--no-plots",
                  "--format", "parquet", "--out", tmp_path / "cli", timeout=300)
    assert cli.returncode == 0, cli.stderr
    back = rpo.read_run(tmp_path / "cli")
    assert res.meta["verdict"]["line"] == back.meta["verdict"]["line"]
    # the folder keeps the scenario's [output] rows and columns: compare those
    t = back.t
    rows = np.searchsorted(res.t, t)
    assert np.array_equal(res.t[rows], t)
    for label in ("r_x", "r_y", "r_z", "q_c_w"):
        assert np.array_equal(res[label][rows], back[label]), label
    df = res.to_pandas()
    assert isinstance(df, pd.DataFrame) and df.attrs["units"]["r_x"] == "m"


def test_rpo_run_writes_the_folder_when_asked_and_refuses_bad_overrides(tmp_path):
    res = rpo.run("000_scenario_III", duration=0.5, out=tmp_path / "r", plots=False, log=False)
    assert (tmp_path / "r" / "run.json").exists() and res.meta["metrics"]["status"] == "ok"
    with pytest.raises(rpo.ScenarioError, match="chaser.mass = -1"):
        rpo.run(III, duration=0.5, overrides={"chaser.mass": -1.0}, log=False)
    with pytest.raises(rpo.ScenarioError, match="unknown key"):
        rpo.scenario(III, {"chaser.mas": 1.0})
