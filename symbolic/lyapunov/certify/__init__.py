"""Certified inequalities: the claims a symbolic proof cannot settle, proved on their stated domain.

The symbolic stage (:mod:`..check`) proves identities and simple sign facts; an inequality such as
V-dot <= -eps |S| under a disturbance bound is beyond it, and the numeric search that finds no
counterexample is not a proof.  This package proves such statements with rigorous interval arithmetic:

* :mod:`.plan`: a claim's *plan* states the certified domain physically (a box of coordinates with units,
  the statement's symbols as expressions of them, hypotheses that cut the box) and optional symbolic
  reductions (an identity rewriting, a positive factor cleared);
* :mod:`.intervals` and :mod:`.bnb`: the prover, vectorised interval enclosures (NumPy float64 with outward
  rounding) in a branch and bound whose leaves close by the natural, mean-value, monotone-face or
  second-order (Hessian) argument;
* :mod:`.certificate`: the certificate (the tree of boxes and the method of each leaf), committed in
  ``docs/certificates/``, keyed by the hash of the statement's sources;
* :mod:`.recheck`: the independent checker, which regenerates every box from the tree and re-evaluates
  each leaf's argument in ``mpmath.iv`` at 80 bits, sharing no arithmetic with the prover.

A plan is registered in ``symbolic/lyapunov/<controller>/plans.py`` as ``PLANS[claim id] = f`` where
``f(statement) -> Plan``; :func:`plan_for` finds it.  The result of :func:`certify` is recorded in the
report; only a certificate that passed the independent re-check makes a claim "proved (certified)".
"""

from __future__ import annotations

from pathlib import Path

from ..core import Claim, Statement
from .certificate import Certification, derive, recheck
from .plan import Coordinate, Plan, Region
from .registry import implementation_tag, plan_for, uncertified_reason
from .store import STORE, read, write

__all__ = ["Coordinate", "Plan", "Region", "Certification", "certify", "implementation_tag", "plan_for", "STORE",
           "uncertified_reason"]

MODES = ("derive", "reuse", "check", "off")


def certify(claim: Claim, tag: str, st: Statement, mode: str = "reuse", store: Path = STORE,
            log=print) -> Certification | None:
    """Certify one statement of ``claim`` (``tag``: "paper" or "corrected").

    * ``derive``: search from scratch and write the certificate;
    * ``reuse``: re-check the stored certificate; derive and write it where it is missing or stale;
    * ``check``: re-check the stored certificate; re-derive (without writing) where it is stale or missing.

    None when the claim has no plan.
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}")
    make = plan_for(claim, tag)
    if make is None or mode == "off":
        return None
    plan = make(st)
    if mode != "derive":
        data = read(claim.id, tag, store)
        if data is not None:
            got = recheck(claim, tag, st, plan, data)
            if got.status != "stale":
                return got
            log(f"  certificate of {claim.id} is stale ({got.reason}): re-deriving")
        elif mode == "check":
            log(f"  certificate of {claim.id} is missing: deriving")
    got, data = derive(claim, tag, st, plan, log=log)
    if data is not None:
        if mode == "check":
            got.note = (got.note + " " if got.note else "") + "(derived during --check: not committed)"
            checked = recheck(claim, tag, st, plan, data)
            got.recheck, got.recheck_seconds = checked.recheck, checked.recheck_seconds
        else:
            write(data, store)
            checked = recheck(claim, tag, st, plan, data)
            got.recheck, got.recheck_seconds = checked.recheck, checked.recheck_seconds
    return got
