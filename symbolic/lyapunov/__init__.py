"""Lyapunov claims of each controller design and the checker that verifies them.

``claims()`` gathers every :class:`~rpo.symbolic.lyapunov.core.Claim` (one module per controller:
``c000``, ``c001``, ``c002``, ``c004``); ``mutations()`` the injected defects that must make the affected
claims fail.  ``python verify.py`` writes ``docs/verification.md`` and ``docs/verification.json``.
"""

from __future__ import annotations

import importlib

from .core import Claim, Mutation

CONTROLLERS = ("c000", "c001", "c002", "c004")


def _modules():
    out = []
    for name in CONTROLLERS:
        try:
            out.append(importlib.import_module(f"{__name__}.{name}"))
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
    return out


def claims(controller: str | None = None) -> list[Claim]:
    return [c for m in _modules() for c in m.CLAIMS if controller in (None, c.controller)]


def mutations(controller: str | None = None) -> list[Mutation]:
    return [x for m in _modules() for x in m.MUTATIONS
            if controller in (None, m.__name__.rsplit(".", 1)[1])]
