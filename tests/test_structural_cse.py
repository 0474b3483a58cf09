"""The NumPy reference's common-subexpression pass keeps every value (against plain lambdify)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from rpo.symbolic.codegen.structural_cse import structural_cse


def test_structural_cse_preserves_values_and_shares_nodes():
    x, y, q = sp.symbols("x y q", real=True)
    shared = sp.sin(x * y) + sp.exp(x)
    exprs = [shared**2 + shared, sp.Matrix([[shared * y, sp.Piecewise((shared, q < 0), (-shared, True))],
                                            [sp.Max(shared, y), sp.Abs(x - y)]])]
    subs, reduced = structural_cse(exprs)
    # the repeated node is named once (its own parts, repeated through it, too)
    named = dict(subs)
    assert [s for s, rhs in subs if sp.simplify(rhs.xreplace(named).xreplace(named) - shared) == 0] != []
    assert isinstance(reduced[1], sp.MatrixBase) and reduced[1].shape == (2, 2)
    fast = sp.lambdify([x, y, q], exprs, "numpy", cse=structural_cse)
    plain = sp.lambdify([x, y, q], exprs, "numpy", cse=False)
    rng = np.random.default_rng(0)
    for _ in range(50):
        a = rng.normal(size=3)
        for f, p in zip(fast(*a), plain(*a), strict=True):
            assert np.allclose(np.asarray(f, float), np.asarray(p, float), rtol=1e-15, atol=0)
