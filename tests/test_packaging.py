"""Packaging: discovered packages, package data, the shipped scenarios, and build.py's checkout check.

The wheel itself is built, installed into a fresh venv and used from outside the checkout by
``.ci/smoke_wheel`` (a step of ``.ci/run``); these tests check the parts that need no install.
"""

from __future__ import annotations

import glob
import importlib.util
import subprocess
import sys
import tomllib
from importlib import resources
from pathlib import Path

import pytest
import structure

import setup
from rpo.runtime.cli.main import main
from rpo.runtime.errors import OutputError, ScenarioError
from rpo.runtime.scenario import SCENARIO_DIR, paper_data, read_scenario, shipped

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
SHIPPED_FILES = sorted((ROOT / "scenarios").rglob("*.toml"))


# --------------------------------------------------------------------------- discovery (setup.py)


def _folders(root: Path) -> set[str]:
    """Every folder under the four tops as a dotted rpo package (``__pycache__`` aside), and ``rpo`` itself
    (setup.API, which is not also a runtime subpackage)."""
    out = {"rpo"}
    for top in setup.TOPS:
        out.add(f"rpo.{top}")
        for d in (root / top).rglob("*"):
            rel = d.relative_to(root)
            if d.is_dir() and "__pycache__" not in rel.parts and rel.as_posix() != setup.API:
                out.add("rpo." + ".".join(rel.parts))
    return out


def test_every_folder_is_a_discovered_package():
    pkgs = setup.packages(ROOT)
    assert len(pkgs) == len(set(pkgs))
    assert set(pkgs) == _folders(ROOT)
    assert {"rpo.symbolic.controllers", "rpo.symbolic.lyapunov.certify", "rpo.runtime.model", "rpo.runtime.csrc",
            "rpo.generated", "rpo.scenarios", "rpo.scenarios.campaigns"} <= set(pkgs)
    assert setup.package_dir() == {"rpo": "runtime/api", "rpo.symbolic": "symbolic", "rpo.runtime": "runtime",
                                   "rpo.generated": "generated", "rpo.scenarios": "scenarios"}
    assert "rpo" in pkgs and "rpo.runtime.api" not in pkgs  # the API is the package rpo, not a runtime subpackage


def test_no_package_list_is_kept_by_hand():
    tool = PYPROJECT["tool"]["setuptools"]
    assert "packages" not in tool and "package-dir" not in tool
    assert structure.figures()["hand_kept_package_entries"] == 0  # issue 23's figure


def test_a_new_subpackage_is_picked_up_with_no_edit(tmp_path):
    for top in setup.TOPS:
        (tmp_path / top).mkdir()
    for new in ("symbolic/physics", "symbolic/codegen/emit", "runtime/model", "scenarios/benchmarks"):
        (tmp_path / new).mkdir(parents=True)
        (tmp_path / new / "__init__.py").write_text("")
    (tmp_path / "runtime" / "model" / "__pycache__").mkdir()
    assert setup.packages(tmp_path) == [
        "rpo", "rpo.symbolic", "rpo.symbolic.codegen", "rpo.symbolic.codegen.emit", "rpo.symbolic.physics",
        "rpo.runtime", "rpo.runtime.model", "rpo.generated", "rpo.scenarios", "rpo.scenarios.benchmarks"]


# --------------------------------------------------------------------------- package data (pyproject.toml)


def _shipped_data(pkg: str) -> set[Path]:
    """The files setuptools installs as ``pkg``'s data (its globs, expanded as setuptools does)."""
    folder = ROOT / setup.package_dir().get(pkg, "")
    if pkg not in setup.package_dir():
        top, _, rest = pkg.removeprefix("rpo.").partition(".")
        folder = ROOT / top / rest.replace(".", "/")
    return {folder / f for pattern in PYPROJECT["tool"]["setuptools"]["package-data"].get(pkg, [])
            for f in glob.glob(pattern, root_dir=folder, recursive=True)}


def test_the_files_the_installed_package_reads_are_package_data():
    data = set().union(*(_shipped_data(pkg) for pkg in setup.packages(ROOT)))
    gen = ROOT / "generated"
    needed = {*(f for f in gen.iterdir() if f.suffix in (".c", ".h", ".json", ".gz")),
              *(ROOT / "runtime" / "csrc").iterdir(), *(ROOT / "runtime" / "flight" / "firmware").iterdir(),
              *(ROOT / "runtime" / "flight" / "data").iterdir(), *SHIPPED_FILES}
    assert needed - data == set()
    assert len(SHIPPED_FILES) >= 17 and any(f.parent.name == "campaigns" for f in SHIPPED_FILES)


def test_what_the_scenarios_extend_is_shipped_too():
    for f in SHIPPED_FILES:
        assert set(read_scenario(f).bases) <= {p.resolve() for p in SHIPPED_FILES}, f


# --------------------------------------------------------------------------- the shipped scenarios


def _rel(paths) -> list[str]:
    return [Path(p).relative_to(SCENARIO_DIR).as_posix() for p in paths]


def test_the_shipped_scenarios_come_through_importlib_resources():
    """In every install mode: this checkout's scenarios/ (pip install -e .) or the installed copy of it."""
    assert SCENARIO_DIR == shipped.folder() == Path(str(resources.files("rpo.scenarios")))
    assert {f: (SCENARIO_DIR / f).read_bytes() for f in _rel(SCENARIO_DIR.rglob("*.toml"))} == \
        {f.relative_to(ROOT / "scenarios").as_posix(): f.read_bytes() for f in SHIPPED_FILES}
    assert paper_data("000_scenario_III") == read_scenario(ROOT / "scenarios" / "000_scenario_III.toml").data
    assert paper_data("campaigns/000_III_mc")["campaign"]["runs"] >= 1


def test_the_list_names_every_shipped_file_with_a_description():
    items = shipped.shipped()
    rel = sorted(f.relative_to(ROOT / "scenarios").as_posix() for f in SHIPPED_FILES)
    assert _rel(s.path for s in items) == [*(f for f in rel if "/" not in f), *(f for f in rel if "/" in f)]
    assert [s.name for s in items] == [f.removesuffix(".toml") for f in _rel(s.path for s in items)]
    by_name = {s.name: s for s in items}
    assert by_name["000_scenario_III"].description.startswith("tumbling target")  # [meta] description
    assert by_name["000_III_ideal"].description == "000 scenario III with ideal actuators"  # its own [meta] name
    assert by_name["campaigns/000_III_mc"].kind == "campaign"
    assert all(s.description and "\n" not in s.description for s in items)


def test_find_by_name_stem_or_file_name():
    assert shipped.find("000_scenario_III").path == SCENARIO_DIR / "000_scenario_III.toml"
    assert shipped.find("000_scenario_III.toml") == shipped.find("000_scenario_III")
    assert shipped.find("000_III_mc") == shipped.find("campaigns/000_III_mc")
    with pytest.raises(ScenarioError, match=r"no shipped scenario '000_scenario_IV'; did you mean 000_scenario_I"):
        shipped.find("000_scenario_IV")


def test_copy_of_a_scenario_is_the_shipped_bytes(tmp_path):
    copies = shipped.copy_out("001_scenario", tmp_path / "mine.toml")
    assert [(c.path, c.written) for c in copies] == [(tmp_path / "mine.toml", True)]
    assert (tmp_path / "mine.toml").read_bytes() == (ROOT / "scenarios" / "001_scenario.toml").read_bytes()
    shipped.copy_out("001_scenario", tmp_path)  # into a folder: under its own name
    assert (tmp_path / "001_scenario.toml").read_bytes() == (tmp_path / "mine.toml").read_bytes()


@pytest.mark.parametrize("name", ["000_III_ideal", "campaigns/000_III_mc", "campaigns/001_mc_c000"])
def test_copy_of_a_variant_brings_its_bases_and_reads_the_same(tmp_path, name):
    """A variant is copied with what it extends (``../`` bases next to it), and reads as the shipped one."""
    copies = shipped.copy_out(name, tmp_path / "edit.toml")
    assert all(c.written and c.path.parent == tmp_path for c in copies)
    src = read_scenario(shipped.find(name).path)
    assert [c.source for c in copies[1:]] == list(src.bases)
    assert read_scenario(tmp_path / "edit.toml").data == src.data
    assert {p.name for p in tmp_path.iterdir()} == {"edit.toml", *(b.name for b in src.bases)}


def test_copy_reuses_an_identical_base_and_refuses_a_different_one(tmp_path):
    shipped.copy_out("000_scenario_III", tmp_path)
    copies = shipped.copy_out("000_III_ideal", tmp_path)
    assert [(c.path.name, c.written) for c in copies] == [("000_III_ideal.toml", True),
                                                          ("000_scenario_III.toml", False)]
    base = tmp_path / "000_scenario_III.toml"
    base.write_text(base.read_text() + "# edited\n")
    with pytest.raises(OutputError, match="000_scenario_III.toml exists and is not the shipped"):
        shipped.copy_out("000_III_no_acc_d", tmp_path)
    assert not (tmp_path / "000_III_no_acc_d.toml").exists()  # refused before anything was written
    (tmp_path / "sub").mkdir()
    with pytest.raises(OutputError, match="would have the name of its base"):
        shipped.copy_out("000_III_ideal", tmp_path / "sub" / "000_scenario_III.toml")
    assert not any((tmp_path / "sub").iterdir())


def test_cli_lists_the_shipped_scenarios(capsys):
    assert main(["scenarios"]) == 0
    out = capsys.readouterr()
    lines = out.out.splitlines()
    assert lines[0].split() == ["name", "description"] and len(lines) == len(SHIPPED_FILES) + 1
    assert any(ln.startswith("campaigns/001_mc ") for ln in lines)
    assert "rpo scenarios NAME --to FILE" in out.err


def test_cli_copies_one_out_and_prints_where_a_shipped_one_is(tmp_path, capsys):
    assert main(["scenarios", "000_III_ideal", "--to", str(tmp_path / "x.toml")]) == 0
    assert capsys.readouterr().err.splitlines() == [f"wrote {tmp_path / 'x.toml'} (a copy of 000_III_ideal.toml)",
                                                    f"wrote {tmp_path / '000_scenario_III.toml'}"]
    assert main(["scenarios", "campaigns/001_mc"]) == 0
    assert capsys.readouterr().out.strip() == str(SCENARIO_DIR / "campaigns" / "001_mc.toml")


@pytest.mark.parametrize("args,message", [
    (["scenarios", "001_scenario", "--to", "{tmp}/taken.toml"], "error: {tmp}/taken.toml exists; not overwritten"),
    (["scenarios", "001_scenario", "--to", "{tmp}/missing/"], "error: {tmp}/missing/001_scenario.toml: cannot copy"),
    (["scenarios", "no_such", "--to", "{tmp}/new.toml"], "error: no shipped scenario 'no_such'"),
    (["scenarios", "--to", "{tmp}/new.toml"], "error: --to needs the NAME"),
])
def test_cli_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, args, message):
    taken = tmp_path / "taken.toml"
    taken.write_text("# mine\n")
    before = sorted(tmp_path.rglob("*"))
    assert main([a.format(tmp=tmp_path) for a in args]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith(message.format(tmp=tmp_path)), err
    assert sorted(tmp_path.rglob("*")) == before and taken.read_text() == "# mine\n"


# --------------------------------------------------------------------------- build.py / verify.py: this checkout


@pytest.mark.parametrize("script", ["build.py", "verify.py"])
def test_scripts_refuse_an_rpo_that_is_not_this_checkouts(tmp_path, script):
    """Another checkout (here: a copy of the scripts) refuses the rpo installed from this one: one line,
    exit 2, before reading or writing anything."""
    for f in ("build.py", "verify.py"):
        (tmp_path / f).write_bytes((ROOT / f).read_bytes())
    res = subprocess.run([sys.executable, script, "--check"], cwd=tmp_path, capture_output=True, text=True)
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr.splitlines() == [
        f"{script}: rpo.symbolic is imported from {_installed().resolve() / 'symbolic'}, not from this checkout: "
        f"run `pip install -e .` in this checkout ({tmp_path.resolve()}) with this Python ({sys.executable})"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["build.py", "verify.py"]


def test_build_py_refuses_when_rpo_is_not_installed():
    """``python -S``: no site-packages, so no rpo at all."""
    res = subprocess.run([sys.executable, "-S", "build.py", "--check"], cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr.splitlines() == [f"build.py: rpo is not installed: run `pip install -e .` in this checkout "
                                       f"({ROOT}) with this Python ({sys.executable})"]


def _installed() -> Path:
    """The folder the installed rpo's symbolic/, runtime/, generated/ are in (this checkout after
    ``pip install -e .``)."""
    spec = importlib.util.find_spec("rpo.symbolic")
    assert spec is not None and spec.origin
    return Path(spec.origin).parents[1]


def test_build_py_accepts_the_checkout_rpo_is_installed_from():
    import build

    assert build.installed_elsewhere(_installed()) is None
