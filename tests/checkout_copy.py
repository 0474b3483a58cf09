"""A copy of this checkout that ``import rpo`` resolves to, as ``pip install -e .`` in the copy would make it.

build.py and verify.py refuse an rpo that is not their own checkout, so the tests and benchmarks that build
or verify a copy (tests/test_add_controller.py, benchmarks/bench_build.py, benchmarks/bench_verify.py) point
``import rpo`` at the copy: ``rpo/<top>`` links to the copy's folders in a folder beside it (outside the copy,
which git must see unchanged), put first on PYTHONPATH.
"""

from __future__ import annotations

import os
from pathlib import Path

#: The folders installed as ``rpo.<top>`` (setup.py's TOPS).
TOPS = ("symbolic", "runtime", "generated", "scenarios")


def importing(copy: Path, env: dict | None = None) -> dict:
    """``env`` (default: this process's) in which ``import rpo`` is ``copy``."""
    site = copy.parent / f"{copy.name}-site"
    (site / "rpo").mkdir(parents=True, exist_ok=True)
    for d in TOPS:
        if not (site / "rpo" / d).exists():
            (site / "rpo" / d).symlink_to(copy / d, target_is_directory=True)
    if not (site / "rpo" / "__init__.py").exists():  # the package rpo itself: setup.py's API folder
        (site / "rpo" / "__init__.py").symlink_to(copy / "runtime" / "api" / "__init__.py")
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(site), env.get("PYTHONPATH")) if p)
    return env
