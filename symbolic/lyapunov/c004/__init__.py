"""Claims of 004 (Sun & Huo): the position (eqs. 21-28) and attitude (eqs. 29-37) Lyapunov arguments,
Theorem 1 (eqs. 38-39) and the relative model they rest on (eqs. 9-20).

Every statement is built from the functions of :mod:`rpo.symbolic.controllers.c004` that generate the C
code (looked up on the module at check time, so mutations are seen): the closed loop is the paper's model
(eqs. 13, 19 / 14, 20) driven by the law (eq. 25 / 34) and the adaptation (eq. 27 / 36), and V-dot is
V differentiated along it (:func:`~rpo.symbolic.lyapunov.core.lie_derivative`).  Where the paper prints
a different form (y of eq. 22, Y under eq. 31, row 1 of L, eq. 9) that form is hand-typed below
(``_printed_*``) as the claim's ``paper`` statement, and the code's form is the ``corrected`` one.

Layers: ``abstract`` is the Lyapunov argument on the relative model (13), (14), (19), (20) as the paper
states it (Theorem 1 takes that model as given); ``spacecraft`` is whether rigid-body motion (eqs. 1-8)
really has that form through eqs. 9-18, and the bounds that use ||R|| = 1 and the target's inertia.
"""

from __future__ import annotations

from . import attitude, common, model, mutations, plant, position, theorem

TITLE = "004: robust adaptive control with MRPs"

CLAIMS = [*position.CLAIMS, *attitude.CLAIMS, *theorem.CLAIMS, *model.CLAIMS, *plant.CLAIMS]
MUTATIONS = mutations.MUTATIONS
UNITS = common.UNITS
