"""How long the edit loop takes: cold, no-op and edit rebuilds, and the first run's compile.

    python benchmarks/bench_build.py [--repeat 3] [--json]

Everything runs on a copy of this checkout (symbolic/, runtime/, generated/, build.py, scenarios/)
in a temporary folder with its own empty compile cache, as separate processes, exactly as a user
types the commands:

* ``cold_build_s``: ``python build.py`` with generated/ emptied and an empty cache (every family
  derived, every file compiled);
* ``noop_build_s``: ``python build.py`` again, with nothing to do;
* ``edit_rebuild_s``: change one coefficient in one controller (a gain of c000, a different value
  each repetition), then ``python build.py`` to a loadable library;
* ``first_run_compile_s``: a fresh install's first ``rpo run scenarios/000_scenario_III.toml
  --duration 1`` with the committed generated/ and an empty cache (the whole command, so an
  upper bound on its compile time);
* ``edit_rebuild_ratio`` = cold / edit.

Each figure is the median of ``--repeat`` runs.  The last line is one JSON object with these keys.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from checkout_copy import importing  # noqa: E402  (tests/checkout_copy.py)

EDIT_FILE = "symbolic/controllers/c000.py"
EDIT_FROM = '"lambda_0 of the attitude surfaces (eqs. 53, 79, 80)", default=0.2)'


def _copy_checkout(dst: Path) -> Path:
    for d in ("symbolic", "runtime", "generated", "scenarios"):
        shutil.copytree(ROOT / d, dst / d, ignore=shutil.ignore_patterns("__pycache__", ".lock", "*.so"))
    shutil.copy(ROOT / "build.py", dst / "build.py")
    return dst


def _timed(cmd: list[str], cwd: Path, env: dict) -> tuple[float, str]:
    t0 = time.perf_counter()
    res = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, check=False)
    dt = time.perf_counter() - t0
    if res.returncode != 0:
        sys.exit(f"bench_build: {' '.join(cmd)} failed (exit {res.returncode}):\n{res.stdout[-2000:]}"
                 f"\n{res.stderr[-2000:]}")
    return dt, res.stdout + res.stderr


RUN_CODE = "import sys; from rpo.runtime.cli.main import main; sys.exit(main(sys.argv[1:]))"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3, help="repetitions of each measurement (median)")
    ap.add_argument("--json", action="store_true", help="print only the JSON line")
    args = ap.parse_args(argv)
    say = (lambda *_a: None) if args.json else print
    py = sys.executable
    cold, noop, edit, first = [], [], [], []
    say(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"python {platform.python_version()}")
    with tempfile.TemporaryDirectory(prefix="rpo-bench-build-") as tmp:
        base = Path(tmp)
        for rep in range(args.repeat):
            work = _copy_checkout(base / f"checkout{rep}")
            env = importing(work, dict(os.environ, RPO_CACHE_DIR=str(base / f"cache{rep}")))
            # first run of a fresh install: committed generated/, empty cache
            dt, out = _timed([py, "-c", RUN_CODE, "run", "scenarios/000_scenario_III.toml", "--duration", "1",
                              "--no-plots", "--quiet", "--out", str(base / f"run{rep}")], work, env)
            first.append(dt)
            say(f"[{rep + 1}/{args.repeat}] first rpo run (compile + 1 s of flight): {dt:.1f} s")
            # cold: nothing generated, empty cache
            env["RPO_CACHE_DIR"] = str(base / f"cold{rep}")
            for f in (work / "generated").iterdir():
                if f.name != "__init__.py":
                    f.unlink()
            dt, _ = _timed([py, "build.py"], work, env)
            cold.append(dt)
            say(f"[{rep + 1}/{args.repeat}] cold build: {dt:.1f} s")
            dt, out = _timed([py, "build.py"], work, env)
            if "nothing to regenerate" not in out or "nothing to compile" not in out:
                sys.exit(f"bench_build: the second build was not a no-op:\n{out}")
            noop.append(dt)
            say(f"[{rep + 1}/{args.repeat}] no-op build: {dt:.2f} s")
            src = work / EDIT_FILE
            text = src.read_text()
            if EDIT_FROM not in text:
                sys.exit(f"bench_build: {EDIT_FILE} no longer contains {EDIT_FROM!r}; update the benchmark")
            src.write_text(text.replace(EDIT_FROM, EDIT_FROM.replace("default=0.2)", f"default=0.2{rep + 1})")))
            dt, out = _timed([py, "build.py"], work, env)
            compiled = re.findall(r"\] (\S+\.c) \(", out)
            if "re-derived controller_c000;" not in out or not compiled or not all("c000" in f for f in compiled):
                sys.exit(f"bench_build: the edit rebuild did not re-derive and recompile exactly c000:\n{out}")
            edit.append(dt)
            say(f"[{rep + 1}/{args.repeat}] edit rebuild (one c000 gain): {dt:.1f} s")
            shutil.rmtree(work)
    med = {k: statistics.median(v) for k, v in
           (("cold_build_s", cold), ("noop_build_s", noop), ("edit_rebuild_s", edit), ("first_run_compile_s", first))}
    med["edit_rebuild_ratio"] = med["cold_build_s"] / med["edit_rebuild_s"]
    if not args.json:
        print("medians: " + ", ".join(f"{k} {v:.2f}" for k, v in med.items()))
        print("targets: edit_rebuild_s <= 20, cold_build_s <= 60, noop_build_s <= 1, first_run_compile_s <= 30, "
              "edit_rebuild_ratio >= 4")
    print(json.dumps({k: round(v, 3) for k, v in med.items()} | {"repeat": args.repeat}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
