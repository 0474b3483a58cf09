"""Figures of a Monte Carlo campaign (matplotlib, Agg, no pyplot; imported inside the functions so
that importing :mod:`rpo.runtime.campaign.reporting` or the statistics costs no matplotlib).

* :func:`envelope_figure`  percentile bands over time (5-95 % shaded, the median as a line), one
  panel per signal, and how many runs are still flying when some stopped early;
* :func:`cdf_figure`       empirical CDFs (e.g. settling times: a run that never settled is +inf,
  so the curve ends below 1 and the panel says how many never did);
* :func:`scatter_figure`   one metric against every numeric dispersed value, Spearman's rho in each
  panel's title.

The functions take arrays, not a campaign folder: :mod:`rpo.runtime.campaign.reporting` does the
reading.  Files are deterministic: same data, same bytes (no date or software version in the
PNG/PDF metadata, a fixed SVG hash salt).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.campaign.stats import Envelope, ecdf
from rpo.runtime.formats import figure_format_of

if TYPE_CHECKING:
    from matplotlib.figure import Figure

DPI = 110
STATUS_COLORS = {"ok": "tab:blue", "diverged": "tab:red"}
#: Panels per scatter figure at most (the draws come sorted by |rho|, so the ones left out matter least).
MAX_SCATTER_PANELS = 24


@dataclass(frozen=True)
class EnvelopePanel:
    """One signal of :func:`envelope_figure`: its y label (with unit), the envelope and a scale
    applied to the values for display (e.g. 180/pi for rad -> deg)."""

    label: str
    env: Envelope
    scale: float = 1.0


def _new_figure(width: float, height: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), dpi=DPI)


def save(fig: Figure, path: str | Path) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix: one of :data:`rpo.runtime.formats.FIGURE_FORMATS`)
    without any date, software version or random id in the file, so the bytes depend on the drawing only."""
    import matplotlib

    p = Path(path)
    fmt = figure_format_of(p)
    meta: dict[str, Any] = fmt.fixed_metadata() if fmt is not None else {}
    # the hash salt fixes the ids of SVG clip paths (otherwise random per process)
    with matplotlib.rc_context({"svg.hashsalt": "rpo-campaign", "pdf.compression": 6}):
        fig.savefig(p, dpi=DPI, metadata=meta)
    return p


def envelope_figure(panels: Sequence[EnvelopePanel], path: str | Path, title: str = "",
                    low: float = 5.0, mid: float = 50.0, high: float = 95.0) -> Path | None:
    """Percentile envelopes over time: per panel the band between the ``low`` and ``high``
    percentiles of the runs (shaded) and the ``mid`` one (line), time in s.  When the number of runs
    with a value changes over time (diverged runs stop early) a last panel shows that count.
    Returns the path written, or None when no panel has data."""
    panels = [p for p in panels if p.env.t.size and np.any(p.env.n_runs > 0)]
    if not panels:
        return None
    counts = panels[0].env
    varying = any(np.any(p.env.n_runs != p.env.n_runs.max()) for p in panels)
    n = len(panels) + (1 if varying else 0)
    fig = _new_figure(8.0, 0.9 + 2.0 * n)
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    for ax, p in zip(axes, panels, strict=False):
        e = p.env
        ax.fill_between(e.t, e.curves[low] * p.scale, e.curves[high] * p.scale, color="tab:blue", alpha=0.25,
                        lw=0, label=f"{low:g}-{high:g} %")
        ax.plot(e.t, e.curves[mid] * p.scale, color="tab:blue", lw=1.2, label=f"median ({mid:g} %)")
        ax.set_ylabel(p.label, fontsize=9)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right")
    if varying:
        ax = axes[-1]
        ax.step(counts.t, counts.n_runs, where="post", color="tab:gray", lw=1.0)
        ax.set_ylabel("runs with data", fontsize=9)
        ax.set_ylim(0, max(1, int(counts.n_runs.max())) * 1.1)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title or "percentile envelopes across runs", fontsize=11)
    fig.tight_layout()
    return save(fig, path)


def cdf_figure(panels: Sequence[tuple[str, Sequence[tuple[str, np.ndarray]]]], path: str | Path,
               title: str = "", never: str = "never settled") -> Path | None:
    """Empirical CDFs: ``panels`` is ``[(x label with unit, [(curve label, values), ...]), ...]``.
    NaN values are dropped; +inf values (a run that never settled) count in n but are not drawn,
    so the curve ends at the fraction that is finite, and the legend says how many were inf
    (``never`` words it).  Returns the path, or None when nothing has a value."""
    kept = [(lab, [(c, np.asarray(v, dtype=float)) for c, v in curves if np.any(~np.isnan(np.asarray(v, float)))])
            for lab, curves in panels]
    kept = [(lab, curves) for lab, curves in kept if curves]
    if not kept:
        return None
    fig = _new_figure(8.0, 0.8 + 2.6 * len(kept))
    axes = fig.subplots(len(kept), 1, squeeze=False)[:, 0]
    for ax, (lab, curves) in zip(axes, kept, strict=True):
        for i, (name, v) in enumerate(curves):
            x, f = ecdf(v)
            fin = np.isfinite(x)
            n_inf = int(np.sum(np.isposinf(x)))
            label = f"{name} (n = {x.size}"
            label += f"; {n_inf} {never})" if n_inf else ")"
            if np.any(fin):
                # a step from 0 at the first value, as an ECDF is drawn
                ax.step(np.r_[x[fin][0], x[fin]], np.r_[0.0, f[fin]], where="post", color=f"C{i}", lw=1.3,
                        label=label)
            else:
                ax.plot([], [], color=f"C{i}", label=label)
            if n_inf:
                ax.axhline(1.0 - n_inf / x.size, color=f"C{i}", lw=0.8, ls=":")
        ax.set_xlabel(lab, fontsize=9)
        ax.set_ylabel("fraction of runs", fontsize=9)
        ax.set_ylim(0.0, 1.02)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(title or "empirical distribution functions", fontsize=11)
    fig.tight_layout()
    return save(fig, path)


def scatter_figure(y_label: str, y: np.ndarray, draws: Sequence[tuple[str, np.ndarray, float]],
                   status: np.ndarray, path: str | Path, title: str = "") -> Path | None:
    """A grid of scatter plots of one metric ``y`` (its label with unit) against each dispersed
    value: ``draws`` is ``[(label, x, rho), ...]`` (rho = Spearman, NaN when undefined), at most
    :data:`MAX_SCATTER_PANELS` of them; points coloured by ``status`` ("ok", "diverged").
    Returns the path, or None when there is nothing to draw."""
    y = np.asarray(y, dtype=float)
    draws = list(draws)[:MAX_SCATTER_PANELS]
    if not draws or not np.any(np.isfinite(y)):
        return None
    ncols = min(4, len(draws))
    nrows = math.ceil(len(draws) / ncols)
    fig = _new_figure(2.6 * ncols + 0.6, 2.3 * nrows + 0.7)
    axes = fig.subplots(nrows, ncols, squeeze=False, sharey=True)
    flat = list(axes.ravel())
    st = np.asarray(status)
    for ax, (label, x, rho) in zip(flat, draws, strict=False):
        x = np.asarray(x, dtype=float)
        for s, color in STATUS_COLORS.items():
            sel = (st == s) & np.isfinite(x) & np.isfinite(y)
            if np.any(sel):
                ax.scatter(x[sel], y[sel], s=8, color=color, alpha=0.7, lw=0, label=s)
        ax.set_title(f"rho = {rho:+.2f}" if math.isfinite(rho) else "rho undefined", fontsize=9)
        ax.set_xlabel(label, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
    for ax in flat[len(draws):]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel(y_label, fontsize=8)
    handles, labels = flat[0].get_legend_handles_labels()
    if len(labels) > 1:
        flat[0].legend(fontsize=7)
    fig.suptitle(title or f"{y_label} against the dispersed values (Spearman rho)", fontsize=10)
    fig.tight_layout()
    return save(fig, path)
