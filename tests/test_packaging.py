"""Packaging: discovered packages, package data, the shipped scenarios, and build.py's checkout check.

The wheel itself is built, installed into a fresh venv and used from outside the checkout by
``.ci/smoke_wheel`` (a step of ``.ci/run``); these tests check the parts that need no install.
"""

from __future__ import annotations

import glob
import tomllib
from pathlib import Path

import structure

import setup
from rpo.runtime.scenario import read_scenario

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
SHIPPED_FILES = sorted((ROOT / "scenarios").rglob("*.toml"))


# --------------------------------------------------------------------------- discovery (setup.py)


def _folders(root: Path) -> set[str]:
    """Every folder under the four tops as a dotted rpo package (``__pycache__`` aside)."""
    out = set()
    for top in setup.TOPS:
        out.add(f"rpo.{top}")
        for d in (root / top).rglob("*"):
            rel = d.relative_to(root)
            if d.is_dir() and "__pycache__" not in rel.parts:
                out.add("rpo." + ".".join(rel.parts))
    return out


def test_every_folder_is_a_discovered_package():
    pkgs = setup.packages(ROOT)
    assert len(pkgs) == len(set(pkgs))
    assert set(pkgs) == _folders(ROOT)
    assert {"rpo.symbolic.controllers", "rpo.symbolic.lyapunov.certify", "rpo.runtime.model", "rpo.runtime.csrc",
            "rpo.generated", "rpo.scenarios", "rpo.scenarios.campaigns"} <= set(pkgs)
    assert setup.package_dir() == {"rpo.symbolic": "symbolic", "rpo.runtime": "runtime",
                                   "rpo.generated": "generated", "rpo.scenarios": "scenarios"}


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
        "rpo.symbolic", "rpo.symbolic.codegen", "rpo.symbolic.codegen.emit", "rpo.symbolic.physics",
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
              *(ROOT / "runtime" / "csrc").iterdir(), *SHIPPED_FILES}
    assert needed - data == set()
    assert len(SHIPPED_FILES) >= 17 and any(f.parent.name == "campaigns" for f in SHIPPED_FILES)


def test_what_the_scenarios_extend_is_shipped_too():
    for f in SHIPPED_FILES:
        assert set(read_scenario(f).bases) <= {p.resolve() for p in SHIPPED_FILES}, f
