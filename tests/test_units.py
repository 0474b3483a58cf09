"""Units in every output: each number of run.json and metrics.json has its unit (the rule of
runtime/outputs/jsonunits.py), the verdict's error in SI beside its degrees, pandas' attrs from the
Parquet file and from RunResult.to_pandas(), read_run() on a results folder, the .mat file's N x k
fields, and human text that never shows rad and deg side by side."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import ModelError, OutputError
from rpo.runtime.jobs.runner import execute_run
from rpo.runtime.outputs.jsonunits import number_units, shown, suffix_unit, without_units
from rpo.runtime.outputs.reading import read_run

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "scenarios"


@pytest.fixture(scope="module")
def folders(model, tmp_path_factory):
    """Three results folders: 001 (ideal actuators, errors at given times, every format), 000 III on
    the full plant (wheels and thrusters: per-unit use) and 002 with the paper's gains (diverges)."""
    tmp = tmp_path_factory.mktemp("units")
    a = execute_run(SCENARIOS / "001_scenario.toml", tmp / "a", model, duration=3.0, plots=False,
                    error_times=[1.0, 2.5], formats=["parquet", "mat", "npz", "csv"])
    b = execute_run(SCENARIOS / "000_scenario_III.toml", tmp / "b", model, duration=2.0, plots=False, plant="full")
    c = execute_run(SCENARIOS / "002_scenario.toml", tmp / "c", model, duration=2.0, plots=False)
    assert c.result.divergence is not None
    return {"001": a, "III": b, "002": c}


def load(outcome, name):
    return json.loads((outcome.out_dir / name).read_text())


# --------------------------------------------------------------------------- the JSON rule


@pytest.mark.parametrize("run", ["001", "III", "002"])
@pytest.mark.parametrize("name", ["run.json", "metrics.json"])
def test_every_number_in_the_json_files_has_a_unit(folders, run, name):
    doc = load(folders[run], name)
    found = list(number_units(doc))
    assert len(found) > 30  # the walk sees the numbers (parameters, metrics, the verdict...)
    assert without_units(doc) == [], f"{run} {name}: numbers without a unit"


def test_the_rule_reads_each_way_of_stating_a_unit_and_sees_a_number_without_one():
    doc = {"time_s": 1.0, "n": 3.5, "steps_done": 4, "fraction": 0.5, "x": "inf",
           "params": {"mu": 3.9e14, "q": [0, 0, 0, 1]}, "units": {"params": {"mu": "m^3/s^2", "q": "-"}},
           "goal": {"final": 2.0, "final_deg": 114.6, "units": {"final": "rad"}},
           "z0": [1.0, 2.0], "rows": [{"torque_peak_N_m": 0.1}]}
    got = {p: u for p, _, u in number_units(doc)}
    assert got["time_s"] == "s" and got["steps_done"] == "-" and got["fraction"] == "-"
    assert got["params.mu"] == "m^3/s^2" and got["params.q[3]"] == "-"
    assert got["goal.final"] == "rad" and got["goal.final_deg"] == "deg" and got["rows[0].torque_peak_N_m"] == "N m"
    # a number without a unit is reported, the text "inf" counts as a number
    assert without_units(doc) == ["n", "x", "z0[0]", "z0[1]"]
    assert suffix_unit("wheel_speed_peak_rad_s") == "rad/s" and suffix_unit("beta_ca_min_m2") == "m^2"
    assert suffix_unit("controller") is None


def test_units_of_run_json_are_those_of_the_model_and_the_columns(folders, model):
    rec = load(folders["001"], "run.json")
    units = rec["units"]  # one object at the top, mirroring the record
    assert units["dt"] == units["t_end"] == "s"
    p_units = {f.name: f.unit for f in model.layouts["p"]}
    assert units["inputs"]["params"] == {k: p_units[k] for k in rec["inputs"]["params"]}
    assert units["inputs"]["params"]["orbit_inc"] == "rad"  # the scenario gives degrees: SI here
    assert units["inputs"]["plant"]["r"] == "m" and units["inputs"]["gains"]["F_max"] == "N"
    assert "units" not in rec["inputs"]  # the objects themselves are as the runner made them
    res = folders["001"].result
    assert units["z0"] == res.z_units and len(rec["z0"]) == len(res.z_units)
    rec = load(folders["002"], "run.json")
    div, units = rec["divergence"], rec["units"]["divergence"]
    assert units["value"] == units["state"].get(div["label"], units["output"].get(div["label"]))
    assert units["time"] == "s"


def test_verdict_json_final_in_si_with_its_unit_and_the_degrees_the_line_shows(folders):
    v = load(folders["001"], "metrics.json")["verdict"]
    att, pos = v["goals"]["att"], v["goals"]["pos"]
    assert att["units"] == {"final": "rad"} and pos["units"] == {"final": "m"}
    assert att["final_deg"] == pytest.approx(math.degrees(att["final"]), rel=1e-15)
    assert f"final {att['final_deg']:.4g} deg" in v["line"]  # what the line shows is final_deg
    assert 0 <= att["final"] <= math.pi  # an angle in rad, not in deg
    assert v["constraints"]["beta_fov"]["units"] == {"min": "m"} and v["constraints"]["beta_ca"]["units"] == {
        "min": "m^2"}
    assert "unit" not in v["constraints"]["beta_fov"]  # one way of stating a unit: the units object
    m = load(folders["III"], "metrics.json")
    assert m["per_wheel"][0]["wheel"] == "1" and "unit" not in m["per_wheel"][0]  # "unit" named a wheel
    assert all("units" in e and e["units"]["diag"] for e in load(folders["001"], "metrics.json")["errors_at"])


# --------------------------------------------------------------------------- pandas


def test_read_parquet_gives_the_units_in_df_attrs(folders):
    pd = pytest.importorskip("pandas")
    import pyarrow.parquet as pq

    out = folders["001"].out_dir
    df = pd.read_parquet(out / "timeseries.parquet")
    schema = pq.read_schema(out / "timeseries.parquet")
    assert df.attrs, "pd.read_parquet gave empty attrs"
    assert df.attrs["units"] == {c: schema.field(c).metadata[b"unit"].decode() for c in df.columns}
    assert df.attrs["units"]["r_x"] == "m" and df.attrs["units"]["t"] == "s" and df.attrs["units"]["w_c_x"] == "rad/s"
    assert df.attrs["fields"]["r"] == ["r_x", "r_y", "r_z"]
    assert df.attrs["run"]["controller"] == "c001" and df.attrs["run"]["units"] == {"dt": "s", "t_end": "s"}
    assert df["r_x"].attrs["units"]["r_x"] == "m"  # a column taken from the frame keeps the frame's attrs


def test_to_pandas_of_the_run_has_the_attrs_of_its_parquet_file(folders):
    pd = pytest.importorskip("pandas")
    o = folders["001"]
    ref = pd.read_parquet(o.out_dir / "timeseries.parquet")
    mem = o.result.to_pandas()  # the in-memory result: every column (the file has the chosen ones)
    assert list(mem.columns) == ["t", *o.result.z_labels, *o.result.y_labels]
    assert mem.attrs["units"]["r_x"] == "m" and set(ref.attrs["units"].items()) <= set(mem.attrs["units"].items())
    assert mem.attrs["fields"]["r"] == ref.attrs["fields"]["r"] == ["r_x", "r_y", "r_z"]
    run = {k: v for k, v in ref.attrs["run"].items() if k not in ("scenario", "model_source_hash", "rpo_version",
                                                                  "created_utc")}  # what only run.json knows
    assert run == {k: mem.attrs["run"][k] for k in run}


def test_read_run_to_pandas_is_the_frame_pd_read_parquet_gives(folders):
    pd = pytest.importorskip("pandas")
    out = folders["001"].out_dir
    df, ref = read_run(out).to_pandas(), pd.read_parquet(out / "timeseries.parquet")
    pd.testing.assert_frame_equal(df, ref)
    assert df.attrs == ref.attrs


def test_to_pandas_without_pandas_is_a_clear_error(folders, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ModelError, match="needs pandas .*pip install pandas"):
        folders["001"].result.to_pandas()


# --------------------------------------------------------------------------- read_run and the formats


def test_read_run_gives_the_written_table_with_units_fields_and_the_record(folders):
    o = folders["001"]
    res = read_run(o.out_dir)
    mem = o.result
    assert res["r"].shape == (mem.t.size, 3) and res.unit("r") == "m" and res.unit("w_c") == "rad/s"
    assert res["r"].tobytes() == mem["r"].tobytes() and res.t.tobytes() == mem.t.tobytes()
    assert res.fields[0] == "q_c" and "env_beta_fov" in res.fields
    assert res.meta["verdict"]["line"] == o.metrics["verdict"]["line"]
    assert res.meta["metrics"]["att_err_final_rad"] == o.metrics["att_err_final_rad"]
    assert res.ok and res.dt == mem.dt and res.steps_done == mem.steps_done
    div = read_run(folders["002"].out_dir)
    assert not div.ok and div.divergence.label == folders["002"].result.divergence.label
    assert div.divergence.time == pytest.approx(folders["002"].result.divergence.time)


@pytest.mark.parametrize("keep", ["timeseries.mat", "timeseries.npz"])
def test_read_run_reads_the_same_table_from_mat_and_npz(folders, tmp_path, keep):
    import shutil

    src = folders["001"].out_dir
    dst = tmp_path / "copy"
    dst.mkdir()
    for name in ("run.json", "metrics.json", keep):
        shutil.copy(src / name, dst / name)
    a, b = read_run(src), read_run(dst)
    assert (a.z_labels, a.z_units, a.y_labels, a.y_units) == (b.z_labels, b.z_units, b.y_labels, b.y_units)
    assert a.z.tobytes() == b.z.tobytes() and a.y.tobytes() == b.y.tobytes() and a.t.tobytes() == b.t.tobytes()
    assert dict(a.field_labels) == dict(b.field_labels)
    (dst / keep).unlink()
    (dst / "timeseries.csv").write_text("t [s]\n0\n")
    with pytest.raises(OutputError, match="no time histories read_run can read .*timeseries.csv"):
        read_run(dst)
    with pytest.raises(OutputError, match="no run.json"):
        read_run(tmp_path)


def test_mat_holds_each_field_as_an_n_by_k_array_with_units_and_labels(folders):
    from scipy.io import loadmat

    o = folders["001"]
    mat = loadmat(o.out_dir / "timeseries.mat", simplify_cells=True)
    h = mat["history"]
    n = o.result.t.size
    assert h["r"].shape == (n, 3) and h["q_c"].shape == (n, 4) and h["t"].shape == (n,)
    assert h["units"]["r"] == "m" and h["units"]["t"] == "s" and h["units"]["w_c"] == "rad/s"
    assert list(h["labels"]["r"]) == ["r_x", "r_y", "r_z"] and h["layouts"]["r"] == "z_c001"
    np.testing.assert_array_equal(h["r"], o.result["r"])
    assert not any(k in mat for k in ("r_x", "columns", "units"))  # no flat columns any more
    assert json.loads(mat["metadata"])["controller"] == "c001"


# --------------------------------------------------------------------------- human text


def test_human_text_shows_angles_in_deg_rates_in_deg_s_wheel_speeds_in_rpm():
    assert shown("att_err_final_rad", "rad") == ("att_err_final_deg", "deg", pytest.approx(180 / math.pi))
    assert shown("rate_err_final_rad_s", "rad/s")[:2] == ("rate_err_final_deg_s", "deg/s")
    assert shown("wheel_speed_peak_rad_s", "rad/s")[:2] == ("wheel_speed_peak_rpm", "rpm")
    assert shown("pos_err_final_m", "m") == ("pos_err_final_m", "m", 1.0)


def test_the_printed_table_and_the_verdict_line_never_show_rad(folders, capsys):
    from rpo.runtime.outputs.metrics import format_table

    for o in folders.values():
        text = format_table(o.metrics) + "\n" + o.metrics["verdict"]["line"]
        assert " rad" not in text and "rad/s" not in text and " deg" in text
