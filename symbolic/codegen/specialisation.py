"""Specialised copies of ``plant_advance`` for the parameter values most runs fly.

``plant_advance`` (RK4 of the whole plant over dt) carries every model a scenario may select:
the propagated target orbit next to the Keplerian one (``orbit_propagated``, blended by 0/1 in
:meth:`.plant.Plant.target_frame`) and the papers' periodic disturbance model (24 sines and
cosines of t per evaluation, :meth:`.plant.Plant.scenario_disturbance`).  A run whose parameter
vector has those switches or amplitudes at 0 computes them and multiplies them by 0.  Here the
same CasADi expression is copied with those entries of p replaced by the constant 0 before code
generation; CasADi folds the products by 0 away, and what is left is the general function's
operations on the same values (its reciprocals are not shared anew, :func:`specialised`).  So
a specialised copy gives the general function's values wherever its condition holds (the
exceptions are the sign of an exact zero, 0 * (-x) = -0 against a folded +0, and a NaN or inf
in a dropped term; the tests compare them at random points).

``measure`` gets the Keplerian copy too.  The composed steps (:func:`.functions.composed_step`)
call the first variant whose listed p
entries are all 0 (checked per step in C; per lane in the lane form, where lanes that disagree
each get their own variant's values: a lane is always bit-identical to the same run alone), else
the general function.  The CasADi fallback (no C compiler) always calls the general function.

Operations (CasADi instructions): ``plant_advance`` 26,566, its Keplerian copy 22,191, without
the disturbance model as well 21,540; ``measure`` 1,595 and 789.  The speed this buys is in the
README (Speed).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Variant:
    """``<function>_<suffix>``: the function with the entries of these p fields set to 0: the
    switches ``zero``, and with ``no_disturbance`` every amplitude of the scenario disturbance."""

    suffix: str
    zero: tuple[str, ...]
    doc: str
    no_disturbance: bool = False


_KEPLER = Variant("kepler", ("orbit_propagated",), "Keplerian target orbit (orbit_propagated 0)")

#: The specialised copies of each function the steps call, tried in this order (the most
#: specialised first).  ``measure`` reads the target's frame too: its Keplerian copy keeps a
#: Keplerian run free of the propagated orbit's state altogether.
VARIANTS = {
    "measure": (_KEPLER,),
    "plant_advance": (
        Variant("kepler_nodist", ("orbit_propagated",),
                "Keplerian target orbit, no scenario disturbance (orbit_propagated and every dist_* amplitude 0)",
                no_disturbance=True),
        _KEPLER,
    ),
}


def zero_fields(p_layout, variant: Variant) -> list[str]:
    """The p fields (of a :class:`.layout.Layout`) that ``variant`` requires to be 0.  The
    disturbance amplitudes are read off the layout (:meth:`.plant.Plant.scenario_disturbance`'s
    ``dist_*`` fields other than its frequencies, in rad/s), so a term added there is covered."""
    out = list(variant.zero)
    if variant.no_disturbance:
        out += [f.name for f in p_layout.fields if f.name.startswith("dist_") and f.unit != "rad/s"]
    return out


def zero_indices(p_layout, variant: Variant) -> list[int]:
    """The entries of p that ``variant`` requires to be 0, ascending."""
    offs = p_layout.offsets()
    out: list[int] = []
    for f in zero_fields(p_layout, variant):
        start, stop = offs[f]
        out.extend(range(start, stop))
    return sorted(out)


def specialised(fn, p_input: int, indices: list[int], name: str):
    """``fn`` (an SX function, as generated: reciprocals already shared) with entries ``indices``
    of its input ``p_input`` replaced by 0 and its common subexpressions eliminated again, named
    ``name``.  Its reciprocals are not shared anew: that rewrite (a / b -> a * (1 / b) where b
    divides several values) changes the last bit, and the copy must keep the general function's
    operations for everything the substitution leaves."""
    import casadi as ca

    syms = [ca.SX.sym(fn.name_in(i), fn.size1_in(i)) for i in range(fn.n_in())]
    outs = fn(*syms)
    outs = list(outs) if isinstance(outs, (list, tuple)) else [outs]
    p = syms[p_input]
    zeros = [ca.SX(0.0)] * len(indices)
    outs = ca.substitute(outs, [p[i] for i in indices], zeros)
    return ca.Function(name, syms, ca.cse(outs), fn.name_in(), fn.name_out())
