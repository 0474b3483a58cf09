"""000, boundary layer (eqs. 52, 84, 106, 119 and the text after eq. 57) and the convergence conclusion."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ...controllers import c000 as c
from ..core import (
    Statement,
    claim_factory,
)
from ..domains import (
    box,
    custom,
)
from .common import _paper_layer, _pos, _printed_layer, _real

claim = claim_factory(__name__)

# =====================================================================================================
# Boundary layer (eqs. 52, 84, 106, 119 and the text after eq. 57)
# =====================================================================================================

def _layer_symbols():
    s = sp.Symbol("s", real=True)
    d = sp.Symbol("d", positive=True)
    return s, d


def _bl_sign(printed: bool):
    """sign(s) S_aug = |S_aug|: the step from eq. 68 to eqs. 69-72 (and 102-104, 117, 129); printed: the
    paper's piecewise S_aug (eq. 52 with the text after eq. 57)."""
    def build():
        s, d = _layer_symbols()
        S = (_paper_layer if printed else c.boundary_layer_surface)(s, d)
        return Statement(sp.sign(s) * S, "==", sp.Abs(S), [box(d, 0.001, 0.5), box(s, -1.5, 1.5)],
                         assumptions=["d > 0"])
    return build


def _bl_zero_inside(printed: bool):
    """S_aug = 0 for |s| <= d (the text after eq. 57)."""
    def build():
        s, d = _layer_symbols()
        S = (_printed_layer if printed else c.boundary_layer_surface)(s, d)
        inside = custom([s], 1, lambda z, env: z * env[d][:, None], "|s| <= d")
        return Statement(S, "==", 0, [box(d, 0.001, 0.5), inside], hypotheses=[sp.Abs(s) <= d],
                         assumptions=["|s| <= d (inside the layer)"])
    return build


def _bl_derivative():
    """S_aug dS_aug/ds = S_aug: S_aug S_aug_dot = S_aug s_dot everywhere (eqs. 57-59)."""
    s, d = _layer_symbols()
    S = c.boundary_layer_surface(s, d)
    return Statement(S * sp.diff(S, s), "==", S, [box(d, 0.001, 0.5), box(s, -1.5, 1.5)])


def _convergence(printed: bool):
    """The conclusion "tracking errors converge to zero asymptotically": where V-dot = 0 (inside the layer,
    |s| <= d, S_aug = 0), d/dt(e^2/2) = e (s - lambda e).  Printed: <= 0 everywhere there (e -> 0);
    corrected: <= 0 for |e| >= d/lambda (ultimate bound |e| <= d/lambda, |s| <= d)."""
    e, edot, s = _real("e edot s")
    lam, d = _pos("lambda_0 d")
    # e_dot from the code's surface s = e_dot + lambda e, for s drawn in the layer: e_dot = s - lambda e.
    # The product is expanded, e s - lambda e^2, so that the checker's round-off scale sees both terms: at
    # the layer's corner (|e| = d/lambda, s = d sgn e) the value is 0 as the difference of two equal terms.
    edot_of_s = sp.solve(sp.Eq(c.sliding_surface(edot, e, lam), s), edot)[0]

    def draw_e(z, env):
        if printed:
            return (z[:, 0] * 3 * env[d] / env[lam])[:, None]
        bound = env[d] / env[lam]
        return (np.sign(z[:, 0] + 1e-300) * bound * (1 + 2 * np.abs(z[:, 0])))[:, None]

    dom = [box(lam, 0.005, 1.0), box(d, 0.001, 1.0),
           custom([e], 1, draw_e, "|e| <= 3 d/lambda" if printed else "|e| >= d/lambda"),
           custom([s], 1, lambda z, env: z * env[d][:, None], "|s| <= d")]
    return Statement(sp.expand(e * edot_of_s), "<=", 0, dom,
                     symbolic=False, assumptions=["inside the boundary layer |s| <= d (V-dot = 0 there)"])


CLAIMS = [
        claim("boundary_layer.zero_inside", "boundary layer", "abstract", "52 and the text after 57",
              "Notation erratum: eq. 52's formula gives S_aug = 0 inside the layer |s| <= d",
              _bl_zero_inside(True), _bl_zero_inside(False),
              correction="S_aug = s - d sat(s/d) (eq. 52 completed by the text: 0 inside, s - d sign(s) outside)",
              note="Reported once: the formula s - d sign(s) alone is nonzero inside the layer; the text after "
                   "eq. 57 completes it into Slotine's s_Delta. The other claims type the paper's S_aug piecewise."),
        claim("boundary_layer.sign", "boundary layer", "abstract", "52, 84, 106, 119; 68-72",
              "sign(s) S_aug = |S_aug| (used from eq. 68 to eq. 72)", _bl_sign(True), _bl_sign(False),
              note="Holds for the paper's piecewise S_aug and for the implemented sat form."),
        claim("boundary_layer.derivative", "boundary layer", "abstract", "57-59",
              "S_aug dS_aug/ds = S_aug (so S_aug S_aug_dot = S_aug s_dot, the step in eq. 58)", None,
              _bl_derivative,
              note="Holds for the implemented layer (dS/ds = 1 outside, S = 0 inside); the V-dot claims use it."),
        claim("convergence", "boundary layer", "abstract", "72 and the conclusion",
              "Where V-dot = 0 (inside the layer) the tracking error still decreases (e -> 0)",
              lambda: _convergence(True), lambda: _convergence(False),
              correction="ultimate bound: |s| <= d and |e| <= d/lambda_0 (e e_dot <= 0 only for |e| >= d/lambda_0)",
              note="Inside the layer V-dot = 0 and e_dot = s - lambda_0 e: e -> s/lambda_0, not 0. The conclusion's "
                   "'converge to zero asymptotically' holds for S_aug only."),
]
