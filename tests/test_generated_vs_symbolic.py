"""Check 4: every generated C function equals its SymPy source evaluated independently.

The reference path is SymPy -> ``sympy.lambdify`` -> NumPy, which shares no code with the
SymPy -> CasADi -> C path except the SymPy expressions themselves.  The closed-loop step is
compared with the same composition (:func:`rpo.symbolic.physics.closed_loop.step`) run on NumPy.

Tolerance: 1e-12 relative, per output field, to the field's magnitude at that point
(``max(|ref|)`` over the field's entries).  Two fields are differences of much larger terms, so
their round-off is set by those terms, named in ``CANCELLATION_SCALE``: the relative
acceleration of eq. 30 (mu/r_t^2 - mu (r_t + x)/r_c^3, terms of ~9 m/s^2) and the differential
disturbance of eq. 45 (a_c - a_t, J2 terms of ~1.5e-2 m/s^2).  Thruster wrenches are sums of
+-1 N forces (+-0.5 N m torques) that cancel exactly in SymPy's rationals but to ~1e-16 in floats.
002's auxiliary states chi_1, chi_2 start at 0 and move by dt (sat(eps) - eps) / (k m) (eqs. 17-18),
a difference of commands of order 1 that is exactly 0 in one evaluation and 1e-15 in the other
when the command is just unsaturated; their scale is 1 (chi is dimensionless, |chi| < 20 in use).
Thruster duties are pair levels of order 1 minus the fault-aware allocation's shifts (the stuck
thrusters' wrench, the null-space move), so a duty near 0 is a cancellation of order-1 terms: scale 1.
"""

from __future__ import annotations

import json
import zlib
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rpo.generated

N_POINTS = 25
RTOL = 1e-12
#: (output layout, field) -> magnitude of the terms whose difference the field is [SI units]
_MANIFEST = json.loads((Path(rpo.generated.__file__).parent / "manifest.json").read_text())
CONTROLLERS = sorted(_MANIFEST["controllers"])
CANCELLATION_SCALE = {("x", "v"): 10.0, ("env", "a_d"): 2e-2, ("env", "F_thr"): 1.0, ("env", "tau_thr"): 1.0,
                      ("env", "F_applied"): 1.0, ("env", "tau_applied"): 1.0}
CANCELLATION_SCALE.update({("xc_c002", "chi1"): 1.0, ("xc_c002", "chi2"): 1.0})
for _c in CONTROLLERS:
    for _f in ("a_d", "F_thr", "tau_thr", "F_applied", "tau_applied"):
        CANCELLATION_SCALE[(f"y_{_c}", f"env_{_f}")] = CANCELLATION_SCALE[("env", _f)]
    CANCELLATION_SCALE[(f"y_{_c}", "thr_duty")] = 1.0


class Inputs:
    """Random, physically sensible inputs by manifest layout / input name."""

    def __init__(self, model, rng):
        self.m, self.rng = model, rng

    def x(self):
        m, g = self.m, self.rng
        o = m.offsets("x")
        x = np.zeros(m.layout_size("x"))
        x[o["q_c"]] = Rotation.random(random_state=g.integers(1 << 30)).as_quat()
        x[o["q_t"]] = Rotation.random(random_state=g.integers(1 << 30)).as_quat()
        x[o["w_c"]] = g.normal(0, 0.1, 3)
        x[o["w_t"]] = g.normal(0, 0.1, 3)
        x[o["h_w"]] = g.normal(0, 0.3, 4)
        x[o["r"]] = g.normal(0, 100, 3)
        x[o["v"]] = g.normal(0, 2, 3)
        x[o["m_prop"]] = g.uniform(0, 1)
        # the target's ECI state: a random low orbit (radius 6.7-7.5e6 m, speed about circular,
        # a few degrees of flight-path angle)
        r_hat = g.normal(size=3)
        r_hat /= np.linalg.norm(r_hat)
        t_hat = np.cross(r_hat, g.normal(size=3))
        t_hat /= np.linalg.norm(t_hat)
        r = g.uniform(6.7e6, 7.5e6)
        x[o["r_T"]] = r * r_hat
        x[o["v_T"]] = np.sqrt(3.986004418e14 / r) * (g.uniform(0.95, 1.1) * t_hat + g.normal(0, 0.05) * r_hat)
        return x

    def hold(self):
        """A sensor hold: the last values the attitude, rate, position and velocity sensors gave."""
        g = self.rng
        return np.concatenate([Rotation.random(random_state=g.integers(1 << 30)).as_quat(), g.normal(0, 0.1, 3),
                               g.normal(0, 10, 3), g.normal(0, 0.2, 3)])

    def p(self):
        m, g = self.m, self.rng
        p = m.vector("p").copy()
        o = m.offsets("p")
        for f in m.layouts["p"]:
            s = o[f.name]
            if f.name.endswith("_on") or f.name in ("actuators_ideal", "fdir_allocation", "orbit_propagated"):
                p[s] = g.integers(0, 2, f.size)
            elif f.name.startswith("fault_") and f.name.endswith("_start"):
                # fault windows open about half of the time t in [0, 400) s the tests draw
                start = g.uniform(0, 400, f.size)
                p[s] = start
                p[o[f.name.removesuffix("_start") + "_end"]] = start + g.uniform(0, 400, f.size)
            elif f.name.startswith("fault_") and f.name.endswith("_end"):
                continue
            elif f.name.endswith("_weak_value"):
                p[s] = g.uniform(0.2, 1.0, f.size)
            elif f.name.startswith("fault_"):
                p[s] = g.uniform(0, 0.01, f.size)
            elif f.name.startswith(("meas_", "dist_")):
                p[s] = g.uniform(0, 0.01, f.size)
            elif f.name.endswith("_misalign"):
                p[s] = g.uniform(-0.1, 0.1, f.size)  # rad, within the +-10 deg bounds
            elif f.name in ("dt", "wheel_delay", "pwpf_uon", "pwpf_uoff"):
                continue
            elif f.name == "orbit_e":
                p[s] = g.uniform(0, 0.1)  # with a within 5 % of 7863 km: perigee above 340 km
            else:
                p[s] *= 1 + g.uniform(-0.05, 0.05, f.size)
        return p

    def value(self, fname, name, shape, layout=None):
        g, n = self.rng, int(np.prod(shape))
        if name in ("x",):
            return self.x()
        if name == "p":
            return self.p()
        if name == "t":
            return g.uniform(0, 400)
        if name == "u":
            return np.concatenate([g.normal(0, 0.05, 4), g.integers(0, 2, 16), g.normal(0, 0.5, 6),
                                   g.integers(0, 2, 4)])
        if name == "w":
            return g.normal(size=n)
        if name == "k":
            return self.m.vector(layout) * (1 + g.uniform(-0.5, 0.5, n))
        if name == "meas":
            w = g.normal(size=self.m.layout_size("w"))
            return self.m.measure(self.x(), self.hold(), g.uniform(0, 400), self.p(), w)[0]
        if name in ("tau", "F"):
            return g.normal(0, 0.1, n)
        if name == "f":
            return g.uniform(-0.1, 0.5, n)
        if name in ("on_prev", "on"):
            return g.integers(0, 2, n).astype(float)
        if name == "duty":
            return g.uniform(0, 1, n)
        if name == "M":
            return g.uniform(-10, 10)
        if name == "e":
            return g.uniform(0, 0.99)
        if name == "rel":
            return np.concatenate([Rotation.random(random_state=g.integers(1 << 30)).as_quat(), g.normal(0, 0.1, 3)])
        if name == "z":
            z = np.zeros(n)
            nx = self.m.layout_size("x")
            z[:nx] = self.x()
            # proximity states (|r| ~ 10 m, |v| ~ 0.2 m/s): far-out states saturate the papers'
            # laws so hard that some designs' auxiliary states overflow within one step
            o = self.m.offsets("x")
            z[o["r"]] = g.normal(0, 10, 3)
            z[o["v"]] = g.normal(0, 0.2, 3)
            z[nx:nx + 16] = g.normal(0, 0.05, 16)
            z[nx + 16:nx + 32] = g.uniform(-0.1, 0.5, 16)
            z[nx + 32:nx + 48] = g.integers(0, 2, 16)
            if n >= nx + 48 + self.m.layout_size("hold"):
                z[nx + 48:nx + 48 + self.m.layout_size("hold")] = self.hold()
            return z
        if name == "xc":
            return g.normal(size=n)
        if name == "hold":
            return self.hold()
        if name == "T_w":
            return g.normal(0, 0.1, n)
        raise KeyError(f"no generator for input {name} of {fname}")


def field_slices(model, layout_name, size):
    if layout_name and layout_name in model.layouts:
        return list(model.offsets(layout_name).items())
    return [("all", slice(0, size))]


def assert_close(model, fname, out_desc, got, ref):
    got, ref = np.ravel(got), np.ravel(ref)
    assert got.shape == ref.shape
    if ref.size == 0:
        return
    for fld, s in field_slices(model, out_desc.layout, ref.size):
        scale = max(np.abs(ref[s]).max(), CANCELLATION_SCALE.get((out_desc.layout, fld), 0.0), 1e-300)
        err = np.abs(got[s] - ref[s]).max()
        assert err <= RTOL * scale, f"{fname}.{out_desc.name}[{fld}]: |C - SymPy| = {err:.3e}, scale {scale:.3e}"


SOURCE_FUNCS = ["plant_rhs", "measure", "env_outputs", "ideal_actuators", "wheel_alloc", "thruster_alloc", "pwpf",
                "pwpf_filter", "wheel_faults", "thruster_faults", "target_orbit", "kepler", "relative_attitude_rhs"]
for _c in CONTROLLERS:
    SOURCE_FUNCS.append(f"law_{_c}")
    if "xc0" in _MANIFEST["controllers"][_c]:
        SOURCE_FUNCS.append(f"xc0_{_c}")


def test_every_generated_function_is_covered(model):
    covered = set(SOURCE_FUNCS) | {"plant_jac", "plant_advance"} | {f"{f}_{c}" for c in CONTROLLERS
                                                                     for f in ("step", "control")}
    # the specialised copies equal their general function (tests/test_specialisation.py)
    covered |= {v.function for vs in model.manifest.specialised.values() for v in vs}
    assert set(model.manifest.functions) == covered


def compare_at_finite_points(model, fname, draw, reference, wanted: int, tries: int) -> None:
    """Compare ``fname`` with ``reference`` at ``wanted`` random points ``draw()`` where the reference
    is finite.  Random states far outside a design's region (e.g. 002's tanh auxiliary system
    escaping within one step) give NaN or inf in both paths: such a point is redrawn, after
    checking that the C code is non-finite in the same entries."""
    desc = model.manifest.functions[fname]
    compared = 0
    for _ in range(tries):
        args = draw()
        with np.errstate(all="ignore"):
            ref = reference(*args)
        got = model.functions[fname](*args)
        if not all(np.all(np.isfinite(r_)) for r_ in ref):
            assert all(np.array_equal(np.isfinite(g_), np.isfinite(r_)) for g_, r_ in zip(got, ref, strict=True))
            continue
        for o, g_, r_ in zip(desc.outputs, got, ref, strict=True):
            assert_close(model, fname, o, g_, r_)
        compared += 1
        if compared == wanted:
            return
    pytest.fail(f"{fname}: only {compared} of {wanted} random points gave a finite result")


def test_generated_plant_advance_equals_numpy_composition(model, sources, numpy_piece):
    from rpo.symbolic.codegen.numpy_reference import numpy_plant_advance

    pieces, ctx = sources
    advance = numpy_plant_advance(pieces, ctx["plant"], make=numpy_piece)
    desc = model.manifest.functions["plant_advance"]
    gen = Inputs(model, np.random.default_rng(7))
    nzp = desc.inputs[0].shape[0]
    for _ in range(N_POINTS // 5):
        zp = gen.value("step", "z", (nzp, 1))
        t, p, w = gen.value("step", "t", 1), gen.p(), gen.value("step", "w", (18, 1))
        cmd = gen.rng.normal(0, 0.2, 9)
        got, ref = model.plant_advance(zp, t, p, w, cmd), advance(zp, t, p, w, cmd)
        for o, g_, r_ in zip(desc.outputs, got, ref, strict=True):
            assert_close(model, "plant_advance", o, g_, r_)


@pytest.mark.parametrize("ctrl", CONTROLLERS)
def test_generated_control_equals_numpy_composition(model, sources, numpy_piece, ctrl):
    from rpo.symbolic.codegen.numpy_reference import numpy_control

    pieces, ctx = sources
    design = next(c for c in ctx["controllers"] if c.name == ctrl)
    control = numpy_control(pieces, ctx["plant"], design, make=numpy_piece)
    fname = f"control_{ctrl}"
    desc = model.manifest.functions[fname]
    gen = Inputs(model, np.random.default_rng(13))
    nx = model.layout_size("x")

    def draw():
        args = [gen.value(fname, i.name, i.shape, i.layout) for i in desc.inputs]
        # a proximity state (as for the step): far-out states saturate some designs so hard that
        # their auxiliary states overflow within one step
        x = gen.value("step", "z", (nx + 48, 1))[:nx]
        args[0] = model.measure(x, gen.hold(), args[2], args[3], gen.rng.normal(size=model.layout_size("w")))[0]
        if desc.inputs[1].layout in model.layouts:  # controller state near its defaults
            args[1] = model.vector(desc.inputs[1].layout) * (1 + gen.rng.uniform(-0.2, 0.2, args[1].size))
        return args

    compare_at_finite_points(model, fname, draw, control, wanted=5, tries=20)


@pytest.mark.parametrize("fname", SOURCE_FUNCS)
def test_generated_function_equals_sympy_source(model, numpy_piece, fname):
    desc = model.manifest.functions[fname]
    ref_fn = numpy_piece(fname)
    gen = Inputs(model, np.random.default_rng(zlib.crc32(fname.encode())))  # replayable
    for _ in range(N_POINTS):
        args = [gen.value(fname, i.name, i.shape, i.layout) for i in desc.inputs]
        got = model.functions[fname](*args)
        ref = ref_fn(*args)
        for o, g_, r_ in zip(desc.outputs, got, ref, strict=True):
            assert_close(model, fname, o, g_, r_)


@pytest.mark.parametrize("ctrl", CONTROLLERS)
def test_generated_step_equals_numpy_composition(model, sources, numpy_piece, ctrl):
    from rpo.symbolic.codegen.numpy_reference import numpy_step

    pieces, ctx = sources
    design = next(c for c in ctx["controllers"] if c.name == ctrl)
    step = numpy_step(pieces, ctx["plant"], design, make=numpy_piece)
    fname = f"step_{ctrl}"
    desc = model.manifest.functions[fname]
    gen = Inputs(model, np.random.default_rng(11))
    wanted = N_POINTS // 5 if ctrl != "baseline" else N_POINTS

    def draw():
        z = gen.value("step", "z", desc.inputs[0].shape)
        t, p = gen.value("step", "t", 1), gen.p()
        k = gen.value("step", "k", desc.inputs[3].shape, desc.inputs[3].layout)
        w = gen.value("step", "w", desc.inputs[4].shape)
        return z, t, p, k, w

    compare_at_finite_points(model, fname, draw, step, wanted=wanted, tries=4 * wanted)


def test_generated_jacobian_equals_finite_differences_of_the_sympy_rhs(model, numpy_piece):
    """plant_jac is CasADi's AD of the translated expression: checked against central differences of
    the independently evaluated SymPy right-hand side (FD accuracy ~1e-7 relative)."""
    rhs = numpy_piece("plant_rhs")
    gen = Inputs(model, np.random.default_rng(5))
    for _ in range(5):
        x, t, p = gen.x(), gen.value("j", "t", 1), gen.p()
        u, w = gen.value("j", "u", (26, 1)), gen.value("j", "w", (18, 1))
        A, B = model.plant_jac(x, u, t, p, w)
        for M, base, which in ((A, x, 0), (B, u, 1)):
            fd = np.zeros_like(M)
            for j in range(base.size):
                h = 1e-6 * max(1.0, abs(base[j]))
                bp, bm = base.copy(), base.copy()
                bp[j] += h
                bm[j] -= h
                args_p = (bp, u, t, p, w) if which == 0 else (x, bp, t, p, w)
                args_m = (bm, u, t, p, w) if which == 0 else (x, bm, t, p, w)
                fd[:, j] = (rhs(*args_p)[0] - rhs(*args_m)[0]) / (2 * h)
            scale = np.abs(fd).max(axis=1, keepdims=True) + 1e-30
            if which == 1:  # thruster on-levels enter through a speed-limit switch: skip the
                cols = np.r_[0:4, 20:26]  # discrete columns' kinks, keep wheel torques and ideal wrench
                fd, M = fd[:, cols], M[:, cols]
                scale = np.abs(fd).max(axis=1, keepdims=True) + 1e-30
            assert np.all(np.abs(M - fd) <= 1e-5 * scale + 1e-12), np.abs(M - fd).max()
