"""Dispersions the flown configuration reads: a dispersed key that changes nothing a run is handed
is refused when the campaign is read, naming the key and why.

A dispersion of a key the run never reads is drawn, recorded in every summary row and never
applied: its statistics (rank correlations, sensitivities) then describe noise, and the report reads
as if the key had been studied (Basilisk's Monte Carlo, issue 1164).  Two checks, in this order:

1. **Explicit reasons** for the common cases, each one line:

   * a gain of a controller that is not flown (``controller.c001.k_p`` on a campaign flying c000);
   * a parameter of a model the scenario switches off (:data:`SWITCHED`: the dipoles with the
     magnetic torques off, the drag coefficients and areas with drag off, the wheel motors,
     thrusters and PWPF with the ideal actuators, the ideal actuators' limits with the wheels and thrusters,
     J2 with J2 off; not the orbit's orientation in free space, which still sets the target's own
     ECI state, integrated and recorded);
   * an amplitude of a disturbance harmonic whose frequency is zero on every axis (``sin(0 t)``
     is 0), or the frequency of a harmonic whose amplitudes are all zero;
   * the ``value`` of a fault whose kind takes none.

   A rule is not applied when its switch (or the value it depends on) is itself dispersed: the key
   is then read in some runs.  Each rule is checked against the generated code by
   ``tests/test_campaign_reach.py`` (the step function's outputs do not change when the key is
   perturbed with the model off, and do with it on).

2. **The general check**, which cannot miss a key the run's inputs do not depend on: the run's
   inputs (every parameter in SI with the faults' windows and values, the flown controller's
   gains, the initial state as validated: attitudes and their frames, rates, relative position and
   velocity, wheel momenta or speeds, the run settings) are built at the nominal scenario and with
   the key alone perturbed (the distribution's own draws at u = 0.1, 0.9, 0.35, 0.65, then a small
   relative change); a key that leaves them all equal is refused.  A perturbation the scenario refuses is
   skipped (the median check and the per-run validation judge those).

Both need only the manifest (no compiled model), so ``rpo mc run``, ``rpo mc plan``, ``rpo validate``
of a campaign and :func:`~.spec.load_campaign` refuse alike, before any folder exists.  The cost is
one scenario validation per tried perturbation (about a millisecond each).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from rpo.runtime.errors import CampaignError, ScenarioError
from rpo.runtime.scenario import validate_scenario
from rpo.runtime.scenario.faults import describe
from rpo.runtime.scenario.schema import ScenarioSchema

if TYPE_CHECKING:
    from rpo.runtime.campaign.dispersions import Dispersion
    from rpo.runtime.campaign.spec import Campaign
    from rpo.runtime.scenario.schema import Scenario


@dataclass(frozen=True)
class Switched:
    """Parameters (p fields) ``fields`` that the generated model leaves unread when the switches
    ``off`` (p fields, 0 or 1) all equal ``off_value``; ``why`` says which model is off, as the
    scenario writes it."""

    fields: tuple[str, ...]
    off: tuple[str, ...]
    why: str
    off_value: float = 0.0


#: The parameters a switched-off model leaves unread (symbolic/physics/plant.py multiplies each
#: model's terms by its 0/1 switch, so with the switch at 0 the terms are exactly zero).  Checked
#: against the generated step functions by tests/test_campaign_reach.py.
SWITCHED: tuple[Switched, ...] = (
    Switched(("chaser_dipole", "target_dipole", "mu_mag"), ("mag_on",),
             "the magnetic torques are off (environment.magnetic = false)"),
    Switched(("chaser_cd", "chaser_area", "target_cd", "target_area", "target_mass", "omega_earth",
              "earth_flattening"), ("drag_on",), "drag is off (environment.drag = false)"),
    Switched(("j2",), ("j2_on",), "J2 is off (environment.j2 = false)"),
    # not the wheels' tilt, misalignment and inertia: the wheels' stored momentum stays in the body
    # (A h_w, with h_w from the initial wheel speeds and J_w)
    Switched(("wheel_torque_max", "wheel_speed_max", "thruster_force", "thruster_misalign",
              "pwpf_km", "pwpf_tm", "pwpf_uon", "pwpf_uoff", "fdir_allocation"), ("actuators_ideal",),
             "the plant flies the ideal actuators (plant.actuators = \"ideal\"): no wheel motor, thruster or PWPF "
             "acts", off_value=1.0),
    Switched(("force_max", "torque_max"), ("actuators_ideal",),
             "these are the ideal actuators' limits and the plant flies the wheels and thrusters "
             "(plant.actuators = \"wheels_thrusters\")"),
)

#: The scenario disturbance's harmonics: (amplitudes, frequency) p-field suffixes; the sine's
#: amplitude is unread at zero frequency, the frequency when both amplitudes are zero.
HARMONICS = (("a1", "b1", "w1"), ("a2", "b2", "w2"))
#: The uniforms of the draws tried by the general check (every component at u): both tails first.
U_TRIED = (0.1, 0.9, 0.35, 0.65)


def check_reach(camp: Campaign, source: str) -> None:
    """Refuse (:class:`CampaignError`, one line) the first dispersion of ``camp`` whose key the
    flown configuration does not read (see the module's docstring)."""
    if not camp.dispersions:
        return
    manifest = camp.manifest
    schema = ScenarioSchema.of(manifest)
    nominal_sc = validate_scenario(camp.case_data(0, {}, share=True), source, manifest, own=True)
    nominal = flown_inputs(nominal_sc)
    dispersed = {d.key for d in camp.dispersions}
    for d in camp.dispersions:
        why = explicit_reason(d.key, nominal_sc, schema, dispersed)
        if why is None and not reaches(camp, d, nominal, source):
            why = ("changes none of the run's inputs (the parameters, the flown controller's gains, the faults, the "
                   "initial state, the run settings) at the other keys' nominal values")
        if why is not None:
            raise CampaignError(f"{source}: dispersions.{d.key}: the flown configuration never reads it: {why}. Its "
                                "draws would be recorded but never applied: remove this dispersion")


def explicit_reason(key: str, sc: Scenario, schema: ScenarioSchema, dispersed: set[str]) -> str | None:
    """Why the scenario ``sc`` (the campaign's nominal) never reads ``key``, for the common cases;
    None when none applies (``dispersed``: every dispersed key, whose rules are skipped)."""
    parts = key.split(".")
    flown = sc.simulation.controller
    if parts[0] == "controller" and len(parts) == 3 and parts[1] != flown:
        return (f"controller {parts[1]} is not flown, simulation.controller = \"{flown}\" (disperse "
                f"controller.{flown}.<gain> instead)")
    if parts[0] == "faults" and len(parts) == 3 and parts[1].isdigit() and parts[2] == "value":
        n = int(parts[1])
        if n < len(sc.faults) and sc.faults[n].spec.value is None and f"faults.{n}.kind" not in dispersed:
            return f"faults[{n}] is a {sc.faults[n].kind} fault, which takes no value"
    by_key = {prm.key: prm.name for prm in schema.params}
    name = by_key.get(key)
    if name is None:
        return None
    p = sc.params(copy=False)
    keys = {prm.name: prm.key for prm in schema.params}

    def value(field: str) -> np.ndarray:
        return np.ravel(np.asarray(p[field], float))

    for rule in SWITCHED:
        if name not in rule.fields or any(keys.get(s) in dispersed for s in rule.off):
            continue
        if all(np.all(value(s) == rule.off_value) for s in rule.off):
            return rule.why
    for kind in ("force", "torque"):
        for a, b, w in HARMONICS:
            amp, cos, freq = (f"dist_{kind}_{s}" for s in (a, b, w))
            if name == amp and keys.get(freq) not in dispersed and not np.any(value(freq)):
                return f"{keys[freq]} is 0 on every axis, and sin(0 t) = 0"
            if name == freq and keys.get(amp) not in dispersed and keys.get(cos) not in dispersed \
                    and not np.any(value(amp)) and not np.any(value(cos)):
                return f"{keys[amp]} and {keys[cos]} are 0 on every axis: the harmonic is absent"
    return None


def flown_inputs(sc: Scenario) -> dict[str, Any]:
    """What a run of ``sc`` is handed, before the model turns it into vectors (a one-to-one step for
    fixed parameters, so equal here means equal there): every parameter (SI, the faults' windows and
    values included), the flown controller's gains (goal gains included), the initial state as
    validated, the faults and the run settings."""
    out: dict[str, Any] = {f"p.{k}": v for k, v in sc.params(copy=False).items()}
    out.update({f"k.{k}": v for k, v in sc.gains().items()})
    for name in ("chaser", "target"):
        b = getattr(sc, name)
        out[f"{name}.attitude"] = (b.attitude_frame, b.angular_velocity_relative_to)
        out[f"{name}.quaternion"] = np.asarray(b.quaternion, float)
        out[f"{name}.rate"] = b.rate_rad_s()
    out["relative.position"] = np.asarray(sc.relative.position, float)
    out["relative.velocity"] = np.asarray(sc.relative.velocity, float)
    c = sc.chaser
    out["chaser.wheels"] = ("momentum", np.asarray(c.wheel_momentum, float)) if c.wheel_momentum is not None else \
        ("rpm", np.asarray(c.wheel_speed_rpm if c.wheel_speed_rpm is not None else [0.0] * 4, float))
    s = sc.simulation
    out["simulation"] = (s.duration, s.seed, s.controller, s.record_every)
    out["faults"] = describe(sc.faults)
    return out


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True))
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return bool(a == b)


def same_inputs(a: Mapping[str, Any], b: Mapping[str, Any]) -> bool:
    """Whether two :func:`flown_inputs` are equal, entry by entry (NaN equal to NaN)."""
    return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)


def candidates(d: Dispersion) -> list[Any]:
    """Values of ``d``'s key to try: its distribution's draws at :data:`U_TRIED` (for a choice,
    candidates from both ends of its list), then the nominal changed by 0.1 % (a number or an array
    of numbers)."""
    out = []
    with np.errstate(all="ignore"):
        for u in U_TRIED:
            try:
                out.append(d.value(np.full(d.dims, u)))
            except (ValueError, ArithmeticError):
                continue
    nom = d.nominal
    if isinstance(nom, (int, float)) and not isinstance(nom, bool):
        out.append(float(nom) * 1.001 if nom else 1e-3)
    elif isinstance(nom, list) and nom and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in nom):
        out.append([float(x) * 1.001 if x else 1e-3 for x in nom])
    return out


def reaches(camp: Campaign, d: Dispersion, nominal: Mapping[str, Any], source: str) -> bool:
    """Whether some value of ``d``'s key (:func:`candidates`) that the scenario accepts changes the
    run's inputs; True also when no candidate differs from the nominal or is accepted (nothing to
    judge by: the median check and each run's validation speak for those)."""
    judged = False
    for value in candidates(d):
        if _same_value(value, d.nominal):
            continue
        try:
            sc = validate_scenario(camp.case_data(0, {d.key: value}, share=True), source, camp.manifest, own=True)
        except ScenarioError:
            continue
        except Exception:  # a value of the wrong type for the key: the median check names it
            continue
        if not same_inputs(flown_inputs(sc), nominal):
            return True
        judged = True
    return not judged


def _same_value(a: Any, b: Any) -> bool:
    try:
        return bool(np.array_equal(np.asarray(a, float), np.asarray(b, float)))
    except (TypeError, ValueError):
        return a == b
