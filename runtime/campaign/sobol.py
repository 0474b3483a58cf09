"""Variance-based global sensitivity: first- and total-order Sobol indices of a Saltelli design.

A campaign with ``sampling = "sobol-indices"`` (:mod:`.sampling`) flies blocks of d + 2 runs, d the
number of dispersions: run 0 of block j takes the uniforms of row j of a matrix A, run 1 those of
row j of B, and run 2 + i those of A with dispersion i's uniforms from B (the matrix AB_i).  Each
dispersion is one *group* (a vector, a rotation, an inertia: all of its uniforms move together),
so its indices are group indices: the share of the output's variance due to that dispersion
alone (first order S_i) and with all its interactions (total order ST_i).

The estimators are those of ``scipy.stats.sobol_indices`` (``method="saltelli_2010"``; Saltelli et
al., Comput. Phys. Commun. 181, 2010, Table 2 (b) and (f)), over the outputs centred on their mean:

    V    = var(f_A, f_B)                               (A and B pooled)
    S_i  = mean(f_B (f_ABi - f_A)) / V
    ST_i = mean((f_A - f_ABi)^2) / (2 V)

computed here rather than by calling SciPy because SciPy asks for a power-of-2 number of blocks
with every output present, and a campaign loses the blocks that hold an invalid, diverged or
unmeasured run (tests/test_campaign_sobol.py checks both give the same numbers on a complete
design).  The confidence intervals are percentile bootstraps over the blocks (a block is resampled
whole: its runs share A and B), from a fixed seed so a report's bytes do not change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

#: Resamples evaluated at once by the bootstrap (bounds its memory: chunk x blocks x (d + 2) floats).
_CHUNK = 64


def block_size(groups: int) -> int:
    """Runs per block of a Saltelli design of ``groups`` dispersions: A, B and one AB_i each."""
    return groups + 2


def split_blocks(cases: ArrayLike, values: ArrayLike, groups: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(f_A (n,), f_B (n,), f_AB (groups, n)) of the complete blocks: those whose every run is among
    ``cases`` with a finite value (``values[i]`` is case ``cases[i]``'s output)."""
    size = block_size(groups)
    cases = np.asarray(cases, dtype=np.int64)
    values = np.asarray(values, dtype=float)
    n_blocks = int(cases.max()) // size + 1 if cases.size else 0
    flat = np.full(n_blocks * size, np.nan)
    flat[cases] = values
    table = flat.reshape(n_blocks, size)
    whole = np.all(np.isfinite(table), axis=1)
    t = table[whole]
    return t[:, 0], t[:, 1], t[:, 2:].T.copy()


def indices(f_A: np.ndarray, f_B: np.ndarray, f_AB: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(S (groups,), ST (groups,)) by Saltelli 2010's estimators; over the last axis (leading axes of
    ``f_A`` / ``f_B`` and the second-to-last of ``f_AB`` are resamples).  A constant output has
    indices 0 (as SciPy)."""
    mean = 0.5 * (f_A.mean(axis=-1) + f_B.mean(axis=-1))
    a, b = f_A - mean[..., None], f_B - mean[..., None]
    ab = f_AB - mean[..., None, None]
    var = 0.5 * ((a**2).mean(axis=-1) + (b**2).mean(axis=-1)) - (0.5 * (a.mean(axis=-1) + b.mean(axis=-1))) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.mean(b[..., None, :] * (ab - a[..., None, :]), axis=-1) / var[..., None]
        st = 0.5 * np.mean((a[..., None, :] - ab) ** 2, axis=-1) / var[..., None]
    s[~np.isfinite(s)] = 0.0
    st[~np.isfinite(st)] = 0.0
    return s, st


@dataclass(frozen=True)
class SobolIndices:
    """First (``first``) and total (``total``) order indices of each group, with their bootstrap
    intervals (``first_ci``, ``total_ci``: (groups, 2) low / high) over ``blocks`` complete blocks."""

    first: np.ndarray
    total: np.ndarray
    first_ci: np.ndarray
    total_ci: np.ndarray
    blocks: int


def sobol_indices(f_A: ArrayLike, f_B: ArrayLike, f_AB: ArrayLike, confidence: float = 0.95,
                  n_boot: int = 2000, seed: int = 0) -> SobolIndices:
    """The indices of the outputs of a Saltelli design and their percentile-bootstrap intervals at
    ``confidence`` (``n_boot`` resamples of the blocks drawn by ``numpy.random.default_rng(seed)``).
    Needs at least 2 blocks."""
    a, b, ab = np.asarray(f_A, float), np.asarray(f_B, float), np.asarray(f_AB, float)
    n = a.size
    if n < 2 or b.shape != a.shape or ab.ndim != 2 or ab.shape[1] != n:
        raise ValueError(f"sobol_indices: need f_A, f_B (n,) and f_AB (d, n) with n >= 2; got {a.shape}, "
                         f"{b.shape}, {ab.shape}")
    s, st = indices(a, b, ab)
    rng = np.random.default_rng(seed)
    boots_s, boots_t = [], []
    for start in range(0, n_boot, _CHUNK):
        idx = rng.integers(0, n, size=(min(_CHUNK, n_boot - start), n))
        bs, bt = indices(a[idx], b[idx], np.moveaxis(ab[:, idx], 0, 1))
        boots_s.append(bs)
        boots_t.append(bt)
    q = [100 * (1 - confidence) / 2, 100 * (1 + confidence) / 2]
    first_ci = np.percentile(np.concatenate(boots_s), q, axis=0).T
    total_ci = np.percentile(np.concatenate(boots_t), q, axis=0).T
    return SobolIndices(s, st, first_ci, total_ci, n)
