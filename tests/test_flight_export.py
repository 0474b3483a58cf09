"""The flight-code export (runtime/flight): the exported C against the generated function it is printed
from, its test vectors, and flown in the loop on this machine against the simulation.

The default run checks two designs (baseline: no states, the full plant; c001: states, RK4, sliding
mode); tests/test_flight_tools.py (``pytest -m flight``) checks every design, under gcc and clang, the
coding-standard checks and the emulated flight processor.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import ModelError
from rpo.runtime.flight import emit
from rpo.runtime.flight.host import HostController
from rpo.runtime.flight.interface import controller_interface
from rpo.runtime.flight.lockstep import bits_equal, compare, fly
from rpo.runtime.flight.package import functions, write_package
from rpo.runtime.flight.vectors import read as read_vectors
from rpo.runtime.jobs.api import scenario as load_scenario
from rpo.runtime.run.preflight import preflight

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ("baseline", "c001")


def rpo(*args, cwd=None, timeout=300) -> subprocess.CompletedProcess:
    env = {**os.environ, "COLUMNS": "100"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def packages(tmp_path_factory):
    """baseline and c001 exported in double precision (200 vector steps each), and c001 in single."""
    root = tmp_path_factory.mktemp("exports")
    out = {}
    for name in DESIGNS:
        out[name] = write_package(name, root / name, steps=200)
    out["c001_single"] = write_package("c001", root / "c001_single", precision="single", steps=200)
    return out


def _loop(model, name: str, scenario: str, steps: int):
    """(interface, simulation, initial state, seed, the simulation's own run of ``steps`` steps)."""
    pre = preflight(load_scenario(scenario, {"simulation.controller": name}), model)
    control, start = functions(model.manifest, name)
    iface = controller_interface(model.manifest, name, control, start)
    ref = pre.sim.run(pre.z0, steps * pre.sim.dt, seed=pre.inputs.seed, record_every=1)
    return iface, pre.sim, pre.z0, pre.inputs.seed, ref


def _make(folder: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["make", "-s", *args], cwd=folder, capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("name", DESIGNS)
def test_the_package_reproduces_its_recorded_run_bit_for_bit(packages, name):
    e = packages[name]
    res = _make(e.folder, "test")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "bit for bit" in res.stdout and f"{e.vectors.steps} steps" in res.stdout
    assert {f"rpo_{name}.h", f"rpo_{name}.c", "Makefile", "README.md", f"rpo_{name}_vectors.txt"} <= set(e.files)


def test_a_changed_constant_fails_the_vector_test(packages, tmp_path):
    """The vector test can fail: one constant of the law changed in its last bit."""
    e = packages["c001"]
    copy = tmp_path / "c001"
    shutil.copytree(e.folder, copy)
    src = copy / "rpo_c001.c"
    text = src.read_text()
    assert " = 0.5;" in text
    src.write_text(text.replace(" = 0.5;", " = 0.50000000000000011;", 1))
    res = _make(copy, "test")
    assert res.returncode != 0, res.stdout + res.stderr
    assert "differs at step" in res.stderr


@pytest.mark.parametrize("name", DESIGNS)
def test_the_exported_law_equals_the_generated_function_at_random_points(model, packages, name):
    """The printed C against CasADi's C of the same function (the simulation's object), bit for bit,
    at 300 points scattered around the recorded run (inputs, states and gains perturbed by 30 %)."""
    e = packages[name]
    spec = model.manifest.controller(name)
    fn = model.functions[spec.control]
    iface = e.interface
    rng = np.random.default_rng(7)
    v = read_vectors(e.folder / f"rpo_{name}_vectors.txt")
    sc = load_scenario(e.scenario, {"simulation.controller": name})
    pre = preflight(sc, model)
    host = HostController(e.folder)
    n_meas = model.layout_size("meas")
    for i in range(300):
        row = v["V"][rng.integers(len(v["V"]))]
        inputs = row[:iface.size("inputs")] * (1 + 0.3 * rng.standard_normal(iface.size("inputs")))
        state = v["V"][rng.integers(len(v["V"]))][-iface.size("state"):] if iface.size("state") else np.zeros(0)
        state = state * (1 + 0.3 * rng.standard_normal(state.size))
        k = pre.sim.k * (1 + 0.3 * rng.standard_normal(pre.sim.k.size))
        host.init(iface.gather("params", {"p": pre.sim.p, "k": k}))
        host.set_state(state)
        out, st = host.step(inputs)
        meas = np.zeros(n_meas)
        t = 0.0
        j = 0
        for _, m in iface.members("inputs"):
            if m.source == "t":
                t = float(inputs[j])
            else:
                meas[m.offset:m.offset + m.size] = inputs[j:j + m.size]
            j += m.size
        cmd, xc_next, diag = (np.ravel(a) for a in fn(meas, state, t, pre.sim.p, k))
        want = np.concatenate([cmd, diag])
        # bit for bit (signed zeros too); a NaN only by place: its sign is the machine's choice
        assert bits_equal(out, want) and bits_equal(st, xc_next), i


@pytest.mark.parametrize("name", DESIGNS)
def test_flown_in_the_loop_on_this_machine_the_run_is_the_simulations(model, packages, name):
    e = packages[name]
    iface, sim, z0, seed, ref = _loop(model, name, e.scenario, 400)
    c = compare(ref, fly(iface, model, sim, z0, 400 * sim.dt, seed, HostController(e.folder)))
    assert c["bit_identical"] and c["max_abs_diff"] == 0.0 and c["rows"] == 401, c


def test_a_changed_package_is_rebuilt_and_the_loop_sees_the_change(model, packages, tmp_path):
    """The host library is keyed by the package's bytes: an edited law is compiled again (never the
    stale one), and the lockstep comparison reports the difference."""
    e = packages["baseline"]
    copy = tmp_path / "baseline"
    shutil.copytree(e.folder, copy)
    src = copy / "rpo_baseline.c"
    text = src.read_text()
    first = text.index(" = params->gains.kp_att;")
    src.write_text(text[:first] + " = 1.01 * params->gains.kp_att;" + text[first + len(" = params->gains.kp_att;"):])
    iface, sim, z0, seed, ref = _loop(model, "baseline", e.scenario, 200)
    c = compare(ref, fly(iface, model, sim, z0, 200 * sim.dt, seed, HostController(copy)))
    assert not c["bit_identical"] and c["max_abs_diff"] > 0


def test_single_precision_compiles_clean_and_stays_near_the_double_loop(model, packages):
    from rpo.runtime.flight.pil import SINGLE_RUN_BOUND, single_error

    e = packages["c001_single"]
    res = _make(e.folder, "test")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "-Wconversion -Wdouble-promotion" in (e.folder / "Makefile").read_text()
    assert "typedef float rpo_c001_real_t;" in (e.folder / "rpo_c001.h").read_text()
    iface, sim, z0, seed, ref = _loop(model, "c001", e.scenario, 2000)
    err = single_error(ref, fly(iface, model, sim, z0, 2000 * sim.dt, seed, HostController(e.folder)))
    assert 0 < err["position_rel"] <= SINGLE_RUN_BOUND, err  # not bit-identical, and near


def test_the_header_names_units_and_the_stack_and_uses_no_heap_or_io(packages):
    e = packages["c001"]
    h = (e.folder / "rpo_c001.h").read_text()
    c = (e.folder / "rpo_c001.c").read_text()
    for member in ("t;", "q_c[4];", "tau_w[3];", "w_hat[3];", "k_p;", "dt;"):
        assert member in h
    for line in h.splitlines():
        if line.strip().startswith("rpo_c001_real_t "):
            assert "/* [" in line, line       # every member says its unit
    assert "#define RPO_C001_STACK_BYTES" in h and "#define RPO_C001_RATE_HZ 100.0" in h
    for word in ("malloc", "free(", "printf", "FILE", "static double", "static float"):
        assert word not in c
    for f in e.folder.glob("*"):
        if f.suffix not in {".c", ".h", ".md", ".txt", ".json"} and f.name != "Makefile":
            continue  # objects and programs make built
        text = f.read_text()
        assert all(("/" + top + "/") not in text for top in ("work", "tmp", "home")), f  # no machine path


def test_literals_are_exact_and_unsupported_operations_are_refused():
    import casadi as ca

    for v in (0.1, -1.5e-300, 2.0**-1074, 1e308, 1 / 3):
        assert float(emit.literal(v, "double")) == v
        if 1e-44 < abs(v) < 3e38:
            assert np.float32(float(emit.literal(v, "single").rstrip("F"))) == np.float32(v)
    for v in (1e308, 2.0**-1074):  # overflows, or would become 0
        with pytest.raises(ModelError, match="outside single precision"):
            emit.literal(v, "single")
    with pytest.raises(ModelError, match="finite"):
        emit.literal(float("inf"), "double")
    x = ca.SX.sym("x")
    f = ca.Function("g", [x], [ca.erf(x)])
    with pytest.raises(ModelError, match="OP_ERF"):
        emit.body(f, "double", lambda i, j: "x", lambda i, j: "y")


def test_export_refuses_a_used_folder_and_bad_options_in_one_line(tmp_path):
    used = tmp_path / "used"
    used.mkdir()
    (used / "keep.txt").write_text("mine")
    res = rpo("export", "c001", "--out", used, "--no-check")
    assert res.returncode == 2 and "exists and is not an empty folder" in res.stderr, res.stderr
    assert (used / "keep.txt").read_text() == "mine" and len(list(used.iterdir())) == 1
    res = rpo("export", "c999", "--out", tmp_path / "x", "--no-check")
    assert res.returncode == 2 and "unknown controller 'c999'" in res.stderr and "c001" in res.stderr
    res = rpo("export", "c001", "--out", tmp_path / "y", "--rate", "-5", "--no-check")
    assert res.returncode == 2 and "--rate must be in (0, 10000] Hz" in res.stderr
    for r in (res,):
        assert "Traceback" not in r.stderr + r.stdout
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


def test_rpo_pil_refuses_a_package_of_another_controller_precision_or_model(packages, tmp_path):
    e = packages["c001"]
    res = rpo("pil", "001_scenario", "--controller", "baseline", "--on", "host", "--package", e.folder)
    assert res.returncode == 2 and "holds controller 'c001', not 'baseline'" in res.stderr, res.stderr
    res = rpo("pil", "001_scenario", "--controller", "c001", "--on", "host", "--precision", "single",
              "--package", e.folder)
    assert res.returncode == 2 and "give --precision double" in res.stderr, res.stderr
    stale = tmp_path / "stale"
    shutil.copytree(e.folder, stale)
    meta = stale / "rpo_c001.json"
    meta.write_text(meta.read_text().replace(e.interface.prefix, e.interface.prefix, 1).replace(
        '"manifest_hash": "', '"manifest_hash": "0000', 1))
    res = rpo("pil", "001_scenario", "--controller", "c001", "--on", "host", "--package", stale, "--duration", "1")
    assert res.returncode == 2 and "exported from another model" in res.stderr, res.stderr
    res = rpo("pil", "001_scenario", "--controller", "c001", "--on", "host", "--package", e.folder, "--duration", "1")
    assert res.returncode == 0 and "bit for bit" in res.stdout, res.stdout + res.stderr


def test_the_package_keeps_the_simulations_bits_under_gnu_flags_and_a_user_mode(packages, tmp_path):
    """CFLAGS of a GNU build (-march=native: an FMA unit, contraction on by default) still give the
    recorded run bit for bit: the source turns contraction off itself; the folder has the umask's mode."""
    import stat

    e = packages["c001"]
    mode = stat.S_IMODE(e.folder.stat().st_mode)
    umask = os.umask(0)
    os.umask(umask)
    assert mode == 0o777 & ~umask, oct(mode)
    copy = tmp_path / "c001"
    shutil.copytree(e.folder, copy)
    res = _make(copy, "test", "CFLAGS=-O2 -march=native")
    assert res.returncode == 0 and "bit for bit" in res.stdout, res.stdout + res.stderr


def test_runs_compare_bit_for_bit_with_nans_at_the_same_places():
    from rpo.runtime.flight.lockstep import compare
    from rpo.runtime.run.result import RunResult

    def run(z):
        z = np.asarray(z, float)
        return RunResult(t=np.arange(z.shape[0]), z=z, y=z.copy(), z_labels=["a", "b"], z_units=["-", "-"],
                         y_labels=["a", "b"], y_units=["-", "-"], steps_done=z.shape[0] - 1,
                         steps_requested=z.shape[0] - 1, dt=1.0, wall_time=0.0)

    x86_nan = np.array([0xFFF8000000000000], dtype=np.uint64).view(float)[0]   # the sign an x86 gives
    arm_nan = np.array([0x7FF8000000000000], dtype=np.uint64).view(float)[0]   # ARM's default NaN
    assert compare(run([[1.0, x86_nan]]), run([[1.0, arm_nan]]))["bit_identical"]
    assert not compare(run([[1.0, x86_nan]]), run([[x86_nan, 1.0]]))["bit_identical"]
    assert not compare(run([[0.0, 1.0]]), run([[-0.0, 1.0]]))["bit_identical"]   # signed zeros count


def test_a_diverging_vector_run_and_a_huge_pil_run_are_refused_in_one_line(packages, tmp_path):
    res = rpo("export", "c002", "--out", tmp_path / "div", "--scenario", "002_scenario", "--vectors", "1000")
    assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert "diverged in step 340" in res.stderr and not (tmp_path / "div").exists()
    res = rpo("pil", "001_scenario", "--controller", "c001", "--on", "host", "--duration", "1e9",
              "--package", packages["c001"].folder)
    assert res.returncode == 2 and "give a shorter --duration" in res.stderr and "Traceback" not in res.stderr
