"""First use: a model compiles only what is called, a step only the plant copies its parameters select,
and the result is bit-identical to the whole library's; a long compile says so at least every few
seconds."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.model import library
from rpo.runtime.model.loader import load_model
from rpo.runtime.model.selection import STUB_RETURN, callees, stub_source, variant_choice
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1]


def _sim(model, scenario: str):
    run = load_scenario(ROOT / "scenarios" / scenario).to_run(model)
    sim = Simulation(model, run.controller, params=run.params, gains=run.gains)
    return sim, sim.initial_state(run.plant), run


def test_a_fresh_model_compiles_nothing_and_a_run_only_its_plant_copy():
    lines: list[str] = []
    model = load_model(log=lines.append)
    assert model.library is None and model._lib_set == frozenset()
    sim, z0, _run = _sim(model, "001_scenario.toml")
    held = model._lib_set
    # 001 flies c001 on a Keplerian target orbit with disturbances: plant_advance_kepler only
    assert {"step_c001", "control_c001", "plant_advance_kepler", "measure_kepler"} <= held
    assert not held & {"plant_jac", "plant_advance", "plant_advance_kepler_nodist", "step_c000", "law_c001"}
    sim.run(z0, 0.5, seed=1)
    assert model._lib_set == held  # flying it needed nothing more


def test_a_function_is_resolved_once_not_on_every_call(model, monkeypatch):
    """``model.plant_rhs(...)`` asks what the function needs on every attribute access: the callee
    graph is parsed once per (names, parameters), else a compiled call costs the parse (1 ms)."""
    from rpo.runtime.model import selection

    seen: list[int] = []
    real = selection.callees
    monkeypatch.setattr(selection, "callees", lambda text: seen.append(1) or real(text))
    f = model.function("step_c001")
    parses = len(seen)
    for _ in range(5):
        assert model.function("step_c001") is f and model.step_c001 is f
    assert len(seen) == parses


@pytest.mark.parametrize("variant", ["plant_advance_kepler_nodist", "plant_advance_kepler", "plant_advance"])
def test_the_python_rule_picks_the_copy_the_c_dispatch_calls(model, variant):
    """A library holding only the copy rpo's rule picks (the others are stubs that return an error):
    if the C dispatch chose another copy, the run would stop at its first step."""
    fresh = load_model(log=None)
    sim_full, z0, run = _sim(model, "000_scenario_III.toml")
    p = sim_full.p.copy()
    offs = model.offsets("p")
    zero = {s.function: s.zero for s in model.manifest.specialised["plant_advance"]}
    for f in (*zero.get("plant_advance_kepler_nodist", ()), *zero.get("plant_advance_kepler", ())):
        p[offs[f]] = 0.0
    if variant != "plant_advance_kepler_nodist":
        p[offs["dist_force_c0"]] = 1e-4  # a constant disturbance force: not the no-disturbance copy
    if variant == "plant_advance":
        p[offs["orbit_propagated"]] = 1.0
        z0 = z0.copy()
    assert variant_choice(model.manifest, offs, "plant_advance", p[None]) == [variant]
    sim = Simulation(fresh, run.controller, gains=run.gains, packed_p=p)
    assert variant in fresh._lib_set
    others = {"plant_advance_kepler_nodist", "plant_advance_kepler", "plant_advance"} - {variant}
    assert not fresh._lib_set & others
    if variant == "plant_advance":  # the propagated target orbit starts on the Keplerian one
        z0 = sim.initial_state(run.plant)
    alone = sim.run(z0, 0.3, seed=2)
    assert alone.divergence is None and alone.steps_done == alone.steps_requested
    whole = Simulation(model, run.controller, gains=run.gains, packed_p=p).run(z0, 0.3, seed=2)
    assert np.array_equal(alone.z, whole.z) and np.array_equal(alone.y, whole.y, equal_nan=True)


def test_a_batch_whose_cases_select_two_copies_links_both_and_equals_the_single_runs():
    model = load_model(log=None)
    sim, z0, _run = _sim(model, "001_scenario.toml")
    p2 = sim.p.copy()
    offs = model.offsets("p")
    for s in model.manifest.specialised["plant_advance"]:
        if s.function == "plant_advance_kepler_nodist":
            for f in s.zero:
                p2[offs[f]] = 0.0
    P = np.array([sim.p, p2])
    assert set(variant_choice(model.manifest, offs, "plant_advance", P)) == {"plant_advance_kepler_nodist",
                                                                            "plant_advance_kepler"}
    out = sim.run_batch(np.array([z0, z0]), 0.2, seeds=[1, 2], params=P)
    assert {"plant_advance_kepler_nodist", "plant_advance_kepler"} <= model._lane_set
    for i in range(2):
        one = Simulation._with(sim, P[i], sim.k).run(z0, 0.2, seed=i + 1)
        assert np.array_equal(one.z, out[i].z)
    scalar = sim.run_batch(np.array([z0, z0]), 0.2, seeds=[1, 2], params=P, lanes=False)
    assert all(np.array_equal(a.z, b.z) for a, b in zip(out, scalar, strict=True))


def test_callees_and_stubs():
    step = (ROOT / "generated" / "step_c001.c").read_text()
    assert callees(step) == ["measure", "measure_kepler", "control_c001", "plant_advance",
                             "plant_advance_kepler_nodist", "plant_advance_kepler"]
    assert callees((ROOT / "generated" / "plant_rhs.c").read_text()) == []
    text = stub_source(["b", "a"], lanes=False).decode()
    assert text.index("int a(") < text.index("int b(") and f"return {STUB_RETURN};" in text
    assert "a_lanes(const rpo_v**" in stub_source(["a"], lanes=True).decode()


def test_a_long_compile_prints_a_line_at_least_every_heartbeat(tmp_path, monkeypatch):
    """One file that takes longer than the heartbeat: lines keep coming while it compiles."""
    monkeypatch.setattr(library, "HEARTBEAT_S", 0.2)

    def slow(cc, name, src, obj, flags=None):
        time.sleep(1.0)
        obj.write_bytes(b"")
        return 1.0

    monkeypatch.setattr(library, "compile_object", slow)
    monkeypatch.setattr(library, "run_cc", lambda cmd, what, cc: open(cmd[cmd.index("-o") + 1], "wb").close())
    stamps: list[tuple[float, str]] = []
    lock = threading.Lock()

    def log(line: str) -> None:
        with lock:
            stamps.append((time.perf_counter(), line))

    objs = [("big.c", b"x" * 100, tmp_path / "obj" / "big.o")]
    (tmp_path / "obj").mkdir()
    library._compile_and_link(["cc"], objs, tmp_path / "lib.so", tmp_path, log, 1, None, "a test library")
    assert any("... compiling big.c" in s for _t, s in stamps)
    gaps = np.diff([t for t, _s in stamps])
    assert gaps.max() < 0.2 + 0.3
