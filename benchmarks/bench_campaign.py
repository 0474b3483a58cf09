"""How long a Monte Carlo campaign takes, what it costs beyond the simulation, and what it writes.

    python benchmarks/bench_campaign.py [--campaign scenarios/campaigns/000_III_mc.toml] [--runs 1000]
                                        [--repeat 3] [--json]

Per repetition, in this process (the model is loaded and compiled once, before any timing):

* ``bare_s``: the bare compute of the campaign's runs: every case's inputs prepared beforehand
  (draw, validation, pre-flight: not timed), then the lockstep runner (``Simulation.run_batch``) on
  the same batches the campaign sends to its workers, one after the other in this process;
* ``wall_1worker_s``: ``run_campaign(..., workers=1)`` into a new folder, everything included
  (draws, validation, pre-flight, simulation, metrics, verdicts, histories, manifest, summary);
* ``campaign_wall_s``: the same with the default workers (every core, the process pool), pool start
  included;
* ``dask_wall_s``: the same on a Dask LocalCluster of as many single-threaded workers, its start
  and shutdown included (skipped without ``dask[distributed]``).

Printed ratios: ``campaign_overhead`` = wall_1worker_s / bare_s (the campaign machinery's cost on
one core; 1.0 would be free), ``dask_ratio`` = dask_wall_s / campaign_wall_s, each the median over
``--repeat`` of the ratio within one repetition (the two are timed back to back there, so a drift
of the shared machine's speed between repetitions cancels; ``*_s`` are medians of the times);
``campaign_mb`` is the size of the pool run's folder [MB, 1e6 bytes].
``requirements``: each ``[requirements]`` entry of the campaign judged on the pool run's folder
(``{"name": "PASS 0/1000 failed", ...}``; docs/campaigns.md).  ``sobol_ishigami``: Sobol indices of
the Ishigami function (a = 7, b = 0.1) on the campaigns' own Saltelli design (2048 blocks), as
``"k/6"`` analytic first and total indices inside their 95 % bootstrap intervals, with the largest
distance to the analytic values (``sobol_ishigami_max_err``).  ``cpu``: avx512f, avx2 or other.
``--json``: the last line is one JSON object with these keys.  ``load_average`` (1 min) is
printed too: wall times on a machine shared with other jobs are not comparable.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DEFAULT = ROOT / "scenarios" / "campaigns" / "000_III_mc.toml"


def folder_mb(path: Path) -> float:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file()) / 1e6


def bare(camp, model, batch: int) -> float:
    """Seconds in run_batch for the campaign's valid cases, batched as the campaign batches them."""
    from rpo.runtime.campaign.execute import batches, prepare_case

    pres = []
    for c in range(camp.runs):
        _row, _draws, pre = prepare_case(camp, model, c)
        if not isinstance(pre, str):
            pres.append(pre)
    t = 0.0
    for idx in batches(list(range(len(pres))), batch):
        g = [pres[i] for i in idx]
        t0 = time.perf_counter()
        g[0].sim.run_batch(np.array([p.z0 for p in g]), g[0].inputs.duration, seeds=[p.inputs.seed for p in g],
                           params=np.array([p.sim.p for p in g]), gains=np.array([p.sim.k for p in g]),
                           record_every=g[0].inputs.record_every)
        t += time.perf_counter() - t0
    return t


def cpu() -> str:
    info = Path("/proc/cpuinfo")
    flags = info.read_text().split("flags", 1)[-1].split("\n", 1)[0] if info.exists() else ""
    return "avx512f" if "avx512f" in flags else "avx2" if "avx2" in flags else "other"


ISHIGAMI_A, ISHIGAMI_B = 7.0, 0.1


def ishigami(x: np.ndarray) -> np.ndarray:
    """The Ishigami function of the rows of ``x`` (n, 3), a = 7, b = 0.1."""
    return np.sin(x[:, 0]) + ISHIGAMI_A * np.sin(x[:, 1]) ** 2 + ISHIGAMI_B * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices() -> tuple[np.ndarray, np.ndarray]:
    """Analytic first and total indices of Ishigami (Saltelli et al., Global Sensitivity Analysis: The
    Primer, 2008, sec. 4.7): V1 = (1 + b pi^4 / 5)^2 / 2, V2 = a^2 / 8, V13 = 8 b^2 pi^8 / 225."""
    import math

    a, b, pi = ISHIGAMI_A, ISHIGAMI_B, math.pi
    v1, v2, v13 = 0.5 * (1 + b * pi**4 / 5) ** 2, a**2 / 8, 8 * b**2 * pi**8 / 225
    v = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


def ishigami_check(blocks: int = 2048, seed: int = 11) -> tuple[str, float]:
    """(``"k/6"``, max |estimate - analytic|): the first and total Sobol indices of the Ishigami function,
    its three inputs dispersed uniform on [-pi, pi] and drawn by the campaign's ``sobol-indices`` design,
    against the analytic values (Saltelli et al., Global Sensitivity Analysis: The Primer, 2008, 4.7)."""
    import math

    from rpo.runtime.campaign.dispersions import Dispersion
    from rpo.runtime.campaign.sampling import Design
    from rpo.runtime.campaign.sobol import block_size, sobol_indices, split_blocks

    pi = math.pi
    first, total = ishigami_indices()
    disps = [Dispersion(key=f"x{i}", dist="uniform", params={"dist": "uniform", "low": -pi, "high": pi},
                        nominal=0.0, unit="rad", size=1) for i in range(3)]
    n = blocks * block_size(3)
    us = Design("sobol-indices", seed, n, disps).uniforms_many(range(n))
    x = np.stack([np.asarray(d.values([u[d.key] for u in us]), float).reshape(-1) for d in disps], axis=1)
    y = ishigami(x)
    r = sobol_indices(*split_blocks(np.arange(n), y, 3), confidence=0.95, n_boot=1000, seed=0)
    inside = sum(int(ci[0] <= ref <= ci[1]) for cis, refs in ((r.first_ci, first), (r.total_ci, total))
                 for ci, ref in zip(cis, refs, strict=True))
    err = float(max(np.max(np.abs(r.first - first)), np.max(np.abs(r.total - total))))
    return f"{inside}/6", err


def requirement_verdicts(folder: Path) -> dict[str, str] | None:
    """Each requirement's verdict as recorded in ``folder``'s summary (None: the campaign states none)."""
    from rpo.runtime.campaign.requirements import read_summary_verdicts

    meta = read_summary_verdicts(folder)
    if not meta:
        return None
    return {v["name"]: f"{v['verdict']} {v['failures']}/{v['n']} failed" for v in meta["verdicts"]}


def campaign(camp, model, tmp: Path, name: str, **kw) -> tuple[float, Path]:
    from rpo.runtime.campaign import run_campaign, start_folder

    folder = tmp / name
    shutil.rmtree(folder, ignore_errors=True)
    t0 = time.perf_counter()
    out = run_campaign(camp, model, start_folder(camp, model, folder), **kw)
    wall = time.perf_counter() - t0
    if out.counts["error"]:
        sys.exit(f"bench_campaign: {out.counts['error']} runs ended in an error in {folder}")
    return wall, folder


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--campaign", default=str(DEFAULT))
    ap.add_argument("--runs", type=int, default=None, help="override campaign.runs (the issue's figure: 1000)")
    ap.add_argument("--duration", type=float, default=None, help="override simulation.duration [s]")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()

    from rpo.runtime.campaign import load_campaign
    from rpo.runtime.campaign.execute import BLOCKS_PER_BATCH, default_workers
    from rpo.runtime.model.loader import load_model
    from rpo.runtime.model.manifest import read_manifest

    camp0 = load_campaign(args.campaign, read_manifest(), runs=args.runs, duration=args.duration)
    model = load_model("auto", controllers=[camp0.scenario_data["simulation"].get("controller", "baseline")])
    camp = load_campaign(args.campaign, model.manifest, runs=args.runs, duration=args.duration)
    lanes = model.lanes()
    from rpo.runtime.campaign.execute import prepare_case
    dt = prepare_case(camp, model, 0)[2].sim.dt
    batch = camp.settings.batch or BLOCKS_PER_BATCH * (lanes.width if lanes is not None else 8)
    workers = default_workers()
    try:
        import dask.distributed  # noqa: F401
        has_dask = not args.no_dask
    except ImportError:
        has_dask = False
    sim = camp.scenario_data["simulation"]
    print(f"{camp.name}: {camp.runs} runs of {sim['duration']:g} s, controller {sim.get('controller')}, "
          f"record every {sim['record_every']} steps, {len(camp.channels)} channel fields; lanes "
          f"{lanes.width if lanes else '-'}, batch {batch}, {workers} workers", flush=True)
    keys = ("bare_s", "wall_1worker_s", "campaign_wall_s", "dask_wall_s", "campaign_mb")
    res: dict[str, list[float]] = {k: [] for k in keys}
    with tempfile.TemporaryDirectory(prefix="rpo-bench-campaign-") as tmpdir:
        tmp = Path(tmpdir)
        campaign(camp, model, tmp, "warm", workers=1, cases=range(min(camp.runs, batch)))  # imports, lane build
        for rep in range(args.repeat):
            res["bare_s"].append(bare(camp, model, batch))
            res["wall_1worker_s"].append(campaign(camp, model, tmp, "one", workers=1)[0])
            wall, folder = campaign(camp, model, tmp, "pool", workers=workers)
            res["campaign_wall_s"].append(wall)
            res["campaign_mb"].append(folder_mb(folder))
            verdicts = requirement_verdicts(folder)
            if has_dask:
                res["dask_wall_s"].append(campaign(camp, model, tmp, "dask", workers=workers, dask="local")[0])
            print(f"  rep {rep + 1}: " + ", ".join(f"{k} {v[-1]:.3g}" for k, v in res.items() if v), flush=True)
    med = {k: statistics.median(v) for k, v in res.items() if v}
    ishigami = ishigami_check()
    overhead = [w / b for w, b in zip(res["wall_1worker_s"], res["bare_s"], strict=True)]
    dask = [d / p for d, p in zip(res["dask_wall_s"], res["campaign_wall_s"], strict=False)]
    print("  per repetition: campaign_overhead " + ", ".join(f"{r:.3f}" for r in overhead)
          + ("; dask_ratio " + ", ".join(f"{r:.3f}" for r in dask) if dask else ""))
    out = {"runs": camp.runs, "duration_s": float(sim["duration"]), "workers": workers, "repeat": args.repeat,
           **{k: round(v, 4) for k, v in med.items()},
           "campaign_overhead": round(statistics.median(overhead), 4),
           "dask_ratio": round(statistics.median(dask), 4) if dask else None,
           "us_per_run_step": round(med["bare_s"] / (camp.runs * round(sim["duration"] / dt)) * 1e6, 4),
           "requirements": verdicts, "sobol_ishigami": ishigami[0], "sobol_ishigami_max_err": round(ishigami[1], 4),
           "cpu": cpu(), "load_average": round(os.getloadavg()[0], 2)}
    print(f"campaign_wall_s {out['campaign_wall_s']:.3g} (target <= 60 for 1000 runs of 300 s), campaign_overhead "
          f"{out['campaign_overhead']:.3g} (<= 1.10), campaign_mb {out['campaign_mb']:.3g} (<= 50), dask_ratio "
          f"{out['dask_ratio'] if out['dask_ratio'] is not None else '-'} (<= 1.3)")
    print(f"requirements: {out['requirements'] or 'none stated'}; Sobol indices of Ishigami inside their "
          f"intervals: {out['sobol_ishigami']} (max error {out['sobol_ishigami_max_err']:.3g}); cpu {out['cpu']}")
    if args.json:
        print(json.dumps(out))


if __name__ == "__main__":
    main()
