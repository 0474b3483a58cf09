"""002: proof plans of the inequality claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ..certify import Coordinate, Plan, Region
from ..core import Statement
from .plans_v1 import PLANS as _PLANS_V1


def _v2_lemma1(st: Statement) -> Plan:
    """Lemma 1 (mu = 1) summed over the three axes: kappa_1 > 0 factored out, the rest on the box."""
    chi = sorted((s for s in st.free_symbols() if s.name.startswith("chi1_")), key=lambda s: s.name)
    (kappa,) = [s for s in st.free_symbols() if s.name == "kappa_1"]
    reg = Region(tuple(Coordinate(c, -4.0, 4.0) for c in chi) + (Coordinate(kappa, 0.01, 5.0, "1/s"),),
                 describe="the search domain")

    def reduce(g):
        rest = sp.expand(g / kappa)
        return kappa, rest

    return Plan([reg], "chi1_i in [-4, 4] (i = 1..3), kappa_1 in [0.01, 5] 1/s", reduce=reduce)


PLANS = {"c002.V2.lemma1": _v2_lemma1, **_PLANS_V1}
