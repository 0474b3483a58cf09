"""`rpo view RUN_FOLDER`: the interactive, offline run page (runtime/outputs/page.py, runtime/cli/view.py).

The page's plotly figure is inspected (the 3D scene, the animated bodies and cursors, the slider,
the verdict's thresholds and settling times from metrics.json); the command's user errors are one
line; and, marked ``browser``, the page is loaded in headless Chromium: it must render (a
screenshot that is not blank, the 3D scene included) without a console error.  CI runs the
browser test (``pytest -m browser``) and fails it when Chromium is missing; locally it is skipped
then, with the reason.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.cli.main import main
from rpo.runtime.outputs import geometry as geo
from rpo.runtime.outputs.page import FRAMES, GENERATOR, page_figure, page_html, read_run_folder, write_page

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "001_scenario.toml"
#: thresholds the 001 run crosses in its first minute (att 80.9 deg at 10 s, 75.2 at 60 s; pos 249 -> 236 m)
THRESHOLDS = {"att_deg": 78.0, "pos_m": 245.0}


@pytest.fixture(scope="module")
def folder(model, tmp_path_factory):
    """A 001 run of 60 s (records once per second: 61 rows), no figures."""
    from rpo.runtime.jobs.runner import execute_run

    out = tmp_path_factory.mktemp("view") / "run"
    execute_run(SCENARIO, out, model, duration=60.0, plots=False, thresholds=THRESHOLDS)
    return out


def _by_name(fig, name: str):
    found = [tr for tr in fig.data if tr.name == name]
    assert len(found) == 1, (name, [tr.name for tr in fig.data])
    return found[0]


def test_the_page_figure(folder):
    rf = read_run_folder(folder)
    metrics = json.loads((folder / "metrics.json").read_text())
    fig = page_figure(rf)
    names = [tr.name for tr in fig.data]
    # the 3D scene: path, goal, target, keep-out sphere, both bodies' axes, the camera cone
    keep_out = geo.keep_out_radius(rf.params)
    assert keep_out == pytest.approx(2.1 + 1.5)
    for name in ("chaser path", "target centre", f"keep-out sphere {keep_out:.3g} m", "chaser", "camera cone",
                 "chaser x", "chaser y", "chaser z", "target x", "target y", "target z"):
        assert name in names
    assert _by_name(fig, "chaser path").type == "scatter3d" and _by_name(fig, "camera cone").type == "scatter3d"
    assert any(n.startswith("goal (r - ctrl_pos_err (target axes))") for n in names)
    # the time histories: the verdict's errors on log axes, their thresholds and settling times
    att = _by_name(fig, "attitude error (ctrl_att_err)")
    np.testing.assert_allclose(att.y, np.degrees(rf.columns["ctrl_att_err"]), rtol=1e-12)
    assert fig.layout[att.yaxis.replace("y", "yaxis")].type == "log"
    for q, unit in (("att", "deg"), ("pos", "m")):
        th = THRESHOLDS["att_deg" if q == "att" else "pos_m"]
        line = _by_name(fig, f"threshold {th:.4g} {unit}")
        assert list(line.y) == [th, th]
        t_set = metrics[f"{q}_settling_time_s"]
        assert t_set is not None and metrics["verdict"]["goals"][q]["time_s"] == t_set
        assert list(_by_name(fig, f"reached at {t_set:.4g} s").x) == [t_set, t_set]
    assert metrics["verdict"]["line"] in fig.layout.title.text.replace("<br>", " ")
    # the animation: a frame per sampled row (all 61 here), each moving the same traces, and a slider step each
    n = len(rf.t)
    assert len(fig.frames) == min(n, FRAMES) == 61
    moving = list(fig.frames[0].traces)
    assert all(list(f.traces) == moving for f in fig.frames)
    assert [fig.data[i].name for i in moving][:8] == ["chaser", "chaser x", "chaser y", "chaser z", "target x",
                                                     "target y", "target z", "camera cone"]
    steps = fig.layout.sliders[0].steps
    assert [s.args[0][0] for s in steps] == [f.name for f in fig.frames]
    last = fig.frames[-1]
    cursors = [tr for tr, i in zip(last.data, moving, strict=True) if fig.data[i].name.startswith("time cursor")]
    assert cursors and all(list(c.x) == [rf.t[-1]] * 2 for c in cursors)
    r_end = geo.series(rf.columns, "r")[-1]
    chaser = last.data[0]
    assert (chaser.x[0], chaser.y[0], chaser.z[0]) == (r_end[1], r_end[2], r_end[0])  # (V-bar, cross-track, R-bar)


def test_the_page_is_one_offline_file(folder, tmp_path):
    html = page_html(read_run_folder(folder), frames=10)
    assert GENERATOR in html and "<title>rpo view: 001 scenario</title>" in html
    assert not re.search(r"<script[^>]*\bsrc=", html), "the page loads a script from elsewhere"
    assert "Plotly.newPlot" in html and len(html) > 3_000_000  # plotly.js inlined (about 4.6 MB)
    assert "rpo view: ready" in html


def test_rpo_view_writes_the_page_and_replaces_only_its_own(folder, tmp_path, capsys):
    assert main(["view", str(folder)]) == 0
    page = folder / "view.html"
    assert capsys.readouterr().out.strip() == f"wrote {page}"
    first = page.stat().st_mtime_ns
    assert main(["view", str(folder)]) == 0 and page.stat().st_mtime_ns >= first  # its own page: replaced
    page.unlink()
    out = tmp_path / "sub" / "page.html"
    (tmp_path / "sub").mkdir()
    assert main(["view", str(folder), "--out", str(out)]) == 0 and out.read_text().count(GENERATOR) == 1


@pytest.mark.parametrize(("case", "message"), [
    ("missing", "no such folder"),
    ("file", "not a folder"),
    ("empty", "is not a run folder: it has no run.json"),
    ("csv", "rpo view reads the Parquet time histories"),
    ("foreign", "exists and is not an rpo view page: refusing to overwrite it"),
])
def test_rpo_view_user_errors_are_one_line(folder, tmp_path, capsys, case, message):
    args = {"missing": [str(tmp_path / "nope")], "file": [str(folder / "run.json")], "empty": [str(tmp_path)]}
    if case == "csv":
        bare = tmp_path / "bare"
        bare.mkdir()
        shutil.copy(folder / "run.json", bare / "run.json")
        args["csv"] = [str(bare)]
    if case == "foreign":
        mine = tmp_path / "notes.html"
        mine.write_text("<html>my notes</html>")
        args["foreign"] = [str(folder), "--out", str(mine)]
    assert main(["view", *args[case]]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and len(err.strip().splitlines()) == 1
    assert "Traceback" not in err
    if case == "foreign":
        assert (tmp_path / "notes.html").read_text() == "<html>my notes</html>"


# --------------------------------------------------------------------------- in a browser

#: wraps the page's console.error and reports uncaught errors and rejections, on the console (the
#: browser's log shows every console level the same way); put before everything else in a copy
HOOK = """<script>(function () {
  var error = console.error;
  console.error = function () { error.apply(console, ["rpo-test console.error:"].concat([].slice.call(arguments))); };
  window.addEventListener("error", function (e) { console.log("rpo-test uncaught: " + e.message); });
  window.addEventListener("unhandledrejection", function (e) { console.log("rpo-test rejection: " + e.reason); });
})();</script>"""


def _chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if found is None:
        reason = "headless Chromium is needed (Debian: apt-get install chromium; .ci/run installs it)"
        if os.environ.get("CI"):
            pytest.fail(f"{reason}: it must run in CI")
        pytest.skip(reason)
    return found


@pytest.mark.browser
def test_the_page_renders_in_a_headless_browser_without_console_errors(folder, tmp_path):
    chromium = _chromium()
    page = write_page(folder, tmp_path / "view.html")
    probe = tmp_path / "probe.html"
    probe.write_text(page.read_text(encoding="utf-8").replace("<head>", "<head>\n" + HOOK, 1), encoding="utf-8")
    shot = tmp_path / "shot.png"
    cmd = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
           "--enable-unsafe-swiftshader", "--hide-scrollbars", "--no-first-run", "--disable-extensions",
           f"--user-data-dir={tmp_path / 'profile'}", "--host-resolver-rules=MAP * ~NOTFOUND",  # offline
           "--enable-logging=stderr", "--v=0", "--window-size=1400,1000", "--virtual-time-budget=30000",
           f"--screenshot={shot}", probe.as_uri()]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    log = res.stderr
    console = [ln for ln in log.splitlines() if "CONSOLE" in ln]
    assert res.returncode == 0, log[-3000:]
    bad = [ln for ln in console if "rpo-test" in ln or "Uncaught" in ln or "Failed to load resource" in ln]
    assert not bad, "\n".join(bad)
    ready = [ln for ln in console if "rpo view: ready" in ln]
    assert ready and f"ready, {len(read_run_folder(folder).t)} frames" in ready[0], "\n".join(console)

    from matplotlib.image import imread

    img = imread(shot)[..., :3]
    assert img.shape[:2] == (1000, 1400)
    ink = np.any(img < 0.95, axis=2)  # not white
    assert ink.mean() > 0.01, f"the page is blank ({ink.mean():.4f} of the pixels drawn)"
    scene = ink[150:750, 50:650]  # the 3D scene (WebGL): its axes, grid and the bodies
    assert scene.mean() > 0.01, f"the 3D scene is blank ({scene.mean():.4f})"
