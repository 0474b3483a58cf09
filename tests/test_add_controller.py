"""Adding a controller is adding one module: copy baseline.py under a new name, build, fly it.

The acceptance check of the edit loop, end to end on a copy of the checkout: `python build.py`
derives and compiles only the new controller's family (the plant and the other controllers are
reused from generated/ and the object cache), `rpo run --controller <new>` flies it, and git
sees no hand-written file changed besides the new module.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

from checkout_copy import TOPS, importing

ROOT = Path(__file__).resolve().parents[1]
RUN = "import sys; from rpo.runtime.cli.main import main; sys.exit(main(sys.argv[1:]))"


def _git(repo: Path, *args: str) -> str:
    return subprocess.run(["git", "-c", "user.email=t@example.com", "-c", "user.name=t", *args], cwd=repo,
                          capture_output=True, text=True, check=True).stdout


def _checkout(repo: Path) -> Path:
    for d in TOPS:
        shutil.copytree(ROOT / d, repo / d, ignore=shutil.ignore_patterns("__pycache__", ".lock"))
    shutil.copy(ROOT / "build.py", repo / "build.py")
    return repo


def _env(repo: Path) -> dict[str, str]:
    """An environment in which ``import rpo`` is the copy ``repo`` (tests/checkout_copy.py)."""
    return importing(repo)


def test_controller_module_without_design_is_one_line_exit_2(tmp_path):
    repo = _checkout(tmp_path / "checkout")
    (repo / "symbolic" / "controllers" / "half_done.py").write_text('"""Not finished yet."""\n')
    before = {p.name: p.read_bytes() for p in (repo / "generated").iterdir() if p.is_file() and p.name != ".lock"}
    res = subprocess.run([sys.executable, "build.py", "--no-compile"], cwd=repo, env=_env(repo),
                         capture_output=True, text=True)
    assert res.returncode == 2
    assert res.stderr.strip() == ("error: symbolic/controllers/half_done.py defines no DESIGN "
                                  "(the controller class to generate)")
    assert {p.name: p.read_bytes() for p in (repo / "generated").iterdir()
            if p.is_file() and p.name != ".lock"} == before


def test_copy_of_baseline_is_a_new_controller(tmp_path, model):
    model.prepare(model.functions)  # every existing object in the cache (a model compiles on first use only)
    repo = _checkout(tmp_path / "checkout")
    _git(repo, "init", "-q")
    _git(repo, "add", "-A")
    _git(repo, "commit", "-qm", "checkout")

    new = repo / "symbolic" / "controllers" / "my_pd.py"
    text = (ROOT / "symbolic" / "controllers" / "baseline.py").read_text()
    assert 'default=0.28)' in text
    new.write_text(text.replace('default=0.28)', 'default=0.3)'))  # one changed gain

    env = _env(repo)
    res = subprocess.run([sys.executable, "build.py"], cwd=repo, env=env, capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "re-derived controller_my_pd;" in res.stdout  # nothing else was derived
    # only the new controller's files are compiled (if not cached already); the rest come from the cache
    compiled = re.findall(r"\] (\S+\.c) \(", res.stdout)
    assert set(compiled) <= {"law_my_pd.c", "control_my_pd.c", "step_my_pd.c"}, res.stdout

    out = tmp_path / "run"
    res = subprocess.run([sys.executable, "-c", RUN, "run", "scenarios/000_scenario_III.toml", "--controller",
                          "my_pd", "--duration", "1", "--no-plots", "--out", str(out)], cwd=repo, env=env,
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "controller my_pd" in res.stdout + res.stderr and (out / "timeseries.parquet").is_file()

    changed = [ln[3:] for ln in _git(repo, "status", "--porcelain", "--untracked-files=all").splitlines()]
    hand_written = [f for f in changed if not f.startswith("generated/")]
    assert hand_written == ["symbolic/controllers/my_pd.py"], changed
    assert {"generated/law_my_pd.c", "generated/control_my_pd.c", "generated/step_my_pd.c",
            "generated/manifest.json"} <= set(changed)
