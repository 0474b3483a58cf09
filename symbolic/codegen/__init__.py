"""rpo.symbolic.codegen: the engine that turns the model's SymPy expressions into CasADi and C.

The other half of ``symbolic/`` (:mod:`rpo.symbolic.physics`, the controllers) states the
equations; this package only translates and generates them, and nothing here adds to the model:

* :mod:`.functions`: what rpo generates, as families (the plant; one per controller module);
* :mod:`.codegen`: the generic engine (family hashes, incremental generation, C files, manifest);
* :mod:`.to_casadi`: SymPy -> CasADi SX (and SymPy -> NumPy through ``lambdify``);
* :mod:`.reciprocals`, :mod:`.specialisation`, :mod:`.c_composition`: shared reciprocals, the
  specialised copies, the C glue of a composed step;
* :mod:`.numpy_reference`, :mod:`.structural_cse`: the independent NumPy evaluation of the same
  expressions for the tests and benchmarks.

Importing this package imports nothing heavy: a build with nothing to do lists and hashes the
families without SymPy or CasADi.
"""
