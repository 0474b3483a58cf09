"""The package ``rpo`` itself (setup.py maps ``rpo`` to this folder): rpo's Python API.

    import rpo
    result = rpo.run("scenarios/001_scenario.toml", duration=600, overrides={"chaser.mass": 90.0})

The names are those of :mod:`rpo.runtime.jobs.api` (``run``, ``campaign``, ``linearize``, ``read_run``,
``scenario``, ``load_summary``, ``load_model``, ``load_scenario``, the error classes), imported on first
use: every ``import rpo.runtime...`` imports this package first, and a figure worker or a campaign
worker should not pay for the scenario schema and the model loader it does not use.
"""

from __future__ import annotations

from typing import Any

__all__ = ["Model", "ModelError", "OutputError", "RpoError", "RunResult", "Scenario", "ScenarioError", "campaign",
           "linearize", "load_model", "load_scenario", "load_summary", "read_run", "run", "scenario"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from rpo.runtime.jobs import api

        return getattr(api, name)
    raise AttributeError(f"module 'rpo' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
