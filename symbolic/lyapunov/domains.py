"""Search domains: how the adversarial search draws a statement's symbols inside its stated assumptions.

A domain is a list of :class:`Var`.  Each maps box coordinates z in [-1, 1]^dim to values of its symbols
that satisfy the assumption it stands for (a unit quaternion is a normalised 4-vector, ``|d| <= rho`` a
ball, a rotation matrix comes from scipy).  So every point of the box is admissible and the optimisers of
:mod:`.check` (local and global) search the box freely: equality constraints are respected by
construction, never by penalties.

The samplers shared by the claims of several controllers live here, and only here: boxes, balls, unit
quaternions and vectors, rotation matrices (scipy, independent of rpo's rotation code), symmetric
positive definite matrices, Kepler orbits.  A sampler used by one controller only stays in its claims
package.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

MU_EARTH = 3.986004418e14      # [m^3/s^2]


@dataclass(frozen=True)
class Var:
    """Symbols drawn together from ``dim`` box coordinates z in [-1, 1]^dim.

    ``draw(z, env)`` maps an (n, dim) array of box coordinates to an (n, len(symbols)) array of values;
    ``env`` holds the values of the variables listed before this one (for dependent bounds such as
    ``|d| <= D``).  ``needs``: the symbols of earlier variables the draw reads, where declared (domain
    pruning, :func:`~.core.prune`, also finds undeclared ones by a trial draw).
    """

    symbols: tuple[sp.Symbol, ...]
    dim: int
    draw: Callable[[np.ndarray, dict], np.ndarray]
    describe: str = ""
    needs: frozenset = field(default_factory=frozenset)


def _syms(symbols) -> tuple[sp.Symbol, ...]:
    if isinstance(symbols, sp.MatrixBase):
        return tuple(symbols)
    if isinstance(symbols, sp.Symbol):
        return (symbols,)
    return tuple(symbols)


def needing(var: Var, *symbols: sp.Symbol) -> Var:
    """``var`` declaring that its draw reads ``symbols`` (drawn by earlier variables)."""
    return Var(var.symbols, var.dim, var.draw, var.describe, var.needs | frozenset(symbols))


# --------------------------------------------------------------------------- elementary samplers

def box(symbols, lo: float, hi: float) -> Var:
    """Each symbol independently in [lo, hi]."""
    s = _syms(symbols)
    return Var(s, len(s), lambda z, env: lo + (z + 1.0) * 0.5 * (hi - lo), f"in [{lo:g}, {hi:g}]")


def ball(symbols, radius: float | sp.Symbol | Callable[[dict], np.ndarray]) -> Var:
    """A vector with Euclidean norm <= radius (radius: a number, a symbol drawn earlier, or f(env), described by
    its docstring)."""
    s = _syms(symbols)

    def draw(z, env):
        n = np.linalg.norm(z, axis=1, keepdims=True)
        unit_ball = z / np.maximum(n, 1.0)
        return unit_ball * _radius(radius, env, len(z))[:, None]

    return Var(s, len(s), draw, f"|.| <= {_radius_text(radius)}",
               frozenset([radius]) if isinstance(radius, sp.Symbol) else frozenset())


def _radius_text(radius) -> str:
    """A radius for the report: a number or symbol as it prints; a function by the first line of its docstring
    (its name if it has none), never its repr (which holds a memory address)."""
    if callable(radius) and not isinstance(radius, sp.Basic):
        doc = (radius.__doc__ or "").strip()
        return doc.splitlines()[0] if doc else f"{radius.__name__}(...)"
    return str(radius)


def _radius(radius, env, n):
    if isinstance(radius, sp.Symbol):
        return np.asarray(env[radius], dtype=float).reshape(n)
    if callable(radius):
        return np.asarray(radius(env), dtype=float).reshape(n)
    return np.full(n, float(radius))


def unit_rows(z: np.ndarray) -> np.ndarray:
    """Each row normalised (a zero row becomes the last unit vector: the search may hit the origin)."""
    n = np.linalg.norm(z, axis=1, keepdims=True)
    fallback = np.zeros_like(z)
    fallback[:, -1] = 1.0
    return np.where(n > 1e-9, z / np.maximum(n, 1e-12), fallback)


def unit_quaternion(symbols) -> Var:
    """Four symbols on the unit sphere (any order; normalised 4-vector)."""
    s = _syms(symbols)
    assert len(s) == 4
    return Var(s, 4, lambda z, env: unit_rows(z), "unit quaternion")


def unit_vector(symbols, describe: str = "") -> Var:
    """A unit vector of any length (normalised box vector)."""
    s = _syms(symbols)
    return Var(s, len(s), lambda z, env: unit_rows(z), describe or f"unit {len(s)}-vector")


def fixed(symbols, values) -> Var:
    """Symbols held at given values (a gain set, a known inertia)."""
    s = _syms(symbols)
    vals = np.asarray(values, dtype=float).reshape(len(s))
    return Var(s, 0, lambda z, env: np.broadcast_to(vals, (len(z), len(s))).copy(), "fixed")


def derived(symbols, exprs, depends: Sequence[sp.Symbol]) -> Var:
    """Symbols defined from earlier ones, e.g. ``rho = |d|`` (``exprs`` in terms of ``depends``)."""
    s = _syms(symbols)
    exprs = list(exprs) if isinstance(exprs, (list, tuple, sp.MatrixBase)) else [exprs]
    f = sp.lambdify(list(depends), exprs, "numpy")

    def draw(z, env):
        cols = f(*[np.asarray(env[d], dtype=float) for d in depends])
        return np.column_stack([np.broadcast_to(np.asarray(c, dtype=float), (len(z),)) for c in cols])

    return Var(s, 0, draw, "derived", frozenset(depends))


def custom(symbols, dim: int, draw: Callable[[np.ndarray, dict], np.ndarray], describe: str) -> Var:
    """Any other parameterisation of a constraint set by box coordinates (documented by ``describe``)."""
    return Var(_syms(symbols), dim, draw, describe)


# --------------------------------------------------------------------------- rotations (scipy, not rpo's code)

def qmul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product, scalar last, row-wise (independent of the symbolic code)."""
    pv, pw, qv, qw = p[:, :3], p[:, 3:], q[:, :3], q[:, 3:]
    return np.hstack([pw * qv + qw * pv + np.cross(pv, qv), pw * qw - np.sum(pv * qv, 1, keepdims=True)])


def rotate(qr: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``q v q*`` for scalar-last unit quaternions (rows)."""
    vq = np.hstack([v, np.zeros((len(v), 1))])
    conj = qr * np.array([-1.0, -1.0, -1.0, 1.0])
    return qmul(qmul(qr, vq), conj)[:, :3]


def rotations_from_mrp(z: np.ndarray) -> np.ndarray:
    """Rotation matrices (n, 3, 3) from MRPs in the unit ball (z clipped to it; scipy): every rotation."""
    from scipy.spatial.transform import Rotation

    sig = z / np.maximum(np.linalg.norm(z, axis=1, keepdims=True), 1.0)
    return Rotation.from_mrp(sig).as_matrix()


def rotation_matrix(symbols, describe: str = "rotation matrix") -> Var:
    """The 9 entries of R (row-major) drawn as a rotation matrix (3 box coordinates: an MRP)."""
    s = _syms(symbols)
    assert len(s) == 9
    return Var(s, 3, lambda z, env: rotations_from_mrp(z).reshape(len(z), 9), describe)


# --------------------------------------------------------------------------- inertia matrices

UPPER = [(i, j) for i in range(3) for j in range(i, 3)]   # 11, 12, 13, 22, 23, 33


def upper(M: sp.MatrixBase) -> list:
    """The 6 upper-triangle entries of a symmetric 3x3 matrix, in the order the samplers draw them."""
    return [M[i, j] for i, j in UPPER]


def spd_rotated(M: sp.MatrixBase, lo: float, hi: float, norm_symbol: sp.Symbol | None = None) -> Var:
    """A symmetric positive definite J = C diag(d) C^T, d in [lo, hi], C any rotation (every such J);
    optionally its 2-norm too (``norm_symbol``)."""
    syms = upper(M) + ([norm_symbol] if norm_symbol is not None else [])

    def draw(z, env):
        d = lo + (z[:, :3] + 1.0) * 0.5 * (hi - lo)
        C = rotations_from_mrp(z[:, 3:6])
        J = np.einsum("nij,nj,nkj->nik", C, d, C)
        cols = [J[:, i, j] for i, j in UPPER]
        if norm_symbol is not None:
            cols.append(d.max(axis=1))
        return np.column_stack(cols)

    return custom(syms, 6, draw, f"J = C diag(d) C^T, d in [{lo:g}, {hi:g}]")


def spd_dominant(M: sp.MatrixBase, diag: tuple[float, float], off: float) -> Var:
    """A symmetric matrix with diagonal in [lo, hi] and |off-diagonal| <= off < lo/2: diagonally dominant,
    so every point is positive definite."""
    lo, hi = diag
    assert 2 * off < lo

    def draw(z, env):
        out = np.empty_like(z)
        for k, (i, j) in enumerate(UPPER):
            out[:, k] = lo + (z[:, k] + 1) * 0.5 * (hi - lo) if i == j else off * z[:, k]
        return out

    return custom(upper(M), 6, draw, f"symmetric, diagonal in [{lo:g}, {hi:g}], |off-diagonal| <= {off:g} "
                                     "(diagonally dominant: positive definite)")


# --------------------------------------------------------------------------- orbits

def kepler(rp: np.ndarray, e: np.ndarray, f: np.ndarray, mu: float = MU_EARTH) -> tuple[np.ndarray, ...]:
    """(r, r_dot, n, n_dot, n_ddot) of a Kepler orbit (perigee radius rp, eccentricity e, true anomaly f);
    n = h/r^2 is the LVLH rate."""
    p = rp * (1 + e)
    h = np.sqrt(mu * p)
    r = p / (1 + e * np.cos(f))
    rdot = np.sqrt(mu / p) * e * np.sin(f)
    n = h / r**2
    rddot = h**2 / r**3 - mu / r**2
    return r, rdot, n, -2 * h * rdot / r**3, -2 * h * rddot / r**3 + 6 * h * rdot**2 / r**4


def kepler_orbit(r_t: sp.Symbol, n: sp.Symbol, n_dot: sp.Symbol, extra: Sequence[sp.Symbol] = (),
                 rp: tuple[float, float] = (6.7e6, 4.3e7), e_max: float = 0.15, mu: float = MU_EARTH) -> Var:
    """(r_t, n, n_dot[, r_t_dot, n_ddot]) of one target orbit: perigee radius in ``rp``, eccentricity in
    [0, e_max], any true anomaly (3 box coordinates)."""
    def draw(z, env):
        rp_ = rp[0] + (z[:, 0] + 1) / 2 * (rp[1] - rp[0])
        e = (z[:, 1] + 1) / 2 * e_max
        r, rdot, nn, nd, ndd = kepler(rp_, e, np.pi * z[:, 2], mu)
        cols = [r, nn, nd] + ([rdot, ndd] if extra else [])
        return np.column_stack(cols)
    return custom([r_t, n, n_dot, *extra], 3, draw,
                  f"Kepler orbit: r_p {rp[0] / 1e3:g}-{rp[1] / 1e3:g} km, e <= {e_max:g}")
