"""Speed of one closed-loop step, three ways, in one process (000 scenario III, baseline controller).

    python benchmarks/bench_step.py [--numpy-steps 200] [--casadi-steps 2000] [--repeat 5]

1. compiled: the generated C step run by the C loop (what ``rpo run`` uses), full 300 s at 100 Hz;
2. numpy: the same SymPy pieces evaluated with NumPy (``sympy.lambdify``) and composed by the same
   ``closed_loop.step`` (a plain-Python/NumPy RK4 of the same equations);
3. casadi: the generated step as a ``casadi.Function`` (CasADi's virtual machine) called once per
   step from Python with NumPy arrays.

Also the per-call overhead of calling one generated function from Python: rpo's ctypes wrapper
against ``casadi.external`` on the same shared library.

Timings are wall-clock medians; the ratios are what to compare across machines.
"""

from __future__ import annotations

import argparse
import gzip
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def median_time(fn, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenario", default=str(ROOT / "scenarios" / "000_scenario_III.toml"))
    ap.add_argument("--numpy-steps", type=int, default=200)
    ap.add_argument("--casadi-steps", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)

    import casadi as ca

    from rpo.runtime.compiled import generated_dir, load_model
    from rpo.runtime.scenario import load_scenario
    from rpo.runtime.simulate import Simulation

    model = load_model()
    run = load_scenario(args.scenario).to_run(model)
    sim = Simulation(model, run.controller, params=run.params, gains=run.gains)
    z0 = sim.initial_state(run.plant)
    n_steps = int(round(run.duration / sim.dt))
    print(f"scenario {Path(args.scenario).name}: {run.duration:g} s at {1 / sim.dt:g} Hz = {n_steps} steps, "
          f"controller {run.controller}")
    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}, "
          f"casadi {ca.__version__}, library {model.library.name}")

    # 1. compiled: the whole run, C loop
    sim.run(z0, run.duration, seed=run.seed)  # warm-up (page in the library)
    t_comp = median_time(lambda: sim.run(z0, run.duration, seed=run.seed), args.repeat)
    us_comp = t_comp / n_steps * 1e6

    # 3. casadi.Function per step from Python: the generated step as serialised by build.py
    step_name = model.manifest["controllers"][run.controller]["step"]
    blob = (generated_dir() / f"{step_name}.casadi.gz").read_bytes()
    step_ca = ca.Function.deserialize(gzip.decompress(blob).decode())
    p, k = sim.p, sim.k
    rng = np.random.default_rng(0)
    W = rng.standard_normal((args.casadi_steps, sim.nw))

    def casadi_loop():
        z = z0.copy()
        for i in range(args.casadi_steps):
            zn, _y = step_ca(z, i * sim.dt, p, k, W[i])
            z = np.asarray(zn).ravel()

    us_ca = median_time(casadi_loop, max(1, args.repeat // 2)) / args.casadi_steps * 1e6

    # 2. numpy: lambdified SymPy pieces + the same step composition (setup excluded from timing)
    print("building the NumPy reference (sympy.lambdify of the plant; about a minute) ...", flush=True)
    t0 = time.perf_counter()
    from rpo.symbolic import functions
    from rpo.symbolic.numpy_reference import numpy_step

    pieces, ctx = functions.sources()
    ctrl = next(c for c in ctx["controllers"] if c.name == run.controller)
    step_np = numpy_step(pieces, ctx["plant"], ctrl)
    print(f"  (setup {time.perf_counter() - t0:.0f} s, not timed)")

    def numpy_loop():
        z = z0.copy()
        for i in range(args.numpy_steps):
            z, _y = step_np(z, i * sim.dt, p, k, W[i % len(W)])

    us_np = median_time(numpy_loop, max(1, args.repeat // 2)) / args.numpy_steps * 1e6

    # per-call overhead of one generated function from Python
    rhs = model.plant_rhs
    x, u, w = z0[: model.layout_size("x")], np.zeros(model.layout_size("u")), np.zeros(model.layout_size("w"))
    n_calls = 20000
    t_ctypes = median_time(lambda: [rhs(x, u, 0.0, p, w) for _ in range(n_calls)], 3) / n_calls * 1e6
    ext = ca.external("plant_rhs", str(model.library))
    n_ext = 2000
    t_ext = median_time(lambda: [ext(x, u, 0.0, p, w) for _ in range(n_ext)], 3) / n_ext * 1e6

    rows = [
        ("compiled (C step in C loop)", us_comp, t_comp),
        ("casadi.Function per step", us_ca, us_ca * n_steps / 1e6),
        ("numpy RK4 of the same equations", us_np, us_np * n_steps / 1e6),
    ]
    print()
    print(f"{'method':34s} {'us/step':>12s} {'300 s run [s]':>14s} {'x compiled':>11s}")
    for name, us, total in rows:
        print(f"{name:34s} {us:12.2f} {total:14.3f} {us / us_comp:11.1f}")
    print()
    print(f"one plant_rhs call from Python: ctypes wrapper {t_ctypes:.2f} us, casadi.external {t_ext:.2f} us "
          f"({t_ext / t_ctypes:.1f}x)")
    goal_ratio, goal_run = us_np / us_comp >= 100, t_comp < 0.1
    print(f"goals: numpy/compiled >= 100x: {'met' if goal_ratio else 'NOT met'} ({us_np / us_comp:.0f}x); "
          f"whole run < 0.1 s: {'met' if goal_run else 'NOT met'} ({t_comp:.3f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
