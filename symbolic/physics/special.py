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


class Fmax(sp.Function):
    """max(a, b), opaque: SymPy's ``Max`` sorts its arguments on construction (even unevaluated),
    which compares whole expression trees and takes minutes on the allocation's large arguments.
    Translated to ``fmax`` (CasADi) and ``numpy.maximum``."""

    nargs = 2

    def fdiff(self, argindex=1):
        a, b = self.args
        return Step(a - b) if argindex == 1 else 1 - Step(a - b)

    def _eval_is_real(self):
        return True


def fmax(*args):
    """max of several values as nested :class:`Fmax` (left to right)."""
    out = args[0]
    for a in args[1:]:
        out = Fmax(out, a)
    return out
