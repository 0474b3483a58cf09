"""SI units of the search domains' symbols, printed with the domains in the report.

Each claims package declares its vocabulary once, in ``UNITS`` (its ``common.py``, exposed by its
``__init__``): a symbol's name -> its SI unit (``"m"``, ``"rad/s"``, ``"N m"``, ...; ``"1"`` for a
dimensionless one).  A name is looked up as it is, then without its trailing index, repeatedly: digits
(``r_e_1`` -> ``r_e``, ``omega_c1`` -> ``omega_c``), an axis letter or an LVLH pair after an underscore
(``D_att_x`` -> ``D_att``, ``h_hat_xx`` -> ``h_hat``) or an axis letter after ``_d`` (``acc_dx`` -> ``acc_d``);
the first name declared wins, so an entry for ``a_3`` overrides one for ``a``.

A name that means different things in different claims of one controller (000's ``b`` is 1/I_cj in the
attitude claims and 1/m_c in the translation ones) maps to a dict ``{context: unit}``; a context is a prefix
of the claim's part or of its id without the controller (``"attitude"``, ``"translation"``,
``"gains.kappa1_varpi1"``), the longest matching one wins.

The controllers' layouts (``k``, ``xc`` of ``symbolic/controllers/``) already state the units of their
fields: :func:`layout_units` reads them (the entries whose unit is neither ``"-"`` nor ``"mixed"``), so a
``UNITS`` dict starts from them and declares only the rest.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

from .core import Claim
from .domains import Var

DIMENSIONLESS = "1"

_INDEX = re.compile(r"(?:_?\d+|_(?:[xyzw]|xx|yy|zz)|(?<=_d)[xyz])$")
_SI = {"m", "s", "kg", "N", "rad", "J", "W", "1"}
#: a set given by its numbers only: the unit follows it ("in [-40, 40] m"); other texts get it in parentheses
_NUMERIC_SET = re.compile(r"^(?:in \[[^\]]*\]|\|\.\| <= [-+0-9.e]+)$")


class MissingUnit(KeyError):
    """A domain symbol without a declared unit."""

    def __str__(self) -> str:
        return str(self.args[0])


def layout_units(*layouts) -> dict[str, str]:
    """The units the controller's layouts state, by symbol name (each field's labels); a field whose unit is
    ``"-"`` (dimensionless, or a gain whose unit the layout leaves open) or ``"mixed"`` is left out."""
    return {label: f.unit for layout in layouts for f in layout.fields if f.unit not in ("-", "mixed")
            for label in f.labels()}


def candidates(name: str) -> list[str]:
    """``name`` and the names it is looked up by after it, most specific first."""
    out = [name]
    while True:
        shorter = _INDEX.sub("", out[-1])
        if not shorter or shorter == out[-1]:
            return out
        out.append(shorter)


def declared(controller: str) -> Mapping:
    """The ``UNITS`` of a controller's claims package (empty if it declares none)."""
    from . import module

    return getattr(module(controller), "UNITS", {})


def _context_unit(entry: Mapping, cl: Claim) -> str | None:
    name = cl.id.split(".", 1)[1]
    hits = [k for k in entry if cl.part.startswith(k) or name.startswith(k)]
    return entry[max(hits, key=len)] if hits else None


def unit_of(cl: Claim, symbol, units: Mapping | None = None) -> str | None:
    """The unit of a domain symbol of one of ``cl``'s statements (None: not declared)."""
    units = declared(cl.controller) if units is None else units
    for name in candidates(str(symbol)):
        if name in units:
            entry = units[name]
            return _context_unit(entry, cl) if isinstance(entry, Mapping) else entry
    return None


def missing(cl: Claim, domain, units: Mapping | None = None) -> list[str]:
    """The symbols of a domain (a list of :class:`Var`) without a declared unit."""
    units = declared(cl.controller) if units is None else units
    return [str(s) for v in domain for s in v.symbols if unit_of(cl, s, units) is None]


def _plain(unit: str) -> bool:
    """A unit made of SI symbols only ("kg m^2", "1/(N m s^5)"), not a phrase."""
    return all(t in _SI for t in re.split(r"[\s/()^*.\-\d]+", unit) if t)


def units_text(cl: Claim, var: Var, units: Mapping | None = None) -> str:
    """What follows a variable's set in the report: its unit (``" m"``, ``" (rad/s)"``), its units per symbol
    where they differ, nothing where it is dimensionless.  MissingUnit for a symbol without a unit."""
    units = declared(cl.controller) if units is None else units
    groups: dict[str, list[str]] = {}
    for s in var.symbols:
        u = unit_of(cl, s, units)
        if u is None:
            raise MissingUnit(f"{cl.id}: no unit declared for the domain symbol {s} (add it to UNITS in "
                              f"symbolic/lyapunov/{cl.controller}/common.py)")
        groups.setdefault(u, []).append(str(s))
    if len(groups) == 1:
        (u,) = groups
        if u == DIMENSIONLESS:
            return ""
        return f" {u}" if _plain(u) and _NUMERIC_SET.match(var.describe) else f" ({u})"
    return " (" + "; ".join(f"{', '.join(names)}: {'dimensionless' if u == DIMENSIONLESS else u}"
                            for u, names in groups.items()) + ")"


def declare(from_layouts: Mapping, own: Mapping) -> dict:
    """A controller's ``UNITS``: the units its layouts state (:func:`layout_units`) and its claims' own; a name
    in both is an error (each unit is declared once)."""
    twice = sorted(set(from_layouts) & set(own))
    if twice:
        raise ValueError(f"units declared twice (the layouts state them): {', '.join(twice)}")
    return {**from_layouts, **own}
