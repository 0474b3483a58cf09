"""rpo.symbolic: the physical plant, environment, actuators and controllers as SymPy expressions.

Every equation lives here exactly once, with the paper equation it implements beside it.  Two halves:

* the model: :mod:`rpo.symbolic.physics` (plant, environment, actuators, the closed-loop step),
  :mod:`rpo.symbolic.controllers` (the papers' designs) and :mod:`rpo.symbolic.lyapunov` (their
  stability claims);
* the engine: :mod:`rpo.symbolic.codegen`, which turns those expressions into CasADi and C.

The same SymPy objects feed the Lyapunov checks and, translated to CasADi by
:mod:`rpo.symbolic.codegen.to_casadi`, the generated C code in ``generated/``.

Conventions (see ``docs/conventions.md``):

* SI units everywhere (m, s, kg, rad, N, N m, T).
* Quaternions are stored scalar-last ``[x, y, z, w]`` and multiplied with the Hamilton
  product.  ``q_B_A`` is the attitude of frame B relative to frame A:
  ``v_A = q ⊗ v_B ⊗ q*``, so ``quat_to_dcm(q)`` is ``C_{A<-B}`` (the same matrix as
  ``scipy.spatial.transform.Rotation.from_quat(q).as_matrix()``).  The attitude matrix
  of the papers' eq. 20 (Shuster's ``A(q) = C_{B<-A}``) is its transpose; the four
  numbers of a quaternion are the same in both conventions.
* Angular velocities are body rates relative to the inertial (ECI) frame, expressed in
  the body frame.
"""
