"""Ranges of every parameter and gain, and the one preflight of ``rpo run`` and ``rpo validate``
(issue 11: bad input refused up front)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import ScenarioError
from rpo.runtime.jobs import runner
from rpo.runtime.model.manifest import Manifest, generated_dir, parse_manifest, read_manifest
from rpo.runtime.run.preflight import preflight
from rpo.runtime.scenario import SCENARIO_DIR, load_scenario, scenario_params
from rpo.runtime.scenario.ranges import ranges_markdown

ROOT = Path(__file__).resolve().parents[1]
III = SCENARIO_DIR / "000_scenario_III.toml"
MANIFEST = read_manifest()


def variant(folder: Path, text: str, manifest: Manifest = MANIFEST, simulation: str = ""):
    """Scenario III, two steps long, with ``text`` (and ``simulation`` keys) merged in (a variant file
    in ``folder``), validated."""
    path = folder / "s.toml"
    path.write_text(f'extends = "{III}"\n[simulation]\nduration = 0.02\n{simulation}' + text)
    return load_scenario(path, manifest)


def test_the_ranges_page_is_current():
    assert (ROOT / "docs" / "parameters.md").read_text() == ranges_markdown(MANIFEST), \
        "run `python -m rpo.runtime.scenario.ranges --write docs/parameters.md`"


def test_every_parameter_and_gain_has_a_finite_range_and_a_reason():
    numeric = [f for f in MANIFEST.layouts["p"]
               if f.scenario is None or f.scenario.kind not in ("switch", "choice")]
    gains = [f for e in MANIFEST.controllers.values() for f in MANIFEST.layouts[e.gains]]
    assert numeric and all(MANIFEST.layouts[e.gains].fields for e in MANIFEST.controllers.values())
    for f in numeric + gains:
        b = f.bounds
        assert b is not None and b.lo is not None and b.hi is not None, f.name
        assert math.isfinite(b.lo) and math.isfinite(b.hi) and b.lo < b.hi, f.name
        assert f.bounds_why, f.name
        values = f.default if f.scenario is None or f.scenario.kind != "inertia" else []
        assert values is not None and all(b.contains(v) for v in values), (f.name, values)
    # sign included: a feedback gain's range starts at 0
    kp = next(f for f in gains if f.name == "kp_att").bounds
    assert kp is not None and kp.lo == 0.0 and not kp.contains(-1e-12)


@pytest.mark.parametrize("path", sorted(SCENARIO_DIR.glob("*.toml")), ids=lambda p: p.stem)
def test_paper_scenarios_are_inside_every_range(path):
    sc = load_scenario(path, MANIFEST)
    for prm in scenario_params(MANIFEST):
        v = sc.get(prm.key)
        if v is not None and prm.kind in ("number", "reciprocal"):
            assert prm.check(v) is None, (prm.key, v)


def test_a_rate_limit_depends_on_the_step(tmp_path):
    gain = "[controller.c000]\nlam_att = 150.0\n"
    with pytest.raises(ScenarioError, match=r"lam_att = 150\.0: \|value\| must be <= 1 / dt = 100 1/s at "
                                            r"simulation\.rate = 100 Hz"):
        variant(tmp_path, gain)
    sc = variant(tmp_path, gain + "[wheels]\ndelay = 0.0\n", simulation="rate = 200.0\n")
    assert sc.gains()["lam_att"][0] == 150.0


def test_a_combination_that_cannot_be_integrated_is_refused_by_the_preflight(model, tmp_path):
    # each value within its range cannot give a nan in step 0; take a range away to reach the backstop
    data = json.loads((generated_dir() / "manifest.json").read_text())
    mass = next(f for f in data["layouts"]["p"] if f["name"] == "chaser_mass")
    mass["bounds"] = {"lo": 0.0, "hi": None, "lo_open": True, "hi_open": False}
    sc = variant(tmp_path, "[chaser]\nmass = 1e-320\nmass_profile = \"constant\"\n", parse_manifest(data))
    with pytest.raises(ScenarioError, match=r"/s\.toml: the first step gives (state|output) \S+ = (nan|inf|-inf) "
                                            r"\(\d+ non-finite\).*at simulation\.rate = 100 Hz$"):
        preflight(sc, model)
    out = tmp_path / "out"
    with pytest.raises(ScenarioError, match="the first step gives"):  # the run refuses it the same way
        runner.execute_run(sc, out, model, plots=False)
    assert not out.exists()


def test_validate_warns_of_a_divergence_that_run_will_meet(model, tmp_path):
    sc = variant(tmp_path, "[chaser]\nangular_velocity_deg_s = [1718.9, 0.0, 0.0]\n")
    pre = preflight(sc, model)
    assert len(pre.notes) == 1 and "w_c_x" in pre.notes[0] and "exit 3" in pre.notes[0]
    z0 = pre.sim.initial_state(pre.inputs.plant)
    np.testing.assert_array_equal(pre.z0, z0)
    assert preflight(load_scenario(III, MANIFEST), model).notes == []


def test_the_runner_goes_through_the_preflight(model, tmp_path, monkeypatch):
    seen = []

    def spy(sc, m):
        seen.append(sc.name)
        raise ScenarioError("stop here")

    monkeypatch.setattr(runner, "preflight", spy)
    with pytest.raises(ScenarioError, match="stop here"):
        runner.execute_run(III, tmp_path / "out", model, duration=0.02, plots=False)
    assert seen == ["000 scenario III"] and not (tmp_path / "out").exists()


def test_preflight_packs_the_parameters_once_with_the_same_bits(tmp_path):
    """The pre-flight hands its Simulation the parameter vector packed on the way to the initial
    state: the same bytes as packing the run's parameters afresh, its own array, and the inputs
    the same as ``to_run``'s."""
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.run.simulate import Simulation

    model = load_model("auto")
    sc = variant(tmp_path, "[chaser]\nmass = 97.5\n", model.manifest)
    pre = preflight(sc, model)
    fresh = Simulation(model, pre.inputs.controller, params=pre.inputs.params, gains=pre.inputs.gains)
    assert pre.sim.p.tobytes() == fresh.p.tobytes() == model.vector("p", sc.to_run(model).params).tobytes()
    assert not np.shares_memory(pre.sim.p, pre.inputs.params["chaser_mass"])
    assert pre.z0.tobytes() == fresh.initial_state(pre.inputs.plant).tobytes()
