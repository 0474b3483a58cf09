"""SIGINT and SIGTERM at any moment of ``rpo run``: a complete folder marked ``interrupted`` (with
everything computed so far) or nothing at all; never a hidden half-written folder; never a
swallowed interrupt (exit 130 for SIGINT, 143 for SIGTERM).  Real subprocesses, real signals; the
driver only prints a marker (and waits) at the moment under test."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
III = ROOT / "scenarios" / "000_scenario_III.toml"

#: the `rpo` command, with a marker on stderr (and a pause) at one moment: MOMENT names the
#: patched function, which prints "RPO-TEST <moment>" and sleeps before doing its work
DRIVER = r"""
import dataclasses, os, sys, time
moment = os.environ["RPO_TEST_MOMENT"]

def mark(fn):
    def wrapper(*a, **k):
        print(f"RPO-TEST {moment}", file=sys.stderr, flush=True)
        time.sleep(float(os.environ.get("RPO_TEST_PAUSE", "4")))
        return fn(*a, **k)
    return wrapper

from rpo.runtime.cli import main as cli
from rpo.runtime.outputs import figure_workers
from rpo.runtime.formats import DEFAULT_FORMATS, OUTPUT_FORMATS
from rpo.runtime.run import simulate
if moment == "inputs":
    simulate.Simulation.initial_state = mark(simulate.Simulation.initial_state)
elif moment == "writing":
    f = OUTPUT_FORMATS[DEFAULT_FORMATS[0]]  # the writer of the default format (the registry holds it)
    OUTPUT_FORMATS[f.name] = dataclasses.replace(f, write=mark(f.write))
elif moment == "plotting":
    figure_workers.Drawing.wait = mark(figure_workers.Drawing.wait)
sys.exit(cli.main(sys.argv[1:]))
"""


class Run:
    """``rpo run III --out <cwd>/out`` in its own session (so that SIGINT can go to the whole
    process group, as Ctrl-C does), its stderr collected by a thread."""

    def __init__(self, cwd: Path, moment: str, *args: str):
        env = {**os.environ, "RPO_TEST_MOMENT": moment}
        self.proc = subprocess.Popen([sys.executable, "-c", DRIVER, "run", str(III), "--out", "out", *args],
                                     cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                     start_new_session=True)
        self.lines: list[str] = []
        self.seen = threading.Condition()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stderr is not None
        for line in self.proc.stderr:
            with self.seen:
                self.lines.append(line.rstrip("\n"))
                self.seen.notify_all()

    def wait_for(self, text: str, timeout: float = 120) -> None:
        with self.seen:
            ok = self.seen.wait_for(lambda: any(text in ln for ln in self.lines) or self.proc.poll() is not None,
                                    timeout)
        assert ok and any(text in ln for ln in self.lines), f"never saw {text!r}: {self.lines}"

    def send(self, sig: int) -> None:
        if sig == signal.SIGINT:
            os.killpg(self.proc.pid, sig)  # Ctrl-C: the figure workers get it too
        else:
            os.kill(self.proc.pid, sig)

    def finish(self, timeout: float = 120) -> tuple[int, list[str]]:
        rc = self.proc.wait(timeout)
        self.reader.join(timeout)
        return rc, self.lines


def _no_hidden_folder(cwd: Path) -> None:
    assert sorted(p.name for p in cwd.iterdir() if p.name.startswith(".")) == []


def _error_line(lines: list[str]) -> str:
    errors = [ln for ln in lines if ln.startswith("error:")]
    assert len(errors) == 1 and not any("Traceback" in ln for ln in lines), lines
    return errors[0]


def _check_interrupted_folder(out: Path, signame: str, figures: bool) -> dict:
    import pyarrow.parquet as pq

    run = json.loads((out / "run.json").read_text())
    metrics = json.loads((out / "metrics.json").read_text())
    assert run["status"] == "interrupted" and metrics["status"] == "interrupted"
    assert run["interrupted"]["signal"] == signame
    assert 0 < run["steps_done"] < run["steps_requested"] == 60000
    assert run["interrupted"]["step"] == run["steps_done"]
    table = pq.read_table(out / "timeseries.parquet")
    assert table.num_rows == run["rows"] == run["steps_done"] + 1  # every step so far, and the state reached
    assert table.column("t")[-1].as_py() == pytest.approx(run["steps_done"] * 0.01)
    assert bool(run["figures"]) == figures and all((out / f).is_file() for f in run["figures"])
    return run


@pytest.mark.parametrize(("sig", "code", "plots", "existing"), [
    (signal.SIGINT, 130, False, True),
    pytest.param(signal.SIGTERM, 143, True, False, marks=pytest.mark.slow),
])
def test_a_signal_during_the_simulation_writes_what_was_computed_marked_interrupted(tmp_path, sig, code, plots,
                                                                                    existing):
    """``existing``: the folder given exists (empty, its own mode): the results go into it and it
    keeps its inode and mode; else it is created by one rename."""
    out = tmp_path / "out"
    if existing:
        out.mkdir()
        out.chmod(0o750)
        ino = out.stat().st_ino
    run = Run(tmp_path, "none", "--duration", "600", *(() if plots else ("--no-plots",)))
    run.wait_for("steps of 0.01 s")  # the runner's line just before the first step
    time.sleep(0.3)
    run.send(sig)
    rc, lines = run.finish()
    assert rc == code
    name = signal.Signals(sig).name
    err = _error_line(lines)
    assert f"interrupted by {name} in step" in err and "the results so far were written to out" in err
    _check_interrupted_folder(out, name, plots)
    if existing:
        assert out.stat().st_ino == ino and out.stat().st_mode & 0o777 == 0o750
    _no_hidden_folder(tmp_path)
    _no_hidden_folder(out)


@pytest.mark.parametrize(("moment", "sig", "code"), [
    ("writing", signal.SIGTERM, 143),
    pytest.param("writing", signal.SIGINT, 130, marks=pytest.mark.slow),
    pytest.param("plotting", signal.SIGINT, 130, marks=pytest.mark.slow),
    pytest.param("plotting", signal.SIGTERM, 143, marks=pytest.mark.slow),
    pytest.param("inputs", signal.SIGTERM, 143, marks=pytest.mark.slow),
])
def test_a_signal_before_the_simulation_or_while_writing_leaves_nothing(tmp_path, moment, sig, code):
    run = Run(tmp_path, moment, "--duration", "1")
    run.wait_for(f"RPO-TEST {moment}")
    run.send(sig)
    rc, lines = run.finish()
    assert rc == code
    assert _error_line(lines) == f"error: interrupted by {signal.Signals(sig).name}"
    assert list(tmp_path.iterdir()) == []  # no folder, no hidden temporary folder


@pytest.mark.slow
def test_a_second_signal_while_the_interrupted_run_is_written_leaves_nothing(tmp_path):
    env_pause = {"RPO_TEST_PAUSE": "6"}
    os.environ.update(env_pause)
    try:
        run = Run(tmp_path, "writing", "--duration", "600", "--no-plots")
    finally:
        os.environ.pop("RPO_TEST_PAUSE")
    run.wait_for("steps of 0.01 s")
    time.sleep(0.3)
    run.send(signal.SIGINT)            # stop: the folder is being written ...
    run.wait_for("RPO-TEST writing")
    run.send(signal.SIGTERM)           # ... and now quit without it
    rc, lines = run.finish()
    assert rc == 143 and _error_line(lines) == "error: interrupted by SIGTERM"
    assert list(tmp_path.iterdir()) == []
