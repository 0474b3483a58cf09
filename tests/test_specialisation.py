"""The specialised copies of measure and plant_advance (rpo.symbolic.codegen.specialisation): each equals
the general function wherever its condition holds, the steps take them exactly when it holds
(scalar and per lane), and a lane keeps the bits of its run alone whatever its neighbours take."""

from __future__ import annotations

import re

import numpy as np
import pytest
from test_generated_vs_symbolic import Inputs
from test_lanes import _model, bits_equal

from rpo.runtime.model.manifest import generated_dir

N_POINTS = 12


def _variants(model):
    return [(base, v.function, v.zero) for base, vs in model.manifest.specialised.items() for v in vs]


def _zeroed(model, p, fields):
    p = p.copy()
    offs = model.offsets("p")
    for f in fields:
        p[offs[f]] = 0.0
    return p


def _args(model, gen, fname, p):
    """Random inputs of measure or plant_advance (a proximity state, the target's ECI orbit)."""
    x = gen.x()
    w = gen.rng.normal(size=model.layout_size("w"))
    t = gen.rng.uniform(0, 400)
    if fname.startswith("measure"):
        return [x, gen.hold(), t, p, w]
    nzp = model.layout_size("zp")
    zp = np.zeros(nzp)
    zp[: x.size] = x
    zp[x.size:] = gen.rng.normal(0, 0.1, nzp - x.size)  # delay line, PWPF states
    return [zp, t, p, w, gen.rng.normal(0, 0.2, 9)]


def test_every_variant_is_generated_and_listed(model):
    names = [f for _b, f, _z in _variants(model)]
    assert sorted(names) == ["measure_kepler", "plant_advance_kepler", "plant_advance_kepler_nodist"]
    for base, fname, _zero in _variants(model):
        d, g = model.manifest.functions[fname], model.manifest.functions[base]
        assert (d.inputs, d.outputs) == (g.inputs, g.outputs)
        assert d.ops < g.ops, (fname, d.ops, g.ops)  # something was folded away


@pytest.mark.parametrize("which", ["measure_kepler", "plant_advance_kepler", "plant_advance_kepler_nodist"])
def test_variant_equals_the_general_function_where_its_condition_holds(model, which):
    base, fname, zero = next(v for v in _variants(model) if v[1] == which)
    gen = Inputs(model, np.random.default_rng(abs(hash(which)) % 2**32))
    for _ in range(N_POINTS):
        p = _zeroed(model, gen.p(), zero)
        args = _args(model, gen, fname, p)
        ref, got = model.functions[base](*args), model.functions[fname](*args)
        for r_, g_ in zip(ref, got, strict=True):
            assert np.all(np.isfinite(r_))
            # equal values (an exact zero may differ in sign: 0 * (-x) in the general function)
            assert np.array_equal(r_, g_), (fname, np.abs(r_ - g_).max())


def test_variant_differs_where_its_condition_fails(model):
    # the check above could pass for a copy that ignores the switch: with the switch on it must not
    gen = Inputs(model, np.random.default_rng(3))
    offs = model.offsets("p")
    p = gen.p()
    p[offs["orbit_propagated"]] = 1.0
    args = _args(model, gen, "plant_advance", p)
    ref, got = model.plant_advance(*args), model.functions["plant_advance_kepler"](*args)
    assert not np.array_equal(ref[0], got[0])


def test_step_tables_are_the_manifest_fields(model):
    """The C glue of every step tests exactly the p entries of each variant's fields."""
    offs = model.offsets("p")
    for ctrl in model.manifest.controllers:
        text = (generated_dir() / f"step_{ctrl}.c").read_text()
        tables = {m.group(1): ([int(v) for v in m.group(2).split(", ")], m.group(3))
                  for m in re.finditer(r"static const casadi_int step_\w+_(z\d+_\d+)\[\d+\] = \{([\d, ]+)\};"
                                       r"  /\* (\w+):", text)}
        listed = {fn: zero for _b, fn, zero in _variants(model)}
        assert sorted(f for _i, f in tables.values()) == sorted(listed), ctrl
        for idx, fn in tables.values():
            want = sorted(i for f in listed[fn] for i in range(offs[f].start, offs[f].stop))
            assert idx == want, (ctrl, fn)


def _scenario_point(model, gen):
    """A step input of c000 whose p has every variant's condition (scenario III-like)."""
    from test_lanes import _scenario_sim
    sim, z0, _run = _scenario_sim(model)
    p = _zeroed(model, sim.p, [f for _b, _f, zero in _variants(model) for f in zero])
    return z0, p, sim.k


def test_step_takes_the_keplerian_copies_when_the_switch_is_off(model):
    """A NaN in the propagated orbit's state r_T, v_T reaches a propagated run (orbit_propagated 1)
    everywhere, a Keplerian one only in r_T, v_T themselves: the step called the Keplerian copies.
    A NaN frequency of the disturbance model with its amplitudes 0 reaches only the general
    plant_advance (sin(nan t) * 0): absent, the step called plant_advance_kepler_nodist."""
    gen = Inputs(model, np.random.default_rng(5))
    z0, p, k = _scenario_point(model, gen)
    zo, po = model.offsets("z_c000"), model.offsets("p")
    step = model.functions["step_c000"]
    w = np.zeros(model.layout_size("w"))
    z = z0.copy()
    z[zo["r_T"]] = np.nan
    z[zo["v_T"]] = np.nan
    p_nan_freq = p.copy()
    p_nan_freq[po["dist_force_w1"]] = np.nan
    p_nan_freq[po["dist_torque_w2"]] = np.nan
    for pp in (p, p_nan_freq):
        z_next, y = step(z, 10.0, pp, k, w)
        assert np.all(np.isnan(z_next[zo["r_T"]])) and np.all(np.isnan(z_next[zo["v_T"]]))
        rest = np.ones(z_next.size, bool)
        rest[zo["r_T"]] = rest[zo["v_T"]] = False
        assert np.all(np.isfinite(z_next[rest])) and np.all(np.isfinite(y[: model.layout_size("meas")]))
    z_next, _ = step(z0, 10.0, p_nan_freq, k, w)  # the r_T state is fine: only the frequency is NaN
    assert np.all(np.isfinite(z_next))
    prop = p.copy()
    prop[po["orbit_propagated"]] = 1.0
    assert np.all(np.isnan(step(z, 10.0, prop, k, w)[0][zo["r"]]))
    amp = p_nan_freq.copy()
    amp[po["dist_force_a1"]] = 1e-3  # an amplitude on: the general plant_advance, the NaN frequency reaches v
    assert np.all(np.isnan(step(z0, 10.0, amp, k, w)[0][zo["v"]]))


def test_lanes_that_take_different_variants_keep_their_bits():
    """One block whose lanes take the general function, the Keplerian copy and the Keplerian copy
    without disturbance (and NaN states only a wrong choice would spread): each lane's result is
    the bits of the same point evaluated alone."""
    model = _model(("c000", "baseline"))
    gen = Inputs(model, np.random.default_rng(11))
    z0, p, k = _scenario_point(model, gen)
    zo, po = model.offsets("z_c000"), model.offsets("p")
    K = model.lanes().width
    n = 2 * K + 1
    Z, T, P = np.tile(z0, (n, 1)), np.full(n, 12.5), np.tile(p, (n, 1))
    kinds = ["nodist", "kepler", "general", "nodist_nan_rT", "kepler_nan_rT", "general_nan_rT"]
    for i in range(n):
        kind = kinds[i % len(kinds)]
        Z[i, zo["r"]] += gen.rng.normal(0, 1, 3)
        if kind.startswith("kepler"):
            P[i, po["dist_torque_b1"]] = 1e-4
        if kind.startswith("general"):
            P[i, po["orbit_propagated"]] = 1.0
        if kind.endswith("nan_rT"):
            Z[i, zo["r_T"]] = np.nan
    Kk = np.tile(k, (n, 1))
    W = gen.rng.normal(size=(n, model.layout_size("w")))
    step = model.functions["step_c000"]
    batched = step.batch(Z, T, P, Kk, W)
    for i in range(n):
        single = step(Z[i], T[i], P[i], Kk[i], W[i])
        for b, s in zip(batched, single, strict=True):
            assert bits_equal(b[i], s), (kinds[i % len(kinds)], i)
        finite_r = np.all(np.isfinite(single[0][zo["r"]]))
        assert finite_r == (not kinds[i % len(kinds)].startswith("general_nan")), (kinds[i % len(kinds)], i)
