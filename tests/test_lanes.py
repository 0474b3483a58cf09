"""Lockstep lanes: the lane form of every generated function equals the scalar function bit for
bit, and a case run in a batch equals the same case run alone, whatever its lane and its
neighbours (including neighbours that diverge)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from rpo.runtime.model import cache, lanes
from rpo.runtime.model.cache import object_key
from rpo.runtime.model.functions import CompiledFunction
from rpo.runtime.model.library import lane_sources
from rpo.runtime.model.loader import load_model
from rpo.runtime.model.manifest import generated_dir
from rpo.runtime.run.simulate import Simulation
from rpo.runtime.scenario import load_scenario

from conftest import SCENARIO_III

#: the controllers whose lane forms the default run compiles (all of them: ``-m slow``)
FAST_CONTROLLERS = ["c000", "baseline"]


@functools.cache
def _model(ctrls: tuple[str, ...] | None):
    return load_model(controllers=None if ctrls is None else list(ctrls))


@pytest.fixture(scope="module")
def lane_model():
    return _model(tuple(FAST_CONTROLLERS))


def bits_equal(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal bit for bit, except that any NaN equals any NaN (payloads are not compared)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return False
    na, nb = np.isnan(a), np.isnan(b)
    return bool(np.array_equal(na, nb) and np.array_equal(a[~na].view(np.uint64), b[~nb].view(np.uint64)))


def _points(model, fn, n: int, rng) -> list[np.ndarray]:
    """n input points for ``fn``: layout defaults and scenario III's state, perturbed, mixed with
    plain random numbers (which reach every branch of the saturations and the NaN paths)."""
    sim = Simulation(model, "c000")
    run = load_scenario("scenarios/000_scenario_III.toml").to_run(model)
    z0 = sim.initial_state(run.plant)
    base = {"p": model.vector("p"), "x": z0[: model.layout_size("x")], "z_c000": z0,
            "zp": z0[: model.layout_size("zp")]}
    out = []
    for d in fn.desc.inputs:
        size = d.size
        lay = d.layout
        nominal = base.get(lay, np.zeros(size))
        if nominal.size != size:
            nominal = np.zeros(size)
        scale = np.maximum(np.abs(nominal), 1.0)
        pts = nominal + 0.1 * scale * rng.standard_normal((n, size))
        pts[n // 2:] = rng.uniform(-3, 3, (n - n // 2, size))  # the second half: anything
        out.append(pts)
    return out


def test_every_generated_file_has_a_lane_form(model):
    sources, skipped = lane_sources(generated_dir(), model.manifest)
    assert skipped == {}, skipped
    assert len(sources) == len(model.manifest.sources) + 1  # + the lane loop driver


def test_unknown_line_is_an_error_naming_it():
    text = ("static int casadi_f0(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, "
            "int mem) {\n  casadi_real a0;\n  a0=erf(a0);\n  return 0;\n}\n")
    with pytest.raises(lanes.LaneError, match=r"x\.c .*'a0=erf\(a0\);'"):
        lanes.lane_source("x.c", text)


def test_sin_cos_pairs_are_fused():
    text = ("static int casadi_f0(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, "
            "int mem) {\n  casadi_real a0, a1, a2, a3;\n  a0=arg[0]? arg[0][0] : 0;\n  a1=sin(a0);\n"
            "  a2=cos(a0);\n  a0=(a0+a1);\n  a3=cos(a0);\n  if (res[0]!=0) res[0][0]=a3;\n  return 0;\n}\n"
            "CASADI_SYMBOL_EXPORT int f(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, "
            "int mem){\n  return casadi_f0(arg, res, iw, w, mem);\n}\n  if (sz_w) *sz_w = 0*sizeof(casadi_real);\n")
    src, _ = lanes.lane_source("f.c", text)
    assert "rpo_sincos(a0,&a1,&rpo_t0);" in src and "a2=rpo_t0;" in src
    assert "a3=rpo_cos(a0);" in src  # a0 was reassigned: a different value, not fused


@pytest.mark.parametrize("name", ["plant_rhs", "plant_jac", "measure", "measure_kepler", "plant_advance",
                                  "plant_advance_kepler", "plant_advance_kepler_nodist", "env_outputs",
                                  "control_c000", "step_c000", "law_baseline", "step_baseline", "target_orbit",
                                  "kepler", "wheel_alloc", "thruster_alloc", "pwpf", "pwpf_filter"])
def test_batch_equals_single_calls_bitwise(lane_model, name):
    fn = lane_model.function(name)
    assert lane_model.lanes().has(name)
    rng = np.random.default_rng(abs(hash(name)) % 2**32)
    n = 2 * lane_model.lanes().width + 3  # full blocks and a short last one
    pts = _points(lane_model, fn, n, rng)
    batched = fn.batch(*pts)
    for i in range(n):
        single = fn(*[p[i] for p in pts])
        for b, s in zip(batched, single, strict=True):
            assert bits_equal(b[i], s), (name, i)


@pytest.mark.slow
def test_batch_equals_single_calls_bitwise_every_function():
    model = _model(None)
    rng = np.random.default_rng(7)
    for name, fn in model.functions.items():
        assert model.lanes().has(name), name
        pts = _points(model, fn, 2 * model.lanes().width + 1, rng)
        batched = fn.batch(*pts)
        for i in range(pts[0].shape[0]):
            for b, s in zip(batched, fn(*[p[i] for p in pts]), strict=True):
                assert bits_equal(b[i], s), (name, i)


def _scenario_sim(model, controller="c000", **kw):
    run = load_scenario("scenarios/000_scenario_III.toml").to_run(model)
    gains = run.gains if controller == run.controller else None
    sim = Simulation(model, controller, params=run.params, gains=gains, **kw)
    return sim, sim.initial_state(run.plant), run


def _same(a, b) -> bool:
    ok = (np.array_equal(a.t, b.t) and bits_equal(a.z, b.z) and bits_equal(a.y, b.y)
          and a.steps_done == b.steps_done and (a.divergence is None) == (b.divergence is None))
    if ok and a.divergence is not None:
        da, db = a.divergence, b.divergence
        ok = (da.step, da.label, da.time) == (db.step, db.label, db.time) and bits_equal(da.state, db.state)
    return ok


def test_run_batch_equals_single_runs_with_diverging_neighbours(lane_model):
    # a tight position bound, so that the cases pushed outward diverge within the run
    r0 = float(np.linalg.norm(SCENARIO_III["relative"]["position"]))
    sim, z0, _run = _scenario_sim(lane_model, bounds={"r": r0 + 15})
    K = lane_model.lanes().width
    n = K + 3
    offs = lane_model.offsets(sim.z_layout)
    Z0 = np.tile(z0, (n, 1))
    rng = np.random.default_rng(1)
    Z0[:, offs["w_c"]] += 1e-3 * rng.standard_normal((n, 3))
    diverging = [1, K - 1, K + 1]
    for i in diverging:
        Z0[i, offs["v"]] = 30 * Z0[i, offs["r"]] / np.linalg.norm(Z0[i, offs["r"]])  # outward at 30 m/s
    seeds = [100 + i for i in range(n)]
    gains = [{"lam_att": 0.2 + 0.01 * i} for i in range(n)]  # per-case gains
    batch = sim.run_batch(Z0, 2.0, seeds, gains=gains, record_every=7, chunk=50)
    assert [i for i, r in enumerate(batch) if not r.ok] == diverging
    for i in range(n):
        k = lane_model.vector(f"k_{sim.controller}", {**sim._gains_given, **gains[i]})
        alone = Simulation._with(sim, sim.p, k)
        ref = alone.run(Z0[i], 2.0, seed=seeds[i], record_every=7)
        assert _same(batch[i], ref), i


def test_run_batch_any_lane_and_per_case_parameters(lane_model):
    sim, z0, _run = _scenario_sim(lane_model, controller="baseline")
    K = lane_model.lanes().width
    params = [{"gg_on": i % 2, "wheel_delay": 0.001 * (i % 3)} for i in range(K)]
    seeds = [5] * K
    batch = sim.run_batch(np.tile(z0, (K, 1)), 1.0, seeds, params=params, t0=12.5)
    for i in (0, K // 2, K - 1):
        alone = Simulation(lane_model, "baseline", params={**sim._params_given, **params[i]})
        ref = alone.run(z0, 1.0, seed=5, t0=12.5)
        assert _same(batch[i], ref), i
    # the same case in every lane gives the same bits
    same = sim.run_batch(np.tile(z0, (K, 1)), 1.0, seeds, params=[params[1]] * K)
    assert all(_same(same[0], r) for r in same[1:])


def test_run_batch_rejects_mixed_dt(lane_model):
    sim, z0, _ = _scenario_sim(lane_model, controller="baseline")
    from rpo.runtime.errors import ModelError

    with pytest.raises(ModelError, match="case 1 has dt"):
        sim.run_batch(np.tile(z0, (2, 1)), 1.0, [0, 1], params=[None, {"dt": 0.02}])
    with pytest.raises(ModelError, match=r"Z0 must have shape \(N, "):
        sim.run_batch(z0[:5], 1.0, [0])


def test_single_call_out_and_shape_errors(lane_model):
    f = lane_model.plant_rhs
    nx = lane_model.layout_size("x")
    x = _points(lane_model, f, 1, np.random.default_rng(3))
    args = [a[0] for a in x]
    ref = f(*args)[0]
    out = np.empty(f.out_sizes[0])
    assert f(*args, out=out) is out and bits_equal(out, ref)
    assert bits_equal(f(*args, out=(out,))[0], ref)
    with pytest.raises(ValueError, match=rf"plant_rhs: input x must have shape \({nx},\)"):
        f(args[0][:3], *args[1:])
    with pytest.raises(TypeError, match="plant_rhs takes 5 inputs"):
        f(*args[:4])
    with pytest.raises(ValueError, match=r"out for xdot|out for"):
        f(*args, out=np.empty(3))
    jac = lane_model.plant_jac
    A = np.empty((nx, nx), order="F")
    B = np.empty((nx, jac.out_shapes[1][1]), order="F")
    jac(*args, out=(A, B))
    A_ref, B_ref = jac(*args)
    assert bits_equal(A, A_ref) and bits_equal(B, B_ref)
    with pytest.raises(ValueError, match="Fortran order"):
        jac(*args, out=(np.empty((nx, nx)), B))


def test_batch_shapes_broadcast_and_errors(lane_model):
    f = lane_model.plant_rhs
    nx = lane_model.layout_size("x")
    pts = _points(lane_model, f, 5, np.random.default_rng(4))
    shared = [pts[0], pts[1][0], 0.25, pts[3][0], pts[4][0]]
    (X,) = f.batch(*shared)
    for i in range(5):
        assert bits_equal(X[i], f(pts[0][i], pts[1][0], 0.25, pts[3][0], pts[4][0])[0])
    out = np.empty((5, nx))
    assert f.batch(*shared, out=out) is out and bits_equal(out, X)
    with pytest.raises(ValueError, match=r"input u must have shape \(N, \d+\) \(one per point\)"):
        f.batch(pts[0], pts[1][:, :2], 0.0, pts[3][0], pts[4][0])
    with pytest.raises(ValueError, match="has 4 points, an earlier input 5"):
        f.batch(pts[0], pts[1][:4], 0.0, pts[3][0], pts[4][0])
    J = lane_model.plant_jac.batch(*shared)
    assert J[0].shape == (5, nx, nx)
    assert bits_equal(J[0][2], lane_model.plant_jac(pts[0][2], pts[1][0], 0.25, pts[3][0], pts[4][0])[0])


def test_ctypes_path_equals_fast_path(lane_model):
    fast = lane_model.plant_rhs
    plain = CompiledFunction(fast._lib, "plant_rhs", fast.desc)
    args = [a[0] for a in _points(lane_model, fast, 1, np.random.default_rng(5))]
    assert bits_equal(plain(*args)[0], fast(*args)[0])
    out = np.empty(fast.out_sizes[0])
    plain(*args, out=out)
    assert bits_equal(out, fast(*args)[0])


def test_lane_objects_are_keyed_by_the_headers(monkeypatch):
    k1 = object_key(b"int x;", "cc")
    monkeypatch.setattr(cache, "headers_digest", lambda: "other")
    assert object_key(b"int x;", "cc") != k1


@pytest.mark.slow
def test_baseline_target_width_is_bit_identical_too(monkeypatch, tmp_path):
    """Without -march=native (the SSE2 width on x86-64) the lanes still equal the scalar runs."""
    monkeypatch.setenv("RPO_LANES_TARGET", "baseline")
    model = load_model(controllers=["baseline"])
    lanes_lib = model.lanes()
    assert lanes_lib.width in (1, 2)
    sim, z0, _ = _scenario_sim(model, controller="baseline")
    n = lanes_lib.width + 1
    batch = sim.run_batch(np.tile(z0, (n, 1)), 0.5, list(range(n)))
    for i in range(n):
        assert _same(batch[i], sim.run(z0, 0.5, seed=i)), i


def test_noise_is_the_documented_function_of_seed_step_and_index(lane_model):
    """The C loops' noise against the NumPy version of its definition (runtime/run/noise.py)."""
    import ctypes

    from rpo.runtime.run import noise

    lane_model.loop_noise(noise.key(7), 0, 1)  # links a library (functions compile on first use) if none is
    lib = lane_model._lib
    lib.rpo_noise_key.restype = ctypes.c_ulonglong
    lib.rpo_noise_key.argtypes = [ctypes.c_ulonglong]
    for seed in (0, 1, 2, 12345, 2**63, 2**64 - 1):
        assert lib.rpo_noise_key(seed) == noise.key(seed)
    nw = lane_model.layout_size("w")
    W = np.empty((2000, nw))
    lib.rpo_noise_fill(ctypes.c_ulonglong(noise.key(7)), ctypes.c_longlong(1000), ctypes.c_longlong(2000),
                       ctypes.c_int(nw), W.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
    ref = noise.noise(7, 1000, 2000, nw)
    np.testing.assert_allclose(W, ref, rtol=0, atol=4e-15)  # NumPy's log/sqrt/cos against rpo_math.h's
    assert bits_equal(lane_model.loop_noise(noise.key(7), 1000, 2000), W)  # the lockstep's noise (runtime/flight)
    # the uniforms themselves are exact integer arithmetic: bit-identical
    u = noise.uniforms(noise.key(7), np.arange(10, dtype=np.uint64))
    assert np.all((u > 0) & (u <= 1))
    # standard normal: mean 0, variance 1, independent components (4e4 samples)
    assert abs(W.mean()) < 0.03 and abs(W.std() - 1) < 0.03
    assert np.max(np.abs(np.corrcoef(W.T) - np.eye(nw))) < 0.1
    # a later step's noise does not depend on the steps before it
    assert bits_equal(noise.noise(7, 2500, 3, nw), ref[1500:1503])
    from rpo.runtime.errors import ModelError

    for bad in (-1, 2**64, 1.5, "3"):
        with pytest.raises(ModelError, match="seed must be"):
            noise.key(bad)


def test_casadi_backend_draws_the_same_noise(lane_model):
    """The fallback backend's NumPy noise agrees with the C loop's to rounding: one step each."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        vm = load_model(backend="casadi")
    sim_c, z0, run = _scenario_sim(lane_model)
    sim_v = Simulation(vm, run.controller, params=run.params, gains=run.gains)
    a = sim_c.run(z0, 0.05, seed=11)
    b = sim_v.run(z0, 0.05, seed=11)
    np.testing.assert_allclose(a.z, b.z, rtol=1e-12, atol=1e-12)


def test_outputs_written_over_inputs_give_the_same_result(lane_model):
    """out= aliasing an input equals the call with separate arrays (plant_rhs writes xdot[0]
    before it reads x[0], so evaluating in place would read its own output)."""
    f = lane_model.plant_rhs
    pts = _points(lane_model, f, 3, np.random.default_rng(8))
    args = [a[0].copy() for a in pts]
    (ref,) = f(*args)
    x = args[0].copy()
    f(x, *args[1:], out=x)
    assert bits_equal(x, ref)
    (want,) = f.batch(*pts)
    X = pts[0].copy()
    f.batch(X, *pts[1:], out=X)
    assert bits_equal(X, want)
