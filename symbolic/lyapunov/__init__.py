"""Lyapunov claims of each controller design and the checker that verifies them.

``claims()`` gathers every :class:`~rpo.symbolic.lyapunov.core.Claim` (one module per controller:
``c000``, ``c001``, ``c002``, ``c004``); ``mutations()`` the injected defects that must make the affected
claims fail.  ``python verify.py`` writes ``docs/verification.md`` and ``docs/verification.json``.
"""

from __future__ import annotations

import importlib

from .core import Claim, Mutation

CONTROLLERS = ("c000", "c001", "c002", "c004")


def _modules(only: str | None = None):
    return [importlib.import_module(f"{__name__}.{name}") for name in (CONTROLLERS if only is None else (only,))]


def claims(controller: str | None = None) -> list[Claim]:
    return [c for m in _modules(controller) for c in m.CLAIMS]


def mutations(controller: str | None = None) -> list[Mutation]:
    return [x for m in _modules(controller) for x in m.MUTATIONS]
