"""Special functions that stay opaque in SymPy and have a direct translation.

``Step(x)`` is the unit step (1 for x >= 0, else 0).  SymPy's own Heaviside analyses its
argument on construction (``as_real_imag``), which takes minutes on the plant's expressions;
this one does nothing on construction.  Its derivative is 0 (almost everywhere), which is what
the generated Jacobians and the Lyapunov checks use.
"""

from __future__ import annotations

import sympy as sp


class Step(sp.Function):
    """Unit step: 1 for x >= 0, 0 for x < 0."""

    nargs = 1

    def fdiff(self, argindex=1):
        return sp.S.Zero

    def _eval_is_real(self):
        return True
