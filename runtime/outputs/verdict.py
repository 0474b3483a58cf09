"""The verdict of a run: which goals were reached and when, and for each goal that was not, the
main reason rpo can measure (pure NumPy, from the recorded columns, the metrics and the run's
parameters; no model).

Goals (as :mod:`rpo.runtime.outputs.metrics` defines them): **attitude** reached when its settling time
exists (the error stays below ``att_deg``, 1 deg by default, from then to the end of the run), at
that time; **position** likewise with ``pos_m`` (0.5 m).  A goal whose error the controller does
not log is "not measured".

Measured reasons (each a fraction of the run ``[t_0, t_end]``, sample i held over
``[t_i, t_{i+1})``: exact when ``record_every = 1``):

* actuator saturation against what the command asked, per family (only the families the run
  flies, from ``actuators_ideal``):

  - ``wheel_torque`` (attitude): the wheel allocation was scaled down onto the torque limit
    (``max_i |wheel_cmd_i| >= (1 - 1e-6) wheel_torque_max``), or a wheel delivered less than it
    was allocated (``|wheel_applied_i| < |wheel_cmd_i| - 1e-6 wheel_torque_max``: a degraded or
    failed wheel; compared only when ``wheel_delay < dt``, where the applied torque is the same
    step's command);
  - ``wheel_speed`` (attitude): a wheel at its speed limit (``|env_wheel_speed_i| >= 0.99
    wheel_speed_max``) while the torque asked of it drives it further (the plant then applies
    none, 000 Fig. 6);
  - ``thrusters`` (position; attitude too when the controller commands thruster torque): the
    thruster allocation was scaled down (``max_j thr_duty_j >= 1 - 1e-6``: some thruster was asked
    for more than full thrust, so the realised force and torque are smaller than commanded);
  - ``ideal_force`` (position), ``ideal_torque`` (attitude): the ideal actuators applied less than
    commanded on some axis (``|cmd - env_*_applied| > 1e-6 x limit``; the command torque is
    ``cmd_tau_w + cmd_tau_thr``);
* a constraint violated (:func:`violated_constraints`, the one rule the verdict and a campaign's
  ``constraint_violated`` use: :data:`CONSTRAINT_RULE`): ``env_beta_fov < 0`` (camera cone) or
  ``env_beta_ca < 0`` (envelope spheres) at some recorded sample, 001's constraints, evaluated for
  every run whether or not its scenario declares them (``[constraints]``: :func:`declared_constraints`);
* a divergence (the run stopped early).

**The main reason** of a goal not reached is the first that applies of:

1. the run diverged (it stopped before the end: nothing after that time was measured);
2. an actuator family acting on that goal saturated for at least ``SATURATION_MIN`` (5 %) of the
   run: ``wheel_speed`` if it is one of them (a wheel at its speed limit gives no torque at all in
   the asked direction, while a torque-limited wheel still gives its maximum: on 000's scenarios
   the momentum limit is what ideal actuators of the same torque remove, docs/reproduction.md),
   else the one saturated longest; the other families over 5 % follow as "also";
3. a constraint violated at some time (the one violated longest);
4. otherwise none that rpo measures: the verdict says so and gives the final error (the run may be
   too short for this design, or its gains too weak).

Saturation is checked before constraints because it is the physical limit that stops a law from
doing what it asks; a constraint violation says where the path went, not why the goal was missed.

Units (``docs/verdict.md``, the JSON rule of :mod:`rpo.runtime.outputs.jsonunits`): SI, a key's unit
in its name (``time_s``, ``min_t_s``, ``final_deg``; ``fraction`` and ``*_fraction`` are fractions of
the run) or, where it differs from entry to entry, in the ``units`` object beside it (a goal's
``final``: rad or m; a constraint's ``min``: m or m^2).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rpo.runtime.model.manifest import FaultVocabulary
from rpo.runtime.outputs.metrics import (
    SPEED_LIMIT_TOL,
    TORQUE_LIMIT_TOL,
    XYZ,
    _block_labels,
    _series,
    _unit_labels,
    held_fraction,
    hold_weights,
    param,
)
from rpo.runtime.scenario.faults import active_faults

#: a family saturated for less than this fraction of the run is not named as the main reason
SATURATION_MIN = 0.05
#: relative tolerance of "applied differs from commanded" (ideal actuators, wheel shortfall)
APPLIED_TOL = 1e-6

GOALS = {"att": "attitude", "pos": "position"}
#: what each family's saturation means, for the verdict's text
FAMILY_TEXT = {
    "wheel_torque": "wheels torque-limited",
    "wheel_speed": "wheels at their speed limit",
    "thrusters": "thrusters saturated",
    "ideal_force": "force actuator saturated",
    "ideal_torque": "torque actuator saturated",
}
CONSTRAINTS = {"env_beta_fov": ("beta_fov", "camera field of view", "m"),
               "env_beta_ca": ("beta_ca", "collision envelope", "m^2")}
#: the rule of "a constraint violated", in words (the campaign report quotes it)
CONSTRAINT_RULE = ("a constraint is violated when its margin (beta_fov [m], the camera cone; beta_ca [m^2], the "
                   "envelope spheres) is below 0 at some recorded sample; both are evaluated for every run, "
                   "whether or not its scenario declares them in [constraints]")
#: the SI unit of each goal's error (``final``) and the factor of the degrees the text shows
GOAL_UNITS = {"att": "rad", "pos": "m"}
DEG = 180.0 / np.pi


def violated_constraints(con: Mapping[str, Mapping[str, Any]], only: Iterable[str] | None = None) -> list[str]:
    """The names of the constraints violated (``con``: :func:`constraints` or a verdict's
    ``constraints``), by :data:`CONSTRAINT_RULE`, in :data:`CONSTRAINTS` order; ``only``: among these
    names.  The verdict's line and main reason and a campaign's ``constraint_violated`` all count
    by this function."""
    keep = None if only is None else set(only)
    return [n for n, c in con.items() if c.get("violated") and (keep is None or n in keep)]


def declared_constraints(scenario_data: Mapping[str, Any]) -> tuple[str, ...]:
    """The constraints a scenario (its TOML data) declares: every one when it has a ``[constraints]``
    table (001's camera cone and envelope spheres come together), else none."""
    return tuple(name for name, _, _ in CONSTRAINTS.values()) if "constraints" in scenario_data else ()


def _units(columns: Mapping[str, Any], labels: tuple[str, ...], prefix: str) -> np.ndarray | None:
    """The unit columns ``<prefix>_<digits>`` (``labels``: the columns' labels) as the rows of a
    (units, samples) array, in unit order; None if there are none."""
    u = _unit_labels(labels, prefix)
    return np.array([np.asarray(columns[k], float) for _, k in u]) if u else None


def _xyz(columns: Mapping[str, Any], prefix: str) -> list[np.ndarray] | None:
    """The x, y, z series of the field ``prefix`` (or its numbered columns), None if not recorded."""
    labels = _block_labels(columns, prefix, XYZ)
    return None if labels is None else _series(columns, labels)


def _weights(t: np.ndarray) -> tuple[np.ndarray, float]:
    """The run's sample-and-hold weights [s] and their sum, the run's span [s]."""
    w = hold_weights(t)
    return w, float(np.sum(w))


def saturation(t: ArrayLike, columns: Mapping[str, Any], params: Mapping[str, Any] | None) -> dict[str, dict]:
    """Per actuator family of this run: ``{"fraction": ..., "goals": [...], "what": ...}``
    (``fraction`` None when a column or limit it needs is missing); see the module docstring."""
    return _saturation(columns, params, *_weights(np.asarray(t, float)))


def _saturation(columns: Mapping[str, Any], params: Mapping[str, Any] | None, w: np.ndarray,
                span: float) -> dict[str, dict]:
    """:func:`saturation` with the run's hold weights ``w`` [s] and their sum ``span`` [s]; the
    wheels and thrusters as (units, samples) arrays, so a maximum or "any" over the units is one
    elementwise pass down the rows."""
    out: dict[str, dict] = {}

    def put(name: str, flag: np.ndarray | None, goals: list[str]) -> None:
        frac = None if flag is None else held_fraction(w, span, flag)
        out[name] = {"fraction": frac, "goals": goals, "what": FAMILY_TEXT[name]}

    with np.errstate(invalid="ignore"):  # NaN samples compare False: not saturated
        if param(params, "actuators_ideal") == 1.0:
            for name, cmd_parts, applied, limit, goal in (
                    ("ideal_force", ("cmd_F",), "env_F_applied", "force_max", "pos"),
                    ("ideal_torque", ("cmd_tau_w", "cmd_tau_thr"), "env_tau_applied", "torque_max", "att")):
                parts = [_xyz(columns, c) for c in cmd_parts]
                app = _xyz(columns, applied)
                lim = param(params, limit)
                flag = None
                if app is not None and lim is not None and all(p is not None for p in parts):
                    flag = np.zeros(len(w), bool)
                    for axis, app_axis in enumerate(app):  # per axis: the command (sum of the parts) vs applied
                        cmd = parts[0][axis]  # type: ignore[index]
                        for part in parts[1:]:
                            cmd = cmd + part[axis]  # type: ignore[index]
                        flag |= np.abs(cmd - app_axis) > APPLIED_TOL * lim
                put(name, flag, [goal])
            return out
        labels = tuple(columns)
        t_max, s_max = param(params, "wheel_torque_max"), param(params, "wheel_speed_max")
        w_cmd, w_app = _units(columns, labels, "wheel_cmd"), _units(columns, labels, "wheel_applied")
        speed = _units(columns, labels, "env_wheel_speed")
        if w_cmd is not None or w_app is not None:
            flag = None
            if w_cmd is not None and t_max is not None:
                cmd_mag = np.abs(w_cmd)
                flag = cmd_mag.max(axis=0) >= (1 - TORQUE_LIMIT_TOL) * t_max
                delay, dt = param(params, "wheel_delay"), param(params, "dt")
                if w_app is not None and w_app.shape == w_cmd.shape and delay is not None and dt is not None \
                        and delay < dt:
                    short = np.abs(w_app) < cmd_mag - APPLIED_TOL * t_max
                    flag = flag | short.any(axis=0)
            put("wheel_torque", flag, ["att"])
            flag = None
            if speed is not None and w_app is not None and s_max is not None and speed.shape == w_app.shape:
                at = (1 - SPEED_LIMIT_TOL) * s_max
                # dh_i/dt = -T_i: a negative torque spins wheel i up in the positive sense
                blocked = ((speed >= at) & (w_app < 0)) | ((speed <= -at) & (w_app > 0))
                flag = np.any(blocked, axis=0)
            put("wheel_speed", flag, ["att"])
        duty = _units(columns, labels, "thr_duty")
        if duty is not None:
            tau_thr = _xyz(columns, "cmd_tau_thr")
            asks_torque = tau_thr is not None and bool((np.abs(np.array(tau_thr)) > 0).any())  # some |tau| > 0
            put("thrusters", duty.max(axis=0) >= 1 - TORQUE_LIMIT_TOL, ["pos", "att"] if asks_torque else ["pos"])
    return out


def constraints(t: ArrayLike, columns: Mapping[str, Any]) -> dict[str, dict]:
    """Per logged constraint margin: the fraction of the run it was < 0, its minimum and when,
    and the first time it was violated (None if never)."""
    t = np.asarray(t, float)
    return _constraints(t, columns, *_weights(t))


def _constraints(t: np.ndarray, columns: Mapping[str, Any], w: np.ndarray, span: float) -> dict[str, dict]:
    """:func:`constraints` with the run's hold weights ``w`` [s] and their sum ``span`` [s]."""
    out = {}
    for col, (name, what, unit) in CONSTRAINTS.items():
        if col not in columns:
            continue
        x = np.asarray(columns[col], float)
        ok = np.isfinite(x)
        if ok.all():  # the usual case; a diverged step's outputs are not finite
            bad = x < 0
            i = int(np.argmin(x))
        elif ok.any():
            bad = ok & (x < 0)
            i = int(np.nanargmin(np.where(ok, x, np.nan)))
        else:
            continue
        violated = bool(bad.any())
        out[name] = {"what": what, "violated_fraction": held_fraction(w, span, bad),
                     "violated": violated, "first_violated_t_s": float(t[np.argmax(bad)]) if violated else None,
                     "min": float(x[i]), "min_t_s": float(t[i]), "units": {"min": unit}}
    return out


def _pct(v: float) -> str:
    return f"{100 * v:.3g} %"


def verdict(metrics: Mapping[str, Any], t: ArrayLike, columns: Mapping[str, Any],
            params: Mapping[str, Any] | None = None, divergence: Any = None,
            faults: FaultVocabulary | None = None) -> dict[str, Any]:
    """The verdict (JSON-ready): ``status`` (``reached``, ``partly reached``, ``not reached``,
    ``not measured``, ``diverged``), per goal ``reached``/``time_s``/``final``/``reason``, the
    ``saturation`` of each actuator family, the ``constraints``, the ``divergence`` message and
    ``line``, the one-line summary ``rpo run`` prints.  ``divergence``: the run's
    :class:`~rpo.runtime.run.result.Divergence` (its ``time``, ``label``, ``message()``) or None;
    ``faults``: the manifest's fault vocabulary (``Manifest.faults``), to list the faults of ``params``
    (None: none listed)."""
    t = np.asarray(t, float)
    w, span = _weights(t)  # shared by every time fraction of the run
    sat = _saturation(columns, params, w, span)
    con = _constraints(t, columns, w, span)
    th = metrics.get("thresholds", {})
    limits = {"att": f"< {th.get('att_deg', 1.0):g} deg", "pos": f"< {th.get('pos_m', 0.5):g} m"}
    goals: dict[str, dict] = {}
    parts: list[str] = []
    for q, name in GOALS.items():
        unit_key = "att_err_final_rad" if q == "att" else "pos_err_final_m"
        final = metrics.get(unit_key)
        final_text = "-" if final is None else (f"{final * DEG:.4g} deg" if q == "att" else f"{final:.4g} m")
        settle = metrics.get(f"{q}_settling_time_s")
        g: dict[str, Any] = {"goal": f"{name} error {limits[q]}", "reached": None, "time_s": None,
                             "final": final, "reason": None, "reason_kind": None, "units": {"final": GOAL_UNITS[q]}}
        if q == "att":  # the degrees the line shows, beside the SI value
            g["final_deg"] = None if final is None else final * DEG
        goals[q] = g
        if final is None:
            g["reason"] = "not measured: the controller logs no such error"
            parts.append(f"{name} not measured")
            continue
        if settle is not None:
            g.update(reached=True, time_s=settle)
            parts.append(f"{name} reached at {settle:.4g} s ({limits[q]})")
            continue
        g["reached"] = False
        kind, reason = _main_reason(q, sat, con, divergence, final_text)
        g.update(reason=reason, reason_kind=kind)
        parts.append(f"{name} NOT reached ({limits[q]}; final {final_text}): {reason}")
    violated = violated_constraints(con)
    if violated:
        parts.append("constraints violated: " + ", ".join(
            f"{n} < 0 for {_pct(con[n]['violated_fraction'] or 0.0)} of the run (min {con[n]['min']:.4g} "
            f"{con[n]['units']['min']} at {con[n]['min_t_s']:.4g} s)" for n in violated))
    elif con:
        parts.append("constraints held")
    active = [] if faults is None else active_faults(faults, params or {}, float(t[-1]) if t.size else 0.0)
    if active:
        parts.append("faults: " + ", ".join(f"{label} at {t_f:g} s" for t_f, label in active))
    measured = [g["reached"] for g in goals.values() if g["reached"] is not None]
    if divergence is not None:
        status = "diverged"
    elif not measured:
        status = "not measured"
    else:
        status = "reached" if all(measured) else ("not reached" if not any(measured) else "partly reached")
    return {"status": status, "goals": goals, "saturation": sat, "constraints": con,
            "faults": [{"time_s": t_f, "fault": label} for t_f, label in active],
            "divergence": None if divergence is None else divergence.message(),
            "saturation_min": SATURATION_MIN, "units": {"saturation_min": "-"},
            "line": f"verdict: {status}: " + "; ".join(parts)}


def name_goal(v: Mapping[str, Any], goal: Mapping[str, Any] | None) -> dict[str, Any]:
    """The verdict ``v`` naming the goal its errors are measured from (a copy with ``goal``, the
    text of the run's ``RunInputs.goal``, rpo.runtime.scenario.goals; run.json).  The controller's
    errors are to its goal gains, which are that goal's (or, for a controller rpo has no goal
    mapping for, its own: the text says so)."""
    return {**v, "goal": goal["text"]} if goal and goal.get("text") else dict(v)


def _main_reason(q: str, sat: dict[str, dict], con: dict[str, dict], divergence: Any,
                 final_text: str) -> tuple[str, str]:
    """(kind, text) of the main reason a goal was not reached, by the rule of the module docstring."""
    if divergence is not None:
        return "divergence", f"the run diverged at t = {divergence.time:.6g} s ({divergence.label})"
    cands = [(f["fraction"], name) for name, f in sat.items() if q in f["goals"] and f["fraction"] is not None]
    over = sorted((c for c in cands if c[0] >= SATURATION_MIN), reverse=True)
    if over:
        # a wheel at its speed limit gives no torque at all in the asked direction, a torque-limited
        # one still gives its maximum: the speed limit is named first (see the module docstring)
        frac, name = next((c for c in over if c[1] == "wheel_speed"), over[0])
        others = [f"{FAMILY_TEXT[n]} {_pct(f)}" for f, n in over if n != name]
        return name, f"{FAMILY_TEXT[name]} {_pct(frac)} of the run" + (f" (also {'; '.join(others)})" if others else "")
    bad = [(con[n]["violated_fraction"] or 0.0, n) for n in violated_constraints(con)]
    if bad:
        frac, n = max(bad)
        c = con[n]
        return "constraint", (f"constraint {n} ({c['what']}) violated {_pct(frac)} of the run, from "
                              f"{c['first_violated_t_s']:.4g} s")
    most = max(cands)[0] if cands else None
    sat_text = (f"no actuator family saturated {_pct(SATURATION_MIN)} of the run or more (most: "
                f"{_pct(most)})" if most is not None else "no actuator saturation measured")
    return "none", (f"none that rpo measures ({sat_text}, no constraint violated, no divergence): "
                    f"the error is still {final_text} at the end (the run may be too short, or the gains too weak)")
