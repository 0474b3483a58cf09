"""Branch and bound: prove ``g >= 0`` on a box (with hypotheses ``h_k >= 0``) or find where it fails.

Boxes are processed a generation at a time, all of a generation in one vectorised evaluation
(:mod:`.intervals`).  A box is closed, as a leaf of the certificate's tree, by the first method that works:

* ``X`` (excluded): some hypothesis is < 0 on the whole box, so no point of the box is in the domain;
* ``N`` (natural): the interval enclosure of g has lower bound >= 0;
* ``M`` (mean value): g is differentiable on the box (no non-smooth operation switches inside it) and
  g(m) + sum_i dg/dx_i(box) (x_i - m_i) >= 0 with m the box's centre: this beats the dependency problem
  of the natural form on small boxes (its overestimation shrinks quadratically with the width);
* ``C`` (monotone corner): g is differentiable on the box and its gradient has a fixed sign in some
  coordinates on the whole box; each such coordinate is fixed at the end where g is smaller, and g is
  bounded on the face that remains (natural, then mean-value form).  This closes boxes that touch a zero of
  g on the domain's edge (``sqrt(x) - x`` at x = 1), where every enclosure of the full box dips below 0;
* ``H`` (second order): the box contains an equilibrium x0 given by the plan where g(x0) = 0 and
  grad g(x0) = 0 hold exactly (checked once, symbolically), g is twice differentiable on the box, and the
  interval Hessian is positive semidefinite on the whole box (Gershgorin: each diagonal lower bound at
  least the sum of the off-diagonal magnitudes of its row).  Then g(x) = (x - x0)^T H(xi) (x - x0) / 2
  >= 0 on the box by Taylor's theorem (the box is convex and contains x0).  This closes the boxes around
  an equilibrium where g = 0, which no first-order enclosure can.

Any other box is split in two at its centre along the coordinate with the largest estimated effect on the
enclosure (width times the gradient's magnitude, or the width relative to the domain where no gradient
bound is finite).  A box whose centre satisfies every hypothesis and has g < 0 there (rigorously, by the
point's enclosure) is a counterexample and stops the search.  Out of budget (boxes or seconds): "cannot
certify", with the boxes left open and the worst of them.

The tree is recorded in preorder (split dimension, or leaf method) so that the checker can regenerate
every box from the root without trusting any stored bound.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .intervals import Program, Unsupported, compile_exprs, down, i_add, i_mul, up

LEAF = {"X": 255, "N": 254, "M": 253, "H": 252, "C": 251}
LEAF_NAME = {v: k for k, v in LEAF.items()}
MAX_DIM = 250
BATCH = 16384


@dataclass
class BnbResult:
    status: str                               # "certified", "counterexample", "cannot"
    tree: bytes = b""                         # preorder: split dim (< 250) or leaf code (LEAF)
    boxes: int = 0                            # leaves (closed boxes)
    methods: dict = field(default_factory=dict)
    seconds: float = 0.0
    counterexample: dict | None = None        # coordinate -> value (status "counterexample")
    value: float | None = None                # g there (an upper bound, < 0)
    reason: str = ""                          # status "cannot"
    open_boxes: int = 0
    worst: dict | None = None                 # the open box with the lowest enclosure: {sym: [lo, hi]}, g lo


def _split_point(lo: float, hi: float) -> float:
    """The split point of [lo, hi]; the checker uses the same formula (plain IEEE arithmetic)."""
    return 0.5 * lo + 0.5 * hi


class _Engine:
    def __init__(self, g: sp.Expr, coords: list[sp.Symbol], hypotheses: list[sp.Expr], equilibria: list[dict]):
        self.coords = coords
        self.prog: Program = compile_exprs([g, *hypotheses], coords)
        self.nh = len(hypotheses)
        self.g = g
        self._grad: Program | None = None
        self._hess: Program | None = None
        self.equilibria = [p for p in equilibria if self._is_equilibrium(p)]

    def _is_equilibrium(self, p: dict) -> bool:
        if set(p) != set(self.coords):
            return False
        sub = {k: sp.Rational(v) for k, v in p.items()}
        if sp.simplify(self.g.xreplace(sub)) != 0:
            return False
        return all(sp.simplify(sp.diff(self.g, x).xreplace(sub)) == 0 for x in self.coords)

    @property
    def grad(self) -> Program:
        if self._grad is None:
            self._grad = compile_exprs([sp.diff(self.g, x) for x in self.coords], self.coords)
        return self._grad

    @property
    def hess(self) -> Program:
        if self._hess is None:
            n = len(self.coords)
            d1 = [sp.diff(self.g, x) for x in self.coords]
            self._hess = compile_exprs([sp.diff(d1[i], self.coords[j]) for i in range(n) for j in range(n)],
                                       self.coords)
        return self._hess

    def mean_value(self, lo, hi):
        """Lower bound of the mean-value form per box, and the gradient magnitude bound (n_boxes, n)."""
        m = 0.5 * lo + 0.5 * hi
        glo_m, _, _ = self.prog.evaluate(m, m)
        dlo, dhi, _ = self.grad.evaluate(lo, hi)
        acc = (glo_m[0], glo_m[0])
        for i in range(lo.shape[1]):
            dx = (down(lo[:, i] - m[:, i]), up(hi[:, i] - m[:, i]))
            acc = i_add(acc, i_mul((dlo[i], dhi[i]), dx))
        mag = np.maximum(np.abs(dlo), np.abs(dhi)).T
        return acc[0], mag, dlo.T, dhi.T

    def monotone_face(self, lo, hi, dlo, dhi):
        """Lower bound of g on each box from its monotone coordinates: where dg/dx_i >= 0 on the whole
        box, min g lies on the face x_i = lo_i (<= 0: on x_i = hi_i); g is evaluated on the face that
        remains (natural form, then the mean-value form on that face)."""
        flo = np.where(dlo >= 0, lo, np.where(dhi <= 0, hi, lo))
        fhi = np.where(dlo >= 0, lo, np.where(dhi <= 0, hi, hi))
        out, _, _ = self.prog.evaluate(flo, fhi)
        best = out[0]
        mv, _, _, _ = self.mean_value(flo, fhi)
        return np.maximum(best, mv)

    def hessian_psd(self, lo, hi) -> np.ndarray:
        n = lo.shape[1]
        hlo, hhi, smooth = self.hess.evaluate(lo, hi)
        hlo, hhi = hlo.reshape(n, n, -1), hhi.reshape(n, n, -1)
        mag = np.maximum(np.abs(hlo), np.abs(hhi))
        ok = smooth.copy()
        for i in range(n):
            off = np.zeros(lo.shape[0])
            for j in range(n):
                if j != i:
                    off = up(off + mag[i, j])
            ok &= hlo[i, i] >= off
        return ok & np.all(np.isfinite(hlo), axis=(0, 1))


def prove(g: sp.Expr, coords: list, hypotheses: list[sp.Expr] = (), equilibria: list[dict] = (),
          max_boxes: int = 400_000, seconds: float = 600.0, strict: bool = False) -> BnbResult:
    """Certify ``g >= 0`` (``strict``: ``g > 0``) on the box ``coords`` ([(symbol, lo, hi)]) where every
    hypothesis is >= 0."""
    holds = (lambda v: v > 0) if strict else (lambda v: v >= 0)
    t0 = time.perf_counter()
    syms = [c[0] for c in coords]
    if len(syms) > MAX_DIM:
        return BnbResult("cannot", reason=f"{len(syms)} coordinates (at most {MAX_DIM})")
    try:
        eng = _Engine(sp.sympify(g), syms, [sp.sympify(h) for h in hypotheses], list(equilibria))
        if syms:    # the gradient compiled now, so that an unsupported derivative is reported, not raised later
            _ = eng.grad
    except Unsupported as exc:
        return BnbResult("cannot", reason=f"no interval rule for {exc}", seconds=time.perf_counter() - t0)
    if not syms:
        # a constant goal: one evaluation, a one-leaf tree over the empty box
        lo_c, hi_c, _ = eng.prog.evaluate(np.zeros((1, 0)), np.zeros((1, 0)))
        good = (lo_c[0, 0] > 0) if strict else (lo_c[0, 0] >= 0)
        if good:
            return BnbResult("certified", tree=bytes([LEAF["N"]]), boxes=1, methods={"N": 1},
                             seconds=time.perf_counter() - t0)
        if hi_c[0, 0] < 0 or (strict and hi_c[0, 0] <= 0):
            return BnbResult("counterexample", counterexample={}, value=float(hi_c[0, 0]),
                             seconds=time.perf_counter() - t0)
        return BnbResult("cannot", reason=f"constant goal enclosed in [{lo_c[0, 0]:.3g}, {hi_c[0, 0]:.3g}]",
                         seconds=time.perf_counter() - t0)
    root_lo = np.array([[float(c[1]) for c in coords]])
    root_hi = np.array([[float(c[2]) for c in coords]])
    scale = np.maximum(root_hi - root_lo, 1e-300)[0]
    # the tree: per node, a split dimension (children in ``kids``) or a leaf code
    code: list[int] = [-1]
    kids: dict[int, tuple[int, int]] = {}
    q_lo, q_hi, q_id = root_lo, root_hi, np.array([0])
    methods = {k: 0 for k in LEAF}
    open_worst = None
    while len(q_id):
        if len(code) > max_boxes or time.perf_counter() - t0 > seconds:
            glo, _, _ = eng.prog.evaluate(q_lo, q_hi)
            w = int(np.argmin(glo[0]))
            open_worst = {"box": {str(s): [float(q_lo[w, i]), float(q_hi[w, i])] for i, s in enumerate(syms)},
                          "g_lower": float(glo[0, w])}
            why = f"{len(code)} nodes" if len(code) > max_boxes else f"{seconds:g} s"
            return BnbResult("cannot", boxes=sum(methods.values()), methods=_named(methods),
                             seconds=time.perf_counter() - t0, open_boxes=len(q_id), worst=open_worst,
                             reason=f"budget exhausted ({why}) with {len(q_id)} boxes open; worst lower "
                                    f"bound {open_worst['g_lower']:.3g}")
        nxt_lo, nxt_hi, nxt_id = [], [], []
        for b0 in range(0, len(q_id), BATCH):
            lo, hi, ids = q_lo[b0:b0 + BATCH], q_hi[b0:b0 + BATCH], q_id[b0:b0 + BATCH]
            out_lo, out_hi, smooth = eng.prog.evaluate(lo, hi)
            excluded = np.any(out_hi[1:] < 0, axis=0) if eng.nh else np.zeros(len(ids), bool)
            natural = ~excluded & holds(out_lo[0])
            leaf = np.full(len(ids), -1)
            leaf[excluded] = LEAF["X"]
            leaf[natural] = LEAF["N"]
            rest = leaf < 0
            mag = None
            if rest.any():
                mv_ok = np.zeros(len(ids), bool)
                idx = np.nonzero(rest & smooth)[0]
                mag = np.full(lo.shape, np.nan)
                if len(idx):
                    mv_lo, mg, dlo, dhi = eng.mean_value(lo[idx], hi[idx])
                    mv_ok[idx] = holds(mv_lo)
                    mag[idx] = mg
                    leaf[mv_ok] = LEAF["M"]
                    sel = ~mv_ok[idx] & np.any((dlo >= 0) | (dhi <= 0), axis=1)
                    if sel.any():
                        face = eng.monotone_face(lo[idx][sel], hi[idx][sel], dlo[sel], dhi[sel])
                        leaf[idx[sel][holds(face)]] = LEAF["C"]
                rest = leaf < 0
                if rest.any() and eng.equilibria and not strict:
                    idx = np.nonzero(rest & smooth)[0]
                    contains = np.zeros(len(idx), bool)
                    for p in eng.equilibria:
                        x0 = np.array([float(p[s]) for s in syms])
                        contains |= np.all((lo[idx] <= x0) & (x0 <= hi[idx]), axis=1)
                    idx = idx[contains]
                    if len(idx):
                        ok = eng.hessian_psd(lo[idx], hi[idx])
                        leaf[idx[ok]] = LEAF["H"]
                        rest = leaf < 0
            if rest.any():
                # counterexample: a centre inside the domain with g < 0 there, rigorously
                idx = np.nonzero(rest)[0]
                m = 0.5 * lo[idx] + 0.5 * hi[idx]
                clo, chi, _ = eng.prog.evaluate(m, m)
                inside = np.all(clo[1:] >= 0, axis=0) if eng.nh else np.ones(len(idx), bool)
                bad = inside & ((chi[0] <= 0) if strict else (chi[0] < 0))
                if bad.any():
                    k = int(idx[np.argmax(bad & (chi[0] == chi[0][bad].min()))])
                    pt = {str(s): float(0.5 * lo[k, i] + 0.5 * hi[k, i]) for i, s in enumerate(syms)}
                    j = int(np.nonzero(idx == k)[0][0])
                    return BnbResult("counterexample", boxes=sum(methods.values()), methods=_named(methods),
                                     seconds=time.perf_counter() - t0, counterexample=pt, value=float(chi[0][j]))
            for i in np.nonzero(leaf >= 0)[0]:
                code[ids[i]] = int(leaf[i])
                methods[LEAF_NAME[int(leaf[i])]] += 1
            idx = np.nonzero(leaf < 0)[0]
            if not len(idx):
                continue
            width = (hi[idx] - lo[idx]) / scale
            if mag is not None:
                est = (hi[idx] - lo[idx]) * np.where(np.isfinite(mag[idx]), mag[idx], np.nan)
                use = np.all(np.isfinite(est), axis=1) & (np.max(np.nan_to_num(est), axis=1) > 0)
                dim = np.where(use, np.argmax(np.nan_to_num(est, nan=-1.0), axis=1), np.argmax(width, axis=1))
            else:
                dim = np.argmax(width, axis=1)
            # never split a degenerate coordinate
            dim = np.where((hi[idx, dim] - lo[idx, dim]) > 0, dim, np.argmax(width, axis=1))
            for r, i in enumerate(idx):
                d = int(dim[r])
                a, b = lo[i, d], hi[i, d]
                s = _split_point(a, b)
                if not (a < s < b):
                    return BnbResult("cannot", boxes=sum(methods.values()), methods=_named(methods),
                                     seconds=time.perf_counter() - t0, open_boxes=len(q_id),
                                     reason=f"a box cannot be split further along {syms[d]} at {a!r}")
                left, right = len(code), len(code) + 1
                code[ids[i]] = d
                code += [-1, -1]
                kids[int(ids[i])] = (left, right)
                l_hi = hi[i].copy()
                l_hi[d] = s
                r_lo = lo[i].copy()
                r_lo[d] = s
                nxt_lo += [lo[i], r_lo]
                nxt_hi += [l_hi, hi[i]]
                nxt_id += [left, right]
        q_lo = np.array(nxt_lo).reshape(-1, len(syms))
        q_hi = np.array(nxt_hi).reshape(-1, len(syms))
        q_id = np.array(nxt_id, dtype=int)
    return BnbResult("certified", tree=_preorder(code, kids), boxes=sum(methods.values()),
                     methods=_named(methods), seconds=time.perf_counter() - t0)


def _named(methods: dict) -> dict:
    return {k: v for k, v in methods.items() if v}


def _preorder(code: list[int], kids: dict[int, tuple[int, int]]) -> bytes:
    out = bytearray()
    stack = [0]
    while stack:
        n = stack.pop()
        out.append(code[n])
        if n in kids:
            left, right = kids[n]
            stack += [right, left]
    return bytes(out)


