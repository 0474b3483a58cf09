"""The ``rpo`` command line, run as a user would (subprocesses): exit codes, one-line errors, outputs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.scenario import paper_data

ROOT = Path(__file__).resolve().parents[1]
III = ROOT / "scenarios" / "000_scenario_III.toml"
BASE = III.read_text()
PAPER = paper_data(III)


def rpo(*args, cwd=None, timeout=120) -> subprocess.CompletedProcess:
    """``python -m rpo.runtime.cli.main ARGS`` (the same entry point as the ``rpo`` script)."""
    env = {**os.environ, "PYTHONWARNINGS": "default", "COLUMNS": "100"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


def assert_user_error(res: subprocess.CompletedProcess, *needles: str) -> None:
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert "Traceback" not in res.stderr + res.stdout
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith("error: ")
    for n in needles:
        assert n in lines[0], (n, lines[0])


# --------------------------------------------------------------------------- help and info


@pytest.mark.parametrize("sub", [[], ["run"], ["validate"], ["info"]], ids=["rpo", "run", "validate", "info"])
def test_help(sub):
    res = rpo(*sub, "--help")
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith(f"Usage: rpo {' '.join(sub)}".rstrip())
    if not sub:
        for cmd in ("run", "validate", "info"):
            assert cmd in res.stdout


def test_console_script_entry_point():
    script = Path(sys.executable).with_name("rpo")
    if not script.exists():
        pytest.skip("the rpo script is not installed next to this python")
    res = subprocess.run([str(script), "--version"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and "rpo" in res.stdout


def test_info_and_validate():
    manifest = json.loads((ROOT / "generated" / "manifest.json").read_text())
    res = rpo("info")
    assert res.returncode == 0, res.stderr
    assert manifest["source_hash"] in res.stdout
    for word in ("target_orbit", "step_baseline", "orbit_a", "wheel_speed_max", "kp_att", "casadi"):
        assert word in res.stdout
    res = rpo("validate", III)
    assert res.returncode == 0, res.stderr
    assert "valid" in res.stdout and PAPER["meta"]["name"] in res.stdout
    assert f"perigee altitude {PAPER['orbit']['perigee_altitude'] / 1e3:g} km" in res.stdout
    # which target orbit a run flies: the scenario's own (000: Keplerian) unless --plant full
    assert "plant       target orbit kepler" in res.stdout
    info = rpo("info").stdout
    assert 'full (--plant full): ' in info and 'plant.target_orbit = "propagated"' in info


def test_run_json_names_the_plant(tmp_path):
    for plant, orbit in (("paper", "kepler"), ("full", "propagated")):
        out = tmp_path / plant
        res = rpo("run", III, "--duration", "0.5", "--plant", plant, "--no-plots", "--out", out, cwd=tmp_path)
        assert res.returncode == 0, res.stderr
        meta = json.loads((out / "run.json").read_text())
        assert meta["plant"]["selected"] == plant and meta["plant"]["target_orbit"].startswith(orbit)
        assert meta["inputs"]["params"]["orbit_propagated"] == (1.0 if plant == "full" else 0.0)


def test_runtime_never_imports_sympy():
    code = ("import sys, rpo.runtime.cli.main, rpo.runtime.scenario, rpo.runtime.outputs.writers, "
            "rpo.runtime.outputs.plots, "
            "rpo.runtime.frames, rpo.runtime.run.simulate\n"
            "from rpo.runtime.scenario import load_scenario\n"
            "from rpo.runtime.model import load_model\n"
            f"load_scenario({str(III)!r}).to_run(load_model())\n"
            "bad = [m for m in sys.modules if m == 'sympy' or m.startswith(('sympy.', 'rpo.symbolic'))]\n"
            "assert not bad, bad\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr


# --------------------------------------------------------------------------- user errors


def sub(old: str, new: str) -> str:
    assert old in BASE, old
    return BASE.replace(old, new, 1)


BAD = {
    "non-unit quaternion": (sub("[0.38831, 0.22356, -0.34408, 0.82512]", "[1, 1, 0, 0]"), "target.quaternion"),
    "eccentricity": (sub("eccentricity = 0.138", "eccentricity = 1.5"), "orbit.eccentricity"),
    "perigee": (sub("perigee_altitude = 400e3", "semi_major_axis = 6000e3"), "orbit.semi_major_axis"),
    "inertia": (sub("[target]\n", "[target]\ninertia = [[1, 0, 0], [0, 2, 0], [0, 0, -3]]\n"), "target.inertia"),
    "mass": (sub("[chaser]\n", "[chaser]\nmass = -1.0\n"), "chaser.mass"),
    "unknown key": (sub("seed = 0 ", "sead = 0 "), "simulation.sead"),
    "wrong type": (sub("rate = 100.0", 'rate = "fast"'), "simulation.rate"),
    "bad TOML": (sub("[orbit]", "[orbit"), "invalid TOML"),
}


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_bad_scenario_is_one_line_exit_2_and_touches_nothing(tmp_path, case):
    text, field = BAD[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    out = tmp_path / "out"
    res = rpo("run", path, "--out", out, cwd=tmp_path)
    assert_user_error(res, "bad.toml", field)
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]  # no runs/, no temporary folder
    res = rpo("validate", path, cwd=tmp_path)
    assert_user_error(res, field)


@pytest.mark.parametrize("args,needle", [
    (["run", "missing.toml"], "missing.toml: cannot read the scenario"),
    (["run", III, "--duration", "-1"], "--duration"),
    (["run", III, "--seed", "x"], "--seed"),
    (["run", III, "--backend", "gpu"], "--backend"),
    (["run"], "SCENARIO"),
    (["frobnicate"], "frobnicate"),
    (["run", III, "--duration", "0.001"], "simulation.duration = 0.001"),
], ids=["missing-file", "duration", "seed", "backend", "no-arg", "command", "too-short"])
def test_bad_command_line(tmp_path, args, needle):
    res = rpo(*args, "--out", tmp_path / "out", cwd=tmp_path) if args[0] == "run" and len(args) > 1 else \
        rpo(*args, cwd=tmp_path)
    assert_user_error(res, needle)
    assert list(tmp_path.iterdir()) == []


def test_existing_output_folder_is_refused_and_left_intact(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("precious")
    res = rpo("run", III, "--duration", "0.05", "--out", out, cwd=tmp_path)
    assert_user_error(res, "not empty", str(out))
    assert [p.name for p in out.iterdir()] == ["keep.txt"]
    assert (out / "keep.txt").read_text() == "precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    # a file in the way is refused as well
    res = rpo("run", III, "--duration", "0.05", "--out", out / "keep.txt", cwd=tmp_path)
    assert_user_error(res, "keep.txt")
    assert (out / "keep.txt").read_text() == "precious"


# --------------------------------------------------------------------------- good and diverged runs


def test_short_run_writes_everything(tmp_path):
    out = tmp_path / "out"
    res = rpo("run", III, "--duration", "2", "--seed", "3", "--out", out, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    assert f"results: {out}" in res.stdout
    names = {p.name for p in out.iterdir()}
    meta = json.loads((out / "run.json").read_text())
    figures = set(meta["figures"])
    assert {"attitude.png", "translation.png", "actuators.png", "thrusters.png", "controller.png",
            "diagnostics.png"} <= figures
    assert {"timeseries.parquet", "run.json", "scenario.toml", "metrics.json"} | figures == names
    assert (out / "scenario.toml").read_text() == BASE
    for f in figures:
        assert (out / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["status"] == "ok" and metrics["t_end_s"] == pytest.approx(2.0)
    assert "metrics" in res.stdout and "attitude" in res.stdout

    assert meta["status"] == "ok" and meta["divergence"] is None
    assert meta["steps_done"] == meta["steps_requested"] == 200
    assert meta["seed"] == 3 and meta["controller"] == PAPER["simulation"]["controller"] == "c000"
    assert meta["backend"] == "compiled"
    manifest = json.loads((ROOT / "generated" / "manifest.json").read_text())
    assert meta["model_source_hash"] == manifest["source_hash"]
    assert meta["overrides"] == {"duration": 2.0, "seed": 3}

    import pyarrow.parquet as pq
    table = pq.read_table(out / "timeseries.parquet")
    t = table["t"].to_numpy()
    assert t.shape == (201,) and t[-1] == pytest.approx(2.0)
    assert table.column_names[:2] == ["t", "q_c_x"] and "r_x" in table.column_names
    assert table.schema.field("r_x").metadata[b"unit"] == b"m"
    assert json.loads(table.schema.metadata[b"rpo.run"])["status"] == "ok"
    r0 = [table[c].to_numpy()[0] for c in ("r_x", "r_y", "r_z")]
    np.testing.assert_array_equal(r0, PAPER["relative"]["position"])
    assert np.all(np.isfinite(table["meas_q_e_w"].to_numpy()))  # the final row has the final state's output


def test_quiet_run_without_plots_and_default_folder(tmp_path):
    res = rpo("run", III, "--duration", "0.5", "--no-plots", "--quiet", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stdout == "" and res.stderr == ""
    (runs,) = list((tmp_path / "runs").iterdir())
    assert runs.name.startswith("000_scenario_III-")
    assert not list(runs.glob("*.png"))
    assert (runs / "timeseries.parquet").exists()


def test_diverged_run_writes_results_and_exits_3(tmp_path):
    path = tmp_path / "spin.toml"
    path.write_text(sub("angular_velocity_deg_s = [0.0, 0.0, 0.0]", "angular_velocity = [30.0, 0.0, 0.0]"))
    out = tmp_path / "out"
    res = rpo("run", path, "--duration", "1", "--out", out, cwd=tmp_path)
    assert res.returncode == 3, res.stderr
    assert "Traceback" not in res.stderr
    assert "diverged" in res.stderr and "w_c_x" in res.stderr and "step 0" in res.stderr
    meta = json.loads((out / "run.json").read_text())
    assert meta["status"] == "diverged"
    assert meta["divergence"]["label"] == "w_c_x" and meta["divergence"]["step"] == 0
    assert meta["steps_done"] < meta["steps_requested"]
    import pyarrow.parquet as pq
    assert pq.read_metadata(out / "timeseries.parquet").num_rows == meta["rows"] >= 1
    assert (out / "attitude.png").exists() and "attitude.png" in meta["figures"]
