"""Seeds and designs of a campaign: which uniforms each run's dispersions get.

Everything descends from the campaign's ``seed`` through :class:`numpy.random.SeedSequence`, with
a *stream id* per dispersed key (the first 8 bytes of sha256 of the key: the same in every
process and Python version, unlike ``hash``):

* ``sampling = "random"``: the uniforms of key ``k`` in run ``i`` are the 64-bit words of
  ``SeedSequence(seed, spawn_key=(id(k), i))`` (top 53 bits, centred in their interval).  Run
  ``i``'s draws need nothing of the other runs, adding a dispersion or more runs leaves every
  other draw unchanged, and a case can be drawn alone (``rpo run --campaign DIR --case i``).
* ``sampling = "lhs"``: a Latin hypercube per key (``scipy.stats.qmc.LatinHypercube`` seeded from
  ``SeedSequence(seed, spawn_key=(id(k),))``): each key's marginal is stratified into ``runs``
  equal-probability strata, and keys are paired at random.  Adding a dispersion leaves the others
  unchanged; changing ``runs`` changes the design (a hypercube is made for its size).
* ``sampling = "sobol"``: one scrambled Sobol sequence over all the keys' dimensions, in the order
  the keys appear in the campaign file (a low-discrepancy design is joint by nature, so a key
  added at the end leaves the earlier keys' draws unchanged; one inserted before them does not).
  ``runs`` should be a power of 2 for the sequence's balance (scipy warns otherwise; rpo accepts it).
* ``sampling = "sobol-indices"``: a Saltelli design for Sobol indices (:mod:`.sobol`), in blocks of
  d + 2 runs (d dispersions, each one group whatever its dimension): row j of a scrambled Sobol
  sequence over twice the keys' dimensions gives A_j (its first half) and B_j (its second half);
  run (d + 2) j flies A_j, run (d + 2) j + 1 flies B_j, run (d + 2) j + 2 + i flies A_j with
  dispersion i's uniforms from B_j.  ``runs`` must be a multiple of d + 2 (best: a power of 2
  times d + 2).  A case's uniforms depend on the seed and its number only (a Sobol sequence's
  first points do not depend on its length), so runs can be drawn one by one and resumed.

The run's own noise seed (random torques, sensor noise: :mod:`rpo.runtime.run.noise`) is the 64-bit
state of ``SeedSequence(seed, spawn_key=(NOISE_STREAM, i))``.
"""

from __future__ import annotations

import hashlib
import warnings
from collections.abc import Sequence

import numpy as np
from scipy.stats import qmc

from rpo.runtime.campaign.dispersions import Dispersion

SAMPLINGS = ("random", "lhs", "sobol", "sobol-indices")
#: Stream id of the runs' noise seeds: a fixed constant ("noise"); a key's sha256-derived id equals
#: it with probability 2**-64.
NOISE_STREAM = 0x6E6F697365  # "noise"
#: Uniforms are kept inside (0, 1): the inverse CDFs of unbounded distributions are infinite at 0 and 1.
U_MIN = 2.0**-53


def stream_id(key: str) -> int:
    """The stream id of a dispersed key (64 bits of sha256, stable everywhere)."""
    return int.from_bytes(hashlib.sha256(key.encode()).digest()[:8], "little")


def run_seed(seed: int, case: int) -> int:
    """Run ``case``'s noise seed, an integer in [0, 2**64)."""
    state = np.random.SeedSequence(seed, spawn_key=(NOISE_STREAM, case)).generate_state(1, np.uint64)
    return int(state[0])


def _uniforms(seed: int, stream: int, case: int, n: int) -> np.ndarray:
    """n uniforms in (0, 1) of one stream and run: the 64-bit words of
    ``SeedSequence(seed, spawn_key=(stream, case))`` (its output is a hash of the key, uniformly
    distributed), their top 53 bits plus one half, times 2**-53."""
    words = np.random.SeedSequence(seed, spawn_key=(stream, case)).generate_state(n, np.uint64)
    return ((words >> np.uint64(11)).astype(np.float64) + 0.5) * 2.0**-53


# SeedSequence's constants (numpy/random/bit_generator.pyx): its hash of the entropy into a pool of
# four 32-bit words and of the pool into the output words
_POOL = 4
_INIT_A, _MULT_A, _INIT_B, _MULT_B = 0x43B0D7E5, 0x931E8875, 0x8B51F9DD, 0x58F38DED
_MIX_L, _MIX_R = np.uint32(0xCA01F9DD), np.uint32(0x4973F715)
_M32 = 0xFFFFFFFF
_SHIFT = np.uint32(16)


def _words32(n: int) -> list[int]:
    """An integer's 32-bit words, least significant first (SeedSequence's coercion of an int)."""
    out = [n & _M32]
    n >>= 32
    while n:
        out.append(n & _M32)
        n >>= 32
    return out


def _hash_consts(init: int, mult: int, n: int) -> np.ndarray:
    """The hash constant before each of n hash steps and after the last: init * mult**i mod 2**32."""
    out, h = [], init
    for _ in range(n + 1):
        out.append(h)
        h = (h * mult) & _M32
    return np.array(out, np.uint32)


def seed_words(seed: int, spawn_keys: Sequence[tuple[int, ...]], n: int) -> np.ndarray:
    """``SeedSequence(seed, spawn_key=k).generate_state(n, np.uint64)`` for every (non-empty) key
    ``k``, as one (len(spawn_keys), n) array: the same algorithm on arrays of the keys, bit for bit
    (tests/test_campaign.py compares it with numpy's), a batch of runs' words at once instead of
    one SeedSequence object per key and run."""
    run = _words32(int(seed))
    run = run + [0] * (_POOL - len(run))  # a spawned sequence pads its entropy to the pool size
    words: dict[int, list[int]] = {}  # a batch's keys repeat their streams and cases: split each once
    ent = []
    for k in spawn_keys:
        e = list(run)
        for x in k:
            w = words.get(x)
            if w is None:
                w = words[x] = _words32(int(x))
            e += w
        ent.append(e)
    out = np.empty((len(ent), n), np.uint64)
    groups: dict[int, list[int]] = {}
    for i, e in enumerate(ent):
        groups.setdefault(len(e), []).append(i)
    n32 = 2 * n
    hb = _hash_consts(_INIT_B, _MULT_B, n32)
    for length, rows in groups.items():
        E = np.array([ent[i] for i in rows], np.uint32).reshape(len(rows), length)
        ha = _hash_consts(_INIT_A, _MULT_A, _POOL * _POOL + (length - _POOL) * _POOL)
        step = iter(range(ha.size - 1))

        def hashmix(v: np.ndarray) -> np.ndarray:
            i = next(step)  # noqa: B023 (the group's own constants, used before the next group)
            v = (v ^ ha[i]) * ha[i + 1]  # noqa: B023
            return v ^ (v >> _SHIFT)

        def mix(x: np.ndarray, y: np.ndarray) -> np.ndarray:
            r: np.ndarray = _MIX_L * x - _MIX_R * y
            return r ^ (r >> _SHIFT)

        pool = [hashmix(E[:, i]) for i in range(_POOL)]
        for src in range(_POOL):
            for dst in range(_POOL):
                if src != dst:
                    pool[dst] = mix(pool[dst], hashmix(pool[src]))
        for src in range(_POOL, length):
            for dst in range(_POOL):
                pool[dst] = mix(pool[dst], hashmix(E[:, src]))
        v = np.stack(pool, axis=1)[:, np.arange(n32) % _POOL]
        v = (v ^ hb[:n32]) * hb[1:]
        v ^= v >> _SHIFT
        out[rows] = np.ascontiguousarray(v).astype("<u4").view("<u8").astype(np.uint64)
    return out


def run_seeds(seed: int, cases: Sequence[int]) -> list[int]:
    """:func:`run_seed` of each case, at once."""
    return [int(w) for w in seed_words(seed, [(NOISE_STREAM, int(c)) for c in cases], 1)[:, 0]]


def noise_case(sampling: str, dispersions: int, case: int) -> int:
    """The case whose noise seed (:func:`run_seed`) run ``case`` flies with: itself, except in a
    Saltelli design (``sobol-indices``, blocks of ``dispersions`` + 2 runs), where every run of a
    block flies its block's noise.  Why: the indices estimate what each dispersion does by comparing
    runs of one block that differ only in that dispersion; with noise drawn afresh per run the noise
    would differ too, and count as an interaction of every dispersion (each total index near 1)."""
    return case // (dispersions + 2) if sampling == "sobol-indices" else case


def _clip(u: np.ndarray) -> np.ndarray:
    return np.clip(u, U_MIN, 1.0 - U_MIN)


class Design:
    """The uniforms of every run of a campaign: :meth:`uniforms` ``(case) -> {key: u}``."""

    def __init__(self, sampling: str, seed: int, runs: int, dispersions: Sequence[Dispersion]):
        if sampling not in SAMPLINGS:
            raise ValueError(f"sampling must be one of {', '.join(SAMPLINGS)}")
        self.sampling, self.seed, self.runs = sampling, int(seed), int(runs)
        self.dispersions = list(dispersions)
        self._table: dict[str, np.ndarray] | None = None
        self._ids = {d.key: stream_id(d.key) for d in self.dispersions}

    def _build(self) -> dict[str, np.ndarray]:
        """The whole design (lhs, sobol, sobol-indices): key -> (runs, dims) uniforms."""
        out: dict[str, np.ndarray] = {}
        if self.sampling == "sobol-indices":
            return self._saltelli()
        if self.sampling == "lhs":
            for d in self.dispersions:
                rng = np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=(stream_id(d.key),)))
                out[d.key] = _clip(qmc.LatinHypercube(d=d.dims, seed=rng).random(self.runs))
        else:
            total = sum(d.dims for d in self.dispersions)
            if total:
                rng = np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=(stream_id("sobol"),)))
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)  # runs not a power of 2: accepted, see above
                    u = qmc.Sobol(d=total, scramble=True, seed=rng).random(self.runs)
                col = 0
                for d in self.dispersions:
                    out[d.key] = _clip(u[:, col: col + d.dims])
                    col += d.dims
        return out

    def _saltelli(self) -> dict[str, np.ndarray]:
        """The Saltelli design (module docstring): key -> (runs, dims) uniforms."""
        d = len(self.dispersions)
        size = d + 2
        if self.runs % size:
            raise ValueError(f"a sobol-indices design of {d} dispersions needs runs in blocks of {size}")
        total = sum(x.dims for x in self.dispersions)
        blocks = self.runs // size
        rng = np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=(stream_id("sobol-indices"),)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # blocks not a power of 2: accepted, see above
            base = _clip(qmc.Sobol(d=2 * total, scramble=True, seed=rng).random(blocks))
        A, B = base[:, :total], base[:, total:]
        rows = np.repeat(A[:, None, :], size, axis=1)  # (blocks, size, total): A everywhere ...
        rows[:, 1] = B                                 # ... B in the second run ...
        col = 0
        for i, x in enumerate(self.dispersions):       # ... and AB_i: group i's columns from B
            rows[:, 2 + i, col: col + x.dims] = B[:, col: col + x.dims]
            col += x.dims
        flat = rows.reshape(self.runs, total)
        out, col = {}, 0
        for x in self.dispersions:
            out[x.key] = flat[:, col: col + x.dims]
            col += x.dims
        return out

    def uniforms(self, case: int) -> dict[str, np.ndarray]:
        """key -> the uniforms (dims,) of run ``case``."""
        if not 0 <= case < self.runs:
            raise IndexError(f"case {case} is not in this campaign (0 .. {self.runs - 1})")
        if self.sampling == "random":
            return {d.key: _uniforms(self.seed, self._ids[d.key], case, d.dims) for d in self.dispersions}
        if self._table is None:
            self._table = self._build()
        return {d.key: self._table[d.key][case] for d in self.dispersions}

    def uniforms_many(self, cases: Sequence[int]) -> list[dict[str, np.ndarray]]:
        """:meth:`uniforms` of each of ``cases`` (the same values; a random design's words for all
        the cases and keys at once)."""
        if self.sampling != "random" or not self.dispersions or not cases:
            return [self.uniforms(c) for c in cases]
        for case in cases:
            if not 0 <= case < self.runs:
                raise IndexError(f"case {case} is not in this campaign (0 .. {self.runs - 1})")
        dims = max(d.dims for d in self.dispersions)
        keys = [(self._ids[d.key], int(c)) for c in cases for d in self.dispersions]
        u = ((seed_words(self.seed, keys, dims) >> np.uint64(11)).astype(np.float64) + 0.5) * 2.0**-53
        nd = len(self.dispersions)
        return [{d.key: u[i * nd + j, : d.dims] for j, d in enumerate(self.dispersions)} for i in range(len(cases))]
