"""The build-system tests' fixture model (``tests/fixtures/tiny_model/``) as code-generation families.

:func:`copy_model` copies the fixture package into a test's folder so that a test may edit it;
:func:`families` imports that copy afresh (under a new package name, so an edited module is
really re-imported) and describes it as the families rpo's build engine generates:
``plant`` (``tiny_rhs``, ``tiny_out``) and ``ctrl_a``/``ctrl_b`` (``law_*``, ``step_*``), which
depend on the plant and compose its right-hand side into their step.
"""

from __future__ import annotations

import importlib
import importlib.util
import itertools
import shutil
import sys
from pathlib import Path

from rpo.symbolic.codegen.codegen import Family, FamilyOutput, Generated

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "tiny_model"
_counter = itertools.count()


def copy_model(dst: Path) -> Path:
    shutil.copytree(FIXTURE, dst, ignore=shutil.ignore_patterns("__pycache__"))
    return dst


def _import(root: Path) -> str:
    name = f"_tiny_model_{next(_counter)}"
    spec = importlib.util.spec_from_file_location(name, root / "__init__.py", submodule_search_locations=[str(root)])
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return name


def families(root: Path, controllers: tuple[str, ...] = ("a", "b")) -> list[Family]:
    pkg = _import(root)

    def out(items) -> FamilyOutput:
        return FamilyOutput([Generated(*it) for it in items], {"x": [{"name": "x", "size": 3, "unit": "m"}]})

    def plant(_resolve) -> FamilyOutput:
        return out(importlib.import_module(f"{pkg}.plant").functions())

    def ctrl(name: str) -> Family:
        def build(resolve) -> FamilyOutput:
            o = out(importlib.import_module(f"{pkg}.ctrl_{name}").functions(resolve))
            o.extra = {"controllers": {name: {"step": f"step_{name}", "law": f"law_{name}"}}}
            return o

        return Family(f"ctrl_{name}", (root / f"ctrl_{name}.py",), build, ("plant",))

    return [Family("plant", (root / "plant.py",), plant), *(ctrl(c) for c in controllers)]
