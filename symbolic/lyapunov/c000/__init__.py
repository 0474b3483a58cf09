"""Claims of 000 (adaptive sliding mode with adjustable acceleration): attitude (eqs. 48-80) and the
three translational axes (eqs. 81-129), each on two layers.

* **abstract**: the paper's per-axis argument for the form of eq. 48 (attitude) and eqs. 81, 105, 30-z
  (translation): X_ddot = -sum a_i f_i + b u + d.  The closed loop is that form driven by the per-axis
  law and adaptation functions of :mod:`rpo.symbolic.controllers.c000` (looked up on the module at check
  time, so mutations are seen); the regressors f, phi and the parameters a, theta are free symbols (the
  identity must hold whatever they are).  V-dot is V differentiated along it with S_aug as a coordinate
  whose rate is s_dot: the paper's step "outside the boundary layer S_aug_dot = s_dot, inside S_aug = 0"
  (eq. 57), which makes S_aug S_aug_dot = S_aug s_dot everywhere; that step is its own claim
  (``c000.boundary_layer.derivative``).
* **spacecraft**: whether the spacecraft equations have that form: the quaternion error (eqs. 53-60),
  Table 1 against the two rigid bodies (eqs. 26-29, 49-50), the products of inertia, eq. 81's scalar
  substitution r_t = r_c - |r_e| against eq. 30, and V-dot of the full law :meth:`C000.law` (the function
  that generates the C code) along the rigid-body / LVLH equations of the plant.

The paper's S_aug is typed piecewise (eq. 52 completed by the text after eq. 57: 0 inside the layer); eq. 52's
formula read alone is reported once, as the notation erratum ``c000.boundary_layer.zero_inside``.  Claims marked
"implementation only" (paper=None) are the ones whose printed counterpart would be a hybrid of printed and
implemented pieces; their printed failures are the claims named in their notes.

V is not in the controller module (000 only adapts); the candidates are written here, as printed (eqs. 57,
89, 109, 123) and as the implementation's proof uses them (positive definite, with the adaptation gains).
"""

from __future__ import annotations

from . import attitude, boundary_layer, common, mutations, translation

TITLE = "000: adaptive sliding mode with adjustable desired acceleration"

CLAIMS = [*boundary_layer.CLAIMS, *attitude.CLAIMS, *translation.CLAIMS]
MUTATIONS = mutations.MUTATIONS
UNITS = common.UNITS
