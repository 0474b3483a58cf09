"""runtime/campaign/stats.py against independent computations and known values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats as sps
from scipy.special import comb

from rpo.runtime.campaign import stats as S

# --------------------------------------------------------------------------- Clopper-Pearson


@pytest.mark.parametrize("k,n", [(0, 59), (1, 59), (3, 10), (10, 10), (0, 1), (7, 200), (199, 200)])
@pytest.mark.parametrize("confidence", [0.95, 0.9])
def test_clopper_pearson_matches_scipy_binomtest(k, n, confidence):
    p, lo, hi = S.clopper_pearson(k, n, confidence)
    ci = sps.binomtest(k, n).proportion_ci(confidence_level=confidence, method="exact")
    assert p == k / n
    assert lo == pytest.approx(ci.low, abs=1e-12)
    assert hi == pytest.approx(ci.high, abs=1e-12)
    _, lo1, hi1 = S.clopper_pearson(k, n, confidence, sided="upper")
    ci1 = sps.binomtest(k, n, alternative="less").proportion_ci(confidence_level=confidence, method="exact")
    assert lo1 == 0.0 and hi1 == pytest.approx(ci1.high, abs=1e-12)
    _, lo2, hi2 = S.clopper_pearson(k, n, confidence, sided="lower")
    ci2 = sps.binomtest(k, n, alternative="greater").proportion_ci(confidence_level=confidence, method="exact")
    assert hi2 == 1.0 and lo2 == pytest.approx(ci2.low, abs=1e-12)


def test_clopper_pearson_zero_failures_in_59_closed_form():
    # k = 0: the bound solves (1 - p)^n = alpha (one-sided) or alpha / 2 (two-sided)
    assert S.clopper_pearson(0, 59, 0.95, sided="upper")[2] == pytest.approx(1 - 0.05 ** (1 / 59), rel=1e-10)
    assert S.clopper_pearson(0, 59, 0.95)[2] == pytest.approx(1 - 0.025 ** (1 / 59), rel=1e-10)
    assert S.clopper_pearson(0, 59, 0.95, sided="upper")[2] == pytest.approx(0.049508, abs=1e-6)
    assert S.clopper_pearson(0, 59, 0.95)[2] == pytest.approx(0.060609, abs=1e-6)


def test_clopper_pearson_edges():
    assert S.clopper_pearson(0, 20)[1] == 0.0
    assert S.clopper_pearson(20, 20)[2] == 1.0
    p, lo, hi = S.clopper_pearson(0, 0)
    assert math.isnan(p) and (lo, hi) == (0.0, 1.0)
    for bad in [(-1, 5), (6, 5), (1, -1)]:
        with pytest.raises(ValueError):
            S.clopper_pearson(*bad)
    with pytest.raises(ValueError):
        S.clopper_pearson(1, 5, confidence=1.0)


# --------------------------------------------------------------------------- Wilks


def test_wilks_runs_known_values():
    assert S.wilks_runs(0.95, 0.95) == 59
    assert S.wilks_runs(0.95, 0.95, two_sided=True) == 93
    # one-sided, higher orders (Guba et al. 2003, table 1): order 2 -> 93, order 3 -> 124
    assert S.wilks_runs(0.95, 0.95, order=2) == 93
    assert S.wilks_runs(0.95, 0.95, order=3) == 124
    assert S.wilks_runs(0.95, 0.95, order=2, two_sided=True) == 153
    assert S.wilks_runs(0.99, 0.95) == 299
    assert S.wilks_runs(0.95, 0.99) == 90


@pytest.mark.parametrize("order,two_sided", [(1, False), (2, False), (3, False), (1, True), (2, True)])
def test_wilks_runs_is_smallest_by_the_binomial_sum(order, two_sided):
    # independent: the explicit binomial sum of the formula, evaluated by brute force over n
    g, b = 0.95, 0.95
    k = 2 * order if two_sided else order

    def conf(n):
        return 1.0 - sum(comb(n, j, exact=True) * (1 - g) ** j * g ** (n - j) for j in range(k))

    n = S.wilks_runs(g, b, order, two_sided)
    assert conf(n) >= b > conf(n - 1)
    assert S.wilks_confidence(n, g, order, two_sided) == pytest.approx(conf(n), abs=1e-12)


def test_wilks_first_order_closed_form():
    for g, b in [(0.9, 0.9), (0.95, 0.95), (0.99, 0.99), (0.9, 0.99)]:
        assert S.wilks_runs(g, b) == math.ceil(math.log(1 - b) / math.log(g))


def test_wilks_bound_order_statistics():
    x = np.arange(100.0)[::-1]  # 99 .. 0, unsorted on purpose
    b = S.wilks_bound(x, 0.95, 0.95)
    assert b.ok and b.value == 99.0 and b.rank == 100 and b.n_needed == 59
    b2 = S.wilks_bound(x, 0.95, 0.95, order=2)
    assert b2.value == 98.0 and b2.n_needed == 93
    lo = S.wilks_bound(x, 0.95, 0.95, side="lower")
    assert lo.value == 0.0
    two = S.wilks_bound(x, 0.95, 0.95, two_sided=True)
    assert (two.lo, two.hi) == (0.0, 99.0) and two.n_needed == 93
    # the largest admissible order for n = 100 at 95/95 is 2 (order 3 needs 124)
    best = S.wilks_bound(x, 0.95, 0.95, order=None)
    assert best.order == 2 and best.value == 98.0
    assert best.achieved == pytest.approx(S.wilks_confidence(100, 0.95, 2))


def test_wilks_bound_too_few_runs_and_inf():
    b = S.wilks_bound(np.arange(58.0), 0.95, 0.95)
    assert b.value is None and not b.ok and b.n_needed == 59 and b.n == 58
    assert b.achieved == pytest.approx(1 - 0.95 ** 58)
    # NaN dropped (n counts values), inf kept: a case that never settled is beyond the bound
    x = np.r_[np.arange(60.0), np.nan, np.inf]
    b = S.wilks_bound(x)
    assert b.n == 61 and b.value == math.inf
    assert S.wilks_bound([], order=None).value is None


def test_wilks_bound_coverage_by_simulation():
    # 59 runs, first order: the max exceeds the 95 % quantile of U(0, 1) in >= 95 % of campaigns
    rng = np.random.default_rng(5)
    maxima = rng.random((4000, 59)).max(axis=1)
    frac = np.mean(maxima >= 0.95)
    assert frac == pytest.approx(1 - 0.95 ** 59, abs=4 * math.sqrt(0.05 * 0.95 / 4000))


# --------------------------------------------------------------------------- bootstrap and mean


def test_percentile_ci_deterministic_and_consistent():
    x = np.random.default_rng(3).normal(size=80)
    a = S.percentile_ci(x, 50, seed=7)
    assert a == S.percentile_ci(x, 50, seed=7)
    assert a != S.percentile_ci(x, 50, seed=8)
    assert a[0] == pytest.approx(np.median(x))
    assert a[1] <= a[0] <= a[2]
    # one q alone equals the same q asked among others (shared resamples)
    many = S.bootstrap_percentiles(x, [5, 50, 95], seed=7)
    assert many[1] == a
    # NaN ignored
    assert S.percentile_ci(np.r_[x, np.nan], 50, seed=7) == a


def test_percentile_ci_edges():
    assert all(math.isnan(v) for v in S.percentile_ci([], 50))
    assert S.percentile_ci([2.5], 95) == (2.5, 2.5, 2.5)
    assert S.percentile_ci([1.0] * 10, 50) == (1.0, 1.0, 1.0)


def test_bootstrap_ci_of_median_covers_about_95_percent():
    # R seeded repetitions of n = 60 draws of N(0, 1); K = the number of 95 % intervals covering the
    # true median 0 is Binomial(R, c), c the true coverage.  The percentile bootstrap of a median
    # slightly under-covers at this n (the median's resampling distribution is discrete: c is about
    # 0.93-0.94), so the claim tested is c in [0.925, 0.975]: the exact 99.9 % Clopper-Pearson
    # interval of K / R must meet that band (a false alarm rate below 0.1 % if the claim holds).
    # With R = 1000 that interval is +-0.025 wide: a 90 % interval (c ~ 0.89, e.g. alpha used for
    # alpha / 2) fails it.  A too wide interval (99 %: c ~ 0.98) is caught by the width: the mean
    # width must be within 10 % of the asymptotic 2 z_0.975 sqrt(pi / 2) / sqrt(n) (the median's
    # standard error for N(0, 1)); measured 0.97 of it, a 99 % interval gives 1.25, a 90 % one 0.82.
    R, n = 1000, 60
    rng = np.random.default_rng(2024)
    hits = 0
    widths = []
    for r in range(R):
        x = rng.normal(size=n)
        _, lo, hi = S.percentile_ci(x, 50, confidence=0.95, n_boot=400, seed=r)
        hits += lo <= 0.0 <= hi
        widths.append(hi - lo)
    ci = sps.binomtest(hits, R).proportion_ci(confidence_level=0.999, method="exact")
    assert ci.high >= 0.925 and ci.low <= 0.975, (hits / R, ci)
    ref = 2.0 * sps.norm.ppf(0.975) * math.sqrt(math.pi / 2.0) / math.sqrt(n)
    assert np.mean(widths) == pytest.approx(ref, rel=0.10)


def test_mean_ci_t_interval():
    x = np.array([1.0, 2.0, 4.0, 7.0])
    m, lo, hi = S.mean_ci(x, 0.95)
    half = 3.182446305284263 * np.std(x, ddof=1) / 2.0  # t_{0.975, 3}
    assert m == 3.5 and lo == pytest.approx(3.5 - half) and hi == pytest.approx(3.5 + half)
    ref = sps.ttest_1samp(x, 0.0).confidence_interval(0.95)
    assert (lo, hi) == pytest.approx((ref.low, ref.high))
    m, lo, hi = S.mean_ci([5.0])
    assert m == 5.0 and math.isnan(lo) and math.isnan(hi)


# --------------------------------------------------------------------------- envelope, ecdf, spearman


def test_envelope_hand_built():
    # three runs on t = 0..4; the third stops after t = 1 (diverged)
    t = np.arange(5.0)
    runs_t = [t, t, t[:2]]
    runs_v = [np.array([0.0, 1, 2, 3, 4]), np.array([10.0, 11, 12, 13, 14]), np.array([20.0, 21])]
    env = S.envelope(runs_t, runs_v, percentiles=(0, 50, 100))
    np.testing.assert_array_equal(env.t, t)
    np.testing.assert_array_equal(env.n_runs, [3, 3, 2, 2, 2])
    np.testing.assert_array_equal(env.curves[50.0], [10, 11, 7, 8, 9])   # median of 3, then mean of 2
    np.testing.assert_array_equal(env.curves[0.0], [0, 1, 2, 3, 4])
    np.testing.assert_array_equal(env.curves[100.0], [20, 21, 12, 13, 14])
    # percentile with interpolation, checked against numpy on the first column
    env5 = S.envelope(runs_t, runs_v)
    assert env5.curves[5.0][0] == pytest.approx(np.percentile([0, 10, 20], 5))
    # NaN inside a run: missing there only
    v = [np.array([0.0, np.nan, 2.0]), np.array([1.0, 1.0, 1.0])]
    e = S.envelope([t[:3], t[:3]], v, (50,))
    np.testing.assert_array_equal(e.n_runs, [2, 1, 2])
    np.testing.assert_array_equal(e.curves[50.0], [0.5, 1.0, 1.5])


def test_envelope_union_grid_and_errors():
    e = S.envelope([[0.0, 2.0], [1.0]], [[1.0, 3.0], [5.0]], (50,))
    np.testing.assert_array_equal(e.t, [0, 1, 2])
    np.testing.assert_array_equal(e.curves[50.0], [1, 5, 3])
    np.testing.assert_array_equal(e.n_runs, [1, 1, 1])
    with pytest.raises(ValueError):
        S.envelope([[0.0, 1.0]], [[1.0]])
    empty = S.envelope([], [])
    assert empty.t.size == 0


def test_envelope_blocks_equal_one_pass(monkeypatch):
    rng = np.random.default_rng(0)
    t = np.arange(50.0)
    ts = [t[: rng.integers(10, 51)] for _ in range(7)]
    vs = [rng.normal(size=x.size) for x in ts]
    full = S.envelope(ts, vs)
    monkeypatch.setattr(S, "_BOOT_BLOCK", 7 * 3)  # 3 time columns per block
    blocked = S.envelope(ts, vs)
    for p in full.curves:
        np.testing.assert_array_equal(full.curves[p], blocked.curves[p])
    np.testing.assert_array_equal(full.n_runs, blocked.n_runs)


def test_ecdf():
    x, f = S.ecdf([3.0, np.nan, 1.0, np.inf, 2.0])
    np.testing.assert_array_equal(x, [1, 2, 3, np.inf])
    np.testing.assert_array_equal(f, [0.25, 0.5, 0.75, 1.0])
    x, f = S.ecdf([])
    assert x.size == 0 and f.size == 0


def test_rank_correlations_monotone_and_skips():
    rng = np.random.default_rng(1)
    n = 50
    a = rng.normal(size=n)
    cols = {
        "draw.a": a,
        "draw.noise": rng.normal(size=n),
        "draw.const": np.full(n, 2.0),
        "draw.choice": np.array(["x", "y"] * (n // 2)),
        "up": np.exp(a),             # monotone increasing in a: rho = 1
        "down": -a ** 3,             # monotone decreasing: rho = -1
        "flag": (a > 0),             # bool as 0/1
    }
    cols["up"][3] = np.nan           # NaN-safe: the pair drops that case
    res = S.rank_correlations(cols, ["draw.a", "draw.noise", "draw.const", "draw.choice", "draw.absent"],
                              ["up", "down", "flag"])
    got = {(r.metric, r.draw): r for r in res}
    assert ("up", "draw.const") not in got and ("up", "draw.choice") not in got
    assert got[("up", "draw.a")].rho == pytest.approx(1.0) and got[("up", "draw.a")].n == n - 1
    assert got[("down", "draw.a")].rho == pytest.approx(-1.0)
    assert got[("up", "draw.a")].p < 1e-10
    assert got[("flag", "draw.a")].rho > 0.8
    assert abs(got[("up", "draw.noise")].rho) < 0.4
    ref = sps.spearmanr(cols["draw.noise"], -a ** 3)
    assert got[("down", "draw.noise")].rho == pytest.approx(ref.statistic)
    assert got[("down", "draw.noise")].p == pytest.approx(ref.pvalue)
    # order: metric, then draw as given
    assert [(r.metric, r.draw) for r in res][:2] == [("up", "draw.a"), ("up", "draw.noise")]
