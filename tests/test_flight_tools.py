"""Every design exported and checked like flight code (``pytest -m flight``, its own step of .ci/run).

For each controller with a paper design (c000, c001, c002, c004) and the reference design (baseline), in
double and single precision: the package compiles warning-free under gcc and clang at the issue's flags,
its objects call no allocation or I/O function and hold no mutable data, every MISRA C:2012 finding is
justified by the shipped deviations file, the stack of a step is bounded on the host and the Cortex-M
targets; the double package reproduces its recorded run bit for bit under both compilers and its
whole-scenario flight on this machine equals the simulation's.  The tools are Debian packages that
.ci/run installs; under CI a missing one fails these tests (never skips them).
"""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from rpo.runtime.flight.checks import check_package
from rpo.runtime.flight.package import write_package
from rpo.runtime.flight.pil import fly_in_the_loop
from rpo.runtime.flight.stack import header_stack

pytestmark = pytest.mark.flight

DESIGNS = ("baseline", "c000", "c001", "c002", "c004")
TOOLS = ("gcc", "clang", "cppcheck", "arm-none-eabi-gcc", "qemu-system-arm", "make")


@pytest.fixture(scope="module", autouse=True)
def tools():
    missing = [t for t in TOOLS if shutil.which(t) is None]
    if missing:
        msg = f"missing {', '.join(missing)} (Debian: clang cppcheck gcc-arm-none-eabi qemu-system-arm make)"
        if os.environ.get("CI"):
            pytest.fail(msg)
        pytest.skip(msg)


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    root = tmp_path_factory.mktemp("flight")
    return {(name, prec): write_package(name, root / f"{name}_{prec}", precision=prec, steps=500,
                                        measure_stack=header_stack)
            for name in DESIGNS for prec in ("double", "single")}


@pytest.mark.parametrize("precision", ["double", "single"])
@pytest.mark.parametrize("name", DESIGNS)
def test_the_package_passes_the_flight_checks(exports, name, precision):
    e = exports[(name, precision)]
    r = check_package(e.folder, precision, e.folder / "misra_deviations.toml")
    j = r.json()
    assert r.passed, r.format_report()
    assert j["export_warnings"] == 0 and j["heap_symbols"] == 0 and j["misra_findings_unjustified"] == 0
    assert j["io_symbols"] == 0 and j["mutable_data_symbols"] == 0 and j["recursion_cycles"] == 0
    assert all(isinstance(b, int) and 0 < b < 16384 for b in j["stack_bytes_per_step"].values()), j
    assert "cortex-m7" in j["stack_bytes_per_step"]
    # the controller's own code needs no deviation: every justified finding is in rpo_math.h or a header
    assert j["justified_findings"], j  # the headers' interface macros (rule 2.5) at least: the list is read
    for f in j["justified_findings"]:
        assert f["file"].endswith(".h"), f
    header = (e.folder / f"rpo_{name}.h").read_text()
    assert f"#define RPO_{name.upper()}_STACK_BYTES {max(j['stack_bytes_per_step'].values())}" in header


@pytest.mark.parametrize("precision", ["double", "single"])
@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("name", DESIGNS)
def test_the_package_passes_its_vectors_under_both_compilers(exports, tmp_path, name, cc, precision):
    """Double: the recorded run bit for bit; single: within its tolerance, compiled with -Wconversion
    -Wdouble-promotion as well."""
    e = exports[(name, precision)]
    work = tmp_path / name
    shutil.copytree(e.folder, work)
    res = subprocess.run(["make", "-s", f"CC={cc}", "test"], cwd=work, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stdout + res.stderr
    if precision == "double":
        assert "bit for bit" in res.stdout
    else:
        assert "-Wconversion -Wdouble-promotion" in (work / "Makefile").read_text()


@pytest.mark.parametrize("name", DESIGNS)
def test_a_whole_scenario_flown_with_the_package_on_this_machine_is_the_simulations(exports, name):
    e = exports[(name, "double")]
    r = fly_in_the_loop(e.scenario, name, where="host", package=e.folder)
    assert r.passed and r.comparison["bit_identical"] and r.comparison["max_abs_diff"] == 0.0, r.text()
    assert r.steps == r.steps_reference > 0
