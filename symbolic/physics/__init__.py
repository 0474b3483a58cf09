"""rpo.symbolic.physics: the model as SymPy expressions, each equation once, with its paper's number.

Rotations, Kepler's equation, the orbit and the target's propagated orbit, rigid-body and relative
dynamics, environment, actuators, faults, mass properties, the papers' constraints; the plant that
assembles them with its layouts (:mod:`.layout`: names, units, bounds, scenario keys); and the
closed-loop step (:mod:`.closed_loop`), the sampled-data model that joins the plant with a design of
``symbolic/controllers/``.  Nothing here knows about CasADi or C: :mod:`rpo.symbolic.codegen`
translates these expressions, and imports from here, never the other way round.
"""
