"""The report of a Monte Carlo campaign folder: ``report.md`` and ``figures/*.png``.

Reads what the campaign runner writes (pyarrow and NumPy only; no pandas):

* ``resolved.json``      the campaign as run (name, runs requested, scenario, controller, command);
* ``summary.parquet``    one row per finished case: ``case``, ``seed``, ``status`` (``ok``,
  ``diverged``, ``invalid``, ``error``), ``message``, the ``draw.*`` columns, the outcome flags
  (bool, nullable) and the metrics (float, NaN = unavailable); units in the schema metadata
  ``rpo.units``;
* ``histories/batch_*.parquet``  the time histories of the flown cases, one file a batch (``case``,
  ``t`` [s], ``err_att_rad``, ``err_pos_m``, ``h_w_norm``...), each case's file named by its line
  in ``manifest.jsonl`` (folders of older versions: ``histories/case_NNNNNN.parquet``).

:func:`write_report` writes the report; :func:`summary_table` and :func:`case_history` give the
columns as NumPy arrays.  Conventions of the report (also in ``docs/campaigns.md``):

* **flown** runs are those with status ``ok`` or ``diverged``; rates (failed, not settled,
  diverged, constraint violated) are over the flown runs, invalid draws and worker errors over
  the done cases;
* the metric table is over the runs flown to the end (``ok``): a diverged run's metrics describe a
  truncated flight;
* the Wilks tolerance bounds are over the flown runs, with a diverged run counted as beyond any
  bound (+inf, or -inf for a bound from below) and a run that never settled as a settling time of
  +inf: the bound is a statement on all flown runs, not only on the good ones;
* the sensitivity table ranks Spearman's rho of each metric (over ``ok`` runs) and of ``failed``
  (over flown runs, 0/1) against every numeric draw; string draws are skipped;
* everything is deterministic: the bootstrap seed is fixed, no date is written, and the files of
  the figures carry no timestamp.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from rpo.runtime.campaign import stats as S
from rpo.runtime.campaign.storage import history_path, read_histories, read_rows
from rpo.runtime.formats import DEFAULT_FIGURE_FORMAT, FIGURE_FORMATS, unknown_figure_format

STATUSES = ("ok", "diverged", "invalid", "error")
FLOWN = ("ok", "diverged")
OUTCOMES = ("att_reached", "pos_reached", "diverged", "constraint_violated", "failed")
#: The metrics with a tolerance bound and a worst-case list: (column, bound side, worst-case title).
MAIN_METRICS: tuple[tuple[str, str, str], ...] = (
    ("pos_err_final_m", "upper", "largest final position error"),
    ("att_err_final_rad", "upper", "largest final attitude error"),
    ("pos_settling_time_s", "upper", "longest position settling time"),
    ("att_settling_time_s", "upper", "longest attitude settling time"),
    ("propellant_kg", "upper", "most propellant"),
    ("delta_v_m_s", "upper", ""),
    ("pos_err_ss_rms_m", "upper", ""),
    ("att_err_ss_rms_rad", "upper", ""),
    ("wheel_momentum_peak_N_m_s", "upper", ""),
    ("beta_fov_min_m", "lower", ""),
    ("beta_ca_min_m2", "lower", ""),
)
#: The metrics drawn against the dispersed values (one scatter grid each).
SCATTER_METRICS = ("att_settling_time_s", "pos_settling_time_s", "att_err_final_rad", "pos_err_final_m",
                   "propellant_kg")
#: History channels of the envelope figure: (column, y label, scale to the displayed unit).
ENVELOPE_CHANNELS = (("err_att_rad", "attitude error [deg]", 180.0 / math.pi),
                     ("err_pos_m", "position error [m]", 1.0),
                     ("h_w_norm", "wheel momentum norm [N m s]", 1.0))
PERCENTILES = (5.0, 50.0, 95.0)


# --------------------------------------------------------------------------- reading


def _column_kind(t: pa.DataType) -> str:
    if pa.types.is_boolean(t):
        return "bool"
    if pa.types.is_integer(t):
        return "int"
    if pa.types.is_floating(t):
        return "float"
    return "string"


def _to_numpy(col: pa.ChunkedArray) -> np.ndarray:
    """A parquet column as NumPy: floats and bools as float64 with NaN for null (bools 1.0/0.0),
    integers as int64/uint64 (float64 with NaN if they have nulls), strings as ``str`` ("" for null)."""
    kind = _column_kind(col.type)
    if kind == "bool" or kind == "float" or (kind == "int" and col.null_count):
        return np.asarray(col.cast(pa.float64()).to_numpy(zero_copy_only=False), dtype=np.float64)
    if kind == "int":
        return np.asarray(col.to_numpy())
    if pa.types.is_dictionary(col.type):
        col = col.cast(pa.string())
    values = col.to_pylist()
    return np.array(["" if v is None else str(v) for v in values], dtype=str)


def _meta_json(schema: pa.Schema, key: bytes) -> dict:
    raw = (schema.metadata or {}).get(key)
    if not raw:
        return {}
    try:
        out = json.loads(raw)
    except ValueError:
        return {}
    return out if isinstance(out, dict) else {}


def summary_table(campaign_dir: str | Path) -> dict[str, np.ndarray]:
    """The columns of ``<campaign_dir>/summary.parquet`` as NumPy arrays, in file order.

    Floats and the nullable bool outcomes are float64 (NaN = null; bools as 1.0/0.0), integers
    keep their type (``case`` int64, ``seed`` uint64), strings are ``str`` arrays ("" = null).
    """
    table = pq.read_table(Path(campaign_dir) / "summary.parquet")
    return {name: _to_numpy(table.column(name)) for name in table.column_names}


def case_history(campaign_dir: str | Path, case: int, columns: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """The time history of one flown case as NumPy arrays (``t`` [s] and the channels, in their
    units; ``columns`` selects some, those absent from the file are left out).  Raises
    FileNotFoundError for a case that has no history (invalid draw, worker error, not done)."""
    folder = Path(campaign_dir)
    rows = read_rows(folder)
    cols = dict(read_histories(folder, [case], rows, columns)).get(case)
    if cols is None:
        path = history_path(folder, case, rows.get(case))
        raise FileNotFoundError(f"case {case} has no history (not in {path}: the case was not flown, "
                                f"or is not done yet)")
    return cols


@dataclass
class CampaignFolder:
    """A campaign folder read into memory: the resolved campaign, the summary columns, their kinds
    (``bool``, ``int``, ``float``, ``string``) and units, and the campaign metadata of the file."""

    path: Path
    resolved: dict
    columns: dict[str, np.ndarray]
    kinds: dict[str, str]
    units: dict[str, str]
    meta: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return str(self.resolved.get("name") or self.meta.get("name") or self.path.name)

    @property
    def requested(self) -> int:
        return int(self.resolved.get("runs", self.meta.get("runs", len(self.cases))))

    @property
    def cases(self) -> np.ndarray:
        return self.columns.get("case", np.empty(0, dtype=np.int64))

    @property
    def status(self) -> np.ndarray:
        return self.columns.get("status", np.empty(0, dtype=str))

    @property
    def draws(self) -> list[str]:
        return [c for c in self.columns if c.startswith("draw.")]

    @property
    def numeric_draws(self) -> list[str]:
        return [c for c in self.draws if self.kinds[c] != "string"]

    @property
    def metrics(self) -> list[str]:
        return [c for c, k in self.kinds.items() if k == "float" and c not in ("case", "seed")
                and not c.startswith("draw.")]

    def mask(self, statuses: Iterable[str]) -> np.ndarray:
        return np.isin(self.status, list(statuses))

    def unit(self, column: str) -> str:
        return self.units.get(column, "")


def read_folder(campaign_dir: str | Path) -> CampaignFolder:
    """Read ``resolved.json`` (optional) and ``summary.parquet`` (required) of a campaign folder."""
    path = Path(campaign_dir)
    summary = path / "summary.parquet"
    if not summary.is_file():
        raise FileNotFoundError(f"{summary} does not exist: not a campaign folder, or no case has finished")
    resolved_path = path / "resolved.json"
    resolved = json.loads(resolved_path.read_text()) if resolved_path.is_file() else {}
    table = pq.read_table(summary)
    columns = {name: _to_numpy(table.column(name)) for name in table.column_names}
    kinds = {name: _column_kind(table.schema.field(name).type) for name in table.column_names}
    units = {str(k): str(v) for k, v in _meta_json(table.schema, b"rpo.units").items()}
    return CampaignFolder(path, resolved, columns, kinds, units, _meta_json(table.schema, b"rpo.campaign"))


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


def _label(c: CampaignFolder, column: str) -> str:
    u = c.unit(column)
    return f"{column} [{u}]" if u else column


def _draw_label(c: CampaignFolder, column: str) -> str:
    name = column[len("draw."):] if column.startswith("draw.") else column
    u = c.unit(column)
    return f"{name} [{u}]" if u else name


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
        panels_s = [(_draw_label(c, d), c.columns[d][flown].astype(float), rho) for rho, d in draws]
        name = f"scatter_{metric}.{fmt}"
        if F.scatter_figure(_label(c, metric), c.columns[metric][flown], panels_s, flown_st, fig_dir / name,
                            f"{c.name}: {metric} against the dispersed values (Spearman rho over ok runs)"):
            written.append((name, f"{metric} against each dispersed value"))
    # a figure of an earlier write that this one did not draw (its data are gone) would contradict
    # the report: remove it; only our own file names are touched
    ours = {n for n, _ in written}
    for f in sorted(fig_dir.glob(f"*.{fmt}")):
        if f.name not in ours and (f.name in (f"envelopes.{fmt}", f"cdf.{fmt}") or f.name.startswith("scatter_")):
            f.unlink()
    return written


def write_report(campaign_dir: str | Path, out: str | Path | None = None, coverage: float = 0.95,
                 confidence: float = 0.95, n_boot: int = 2000, seed: int = 0, figures: bool = True,
                 top: int = 15, worst: int = 5, fmt: str = DEFAULT_FIGURE_FORMAT) -> Path:
    """Write ``report.md`` (and ``figures/*.<fmt>``) of a finished or partly finished campaign into
    ``out`` (default: the campaign folder); returns the path of ``report.md``.

    ``coverage`` and ``confidence`` (fractions) set the Wilks tolerance bounds and the confidence
    of every interval; ``n_boot`` and ``seed`` the bootstrap of the percentiles (the same folder
    gives the same bytes); ``top`` the rows of the sensitivity table, ``worst`` the rows per
    worst-case list.  The report's conventions are in the module docstring.
    """
    if fmt not in FIGURE_FORMATS:
        raise ValueError(unknown_figure_format(fmt))
    c = read_folder(campaign_dir)
    out_dir = Path(out) if out is not None else c.path
    out_dir.mkdir(parents=True, exist_ok=True)
    cdir = c.path.resolve()
    conf_pct = f"{100 * confidence:g} %"
    cov_pct = f"{100 * coverage:g} %"
    st = c.status
    ok, flown = c.mask(["ok"]), c.mask(FLOWN)
    counts = {s: int(np.sum(st == s)) for s in STATUSES}
    other = sorted(set(st.tolist()) - set(STATUSES))
    n_done, n_flown, n_ok = len(st), int(flown.sum()), int(ok.sum())
    L: list[str] = [f"# Monte Carlo campaign: {c.name}", ""]

    # ---------------------------------------------------------------- header
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
    missing = sorted(set(range(c.requested)) - {int(x) for x in c.cases})
    if missing:
        L += ["", f"**Incomplete campaign: {len(missing)} of the {c.requested} requested cases have no result "
                  f"(cases {_ranges(missing)}); everything below covers the {n_done} done.**"]
    L.append("")

    # ---------------------------------------------------------------- status
    L += ["## Status", ""]
    rows = [[s, str(counts[s]), _pct(counts[s] / n_done if n_done else math.nan)] for s in STATUSES]
    rows += [[s, str(int(np.sum(st == s))), _pct(float(np.sum(st == s)) / n_done)] for s in other]
    L += _table(["status", "cases", "of done"], rows)
    L.append("")
    msg = c.columns.get("message")
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

    # ---------------------------------------------------------------- failure rates
    L += ["## Failure rates", "",
          f"Over the {n_flown} flown runs (ok + diverged); invalid draws and worker errors over the {n_done} "
          f"done cases. Exact Clopper-Pearson intervals: the two-sided {conf_pct} interval, and the one-sided "
          f"upper bound (the rate is at most this with {conf_pct} confidence).", ""]
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

    # ---------------------------------------------------------------- Wilks
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
        value = _f(b.value) if b.ok else f"needs {b.n_needed} runs"
        order_txt = f"{b.order} ({'largest' if side == 'upper' else 'smallest'})" if b.ok else "-"
        rows.append([metric, c.unit(metric), "upper" if side == "upper" else "lower", str(b.n), order_txt, value,
                     f"{100 * b.achieved:.2f} %"])
    if rows:
        L += _table(["metric", "unit", "bound", "n", "order", f"{cov_pct} / {conf_pct} bound",
                     "confidence achieved"], rows)
    else:
        L.append("No main metric has a value.")
    L.append("")

    # ---------------------------------------------------------------- metrics
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
        mean = S.mean_ci(v, confidence)
        pcs = S.bootstrap_percentiles(v, PERCENTILES, confidence, n_boot, seed)
        cells = [f"{_f(e)} [{_f(lo)}, {_f(hi)}]" for e, lo, hi in (mean, *pcs)]
        rows.append([metric, c.unit(metric), str(v.size), *cells, _f(float(v.min())), _f(float(v.max()))])
    if rows:
        L += _table(["metric", "unit", "n", "mean", "p5", "p50", "p95", "min", "max"], rows)
    else:
        L.append("No run flown to the end has a metric value.")
    L.append("")

    # ---------------------------------------------------------------- sensitivity
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
        rows = [[x.metric, x.draw[len("draw."):], f"{x.rho:+.3f}", f"{x.p:.3g}" + (" *" if x.p < alpha_fw else ""),
                 str(x.n)] for x in ranked[:top]]
        L += _table(["metric", "dispersed value", "rho", "p", "n"], rows)
    else:
        L.append("No pair of a varying metric and a varying numeric dispersed value.")
    if skipped:
        L += ["", f"Not correlated (non-numeric draws: a choice among strings has no order): "
                  f"{', '.join(f'`{d}`' for d in skipped)}."]
    L.append("")

    # ---------------------------------------------------------------- worst cases
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
        L += [f"### {title[0].upper()}{title[1:]} (`{metric}`, runs flown to the end)", ""]
        rows = [[str(int(cases[i])), "not settled" if np.isnan(v[i]) else _f(float(v[i])),
                 f"`{refly_command(cdir, int(cases[i]))}`"] for i in pick]
        L += _table(["case", f"value [{c.unit(metric)}]" if c.unit(metric) else "value", "re-fly"], rows)
        L.append("")
    if len(L) == n_lists:
        L += ["No flown case to list.", ""]

    # ---------------------------------------------------------------- figures
    if figures:
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

    text = "\n".join(L).rstrip("\n") + "\n"
    path = out_dir / "report.md"
    path.write_text(text)
    return path
