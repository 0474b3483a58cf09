"""The package list of rpo, discovered from the folders (everything else is in pyproject.toml).

The import names are ``rpo.<top>.<sub>...`` but the folders are the top-level ``symbolic/``,
``runtime/``, ``generated/`` and ``scenarios/`` of the repository (no ``rpo/`` folder: that is the
layout the users asked for).  pyproject.toml alone cannot discover that: ``[tool.setuptools.packages.find]``
names what it finds after the folders (``symbolic.controllers``, never ``rpo.symbolic.controllers``) and
has no prefix option, so pyproject would need a ``packages`` list naming every subpackage by hand.
Here every folder under one of the four tops becomes ``rpo.<top>.<sub>`` and ``package_dir`` maps the
four tops; a new ``symbolic/<name>/`` or ``runtime/<name>/`` is installed by ``pip install`` with no edit.

The folders are found with :func:`setuptools.find_namespace_packages` (every folder, ``__pycache__``
excepted), not ``find_packages`` (only folders with an ``__init__.py``): ``runtime/csrc/`` (C sources)
and ``scenarios/campaigns/`` hold only data, and setuptools deprecates installing a folder of package
data that is not in ``packages``.  An editable install (``pip install -e .``) maps only the four tops to
the checkout, so there a package added later is importable even without reinstalling.
"""

from pathlib import Path

from setuptools import find_namespace_packages, setup

#: The folders installed as ``rpo.<top>``; ``scenarios`` holds no code, only the shipped scenario
#: files (package data, read through importlib.resources: ``rpo.runtime.scenario.shipped``).
TOPS = ("symbolic", "runtime", "generated", "scenarios")

#: The folder installed as the package ``rpo`` itself (``import rpo; rpo.run(...)``): the Python API,
#: which lives with the runtime it calls; it is not also ``rpo.runtime.api``.
API = "runtime/api"


def packages(root: Path = Path(".")) -> list[str]:
    """Every package of rpo in the checkout ``root``: the tops and each folder under them."""
    found = ["rpo"]
    api = Path(API).relative_to("runtime").as_posix().replace("/", ".")
    for top in TOPS:
        found.append(f"rpo.{top}")
        skip = [api, f"{api}.*"] if top == "runtime" else []
        subs = find_namespace_packages(str(root / top), exclude=["__pycache__", "*.__pycache__", *skip])
        found.extend(f"rpo.{top}.{sub}" for sub in sorted(subs))
    return found


def package_dir() -> dict[str, str]:
    """Where each top is (relative to the checkout, as setuptools requires)."""
    return {"rpo": API, **{f"rpo.{top}": top for top in TOPS}}


if __name__ == "__main__":  # run by pip's build backend; tests import packages() to check the discovery
    setup(packages=packages(), package_dir=package_dir())
