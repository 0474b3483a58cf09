"""The noise inputs ``w`` of every step: standard-normal samples as a pure function of
(seed, step, index), drawn in C by the simulation loops (``runtime/csrc/rpo_noise.h``).

Sample ``i`` of global step ``g`` of a run with seed ``s``: SplitMix64 from a key made of the
seed, at counters ``2 (g P + i // 2)`` and ``+1`` (``P = ceil(nw / 2)``), turned into a normal pair
by Box-Muller (cos for even ``i``, sin for odd ``i``).  A run's noise is therefore the same
whatever the chunk size, the batch and lane it runs in, the process or the machine, and step
``g``'s noise needs none of the steps before it.

:func:`noise` is the NumPy version of the same definition, used by the CasADi fallback backend
and by the tests as an independent check of the C code: its uniforms are bit-identical, its
normals agree to rounding (NumPy's log, sqrt and cos against rpo_math.h's).
"""

from __future__ import annotations

import numpy as np

from rpo.runtime.errors import ModelError

_M1, _M2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)
_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_SALT = np.uint64(0x5851F42D4C957F2D)
_MAX_SEED = 2**64 - 1


def _mix(z: np.ndarray) -> np.ndarray:
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


def check_seed(seed) -> int:
    """A seed as the loops take it: an integer in [0, 2**64 - 1], or a clear error."""
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
        raise ModelError(f"seed must be an integer in [0, 2**64 - 1], got {seed!r}")
    if not 0 <= int(seed) <= _MAX_SEED:
        raise ModelError(f"seed must be in [0, 2**64 - 1], got {seed}")
    return int(seed)


def key(seed: int) -> int:
    """The 64-bit noise key of a seed (``rpo_noise_key1`` in rpo_noise.h)."""
    with np.errstate(over="ignore"):
        z = np.array([check_seed(seed)], dtype=np.uint64)
        return int(_mix(_mix(z) ^ _SALT)[0])


def uniforms(k: int, counters: np.ndarray) -> np.ndarray:
    """The uniforms in (0, 1] at the given counters of key ``k``."""
    with np.errstate(over="ignore"):
        z = _mix(np.uint64(k) + np.asarray(counters, dtype=np.uint64) * _GAMMA)
    return ((z >> np.uint64(11)).astype(np.float64) + 1.0) * 2.0**-53


def noise(seed: int, g0: int, n: int, nw: int) -> np.ndarray:
    """w of steps g0 .. g0 + n - 1, shape (n, nw)."""
    pairs = (nw + 1) // 2
    g = np.arange(g0, g0 + n, dtype=np.uint64)[:, None]
    j = np.arange(pairs, dtype=np.uint64)[None, :]
    c = np.uint64(2) * (g * np.uint64(pairs) + j)
    k = key(seed)
    u1, u2 = uniforms(k, c), uniforms(k, c + np.uint64(1))
    r = np.sqrt(-2.0 * np.log(u1))
    theta = 6.283185307179586 * (u2 - 2.0**-53)
    out = np.empty((n, 2 * pairs))
    out[:, 0::2] = r * np.cos(theta)
    out[:, 1::2] = r * np.sin(theta)
    return out[:, :nw]
