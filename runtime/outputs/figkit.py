"""Drawing helpers shared by the figures of one run (:mod:`rpo.runtime.outputs.plots`,
:mod:`rpo.runtime.outputs.views`): matplotlib's object API on the Agg canvas, no pyplot.

Long series are drawn through a min/max envelope per horizontal pixel (:func:`envelope`), which
looks the same as every point and keeps vector files small.  No layout engine: fixed margins
(constrained layout cost half of the drawing time).  An error the verdict judges is drawn by
:func:`judged_panel`, with its threshold (a red dashed line labelled ``threshold ...``) and its
settling time (a green line labelled ``reached at ... s``), or "not reached" written in the panel.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import LogLocator, MaxNLocator, NullLocator

from rpo.runtime.formats import figure_format_of
from rpo.runtime.outputs.plotdata import Judged, PlotData

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from rpo.runtime.model.manifest import LayoutField

RAD2DEG = 180.0 / np.pi
RADS2RPM = 60.0 / (2.0 * np.pi)
#: Envelope bins per line: about one per horizontal pixel of a 9 inch figure at DPI.
ENVELOPE_BINS = 1000
DPI = 110
AXES_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red")
XYZ = ("x", "y", "z")
THRESHOLD_STYLE: dict[str, Any] = {"color": "red", "ls": "--", "lw": 1.0}
SETTLED_STYLE: dict[str, Any] = {"color": "tab:green", "ls": "-.", "lw": 1.2}
#: Fixed margins [inch].
MARGIN = {"left": 0.85, "right": 1.75, "bottom": 0.55, "top": 0.75, "hspace": 0.45}


def envelope(t: np.ndarray, x: np.ndarray, n_bins: int = ENVELOPE_BINS) -> tuple[np.ndarray, np.ndarray]:
    """``(t, x)`` reduced to the first, minimum, maximum and last sample of each of ``n_bins``
    consecutive bins, in time order: the drawn line covers the same pixels as the full series."""
    n = len(t)
    k = n // n_bins
    if k < 4:
        return t, x
    m = n_bins * k
    b = x[:m].reshape(n_bins, k)
    lo = np.where(np.isnan(b), np.inf, b).argmin(axis=1)
    hi = np.where(np.isnan(b), -np.inf, b).argmax(axis=1)
    base = np.arange(n_bins) * k
    idx = np.concatenate([base, base + lo, base + hi, base + k - 1, np.arange(m, n)])
    idx = np.unique(idx)
    return t[idx], x[idx]


def legend(ax: Axes, ncol: int = 1) -> None:
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, frameon=False, ncol=ncol)


def lines(ax: Axes, t, data, labels: Sequence[str], ylabel: str, colors: Sequence[str] | None = None) -> None:
    n = data.shape[1]
    for i in range(n):  # x, y, z, w in the usual colours; longer fields (estimates) in the tab10 cycle
        color = colors[i] if colors else (AXES_COLORS[i] if n <= 4 else f"C{i % 10}")
        ax.plot(*envelope(t, data[:, i]), lw=1.0, color=color, label=labels[i])
    ax.set_ylabel(ylabel, fontsize=9)
    ax.tick_params(labelsize=8)
    ax.yaxis.set_major_locator(MaxNLocator(4))  # every tick is five artists: fewer is faster
    if n > 1 or labels[0]:
        legend(ax, 1 if n <= 8 else 2)


def norm(ax: Axes, t, data, label: str) -> None:
    ax.plot(*envelope(t, np.linalg.norm(data, axis=1)), lw=1.2, color="k", label=label)


def limits(ax: Axes, value: float | None, label: str = "limit") -> None:
    if value:
        for s in (1, -1):
            ax.axhline(s * value, color="red", ls=":", lw=1.0, label=label if s == 1 else None)


def components(f: LayoutField) -> list[str]:
    """Legend entries of a field: its component names (``x``, ``alpha_xx1``, ``wheel 1``...)."""
    if f.size == 1:
        return [""]
    out = []
    for lbl in f.labels:
        c = lbl[len(f.name) + 1:] if lbl.startswith(f.name + "_") else lbl
        what = "wheel" if "wheel" in f.name or f.name == "h_w" else "thruster" if f.name.startswith("thr_") else "#"
        out.append((f"{what} {int(c)}" if what != "#" else f"#{int(c)}") if c.isdigit() else c)
    return out


def figure(n_panels: int, height: float = 2.0, ncols: int = 1, titled: bool = False,
           width: float | None = None, title_lines: int = 0) -> tuple[Figure, list]:
    """A figure of ``n_panels`` panels over time in ``ncols`` columns (filled down each column),
    with room right of each panel for its legend (and above for ``title_lines`` more title lines)."""
    rows = -(-n_panels // ncols)
    gap = MARGIN["hspace"] + (0.25 if titled else 0.0)
    width = width or (9.0 if ncols == 1 else 15.0)
    top = MARGIN["top"] + (0.3 if titled else 0.0) + 0.2 * title_lines
    h = top + MARGIN["bottom"] + height * rows + gap * (rows - 1)
    fig = Figure(figsize=(width, h))
    axes = fig.subplots(rows, ncols, sharex=True, squeeze=False)
    axes[0, 0].xaxis.set_major_locator(MaxNLocator(6))  # shared by every panel
    ax_w = (width - MARGIN["left"] - ncols * MARGIN["right"] - (ncols - 1) * MARGIN["left"]) / ncols
    fig.subplots_adjust(left=MARGIN["left"] / width, right=1 - MARGIN["right"] / width,
                        bottom=MARGIN["bottom"] / h, top=1 - top / h,
                        hspace=gap / height, wspace=(MARGIN["right"] + MARGIN["left"]) / ax_w)
    flat = list(axes.T.ravel())
    for ax in flat[n_panels:]:
        ax.set_visible(False)
    return fig, flat[:n_panels]


def events(ax: Axes, d: PlotData) -> None:
    """The divergence (red dashed) and the faults (orange dotted) as vertical lines."""
    if d.divergence is not None:
        ax.axvline(d.divergence[0], color="red", lw=1.0, ls="--")
    for t_f, _label in d.faults:
        ax.axvline(t_f, color="darkorange", lw=1.0, ls=":")


def finish(fig: Figure, axes, d: PlotData, title: str, time_axes: bool = True) -> Figure:
    """Grids, events, the time labels of the bottom panels and the title (faults, divergence)."""
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if time_axes:
            events(ax, d)
    if time_axes:
        bottom = {ax.get_subplotspec().colspan.start: ax for ax in axes}  # the lowest panel of each column
        for ax in bottom.values():
            ax.set_xlabel("time [s]")
            ax.xaxis.set_tick_params(labelbottom=True)
    if d.faults:
        shown = "; ".join(f"{label} at {t_f:g} s" for t_f, label in d.faults[:4])
        title = f"{title}\nfaults (dotted): {shown}{' ...' if len(d.faults) > 4 else ''}"
    if d.divergence is not None:
        title = f"{title}\nDIVERGED at t = {d.divergence[0]:.6g} s ({d.divergence[1]})"
    fig.suptitle(f"{d.title}: {title}", fontsize=11, y=1 - 0.12 / fig.get_figheight(), va="top")
    return fig


def save(fig: Figure, path: Path) -> None:
    fmt = figure_format_of(path)  # its quick options (PNG: a fast zlib level)
    extra: dict[str, Any] = fmt.quick_options() if fmt is not None else {}
    fig.savefig(path, dpi=DPI, **extra)


def _fmt(v: float) -> str:
    return f"{v:.4g}"


def judged_panel(ax: Axes, t: np.ndarray, j: Judged, log: bool = True, color: str = "k") -> None:
    """The error ``j`` as the verdict judges it: its series, its threshold and its settling time,
    and above the panel where it comes from (its columns).

    ``log``: a logarithmic y axis (the error's decay over decades and the threshold on the same
    scale: a 0.5 m threshold is a hair on a linear 250 m axis; zeros are not drawn)."""
    ax.plot(*envelope(t, j.signal), lw=1.2, color=color, label=j.label)
    ax.text(0.0, 1.02, f"{j.label}{' judged by the verdict' if j.judged else ''}: {j.source}",
            transform=ax.transAxes, fontsize=8, va="bottom")
    if j.threshold is not None:
        ax.axhline(j.threshold, label=f"threshold {_fmt(j.threshold)} {j.unit}", **THRESHOLD_STYLE)
        if j.settling is not None:
            ax.axvline(j.settling, label=f"reached at {_fmt(j.settling)} s", **SETTLED_STYLE)
        else:
            ax.text(0.99, 0.95, "not reached", transform=ax.transAxes, ha="right", va="top", fontsize=9,
                    color="red")
    ax.set_ylabel(f"{j.label} [{j.unit}]", fontsize=9)
    ax.tick_params(labelsize=8)
    if log:
        ax.set_yscale("log")
        # at most 6 labelled decades and no minor ticks: an error falls over ten decades, where eight
        # minor ticks a decade are noise, and every tick is an artist drawn (a third of a figure's time)
        ax.yaxis.set_major_locator(LogLocator(numticks=6))
        ax.yaxis.set_minor_locator(NullLocator())
        finite = j.signal[np.isfinite(j.signal) & (j.signal > 0)]
        if finite.size:
            lo = min(float(finite.min()), j.threshold or np.inf)
            hi = max(float(finite.max()), j.threshold or 0.0)
            ax.set_ylim(lo / 2, hi * 2)
    else:
        ax.yaxis.set_major_locator(MaxNLocator(4))
        ax.set_ylim(bottom=0)
    legend(ax)
