"""The first hour's waits, each from an empty compile cache in a fresh process:

    python benchmarks/bench_first_use.py [--repeat 1] [--json]

* ``first_run_s``: ``rpo run scenarios/001_scenario.toml --duration 1 --no-plots`` (compile included);
* ``first_campaign_s``: ``rpo mc run scenarios/campaigns/000_III_mc.toml --runs 8 --duration 1``;
* ``first_batch_call_s``: ``load_model()`` and the first ``model.plant_rhs.batch(...)`` from Python
  (100 points: the scalar loop; a batch of 2e5 points or more compiles the lane form first);
* ``max_silent_s``: the longest interval without a line on stdout or stderr during those three
  (the wait for the interpreter and the imports before the first line included);
* ``first_lanes_s``: for reference, ``rpo build --lanes --controller c000`` from an empty cache
  (what a campaign long enough to fly in lanes pays once).

Medians of ``--repeat`` (each repetition from a new empty cache).  Targets (issue 24, on the 2-core
AVX2 machine): first_run_s <= 12, first_campaign_s <= 30, first_batch_call_s <= 10, max_silent_s <= 5.
The CPU's vector extension is printed with the figures (``cpu``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BATCH = """
import numpy as np
from rpo.runtime import load_model
m = load_model()
f = m.plant_rhs
x = np.zeros((100, m.layout_size("x"))); x[:, 3] = 1.0
f.batch(x, np.zeros(m.layout_size("u")), 0.0, m.vector("p"), np.zeros(m.layout_size("w")))
print("batch done")
"""


def cpu() -> str:
    info = Path("/proc/cpuinfo")
    flags = info.read_text().split("flags", 1)[-1].split("\n", 1)[0] if info.exists() else ""
    return "avx512f" if "avx512f" in flags else "avx2" if "avx2" in flags else "other"


def timed(cmd: list[str], cache: Path) -> tuple[float, float, int]:
    """(wall s, longest silence s, exit code) of ``cmd`` with an empty cache ``cache``."""
    env = {**os.environ, "RPO_CACHE_DIR": str(cache), "PYTHONUNBUFFERED": "1"}
    t0 = time.perf_counter()
    stamps = [t0]
    lock = threading.Lock()
    proc = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def pump(stream) -> None:
        for _line in stream:
            with lock:
                stamps.append(time.perf_counter())

    threads = [threading.Thread(target=pump, args=(s,)) for s in (proc.stdout, proc.stderr)]
    for t in threads:
        t.start()
    rc = proc.wait()
    for t in threads:
        t.join()
    end = time.perf_counter()
    stamps = sorted(stamps) + [end]
    silent = max(b - a for a, b in zip(stamps, stamps[1:], strict=False))
    return end - t0, silent, rc


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--no-lanes", action="store_true", help="skip first_lanes_s")
    args = ap.parse_args(argv)
    rpo = [sys.executable, "-m", "rpo.runtime.cli.main"]
    jobs = {
        "first_run_s": [*rpo, "run", "scenarios/001_scenario.toml", "--duration", "1", "--no-plots"],
        "first_campaign_s": [*rpo, "mc", "run", "scenarios/campaigns/000_III_mc.toml", "--runs", "8",
                             "--duration", "1"],
        "first_batch_call_s": [sys.executable, "-c", BATCH],
    }
    if not args.no_lanes:
        jobs["first_lanes_s"] = [*rpo, "build", "--lanes", "--controller", "c000"]
    walls: dict[str, list[float]] = {k: [] for k in jobs}
    silent: list[float] = []
    for _ in range(args.repeat):
        for key, cmd in jobs.items():
            with tempfile.TemporaryDirectory() as tmp:
                out = Path(tmp) / "out"
                full = [*cmd, "--out", str(out)] if "run" in cmd and "-c" not in cmd else cmd
                wall, quiet, rc = timed(full, Path(tmp) / "cache")
                if rc != 0:
                    print(f"{key}: {' '.join(full)} exited {rc}", file=sys.stderr)
                    return 1
                walls[key].append(wall)
                if key != "first_lanes_s":
                    silent.append(quiet)
                print(f"{key:20s} {wall:6.1f} s (longest silence {quiet:.1f} s)")
    fig = {k: round(statistics.median(v), 2) for k, v in walls.items()}
    fig["max_silent_s"] = round(max(silent), 2)
    fig.update({"repeat": args.repeat, "cores": len(os.sched_getaffinity(0)), "cpu": cpu()})
    if args.json:
        print(json.dumps(fig))
    return 0


if __name__ == "__main__":
    sys.exit(main())
