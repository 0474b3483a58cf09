"""Sobol indices of a campaign's Saltelli design (``sampling = "sobol-indices"``): the Ishigami
function against its analytic indices, the estimator against ``scipy.stats.sobol_indices``, the
design drawn one case at a time, group indices of a vector dispersion, and the report's table."""

from __future__ import annotations

import math

import numpy as np
import pytest
from drift_scenario import drift_scenario
from scipy import stats

from benchmarks.bench_campaign import ishigami, ishigami_indices
from rpo.runtime.campaign import loads_campaign, run_campaign, start_folder
from rpo.runtime.campaign.dispersions import Dispersion
from rpo.runtime.campaign.reporting import write_report
from rpo.runtime.campaign.sampling import Design
from rpo.runtime.campaign.sobol import indices, sobol_indices, split_blocks
from rpo.runtime.errors import CampaignError


def uniform_pi(key: str) -> Dispersion:
    return Dispersion(key=key, dist="uniform", params={"dist": "uniform", "low": -math.pi, "high": math.pi},
                      nominal=0.0, unit="rad", size=1)


def saltelli_ishigami(blocks: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(cases, outputs) of Ishigami on the campaign's design, through the dispersions' own draws."""
    disps = [uniform_pi(f"x{i}") for i in range(3)]
    design = Design("sobol-indices", seed, blocks * 5, disps)
    us = design.uniforms_many(range(blocks * 5))
    x = np.stack([np.asarray(d.values([u[d.key] for u in us]), float).reshape(-1) for d in disps], axis=1)
    return np.arange(blocks * 5), ishigami(x)


def test_ishigami_analytic_indices_lie_in_the_bootstrap_intervals():
    first, total = ishigami_indices()
    assert first == pytest.approx([0.3139, 0.4424, 0.0], abs=1e-4)
    assert total == pytest.approx([0.5576, 0.4424, 0.2437], abs=1e-4)
    cases, y = saltelli_ishigami(4096, seed=7)
    res = sobol_indices(*split_blocks(cases, y, 3), confidence=0.95, n_boot=1000, seed=0)
    assert res.blocks == 4096
    for i in range(3):
        assert res.first_ci[i, 0] <= first[i] <= res.first_ci[i, 1], (i, res.first[i], res.first_ci[i])
        assert res.total_ci[i, 0] <= total[i] <= res.total_ci[i, 1], (i, res.total[i], res.total_ci[i])
    # and the intervals are informative: no wider than 0.1
    assert np.all(np.diff(res.first_ci, axis=1) < 0.1) and np.all(np.diff(res.total_ci, axis=1) < 0.1)


def test_estimator_is_scipys_on_a_complete_design():
    cases, y = saltelli_ishigami(256, seed=3)
    f_A, f_B, f_AB = split_blocks(cases, y, 3)
    ref = stats.sobol_indices(func={"f_A": f_A[None], "f_B": f_B[None], "f_AB": f_AB[:, None]}, n=256)
    s, st = indices(f_A, f_B, f_AB)
    assert s == pytest.approx(ref.first_order, abs=1e-12)
    assert st == pytest.approx(ref.total_order, abs=1e-12)


def test_incomplete_blocks_are_left_out():
    cases, y = saltelli_ishigami(16, seed=3)
    y = y.copy()
    y[7] = np.nan                  # block 1
    keep = cases != 13             # block 2 lost a run
    f_A, _, f_AB = split_blocks(cases[keep], y[keep], 3)
    assert f_A.size == 14 and f_AB.shape == (3, 14)
    assert f_A[0] == y[0] and f_A[1] == y[15]


def test_design_draws_one_case_at_a_time():
    disps = [uniform_pi("a"), Dispersion(key="v", dist="normal", params={"dist": "normal", "std": [1.0, 2.0, 3.0]},
                                         nominal=[0.0, 0.0, 0.0], unit="m", size=3)]
    full = Design("sobol-indices", 11, 4 * 40, disps)
    longer = Design("sobol-indices", 11, 4 * 64, disps)
    for case in (0, 1, 2, 3, 77, 159):
        u, w = full.uniforms(case), longer.uniforms(case)
        assert all(np.array_equal(u[k], w[k]) for k in u)
    # block 5: A, B, AB_a (a from B, v from A), AB_v (v from B, a from A): v moves as one group
    A, B, ABa, ABv = (full.uniforms(4 * 5 + r) for r in range(4))
    assert np.array_equal(ABa["a"], B["a"]) and np.array_equal(ABa["v"], A["v"])
    assert np.array_equal(ABv["v"], B["v"]) and np.array_equal(ABv["a"], A["a"])
    assert not np.array_equal(A["v"], B["v"])


def test_group_indices_of_a_vector_dispersion():
    # y = x0 + x1 * x2 with x0 one dispersion and (x1, x2) one vector dispersion: the vector's group
    # carries all of the interaction, so its first and total indices agree (1/3 of V is x0's, 2/3 the vector's)
    disps = [Dispersion(key="s", dist="uniform", params={"dist": "uniform", "low": -1.0, "high": 1.0}, nominal=0.0,
                        unit="", size=1),
             Dispersion(key="v", dist="uniform", params={"dist": "uniform", "low": -math.sqrt(2), "high": math.sqrt(2)},
                        nominal=[0.0, 0.0], unit="", size=2)]
    n = 2048
    design = Design("sobol-indices", 5, n * 4, disps)
    us = design.uniforms_many(range(n * 4))
    s = np.asarray(disps[0].values([u["s"] for u in us]), float).reshape(-1)
    v = np.asarray(disps[1].values([u["v"] for u in us]), float).reshape(-1, 2)
    # var(x0) = 1/3; var(x1 x2) = (2/3)^2 = 4/9
    y = s + v[:, 0] * v[:, 1]
    res = sobol_indices(*split_blocks(np.arange(n * 4), y, 2), n_boot=500)
    ref = np.array([1 / 3, 4 / 9]) / (1 / 3 + 4 / 9)
    for i in range(2):
        assert res.first_ci[i, 0] <= ref[i] <= res.first_ci[i, 1]
        assert res.total_ci[i, 0] <= ref[i] <= res.total_ci[i, 1]


# --------------------------------------------------------------------------- a campaign

SOBOL_CAMPAIGN = drift_scenario("sobol", 200.0) + """[controller.baseline]
kp_pos = 0.0
kd_pos = 0.0
[campaign]
runs = 256
seed = 5
rate_hz = 0.1
sampling = "sobol-indices"
[dispersions.relative.position]
dist = "normal"
std = [5.0, 5.0, 5.0]
[dispersions.relative.velocity]
dist = "normal"
std = [0.0001, 0.0001, 0.0001]
"""


def test_runs_must_be_whole_blocks(model):
    with pytest.raises(CampaignError) as exc:
        loads_campaign(SOBOL_CAMPAIGN.replace("runs = 256", "runs = 250"), "s.toml", model.manifest)
    msg = str(exc.value)
    assert "campaign.runs = 250" in msg and "blocks of 4 runs" in msg and "\n" not in msg


def test_report_gives_the_indices_of_each_metric_against_each_dispersion(model, tmp_path):
    camp = loads_campaign(SOBOL_CAMPAIGN, "s.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path / "mc")
    out = run_campaign(camp, model, folder, workers=1)
    assert out.counts["ok"] == 256
    text = write_report(folder, out=tmp_path / "rep", figures=False).read_text()
    sec = text.split("## Global sensitivity (Sobol indices)", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in sec.splitlines() if line.startswith("| pos_err_final_m |")]
    assert len(rows) == 2, sec
    # free drift with no position gains: the final position error is decided by the initial offset
    # (std 5 m) far more than by the velocity (std 0.1 mm/s over 200 s: ~2 cm)
    first = rows[0].split("|")
    assert first[2].strip() == "`relative.position`"
    s_pos = float(first[3].split()[0])
    assert s_pos > 0.9 and "| 64 |" in rows[0]
    assert "## Which dispersion matters" in text  # the rank correlations stay beside it


def test_runs_of_a_block_share_their_noise_and_blocks_do_not(model):
    """Within a Saltelli block the runs differ only by the dispersions they swap: the sensor noise is the
    block's, else it would count as an interaction of every dispersion (each total index near 1)."""
    from rpo.runtime.campaign.execute import run_seed_of
    from rpo.runtime.campaign.records import case_seeds
    from rpo.runtime.campaign.sampling import run_seed

    camp = loads_campaign(SOBOL_CAMPAIGN, "s.toml", model.manifest)
    size = len(camp.dispersions) + 2
    seeds = [camp.seed_of(c) for c in range(3 * size)]
    blocks = [set(seeds[b * size:(b + 1) * size]) for b in range(3)]
    assert all(len(b) == 1 for b in blocks) and len(set.union(*blocks)) == 3
    # every place that makes a run's seed agrees: the batched draws, the error rows, the manifest check
    fresh = loads_campaign(SOBOL_CAMPAIGN, "s.toml", model.manifest)
    fresh.draws_many(range(3 * size))
    assert [fresh.seed_of(c) for c in range(3 * size)] == seeds
    resolved = camp.resolved()
    assert [run_seed_of(resolved, c) for c in range(3 * size)] == seeds
    assert list(case_seeds(camp.settings.seed, camp.runs, "sobol-indices", len(camp.dispersions))[:3 * size]) == seeds
    # any other design: each run its own noise, as before
    rnd = loads_campaign(SOBOL_CAMPAIGN.replace('"sobol-indices"', '"random"'), "s.toml", model.manifest)
    assert [rnd.seed_of(c) for c in range(5)] == [run_seed(5, c) for c in range(5)]
