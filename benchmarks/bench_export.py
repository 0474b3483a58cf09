"""Flight code, measured: every design exported, checked, and flown in the loop (issue 26's figures).

    python benchmarks/bench_export.py [--json] [--full] [--designs baseline,c000,...]

For each controller with a paper design (c000, c001, c002, c004) and the reference design (baseline):

* ``rpo export`` in double and single precision, then the flight checks (``rpo.runtime.flight.checks``):
  ``export_warnings`` (gcc and clang, ``-std=c99 -Wall -Wextra -Wpedantic -Werror`` and more; single
  precision adds ``-Wconversion -Wdouble-promotion``), ``heap_symbols`` (allocation calls in the objects),
  ``misra_findings_unjustified`` / ``misra_findings_total`` (cppcheck's MISRA C:2012 addon against the
  package's deviations file), summed over the ten packages;
* ``host_bit_identical``: the double package reproduces its test vectors bit for bit (``make test``) and
  flies its whole scenario on this machine equal to the simulation's run, every design;
* ``pil_max_abs_diff``: the largest |difference| between the Cortex-M7 run (QEMU mps2-an500, double) and
  the simulation's, over every state and output of every design's scenario (whole; c001's first 300 s
  unless ``--full``: its 5000 s are 500 000 steps, about 7 minutes);
* ``pil_single_rel_err``: the largest position deviation of the Cortex-M4F run (QEMU mps2-an386, single
  precision) from the simulation's, relative to the run's largest distance, over the designs;
  ``single_bound`` is the bound it is held to (``rpo.runtime.flight.pil.SINGLE_RUN_BOUND``);
* ``stack_bytes_per_step``: the worst-case stack of a step on the Cortex-M7 build (static, summed along
  gcc's call graph) per design, and ``stack_bytes_painted`` what the target measured by painting;
* ``instructions_per_step``: the median instructions of a step on the Cortex-M7 (QEMU ``-icount``, exact)
  per design; ``pil_us_per_step`` and ``pil_to_host_ratio``: the wall time of a lockstep step with QEMU
  against the same lockstep with the package compiled for this machine, in this process.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: controller -> (scenario, duration [s] of the PIL run or None: the whole scenario)
RUNS = {"baseline": ("ref_scenario", None), "c000": ("000_scenario_I", None), "c001": ("001_scenario", 300.0),
        "c002": ("002_scenario_kappa3", None), "c004": ("004_scenario", None)}


def cpu() -> str:
    try:
        flags = Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.machine()
    return "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else platform.machine()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print one JSON line with the figures")
    ap.add_argument("--full", action="store_true", help="fly c001's whole 5000 s on the target")
    ap.add_argument("--designs", default=",".join(RUNS), help="comma-separated controllers")
    args = ap.parse_args(argv)
    from rpo.runtime.flight.checks import check_package
    from rpo.runtime.flight.package import write_package
    from rpo.runtime.flight.pil import SINGLE_RUN_BOUND, fly_in_the_loop
    from rpo.runtime.flight.stack import header_stack

    designs = [d for d in args.designs.split(",") if d]
    out: dict = {"cpu": cpu(), "designs": designs, "export_warnings": 0, "heap_symbols": 0,
                 "misra_findings_unjustified": 0, "misra_findings_total": 0, "host_bit_identical": True,
                 "pil_max_abs_diff": 0.0, "pil_single_rel_err": 0.0, "single_bound": SINGLE_RUN_BOUND,
                 "stack_bytes_per_step": {}, "stack_bytes_painted": {}, "instructions_per_step": {},
                 "pil_us_per_step": {}, "pil_to_host_ratio": {}, "pil_steps": {}, "pil_passed": True, "seconds": {}}
    t_all = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="rpo-bench-export-") as tmp:
        for name in designs:
            scenario, duration = RUNS[name]
            if args.full:
                duration = None
            t0 = time.perf_counter()
            for prec in ("double", "single"):
                e = write_package(name, Path(tmp) / f"{name}_{prec}", precision=prec, measure_stack=header_stack)
                r = check_package(e.folder, prec, e.folder / "misra_deviations.toml").json()
                out["export_warnings"] += r["export_warnings"]
                out["heap_symbols"] += r["heap_symbols"]
                out["misra_findings_unjustified"] += r["misra_findings_unjustified"]
                out["misra_findings_total"] += r["misra_findings_total"]
                if prec == "double":
                    out["stack_bytes_per_step"][name] = r["stack_bytes_per_step"].get("cortex-m7")
                    made = subprocess.run(["make", "-s", "test"], cwd=e.folder, capture_output=True, text=True)
                    host = fly_in_the_loop(scenario, name, where="host", package=e.folder)
                    out["host_bit_identical"] &= made.returncode == 0 and bool(host.comparison["bit_identical"])
                    pil = fly_in_the_loop(scenario, name, where="qemu", duration=duration, package=e.folder)
                    j = pil.json()
                    out["pil_max_abs_diff"] = max(out["pil_max_abs_diff"], j["pil_max_abs_diff"])
                    out["instructions_per_step"][name] = j["instructions_per_step_median"]
                    out["stack_bytes_painted"][name] = j["stack_bytes_measured_max"]
                    out["pil_us_per_step"][name] = j["wall_us_per_step"]
                    out["pil_to_host_ratio"][name] = round(pil.wall_s / pil.steps / (host.wall_s / host.steps), 1)
                    out["pil_steps"][name] = pil.steps
                    out["pil_passed"] &= pil.passed
                else:
                    pil = fly_in_the_loop(scenario, name, precision="single", where="qemu", duration=duration,
                                          package=e.folder)
                    out["pil_single_rel_err"] = max(out["pil_single_rel_err"], pil.json()["pil_single_rel_err"])
                    out["pil_passed"] &= pil.passed
            out["seconds"][name] = round(time.perf_counter() - t0, 1)
    out["seconds"]["total"] = round(time.perf_counter() - t_all, 1)
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:28s} {v}")
    ok = (out["export_warnings"] == 0 and out["heap_symbols"] == 0 and out["misra_findings_unjustified"] == 0
          and out["host_bit_identical"] and out["pil_max_abs_diff"] == 0.0 and out["pil_passed"])
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
