"""A dispersion of a key the flown configuration does not read is refused (runtime/campaign/reach.py).

* every dispersed key of every shipped campaign changes what the simulation is handed (the packed
  parameter and gain vectors and the initial state of the pre-flight: what the lockstep loop gets);
* each rule of ``reach.SWITCHED`` holds in the generated code: with the model off, perturbing its
  parameters leaves the step function's outputs unchanged at several states, with it on they change;
* the refusals: the key named, the reason given, exit 2 and nothing written.
"""

from __future__ import annotations

import copy
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.campaign import reach
from rpo.runtime.campaign.spec import load_campaign
from rpo.runtime.errors import CampaignError
from rpo.runtime.run import noise
from rpo.runtime.run.preflight import preflight
from rpo.runtime.scenario import read_scenario, validate_scenario
from rpo.runtime.scenario.schema import ScenarioSchema

ROOT = Path(__file__).resolve().parent.parent
CAMPAIGNS = ROOT / "scenarios" / "campaigns"
FILES = sorted(CAMPAIGNS.glob("*.toml"))


def _handed(model, camp, draws):
    """(p, k, z0) handed to the simulation for the campaign's case 0 with ``draws``."""
    sc = validate_scenario(camp.case_data(0, draws), "case", model.manifest)
    pre = preflight(sc, model)
    return pre.sim.p.copy(), pre.sim.k.copy(), pre.z0.copy()


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_every_dispersed_key_changes_the_simulated_inputs(path, model):
    camp = load_campaign(path, model.manifest)
    base = _handed(model, camp, {})
    for d in camp.dispersions:
        changed = False
        for value in reach.candidates(d):
            try:
                got = _handed(model, camp, {d.key: value})
            except Exception:  # a candidate the scenario refuses: the next one
                continue
            if any(not np.array_equal(a, b) for a, b in zip(got, base, strict=True)):
                changed = True
                break
        assert changed, f"{path.name}: dispersions.{d.key} changes none of p, k, z0"


def _data(model, name, **fields):
    """Scenario ``name``'s table with p fields set (by field name, SI values), without its faults."""
    src = read_scenario(ROOT / "scenarios" / f"{name}.toml")
    data = copy.deepcopy(src.data)
    schema = ScenarioSchema.of(model.manifest)
    for field, v in fields.items():
        prm = schema.param(field)
        *tables, leaf = prm.key.split(".")
        node = data
        for t in tables:
            node = node.setdefault(t, {})
        node[leaf] = prm.to_scenario(np.ravel(np.asarray(v, float)).tolist())
    data.pop("faults", None)
    return data


def _preflight(model, data):
    sc = validate_scenario(data, "probe", model.manifest)
    return sc, preflight(sc, model)


def _outputs(pre):
    """The step function's next state and outputs over 300 steps from the initial state, with a
    fixed noise: what a run reads of its parameters and initial state."""
    sim = pre.sim
    z = pre.z0.copy()
    out = []
    for i in range(300):
        w = noise.noise(5, i, 1, sim.nw)[0]
        z1, y = sim.step_fn(z, i * sim.dt, sim.p, sim.k, w)
        if i % 50 == 0 or i < 3:
            out.append(np.concatenate([np.ravel(z1), np.ravel(y)]))
        z = np.ravel(np.asarray(z1, float))
    return np.concatenate(out)


def _perturbed_outputs(model, name, switches, field):
    """:func:`_outputs` of scenario ``name`` (with ``switches``) with p field ``field`` changed in
    the scenario file (so that what it changes in the initial state is included): a switch or
    choice flipped, a number by 2 % (0.01 where it is 0)."""
    sc, _ = _preflight(model, _data(model, name, **switches))
    v = np.ravel(np.asarray(sc.params()[field], float))
    kind = ScenarioSchema.of(model.manifest).param(field).kind
    new = 1.0 - v if kind in ("switch", "choice") else np.where(v == 0.0, 0.01, v * 1.02)
    return _outputs(_preflight(model, _data(model, name, **switches, **{field: new}))[1])


#: (scenario, switches) where each rule's model is off and where it is on (000 scenario III has
#: every environment term and the wheels and thrusters on)
OFF_ON = {
    "mag_on": (("000_scenario_III", {"mag_on": 0}), ("000_scenario_III", {})),
    "drag_on": (("000_scenario_III", {"drag_on": 0}), ("000_scenario_III", {})),
    "j2_on": (("000_scenario_III", {"j2_on": 0}), ("000_scenario_III", {})),
    "actuators_ideal": (("000_III_ideal", {}), ("000_scenario_III", {})),
    "force_max": (("000_scenario_III", {}), ("000_III_ideal", {})),
}


@pytest.mark.parametrize("rule", reach.SWITCHED, ids=[r.fields[0] for r in reach.SWITCHED])
def test_each_switched_rule_holds_in_the_generated_code(rule, model):
    key = "force_max" if rule.fields[0] == "force_max" else rule.off[0]
    (off_name, off_sw), (on_name, on_sw) = OFF_ON[key]
    sc, pre = _preflight(model, _data(model, off_name, **off_sw))
    p = sc.params(copy=False)
    assert all(float(np.ravel(p[s])[0]) == rule.off_value for s in rule.off), "the 'off' scenario has the model on"
    base = _outputs(pre)
    for field in rule.fields:
        assert np.array_equal(_perturbed_outputs(model, off_name, off_sw, field), base), \
            f"{field} is read with {rule.why}"
    # the same perturbations with the model on: the probe sees them (else the check above proves nothing)
    base = _outputs(_preflight(model, _data(model, on_name, **on_sw))[1])
    seen = [f for f in rule.fields if not np.array_equal(_perturbed_outputs(model, on_name, on_sw, f), base)]
    assert seen, f"none of {rule.fields} changes the outputs with the model on"


@pytest.mark.parametrize("kind", ["force", "torque"])
def test_harmonic_rules_hold_in_the_generated_code(kind, model):
    """001's disturbance has no first harmonic (sin1 = cos1 = omega1 = 0): its amplitude and its
    frequency are unread; with the other one non-zero, each is read."""
    amp, freq = f"dist_{kind}_a1", f"dist_{kind}_w1"
    base = _outputs(_preflight(model, _data(model, "001_scenario"))[1])
    for field in (amp, freq):
        assert np.array_equal(_perturbed_outputs(model, "001_scenario", {}, field), base), field
    for field, other in ((amp, freq), (freq, amp)):
        sw = {other: [0.01, 0.02, 0.03]}
        on = _outputs(_preflight(model, _data(model, "001_scenario", **sw))[1])
        assert not np.array_equal(_perturbed_outputs(model, "001_scenario", sw, field), on), field


# ------------------------------------------------------------------------------- refusals


def _extend(tmp_path, base, text, name="c.toml"):
    f = tmp_path / name
    f.write_text(f'extends = "{(CAMPAIGNS / base).as_posix()}"\n{text}')
    return f


REFUSED = {
    "controller-not-flown": ("001_mc_c000.toml", "[dispersions.controller.c001.k_p]\ndist = 'normal'\nrel_std = 0.1\n",
                             "controller.c001.k_p", 'controller c001 is not flown, simulation.controller = "c000"'),
    "magnetic-off": ("001_mc.toml", "[dispersions.target.dipole]\ndist = 'normal'\nstd = 0.1\n",
                     "target.dipole", "the magnetic torques are off"),
    "drag-off": ("001_mc.toml", "[dispersions.target.drag_area]\ndist = 'normal'\nrel_std = 0.1\n",
                 "target.drag_area", "drag is off"),
    "ideal-limit-on-wheels": ("000_III_mc.toml", "[dispersions.plant.max_force]\ndist = 'normal'\nrel_std = 0.1\n",
                              "plant.max_force", "ideal actuators' limits"),
    "wheels-on-ideal": ("001_mc.toml", "[dispersions.wheels.max_torque]\ndist = 'normal'\nrel_std = 0.1\n",
                        "wheels.max_torque", "the plant flies the ideal actuators"),
    "sine-at-zero-frequency": ("001_mc.toml", "[dispersions.disturbance.force.sin1]\ndist = 'normal'\nstd = 0.001\n",
                               "disturbance.force.sin1", "omega1 is 0 on every axis"),
    "fault-takes-no-value": ("000_III_mc.toml",
                             "[dispersions.faults.0.value]\ndist = 'normal'\nmean = 0.5\nstd = 0.1\n",
                             "faults.0.value", "wheel_off fault, which takes no value"),
    "j2-off": ("002_mc.toml", "[dispersions.environment.constants.j2]\ndist = 'normal'\nrel_std = 0.01\n",
               "environment.constants.j2", "J2 is off"),
}


@pytest.mark.parametrize("case", REFUSED, ids=list(REFUSED))
def test_refused_naming_the_key_and_why(case, tmp_path, model):
    base, text, key, why = REFUSED[case]
    with pytest.raises(CampaignError) as exc:
        load_campaign(_extend(tmp_path, base, text), model.manifest)
    msg = str(exc.value)
    assert "\n" not in msg
    assert f"dispersions.{key}: the flown configuration never reads it" in msg and why in msg, msg


def test_switch_dispersed_too_is_accepted(tmp_path, model):
    """A dipole read in the runs where the dispersed switch turns the magnetic torques on."""
    text = ("[dispersions.target.dipole]\ndist = 'normal'\nstd = 0.1\n"
            "[dispersions.environment.magnetic]\ndist = 'choice'\nvalues = [true, false]\n")
    camp = load_campaign(_extend(tmp_path, "001_mc.toml", text), model.manifest)
    assert {"target.dipole", "environment.magnetic"} <= {d.key for d in camp.dispersions}


def test_the_general_check_alone_catches_a_controller_not_flown(tmp_path, model, monkeypatch):
    """Without the explicit reasons, comparing the run's inputs still refuses the key."""
    monkeypatch.setattr(reach, "explicit_reason", lambda *a, **k: None)
    f = _extend(tmp_path, "001_mc_c000.toml", REFUSED["controller-not-flown"][1])
    with pytest.raises(CampaignError, match=r"dispersions\.controller\.c001\.k_p: .*changes none of the run's inputs"):
        load_campaign(f, model.manifest)


def _rpo(*args):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], env=env,
                          capture_output=True, text=True, timeout=300)


def test_cli_refuses_before_writing(tmp_path, model):
    f = _extend(tmp_path, *REFUSED["controller-not-flown"][:2])
    out = tmp_path / "mc"
    for args in (("mc", "run", f, "--out", out, "--runs", "4"), ("validate", f)):
        res = _rpo(*args)
        assert res.returncode == 2, (args, res.stderr)
        assert "dispersions.controller.c001.k_p" in res.stderr and "Traceback" not in res.stderr
        assert not out.exists()
