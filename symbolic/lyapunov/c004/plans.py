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


def _v_lower_bound(st: Statement) -> Plan:
    """The bound on V in the proof of Theorem 1: V1 + V2 - rhs is a sum of squares once J and the gains
    are written by a domain map.

    * J = lambda_J I + C C^T, C lower triangular (c_ii >= 0): every J - lambda_J I that is positive
      semidefinite has such a (Cholesky) factor, so every drawn point (lambda_J = min eig J) is covered;
      then s2^T J s2 - lambda_J |s2|^2 = |C^T s2|^2.  Bounds: lambda_min(J) >= 200 - 2*60 = 80 (Gershgorin)
      and <= 700; (C C^T)_ii = J_ii - lambda_J <= 620, so |c_ij| <= sqrt(620) < 25.
    * gamma = max gamma_i: one region per index k of the largest gain, gamma_k = G and gamma_i = G (1 - v_i)
      with v_i in [0, 0.99] (v_i = 1 - gamma_i/G <= 1 - 0.01/G); Max simplifies to G exactly (v_i >= 0), and
      z^2/(2 gamma_i) - z^2/(2 G) = z^2 v_i / (2 G (1 - v_i)) >= 0.

    The rewritten gap (checked to be identical) is a sum of such nonnegative terms: the natural enclosure
    closes it on one box per region."""
    sym = _by_name(st)
    s2 = _vec(sym, "s_2")
    lam = sym["lambda_J"]
    J = {(i, j): sym[f"J_{i}{j}"] for i in range(1, 4) for j in range(i, 4)}
    cd = [sp.Symbol(f"c_{i}{i}", nonnegative=True) for i in range(1, 4)]
    c21, c31, c32 = (sp.Symbol(f"c_{i}{j}", real=True) for i, j in ((2, 1), (3, 1), (3, 2)))
    C = sp.Matrix([[cd[0], 0, 0], [c21, cd[1], 0], [c31, c32, cd[2]]])
    CCt = C * C.T
    lam_c = sp.Symbol("lambda", positive=True)
    j_subs = {J[i, j]: CCt[i - 1, j - 1] + (lam_c if i == j else 0) for (i, j) in J}
    j_subs[lam] = lam_c
    j_coords = ([Coordinate(lam_c, 80.0, 700.0, "kg m^2")] + [Coordinate(c, 0.0, 25.0, "sqrt(kg) m") for c in cd]
                + [Coordinate(c, -25.0, 25.0, "sqrt(kg) m") for c in (c21, c31, c32)])
    Cts = C.T * sp.Matrix(s2)
    gam = [sym[f"gamma_{i}"] for i in range(1, 7)]
    # each gain's estimate errors (eqs. 23, 32); rho~_f is in V1 but not in the printed zeta
    zeta = {1: [sym["mtilde_Delta"]], 2: [], 3: [sym["rhotilde_m"]], 4: _vec(sym, "thetatilde_Delta", 6),
            5: [sym["rhotilde_tau"]], 6: [sym["rhotilde_J"]]}
    rf = sym["rhotilde_f"]
    other = ([Coordinate(x, -40.0, 40.0, "m") for x in _vec(sym, "r_e")]
             + [Coordinate(x, -2.0, 2.0, "m/s") for x in _vec(sym, "s_1")]
             + [Coordinate(x, -2.0, 2.0, "rad/s") for x in s2]
             + [Coordinate(x, -20.0, 20.0) for x in (*zeta[1], rf, *zeta[3], *zeta[5], *zeta[6])]
             + [Coordinate(x, -100.0, 100.0, "kg m^2") for x in zeta[4]]
             + [Coordinate(sym["k_0"], 0.01, 1.0, "N/m"), Coordinate(sym["m"], 20.0, 100.0, "kg")])
    G = sp.Symbol("gamma_max", positive=True)
    regions, targets = [], []
    for k in range(6):
        coords, subs, hyps = [Coordinate(G, 0.01, 1.0)], {gam[k]: G}, []
        target = sum(e**2 for e in Cts) / 2
        for i in range(6):
            if i == k:
                continue
            v = sp.Symbol(f"v_{i + 1}", nonnegative=True)
            coords.append(Coordinate(v, 0.0, 0.99))
            subs[gam[i]] = G * (1 - v)
            hyps.append(G * (1 - v) - sp.Rational(1, 100))
            target += sum(z**2 for z in zeta[i + 1]) * v / (2 * G * (1 - v))
        target += rf**2 / (2 * subs[gam[1]])
        regions.append(Region(tuple(other + j_coords + coords), {**j_subs, **subs}, tuple(hyps),
                              describe=f"gamma_{k + 1} = max gamma_i"))
        targets.append(target)

    def reduce(g):
        # the region is the one whose ratio coordinates v_i are those in g; return its sum of squares
        # (the certificate re-checks that the two are identical)
        used = {x for x in g.free_symbols if x.name.startswith("v_")}
        for reg, tgt in zip(regions, targets, strict=True):
            if used == {c.symbol for c in reg.coords if c.symbol.name.startswith("v_")}:
                return tgt
        raise ValueError("no region matches")

    return Plan(regions, "r_e in [-40, 40]^3 m, s1 in [-2, 2]^3 m/s, s2 in [-2, 2]^3 rad/s, m~, rho~_f, "
                         "rho~_m, rho~_tau, rho~_J in [-20, 20], theta~ in [-100, 100]^6 kg m^2, k0 in [0.01, 1] "
                         "N/m, m in [20, 100] kg, gamma_1..6 in [0.01, 1]; J = lambda_J I + C C^T with "
                         "lambda_J in [80, 700] kg m^2, C lower triangular, c_ii in [0, 25], |c_ij| <= 25 "
                         "(every J of the search domain with lambda_J = its least eigenvalue, and more: any "
                         "lambda_J <= min eig J)",
                reduce=reduce,
                note="Certified for every lambda_J with J - lambda_J I = C C^T (a lower bound on the least "
                     "eigenvalue), which contains the drawn lambda_J = min eig J of every diagonally dominant "
                     "J of the search domain (Cholesky factor of J - lambda_min I, bounds in the plan).")


# No plan yet for position.n1_bound, attitude.n2_bound, position.V1dot_bound, attitude.V2dot_bound and
# theorem.Vdot_bound: each rests on ||n|| <= rho ||w_t||^2, whose proof needs |R a| = |a| for R = R(sigma_e)
# and ||J_t^-1|| ||J_t|| from eigenvalues (neither is a syntactic cancellation the prover can use), and whose
# gap is 0 at w = w_e with a square root of a quartic there (no first- or second-order leaf closes it).
PLANS = {"c004.theorem.Vs_bound": _vs_bound, "c004.theorem.V_lower_bound": _v_lower_bound}
