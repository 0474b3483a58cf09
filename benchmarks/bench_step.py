"""Speed where the user waits, in one process: lockstep batches, the scalar loop, single and batched
calls from Python, Basilisk side by side, and the whole ``rpo run``.

    python benchmarks/bench_step.py [--repeat 5] [--runs 64] [--json] [--no-basilisk] [--no-run] [--references]

Figures (medians of ``--repeat``; the keys of the ``--json`` line):

* ``scalar_us_per_step``: scenario III closed loop (c000), 300 s at 100 Hz, one run in the C loop
  (``Simulation.run``), recording every 100th step (1 Hz);
* ``batch_us_per_run_step``: the same, ``--runs`` cases (different seeds) in lockstep
  (``Simulation.run_batch``, K per call), wall time / (runs x steps), same recording; and
  ``batch_speedup`` = scalar / batch.  ``lanes`` is K;
* ``basilisk_us_per_step`` and ``basilisk_ratio`` = Basilisk / rpo batched: Basilisk's single
  spacecraft (point mass + J2 + gravity gradient + 4 wheels, RK4 at 0.01 s, 300 s;
  ``benchmarks/basilisk_case.py``), in this process, when ``bsk`` is installed
  (``pip install -e ".[bench]"``); null otherwise;
* ``plant_rhs_call_us``: one ``model.plant_rhs(x, u, t, p, w, out=o)`` call from Python, the same
  arrays every call; ``plant_rhs_batch_us_per_point``: ``model.plant_rhs.batch(X, ...)`` over 10^4
  points, per point; ``plant_rhs_loop_us_per_point``: the compiled lane code's own cost per
  evaluation (K points evaluated repeatedly in C, nothing gathered or returned), and
  ``plant_rhs_batch_ratio`` = batch / loop (target: within 1.25);
* ``run_total_s``, ``run_write_s``, ``output_mb``: scenario III's ``rpo run`` (000, the README's second run) with the
  compile cached (``benchmarks/bench_run.py``, fresh processes).

With ``--references`` also the per-step cost of the same step evaluated by CasADi's virtual machine
(the generated ``step_<ctrl>`` as a ``casadi.Function`` called from Python, ``casadi_us_per_step``)
and by NumPy (the lambdified SymPy pieces composed by the same ``closed_loop.step``,
``numpy_us_per_step``; about a minute of setup), and their ratios to the scalar C loop.

Targets (issue 10): batch_us_per_run_step <= 1, batch_speedup >= 4, basilisk_ratio >= 15,
plant_rhs_call_us <= 1.5, plant_rhs_batch_ratio <= 1.25, run_total_s <= 3, run_write_s <= 1.5,
output_mb <= 25.
"""

from __future__ import annotations

import os

# OpenBLAS's worker threads spin after any BLAS call and took 6 % of a core in the profiles here;
# rpo does no BLAS work, so one thread (set before NumPy loads it)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import ctypes  # noqa: E402
import json  # noqa: E402
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
SCENARIO = ROOT / "scenarios" / "000_scenario_III.toml"
#: the batch and scalar runs record every 100th step (1 Hz): what a campaign keeps per run
RECORD_EVERY = 100


def median_time(fn, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out)


def per_call_us(fn, n: int, repeat: int) -> float:
    def loop():
        for _ in range(n):
            fn()
    return median_time(loop, repeat) / n * 1e6


def references(model, sim, z0, controller: str, repeat: int, casadi_steps: int = 2000,
               numpy_steps: int = 200) -> dict:
    """Per-step cost of the same closed-loop step in CasADi's VM and in NumPy (lambdified SymPy)."""
    import gzip

    import casadi as ca

    from rpo.runtime.model.manifest import generated_dir
    from rpo.symbolic.codegen import functions
    from rpo.symbolic.codegen.numpy_reference import numpy_step

    step_name = model.manifest.controllers[controller].step
    step_ca = ca.Function.deserialize(gzip.decompress((generated_dir() / f"{step_name}.casadi.gz").read_bytes())
                                      .decode())
    p, k = sim.p, sim.k
    W = np.random.default_rng(0).standard_normal((casadi_steps, sim.nw))

    def casadi_loop():
        z = z0.copy()
        for i in range(casadi_steps):
            zn, _y = step_ca(z, i * sim.dt, p, k, W[i])
            z = np.asarray(zn).ravel()

    out = {"casadi_us_per_step": median_time(casadi_loop, max(1, repeat // 2)) / casadi_steps * 1e6}
    print("building the NumPy reference (sympy.lambdify of the plant; about a minute) ...", flush=True)
    pieces, ctx = functions.sources()
    ctrl = next(c for c in ctx["controllers"] if c.name == controller)
    step_np = numpy_step(pieces, ctx["plant"], ctrl)

    def numpy_loop():
        z = z0.copy()
        for i in range(numpy_steps):
            z, _y = step_np(z, i * sim.dt, p, k, W[i % len(W)])

    out["numpy_us_per_step"] = median_time(numpy_loop, max(1, repeat // 2)) / numpy_steps * 1e6
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--runs", type=int, default=64, help="cases in the lockstep batch")
    ap.add_argument("--duration", type=float, default=None, help="simulated seconds (default: the scenario's)")
    ap.add_argument("--json", action="store_true", help="print one JSON line with the figures last")
    ap.add_argument("--no-basilisk", action="store_true")
    ap.add_argument("--no-run", action="store_true", help="skip the whole-command figures (bench_run.py)")
    ap.add_argument("--references", action="store_true", help="also CasADi's VM and NumPy per step (slow setup)")
    args = ap.parse_args(argv)

    from rpo.runtime.model import fastcall
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.run.simulate import Simulation
    from rpo.runtime.scenario import load_scenario

    model = load_model(log=print)
    run = load_scenario(SCENARIO).to_run(model)
    sim = Simulation(model, run.controller, params=run.params, gains=run.gains)
    z0 = sim.initial_state(run.plant)
    duration = args.duration or run.duration
    n_steps = int(round(duration / sim.dt))
    lanes = model.lanes()
    K = lanes.width
    print(f"scenario {SCENARIO.name}: {duration:g} s at {1 / sim.dt:g} Hz = {n_steps} steps, controller "
          f"{run.controller}; machine {platform.machine()}, {K} lanes, python {platform.python_version()}")
    fig: dict = {"lanes": K, "runs": args.runs, "record_every": RECORD_EVERY, "repeat": args.repeat}

    # calls from Python
    f = model.plant_rhs
    x = z0[: model.layout_size("x")].copy()
    u = np.zeros(model.layout_size("u"))
    w = np.zeros(model.layout_size("w"))
    p = sim.p
    out = np.empty(f.out_sizes[0])
    fig["fastcall"] = not fastcall.why_not
    fig["plant_rhs_call_us"] = per_call_us(lambda: f(x, u, 0.0, p, w, out=out), 20000, args.repeat)
    n_pts = 10000
    rng = np.random.default_rng(0)
    X = x + 1e-3 * rng.standard_normal((n_pts, x.size))
    Xout = np.empty((n_pts, x.size))
    f.batch(X, u, 0.0, p, w, out=Xout)
    batch_t, loop_t = [], []
    ins = [np.ascontiguousarray(X[:K]), u, np.zeros(1), p, w]
    dp = ctypes.POINTER(ctypes.c_double)
    in_p = (dp * 5)(*[a.ctypes.data_as(dp) for a in ins])
    in_n = (ctypes.c_longlong * 5)(*f.in_sizes)
    in_s = (ctypes.c_longlong * 5)(x.size, 0, 0, 0, 0)
    out_n = (ctypes.c_longlong * 1)(*f.out_sizes)
    rep = lanes.lib.rpo_repeat_lanes
    reps = 20000

    def loop():
        rep(ctypes.c_void_p(lanes.pointers["plant_rhs"]), ctypes.c_longlong(lanes.work["plant_rhs"]), 5, in_p, in_n,
            in_s, 1, out_n, ctypes.c_longlong(reps))

    for _ in range(args.repeat):  # interleaved, as above
        batch_t.append(median_time(lambda: f.batch(X, u, 0.0, p, w, out=Xout), 1) / n_pts * 1e6)
        loop_t.append(median_time(loop, 1) / (reps * K) * 1e6)
    fig["plant_rhs_batch_us_per_point"] = statistics.median(batch_t)
    fig["plant_rhs_loop_us_per_point"] = statistics.median(loop_t)
    fig["plant_rhs_batch_ratio"] = statistics.median(b / lp for b, lp in zip(batch_t, loop_t, strict=True))

    # closed loop: scalar C loop, lockstep batch and (when installed) Basilisk, interleaved, so that
    # every figure sees the same machine (a shared VM's speed drifts by tens of percent)
    Z0 = np.tile(z0, (args.runs, 1))
    seeds = list(range(args.runs))
    bsk = None
    if not args.no_basilisk:
        try:
            from basilisk_case import basilisk_us_per_step

            bsk = basilisk_us_per_step
        except ImportError as exc:
            print(f"Basilisk not measured: {exc}")
    sim.run(z0, duration, seed=0, record_every=RECORD_EVERY)
    sim.run_batch(Z0[:K], duration, seeds[:K], record_every=RECORD_EVERY)
    ts, tb, tk = [], [], []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        sim.run(z0, duration, seed=0, record_every=RECORD_EVERY)
        ts.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        sim.run_batch(Z0, duration, seeds, record_every=RECORD_EVERY)
        tb.append(time.perf_counter() - t0)
        if bsk is not None:
            b = bsk(duration=duration, dt=sim.dt, repeat=1)
            tk.append(b["us_per_step"])
            fig["basilisk_version"] = b["basilisk_version"]
    fig["scalar_us_per_step"] = statistics.median(ts) / n_steps * 1e6
    fig["batch_us_per_run_step"] = statistics.median(tb) / (args.runs * n_steps) * 1e6
    fig["batch_speedup"] = fig["scalar_us_per_step"] / fig["batch_us_per_run_step"]
    fig["basilisk_us_per_step"] = statistics.median(tk) if tk else None
    # the ratio of each repetition's pair, then the median: drift between repetitions cancels
    per_run_step = [b / (args.runs * n_steps) * 1e6 for b in tb]
    fig["basilisk_ratio"] = (statistics.median(k / b for k, b in zip(tk, per_run_step, strict=True))
                             if tk else None)

    if args.references:
        fig.update(references(model, sim, z0, run.controller, args.repeat))

    # the whole command
    if not args.no_run:
        import bench_run

        r = bench_run.measure(str(SCENARIO), repeat=args.repeat)
        fig.update({k: r[k] for k in ("run_total_s", "run_write_s", "output_mb", "load_average")})

    print()
    rows = [("CasADi VM per step from Python, us", "casadi_us_per_step", None),
            ("NumPy RK4 of the same equations, us", "numpy_us_per_step", None),
            ("scalar C loop, us/step", "scalar_us_per_step", None),
            (f"lockstep batch ({K} lanes), us/run-step", "batch_us_per_run_step", "<= 1"),
            ("batch speedup", "batch_speedup", ">= 4"),
            ("Basilisk, us/step", "basilisk_us_per_step", None),
            ("Basilisk / rpo batched", "basilisk_ratio", ">= 15"),
            ("plant_rhs single call (out=), us", "plant_rhs_call_us", "<= 1.5"),
            ("plant_rhs.batch, us/point", "plant_rhs_batch_us_per_point", None),
            ("compiled lane code alone, us/point", "plant_rhs_loop_us_per_point", None),
            ("batch / compiled", "plant_rhs_batch_ratio", "<= 1.25"),
            ("rpo run total, s", "run_total_s", "<= 3"),
            ("rpo run writing, s", "run_write_s", "<= 1.5"),
            ("rpo run output, MB", "output_mb", "<= 25")]
    for label, key, target in rows:
        v = fig.get(key)
        print(f"{label:42s} {'-' if v is None else f'{v:10.3f}':>10s}   {target or ''}")
    if args.json:
        print(json.dumps({k: (round(v, 4) if isinstance(v, float) else v) for k, v in fig.items()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
