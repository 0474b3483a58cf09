"""Check 5: the generated Kepler solver against a bracketing root finder (000 eq. 32)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def test_kepler_against_brentq_on_a_grid(model):
    worst = 0.0
    for e in np.linspace(0.0, 0.99, 34):
        for M in np.linspace(0.0, 2 * np.pi, 61):
            E_ref = brentq(lambda E, M=M, e=e: E - e * np.sin(E) - M, M - 1.0, M + 1.0, xtol=1e-15, rtol=1e-15)
            E = float(model.kepler(M, e)[0][0])
            worst = max(worst, abs(E - E_ref))
    assert worst < 1e-12, f"worst |E - E_ref| = {worst:.2e} rad"


def test_kepler_is_continuous_across_revolutions(model):
    """M outside [0, 2 pi) (long runs): E - e sin E = M still holds and E is monotone."""
    e = 0.7
    Ms = np.linspace(-30, 30, 2001)
    E = np.array([model.kepler(M, e)[0][0] for M in Ms])
    assert np.abs(E - e * np.sin(E) - Ms).max() < 1e-12
    assert np.all(np.diff(E) > 0)
