"""runtime/campaign/reporting.py on a synthetic campaign folder built here to the runner's format."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from scipy import stats as sps

from rpo.runtime.campaign import reporting as R
from rpo.runtime.campaign import storage

UNITS = {
    "draw.relative.position[0]": "m", "draw.relative.position[1]": "m", "draw.relative.position[2]": "m",
    "draw.chaser.mass": "kg", "t_end_s": "s", "att_settling_time_s": "s", "pos_settling_time_s": "s",
    "att_err_final_rad": "rad", "pos_err_final_m": "m", "propellant_kg": "kg", "beta_fov_min_m": "m",
}
DURATION = 120.0


def build_campaign(path: Path, requested: int, statuses: dict[int, str], seed: int = 0,
                   legacy: bool = False) -> dict:
    """Write resolved.json, summary.parquet and histories/ for the cases of ``statuses`` (case ->
    status; the cases not in it are "not done").  Returns the columns written (NumPy, NaN = null)."""
    rng = np.random.default_rng(seed)
    path.mkdir(parents=True, exist_ok=True)
    (path / "histories").mkdir()
    cases = np.array(sorted(statuses), dtype=np.int64)
    n = cases.size
    st = np.array([statuses[int(k)] for k in cases])
    flown = np.isin(st, ["ok", "diverged"])
    pos = rng.normal(0.0, 2.0, size=(n, 3))
    mass = rng.uniform(180.0, 220.0, size=n)
    unit = np.array(["wheel0", "wheel1", "wheel2"])[rng.integers(0, 3, size=n)]
    # metrics: the final position error grows with |x0| (a monotone relation the sensitivity must find),
    # the propellant with the mass; the rest is noise
    pos_err = 0.01 * np.abs(pos[:, 0]) + 1e-4 * rng.random(n)
    att_err = 1e-3 * rng.random(n)
    prop = 0.002 * mass + 0.01 * rng.random(n)
    att_set = rng.uniform(20.0, 60.0, size=n)
    pos_set = rng.uniform(30.0, 90.0, size=n)
    beta = rng.uniform(0.5, 2.0, size=n)
    t_end = np.full(n, DURATION)
    ok = st == "ok"
    div = st == "diverged"
    # two ok runs never settled in attitude (null settling time, goal not reached)
    never = np.flatnonzero(ok)[:2]
    att_set[never] = np.nan
    t_end[div] = 40.0 + 10.0 * np.arange(div.sum())
    for a in (pos_err, att_err, prop, att_set, pos_set, beta):
        a[~flown] = np.nan
    t_end[~flown] = np.nan
    att_reached = np.where(flown, True, None).astype(object)
    att_reached[never] = False
    att_reached[div] = False
    pos_reached = np.where(flown, True, None).astype(object)
    pos_reached[div] = False
    constraint = np.where(flown, False, None).astype(object)
    constraint[np.flatnonzero(ok)[5:6]] = True
    failed = np.where(flown, False, None).astype(object)
    for i in range(n):
        if flown[i]:
            failed[i] = bool(div[i] or constraint[i] or not att_reached[i] or not pos_reached[i])
    message = np.array(["" for _ in range(n)], dtype=object)
    message[st == "invalid"] = "chaser.mass below the dry mass"
    message[st == "error"] = "worker died"
    message[div] = "state x[3] above its bound"
    cols = {
        "case": pa.array(cases, pa.int64()),
        "seed": pa.array(rng.integers(0, 2**63, size=n).astype(np.uint64), pa.uint64()),
        "status": pa.array(st.tolist(), pa.string()),
        "message": pa.array(message.tolist(), pa.string()),
        "draw.relative.position[0]": pa.array(pos[:, 0]),
        "draw.relative.position[1]": pa.array(pos[:, 1]),
        "draw.relative.position[2]": pa.array(pos[:, 2]),
        "draw.chaser.mass": pa.array(mass),
        "draw.faults.0.unit": pa.array(unit.tolist(), pa.string()),
        "att_reached": pa.array(att_reached.tolist(), pa.bool_()),
        "pos_reached": pa.array(pos_reached.tolist(), pa.bool_()),
        "diverged": pa.array(np.where(flown, div, None).tolist(), pa.bool_()),
        "constraint_violated": pa.array(constraint.tolist(), pa.bool_()),
        "failed": pa.array(failed.tolist(), pa.bool_()),
    }
    for name, a in (("t_end_s", t_end), ("att_settling_time_s", att_set), ("pos_settling_time_s", pos_set),
                    ("att_err_final_rad", att_err), ("pos_err_final_m", pos_err), ("propellant_kg", prop),
                    ("beta_fov_min_m", beta)):
        cols[name] = pa.array(a, pa.float64(), mask=np.isnan(a))
    meta = {b"rpo.units": json.dumps(UNITS).encode(), b"rpo.campaign": json.dumps({"name": "synth", "runs": requested})}
    pq.write_table(pa.table(cols).replace_schema_metadata(meta), path / "summary.parquet")
    resolved = {"format": 1, "name": "synth", "runs": requested, "campaign_file": "synth.toml",
                "scenario": "scenarios/000_scenario_III.toml", "controller": "c000", "duration_s": DURATION,
                "dispersions": [{"key": "relative.position", "dist": "normal", "size": 3, "unit": "m",
                                 "columns": [f"draw.relative.position[{i}]" for i in range(3)]},
                                {"key": "chaser.mass", "dist": "uniform", "size": 1, "unit": "kg",
                                 "columns": ["draw.chaser.mass"]}],
                "command": "rpo mc run synth.toml", "ignored": {"x": 1}}
    (path / "resolved.json").write_text(json.dumps(resolved))
    # histories of the flown cases: the errors decay from a per-run start; a diverged run stops at t_end
    # (legacy=True: one file per case and no manifest, as rpo wrote them before batch files)
    t_full = np.arange(0.0, DURATION + 1.0)
    runs = []
    for i in np.flatnonzero(flown):
        t = t_full[t_full <= t_end[i]]
        e0 = 1.0 + rng.random()
        h = {"err_att_rad": 0.1 * e0 * np.exp(-t / 20.0), "err_pos_m": 5.0 * e0 * np.exp(-t / 30.0),
             "h_w_norm": 0.2 * e0 * (1 - np.exp(-t / 10.0)), "m_prop": np.linspace(0.0, prop[i], t.size),
             "r_x": np.zeros(t.size)}
        if legacy:
            table = {"t": pa.array(t), **{k: pa.array(v.astype(np.float32)) for k, v in h.items()}}
            pq.write_table(pa.table(table), storage.legacy_history_path(path, int(cases[i])))
        else:
            runs.append(storage.History(int(cases[i]), t, h, {"case": int(cases[i]), "status": str(st[i])}))
    # as the campaign writes them: a file per batch of (here) 16 flown runs, named in each run's line
    rows = [{"case": int(c), "seed": 0, "status": str(s)} for c, s in zip(cases, st, strict=True)]
    for b in range(0, len(runs), 16):
        name = storage.write_histories(path, runs[b:b + 16], {"err_pos_m": "m"})
        for r in rows:
            if r["case"] in {h.case for h in runs[b:b + 16]}:
                r["history"] = name
    if not legacy:
        storage.append_rows(path, rows)
    return {"case": cases, "status": st, "pos": pos, "mass": mass, "pos_err": pos_err, "att_err": att_err,
            "prop": prop, "att_set": att_set, "pos_set": pos_set, "t_end": t_end, "failed": failed,
            "constraint": constraint, "flown": flown, "ok": ok, "div": div}


#: 150 requested; cases 137 and 141-149 not done; 4 invalid, 1 error, 2 diverged: 135 flown.
STATUSES = {k: "ok" for k in range(141) if k != 137}
STATUSES.update({3: "invalid", 17: "invalid", 50: "invalid", 99: "invalid", 64: "error", 10: "diverged",
                 77: "diverged"})


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    path = tmp_path_factory.mktemp("campaign") / "synth"
    data = build_campaign(path, 150, STATUSES)
    report = R.write_report(path)  # into the folder itself
    return path, data, report, report.read_text()


def section(text: str, title: str) -> str:
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert m, f"no section {title!r}"
    return m.group(1)


def row(text: str, first: str) -> list[str]:
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cells[0] == first:
            return cells
    raise AssertionError(f"no table row starting with {first!r}")


def body_rows(text: str) -> list[list[str]]:
    """The cells of the body rows of the first markdown table in ``text`` (header and rule skipped)."""
    lines = [ln for ln in text.splitlines() if ln.startswith("|")]
    return [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in lines[2:]]


def f4(v: float) -> str:
    return f"{v:.4g}"


def pct(v: float) -> str:
    return f"{100 * v:.2f} %"


def test_report_sections_and_header(campaign):
    path, data, report, text = campaign
    assert report == path / "report.md"
    assert text.startswith("# Monte Carlo campaign: synth\n")
    for title in ("Status", "Failure rates", "Tolerance bounds (Wilks)", "Metrics", "Which dispersion matters",
                  "Worst cases", "Figures"):
        section(text, title)
    assert "- runs requested: 150; done: 140; flown: 135 (ok 133, diverged 2); invalid draws: 4; errors: 1" in text
    assert "**Incomplete campaign: 10 of the 150 requested cases have no result (cases 137, 141-149)" in text
    assert "- command: `rpo mc run synth.toml`" in text


def test_status_and_failure_rates_match_independent_counts(campaign):
    _, data, _, text = campaign
    s = section(text, "Status")
    assert row(s, "ok")[1:] == ["133", pct(133 / 140)]
    assert row(s, "invalid")[1] == "4" and row(s, "error")[1] == "1" and row(s, "diverged")[1] == "2"
    errors = s.split("Messages of the error cases:")[1]
    assert row(errors, "1")[1] == "worker died"
    assert row(s.split("Messages of the invalid cases:")[1], "4")[1] == "chaser.mass below the dry mass"

    f = section(text, "Failure rates")
    flown = data["flown"]
    k_failed = int(sum(bool(x) for x in data["failed"][flown]))
    assert k_failed == 2 + 2 + 1  # diverged, never settled (goal not reached), constraint violated
    cells = row(f, "failed")
    ci = sps.binomtest(k_failed, 135).proportion_ci(0.95, method="exact")
    up = sps.binomtest(k_failed, 135, alternative="less").proportion_ci(0.95, method="exact")
    assert cells[1:] == [str(k_failed), "135", pct(k_failed / 135), f"[{pct(ci.low)}, {pct(ci.high)}]",
                         pct(up.high)]
    # not settled: the 2 ok runs with a null settling time (the diverged ones have one in this data)
    assert row(f, "attitude not settled")[1:3] == ["2", "135"]
    assert row(f, "position not settled")[1:3] == ["0", "135"]
    assert row(f, "position not settled")[5] == pct(1 - 0.05 ** (1 / 135))  # k = 0 closed form
    assert row(f, "diverged")[1:3] == ["2", "135"]
    assert row(f, "constraint violated")[1:3] == ["1", "135"]
    assert row(f, "invalid draw (of done cases)")[1:3] == ["4", "140"]
    assert row(f, "worker error (of done cases)")[1:3] == ["1", "140"]


def test_wilks_section_matches_order_statistics(campaign):
    _, data, _, text = campaign
    w = section(text, "Tolerance bounds (Wilks)")
    assert "needs 59 flown runs" in w and "a two-sided interval needs 93" in w and "135 flown runs: enough." in w
    # n = 135 admits order 3 (124 <= 135 < 153): the 3rd largest, diverged runs counting as +inf
    flown = data["flown"]
    v = data["pos_err"][flown].copy()
    v[data["div"][flown]] = np.inf
    cells = row(w, "pos_err_final_m")
    assert cells[3:6] == ["135", "3 (largest)", f4(np.sort(v)[-3])]
    assert cells[6] == f"{100 * sps.binom.sf(2, 135, 0.05):.2f} %"
    # attitude settling: 2 never settled + 2 diverged = 4 infinite values > order 3 -> inf
    assert row(w, "att_settling_time_s")[5] == "inf"
    # a bound from below for the margin: the 3rd smallest, diverged as -inf -> the smallest of the ok runs
    lo_cells = row(w, "beta_fov_min_m")
    assert lo_cells[2] == "lower" and lo_cells[4] == "3 (smallest)"
    beta = R.summary_table(campaign[0])["beta_fov_min_m"]
    assert lo_cells[5] == f4(np.nanmin(beta[data["ok"]]))


def test_metric_table_matches_numpy(campaign):
    path, data, _, text = campaign
    m = section(text, "Metrics")
    ok = data["ok"]
    for col, key in (("pos_err_final_m", "pos_err"), ("propellant_kg", "prop"), ("att_settling_time_s", "att_set")):
        v = data[key][ok]
        v = v[~np.isnan(v)]
        cells = row(m, col)
        assert cells[1] == R.read_folder(path).unit(col)
        assert cells[2] == str(v.size)
        assert cells[3].startswith(f4(v.mean()) + " [")
        lo, hi = sps.t.interval(0.95, v.size - 1, loc=v.mean(), scale=sps.sem(v))
        assert cells[3] == f"{f4(v.mean())} [{f4(lo)}, {f4(hi)}]"
        for cell, q in zip(cells[4:7], (5, 50, 95), strict=True):
            assert cell.startswith(f4(np.percentile(v, q)) + " [")
        assert cells[7:9] == [f4(v.min()), f4(v.max())]
    assert row(m, "att_settling_time_s")[2] == "131"  # 133 ok minus 2 never settled


def test_angles_are_shown_in_degrees_throughout_the_report(campaign):
    """The summary holds SI (att_err_final_rad); the report shows angles in deg, renamed so its name
    says so, and no table shows rad beside deg."""
    _, data, _, text = campaign
    assert "Units: SI as in `summary.parquet`, except angles in deg" in text
    m = section(text, "Metrics")
    v = np.degrees(data["att_err"][data["ok"]])
    cells = row(m, "att_err_final_deg")
    assert cells[1] == "deg" and cells[3] == f"{f4(v.mean())} [" + cells[3].split(" [")[1]
    assert cells[7:9] == [f4(v.min()), f4(v.max())]
    assert row(section(text, "Tolerance bounds (Wilks)"), "att_err_final_deg")[1] == "deg"
    units = [r[1] for line in text.split("\n## ")[1:] for r in body_rows(line) if len(r) > 1]
    assert "rad" not in units and "rad/s" not in units
    assert "| att_err_final_rad |" not in text


def test_sensitivity_finds_the_monotone_relations(campaign):
    _, data, _, text = campaign
    s = section(text, "Which dispersion matters")
    ok = data["ok"]
    rho = sps.spearmanr(data["pos"][ok, 0], data["pos_err"][ok]).statistic
    # |x0| drives pos_err, so rho vs x0 is weak; the mass drives the propellant: strong and first
    cells = body_rows(s)[0]
    ref = sps.spearmanr(data["mass"][ok], data["prop"][ok])
    assert cells[:3] == ["propellant_kg", "chaser.mass", f"{ref.statistic:+.3f}"]
    assert cells[3].endswith("*")
    assert abs(rho) < 0.5
    assert "`draw.faults.0.unit`" in s  # the string draw is named as skipped


def test_worst_cases_and_commands(campaign):
    path, data, _, text = campaign
    w = section(text, "Worst cases")
    cdir = path.resolve()
    assert "### Diverged (2)" in w
    errors = w.split("### Worker errors (1)")[1]
    assert row(errors, "64")[1:] == ["worker died", f"`rpo run --campaign {cdir} --case 64`"]
    assert f"`rpo run --campaign {cdir} --case 10`" in w and f"`rpo run --campaign {cdir} --case 77`" in w
    # largest final position error among ok runs: first row of its table
    ok = np.flatnonzero(data["ok"])
    worst = ok[np.argsort(-data["pos_err"][ok])][:5]
    block = w.split("### Largest final position error")[1].split("###")[0]
    cases = [r[0] for r in body_rows(block)]
    assert cases == [str(int(data["case"][i])) for i in worst]
    # the never-settled runs lead the attitude settling list
    block = w.split("### Longest attitude settling time")[1].split("###")[0]
    rows = body_rows(block)
    assert [r[1] for r in rows[:3]] == ["not settled", "not settled", f4(np.nanmax(data["att_set"][data["ok"]]))]
    assert rows[0][2] == f"`rpo run --campaign {cdir} --case {rows[0][0]}`"


def test_figures_written_and_linked(campaign):
    path, _, _, text = campaign
    fig = section(text, "Figures")
    for name in ("envelopes.png", "cdf.png", "scatter_pos_err_final_m.png", "scatter_propellant_kg.png",
                 "scatter_att_settling_time_s.png"):
        assert f"(figures/{name})" in fig
        data = (path / "figures" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
        assert b"Software" not in data[:4096] and b"Creation Time" not in data


def test_two_writes_give_identical_bytes(campaign, tmp_path):
    path, _, _, text = campaign
    again = R.write_report(path, out=tmp_path / "again")
    assert again.read_text() == text
    for f in sorted((path / "figures").iterdir()):
        assert (tmp_path / "again" / "figures" / f.name).read_bytes() == f.read_bytes(), f.name


def test_summary_table_and_case_history(campaign):
    path, data, _, _ = campaign
    cols = R.summary_table(path)
    assert cols["case"].dtype == np.int64 and cols["seed"].dtype == np.uint64
    np.testing.assert_array_equal(cols["case"], data["case"])
    assert cols["status"].dtype.kind == "U"
    assert cols["failed"].dtype == np.float64
    assert np.isnan(cols["failed"][data["status"] == "invalid"]).all()
    np.testing.assert_array_equal(cols["pos_err_final_m"], data["pos_err"])
    h = R.case_history(path, 10, columns=["t", "err_pos_m", "absent"])  # diverged: ends early
    assert set(h) == {"t", "err_pos_m"} and h["t"][-1] == data["t_end"][data["case"] == 10][0]
    full = R.case_history(path, 0)
    assert full["t"].size == int(DURATION) + 1 and full["err_att_rad"].dtype == np.float32
    with pytest.raises(FileNotFoundError, match="case 3 has no history"):
        R.case_history(path, 3)  # invalid: never flown


def test_batch_files_read_as_the_per_case_files_of_older_folders(campaign, tmp_path):
    """The same synthetic campaign written with one history file per batch (named in the manifest)
    and with one file per case (older folders, no manifest): every case's history and the whole
    report are the same."""
    path, data, _, text = campaign
    old = tmp_path / "legacy"
    build_campaign(old, 150, STATUSES, legacy=True)
    assert not (old / storage.MANIFEST).exists() and not list((old / "histories").glob(storage.HISTORY_GLOB))
    assert len(list((path / "histories").glob(storage.HISTORY_GLOB))) == math.ceil(data["flown"].sum() / 16)
    for case in data["case"][data["flown"]]:
        a, b = R.case_history(path, int(case)), R.case_history(old, int(case))
        assert list(a) == list(b) == ["t", "err_att_rad", "err_pos_m", "h_w_norm", "m_prop", "r_x"]
        for k in a:
            assert a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k]), (case, k)
    again = R.write_report(old, out=tmp_path / "legacy_report").read_text()
    assert again.replace(str(old), str(path)) == text  # the folder's path is in the report's heading


def test_small_complete_campaign_not_enough_runs(tmp_path):
    statuses = {k: "ok" for k in range(30)}
    statuses[4] = "diverged"
    build_campaign(tmp_path / "small", 30, statuses, seed=3)
    text = R.write_report(tmp_path / "small", figures=False).read_text()
    assert "Incomplete" not in text and "## Figures" not in text
    w = section(text, "Tolerance bounds (Wilks)")
    assert "30 flown runs: **not enough** (29 more needed)." in w
    assert row(w, "pos_err_final_m")[4:6] == ["-", "needs 59 runs"]
    # other coverage/confidence: 90/90 first order needs 22 runs
    text = R.write_report(tmp_path / "small", out=tmp_path / "r9090", coverage=0.9, confidence=0.9,
                          figures=False).read_text()
    assert f"needs {math.ceil(math.log(0.1) / math.log(0.9))} flown runs" in text
    assert "30 flown runs: enough." in text


def test_missing_summary_is_a_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="summary.parquet does not exist"):
        R.write_report(tmp_path)


def test_degenerate_folders(tmp_path):
    # nothing flown: every draw refused
    build_campaign(tmp_path / "inv", 5, {k: "invalid" for k in range(5)})
    text = R.write_report(tmp_path / "inv").read_text()
    assert row(section(text, "Failure rates"), "invalid draw (of done cases)")[1:4] == ["5", "5", "100.00 %"]
    assert "No main metric has a value." in text and "No flown case to list." in text
    assert "No figure (no data to draw)." in text
    # figures of an earlier write that no longer apply are removed; other files are left alone
    (tmp_path / "inv" / "figures" / "cdf.png").write_bytes(b"stale")
    (tmp_path / "inv" / "figures" / "mine.png").write_bytes(b"user")
    R.write_report(tmp_path / "inv")
    assert sorted(f.name for f in (tmp_path / "inv" / "figures").iterdir()) == ["mine.png"]
    # an empty summary (the runner wrote the file before any case finished)
    (tmp_path / "empty").mkdir()
    pq.write_table(pa.table({"case": pa.array([], pa.int64()), "seed": pa.array([], pa.uint64()),
                             "status": pa.array([], pa.string()), "message": pa.array([], pa.string())}),
                   tmp_path / "empty" / "summary.parquet")
    text = R.write_report(tmp_path / "empty").read_text()
    assert "done: 0" in text and "No case done." in text
    with pytest.raises(ValueError, match="figure format"):
        R.write_report(tmp_path / "empty", fmt="jpg")


def test_imports_stay_light():
    # the runtime never imports sympy; pandas is not a dependency; matplotlib only when drawing
    code = ("import sys; import rpo.runtime.campaign.reporting, rpo.runtime.campaign.stats, "
            "rpo.runtime.campaign.figures; "
            "print(sorted(m for m in ('sympy', 'pandas', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
