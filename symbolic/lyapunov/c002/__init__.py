"""Claims of 002 (Li et al.): Theorem 1 and its three Lyapunov arguments (eqs. 19-43).

The paper's proof has three candidates:

* V1 (eq. 26) for the sliding surfaces s1, s2 and the estimation errors alpha~ = alpha - alpha^
  (Theorem 1 i), along eqs. 19-20 (the surfaces' dynamics, where the auxiliary systems eqs. 17-18
  cancel the saturation), under the laws eqs. 23-24 and the adaptation eq. 25, with the lumped
  bounds eqs. 21-22;
* V2 (eq. 35) for the auxiliary states chi1, chi2 (Theorem 1 ii, the condition kappa > varpi);
* V3 (eq. 39) for the tracking errors q~_v, r~ (Theorem 1 iii).

Two layers.  *Spacecraft*: the relative model of :mod:`rpo.symbolic.controllers.c002` (eqs. 2-4, 7,
9, 11-12, with the corrected n_r and n_t) really gives eqs. 19-20, and its C_r, n_r, C_t, n_t obey the
lumped bounds eqs. 21-22.  *Abstract*: J s1_dot = eps_r + Phi1, m s2_dot = eps_t + Phi2 with
||Phi1||, ||Phi2|| inside the bounds of eqs. 21-22 (drawn in those balls), the rest of the proof.

Everything the controller computes comes from the module (looked up at check time, so mutations are
seen): the surfaces (eqs. 15-16), the auxiliary rates (eqs. 17-18), the laws (eqs. 23-24), the
adaptation (eq. 25), the model.  V1, V2, V3 and the paper's right-hand sides are typed from the paper
(the code has no Lyapunov functions).  The identity ``cosh^2 = 1/(1 - tanh^2)`` (phi^-1 of eqs. 17-18
is computed as cosh^2 in the code) is applied before the symbolic proof: :func:`_tanh_form`.
"""

from __future__ import annotations

from . import common, gains, model, mutations, plant, v1, v2, v3

TITLE = "002: adaptive sliding mode with a tanh anti-saturation system"

CLAIMS = [*model.CLAIMS, *plant.CLAIMS, *v1.CLAIMS, *v2.CLAIMS, *v3.CLAIMS, *gains.CLAIMS]
MUTATIONS = mutations.MUTATIONS
UNITS = common.UNITS
