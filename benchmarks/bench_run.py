"""How long ``rpo run`` takes once the model is compiled, and how much it writes.

    python benchmarks/bench_run.py [--repeat 5] [--scenario scenarios/000_scenario_III.toml] [--json] [--profile]

Each repetition runs the whole command as a user types it, in a fresh process, into a new folder
under a temporary directory (the compile cache is the user's, ``RPO_CACHE_DIR`` if set; one
unmeasured run first fills it):

* ``run_total_s``: wall time of ``python -m rpo.runtime.cli.main run <scenario> --out <folder>``
  (start of the interpreter to exit: imports, scenario, model load, simulation, metrics, data
  files, figures, the atomic rename);
* ``run_write_s``: the part spent writing the folder (data files, figures, rename), as the
  command prints it (``+X s writing``);
* ``output_mb``: size of the folder [MB, 1e6 bytes];
* ``cpu_s``: CPU time (user + system) of the command and of the first figure worker (the one it
  forks is not counted), and ``load_average`` (1 min) at the end: wall times on a machine shared
  with other jobs are not comparable, CPU times are.

Medians of ``--repeat`` runs are printed; with ``--json`` the last line is one JSON object with
these keys.  ``--profile`` adds where the time goes: the CLI's import time
(``python -X importtime -m rpo.runtime.cli.main --help``) and each stage of one in-process
``execute_run`` (scenario, model, simulation, metrics, write = data files + the wait for the
figures after them).  Extra arguments after ``--`` are
passed to ``rpo run`` (e.g. ``-- --format parquet,mat``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def folder_mb(path: Path) -> float:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file()) / 1e6


def one_run(scenario: str, out: Path, extra: list[str]) -> tuple[float, float, float]:
    """(wall time, writing time as printed, CPU time of the command and the workers it waited for)."""
    cmd = [sys.executable, "-m", "rpo.runtime.cli.main", "run", scenario, "--out", str(out), *extra]
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=False)
    total = time.perf_counter() - t0
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
    if res.returncode != 0:
        sys.exit(f"bench_run: {' '.join(cmd)} failed (exit {res.returncode}):\n{res.stderr[-2000:]}")
    m = re.search(r"\(\+([0-9.eE+-]+) s writing\)", res.stdout)
    return total, float(m.group(1)) if m else float("nan"), cpu


def import_time() -> float:
    res = subprocess.run([sys.executable, "-X", "importtime", "-m", "rpo.runtime.cli.main", "--help"], cwd=ROOT,
                         capture_output=True, text=True, check=True)
    top = [int(line.split("|")[1]) for line in res.stderr.splitlines()
           if line.startswith("import time:") and line.split("|")[2].strip() and
           not line.split("|")[2].startswith("  ") and line.split("|")[1].strip().isdigit()]
    return sum(top) / 1e6


def stage_profile(scenario: str, out: Path) -> dict[str, float]:
    code = ("import json, sys, time; t0 = time.perf_counter()\n"
            "from rpo.runtime.outputs.figure_workers import start; start()\n"  # as rpo run does, first
            "from rpo.runtime.jobs.runner import execute_run\n"
            "from rpo.runtime.model import load_model\n"
            "t1 = time.perf_counter()\n"
            "o = execute_run(sys.argv[1], sys.argv[2], lambda c: load_model(controllers=[c]))\n"
            "print(json.dumps({'imports': t1 - t0, **o.timings}))\n")
    res = subprocess.run([sys.executable, "-c", code, scenario, str(out)], cwd=ROOT, capture_output=True, text=True,
                         check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def measure(scenario: str, repeat: int = 5, extra: list[str] | None = None) -> dict:
    """The medians of ``repeat`` runs of the command (after one unmeasured run), as a dict with the
    keys of the ``--json`` line."""
    extra = extra or []
    with tempfile.TemporaryDirectory(prefix="rpo-bench-run-") as tmp:
        base = Path(tmp)
        one_run(scenario, base / "warm", extra)  # fills the compile cache, not measured
        totals, writes, sizes, cpus = [], [], [], []
        for k in range(repeat):
            out = base / f"run{k}"
            total, write, cpu = one_run(scenario, out, extra)
            totals.append(total)
            writes.append(write)
            cpus.append(cpu)
            sizes.append(folder_mb(out))
            print(f"run {k + 1}/{repeat}: total {total:.2f} s, writing {write:.2f} s, {sizes[-1]:.1f} MB, "
                  f"CPU {cpu:.2f} s, load average {os.getloadavg()[0]:.2f}", file=sys.stderr)
    return {"run_total_s": round(statistics.median(totals), 3), "run_write_s": round(statistics.median(writes), 3),
            "output_mb": round(statistics.median(sizes), 2), "cpu_s": round(statistics.median(cpus), 3),
            "load_average": round(os.getloadavg()[0], 2)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--scenario", default="scenarios/000_scenario_III.toml")
    ap.add_argument("--json", action="store_true", help="print one JSON line with the medians last")
    ap.add_argument("--profile", action="store_true", help="also print the import time and the stages")
    ap.add_argument("extra", nargs="*", help="arguments passed to rpo run (after --)")
    args = ap.parse_args(argv)
    result = measure(args.scenario, args.repeat, args.extra)
    with tempfile.TemporaryDirectory(prefix="rpo-bench-run-") as tmp:
        base = Path(tmp)
        print(f"run_total_s {result['run_total_s']:.2f} s (target <= 3), run_write_s {result['run_write_s']:.2f} s "
              f"(target <= 1.5), output_mb {result['output_mb']:.1f} MB (target <= 25)")
        if args.profile:
            print(f"profile: CLI imports (rpo --help) {import_time():.2f} s")
            stages = stage_profile(args.scenario, base / "profile")
            print("profile: " + ", ".join(f"{k} {v:.2f} s" for k, v in stages.items()))
    if args.json:
        print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
