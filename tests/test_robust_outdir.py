"""The output folder is checked completely before anything is computed, and the results are
never lost at the end: refused folders are named in one line and left as they were."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import OutputError
from rpo.runtime.formats import OUTPUT_FORMATS
from rpo.runtime.jobs.runner import execute_run
from rpo.runtime.outputs.writers import OutputSpec, check_out_dir, write_run
from rpo.runtime.run.simulate import Simulation

from conftest import Q_C0_III, Q_T0_III, unit

ROOT = Path(__file__).resolve().parents[1]
III = ROOT / "scenarios" / "000_scenario_III.toml"
NO_PLOTS = OutputSpec(figures=False)


def _replace_writer(monkeypatch, write) -> None:
    """The default format's writer replaced by ``write`` (the registry holds the writers)."""
    name = NO_PLOTS.formats[0]
    monkeypatch.setitem(OUTPUT_FORMATS, name, dataclasses.replace(OUTPUT_FORMATS[name], write=write))


@pytest.fixture(scope="module")
def short_run(model):
    sim = Simulation(model)
    z0 = sim.initial_state({"q_c": unit(Q_C0_III), "q_t": unit(Q_T0_III), "r": [60, 0, 25], "v": [3, -0.5, 5]})
    return sim.run(z0, 0.05)


def _refused(path, *needles: str) -> str:
    with pytest.raises(OutputError) as err:
        check_out_dir(path)
    msg = str(err.value)
    assert "\n" not in msg and all(n in msg for n in needles), msg
    return msg


def test_dot_dotdot_root_and_the_current_folder_are_refused(tmp_path, monkeypatch):
    (tmp_path / "sub").mkdir()
    monkeypatch.chdir(tmp_path / "sub")
    for path in (".", "..", "/", "./", "../sub/..", tmp_path / "sub", "../sub"):
        _refused(path, "output folder")
    _refused(".", "not ., .. or /")
    _refused(tmp_path / "sub", "is the current folder")
    assert list((tmp_path / "sub").iterdir()) == []


def test_a_read_only_empty_folder_is_refused_and_left_as_it_is(tmp_path):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o555)
    try:
        _refused(out, str(out), "not writable", "0o555")  # also as root: the mode bits are respected
        assert out.stat().st_mode & 0o777 == 0o555 and list(out.iterdir()) == []
    finally:
        out.chmod(0o755)


def test_an_unwritable_parent_is_refused_before_the_model_is_even_loaded(tmp_path):
    parent = tmp_path / "locked"
    parent.mkdir()
    parent.chmod(0o555)

    def model(_controller):
        raise AssertionError("the model was loaded: the folder check came too late")

    try:
        with pytest.raises(OutputError, match=f"its parent {parent} is not writable"):
            execute_run(III, parent / "new" / "out", model, duration=0.05, plots=False)
        assert list(parent.iterdir()) == []
    finally:
        parent.chmod(0o755)


def test_a_file_in_the_way_of_a_missing_parent_is_refused(tmp_path):
    (tmp_path / "f").write_text("x")
    _refused(tmp_path / "f" / "out", "is not a folder")
    assert (tmp_path / "f").read_text() == "x"


def test_a_symlink_to_an_empty_folder_is_resolved_and_the_results_land_in_the_target(model, short_run, tmp_path):
    target = tmp_path / "target"
    target.mkdir()
    link = tmp_path / "link"
    link.symlink_to(target)
    assert check_out_dir(link) == target.resolve()
    written = write_run(short_run, link, model, output=NO_PLOTS)
    assert written == target.resolve() and link.is_symlink() and link.resolve() == target.resolve()
    assert json.loads((target / "run.json").read_text())["status"] == "ok"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "target"]


def test_a_symlink_to_a_non_empty_folder_or_a_file_is_refused(tmp_path):
    full = tmp_path / "full"
    full.mkdir()
    (full / "keep").write_text("x")
    (tmp_path / "l1").symlink_to(full)
    _refused(tmp_path / "l1", "not empty", f"-> {full}")
    (tmp_path / "l2").symlink_to(full / "keep")
    _refused(tmp_path / "l2", "not a folder")
    assert (full / "keep").read_text() == "x"


def test_a_dangling_symlink_gets_its_target_created(model, short_run, tmp_path):
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "later" / "out")
    written = write_run(short_run, link, model, output=NO_PLOTS)
    assert written == (tmp_path / "later" / "out").resolve() and (link / "run.json").is_file()


def test_an_existing_empty_folder_is_filled_in_place_keeping_its_mode(model, short_run, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    out.chmod(0o710)
    ino = out.stat().st_ino
    write_run(short_run, out, model, output=NO_PLOTS)
    assert out.stat().st_ino == ino and out.stat().st_mode & 0o777 == 0o710
    assert sorted(p.name for p in out.iterdir()) == ["run.json", "timeseries.parquet"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


@pytest.mark.parametrize("existing", [False, True])
def test_a_folder_that_appears_while_writing_is_never_replaced_and_the_results_are_kept(model, short_run, tmp_path,
                                                                                         monkeypatch, existing):
    out = tmp_path / "out"
    if existing:
        out.mkdir()
    real = OUTPUT_FORMATS[NO_PLOTS.formats[0]].write

    def write_and_race(path, table):  # someone else creates the folder (or a file in it) meanwhile
        real(path, table)
        out.mkdir(exist_ok=True)
        (out / "theirs.txt").write_text("theirs") if existing else None

    _replace_writer(monkeypatch, write_and_race)
    with pytest.raises(OutputError) as err:
        write_run(short_run, out, model, output=NO_PLOTS)
    msg = str(err.value)
    assert "\n" not in msg and f"cannot move the results into {out}" in msg and "they are complete in " in msg
    kept = Path(msg.rsplit("they are complete in ", 1)[1])
    assert kept.is_dir() and json.loads((kept / "run.json").read_text())["steps_done"] == short_run.steps_done
    assert sorted(p.name for p in out.iterdir()) == (sorted(["theirs.txt", kept.name]) if existing else [])


def test_an_error_while_writing_leaves_no_temporary_folder(model, short_run, tmp_path, monkeypatch):
    def broken(path, table):
        Path(path).write_bytes(b"half")
        raise OSError(28, "No space left on device")

    _replace_writer(monkeypatch, broken)
    with pytest.raises(OutputError, match="No space left on device"):
        write_run(short_run, tmp_path / "out", model, output=NO_PLOTS)
    assert list(tmp_path.iterdir()) == []
    assert np.isfinite(short_run.z).all()


@pytest.mark.parametrize("code, fix", [("ENOSPC", "free space"), ("EROFS", "make it writable"),
                                       ("EACCES", "make it writable")])
def test_an_os_error_of_any_command_is_one_line_naming_the_path(monkeypatch, capsys, tmp_path, code, fix):
    """A full disk or a read-only folder met anywhere (here: while `rpo run` writes its folder) ends in
    one `error:` line naming the path, what happened and what to do, exit 1, no traceback."""
    import errno
    import os

    import rpo.runtime.jobs.runner as runner
    from rpo.runtime.cli.main import main

    path = str(tmp_path / "out" / "timeseries.parquet")

    def refuse(*_a, **_k):
        raise OSError(getattr(errno, code), os.strerror(getattr(errno, code)), path)

    monkeypatch.setattr(runner, "execute_run", refuse)
    assert main(["run", str(III), "--duration", "0.1", "--no-plots", "--out", str(tmp_path / "out"), "-q"]) == 1
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and "Traceback" not in err, err
    assert path in lines[0] and f"({code})" in lines[0] and fix in lines[0] and "run the command again" in lines[0]
