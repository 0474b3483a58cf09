"""Which claims have a proof plan, and why the others have none: each controller's ``plans.py``
(``PLANS``, ``UNCERTIFIED``), found by the claim's controller name."""

from __future__ import annotations

import importlib
from collections.abc import Callable

from ..core import Claim, Statement
from .plan import Plan

_PACKAGE = __name__.rsplit(".", 2)[0]        # rpo.symbolic.lyapunov


def implementation_tag(claim: Claim) -> str:
    """The statement that describes rpo's code: ``corrected`` where the claim has one, else ``paper``."""
    return "corrected" if claim.corrected is not None else "paper"


def plan_for(claim: Claim, tag: str | None = None) -> Callable[[Statement], Plan] | None:
    """The plan function registered for one statement of ``claim`` (``tag``: "paper" or "corrected"; default
    the implementation's).  A ``PLANS`` entry is a function, the plan of the implementation's statement, or a
    dict ``{"paper": f, "corrected": g}``.  None: no plan."""
    try:
        mod = importlib.import_module(f"{_PACKAGE}.{claim.controller}.plans")
    except ModuleNotFoundError as exc:
        if exc.name and exc.name.endswith(".plans"):
            return None
        raise
    entry = getattr(mod, "PLANS", {}).get(claim.id)
    tag = tag or implementation_tag(claim)
    if isinstance(entry, dict):
        return entry.get(tag)
    return entry if tag == implementation_tag(claim) else None


def uncertified_reason(claim: Claim) -> str:
    """The written reason why a claim has no certificate (its plans module's ``UNCERTIFIED[claim id]``: what
    was tried and why it does not close), or ''."""
    try:
        mod = importlib.import_module(f"{_PACKAGE}.{claim.controller}.plans")
    except ModuleNotFoundError as exc:
        if exc.name and exc.name.endswith(".plans"):
            return ""
        raise
    return getattr(mod, "UNCERTIFIED", {}).get(claim.id, "")
