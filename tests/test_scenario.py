"""rpo.runtime.scenario: the shipped scenarios load and map to a valid z0; bad input gives one-line errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime import frames as fr
from rpo.runtime.errors import ScenarioError
from rpo.runtime.model.manifest import read_manifest
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import load_scenario, loads_scenario, paper_data, validate_scenario

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = sorted((ROOT / "scenarios").glob("000_scenario_*.toml"))
III = ROOT / "scenarios" / "000_scenario_III.toml"

MINIMAL = """
[simulation]
duration = 1.0
[chaser]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[target]
attitude_frame = "eci"
quaternion = [0, 0, 0, 1]
[relative]
position = [10.0, 0.0, 0.0]
velocity = [0.0, 0.0, 0.0]
"""


@pytest.fixture(scope="module")
def model():
    from rpo.runtime.model.loader import load_model
    return load_model()


def scalar(params, name):
    return float(np.ravel(params[name])[0])


# --------------------------------------------------------------------------- the shipped scenarios


def test_three_scenarios_exist():
    assert [p.name for p in SCENARIOS] == ["000_scenario_I.toml", "000_scenario_II.toml", "000_scenario_III.toml"]


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_scenario_maps_to_valid_z0(model, path):
    sc = load_scenario(path)
    sim_table = paper_data(path)["simulation"]
    run = sc.to_run(model)
    sim = Simulation(model, run.controller, params=run.params, gains=run.gains)
    z0 = sim.initial_state(run.plant)
    assert np.all(np.isfinite(z0))
    assert run.duration == sim_table["duration"] and run.controller == sim_table["controller"] == "c000"
    assert run.dt == pytest.approx(1 / sim_table["rate"])
    offs = model.offsets(f"z_{run.controller}")
    for q in ("q_c", "q_t"):
        assert np.linalg.norm(z0[offs[q]]) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_array_equal(z0[offs["r"]], sc.relative.position)
    np.testing.assert_array_equal(z0[offs["v"]], sc.relative.velocity)
    # the paper's relative attitude q_t^-1 q_c is kept whatever the attitude frame
    rel = fr.quat_multiply(fr.quat_conjugate(run.plant["q_t"]), run.plant["q_c"])
    rel_typed = fr.quat_multiply(fr.quat_conjugate(sc.target.quaternion), sc.chaser.quaternion)
    np.testing.assert_allclose(rel, rel_typed, atol=1e-12)
    # wheels at rest relative to the body: the generated env_outputs agrees
    p = model.vector("p", run.params)
    x = model.vector("x", {**run.plant, "m_prop": 0.0})
    env = model.functions["env_outputs"](x, np.zeros(model.layout_size("u")), 0.0, p,
                                         np.zeros(model.layout_size("w")))[0]
    np.testing.assert_allclose(np.ravel(env)[model.offsets("env")["wheel_speed"]], 0.0, atol=1e-12)


def target_inertia(params) -> dict[str, float]:
    return dict(zip(("xx", "yy", "zz", "xy", "xz", "yz"), np.ravel(params["target_inertia"]), strict=True))


def test_scenario_III_values(model):
    sc = load_scenario(III)
    paper = paper_data("000_scenario_III")
    run = sc.to_run(model)
    r_e = scalar(run.params, "r_earth")
    orbit = paper["orbit"]
    assert scalar(run.params, "orbit_a") * (1 - orbit["eccentricity"]) == pytest.approx(
        r_e + orbit["perigee_altitude"], rel=1e-14)
    assert scalar(run.params, "orbit_inc") == pytest.approx(math.radians(orbit["inclination_deg"]))
    assert scalar(run.params, "orbit_argp") == pytest.approx(math.radians(orbit["arg_perigee_deg"]))
    # the paper's omega_t(0) = [(1 - L) s / cos(g), 2 s L, 1.2 L], s = 0.1, g = 0.5, L = 1 - I_t22 / I_t11
    I_t = target_inertia(run.params)
    L = 1 - I_t["yy"] / I_t["xx"]
    np.testing.assert_allclose(run.plant["w_t"], [(1 - L) * 0.1 / math.cos(0.5), 0.2 * L, 1.2 * L], atol=1e-9)
    np.testing.assert_array_equal(run.plant["w_c"], 0.0)
    np.testing.assert_array_equal(run.gains["r_goal"], paper["controller"]["c000"]["r_goal"])
    # attitudes were given relative to the orbit frame R
    q_IL = run.frame_info["q_IL0"]
    np.testing.assert_allclose(fr.attitude_from_eci(run.plant["q_t"], "orbit", q_IL),
                               fr.quat_normalize(paper["target"]["quaternion"]), atol=1e-12)


def test_scenario_I_target_is_nadir_pointing_in_geo(model):
    run = load_scenario(ROOT / "scenarios" / "000_scenario_I.toml").to_run(model)
    paper = paper_data("000_scenario_I")
    mu, a = scalar(run.params, "mu"), scalar(run.params, "orbit_a")
    assert a == paper["orbit"]["semi_major_axis"] and scalar(run.params, "orbit_e") == paper["orbit"]["eccentricity"]
    n = math.sqrt(mu / a**3)
    assert run.frame_info["n0"] == pytest.approx(n, rel=1e-12)
    assert n == pytest.approx(7.2922e-5, rel=1e-4)  # geostationary: one turn per sidereal day
    np.testing.assert_allclose(run.plant["w_t"], [0, -n, 0], atol=1e-15)  # zero rate relative to R
    o = model.functions["target_orbit"](0.0, model.vector("p", run.params))
    r_eci = np.ravel(o[5])
    C_IT = fr.dcm_from_quat(run.plant["q_t"])
    np.testing.assert_allclose(C_IT[:, 2], -r_eci / np.linalg.norm(r_eci), atol=1e-12)  # body Z to nadir
    np.testing.assert_allclose(run.plant["w_c"], np.radians(paper["chaser"]["angular_velocity_deg_s"]))


def test_scenario_II_goal_and_rates(model):
    run = load_scenario(ROOT / "scenarios" / "000_scenario_II.toml").to_run(model)
    paper = paper_data("000_scenario_II")
    np.testing.assert_array_equal(run.gains["r_goal"], paper["controller"]["c000"]["r_goal"])
    np.testing.assert_allclose(run.plant["w_t"], np.radians(paper["target"]["angular_velocity_deg_s"]))


def test_paper_data_resolves_extends():
    """paper_data is the merged table a run flies: a variant gets its base's values."""
    var, base = paper_data("000_III_no_acc_d"), paper_data("000_scenario_III")
    assert var["controller"]["c000"]["acc_d_on"] == 0.0 != base["controller"]["c000"]["acc_d_on"]
    assert var["orbit"] == base["orbit"] and var["relative"] == base["relative"]
    assert "reproduction" in base and var["reproduction"] != base["reproduction"]  # each file's own table
    assert paper_data(III) == base


# --------------------------------------------------------------------------- defaults and mapping


def test_omitted_values_fall_back_to_the_manifest(model):
    sc = loads_scenario(MINIMAL, "minimal.toml")
    assert sc.param_overrides() == {}
    run = sc.to_run(model)
    defaults = model.defaults("p")
    assert run.params.keys() == defaults.keys()
    for k, v in defaults.items():
        np.testing.assert_array_equal(run.params[k], v, err_msg=k)
    for k, v in model.defaults("k_baseline").items():
        np.testing.assert_array_equal(run.gains[k], v, err_msg=k)
    assert sc.name == "minimal" and run.seed == 0 and run.record_every == 1


def test_keys_map_to_parameters_in_SI(model):
    text = MINIMAL.replace("[simulation]", "[simulation]\nrate = 50.0") + """
[orbit]
perigee_altitude = 500e3
eccentricity = 0.1
inclination_deg = 90.0
[environment]
drag = false
[environment.constants]
r_earth = 6371000.0
[wheels]
tilt_deg = 45.0
max_speed_rpm = 6000.0
[thrusters]
pwpf = { u_on = 0.5, u_off = 0.2 }
"""
    text = text.replace('[chaser]\n', '[chaser]\nmass_profile = "constant"\nmass = 120\n'
                        'inertia = [[10, 1, 0], [1, 12, 0.5], [0, 0.5, 14]]\n')
    p = loads_scenario(text, "t.toml").to_run(model).params
    assert scalar(p, "dt") == 0.02
    assert scalar(p, "orbit_a") == pytest.approx((6371000.0 + 500e3) / 0.9)
    assert scalar(p, "orbit_inc") == pytest.approx(math.pi / 2)
    assert scalar(p, "drag_on") == 0.0 and scalar(p, "j2_on") == 1.0
    assert scalar(p, "wheel_beta") == pytest.approx(math.pi / 4)
    assert scalar(p, "wheel_speed_max") == pytest.approx(6000 * 2 * math.pi / 60)
    assert scalar(p, "pwpf_uon") == 0.5 and scalar(p, "pwpf_uoff") == 0.2
    assert scalar(p, "mass_profile_on") == 0.0 and scalar(p, "chaser_mass") == 120.0
    labels = [lbl.rsplit("_", 1)[1] for lbl in model.labels("p") if lbl.startswith("chaser_inertia_")]
    I = {"xx": 10, "yy": 12, "zz": 14, "xy": 1, "xz": 0, "yz": 0.5}
    np.testing.assert_array_equal(p["chaser_inertia"], [I[c] for c in labels])


def test_wheel_speed_and_rate_relative_to_frame(model):
    text = MINIMAL.replace('[chaser]\nattitude_frame = "eci"', '[chaser]\nattitude_frame = "lvlh"') + ""
    text = text.replace("[target]", 'angular_velocity_deg_s = [1.0, 2.0, 3.0]\n'
                        'wheel_speed_rpm = [100.0, -200.0, 0.0, 50.0]\n[target]')
    text = text.replace('[target]\nattitude_frame = "eci"',
                        '[target]\nattitude_frame = "lvlh"\nangular_velocity_relative_to = "attitude_frame"')
    run = loads_scenario(text, "t.toml").to_run(model)
    n = run.frame_info["n0"]
    np.testing.assert_allclose(run.plant["w_t"], [0, 0, n], atol=1e-18)  # fixed in LVLH
    np.testing.assert_allclose(run.plant["w_c"], np.radians([1, 2, 3]))
    p = model.vector("p", run.params)
    x = model.vector("x", {**run.plant, "m_prop": 0.0})
    env = model.functions["env_outputs"](x, np.zeros(model.layout_size("u")), 0.0, p,
                                         np.zeros(model.layout_size("w")))[0]
    np.testing.assert_allclose(np.ravel(env)[model.offsets("env")["wheel_speed"]] * 60 / (2 * math.pi),
                               [100, -200, 0, 50], rtol=1e-10)


def test_near_unit_quaternion_is_normalised():
    sc = loads_scenario(MINIMAL.replace("quaternion = [0, 0, 0, 1]", "quaternion = [0, 0, 0, 1.0009]", 1), "t")
    assert np.linalg.norm(sc.chaser.quaternion) == pytest.approx(1.0, abs=1e-15)


def test_overrides_are_revalidated():
    sc = load_scenario(III)
    short = sc.with_overrides(duration=2.0, seed=7)
    assert short.simulation.duration == 2.0 and short.simulation.seed == 7
    assert sc.simulation.duration == 300.0
    assert short.text == sc.text
    with pytest.raises(ScenarioError, match=r"simulation\.duration = 0\.001: must be at least one step"):
        sc.with_overrides(duration=0.001)


# --------------------------------------------------------------------------- bad input

BASE = III.read_text()


def replaced(old: str, new: str) -> str:
    assert old in BASE, old
    return BASE.replace(old, new, 1)


Q_T = "quaternion = [" + ", ".join(map(str, paper_data(III)["target"]["quaternion"])) + "]"
BAD = {
    "non-unit quaternion": (replaced(Q_T, "quaternion = [0.5, 0.5, 0.5, 0.6]"),
                            "target.quaternion = [0.5, 0.5, 0.5, 0.6]: must be a unit quaternion", "1.05357"),
    "quaternion length": (replaced(Q_T, "quaternion = [0.5, 0.5, 0.5]"), "target.quaternion", "must have 4 values"),
    "eccentricity >= 1": (replaced("eccentricity = 0.138", "eccentricity = 1.2"),
                          "orbit.eccentricity = 1.2: must be in [0, 1)", None),
    "eccentricity = 1": (replaced("eccentricity = 0.138", "eccentricity = 1.0"), "orbit.eccentricity", "[0, 1)"),
    "perigee below surface": (replaced("perigee_altitude = 400e3", "semi_major_axis = 7000e3")
                              .replace("eccentricity = 0.138", "eccentricity = 0.2"),
                              "orbit.semi_major_axis = 7000000.0: perigee below the surface", "6378137"),
    "negative perigee altitude": (replaced("perigee_altitude = 400e3", "perigee_altitude = -1e3"),
                                  "orbit.perigee_altitude = -1000.0", "must be > 0"),
    "non-PD inertia": (replaced("[chaser]\n", "[chaser]\ninertia = [[11, 0, 0], [0, -14, 0], [0, 0, 13]]\n"),
                       "chaser.inertia", "positive definite"),
    "asymmetric inertia": (replaced("[chaser]\n", "[chaser]\ninertia = [[11, 1, 0], [0, 14, 0], [0, 0, 13]]\n"),
                           "chaser.inertia", "symmetric"),
    "triangle inequality": (replaced("[target]\n", "[target]\ninertia = [[1, 0, 0], [0, 1, 0], [0, 0, 3]]\n"),
                            "target.inertia", "triangle inequality"),
    "negative mass": (replaced("[chaser]\n", "[chaser]\nmass = -100.0\n"), "chaser.mass = -100.0: must be > 0 kg",
                      None),
    "unknown key": (replaced("[chaser]\n", "[chaser]\nmasss = 100.0\n"), "chaser.masss = 100.0: unknown key",
                    "did you mean 'mass'"),
    "unknown table": (BASE + "\n[foo]\nbar = 1\n", "foo = { bar = 1 }: unknown key", None),
    "unknown gain": (replaced("r_goal = [5.0", "r_gaol = [5.0"), "controller.baseline.r_gaol", "unknown key"),
    "wrong type": (replaced("duration = 300.0", 'duration = "300"'), 'simulation.duration = "300": must be a number',
                   None),
    "wrong type bool": (replaced("j2 = true", "j2 = 1"), "environment.j2 = 1: must be true or false", None),
    "wrong type int": (replaced("seed = 0 ", "seed = 1.5 "), "simulation.seed = 1.5: must be an integer", None),
    "bad frame": (replaced('attitude_frame = "orbit"', 'attitude_frame = "body"'), "chaser.attitude_frame", "'eci'"),
    "missing table": (BASE.split("[relative]")[0], "relative: required table is missing", None),
    "not finite": (replaced("duration = 300.0", "duration = nan"), "simulation.duration = nan", "finite"),
    "wheel delay": (BASE + "\n[wheels]\ndelay = 0.05\n", "wheels.delay = 0.05", "[0, 0.04)"),
    "pwpf levels": (BASE + "\n[thrusters]\npwpf = { u_on = 0.1, u_off = 0.15 }\n", "thrusters.pwpf.u_off = 0.15",
                    "u_off < u_on"),
    "unknown controller": (replaced('controller = "c000"', 'controller = "nope"'), "simulation.controller",
                           "available: baseline"),
    "bad TOML": (replaced("duration = 300.0", "duration = = 300.0"), "invalid TOML", "line 21"),
}


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_bad_input_gives_one_line_naming_the_field(case):
    text, must, also = BAD[case]
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text, "scenario.toml")
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith("scenario.toml: ")
    assert must in msg
    if also:
        assert also in msg


def test_bad_file(tmp_path):
    with pytest.raises(ScenarioError, match="cannot read the scenario"):
        load_scenario(tmp_path / "missing.toml")
    bad = tmp_path / "latin1.toml"
    bad.write_bytes(b"[meta]\nname = '\xe9'\n")
    with pytest.raises(ScenarioError, match="latin1.toml: cannot read"):
        load_scenario(bad)


def test_initial_wheel_speed_above_the_limit_is_refused(model):
    text = (ROOT / "scenarios" / "000_scenario_III.toml").read_text()
    text = text.replace("wheel_speed_rpm = [0.0, 0.0, 0.0, 0.0]", "wheel_speed_rpm = [8000.0, 0.0, 0.0, 0.0]")
    assert "8000.0" in text
    with pytest.raises(ScenarioError, match=r"chaser.wheel_speed_rpm = .*<= wheels.max_speed_rpm = 7000 rpm"):
        loads_scenario(text, "s.toml").to_run(model)


def test_extends_merges_tables_and_refuses_cycles(tmp_path):
    """A variant file names its base and gives only what differs; a cycle is a one-line error."""
    base = load_scenario(ROOT / "scenarios" / "000_scenario_III.toml")
    var = load_scenario(ROOT / "scenarios" / "000_III_no_acc_d.toml")
    assert var.controller["c000"]["acc_d_on"] == 0.0 and base.controller["c000"]["acc_d_on"] == 1.0
    # everything else, including the rest of the same table, is the base's
    assert var.controller["c000"]["acc_d"] == base.controller["c000"]["acc_d"]
    assert var.params().keys() == base.params().keys()
    for k, v in base.params().items():
        assert np.array_equal(var.params()[k], v), k
    (tmp_path / "a.toml").write_text('extends = "b.toml"\n')
    (tmp_path / "b.toml").write_text('extends = "a.toml"\n')
    with pytest.raises(ScenarioError, match="cycle"):
        load_scenario(tmp_path / "a.toml")


# --------------------------------------------------------------------------- the schema comes from the manifest


@pytest.fixture
def manifest():
    """The generated manifest's JSON data (a copy), to patch what symbolic/ declared; :func:`typed`
    makes the typed manifest a scenario is validated against."""
    import json

    from rpo.runtime.model.manifest import generated_dir
    return json.loads((generated_dir() / "manifest.json").read_text())


def typed(data):
    """The typed manifest of (patched) manifest data."""
    from rpo.runtime.model.manifest import parse_manifest
    return parse_manifest(data)


def p_field(manifest, name):
    return next(f for f in manifest["layouts"]["p"] if f["name"] == name)


def test_every_parameter_has_a_scenario_key_and_the_old_keys_are_kept(manifest):
    # the fault parameters are set by the [[faults]] array instead: every one of them by some entry
    from rpo.runtime.scenario.faults import fault_model, fault_params

    faults = [f for f in manifest["layouts"]["p"] if f["name"].startswith("fault_")]
    defaults = {f["name"]: f["default"] for f in faults}
    m = typed(manifest)
    Fault, vocab = fault_model(m), m.faults
    reached: set[str] = set()
    for kind, spec in vocab.kinds.items():  # every unit of every kind
        family = vocab.families[spec.family]
        for i, label in enumerate(family.units):
            u = label if family.first is None else family.first + i
            v = None if spec.value is None else ([0.5] * spec.value.shape if spec.value.shape > 1 else 0.5)
            reached |= set(fault_params([Fault(kind=kind, unit=u, time=1.0, value=v)], defaults))
    assert reached == set(defaults)
    keys = {f["name"]: f["scenario"]["key"] for f in manifest["layouts"]["p"] if not f["name"].startswith("fault_")}
    assert len(set(keys.values())) == len(keys)
    assert keys["orbit_e"] == "orbit.eccentricity" and keys["dt"] == "simulation.rate"
    assert keys["wheel_speed_max"] == "wheels.max_speed_rpm" and keys["pwpf_uoff"] == "thrusters.pwpf.u_off"
    e = p_field(manifest, "orbit_e")
    assert e["bounds"] == {"lo": 0.0, "hi": 1.0, "lo_open": False, "hi_open": True}
    inc = p_field(manifest, "orbit_inc")["scenario"]
    assert inc["unit"] == "deg" and inc["scale"] == pytest.approx(math.pi / 180)
    assert p_field(manifest, "gg_on")["presets"] == {"full": [1.0]}


def test_a_bound_declared_in_symbolic_is_what_validation_enforces(manifest):
    text = replaced("eccentricity = 0.138", "eccentricity = 0.6")
    loads_scenario(text, "s.toml", typed(manifest))  # e < 1: valid with the generated bounds
    p_field(manifest, "orbit_e")["bounds"]["hi"] = 0.5
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text, "s.toml", typed(manifest))
    assert str(info.value) == "s.toml: orbit.eccentricity = 0.6: must be in [0, 0.5)"
    # in the scenario's unit (deg), from the SI bound (rad)
    p_field(manifest, "orbit_inc")["bounds"] = {"lo": 0.0, "hi": math.radians(50), "lo_open": False,
                                                 "hi_open": False}
    with pytest.raises(ScenarioError, match=r"^s\.toml: orbit\.inclination_deg = 55\.0: must be in \[0, 50\] deg$"):
        loads_scenario(BASE, "s.toml", typed(manifest))


def test_keys_units_and_scales_come_from_the_manifest(manifest, model):
    f = p_field(manifest, "wheel_beta")
    f["scenario"].update(key="wheels.tilt_rad", unit="rad", scale=1.0)
    f["bounds"] = {"lo": 0.0, "hi": 1.0, "lo_open": True, "hi_open": False}
    text = BASE + "\n[wheels]\ntilt_rad = 0.6\n"
    sc = loads_scenario(text, "s.toml", typed(manifest))
    assert scalar(sc.params(), "wheel_beta") == 0.6
    with pytest.raises(ScenarioError, match=r"wheels\.tilt_rad = 1\.5: must be in \(0, 1\] rad$"):
        loads_scenario(text.replace("tilt_rad = 0.6", "tilt_rad = 1.5"), "s.toml", typed(manifest))
    with pytest.raises(ScenarioError, match=r"wheels\.tilt_deg = 30\.0: unknown key \(.*allowed: .*tilt_rad"):
        loads_scenario(BASE + "\n[wheels]\ntilt_deg = 30.0\n", "s.toml", typed(manifest))
    # a new parameter gets its table and key without an edit of runtime/
    manifest["layouts"]["p"].append({"name": "new_p", "size": 1, "unit": "s", "doc": "new", "labels": ["new_p"],
                                     "default": [1.0], "scenario": {"key": "extra.new_key", "kind": "number",
                                                                     "unit": "ms", "scale": 1e-3}})
    sc = loads_scenario(BASE + "\n[extra]\nnew_key = 250.0\n", "s.toml", typed(manifest))
    assert sc.param_overrides()["new_p"] == pytest.approx(0.25)


def test_the_full_plant_preset_comes_from_the_manifest(manifest):
    sc = load_scenario(ROOT / "scenarios" / "001_scenario.toml", typed(manifest))
    full = sc.with_overrides(plant="full").params()
    defaults = {f["name"]: f["default"] for f in manifest["layouts"]["p"]}
    for f in manifest["layouts"]["p"]:
        if "full" in f.get("presets", {}):
            np.testing.assert_array_equal(full[f["name"]], f["presets"]["full"], err_msg=f["name"])
    assert scalar(full, "actuators_ideal") == 0.0 and scalar(full, "mag_on") == 1.0   # 001 flies ideal, no B
    np.testing.assert_array_equal(full["dist_torque_s_nu"], defaults["dist_torque_s_nu"])
    # the scenario's own bodies, orbit and constraints stay
    assert scalar(full, "chaser_mass") == paper_data("001_scenario")["chaser"]["mass"]
    np.testing.assert_array_equal(full["orbit_e"], sc.params()["orbit_e"])
    # a preset value patched in the manifest is what --plant full applies
    p_field(manifest, "mag_on")["presets"]["full"] = [0.0]
    p_field(manifest, "wheel_inertia")["presets"]["full"] = [0.002]
    sc = load_scenario(ROOT / "scenarios" / "001_scenario.toml", typed(manifest))
    full = sc.with_overrides(plant="full").params()
    assert scalar(full, "mag_on") == 0.0 and scalar(full, "wheel_inertia") == 0.002
    assert sc.with_overrides(plant="full").get("wheels.inertia") == 0.002


def test_gain_bounds_from_the_manifest(manifest):
    text = replaced("r_goal = [5.0, 0.0, 0.0]\n", "r_goal = [5.0, 0.0, 0.0]\nkp_att = -0.1\n")
    kp = next(f for f in manifest["layouts"]["k_baseline"] if f["name"] == "kp_att")
    kp.pop("bounds")  # symbolic/controllers/baseline.py declares kp_att >= 0: take it away here
    loads_scenario(text, "s.toml", typed(manifest))  # no bound declared on kp_att
    kp["bounds"] = {"lo": 0.0, "hi": None, "lo_open": False, "hi_open": False}
    with pytest.raises(ScenarioError, match=r"^s\.toml: controller\.baseline\.kp_att = -0\.1: must be >= 0 N m$"):
        loads_scenario(text, "s.toml", typed(manifest))


def test_gain_overrides_are_validated_like_the_gains_table():
    sc = load_scenario(III)
    over = sc.with_overrides(gains={"acc_d_on": 0.0, "d_att": [0.01, 0.01, 0.01]})
    assert over.controller["c000"]["acc_d_on"] == 0.0 and over.controller["c000"]["d_att"] == [0.01] * 3
    assert over.controller["c000"]["lam_att"] == sc.controller["c000"]["lam_att"]
    with pytest.raises(ScenarioError, match=r"controller\.c000\.nope = 1\.0: unknown key"):
        sc.with_overrides(gains={"nope": 1.0})
    with pytest.raises(ScenarioError, match=r"controller\.c000\.d_att = \[1\.0\]: must have 3 values, got 1"):
        sc.with_overrides(gains={"d_att": [1.0]})


def test_validate_scenario_reports_the_reproduction_table():
    data = paper_data("000_scenario_I")
    data["reproduction"]["run"][0]["plants"] = ["moon"]
    with pytest.raises(ScenarioError, match=r'^x\.toml: reproduction\.run\[0\]\.plants\[0\] = "moon": must be one of'):
        validate_scenario(data, "x.toml", read_manifest())


def test_inertia_moments_are_those_of_the_tensor_as_given():
    """The bounds check the principal moments of the tensor as written (eigvalsh of it): reused
    from the physical check when the tensor is exactly symmetric, computed again when it is only
    symmetric within the tolerance."""
    from rpo.runtime.scenario.sections import _physical_tensor

    rng = np.random.default_rng(5)
    for i in range(300):
        A = rng.normal(size=(3, 3))
        I = 0.1 * (A @ A.T) + 3.0 * np.eye(3)  # near-isotropic: a physical body
        if i % 2:
            I[0, 1] *= 1.0 + 1e-13  # symmetric within 1e-9 of the largest entry, not exactly
        tensor, moments = _physical_tensor(I.tolist())
        assert tensor == I.tolist()
        assert moments.tobytes() == np.linalg.eigvalsh(np.array(tensor)).tobytes()


def test_wheel_momentum_check_agrees_with_allclose():
    """The wheel-speed round trip is checked as np.allclose(rtol=1e-9, atol=1e-9) would: the same
    answer near the tolerance, for nan and for infinities."""
    from rpo.runtime.scenario.initial_state import _close

    rng = np.random.default_rng(2)
    inf, nan = math.inf, math.nan
    cases = [([inf, 1.0], [inf, 1.0]), ([inf, 1.0], [-inf, 1.0]), ([nan, 1.0], [nan, 1.0]), ([1.0, 2.0], [1.0, inf])]
    for _ in range(3000):
        b = rng.normal(size=4) * 10.0 ** rng.integers(-12, 4)
        cases.append((b + rng.normal(size=4) * 10.0 ** rng.integers(-13, -7) * (1 + np.abs(b)), b))
    for a, b in cases:
        a, b = np.array(a, float), np.array(b, float)
        assert _close(a, b) == np.allclose(a, b, rtol=1e-9, atol=1e-9)


def test_a_scenario_s_values_are_handed_out_as_copies():
    """The parameters a scenario sets are computed once; what params() and param_overrides() return
    is the caller's to change."""
    sc = load_scenario(ROOT / "scenarios" / "001_scenario.toml")
    name = next(k for k, v in sc.param_overrides().items() if isinstance(v, np.ndarray))
    want = sc.params()[name].copy()
    sc.params()[name][:] = -1.0
    sc.param_overrides()[name][:] = -1.0
    np.testing.assert_array_equal(sc.params()[name], want)
    np.testing.assert_array_equal(sc.param_overrides()[name], want)
    np.testing.assert_array_equal(sc.params(copy=False)[name], want)
