"""Statistics of a Monte Carlo campaign: NumPy and SciPy only (no pandas, no matplotlib).

Every function takes plain arrays (NaN = no value) and returns plain numbers, so it can be tested
against independent computations and used outside the report:

* :func:`percentile_ci`, :func:`bootstrap_percentiles`  a percentile and its percentile-bootstrap
  confidence interval (deterministic for a given seed);
* :func:`mean_ci`           the mean and its Student-t confidence interval;
* :func:`clopper_pearson`   a rate k / n and its exact (Clopper-Pearson) interval;
* :func:`wilks_runs`, :func:`wilks_confidence`, :func:`wilks_bound`  how many runs a
  distribution-free tolerance bound needs (Wilks), and the bound a sample gives;
* :func:`envelope`          percentile curves over time across runs of different lengths;
* :func:`ecdf`              the empirical distribution function;
* :func:`rank_correlations` Spearman's rho between every metric and every dispersed value.

Percentiles ``q`` are in percent (0..100, as :func:`numpy.percentile`); ``coverage`` and
``confidence`` are fractions (0..1).  The values keep the unit of the input.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike
from scipy import stats as sps

#: Elements per bootstrap block (resamples x sample size): bounds the memory of a bootstrap of a
#: large campaign (16 MB of indices) while keeping NumPy's per-call overhead negligible.
_BOOT_BLOCK = 2_000_000

Sided = Literal["two", "upper", "lower"]


def _finite(x: ArrayLike) -> np.ndarray:
    """``x`` as float64 without its NaN entries (+-inf are kept: they are values, e.g. "never")."""
    a = np.asarray(x, dtype=float).ravel()
    return a[~np.isnan(a)]


def _check_fraction(name: str, v: float) -> None:
    if not 0.0 < v < 1.0:
        raise ValueError(f"{name} = {v!r}: must be strictly between 0 and 1")


# --------------------------------------------------------------------------- percentiles and means


def bootstrap_percentiles(x: ArrayLike, qs: Sequence[float], confidence: float = 0.95, n_boot: int = 2000,
                          seed: int = 0) -> list[tuple[float, float, float]]:
    """Percentiles ``qs`` [%] of ``x`` (NaN dropped) with percentile-bootstrap confidence intervals.

    For each q: the estimate is ``numpy.percentile(x, q)`` (linear interpolation between order
    statistics); the interval is the (a/2, 1 - a/2) quantiles, a = 1 - ``confidence``, of the same
    percentile computed on ``n_boot`` resamples of x drawn with replacement (Efron & Tibshirani,
    *An Introduction to the Bootstrap*, 1993, ch. 13, the "percentile interval").  All qs share the
    resamples, drawn by ``numpy.random.default_rng(seed)`` in blocks whose size depends only on
    ``len(x)``: the result for one q does not depend on which other qs are asked for.

    Returns ``[(estimate, lo, hi), ...]`` in the order of ``qs``; all NaN when x has no value, and
    ``lo = hi = estimate`` for a single value.  Caveat: for extreme percentiles of small samples
    (q = 5 with n < 50, say) the percentile bootstrap under-covers: the resamples cannot go beyond
    the sample's extremes.
    """
    _check_fraction("confidence", confidence)
    a = _finite(x)
    q = np.asarray(qs, dtype=float)
    if a.size == 0:
        return [(math.nan, math.nan, math.nan) for _ in q]
    est = np.percentile(a, q)
    if a.size == 1:
        return [(float(e), float(e), float(e)) for e in est]
    rng = np.random.default_rng(seed)
    n = a.size
    rows = max(1, _BOOT_BLOCK // n)
    boots = np.empty((n_boot, q.size))
    for start in range(0, n_boot, rows):
        m = min(rows, n_boot - start)
        idx = rng.integers(0, n, size=(m, n))
        boots[start:start + m] = np.percentile(a[idx], q, axis=1).T
    alpha = 1.0 - confidence
    lo = np.percentile(boots, 100.0 * alpha / 2.0, axis=0)
    hi = np.percentile(boots, 100.0 * (1.0 - alpha / 2.0), axis=0)
    return [(float(e), float(l_), float(h)) for e, l_, h in zip(est, lo, hi, strict=True)]


def percentile_ci(x: ArrayLike, q: float, confidence: float = 0.95, n_boot: int = 2000,
                  seed: int = 0) -> tuple[float, float, float]:
    """The ``q``-th percentile [%] of ``x`` (NaN dropped) and its percentile-bootstrap confidence
    interval: ``(estimate, lo, hi)``, in the unit of x.  See :func:`bootstrap_percentiles` for the
    formula and the reference; deterministic for a given ``seed``."""
    return bootstrap_percentiles(x, [q], confidence, n_boot, seed)[0]


def mean_ci(x: ArrayLike, confidence: float = 0.95) -> tuple[float, float, float]:
    """The mean of ``x`` (NaN dropped) and its Student-t confidence interval ``(mean, lo, hi)``.

    ``mean +- t_{1-a/2, n-1} s / sqrt(n)``, s the sample standard deviation (ddof = 1),
    a = 1 - ``confidence`` (e.g. Montgomery & Runger, *Applied Statistics and Probability for
    Engineers*, sec. 8.2).  Exact for normal data, and by the central limit theorem close for the
    sample sizes of a campaign; chosen over a bootstrap because it needs no random numbers.
    The bounds are NaN for fewer than 2 values; an infinite value makes the mean infinite.
    """
    _check_fraction("confidence", confidence)
    a = _finite(x)
    if a.size == 0:
        return (math.nan, math.nan, math.nan)
    m = float(np.mean(a))
    if a.size < 2 or not np.all(np.isfinite(a)):
        return (m, math.nan, math.nan)
    half = float(sps.t.ppf(0.5 + confidence / 2.0, a.size - 1) * np.std(a, ddof=1) / math.sqrt(a.size))
    return (m, m - half, m + half)


# --------------------------------------------------------------------------- rates


def clopper_pearson(k: int, n: int, confidence: float = 0.95, sided: Sided = "two") -> tuple[float, float, float]:
    """A rate ``k / n`` (e.g. failures over flown runs) and its exact Clopper-Pearson interval.

    Two-sided (``sided="two"``), a = 1 - ``confidence``::

        lo = B(a/2; k, n - k + 1)          (0 when k = 0)
        hi = B(1 - a/2; k + 1, n - k)      (1 when k = n)

    with B(p; a, b) the p-quantile of the beta distribution (Clopper & Pearson, Biometrika 26,
    1934, p. 404).  ``sided="upper"`` gives the one-sided upper bound (lo = 0, hi = B(1 - a;
    k + 1, n - k)): "the rate is at most hi with this confidence", e.g. k = 0, n = 59 gives
    hi = 1 - 0.05^(1/59) = 0.0495 at 95 %; ``sided="lower"`` the one-sided lower bound (hi = 1).
    The interval is conservative: it covers the true rate with at least the confidence.

    Returns ``(k / n, lo, hi)``; ``(nan, 0, 1)`` when n = 0 (no information).
    """
    _check_fraction("confidence", confidence)
    if n < 0 or k < 0 or k > n:
        raise ValueError(f"clopper_pearson: need 0 <= k <= n, got k = {k}, n = {n}")
    if sided not in ("two", "upper", "lower"):
        raise ValueError(f"sided = {sided!r}: one of 'two', 'upper', 'lower'")
    if n == 0:
        return (math.nan, 0.0, 1.0)
    alpha = 1.0 - confidence
    tail = alpha / 2.0 if sided == "two" else alpha
    lo = 0.0 if k == 0 or sided == "upper" else float(sps.beta.ppf(tail, k, n - k + 1))
    hi = 1.0 if k == n or sided == "lower" else float(sps.beta.ppf(1.0 - tail, k + 1, n - k))
    return (k / n, lo, hi)


# --------------------------------------------------------------------------- Wilks tolerance bounds


def wilks_confidence(n: int, coverage: float, order: int = 1, two_sided: bool = False) -> float:
    """The confidence that the ``order``-th largest of ``n`` runs bounds the ``coverage`` quantile
    (one-sided), or that the ``order``-th smallest and largest enclose ``coverage`` of the
    population (two-sided), for any continuous distribution (Wilks, Ann. Math. Stat. 12, 1941;
    Guba, Makai & Pal, Reliab. Eng. Syst. Saf. 80, 2003, eqs. 3-5)::

        one-sided:  P = 1 - sum_{j=0}^{m-1}  C(n, j) (1 - g)^j g^(n - j)      (m = order)
        two-sided:  P = 1 - sum_{j=0}^{2m-1} C(n, j) (1 - g)^j g^(n - j)

    i.e. the probability that at least m (2m) of the n runs fall outside the g-quantile(s):
    ``binom.sf(m - 1, n, 1 - g)``.  For order 1, one-sided, P = 1 - g^n.
    """
    _check_fraction("coverage", coverage)
    if order < 1:
        raise ValueError(f"order = {order}: must be >= 1")
    k = 2 * order if two_sided else order
    if n < k:
        return 0.0
    return float(sps.binom.sf(k - 1, n, 1.0 - coverage))


def wilks_runs(coverage: float, confidence: float, order: int = 1, two_sided: bool = False) -> int:
    """The smallest number of runs n for which the ``order``-th extreme run is a tolerance bound of
    the ``coverage`` quantile with at least ``confidence`` (:func:`wilks_confidence` >= confidence).

    Examples at 95 % / 95 %: one-sided 59 (order 1), 93 (order 2), 124 (order 3); two-sided 93
    (order 1), 153 (order 2).  The confidence grows with n, so the first n that reaches it is found
    by bisection after doubling.
    """
    _check_fraction("confidence", confidence)
    hi = 2 * order if two_sided else order
    while wilks_confidence(hi, coverage, order, two_sided) < confidence:
        hi *= 2
    lo = 0  # wilks_confidence(lo) < confidence (0 runs give nothing)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if wilks_confidence(mid, coverage, order, two_sided) >= confidence:
            hi = mid
        else:
            lo = mid
    return hi


@dataclass(frozen=True)
class WilksBound:
    """A distribution-free tolerance bound from :func:`wilks_bound`.

    ``value`` is the bound (one-sided: upper, or lower with ``side="lower"``), ``lo``/``hi`` the
    two-sided interval; they are None when the sample is too small, and then ``n_needed`` says how
    many runs the requested order needs.  ``rank`` is the 1-based rank of the order statistic used
    in the sorted sample (ascending), ``achieved`` the confidence the sample really gives.
    """

    value: float | None
    lo: float | None
    hi: float | None
    n: int
    n_needed: int
    order: int
    rank: int | None
    achieved: float
    coverage: float
    confidence: float
    side: str

    @property
    def ok(self) -> bool:
        """Whether the sample is large enough for the bound."""
        return self.n >= self.n_needed


def wilks_max_order(n: int, coverage: float, confidence: float, two_sided: bool = False) -> int:
    """The largest order m whose bound still has ``confidence`` with ``n`` runs (0 when even m = 1
    needs more runs): the least conservative valid Wilks bound for this n."""
    m = 0
    while wilks_confidence(n, coverage, m + 1, two_sided) >= confidence:
        m += 1
    return m


def wilks_bound(x: ArrayLike, coverage: float = 0.95, confidence: float = 0.95, order: int | None = 1,
                two_sided: bool = False, side: Literal["upper", "lower"] = "upper") -> WilksBound:
    """The order statistic of ``x`` that is a ``coverage`` / ``confidence`` tolerance bound (Wilks).

    One-sided upper (default): the ``order``-th largest value u satisfies P(F(u) >= coverage) >=
    confidence when len(x) >= :func:`wilks_runs` (coverage, confidence, order); ``side="lower"``
    gives the order-th smallest (a bound from below, e.g. for a constraint margin).  Two-sided:
    the order-th smallest and largest enclose ``coverage`` of the population.  ``order=None`` takes
    the largest order the sample admits (:func:`wilks_max_order`; the tightest valid bound; the
    order is fixed by n alone, not by the values, so the guarantee holds).

    NaN entries are dropped (so n counts only values); +-inf are kept, so a case that never
    settled (inf) counts as beyond the bound.  When n is too small the result has ``value=None``
    and ``n_needed`` gives the runs needed (for order 1 when ``order=None``).
    """
    _check_fraction("confidence", confidence)
    a = np.sort(_finite(x))
    n = int(a.size)
    m = wilks_max_order(n, coverage, confidence, two_sided) if order is None else order
    m_need = max(m, 1)
    needed = wilks_runs(coverage, confidence, m_need, two_sided)
    achieved = wilks_confidence(n, coverage, m_need, two_sided) if n else 0.0
    if n < needed or m < 1:
        return WilksBound(None, None, None, n, needed, m_need, None, achieved, coverage, confidence,
                          "two" if two_sided else side)
    if two_sided:
        lo, hi = float(a[m - 1]), float(a[n - m])
        return WilksBound(None, lo, hi, n, needed, m, n - m + 1, achieved, coverage, confidence, "two")
    rank = n - m + 1 if side == "upper" else m
    return WilksBound(float(a[rank - 1]), None, None, n, needed, m, rank, achieved, coverage, confidence, side)


# --------------------------------------------------------------------------- over time and distributions


class Envelope(NamedTuple):
    """Percentile curves across runs: ``t`` [s] (the union of the runs' times), ``curves`` {percentile:
    values at t} and ``n_runs`` (how many runs have a value at each t)."""

    t: np.ndarray
    curves: dict[float, np.ndarray]
    n_runs: np.ndarray


def envelope(times_list: Sequence[ArrayLike], values_list: Sequence[ArrayLike],
             percentiles: Sequence[float] = (5, 50, 95)) -> Envelope:
    """Percentile curves of a signal across runs, over time.

    The grid is the union of all runs' times (runs of one campaign share one grid, up to where a
    diverged run stopped).  At each time t_j the curve of percentile q is ``numpy.nanpercentile``
    of the values the runs have at t_j: a run that stopped early (or has NaN there) contributes
    only while it has values, and ``n_runs[j]`` says how many runs did.  Where no run has a value
    the curves are NaN.  Values keep their unit; percentiles are in percent.
    """
    if len(times_list) != len(values_list):
        raise ValueError(f"envelope: {len(times_list)} time arrays but {len(values_list)} value arrays")
    ts = [np.asarray(t, dtype=float).ravel() for t in times_list]
    vs = [np.asarray(v, dtype=float).ravel() for v in values_list]
    for i, (t, v) in enumerate(zip(ts, vs, strict=True)):
        if t.shape != v.shape:
            raise ValueError(f"envelope: run {i} has {t.size} times but {v.size} values")
    q = [float(p) for p in percentiles]
    if not ts:
        return Envelope(np.empty(0), {p: np.empty(0) for p in q}, np.empty(0, dtype=np.int64))
    grid = np.unique(np.concatenate(ts))
    idx = [np.searchsorted(grid, t) for t in ts]
    # time blocks, so that runs x block stays bounded for long campaigns (one column of all runs
    # is what nanpercentile needs, so blocking over time rather than runs)
    block = max(1, _BOOT_BLOCK // max(1, len(ts)))
    curves = {p: np.full(grid.size, np.nan) for p in q}
    count = np.zeros(grid.size, dtype=np.int64)
    for j0 in range(0, grid.size, block):
        j1 = min(grid.size, j0 + block)
        mat = np.full((len(ts), j1 - j0), np.nan)
        for r, (ix, v) in enumerate(zip(idx, vs, strict=True)):
            sel = (ix >= j0) & (ix < j1)
            mat[r, ix[sel] - j0] = v[sel]
        have = ~np.isnan(mat)
        count[j0:j1] = have.sum(axis=0)
        cols = count[j0:j1] > 0
        if np.any(cols):
            pc = np.nanpercentile(mat[:, cols], q, axis=0)
            for k, p in enumerate(q):
                curves[p][j0:j1][cols] = pc[k]
    return Envelope(grid, curves, count)


def ecdf(x: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The empirical distribution function of ``x``: ``(values sorted ascending, F)`` with
    F_i = i / n, i = 1..n (the fraction of values <= the i-th).  NaN are dropped; +inf are kept
    (sorted last), so with "never settled" as inf the finite part of the curve ends below 1."""
    a = np.sort(_finite(x))
    return a, np.arange(1, a.size + 1, dtype=float) / max(a.size, 1)


# --------------------------------------------------------------------------- sensitivity


@dataclass(frozen=True)
class RankCorrelation:
    """Spearman's rank correlation of one metric with one dispersed value, over ``n`` cases."""

    metric: str
    draw: str
    rho: float
    p: float
    n: int


def numeric(column: np.ndarray) -> np.ndarray | None:
    """A summary column as float64 (bools as 0/1), or None for a non-numeric (string) column."""
    a = np.asarray(column)
    if a.dtype.kind in "biuf":
        return a.astype(float)
    return None


def rank_correlations(summary_columns: Mapping[str, np.ndarray], draws: Sequence[str],
                      metrics: Sequence[str]) -> list[RankCorrelation]:
    """Spearman's rho and its p-value (``scipy.stats.spearmanr``, two-sided test of rho = 0) of
    every metric against every dispersed value, in the order (metric, draw).

    Pairs use the cases where both are finite.  A pair is skipped when fewer than 3 such cases
    remain or either side is constant over them (rho undefined); a non-numeric column (a discrete
    choice among strings) is skipped: its categories have no order for a rank correlation to
    measure.  Bool columns count as 0/1.  rho = +1 means the metric grows monotonically with the
    draw (Spearman, Am. J. Psychol. 15, 1904; rho is Pearson's r of the ranks, ties averaged).
    """
    out: list[RankCorrelation] = []
    cols = {name: numeric(summary_columns[name]) for name in (*draws, *metrics) if name in summary_columns}
    for m in metrics:
        y = cols.get(m)
        if y is None:
            continue
        for d in draws:
            x = cols.get(d)
            if x is None:
                continue
            ok = np.isfinite(x) & np.isfinite(y)
            if ok.sum() < 3:
                continue
            xs, ys = x[ok], y[ok]
            if np.all(xs == xs[0]) or np.all(ys == ys[0]):
                continue
            res = sps.spearmanr(xs, ys)
            out.append(RankCorrelation(m, d, float(res.statistic), float(res.pvalue), int(ok.sum())))
    return out
