"""What the Lyapunov verification proves, and what re-checking and deriving it costs.

    python benchmarks/bench_verify.py [--json] [--derive] [--jobs 2]

Runs, as separate processes on a copy of this checkout (so nothing committed is touched):

* ``check_wall_s``: ``python verify.py --check`` (every claim re-checked, every committed certificate
  re-checked independently, stale ones re-derived), the command CI runs;
* ``derive_wall_s`` (only with ``--derive``, it takes longest): ``python verify.py --rederive --no-mutations``,
  every certificate derived from scratch;

and reads the committed report (``docs/verification.json``) for

* ``sampled_only``: claims whose only evidence is the numeric search (not proved, not failing);
* ``certified``, ``proved_symbolic``, ``fails``: claims per evidence;
* ``certificates_rechecked``: the percentage of certificates that passed the independent re-check in the
  ``--check`` run (parsed from its summary line);
* ``mutations_caught``: caught / total in the committed report, as "n/N".

The last line is one JSON object with these keys (and the host's CPU flags: avx512f or avx2 only).
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from checkout_copy import importing  # noqa: E402  (tests/checkout_copy.py)


def _copy(dst: Path) -> Path:
    for d in ("symbolic", "runtime", "generated", "scenarios", "docs"):
        shutil.copytree(ROOT / d, dst / d, ignore=shutil.ignore_patterns("__pycache__", ".lock", "*.so"))
    for f in ("build.py", "verify.py"):
        shutil.copy(ROOT / f, dst / f)
    return dst


def _run(cmd: list[str], cwd: Path) -> tuple[float, str, int]:
    t0 = time.perf_counter()
    res = subprocess.run(cmd, cwd=cwd, env=importing(cwd), capture_output=True, text=True, check=False)
    return time.perf_counter() - t0, res.stdout + res.stderr, res.returncode


def _cpu() -> str:
    try:
        flags = Path("/proc/cpuinfo").read_text()
    except OSError:
        return "unknown"
    return "avx512f" if " avx512f" in flags else ("avx2" if " avx2" in flags else "no avx2")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print only the JSON line")
    ap.add_argument("--derive", action="store_true", help="also derive every certificate from scratch")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    say = (lambda *_a: None) if args.json else print

    report = json.loads((ROOT / "docs" / "verification.json").read_text())
    claims = report["claims"]
    out: dict = {"claims": len(claims),
                 "sampled_only": sum(c["evidence"] == "sampled" for c in claims),
                 "proved_symbolic": sum(c["evidence"] == "symbolic" for c in claims),
                 "certified": sum(c["evidence"] == "certified" for c in claims),
                 "fails": sum(c["status"] == "fails" for c in claims)}
    muts = report.get("mutations") or []
    out["mutations_caught"] = f"{sum(m['caught'] for m in muts)}/{len(muts)}"
    with tempfile.TemporaryDirectory() as tmp:
        work = _copy(Path(tmp) / "checkout")
        say("verify.py --check ...")
        dt, text, rc = _run([sys.executable, "verify.py", "--check", "--jobs", str(args.jobs)], work)
        out["check_wall_s"] = round(dt, 1)
        out["check_exit"] = rc
        m = re.search(r"(\d+) certificates \((\d+) boxes\), (\d+) re-checked", text)
        if m:
            n, rechecked = int(m.group(1)), int(m.group(3))
            out["certificates"] = n
            out["certificate_boxes"] = int(m.group(2))
            out["certificates_rechecked"] = round(100.0 * rechecked / n, 1) if n else 100.0
        say(text[-1500:])
        if args.derive:
            say("verify.py --rederive --no-mutations ...")
            dt, text, rc = _run([sys.executable, "verify.py", "--rederive", "--no-mutations", "--jobs",
                                 str(args.jobs)], work)
            out["derive_wall_s"] = round(dt, 1)
            out["derive_exit"] = rc
            say(text[-1500:])
    out["cpu"] = _cpu()
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
