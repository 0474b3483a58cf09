"""The sections of a campaign's ``report.md`` that qualify a design: the requirements' verdicts
(:mod:`.requirements`) and the Sobol indices of a Saltelli design (:mod:`.sobol`), in the style of
:mod:`.sections` (:func:`.reporting.write_report` joins them)."""

from __future__ import annotations

import numpy as np

from rpo.runtime.campaign import requirements as R
from rpo.runtime.campaign import sobol as SI
from rpo.runtime.campaign.folder import MAIN_METRICS
from rpo.runtime.campaign.sections import ReportContext, _md, _shown, _table
from rpo.runtime.outputs.metrics import UNITS


def requirement_lines(x: ReportContext) -> list[str]:
    """``## Requirements``: each requirement of the campaign judged PASS, FAIL or UNDECIDED over the
    done cases (rpo.runtime.campaign.requirements); nothing for a campaign without requirements."""
    c = x.c
    reqs = R.of_resolved(c.resolved)
    if not reqs:
        return []
    seq = c.resolved.get("sequential") or {}
    looks = int(seq.get("looks", 1))
    verdicts = R.judge(reqs, x.st, c.columns, looks)
    L = ["## Requirements", "",
         f"Over the {x.n_done} done cases: a run meets a requirement when it was flown to the end (status ok) "
         "and its metric is within the bound (in the summary's SI unit); a diverged run, a run in error, an "
         "invalid draw and a null metric fail it. PASS when the one-sided lower Clopper-Pearson bound of the "
         "probability of meeting it reaches the required probability, FAIL when the one-sided upper bound is "
         "below it, else UNDECIDED with the runs still needed if no further run fails."]
    if looks > 1:
        L[-1] += (f" Sequential campaign: {looks} planned looks, each judged at confidence 1 - (1 - confidence) / "
                  f"{looks} (Bonferroni), so the stated confidence holds over all the looks.")
    L.append("")
    rows = []
    for v in verdicts:
        r = v.requirement
        unit = c.unit(r.metric) or UNITS.get(r.metric, "")
        name = f"`{r.name}`" + (f": {_md(r.description)}" if r.description else "")
        more = "0" if v.verdict == "PASS" else ("-" if v.runs_still_needed is None else str(v.runs_still_needed))
        rows.append([name, f"`{r.metric}`", f"{'<=' if r.kind == 'max' else '>='} {r.bound:g} {unit}".rstrip(),
                     f"{v.met}/{v.n}", f"{100 * r.probability:g} % at {100 * v.confidence_used:g} %",
                     f"{100 * v.lower:.4f} %", f"{100 * v.upper:.4f} %", f"**{v.verdict}**", more])
    L += _table(["requirement", "metric", "bound", "met k/n", "required (confidence)", "lower bound",
                 "upper bound", "verdict", "runs still needed"], rows)
    L.append("")
    return L


def _with_ci(v: float, ci: np.ndarray) -> str:
    return f"{v:.3f} [{ci[0]:.3f}, {ci[1]:.3f}]"


def sobol_lines(x: ReportContext) -> list[str]:
    """``## Global sensitivity (Sobol indices)`` of a campaign flown on a Saltelli design
    (``sampling = "sobol-indices"``): first- and total-order indices of the main metrics, the
    requirements' metrics and ``failed`` against each dispersion, with bootstrap intervals."""
    c = x.c
    r = c.resolved
    if r.get("sampling") != "sobol-indices":
        return []
    keys = [str(d.get("key", "?")) for d in r.get("dispersions", []) if isinstance(d, dict)]
    d = len(keys)
    L = ["## Global sensitivity (Sobol indices)", "",
         f"Saltelli design: blocks of {d + 2} runs (A, B and one run per dispersion with that dispersion's "
         "values from B); each dispersion is one group (all of its components together). First order S: the "
         "share of the metric's variance due to that dispersion alone; total order ST: with all its "
         "interactions (ST - S large: it acts through interactions; ST near 0: it does not matter). Estimators "
         f"of Saltelli et al. 2010 (as `scipy.stats.sobol_indices`), {x.conf_pct} percentile-bootstrap intervals "
         f"over the blocks ({x.n_boot} resamples, seed {x.seed}). Each metric over the blocks whose every run was "
         "flown to the end with a value (`failed`, 0/1: every run flown); the other blocks are left out.", ""]
    metrics = [m for m, _, _ in MAIN_METRICS] + [q.metric for q in R.of_resolved(r)] + ["failed"]
    rows = []
    for metric in dict.fromkeys(metrics):
        col = c.columns.get(metric)
        if col is None:
            continue
        v = col.astype(float).copy()
        v[~(x.flown if metric == "failed" else x.ok)] = np.nan
        f_A, f_B, f_AB = SI.split_blocks(c.cases, v, d)
        if f_A.size < 2 or np.var(np.concatenate([f_A, f_B])) == 0.0:
            continue
        res = SI.sobol_indices(f_A, f_B, f_AB, x.confidence, x.n_boot, x.seed)
        name = _shown(c, metric)[0]
        for i in np.argsort(-res.total, kind="stable"):
            rows.append([name, f"`{keys[i]}`", _with_ci(res.first[i], res.first_ci[i]),
                         _with_ci(res.total[i], res.total_ci[i]), str(res.blocks)])
    if rows:
        L += _table(["metric", "dispersion", f"S [{x.conf_pct}]", f"ST [{x.conf_pct}]", "blocks"], rows)
    else:
        L.append("No metric varies over two or more complete blocks.")
    L.append("")
    return L
