"""The results folder: [output] selection and decimation, the formats (bit for bit, with units),
the figures in each format, metrics independent of what is written, and bad [output] entries."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import ScenarioError
from rpo.runtime.formats import matlab_names
from rpo.runtime.jobs.runner import execute_run
from rpo.runtime.outputs.writers import written_rows
from rpo.runtime.scenario import loads_scenario
from rpo.runtime.scenario.channels import DEFAULT_CHANNELS, ChannelError, select

ROOT = Path(__file__).resolve().parents[1]
III = ROOT / "scenarios" / "000_scenario_III.toml"
BASE = III.read_text()


def scenario(tmp_path: Path, output: str = "", name: str = "s.toml") -> Path:
    """Scenario III with an [output] table appended (written into tmp_path)."""
    path = tmp_path / name
    path.write_text(BASE + ("\n[output]\n" + output if output else ""))
    return path


def run(model, path: Path, out: Path, **kw):
    kw.setdefault("duration", 0.5)
    return execute_run(path, out, model, **kw)


def selected(outcome, model):
    """{label: in-memory column} of the run's default-or-chosen selection, rows as written."""
    r = outcome.result
    ctrl = r.meta["controller"]
    o = outcome.scenario.output
    sel = select(o.channels, model.layouts[f"z_{ctrl}"], model.layouts[f"y_{ctrl}"])
    rows = written_rows(r.t, r.dt, o.step(r.dt, r.meta["record_every"]))
    cols = {"t": r.t[rows]}
    cols.update({lbl: r.column(lbl)[rows] for lbl in sel.labels})
    units = {"t": "s", **dict(zip(r.z_labels, r.z_units, strict=True)), **dict(zip(r.y_labels, r.y_units, strict=True))}
    return cols, units


# --------------------------------------------------------------------------- channels


def test_select_fields_labels_patterns_and_default(model):
    z, y = model.layouts["z_c000"], model.layouts["y_c000"]
    s = select(["r", "meas_q_e_w", "env_M_gg_*"], z, y)
    assert s.z == ("r_x", "r_y", "r_z")
    assert s.y == ("meas_q_e_w", *(f"env_M_gg_{b}_{c}" for b in ("c", "t") for c in "xyz"))
    default = select(None, z, y)
    assert select(["default"], z, y) == default
    assert "thr_on_00" in default.y and "pwpf_f_00" not in default.z and "ctrl_s_att_x" in default.y
    assert set(select(["*"], z, y).labels) == {lbl for f in (*z, *y) for lbl in f.labels}
    # the default set skips what a controller does not log (baseline has no ctrl_q_err)
    assert "ctrl_q_err" in DEFAULT_CHANNELS or "ctrl_*" in DEFAULT_CHANNELS
    assert "ctrl_att_err" in select(None, model.layouts["z_baseline"], model.layouts["y_baseline"]).y


@pytest.mark.parametrize("entry,near", [("ctrl_s_atx", "ctrl_s_att_x"), ("whel_speed*", "wheel"), ("rr", "r")])
def test_unknown_channel_lists_close_matches(model, entry, near):
    with pytest.raises(ChannelError) as exc:
        select([entry], model.layouts["z_c000"], model.layouts["y_c000"])
    assert entry in str(exc.value) and near in str(exc.value) and "close matches" in str(exc.value)


def test_matlab_names_are_valid_and_distinct():
    names = matlab_names(["t", "r_x", "1bad", "a-b", "units", "x" * 80, "x" * 80])
    assert names[:2] == ["t", "r_x"]
    assert len(set(names)) == len(names)
    assert all(n[0].isalpha() and len(n) <= 63 and n.replace("_", "").isalnum() for n in names)
    assert "units" not in names  # reserved for the units struct


# --------------------------------------------------------------------------- formats round-trip


def test_formats_round_trip_bit_for_bit_with_units(model, tmp_path):
    out = tmp_path / "out"
    o = run(model, scenario(tmp_path), out, formats=["parquet", "mat", "csv", "npz"], plots=False)
    cols, units = selected(o, model)
    files = {p.name for p in out.iterdir()}
    assert {"timeseries.parquet", "timeseries.mat", "timeseries.csv", "timeseries.npz"} <= files
    assert not any(f.endswith((".png", ".svg", ".pdf")) for f in files)

    import pyarrow.parquet as pq
    table = pq.read_table(out / "timeseries.parquet")
    assert table.column_names == list(cols)
    for lbl, want in cols.items():
        got = table[lbl].to_numpy()
        assert got.dtype == np.float64 and got.tobytes() == want.tobytes(), lbl  # bit for bit, NaN included
        assert table.schema.field(lbl).metadata[b"unit"].decode() == units[lbl]
    run_meta = json.loads(table.schema.metadata[b"rpo.run"])
    assert run_meta["status"] == "ok" and run_meta["controller"] == "c000"
    assert json.loads(table.schema.metadata[b"rpo.units"])["r_x"] == "m"

    # .mat: one N x k array per layout field in the struct `history` (was: one N x 1 variable per
    # column, a `units` struct and a `columns` cell array; the format changed on purpose)
    from scipy.io import loadmat
    mat = loadmat(out / "timeseries.mat")
    h = mat["history"][0, 0]
    labels = {name: [str(x[0]) for x in h["labels"][0, 0][name].ravel()] for name in h["labels"][0, 0].dtype.names}
    assert [lbl for name in labels for lbl in labels[name]] == list(cols)  # every column, in order
    for name, lbls in labels.items():
        block = h[name]
        assert block.shape == (len(cols["t"]), len(lbls)), name
        for i, lbl in enumerate(lbls):
            assert block[:, i].tobytes() == cols[lbl].tobytes(), lbl
            assert str(h["units"][0, 0][name][0]) == units[lbl], lbl
    assert labels["r"] == ["r_x", "r_y", "r_z"] and labels["t"] == ["t"]
    assert json.loads(str(mat["metadata"][0]))["status"] == "ok"

    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    assert header == [f"{lbl} [{units[lbl]}]" for lbl in cols]
    csv = np.loadtxt(out / "timeseries.csv", delimiter=",", skiprows=1)
    for i, (lbl, want) in enumerate(cols.items()):
        assert csv[:, i].tobytes() == want.tobytes(), lbl

    npz = np.load(out / "timeseries.npz")
    assert npz["t"].tobytes() == cols["t"].tobytes()
    assert list(npz["z_labels"]) + list(npz["y_labels"]) == list(cols)[1:]

    meta = json.loads((out / "run.json").read_text())
    assert meta["output"]["formats"] == ["parquet", "mat", "csv", "npz"] and meta["figures"] == []
    assert meta["output"]["rows_written"] == len(cols["t"]) == 51


# --------------------------------------------------------------------------- selection and decimation


def test_output_table_selects_and_decimates(model, tmp_path):
    out = tmp_path / "out"
    o = run(model, scenario(tmp_path, 'channels = ["r", "ctrl_att_err", "meas_q_e_w"]\nevery = 10\n'), out,
            duration=0.55, plots=False)
    import pyarrow.parquet as pq
    table = pq.read_table(out / "timeseries.parquet")
    assert table.column_names == ["t", "r_x", "r_y", "r_z", "meas_q_e_w", "ctrl_att_err"]
    t = table["t"].to_numpy()
    np.testing.assert_allclose(t, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.55], atol=1e-12)  # and the final row
    assert len(o.result.t) == 56  # the in-memory record keeps every step
    rows = written_rows(o.result.t, o.result.dt, 10)
    assert table["r_x"].to_numpy().tobytes() == o.result.column("r_x")[rows].tobytes()
    # rate_hz says the same
    out2 = tmp_path / "out2"
    run(model, scenario(tmp_path, 'channels = ["r"]\nrate_hz = 10.0\n', "s2.toml"), out2, duration=0.55, plots=False)
    assert pq.read_table(out2 / "timeseries.parquet")["t"].to_numpy().tobytes() == t.tobytes()


def test_metrics_do_not_depend_on_what_is_written(model, tmp_path):
    full = run(model, scenario(tmp_path, "", "a.toml"), tmp_path / "a", duration=2.0, plots=False)
    thin = run(model, scenario(tmp_path, 'channels = ["r"]\nevery = 50\n', "b.toml"), tmp_path / "b",
               duration=2.0, plots=False)
    a = json.loads((tmp_path / "a" / "metrics.json").read_text())
    b = json.loads((tmp_path / "b" / "metrics.json").read_text())
    assert a == b and full.metrics["chatter_cmd_tau_w_tv_per_s"] == thin.metrics["chatter_cmd_tau_w_tv_per_s"]
    assert json.loads((tmp_path / "b" / "run.json").read_text())["output"]["rows_written"] == 5


# --------------------------------------------------------------------------- figures


MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "svg": b"<?xml", "pdf": b"%PDF"}


@pytest.mark.parametrize("fmt", ["png", "svg", "pdf"])
def test_figures_in_each_format(model, tmp_path, fmt):
    out = tmp_path / "out"
    run(model, scenario(tmp_path), out, duration=0.3, figure_format=fmt)
    meta = json.loads((out / "run.json").read_text())
    assert "plot_error" not in meta
    assert meta["figures"] == [f"{n}.{fmt}" for n in ("attitude", "translation", "errors", "lvlh", "approach",
                                                      "actuators", "thrusters", "controller", "constraints",
                                                      "diagnostics")]
    for f in meta["figures"]:
        assert (out / f).read_bytes()[:len(MAGIC[fmt])] == MAGIC[fmt], f
    assert not list(tmp_path.glob(".*.tmp"))  # the temporary folder was renamed


def test_figure_format_from_the_output_table(model, tmp_path):
    out = tmp_path / "out"
    run(model, scenario(tmp_path, 'figure_format = "svg"\nformats = ["csv"]\n'), out, duration=0.2)
    names = {p.name for p in out.iterdir()}
    assert "attitude.svg" in names and "timeseries.csv" in names and "timeseries.parquet" not in names
    out2 = tmp_path / "out2"
    run(model, scenario(tmp_path, "figures = false\n", "nf.toml"), out2, duration=0.2)
    assert not [n for n in os.listdir(out2) if n.endswith(".png")]


def test_the_data_path_never_imports_matplotlib(tmp_path):
    """Figures are drawn by worker processes: the run's own process never imports matplotlib."""
    code = ("import sys\n"
            "from rpo.runtime.jobs.runner import execute_run\n"
            "from rpo.runtime.model import load_model\n"
            f"o = execute_run({str(III)!r}, {str(tmp_path / 'out')!r}, lambda c: load_model(controllers=[c]), "
            "duration=0.2)\n"
            "assert 'matplotlib' not in sys.modules, 'matplotlib imported in the data path'\n"
            "import json; print(json.dumps(json.load(open(o.out_dir / 'run.json'))['figures']))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert "attitude.png" in json.loads(res.stdout.strip().splitlines()[-1])


# --------------------------------------------------------------------------- bad [output] entries


BAD_OUTPUT = {
    "unknown channel": ('channels = ["r", "ctrl_s_atx"]\n', "output.channels[1]", "ctrl_s_att_x"),
    "pattern matches nothing": ('channels = ["foo_*"]\n', "output.channels[0]", "unknown pattern"),
    "empty channels": ("channels = []\n", "output.channels", "must have 1 values, got 0"),
    "rate_hz": ("rate_hz = 30.0\n", "output.rate_hz", "whole number"),
    "both rates": ("every = 10\nrate_hz = 10.0\n", "output.rate_hz", "not both"),
    "every": ("every = 0\n", "output.every", ">= 1"),
    "format": ('formats = ["parquet", "hdf5"]\n', "output.formats[1]", "'parquet', 'mat', 'csv' or 'npz'"),
    "figure format": ('figure_format = "jpg"\n', "output.figure_format", "'png', 'svg' or 'pdf'"),
    "unknown key": ('chanels = ["r"]\n', "output.chanels", "did you mean 'channels'"),
}


def rpo(*args, cwd=None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONWARNINGS": "default", "COLUMNS": "100"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("case", BAD_OUTPUT, ids=list(BAD_OUTPUT))
def test_bad_output_entry_is_one_line_exit_2_and_touches_nothing(tmp_path, case):
    text, key, needle = BAD_OUTPUT[case]
    scenario(tmp_path, text, "bad.toml")
    out = tmp_path / "out"
    out.mkdir()
    res = rpo("run", "bad.toml", "--out", out, cwd=tmp_path)
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr + res.stdout
    (line,) = res.stderr.strip().splitlines()
    assert line.startswith("error: bad.toml: ") and key in line and needle in line, line
    assert list(out.iterdir()) == [] and sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "out"]


def test_every_must_be_a_multiple_of_the_record(model):
    text = BASE.replace("record_every = 1 ", "record_every = 4 ") + "\n[output]\nevery = 10\n"
    with pytest.raises(ScenarioError, match=r"output.every = 10: .*multiple of simulation.record_every = 4"):
        loads_scenario(text, "x.toml", model.manifest)


def test_controller_override_revalidates_the_channels(model):
    sc = loads_scenario(BASE + '\n[output]\nchannels = ["ctrl_s_att"]\n', "x.toml", model.manifest)
    with pytest.raises(ScenarioError, match=r"output.channels\[0\] = \"ctrl_s_att\": unknown channel"):
        sc.with_overrides(controller="c001")


@pytest.mark.parametrize("arg,needle", [("hdf5", "unknown format hdf5"), ("parquet,parquet", "twice")])
def test_bad_format_option(tmp_path, arg, needle):
    res = rpo("run", III, "--format", arg, "--out", tmp_path / "out", cwd=tmp_path)
    assert res.returncode == 2 and "Traceback" not in res.stderr and needle in res.stderr
    assert list(tmp_path.iterdir()) == []
