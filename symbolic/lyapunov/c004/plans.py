"""004: proof plans of the inequality claims (certified domains; see ``symbolic/lyapunov/certify``)."""

from __future__ import annotations

import sympy as sp

from ..certify import Coordinate, Plan, Region
from ..core import Statement


def _by_name(st: Statement) -> dict:
    """The statement's free symbols by name."""
    return {s.name: s for s in st.free_symbols()}


def _vec(sym: dict, name: str, n: int = 3) -> list:
    return [sym[f"{name}_{k}"] for k in range(1, n + 1)]


def _ordered(gains: list, k: int, tag: str, lo: float, hi: float, unit: str):
    """Domain map for the gains ``gains`` (each in [lo, hi]) where gains[k] is the smallest:
    gains[k] = t, gains[i] = t + a_i with a_i >= 0 and t + a_i <= hi.  Min(gains) then simplifies to t
    exactly (SymPy knows a_i >= 0), which puts the set where the gap is 0 (a gain equal to the minimum)
    on the face a_i = 0 instead of inside the box.  Returns (coordinates, subs, hypotheses)."""
    t = sp.Symbol(f"{tag}_min", positive=True)
    coords, subs, hyps = [Coordinate(t, lo, hi, unit)], {gains[k]: t}, []
    for i, g in enumerate(gains):
        if i != k:
            a = sp.Symbol(f"{tag}_a{i + 1}", nonnegative=True)
            coords.append(Coordinate(a, 0.0, hi - lo, unit))
            subs[g] = t + a
            hyps.append(hi - t - a)
    return coords, subs, hyps


# --------------------------------------------------------------------------- theorem (section 4)

def _vs_bound(st: Statement) -> Plan:
    """Eq. 39, last line, on s1 = s2 = 0: one region per choice of the smallest gain of Lambda1 and of
    Lambda2 (nine in all, they cover the gain box); in each, the expanded gap is a sum of monomials with
    nonnegative coefficients in even powers of r_e, sigma_e (the omega terms cancel: r^T S(w) r = 0, and
    sigma^T G(sigma) = (1 + |sigma|^2)/4 sigma^T), so the natural enclosure closes it."""
    sym = _by_name(st)
    r, sig, w = _vec(sym, "r_e"), _vec(sym, "sigma_e"), _vec(sym, "omega")
    l1, l2 = _vec(sym, "lambda1"), _vec(sym, "lambda2")
    base = ([Coordinate(x, -40.0, 40.0, "m") for x in r] + [Coordinate(x, -1.0, 1.0) for x in sig]
            + [Coordinate(x, -0.1, 0.1, "rad/s") for x in w])
    ball = 1 - sum(x**2 for x in sig)
    regions = []
    for i in range(3):
        c1, s1, h1 = _ordered(l1, i, "lambda1", 0.01, 1.0, "1/s")
        for j in range(3):
            c2, s2, h2 = _ordered(l2, j, "lambda2", 0.01, 1.0, "1/s")
            regions.append(Region(tuple(base + c1 + c2), {**s1, **s2}, (ball, *h1, *h2),
                                  describe=f"lambda1_{i + 1} = min Lambda1, lambda2_{j + 1} = min Lambda2"))
    return Plan(regions, "r_e in [-40, 40]^3 m, |sigma_e| <= 1, omega in [-0.1, 0.1]^3 rad/s, "
                         "lambda1_i, lambda2_i in [0.01, 1] 1/s (the search domain)",
                reduce=sp.expand)


PLANS = {"c004.theorem.Vs_bound": _vs_bound}
