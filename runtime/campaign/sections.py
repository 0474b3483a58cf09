"""The sections of a campaign's ``report.md``, one function each, in the order the report prints them
(:func:`.reporting.write_report` joins them), and the report's figures (drawn by :mod:`.figures`)."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rpo.runtime.campaign import stats as S
from rpo.runtime.campaign.folder import (
    ENVELOPE_CHANNELS,
    FLOWN,
    MAIN_METRICS,
    PERCENTILES,
    SCATTER_METRICS,
    STATUSES,
    CampaignFolder,
)
from rpo.runtime.campaign.sequential import stopped_at
from rpo.runtime.campaign.storage import read_histories, read_rows
from rpo.runtime.outputs.jsonunits import shown
from rpo.runtime.outputs.verdict import CONSTRAINT_RULE, declared_constraints

# --------------------------------------------------------------------------- formatting


def _f(v: float | None, never: str = "n/a") -> str:
    """A number with 4 significant digits; NaN/None as ``n/a``, +inf as ``never``-like text."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "n/a"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return f"{v:.4g}"


def _pct(v: float) -> str:
    return "n/a" if math.isnan(v) else f"{100.0 * v:.2f} %"


def _ranges(values: Iterable[int]) -> str:
    """``0, 3-5, 9`` for [0, 3, 4, 5, 9]."""
    vals = sorted(values)
    parts: list[str] = []
    i = 0
    while i < len(vals):
        j = i
        while j + 1 < len(vals) and vals[j + 1] == vals[j] + 1:
            j += 1
        parts.append(str(vals[i]) if i == j else f"{vals[i]}-{vals[j]}")
        i = j + 1
    return ", ".join(parts)


def _table(header: Sequence[str], rows: Iterable[Sequence[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(" --- " for _ in header) + "|"]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return out


def _md(text: str) -> str:
    """A message in a table cell: one line, no pipe."""
    return " ".join(text.split()).replace("|", "\\|")


def refly_command(campaign_dir: str | Path, case: int) -> str:
    """The command that flies ``case`` of the campaign again (with its history and figures)."""
    return f"rpo run --campaign {campaign_dir} --case {int(case)}"


# --------------------------------------------------------------------------- the sections


def _flag_count(c: CampaignFolder, column: str, rows: np.ndarray, value: float = 1.0) -> tuple[int, int] | None:
    """(cases where ``column`` == value, cases where it is not null) among ``rows``; None if absent."""
    a = c.columns.get(column)
    if a is None or c.kinds.get(column) not in ("bool", "float", "int"):
        return None
    v = a[rows].astype(float)
    have = ~np.isnan(v)
    if not np.any(have):
        return None
    return int(np.sum(v[have] == value)), int(np.sum(have))


def _not_settled(c: CampaignFolder, settling: str, reached: str, flown: np.ndarray) -> tuple[int, int] | None:
    """(flown runs whose settling time is null, flown runs where the error is measured): measured =
    ``reached`` not null when the runner has that column (null = the controller logs no such error)."""
    s = c.columns.get(settling)
    if s is None:
        return None
    measured = flown.copy()
    r = c.columns.get(reached)
    if r is not None:
        measured &= ~np.isnan(r.astype(float))
    if not np.any(measured):
        return None
    return int(np.sum(np.isnan(s[measured]))), int(np.sum(measured))


def _wilks_values(c: CampaignFolder, metric: str, side: str, flown: np.ndarray) -> np.ndarray:
    """The values a tolerance bound of ``metric`` is taken over: flown runs; diverged ones beyond
    any bound; for a settling time a null is "never" (+inf); other nulls are dropped."""
    v = c.columns[metric][flown].astype(float).copy()
    st = c.status[flown]
    if metric.endswith("settling_time_s"):
        v[np.isnan(v)] = math.inf
    v[st == "diverged"] = math.inf if side == "upper" else -math.inf
    return v


def _shown(c: CampaignFolder, column: str) -> tuple[str, str, float]:
    """(name, unit, factor from the summary's SI value) of a column as the report shows it: angles in
    deg, angular rates in deg/s, wheel speeds in rpm (rpo.runtime.outputs.jsonunits.shown), the rest as
    the summary has it."""
    return shown(column, c.unit(column))


def _label(c: CampaignFolder, column: str) -> str:
    name, u, _ = _shown(c, column)
    return f"{name} [{u}]" if u else name


def _draw_label(c: CampaignFolder, column: str) -> str:
    name, u, _ = _shown(c, column)
    name = name[len("draw."):] if name.startswith("draw.") else name
    return f"{name} [{u}]" if u else name


#: how the report's units are chosen, in words (the header says it)
UNITS_TEXT = ("Units: SI as in `summary.parquet`, except angles in deg, angular rates in deg/s and wheel speeds "
              "in rpm (a column's unit suffix says which: `att_err_final_rad` is shown as `att_err_final_deg`).")


@dataclass
class _Histories:
    t: list[np.ndarray]
    channels: dict[str, list[np.ndarray]]
    cases: list[int]
    missing: list[int]


def _read_histories(c: CampaignFolder, flown: np.ndarray) -> _Histories:
    wanted = [ch for ch, _, _ in ENVELOPE_CHANNELS]
    h = _Histories([], {ch: [] for ch in wanted}, [], [])
    for case, cols in read_histories(c.path, c.cases[flown], read_rows(c.path), ["t", *wanted]):
        if cols is None or "t" not in cols:
            h.missing.append(case)
            continue
        t = cols["t"]
        h.t.append(t)
        h.cases.append(case)
        for ch in wanted:
            h.channels[ch].append(cols[ch] if ch in cols else np.full(t.size, np.nan))
    return h


def _write_figures(c: CampaignFolder, fig_dir: Path, ok: np.ndarray, flown: np.ndarray, hist: _Histories,
                   correlations: Mapping[tuple[str, str], S.RankCorrelation], fmt: str) -> list[tuple[str, str]]:
    """Draw the figures; returns [(file name, caption), ...] of those written."""
    from rpo.runtime.campaign import figures as F

    fig_dir.mkdir(parents=True, exist_ok=True)
    written: list[tuple[str, str]] = []

    panels = [F.EnvelopePanel(label, S.envelope(hist.t, hist.channels[ch], PERCENTILES), scale)
              for ch, label, scale in ENVELOPE_CHANNELS if any(np.any(~np.isnan(v)) for v in hist.channels[ch])]
    name = f"envelopes.{fmt}"
    if F.envelope_figure(panels, fig_dir / name, f"{c.name}: 5-95 % envelopes over {len(hist.t)} flown runs"):
        written.append((name, "percentile envelopes over time (5-95 % shaded, median line)"))

    flown_st = c.status[flown]
    settle = []
    for col, what in (("att_settling_time_s", "attitude"), ("pos_settling_time_s", "position")):
        if col in c.columns and np.any(np.isfinite(c.columns[col][flown])):
            v = c.columns[col][flown].astype(float).copy()
            v[np.isnan(v) | (flown_st == "diverged")] = math.inf  # never settled, or diverged
            settle.append((what, v))
    cdf_panels: list[tuple[str, Sequence[tuple[str, np.ndarray]]]] = []
    if settle:
        cdf_panels.append(("settling time [s] (flown runs; never settled or diverged = inf)", settle))
    if "propellant_kg" in c.columns:
        cdf_panels.append((f"{_label(c, 'propellant_kg')} (runs flown to the end)",
                           [("propellant", c.columns["propellant_kg"][ok])]))
    name = f"cdf.{fmt}"
    if F.cdf_figure(cdf_panels, fig_dir / name, f"{c.name}: distributions"):
        written.append((name, "empirical CDFs of the settling times and the propellant"))

    for metric in SCATTER_METRICS:
        if metric not in c.columns:
            continue
        draws = []
        for d in c.numeric_draws:
            r = correlations.get((metric, d))
            draws.append((r.rho if r else math.nan, d))
        # the draws that matter most first; undefined rho last; then by name (deterministic)
        draws.sort(key=lambda rd: (math.isnan(rd[0]), -abs(rd[0]) if not math.isnan(rd[0]) else 0.0, rd[1]))
        panels_s = [(_draw_label(c, d), c.columns[d][flown].astype(float) * _shown(c, d)[2], rho) for rho, d in draws]
        name = f"scatter_{metric}.{fmt}"
        shown_name, _, k = _shown(c, metric)
        if F.scatter_figure(_label(c, metric), c.columns[metric][flown] * k, panels_s, flown_st, fig_dir / name,
                            f"{c.name}: {shown_name} against the dispersed values (Spearman rho over ok runs)"):
            written.append((name, f"{shown_name} against each dispersed value"))
    # a figure of an earlier write that this one did not draw (its data are gone) would contradict
    # the report: remove it; only our own file names are touched
    ours = {n for n, _ in written}
    for f in sorted(fig_dir.glob(f"*.{fmt}")):
        if f.name not in ours and (f.name in (f"envelopes.{fmt}", f"cdf.{fmt}") or f.name.startswith("scatter_")):
            f.unlink()
    return written


@dataclass(frozen=True)
class ReportContext:
    """What every section of the report reads: the folder, the masks and counts, the statistics' settings."""

    c: CampaignFolder
    cdir: Path
    coverage: float
    confidence: float
    n_boot: int
    seed: int
    top: int
    worst: int

    @property
    def conf_pct(self) -> str:
        return f"{100 * self.confidence:g} %"

    @property
    def cov_pct(self) -> str:
        return f"{100 * self.coverage:g} %"

    @property
    def st(self) -> np.ndarray:
        return self.c.status

    @property
    def ok(self) -> np.ndarray:
        return self.c.mask(["ok"])

    @property
    def flown(self) -> np.ndarray:
        return self.c.mask(FLOWN)

    @property
    def counts(self) -> dict[str, int]:
        return {s: int(np.sum(self.st == s)) for s in STATUSES}

    @property
    def other(self) -> list[str]:
        return sorted(set(self.st.tolist()) - set(STATUSES))

    @property
    def n_done(self) -> int:
        return len(self.st)

    @property
    def n_flown(self) -> int:
        return int(self.flown.sum())

    @property
    def n_ok(self) -> int:
        return int(self.ok.sum())

    @property
    def msg(self) -> np.ndarray | None:
        return self.c.columns.get("message")


def header_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    c, cdir, counts = x.c, x.cdir, x.counts
    n_done, n_flown = x.n_done, x.n_flown
    conf_pct, cov_pct = x.conf_pct, x.cov_pct
    n_boot, seed = x.n_boot, x.seed
    r = c.resolved
    L.append(f"- folder: `{cdir}`")
    for key, label in (("scenario_file", "scenario"), ("controller", "controller"), ("campaign_file", "campaign file")):
        if r.get(key):
            L.append(f"- {label}: `{r[key]}`")
    if r.get("duration_s") is not None:
        L.append(f"- duration: {_f(float(r['duration_s']))} s")
    if r.get("command"):
        L.append(f"- command: `{r['command']}`")
    dispersed = [d.get("key", "?") for d in r.get("dispersions", []) if isinstance(d, dict)]
    if dispersed:
        L.append(f"- dispersed: {', '.join(f'`{k}`' for k in dispersed)}")
    L.append(f"- runs requested: {c.requested}; done: {n_done}; flown: {n_flown} "
             f"(ok {counts['ok']}, diverged {counts['diverged']}); invalid draws: {counts['invalid']}; "
             f"errors: {counts['error']}")
    L.append(f"- statistics: intervals at {conf_pct} confidence; tolerance bounds for {cov_pct} coverage at "
             f"{conf_pct} confidence; percentile intervals by bootstrap ({n_boot} resamples, seed {seed})")
    L.append(f"- {UNITS_TEXT}")
    missing = sorted(set(range(c.requested)) - {int(x) for x in c.cases})
    stop = stopped_at(r, c.cases, x.st, c.columns)
    if stop:
        L += ["", f"**Sequential campaign: stopped after {stop[0]} of at most {c.requested} runs (look {stop[1]} of "
                  f"{stop[2]}): every requirement is decided.** Everything below covers those {stop[0]} runs, the "
                  f"rows a campaign of {stop[0]} runs gives."]
    elif missing:
        L += ["", f"**Incomplete campaign: {len(missing)} of the {c.requested} requested cases have no result "
                  f"(cases {_ranges(missing)}); everything below covers the {n_done} done.**"]
    L.append("")
    return L


def status_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    st, counts, other, n_done = x.st, x.counts, x.other, x.n_done
    msg = x.msg
    L += ["## Status", ""]
    rows = [[s, str(counts[s]), _pct(counts[s] / n_done if n_done else math.nan)] for s in STATUSES]
    rows += [[s, str(int(np.sum(st == s))), _pct(float(np.sum(st == s)) / n_done)] for s in other]
    L += _table(["status", "cases", "of done"], rows)
    L.append("")
    if msg is not None:
        for s in ("invalid", "error", "diverged"):
            sel = (st == s) & (msg != "")
            if not np.any(sel):
                continue
            uniq, n_msg = np.unique(msg[sel], return_counts=True)
            order = sorted(range(len(uniq)), key=lambda i: (-int(n_msg[i]), str(uniq[i])))
            L += [f"Messages of the {s} cases:", ""]
            L += _table(["cases", "message"], [[str(int(n_msg[i])), _md(str(uniq[i]))] for i in order[:10]])
            if len(order) > 10:
                L.append(f"\n({len(order) - 10} more distinct messages)")
            L.append("")
    return L


def failure_rate_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    c, counts, flown = x.c, x.counts, x.flown
    n_done, n_flown, confidence, conf_pct = x.n_done, x.n_flown, x.confidence, x.conf_pct
    L += ["## Failure rates", "",
          f"Over the {n_flown} flown runs (ok + diverged); invalid draws and worker errors over the {n_done} "
          f"done cases. Exact Clopper-Pearson intervals: the two-sided {conf_pct} interval, and the one-sided "
          f"upper bound (the rate is at most this with {conf_pct} confidence).", "", *_constraint_rule(c), ""]
    events: list[tuple[str, tuple[int, int] | None]] = [
        ("failed", _flag_count(c, "failed", flown)),
        ("attitude not settled", _not_settled(c, "att_settling_time_s", "att_reached", flown)),
        ("position not settled", _not_settled(c, "pos_settling_time_s", "pos_reached", flown)),
        ("attitude goal not reached", _flag_count(c, "att_reached", flown, 0.0)),
        ("position goal not reached", _flag_count(c, "pos_reached", flown, 0.0)),
        ("diverged", (counts["diverged"], n_flown) if n_flown else None),
        ("constraint violated", _flag_count(c, "constraint_violated", flown)),
        ("invalid draw (of done cases)", (counts["invalid"], n_done) if n_done else None),
        ("worker error (of done cases)", (counts["error"], n_done) if n_done else None),
    ]
    rows = []
    for label, kn in events:
        if kn is None:
            continue
        k, n = kn
        p, lo, hi = S.clopper_pearson(k, n, confidence)
        _, _, up = S.clopper_pearson(k, n, confidence, sided="upper")
        rows.append([label, str(k), str(n), _pct(p), f"[{_pct(lo)}, {_pct(hi)}]", _pct(up)])
    if rows:
        L += _table(["event", "runs", "of", "rate", f"{conf_pct} interval", f"upper {conf_pct} bound"], rows)
    else:
        L.append("No case done.")
    L.append("")
    return L


def _constraint_rule(c: CampaignFolder) -> list[str]:
    """What "constraint violated" and "failed" count, in words: the verdict's rule, and which
    constraints this campaign's scenario declares (from ``resolved.json``)."""
    scenario = c.resolved.get("scenario")
    if isinstance(scenario, dict):
        names = declared_constraints(scenario)
        declared = (f"this campaign's scenario declares {', '.join(f'`{n}`' for n in names)}" if names else
                    "this campaign's scenario declares none, so a violated constraint is counted but fails no run")
    else:
        declared = "which constraints the scenario declares is not recorded in this folder"
    return [f"`constraint violated` counts the runs whose verdict names a violated constraint (the rule of "
            f"`rpo run`'s verdict, docs/verdict.md): {CONSTRAINT_RULE}. `failed` counts the runs that diverged, "
            f"missed a measured goal, or violated a constraint their scenario declares in `[constraints]`: "
            f"{declared}."]


def wilks_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    c, flown, n_flown = x.c, x.flown, x.n_flown
    coverage, confidence, conf_pct, cov_pct = x.coverage, x.confidence, x.conf_pct, x.cov_pct
    n1 = S.wilks_runs(coverage, confidence)
    n2 = S.wilks_runs(coverage, confidence, two_sided=True)
    n1b = S.wilks_runs(coverage, confidence, order=2)
    L += ["## Tolerance bounds (Wilks)", "",
          f"A one-sided distribution-free bound on the {cov_pct} quantile at {conf_pct} confidence needs "
          f"{n1} flown runs (the largest run; {n1b} for the second largest); a two-sided interval needs {n2}. "
          f"This campaign has {n_flown} flown runs: "
          + ("enough." if n_flown >= n1 else f"**not enough** ({n1 - n_flown} more needed)."), "",
          "Each bound is the order statistic of the highest order the sample admits (the tightest valid "
          "one). Diverged runs count as beyond the bound, and a run that never settled as an infinite "
          "settling time, so an `inf` bound means too many such runs for this coverage.", ""]
    rows = []
    for metric, side, _ in MAIN_METRICS:
        if metric not in c.columns or not np.any(np.isfinite(c.columns[metric][flown])):
            continue
        b = S.wilks_bound(_wilks_values(c, metric, side, flown), coverage, confidence, order=None,
                          side="lower" if side == "lower" else "upper")
        name, unit, k = _shown(c, metric)
        value = _f(b.value * k) if b.ok else f"needs {b.n_needed} runs"
        order_txt = f"{b.order} ({'largest' if side == 'upper' else 'smallest'})" if b.ok else "-"
        rows.append([name, unit, "upper" if side == "upper" else "lower", str(b.n), order_txt, value,
                     f"{100 * b.achieved:.2f} %"])
    if rows:
        L += _table(["metric", "unit", "bound", "n", "order", f"{cov_pct} / {conf_pct} bound",
                     "confidence achieved"], rows)
    else:
        L.append("No main metric has a value.")
    L.append("")
    return L


def metric_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    c, ok, n_ok = x.c, x.ok, x.n_ok
    confidence, conf_pct, n_boot, seed = x.confidence, x.conf_pct, x.n_boot, x.seed
    L += ["## Metrics", "",
          f"Over the {n_ok} runs flown to the end (status ok); n counts the runs with a value (for a "
          f"settling time: those that settled). Mean with its Student-t {conf_pct} interval, percentiles "
          f"with their bootstrap {conf_pct} interval.", ""]
    rows = []
    for metric in c.metrics:
        v = c.columns[metric][ok]
        v = v[~np.isnan(v)]
        if v.size == 0:
            continue
        name, unit, k = _shown(c, metric)
        if k != 1.0:
            v = v * k
        mean = S.mean_ci(v, confidence)
        pcs = S.bootstrap_percentiles(v, PERCENTILES, confidence, n_boot, seed)
        cells = [f"{_f(e)} [{_f(lo)}, {_f(hi)}]" for e, lo, hi in (mean, *pcs)]
        rows.append([name, unit, str(v.size), *cells, _f(float(v.min())), _f(float(v.max()))])
    if rows:
        L += _table(["metric", "unit", "n", "mean", "p5", "p50", "p95", "min", "max"], rows)
    else:
        L.append("No run flown to the end has a metric value.")
    L.append("")
    return L


def sensitivity_lines(x: ReportContext) -> tuple[list[str], dict]:
    """The section and the (metric, draw) -> correlation pairs the scatter figures use."""
    L: list[str] = []
    c, ok, flown, confidence, top = x.c, x.ok, x.flown, x.confidence, x.top
    num_draws = c.numeric_draws
    ok_cols = {k: v[ok] for k, v in c.columns.items()}
    flown_cols = {k: v[flown] for k, v in c.columns.items()}
    corr = S.rank_correlations(ok_cols, num_draws, c.metrics)
    corr += S.rank_correlations(flown_cols, num_draws, ["failed"] if "failed" in c.columns else [])
    by_pair = {(x.metric, x.draw): x for x in corr if x.metric != "failed"}
    L += ["## Which dispersion matters", ""]
    skipped = [d for d in c.draws if d not in num_draws]
    if corr:
        ranked = sorted(corr, key=lambda x: (-abs(x.rho), x.metric, x.draw))
        alpha_fw = (1.0 - confidence) / len(corr)
        L += [f"Spearman's rank correlation of each metric (over ok runs) and of `failed` (0/1, over flown "
              f"runs) with each numeric dispersed value; the {min(top, len(ranked))} largest |rho| of "
              f"{len(corr)} pairs. With that many pairs some small p-values occur by chance: `*` marks "
              f"p < {_f(alpha_fw)} (Bonferroni, family-wise {100 * (1 - confidence):g} %).", ""]
        rows = [[_shown(c, x.metric)[0], x.draw[len("draw."):], f"{x.rho:+.3f}",
                 f"{x.p:.3g}" + (" *" if x.p < alpha_fw else ""), str(x.n)] for x in ranked[:top]]
        L += _table(["metric", "dispersed value", "rho", "p", "n"], rows)
    else:
        L.append("No pair of a varying metric and a varying numeric dispersed value.")
    if skipped:
        L += ["", f"Not correlated (non-numeric draws: a choice among strings has no order): "
                  f"{', '.join(f'`{d}`' for d in skipped)}."]
    L.append("")
    return L, by_pair


def worst_case_lines(x: ReportContext) -> list[str]:
    L: list[str] = []
    c, cdir, st, ok, msg, worst = x.c, x.cdir, x.st, x.ok, x.msg, x.worst
    L += ["## Worst cases", "", "Each case can be flown again, with its full history and figures, by the "
          "command given.", ""]
    cases = c.cases
    n_lists = len(L)
    div = np.flatnonzero(st == "diverged")
    if div.size:
        L += [f"### Diverged ({div.size})", ""]
        t_end = c.columns.get("t_end_s")
        rows = [[str(int(cases[i])), _f(float(t_end[i])) if t_end is not None else "n/a",
                 _md(str(msg[i])) if msg is not None else "", f"`{refly_command(cdir, int(cases[i]))}`"]
                for i in div[:max(worst, 20)]]
        L += _table(["case", "t_end [s]", "message", "re-fly"], rows)
        if div.size > max(worst, 20):
            L.append(f"\n({div.size - max(worst, 20)} more diverged cases)")
        L.append("")
    err = np.flatnonzero(st == "error")
    if err.size:
        L += [f"### Worker errors ({err.size})", ""]
        L += _table(["case", "message", "re-fly"],
                    [[str(int(cases[i])), _md(str(msg[i])) if msg is not None else "",
                      f"`{refly_command(cdir, int(cases[i]))}`"] for i in err[:max(worst, 20)]])
        if err.size > max(worst, 20):
            L.append(f"\n({err.size - max(worst, 20)} more worker errors)")
        L.append("")
    for metric, _side, title in MAIN_METRICS:
        if not title or metric not in c.columns:
            continue
        v = c.columns[metric]
        settling = metric.endswith("settling_time_s")
        idx = np.flatnonzero(ok & (np.isfinite(v) | (settling & np.isnan(v))))
        if idx.size == 0:
            continue
        badness = np.where(np.isnan(v[idx]), math.inf, v[idx])  # not settled first: the worst
        pick = idx[np.lexsort((cases[idx], -badness))][:worst]
        name, unit, k = _shown(c, metric)
        L += [f"### {title[0].upper()}{title[1:]} (`{name}`, runs flown to the end)", ""]
        rows = [[str(int(cases[i])), "not settled" if np.isnan(v[i]) else _f(float(v[i]) * k),
                 f"`{refly_command(cdir, int(cases[i]))}`"] for i in pick]
        L += _table(["case", f"value [{unit}]" if unit else "value", "re-fly"], rows)
        L.append("")
    if len(L) == n_lists:
        L += ["No flown case to list.", ""]
    return L


def figure_lines(x: ReportContext, out_dir: Path, by_pair: dict, fmt: str) -> list[str]:
    L: list[str] = []
    c, ok, flown = x.c, x.ok, x.flown
    hist = _read_histories(c, flown)
    fig_dir = out_dir / "figures"
    written = _write_figures(c, fig_dir, ok, flown, hist, by_pair, fmt)
    L += ["## Figures", ""]
    if hist.missing:
        L += [f"{len(hist.missing)} flown cases have no history file (cases {_ranges(hist.missing)}); "
              f"the envelopes cover the {len(hist.t)} others.", ""]
    for name, caption in written:
        L += [f"![{caption}](figures/{name})", ""]
    if not written:
        L += ["No figure (no data to draw).", ""]
    return L
