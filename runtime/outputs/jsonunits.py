"""The units of the numbers in the JSON files of a results folder (``run.json``, ``metrics.json``, the
verdict in both): one rule, declared here, that the writers follow, ``docs/outputs.md`` states and
the tests check on every number (:func:`number_units`); and the units human text shows
(:func:`shown`).

**The rule.** Every number is in SI, and its unit is written beside it, in one of two ways:

1. **the key's name ends in its unit** (:data:`SUFFIXES`): ``time_s`` [s], ``pos_err_final_m`` [m],
   ``att_err_final_rad`` [rad], ``torque_peak_N_m`` [N m], ``beta_ca_min_m2`` [m^2]; ``_deg``
   (degrees) only where a name says so (``final_deg``, ``att_deg``); ``fraction`` and
   ``*_fraction``, ``*_share`` are fractions (0 to 1), and the counts and identifiers of
   :data:`COUNTS` (``steps_done``, ``rows``, ``firings``, ``seed``...) are integers: both without
   unit (``-``);
2. **a ``units`` object beside the numbers**, where the unit is not in the key's name: its entry
   for a key is that value's unit (a string: of the number, of every number of the list or of
   every number inside the object), a list (the units of a list, entry by entry) or an object
   (mirroring an object).  Maps by label or parameter name (``inputs.params``, a divergence's
   ``state``, ``z0``) and keys whose unit differs from entry to entry (a goal's ``final``, rad or
   m; a constraint's ``min``, m or m^2) are written so.

A ``units`` entry comes first (``metrics.json``'s top-level ``units`` gives every scalar metric's,
e.g. ``chatter_cmd_F_tv_per_s`` in N/s), then a ``units`` entry of an enclosing object, then the
key's name.  Non-finite values are written as the text ``"nan"``, ``"inf"``, ``"-inf"`` (strict
JSON) and count as numbers.

**Human text** (the verdict's ``line``, ``rpo run``'s table, a campaign's ``report.md``) shows
angles in deg, body rates in deg/s and wheel speeds in rpm, everything else in SI, and names the
unit beside each number (:func:`shown`: one document never shows rad and deg side by side).

:func:`annotate_run` and :func:`annotate_metrics` add the ``units`` objects a run's record and
metrics need (from the model's layouts and the run's column units); :func:`number_units` reads
the rule back: every number of a JSON document with its path and unit (None when it has none).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rpo.runtime.model.loader import Model
    from rpo.runtime.run.result import RunResult

#: unit suffix of a key -> its unit, the longest first (``_rad_s`` before ``_s``)
SUFFIXES: dict[str, str] = {
    "_N_m_s": "N m s", "_N_s": "N s", "_N_m": "N m", "_rad_s": "rad/s", "_deg_s": "deg/s", "_m_s": "m/s",
    "_per_s": "1/s", "_m2": "m^2", "_rad": "rad", "_deg": "deg", "_rpm": "rpm", "_kg": "kg", "_s": "s", "_m": "m",
    "_fraction": "-", "_share": "-",
}
#: keys of integers without a unit: counts and identifiers
COUNTS = frozenset({"steps_done", "steps_requested", "rows", "rows_written", "columns_written", "step", "firings",
                    "seed", "record_every", "every"})
#: the text a non-finite number is written as
NON_FINITE = frozenset({"nan", "inf", "-inf"})
#: ``inputs.frame_info`` (the LVLH frame at t = 0): its keys' units
FRAME_INFO_UNITS = {"q_IL0": "-", "n0": "rad/s"}
#: the goal flown (``goal``, ``inputs.goal``: rpo.runtime.scenario.goals.GoalFlown.record): its keys'
#: units besides ``gains`` (the controller's goal gains, in their layout's units)
GOAL_UNITS = {"position": "m", "attitude": "-"}
#: an ``errors_at`` entry of ``metrics.json``: the keys without a unit suffix
ERRORS_AT_UNITS = {"t": "s", "t_sample": "s", "q": "-"}
#: ``metrics.json``'s ``thresholds``: the keys without a unit suffix
THRESHOLD_UNITS = {"chatter_deadband": "-"}


def suffix_unit(key: str) -> str | None:
    """The unit a key's name states (:data:`SUFFIXES`, :data:`COUNTS`), or None."""
    if key in COUNTS:
        return "-"
    for suffix, unit in SUFFIXES.items():
        if key.endswith(suffix) or key == suffix[1:]:
            return unit
    return None


def _is_number(v: Any) -> bool:
    return (isinstance(v, (int, float)) and not isinstance(v, bool)) or (isinstance(v, str) and v in NON_FINITE)


def number_units(doc: Any) -> Iterator[tuple[str, Any, str | None]]:
    """Every number of the JSON document ``doc`` as ``(path, value, unit)`` by the module's rule
    (``path`` like ``verdict.goals.att.final``, ``inputs.params.orbit_e``, ``z0[3]``); ``unit`` is
    None for a number without one."""
    yield from _walk(doc, None, "")


def _walk(node: Any, given: Any, path: str) -> Iterator[tuple[str, Any, str | None]]:
    if isinstance(node, Mapping):
        own = node.get("units")
        own = own if isinstance(own, Mapping) else None
        for key, value in node.items():
            if own is not None and key == "units":
                continue  # the units themselves (text)
            if own is not None and key in own:
                sub = own[key]
            elif isinstance(given, Mapping) and key in given:
                sub = given[key]
            elif (unit := suffix_unit(str(key))) is not None:
                sub = unit
            else:
                sub = given if isinstance(given, str) else None
            yield from _walk(value, sub, f"{path}.{key}" if path else str(key))
    elif isinstance(node, (list, tuple)):
        for i, value in enumerate(node):
            if isinstance(given, (list, tuple)):
                sub = given[i] if i < len(given) else None
            else:
                sub = given
            yield from _walk(value, sub, f"{path}[{i}]")
    elif _is_number(node):
        yield path, node, given if isinstance(given, str) else None


def without_units(doc: Any) -> list[str]:
    """The paths of the numbers of ``doc`` that have no unit by the rule (empty: every number has one)."""
    return [p for p, _, u in number_units(doc) if u is None]


# --------------------------------------------------------------------------- what the writers add


def _field_units(model: Any, layout: str | None) -> dict[str, str]:
    """Field name -> unit of one of the model's layouts ({} if the model has no such layout)."""
    layouts = getattr(model, "layouts", None) or {}
    if layout is None or layout not in layouts:
        return {}
    return {f.name: f.unit for f in layouts[layout]}


def _gains_layout(model: Any, controller: Any) -> str | None:
    ctrls = getattr(getattr(model, "manifest", None), "controllers", None) or {}
    spec = ctrls.get(controller) if isinstance(controller, str) else None
    return None if spec is None else spec.gains


def _only(units: Mapping[str, str], values: Any) -> dict[str, str]:
    """``units`` restricted to the keys of the mapping ``values``."""
    return {k: units[k] for k in values if k in units} if isinstance(values, Mapping) else {}


def annotate_run(rec: dict[str, Any], result: RunResult, model: Model | Any) -> dict[str, Any]:
    """``rec`` (a run record, ``run.json``) with its ``units`` object added, in place: one object at
    the top that mirrors the record (the module's rule), for ``dt``, ``t_end``, ``wall_time``,
    ``z0``, the divergence, the inputs (the parameters, gains and plant state by name, from the
    model's layouts), the goal flown, the overrides and the interruption; the objects themselves
    are left as they are.  Returns ``rec``."""
    z_units = dict(zip(result.z_labels, result.z_units, strict=True))
    y_units = dict(zip(result.y_labels, result.y_units, strict=True))
    own: dict[str, Any] = {"dt": "s", "t_end": "s", "wall_time": "s"}
    z0 = rec.get("z0")  # the initial state, a list (or array) over the state labels
    if z0 is not None and not isinstance(z0, (str, Mapping)) and len(z0) == len(result.z_units):
        own["z0"] = list(result.z_units)
    div = rec.get("divergence")
    if isinstance(div, dict):
        label_unit = (y_units if div.get("where") == "output" else z_units).get(div.get("label"), "-")
        own["divergence"] = {"time": "s", "value": label_unit, "bound": label_unit, "state": z_units,
                             "last_good_state": z_units, "output": y_units}
    controller = rec.get("controller")
    gains = _field_units(model, _gains_layout(model, controller))
    inputs = rec.get("inputs")
    if isinstance(inputs, dict):
        gains = _field_units(model, _gains_layout(model, inputs.get("controller", controller))) or gains
        own["inputs"] = {"params": _only(_field_units(model, "p"), inputs.get("params")),
                         "gains": _only(gains, inputs.get("gains")),
                         "plant": _only(_field_units(model, "x"), inputs.get("plant")),
                         "duration": "s", "dt": "s",
                         "frame_info": _only(FRAME_INFO_UNITS, inputs.get("frame_info"))}
        if isinstance(inputs.get("goal"), dict):
            own["inputs"]["goal"] = _goal_units(inputs["goal"], gains)
    if isinstance(rec.get("goal"), dict):
        own["goal"] = _goal_units(rec["goal"], gains)
    overrides = rec.get("overrides")
    if isinstance(overrides, dict) and overrides:
        own["overrides"] = {"duration": "s", "gains": _only(gains, overrides.get("gains"))}
    if isinstance(rec.get("interrupted"), dict):
        own["interrupted"] = {"time": "s"}
    rec["units"] = own
    return rec


def _goal_units(goal: Mapping[str, Any], gains: Mapping[str, str]) -> dict[str, Any]:
    """The units of a goal flown's record: its position and attitude, and its controller's goal gains."""
    return {**_only(GOAL_UNITS, goal), "gains": _only(gains, goal.get("gains"))}


def annotate_metrics(metrics: Mapping[str, Any], result: RunResult) -> dict[str, Any]:
    """A copy of ``metrics`` (``metrics.json``) with the ``units`` objects of the module's rule added
    where a key does not say its unit: the thresholds' and each ``errors_at`` entry's (its ``diag``
    columns in the run's column units).  The verdict inside is left as it is (it has its own)."""
    out = dict(metrics)
    th = out.get("thresholds")
    if isinstance(th, Mapping):
        out["thresholds"] = {**th, "units": _only(THRESHOLD_UNITS, th)}
    entries = out.get("errors_at")
    if isinstance(entries, list):
        labels = dict(zip(result.z_labels, result.z_units, strict=True))
        labels.update(zip(result.y_labels, result.y_units, strict=True))
        out["errors_at"] = [{**e, "units": {**ERRORS_AT_UNITS, "diag": _only(labels, e.get("diag"))}}
                            if isinstance(e, Mapping) else e for e in entries]
    return out


# --------------------------------------------------------------------------- human text

#: SI unit -> (the unit human text shows, the factor from SI, the name suffix then); wheel speeds
#: (rad/s in a column whose name says ``wheel_speed``) are shown in rpm (:data:`WHEEL_SPEED`)
HUMAN: dict[str, tuple[str, float, str]] = {"rad": ("deg", 180.0 / math.pi, "_deg"),
                                            "rad/s": ("deg/s", 180.0 / math.pi, "_deg_s")}
WHEEL_SPEED = ("rpm", 60.0 / (2.0 * math.pi), "_rpm")


def shown(name: str, unit: str) -> tuple[str, str, float]:
    """(name, unit, factor) of the SI quantity ``name`` [``unit``] in human text: angles in deg,
    angular rates in deg/s, wheel speeds in rpm (a name's SI suffix becomes the shown one:
    ``att_err_final_rad`` is shown as ``att_err_final_deg``); other units as they are (factor 1)."""
    rule = WHEEL_SPEED if unit == "rad/s" and "wheel_speed" in name else HUMAN.get(unit)
    if rule is None:
        return name, unit, 1.0
    to, factor, suffix = rule
    si = next((sfx for sfx, u in SUFFIXES.items() if u == unit and name.endswith(sfx)), None)
    return (name[: -len(si)] + suffix if si else name), to, factor
