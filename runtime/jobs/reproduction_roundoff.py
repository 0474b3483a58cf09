"""Round-off sensitivity of the report's outcomes: each run flown again from perturbed initial states.

A closed loop whose actuators saturate and whose disturbances are random may be chaotic: two
runs that differ in the last bit of one state entry can end tens of degrees apart after 5000 s,
and then "settles" or "does not settle" is a property of the bits, not of the design.  The
report says which of its outcomes are like that.  For every run it flew (status ok or diverged),
:func:`fly_copies` flies ``copies`` more runs from the same scenario, identical in everything
(parameters, gains, random-torque seed, duration, recording step) except the initial state,
each entry of which is multiplied by ``1 + REL * n`` with ``n`` standard normal (a few units in
the last place of a double; entries that are exactly 0 stay 0).  The draws come from
``numpy.random.default_rng(SEED)``, so the copies, and the report, are the same on every
invocation.  The copies are metered by the same code as the run itself
(:func:`rpo.runtime.outputs.metrics.compute_metrics` with the run's thresholds and goal), and a
goal counts as reached in a copy, as in the run, by the rule of the verdict
(:mod:`rpo.runtime.outputs.verdict`): its settling time exists (the error is below the threshold
from its last crossing to the last recorded sample).  Copies that diverge are counted too.

The copies fly in lockstep, K at a time (:meth:`Simulation.run_batch`, K = the model's lane
width), and only their metrics are kept.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: perturbed copies per run (``rpo report`` flies this many unless told otherwise)
COPIES = 16
#: relative size of the perturbation: 1e-15 is 4.5 units in the last place of a double at 1
REL = 1e-15
#: the perturbations' seed (fixed: the report is reproducible)
SEED = 20261203

GOALS = ("att", "pos")


def perturbed(z0: np.ndarray, copies: int, *, seed: int = SEED, rel: float = REL) -> np.ndarray:
    """``copies`` initial states (rows), each entry of ``z0`` times ``1 + rel n``, ``n`` standard normal."""
    rng = np.random.default_rng(seed)
    z0 = np.asarray(z0, float)
    return z0 * (1.0 + rel * rng.standard_normal((copies, z0.size)))


def reached(m: dict[str, Any] | None, q: str) -> bool | None:
    """Whether goal ``q`` (``att``, ``pos``) was reached in a run with metrics ``m``, by the verdict's
    rule (its settling time exists); None when the controller logs no such error or there are no metrics."""
    if not m or m.get(f"{q}_err_final_{'rad' if q == 'att' else 'm'}") is None:
        return None
    return m.get(f"{q}_settling_time_s") is not None


def summarize(flags: list[dict[str, bool | None]], copies: int, *, seed: int = SEED, rel: float = REL) -> dict:
    """The JSON entry of a run's copies from each copy's ``{"att": ..., "pos": ..., "diverged": ...}``."""
    out: dict[str, Any] = {"copies": copies, "rel": rel, "seed": seed,
                           "diverged": sum(1 for f in flags if f["diverged"])}
    for q in GOALS:
        vals = [f[q] for f in flags]
        out[f"{q}_settled"] = None if any(v is None for v in vals) else sum(1 for v in vals if v)
    measured = [q for q in GOALS if out[f"{q}_settled"] is not None]
    out["converged"] = sum(1 for f in flags if measured and all(f[q] for q in measured))
    return out


def fly_copies(outcome: Any, model: Any, copies: int = COPIES, *, seed: int = SEED, rel: float = REL) -> dict:
    """Fly ``copies`` perturbed copies of the run ``outcome`` (a
    :class:`~rpo.runtime.jobs.runner.RunOutcome`) and return :func:`summarize`'s entry."""
    from rpo.runtime.outputs.metrics import compute_metrics, result_columns
    from rpo.runtime.run.preflight import preflight

    pre = preflight(outcome.scenario, model)  # the run's own closed loop and initial state, rebuilt
    if not np.array_equal(pre.z0, outcome.result.z[0]):
        raise RuntimeError("the rebuilt initial state differs from the run's: the copies would not be copies")
    sim, inputs = pre.sim, pre.inputs
    thresholds = outcome.metrics.get("thresholds")
    goal = np.ravel(inputs.gains["r_goal"]) if "r_goal" in inputs.gains else None
    lanes = model.lanes() if getattr(model, "backend", None) == "compiled" else None
    block = lanes.width if lanes is not None else 1
    Z = perturbed(pre.z0, copies, seed=seed, rel=rel)
    flags: list[dict[str, bool | None]] = []
    for b in range(0, copies, block):
        zb = Z[b:b + block]
        n = len(zb)
        results = sim.run_batch(zb, inputs.duration, seeds=[inputs.seed] * n, params=np.tile(sim.p, (n, 1)),
                                gains=np.tile(sim.k, (n, 1)), record_every=inputs.record_every)
        for res in results:
            m = compute_metrics(res.t, result_columns(res), thresholds, goal=goal, params=inputs.params,
                                per_unit=False)
            flags.append({"att": reached(m, "att"), "pos": reached(m, "pos"), "diverged": res.divergence is not None})
    return summarize(flags, copies, seed=seed, rel=rel)


def outcome(metrics: dict | None, entry: dict | None, q: str) -> dict[str, Any]:
    """Goal ``q`` (``att``, ``pos`` or ``both``) of a run and of its copies: ``reached`` (the run;
    None when not measured), ``k`` of ``n`` copies reaching it (None when none were flown) and
    ``depends``: True when the copies do not all agree with the run (the outcome depends on round-off)."""
    if q == "both":
        goals = [g for g in GOALS if reached(metrics, g) is not None]
        run = all(reached(metrics, g) for g in goals) if goals else None
        key = "converged"
    else:
        run, key = reached(metrics, q), f"{q}_settled"
    k = None if not entry or entry.get(key) is None else int(entry[key])
    n = None if k is None else int(entry["copies"])  # type: ignore[index]
    depends = run is not None and k is not None and n is not None and k != (n if run else 0)
    return {"reached": run, "k": k, "n": n, "depends": depends}


def fraction_text(o: dict[str, Any]) -> str:
    """``"k/N"`` of an :func:`outcome`, ``"-"`` when no copies were flown."""
    return "-" if o["k"] is None else f"{o['k']}/{o['n']}"
