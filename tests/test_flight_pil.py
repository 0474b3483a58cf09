"""Processor in the loop (``pytest -m flight``): one scenario per controller flown with its exported
package on the emulated Cortex-M7 (double precision, QEMU mps2-an500) against rpo's plant, equal to the
simulation's run bit for bit; and the single-precision package on the Cortex-M4F (mps2-an386) within
its bound and reaching what the double-precision loop reaches.

The scenarios are the controllers' shipped ones, whole, except c001's 5000 s (500 000 steps, about
7 minutes at QEMU's 0.8 ms round trip): its first 300 s (30 000 steps, the whole transient) here;
``python benchmarks/bench_export.py --full`` flies all of it.
"""

from __future__ import annotations

import os
import shutil

import pytest

from rpo.runtime.flight.pil import SINGLE_RUN_BOUND, fly_in_the_loop

pytestmark = pytest.mark.flight

#: controller -> (scenario, duration [s] or None for the whole scenario)
PIL_RUNS = {"baseline": ("ref_scenario", None), "c000": ("000_scenario_I", None), "c001": ("001_scenario", 300.0),
            "c002": ("002_scenario_kappa3", None), "c004": ("004_scenario", None)}


@pytest.fixture(scope="module", autouse=True)
def tools():
    missing = [t for t in ("arm-none-eabi-gcc", "qemu-system-arm") if shutil.which(t) is None]
    if missing:
        msg = f"missing {', '.join(missing)} (Debian: gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)"
        if os.environ.get("CI"):
            pytest.fail(msg)
        pytest.skip(msg)


@pytest.mark.parametrize("name", sorted(PIL_RUNS))
def test_the_run_on_the_cortex_m7_is_the_simulations_bit_for_bit(name):
    scenario, duration = PIL_RUNS[name]
    r = fly_in_the_loop(scenario, name, where="qemu", duration=duration)
    j = r.json()
    assert r.passed, r.text()
    assert j["pil_max_abs_diff"] == 0.0 and j["bit_identical"] and j["core"] == "m7"
    assert r.steps == r.steps_reference >= 3000
    assert 100 < j["instructions_per_step_median"] <= j["instructions_per_step_max"] < 10**6
    assert 0 < j["stack_bytes_measured_max"] < 16384


@pytest.mark.parametrize("name", ["baseline", "c002"])
def test_the_single_precision_run_on_the_cortex_m4f_stays_within_its_bound(name):
    scenario, duration = PIL_RUNS[name]
    r = fly_in_the_loop(scenario, name, precision="single", where="qemu", duration=duration)
    j = r.json()
    assert r.passed, r.text()
    assert j["core"] == "m4f" and 0 <= j["pil_single_rel_err"] <= SINGLE_RUN_BOUND
    assert j["verdict"] == j["verdict_simulation"]


def test_a_changed_law_on_the_target_is_seen(tmp_path):
    """The comparison can fail: the same package with one gain scaled by 1.01 in its C differs."""
    from rpo.runtime.flight.package import write_package

    folder = tmp_path / "c004"
    write_package("c004", folder, steps=10)
    src = folder / "rpo_c004.c"
    text = src.read_text()
    needle = " = params->gains.k"
    i = text.index(needle)
    j = text.index(";", i)
    src.write_text(text[:i] + " = 1.01 * " + text[i + 3:j] + text[j:])
    r = fly_in_the_loop("004_scenario", "c004", where="qemu", duration=5.0, package=folder)
    assert not r.passed and not r.comparison["bit_identical"] and r.comparison["max_abs_diff"] > 0


def test_rpo_pil_prints_its_figures_as_one_json_line():
    import json
    import subprocess
    import sys

    res = subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", "pil", "002_scenario_kappa3", "--controller",
                          "c002", "--duration", "2", "--json"], capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    j = json.loads(res.stdout.strip().splitlines()[-1])
    assert j["passed"] and j["steps"] == 400 and j["pil_max_abs_diff"] == 0.0 and j["on"] == "qemu"
    bad = subprocess.run([sys.executable, "-m", "rpo.runtime.cli.main", "pil", "002_scenario_kappa3", "--controller",
                          "c002", "--duration", "-1"], capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2 and "--duration must be > 0 s" in bad.stderr and "Traceback" not in bad.stderr
