"""Lyapunov claims of each controller design and the checker that verifies them.

The claims of controller ``<c>`` live in ``symbolic/lyapunov/<c>/`` (a package whose ``__init__`` exposes
``CLAIMS``, ``MUTATIONS``, ``UNITS`` (the SI unit of each domain symbol, :mod:`.units`) and optionally
``TITLE``; a single module ``<c>.py`` works too).  They are
*discovered*: every module or package here whose name is a controller module of
``symbolic/controllers/`` is a claims module, so adding one needs no registration, and a controller
without claims (``baseline``, or a new copy of a design) is simply not checked.

``claims()`` gathers every :class:`~rpo.symbolic.lyapunov.core.Claim`; ``mutations()`` the injected
defects that must make the affected claims fail.  ``python verify.py`` writes ``docs/verification.md``
and ``docs/verification.json``.
"""

from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path
from types import ModuleType

from .core import Claim, Mutation

_HERE = Path(__file__).resolve().parent
_CONTROLLERS_DIR = _HERE.parent / "controllers"


def controllers() -> tuple[str, ...]:
    """Controllers with a claims module, sorted: the names shared by ``symbolic/controllers/`` and this
    package (found on disk at each call, so a new claims package is seen without editing a list)."""
    designs = {m.name for m in pkgutil.iter_modules([str(_CONTROLLERS_DIR)]) if not m.name.startswith("_")}
    here = {m.name for m in pkgutil.iter_modules([str(_HERE)]) if not m.name.startswith("_")}
    return tuple(sorted(designs & here))


def module(controller: str) -> ModuleType:
    """The claims module (package) of one controller; ValueError naming the known ones otherwise."""
    if controller not in controllers():
        raise ValueError(f"no claims module for controller {controller!r} (claims exist for "
                         f"{', '.join(controllers()) or 'none'})")
    return importlib.import_module(f"{__name__}.{controller}")


def _modules(only: str | None = None) -> list[ModuleType]:
    return [module(name) for name in (controllers() if only is None else (only,))]


def title(controller: str) -> str:
    """The heading of a controller's section in the report (its package's ``TITLE``, else its name)."""
    return getattr(module(controller), "TITLE", controller) if controller in controllers() else controller


def claims(controller: str | None = None) -> list[Claim]:
    return [c for m in _modules(controller) for c in m.CLAIMS]


def mutations(controller: str | None = None) -> list[Mutation]:
    return [x for m in _modules(controller) for x in getattr(m, "MUTATIONS", [])]
