"""Monte Carlo campaigns: statistics against an analytic case, dispersions provably applied,
determinism across executors, SIGKILL and resume, divergence and invalid draws, bad input.

The analytic reference is the Clohessy-Wiltshire solution (independent of the generated model):
uncontrolled relative motion about a circular orbit from a Gaussian initial state; the campaign's
final mean and covariance must match the linear propagation of the initial ones through the CW
state-transition matrix within the sampling confidence interval.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from drift_scenario import drift_scenario
from scipy import stats
from scipy.spatial.transform import Rotation

from rpo.runtime.campaign import load_campaign, loads_campaign, run_campaign, start_folder, storage
from rpo.runtime.campaign.sampling import Design, run_seed, run_seeds, seed_words
from rpo.runtime.errors import CampaignError

ROOT = Path(__file__).resolve().parents[1]
MU = 3.986004418e14
A_ORBIT = 7.0e6

#: A free-flying pair on a circular orbit, no disturbance, the baseline law with zero position
#: gains and ideal actuators: the relative translation is the uncontrolled nonlinear relative
#: motion, which CW approximates to O(|r| / a).
BASE = drift_scenario("cw", 1500.0, A_ORBIT) + """[controller.baseline]
kp_pos = 0.0
kd_pos = 0.0
kp_att = 0.0
kd_att = 0.0
"""

CW_CAMPAIGN = BASE + """
[campaign]
runs = 256
seed = 11
rate_hz = 0.1
[dispersions.relative.position]
dist = "normal"
std = [2.0, 3.0, 1.5]
[dispersions.relative.velocity]
dist = "normal"
std = [0.002, 0.001, 0.0015]
"""


def cw_stm(n: float, t: float) -> np.ndarray:
    """Clohessy-Wiltshire state-transition matrix, x radial, y along-track, z normal; state [r, v]
    with v the derivative in the rotating frame (rpo's LVLH)."""
    s, c = math.sin(n * t), math.cos(n * t)
    return np.array([
        [4 - 3 * c, 0, 0, s / n, 2 * (1 - c) / n, 0],
        [6 * (s - n * t), 1, 0, -2 * (1 - c) / n, (4 * s - 3 * n * t) / n, 0],
        [0, 0, c, 0, 0, s / n],
        [3 * n * s, 0, 0, c, 2 * s, 0],
        [-6 * n * (1 - c), 0, 0, -2 * s, 4 * c - 3, 0],
        [0, 0, -n * s, 0, 0, c],
    ])


@pytest.fixture(scope="module")
def cw_folder(model, tmp_path_factory):
    camp = loads_campaign(CW_CAMPAIGN, "cw.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path_factory.mktemp("cw") / "mc")
    out = run_campaign(camp, model, folder, workers=1)
    assert out.counts["ok"] == camp.runs
    return folder, camp


def _final_states(folder: Path, runs: int) -> np.ndarray:
    rows = storage.read_rows(folder)
    X = []
    for c in range(runs):
        cols, _, _ = storage.read_history(folder, c, rows)
        X.append([cols[k][-1] for k in ("r_x", "r_y", "r_z", "v_x", "v_y", "v_z")])
        assert rows[c]["status"] == "ok"
    return np.array(X, float)


def test_statistics_match_the_clohessy_wiltshire_propagation(cw_folder):
    folder, camp = cw_folder
    n = math.sqrt(MU / A_ORBIT**3)
    phi = cw_stm(n, 1500.0)
    m0 = np.array([50.0, 20.0, -10.0, 0.0, -0.05, 0.01])
    P0 = np.diag(np.array([2.0, 3.0, 1.5, 0.002, 0.001, 0.0015]) ** 2)
    mean_ref, P_ref = phi @ m0, phi @ P0 @ phi.T
    X = _final_states(folder, camp.runs)
    N = X.shape[0]
    # the mean: each component within 4.5 standard errors (two-sided p ~ 7e-6 per component)
    se = np.sqrt(np.diag(P_ref) / N)
    z = (X.mean(axis=0) - mean_ref) / se
    assert np.all(np.abs(z) < 4.5), z
    # the variances: (N - 1) S_ii / P_ii ~ chi^2(N - 1); inside its 1e-5 .. 1 - 1e-5 quantiles
    S = np.cov(X.T)
    ratio = (N - 1) * np.diag(S) / np.diag(P_ref)
    lo, hi = stats.chi2.ppf([1e-5, 1 - 1e-5], N - 1)
    assert np.all((ratio > lo) & (ratio < hi)), (ratio, lo, hi)
    # the correlations that CW makes strong (|rho| > 0.3): Fisher z within 4.5 / sqrt(N - 3)
    d = np.sqrt(np.diag(P_ref))
    R_ref, R = P_ref / np.outer(d, d), S / np.outer(np.sqrt(np.diag(S)), np.sqrt(np.diag(S)))
    strong = np.abs(R_ref) > 0.3
    np.fill_diagonal(strong, False)
    assert strong.sum() >= 4  # the along-track/radial coupling: a test that can fail
    dz = np.abs(np.arctanh(R[strong]) - np.arctanh(R_ref[strong])) * math.sqrt(N - 3)
    assert np.all(dz < 4.5), dz
    # and a wrong reference is told apart: without the Coriolis coupling the along-track variance is off
    phi_bad = phi.copy()
    phi_bad[1, 0] = 0.0
    P_bad = phi_bad @ P0 @ phi_bad.T
    assert not lo < (N - 1) * S[1, 1] / P_bad[1, 1] < hi


def test_dispersions_are_applied_as_drawn(model, tmp_path):
    text = BASE + """
[campaign]
runs = 24
seed = 5
rate_hz = 0.1
sampling = "lhs"
[dispersions.relative.position]
dist = "normal"
std = 2.0
[dispersions.chaser.mass]
dist = "uniform"
low = 80.0
high = 120.0
[dispersions.chaser.inertia]
dist = "inertia"
moment_std = 0.1
axes_sigma_deg = 3.0
[dispersions.target.quaternion]
dist = "rotation"
sigma_deg = 10.0
[dispersions.controller.baseline.kd_att]
dist = "lognorm"
shapes = { s = 0.3 }
scale = 2.0
"""
    camp = loads_campaign(text.replace('duration = 1500.0', 'duration = 20.0'), "applied.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path / "mc")
    before = camp.hash
    run_campaign(camp, model, folder, workers=1)
    assert camp.hash == before  # the runs' scenarios share the base's tables: none was changed
    rows = storage.read_rows(folder)
    for c in range(camp.runs):
        draws, row = camp.draws(c), rows[c]
        applied = row["applied"]
        # the initial state the simulation was handed, and its first recorded row
        assert applied["z0"]["r"] == draws["relative.position"]
        q = np.array(draws["target.quaternion"])
        assert np.allclose(applied["z0"]["q_t"], q / np.linalg.norm(q), rtol=0, atol=1e-15)
        cols, _, _ = storage.read_history(folder, c)
        assert [cols[f"r_{a}"][0] for a in "xyz"] == list(np.float32(draws["relative.position"]))
        # the parameters and gains in the vectors passed to the lockstep loop
        assert applied["p"]["chaser_mass"] == [draws["chaser.mass"]]
        I = np.array(draws["chaser.inertia"])
        want = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
        labels = model.manifest.layouts["p"].field("chaser_inertia").labels
        ax = {"x": 0, "y": 1, "z": 2}
        got = dict(zip([(ax[lbl[-2]], ax[lbl[-1]]) for lbl in labels], applied["p"]["chaser_inertia"], strict=True))
        assert sorted(got.values()) == sorted(want)
        assert all(got[(i, j)] == I[i, j] for (i, j) in got)
        assert applied["k"]["kd_att"] == [draws["controller.baseline.kd_att"]]
        # and the summary's draw columns are the same numbers
        assert row["draws"]["draw.chaser.mass"] == draws["chaser.mass"]
        # the only fields that differ from the undispersed scenario are the dispersed ones
        assert set(applied["p"]) == {"chaser_mass", "chaser_inertia"}
        assert set(applied["k"]) == {"kd_att"}
    # the inertia draws are physical (SPD, triangle inequality) and the rotations are of ~10 deg
    angles = []
    for c in range(camp.runs):
        d = camp.draws(c)
        lam = np.linalg.eigvalsh(np.array(d["chaser.inertia"]))
        assert lam.min() > 0 and lam[0] + lam[1] >= lam[2]
        rel = Rotation.from_quat([0, 0, 0, 1]).inv() * Rotation.from_quat(d["target.quaternion"])
        angles.append(np.degrees(rel.magnitude()))
    assert 5 < np.median(angles) < 25  # |phi| of a 3-D normal of 10 deg per axis: median ~15 deg


def test_seeds_streams_and_designs(model):
    camp = loads_campaign(CW_CAMPAIGN, "cw.toml", model.manifest)
    more = loads_campaign(CW_CAMPAIGN + '[dispersions.chaser.mass]\ndist = "normal"\nrel_std = 0.05\n',
                          "cw2.toml", model.manifest)
    bigger = loads_campaign(CW_CAMPAIGN, "cw.toml", model.manifest, runs=1000)
    for c in (0, 7, 255):
        a, b = camp.draws(c), more.draws(c)
        # adding a dispersion leaves the other draws (and the noise seed) unchanged; so does adding runs
        assert a["relative.position"] == b["relative.position"] == bigger.draws(c)["relative.position"]
        assert a["relative.velocity"] == b["relative.velocity"]
        assert camp.seed_of(c) == more.seed_of(c) == run_seed(11, c)
    assert len({camp.seed_of(c) for c in range(256)}) == 256
    # a Latin hypercube puts exactly one run in each of the N strata of every coordinate
    d = Design("lhs", 3, 64, camp.dispersions)
    U = np.array([d.uniforms(c)["relative.position"] for c in range(64)])
    for j in range(3):
        assert sorted(np.floor(U[:, j] * 64).astype(int)) == list(range(64))
    # Sobol: the first 2^k points of a scrambled Sobol sequence are balanced in each half
    s = Design("sobol", 3, 64, camp.dispersions)
    U = np.array([s.uniforms(c)["relative.position"] for c in range(64)])
    assert all((U[:, j] < 0.5).sum() == 32 for j in range(3))


def test_batch_draws_are_the_single_draws(model, tmp_path):
    # a batch of runs takes its uniforms from one array computation of SeedSequence's hash
    # (sampling.seed_words): the same words as numpy's SeedSequence, the same draws as one case alone
    rng = np.random.default_rng(4)
    for seed in (0, 1, 3000, 2**32, 2**63 - 1, 2**70 + 9):
        keys = [(int(rng.integers(0, 2**63)) * 2 + 1, int(c)) for c in (0, 1, 2**32 - 1, 2**32, 12345)]
        keys += [(5, 0), (0x6E6F697365, 3), (2**40, 7, 1)]
        for n in (1, 3, 17):
            got = seed_words(seed, keys, n)
            for k, row in zip(keys, got, strict=True):
                assert np.array_equal(row, np.random.SeedSequence(seed, spawn_key=k).generate_state(n, np.uint64))
    assert run_seeds(11, [0, 5, 2**33]) == [run_seed(11, c) for c in (0, 5, 2**33)]
    path = ROOT / "scenarios" / "campaigns" / "000_III_mc.toml"
    for sampling in ("random", "lhs"):
        text = path.read_text().replace('sampling = "random"', f'sampling = "{sampling}"')
        (tmp_path / "c.toml").write_text(text.replace('extends = "../', f'extends = "{path.parents[1]}/'))
        camp = load_campaign(tmp_path / "c.toml", model.manifest, runs=40)
        cases = [0, 3, 17, 39]
        for c, many in zip(cases, camp.draws_many(cases), strict=True):
            assert json.dumps(many) == json.dumps(camp.draws(c))
            # the noise seeds the batch made at once are each run's own
            assert camp.seed_of(c) == run_seed(camp.settings.seed, c) == camp.case_data(c)["simulation"]["seed"]


def test_same_summary_bytes_in_process_pool_and_dask(model, tmp_path):
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 40").replace("duration = 1500.0", "duration = 200.0")
    text = text.replace("rate_hz = 0.1\n", "rate_hz = 0.1\nbatch = 8\n")
    camp = loads_campaign(text, "det.toml", model.manifest)
    out = {}
    for name, kw in (("one", {"workers": 1}), ("pool", {"workers": 2}), ("dask", {"workers": 2, "dask": "local"})):
        folder = start_folder(camp, model, tmp_path / name)
        res = run_campaign(camp, model, folder, **kw)
        assert res.counts["ok"] == 40, res
        out[name] = (folder / storage.SUMMARY).read_bytes()
    assert out["one"] == out["pool"] == out["dask"]
    # the summary made from the rows in memory is the one of the manifest's lines as read back
    storage.write_summary(folder, storage.read_resolved(folder), storage.read_rows(folder))
    assert (folder / storage.SUMMARY).read_bytes() == out["dask"]
    names = pq.read_schema(folder / storage.SUMMARY).names
    assert [c for c in names if c.startswith("draw.")] == [f"draw.relative.position[{i}]" for i in range(3)] + [
        f"draw.relative.velocity[{i}]" for i in range(3)]


def _rpo(*args, **kw) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONWARNINGS": "default"}
    return subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", *map(str, args)], env=env, capture_output=True,
                          text=True, timeout=kw.pop("timeout", 300), **kw)


def _wait_for(cond, timeout=120.0) -> None:
    t0 = time.perf_counter()
    while not cond():
        assert time.perf_counter() - t0 < timeout, "the campaign did not get there in time"
        time.sleep(0.005)


@pytest.mark.slow  # ~40 s: seven campaigns of 64 runs as subprocesses
def test_sigkill_at_any_moment_then_resume_gives_the_same_summary(model, tmp_path):
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 64").replace("duration = 1500.0", "duration = 3000.0")
    text = text.replace("rate_hz = 0.1\n", "rate_hz = 0.1\nbatch = 4\n")
    path = tmp_path / "kill.toml"
    path.write_text(text)
    ref = tmp_path / "ref"
    res = _rpo("mc", "run", path, "--out", ref, "--workers", "2", "-q")
    assert res.returncode == 0, res.stderr
    want = (ref / storage.SUMMARY).read_bytes()

    def lines(folder: Path) -> int:
        try:
            return (folder / storage.MANIFEST).read_bytes().count(b"\n")
        except FileNotFoundError:
            return 0

    def histories(folder: Path) -> int:
        d = folder / storage.HISTORIES
        return len(list(d.glob(storage.HISTORY_GLOB))) if d.is_dir() else 0

    # the moments: as soon as the folder exists (before any run), once a history is written (its
    # line maybe not), and twice in the middle of the campaign (after 8 and 40 lines)
    moments = {"folder": lambda f: (f / storage.RESOLVED).exists(), "history": lambda f: histories(f) > 0,
               "8 lines": lambda f: lines(f) >= 8, "40 lines": lambda f: lines(f) >= 40}
    for name, cond in moments.items():
        folder = tmp_path / name.replace(" ", "_")
        proc = subprocess.Popen([sys.executable, "-m", "rpo.runtime.cli.main", "mc", "run", str(path), "--out",
                                 str(folder), "--workers", "2", "-q"], start_new_session=True,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _wait_for(lambda f=folder, c=cond, p=proc: c(f) or p.poll() is not None)
        os.killpg(proc.pid, signal.SIGKILL)  # the command and its workers, at once
        proc.wait()
        done = len(storage.read_rows(folder))
        assert done < 64, f"{name}: the campaign finished before the kill"
        res = _rpo("mc", "resume", folder, "--workers", "2", "-q")
        assert res.returncode == 0, res.stderr
        assert (folder / storage.SUMMARY).read_bytes() == want, (name, done)
        assert not list(folder.rglob(".*.tmp"))
        _assert_same_histories(folder, ref)
    # SIGINT (and SIGTERM): the command stops dispatching, keeps what came back, writes the summary
    # of the runs so far and exits 130 (143) naming resume; resume then gives the same summary
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        folder = tmp_path / f"signal_{code}"
        proc = subprocess.Popen([sys.executable, "-m", "rpo.runtime.cli.main", "mc", "run", str(path), "--out",
                                 str(folder), "--workers", "2", "-q"], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        _wait_for(lambda f=folder, p=proc: lines(f) >= 8 or p.poll() is not None)
        proc.send_signal(sig)
        _out, err = proc.communicate(timeout=120)
        assert proc.returncode == code, (proc.returncode, err)
        assert "rpo mc resume" in err and "Traceback" not in err, err
        partial = pq.read_table(folder / storage.SUMMARY)
        assert 8 <= partial.num_rows < 64
        res = _rpo("mc", "resume", folder, "--workers", "2", "-q")
        assert res.returncode == 0, res.stderr
        assert (folder / storage.SUMMARY).read_bytes() == want
    # a cut-off last line (a write killed half-way) is ignored and repaired by resume
    folder = tmp_path / "8_lines"
    raw = (folder / storage.MANIFEST).read_bytes()
    (folder / storage.MANIFEST).write_bytes(raw + raw.splitlines()[0][:37])
    res = _rpo("mc", "resume", folder, "-q")
    assert res.returncode == 0, res.stderr
    assert (folder / storage.SUMMARY).read_bytes() == want
    assert (folder / storage.MANIFEST).read_bytes() == raw


def _assert_same_histories(folder: Path, ref: Path) -> None:
    """Every case of ``ref`` has the same history in ``folder`` (values and types), and ``folder``
    holds no history file that no manifest line names."""
    rows, ref_rows = storage.read_rows(folder), storage.read_rows(ref)
    named = {r["history"] for r in rows.values() if "history" in r}
    assert {p.name for p in (folder / storage.HISTORIES).glob(storage.HISTORY_GLOB)} == named
    got = dict(storage.read_histories(folder, sorted(rows), rows))
    want = dict(storage.read_histories(ref, sorted(ref_rows), ref_rows))
    assert got.keys() == want.keys()
    for c, w in want.items():
        g = got[c]
        assert (g is None) == (w is None), c
        if w is not None:
            assert list(g) == list(w) and all(g[k].dtype == w[k].dtype and np.array_equal(g[k], w[k]) for k in w), c


def test_a_batch_lost_before_its_lines_is_flown_again_and_its_file_removed(model, tmp_path):
    # a kill after a batch's history file was renamed into place but before its lines: its runs are
    # not done; resume flies them (here in other batches) and removes the file no line names
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 12").replace("duration = 1500.0", "duration = 200.0")
    camp = loads_campaign(text, "lost.toml", model.manifest)
    ref = start_folder(camp, model, tmp_path / "ref")
    run_campaign(camp, model, ref, workers=1, batch=4)
    assert len(list((ref / storage.HISTORIES).glob(storage.HISTORY_GLOB))) == 3
    folder = start_folder(camp, model, tmp_path / "mc")
    run_campaign(camp, model, folder, workers=1, batch=4)
    raw = (folder / storage.MANIFEST).read_bytes().splitlines(keepends=True)
    lost = [json.loads(x) for x in raw[-4:]]
    (folder / storage.MANIFEST).write_bytes(b"".join(raw[:-4]))
    orphan = folder / storage.HISTORIES / lost[0]["history"]
    assert orphan.exists() and {r["history"] for r in lost} == {orphan.name}
    out = run_campaign(camp, model, folder, workers=1, batch=3)  # resume: the 4 lost runs, in 2 batches
    assert out.flown_now == 4 and out.counts["ok"] == 12
    assert not orphan.exists()
    assert (folder / storage.SUMMARY).read_bytes() == (ref / storage.SUMMARY).read_bytes()
    _assert_same_histories(folder, ref)


def test_resume_refuses_a_changed_campaign_or_model(model, tmp_path):
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 8").replace("duration = 1500.0", "duration = 20.0")
    path = tmp_path / "c.toml"
    path.write_text(text)
    folder = tmp_path / "mc"
    assert _rpo("mc", "run", path, "--out", folder, "--workers", "1", "-q").returncode == 0
    path.write_text(text.replace("std = [2.0, 3.0, 1.5]", "std = [2.0, 3.0, 2.5]"))
    res = _rpo("mc", "resume", folder)
    assert res.returncode == 2 and "dispersions[0].params.std[2]: 1.5 then, 2.5 now" in res.stderr, res.stderr
    path.write_text(text)
    original = json.loads((folder / storage.RESOLVED).read_text())
    fp = original["model_fingerprint"]
    step = f"step_{original['controller']}.c"
    assert step in fp["files"] and "plant_advance.c" in fp["files"] and "plant_jac.c" not in fp["files"]
    # a rebuild that changed nothing its runs reach (another controller, say): the manifest's hash
    # differs, the fingerprint does not: resumed
    resolved = {**original, "model_hash": "0" * 64}
    (folder / storage.RESOLVED).write_text(json.dumps(resolved))
    res = _rpo("mc", "resume", folder)
    assert res.returncode == 0, res.stderr
    # a file its runs reach changed: refused naming it
    resolved = json.loads(json.dumps(original))
    resolved["model_fingerprint"]["files"][step] = "0" * 64
    (folder / storage.RESOLVED).write_text(json.dumps(resolved))
    res = _rpo("mc", "resume", folder)
    assert res.returncode == 2 and "the model changed" in res.stderr and f"generated/{step} changed" in res.stderr
    res = _rpo("run", "--campaign", folder, "--case", 1)
    assert res.returncode == 2 and f"generated/{step} changed" in res.stderr, res.stderr
    # a folder of an older rpo (no fingerprint): the whole manifest's hash decides
    resolved = {k: v for k, v in original.items() if k != "model_fingerprint"}
    resolved["model_hash"] = "0" * 64
    (folder / storage.RESOLVED).write_text(json.dumps(resolved))
    res = _rpo("mc", "resume", folder)
    assert res.returncode == 2 and "the model changed" in res.stderr and "no per-file fingerprint" in res.stderr


def test_diverging_and_invalid_draws_are_recorded_and_the_campaign_goes_on(model, tmp_path):
    # a relative speed above 1e8 m / 3000 s = 33 km/s carries |r| past the divergence bound (1e8 m)
    # before the end: a divergence in the middle of the run, not a refused input
    text = BASE.replace("duration = 1500.0", "duration = 3000.0") + """
[campaign]
runs = 32
seed = 2
rate_hz = 0.01
[dispersions.relative.velocity]
dist = "uniform"
low = [0.0, 0.0, 0.0]
high = [6.0e4, 0.0, 0.0]
[dispersions.chaser.mass]
dist = "normal"
mean = 3.0
std = 3.0
"""
    camp = loads_campaign(text, "div.toml", model.manifest)
    folder = start_folder(camp, model, tmp_path / "mc")
    out = run_campaign(camp, model, folder, workers=2)
    rows = storage.read_rows(folder)
    assert len(rows) == 32 and out.missing == []
    c = out.counts
    assert c["diverged"] > 0 and c["ok"] > 0 and c["invalid"] > 0 and c["error"] == 0, c
    for r in rows.values():
        mass = r["draws"]["draw.chaser.mass"]
        if r["status"] == "invalid":
            # a refused draw: told why, never clipped (the drawn value is kept as drawn) nor flown
            assert mass < 0.01 and "chaser.mass" in r["message"], r["message"]
            assert "history" not in r and not storage.legacy_history_path(folder, r["case"]).exists()
        else:
            assert mass >= 0.01
        if r["status"] == "diverged":
            assert "diverged in step" in r["message"] and r["outcome"]["diverged"] and r["outcome"]["failed"]
            step = int(r["message"].split("diverged in step ")[1].split()[0])
            assert 100 < step < 3000  # in the middle of the run
            cols, _, _ = storage.read_history(folder, r["case"])
            assert cols["t"][-1] < 3000.0  # its history ends where it stopped
    table = pq.read_table(folder / storage.SUMMARY)
    assert table.column("status").to_pylist().count("invalid") == c["invalid"]


BAD = {
    "unknown key": ('[dispersions.relative.positon]\ndist = "normal"\nstd = 1.0\n', "dispersions.relative.positon"),
    "unknown distribution": ('[dispersions.chaser.mass]\ndist = "gaussian"\nstd = 1.0\n', "unknown distribution"),
    "negative spread": ('[dispersions.chaser.mass]\ndist = "normal"\nstd = -1.0\n', "dispersions.chaser.mass.std"),
    "empty truncation": ('[dispersions.chaser.mass]\ndist = "normal"\nstd = 1.0\nlow = 200.0\nhigh = 300.0\n',
                         "excludes everything"),
    "bad shape": ('[dispersions.chaser.mass]\ndist = "lognorm"\nshapes = { k = 1.0 }\n', "shapes.k"),
    "runs = 0": ("", "campaign.runs"),
    "fixed section": ('[dispersions.simulation.duration]\ndist = "uniform"\nlow = 1.0\nhigh = 2.0\n',
                      "dispersions.simulation.duration"),
}


def _bad_text(case: str) -> str:
    extra, _ = BAD[case]
    return BASE + "\n[campaign]\nruns = " + ("0" if case == "runs = 0" else "10") + "\n" + extra


def test_a_draw_that_overflows_is_an_invalid_run_named_in_its_message(model, tmp_path):
    # a spread so wide that some draws overflow to inf: refused like any invalid draw (the campaign
    # goes on), its summary cell null, the message naming the value
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 16").replace("duration = 1500.0", "duration = 20.0")
    text += "\n[dispersions.chaser.mass]\ndist = \"normal\"\nstd = 1e308\n"
    camp = loads_campaign(text, "inf.toml", model.manifest)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the overflow is the row's message, not a NumPy warning
        out = run_campaign(camp, model, start_folder(camp, model, tmp_path / "mc"), workers=1)
    assert out.counts["invalid"] == 16 and out.missing == []
    rows = storage.read_rows(tmp_path / "mc")
    over = [r for r in rows.values() if r["draws"]["draw.chaser.mass"] is None]
    assert over and all("chaser.mass = inf" in r["message"] or "chaser.mass = -inf" in r["message"] for r in over)
    mass = pq.read_table(tmp_path / "mc" / storage.SUMMARY).column("draw.chaser.mass").to_pylist()
    assert mass.count(None) == len(over)


@pytest.mark.parametrize("case", list(BAD))
def test_bad_campaign_is_refused_naming_the_key(model, case):
    with pytest.raises(CampaignError) as exc:
        loads_campaign(_bad_text(case), "bad.toml", model.manifest)
    msg = str(exc.value)
    assert BAD[case][1] in msg and "\n" not in msg and msg.startswith("bad.toml: "), msg


@pytest.mark.parametrize("case", ["unknown key", "runs = 0"])
def test_bad_campaign_is_one_line_exit_2_and_writes_nothing(tmp_path, case):
    path = tmp_path / "bad.toml"
    path.write_text(_bad_text(case))
    res = _rpo("mc", "run", path, "--out", tmp_path / "out")
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and BAD[case][1] in lines[0], res.stderr
    assert "Traceback" not in res.stderr
    assert not (tmp_path / "out").exists()
    res = _rpo("mc", "run", path, "--out", tmp_path / "out", "--runs", "0")
    assert res.returncode == 2 and "--runs" in res.stderr and "Traceback" not in res.stderr


def test_bad_campaign_in_python(model):
    with pytest.raises(CampaignError, match=r"dispersions\.orbit\.eccentricity\.low = -1\.0: .*excludes"):
        loads_campaign(BASE + '[campaign]\nruns = 3\n[dispersions.orbit.eccentricity]\ndist = "normal"\n'
                              'std = 0.001\nlow = -1.0\nhigh = -0.5\n', "x", model.manifest)
    with pytest.raises(CampaignError, match="median"):  # almost every draw would be refused
        loads_campaign(BASE + '[campaign]\nruns = 3\n[dispersions.chaser.mass]\ndist = "uniform"\n'
                              'low = -10.0\nhigh = -1.0\n', "x", model.manifest)


def test_one_case_flown_alone_is_the_campaigns_run(model, tmp_path):
    text = CW_CAMPAIGN.replace("runs = 256", "runs = 12").replace("duration = 1500.0", "duration = 100.0")
    path = tmp_path / "c.toml"
    path.write_text(text)
    folder = tmp_path / "mc"
    assert _rpo("mc", "run", path, "--out", folder, "-q").returncode == 0
    res = _rpo("run", "--campaign", folder, "--case", 7, "--no-plots")
    assert res.returncode == 0, res.stderr
    assert "the campaign's run, bit for bit" in res.stdout
    case_dir = folder / "cases" / "case_000007"
    assert (case_dir / "timeseries.parquet").exists()
    # its scenario.toml is the case's scenario: flying it again gives the same run
    rerun = _rpo("run", case_dir / "scenario.toml", "--out", tmp_path / "rerun", "--no-plots", "-q")
    assert rerun.returncode == 0, rerun.stderr
    a = pq.read_table(case_dir / "timeseries.parquet")
    b = pq.read_table(tmp_path / "rerun" / "timeseries.parquet")
    assert a.column("r_x").to_pylist() == b.column("r_x").to_pylist()
    bad = _rpo("run", "--campaign", folder, "--case", 12)
    assert bad.returncode == 2 and "--case 12: must be in [0, 11]" in bad.stderr
    # without its history file, the re-fly compares status and metrics, and says so
    for h in (folder / storage.HISTORIES).iterdir():
        h.unlink()
    res = _rpo("run", "--campaign", folder, "--case", 3, "--no-plots", "--out", tmp_path / "again")
    assert res.returncode == 0, res.stderr
    assert "bit for bit (status and metrics; its history file is missing" in res.stdout


def test_report_of_a_campaign_folder(cw_folder):
    from rpo.runtime.campaign import load_history, load_summary
    from rpo.runtime.campaign.reporting import write_report

    folder, camp = cw_folder
    path = write_report(folder, figures=False)
    text = path.read_text()
    assert f"runs requested: {camp.runs}; done: {camp.runs}" in text and "## Failure rates" in text
    df = load_summary(folder)  # the Python API: pandas
    assert len(df) == camp.runs and list(df["case"]) == list(range(camp.runs))
    assert df.attrs["units"]["pos_err_final_m"] == "m"
    h = load_history(folder, 3)
    assert h["t"].iloc[-1] == 1500.0 and "err_pos_m" in h.columns


@pytest.mark.slow  # a Dask cluster of its own: ~10 s
def test_dask_scheduler_address_gives_the_same_summary(model, tmp_path):
    from dask.distributed import LocalCluster

    text = CW_CAMPAIGN.replace("runs = 256", "runs = 24").replace("duration = 1500.0", "duration = 100.0")
    camp = loads_campaign(text.replace("rate_hz = 0.1\n", "rate_hz = 0.1\nbatch = 8\n"), "addr.toml",
                          model.manifest)
    one = start_folder(camp, model, tmp_path / "one")
    run_campaign(camp, model, one, workers=1)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        folder = start_folder(camp, model, tmp_path / "addr")
        out = run_campaign(camp, model, folder, workers=2, dask=cluster.scheduler_address)
    assert out.counts["ok"] == 24
    assert (folder / storage.SUMMARY).read_bytes() == (one / storage.SUMMARY).read_bytes()


def test_fast_inverse_cdfs_agree_with_scipy():
    from rpo.runtime.campaign.dispersions import _truncated_normal_ppf
    from rpo.runtime.campaign.sampling import _uniforms

    u = np.linspace(1e-6, 1 - 1e-6, 201)
    for a, b in ((-1.0, 2.0), (-4.0, 4.0), (0.5, 3.0), (2.0, 9.0), (-9.0, -3.0), (-0.1, 0.1)):
        mine = np.array([_truncated_normal_ppf(x, a, b) for x in u])
        ref = stats.truncnorm.ppf(u, a, b)
        assert np.allclose(mine, ref, rtol=1e-12, atol=1e-12), (a, b, np.max(np.abs(mine - ref)))
        assert np.all((mine >= a) & (mine <= b))
    w = np.concatenate([_uniforms(7, 123, c, 64) for c in range(200)])
    assert np.all((w > 0) & (w < 1))
    assert stats.kstest(w, "uniform").pvalue > 1e-4  # uniform (a fixed sample: this either always passes or never)


def test_rotation_draws_agree_with_scipy_rotation():
    from rpo.runtime.campaign.dispersions import _rotvec_quat
    from rpo.runtime.frames import quat_multiply

    rng = np.random.default_rng(4)
    for scale in (1e-9, 1e-5, 1e-3, 0.1, 1.0, 3.0):
        phi = rng.normal(size=3) * scale
        assert np.allclose(_rotvec_quat(phi), Rotation.from_rotvec(phi).as_quat(), rtol=0, atol=1e-15)
        q0 = Rotation.random(random_state=rng).as_quat()
        ref = (Rotation.from_quat(q0) * Rotation.from_rotvec(phi)).as_quat()
        got = quat_multiply(q0, _rotvec_quat(phi))
        assert np.allclose(got * np.sign(got @ ref), ref, rtol=0, atol=1e-15)


def test_manifest_lines_are_fsynced_off_the_critical_path_and_errors_surface(tmp_path, monkeypatch):
    """The Syncer writes whole lines at once (a reader sees them before any fsync), fsyncs them on
    its thread, and an fsync that fails (a full or failing disk) is raised by close, not lost."""
    synced: list[int] = []
    real = os.fsync

    def fsync(fd):
        synced.append(fd)
        real(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    s = storage.Syncer(tmp_path)
    s.append([{"case": 0, "status": "ok"}, {"case": 1, "status": "ok"}])
    s.append([])  # nothing to write: no fsync
    s.close()
    assert sorted(storage.read_rows(tmp_path)) == [0, 1] and len(synced) == 1

    def failing(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", failing)
    s = storage.Syncer(tmp_path)
    s.append([{"case": 2, "status": "ok"}])
    with pytest.raises(OSError, match="No space"):
        s.close()
    assert 2 in storage.read_rows(tmp_path)  # the line itself was written


def test_draw_columns_in_dispersion_then_index_order_whatever_the_key_order():
    disps = [{"key": "chaser.quaternion"}, {"key": "chaser.inertia"}, {"key": "thrusters.misalignment_deg"},
             {"key": "faults.0.unit"}, {"key": "faults.0.time"}]
    want = (["draw.chaser.quaternion.angle_deg"] + [f"draw.chaser.quaternion[{i}]" for i in range(4)]
            + [f"draw.chaser.inertia[{i}][{j}]" for i in range(3) for j in range(i, 3)]
            + [f"draw.thrusters.misalignment_deg[{i}]" for i in range(12)]
            + ["draw.faults.0.unit", "draw.faults.0.time"])
    for keys in (want, sorted(want), sorted(want, reverse=True)):  # as drawn, as a manifest line sorts them, ...
        assert storage.draw_columns(disps, [{"draws": dict.fromkeys(keys, 0.0)}]) == want
