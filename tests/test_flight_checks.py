"""The flight-code checks (rpo.runtime.flight) on the hand-made toy packages tests/flight_toy/ (double) and
tests/flight_toy_single/ (float): the clean toys pass, every check is shown to fail on a toy with the
defect it looks for, and a missing tool is an error naming its Debian package.

The tools are gcc, clang, binutils, gcc-arm-none-eabi and cppcheck (Debian packages); without one the
tests skip, except under CI (CI set in the environment), where they fail.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from rpo.runtime.errors import ModelError
from rpo.runtime.flight import checks, cppcheck, tools
from rpo.runtime.flight.callgraph import CallGraph, Frame, cycles, stack_bound

pytestmark = pytest.mark.flight

HERE = Path(__file__).resolve().parent
TOY = HERE / "flight_toy"
TOY_SINGLE = HERE / "flight_toy_single"
DEVIATIONS = TOY / "misra_deviations.toml"
DEVIATIONS_SINGLE = TOY_SINGLE / "misra_deviations.toml"
PROGRAMS = ("gcc", "clang", "nm", "arm-none-eabi-gcc", "arm-none-eabi-nm", "cppcheck")


@pytest.fixture(autouse=True, scope="module")
def _tools() -> None:
    missing = [p for p in PROGRAMS if shutil.which(p) is None]
    if missing:
        reason = f"the flight checks need {', '.join(missing)} (Debian: " + \
            ", ".join(sorted({tools.DEBIAN_PACKAGES[p] for p in missing})) + ")"
        if os.environ.get("CI"):
            pytest.fail(f"{reason}: they must run in CI")
        pytest.skip(reason)


def toy(tmp_path: Path, src: Path = TOY, **files: str) -> Path:
    """A copy of a toy package with files added or replaced (keyword: file name with . as __)."""
    pkg = tmp_path / "pkg"
    shutil.copytree(src, pkg)
    for name, text in files.items():
        (pkg / name.replace("__", ".")).write_text(text)
    return pkg


def package(tmp_path: Path, **files: str) -> Path:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    for name, text in files.items():
        (pkg / name.replace("__", ".")).write_text(text)
    return pkg


@pytest.fixture(scope="module")
def clean() -> checks.PackageCheck:
    return checks.check_package(TOY, "double", DEVIATIONS)


# ---------------------------------------------------------------------------------------------- clean toys


def test_the_clean_toy_passes_every_check(clean):
    j = clean.json()
    assert clean.passed, clean.format_report()
    assert j["export_warnings"] == 0 and j["warnings_by_compiler"] == {"gcc": 0, "clang": 0}
    assert j["heap_symbols"] == 0 and j["io_symbols"] == 0 and j["mutable_data_symbols"] == 0
    assert j["misra_findings_unjustified"] == 0 and j["misra_findings_total"] == j["misra_findings_justified"] > 0
    assert j["misra_by_rule"] == {"8.9": 6, "19.2": 2}
    assert j["recursion_cycles"] == 0 and j["vla"] == 0 and j["findings"] == []
    assert set(j["stack_bytes_per_step"]) == {"host-gcc", "cortex-m7"}
    assert all(isinstance(b, int) and 0 < b < 1024 for b in j["stack_bytes_per_step"].values())
    assert {"sqrt", "atan2"} <= set(j["stack_not_counted"]["host-gcc"])
    assert set(j["library_symbols"]["host-gcc"]) == {"atan2", "fmax", "fmin", "sqrt"}
    assert "PASSED" in clean.format_report() and "8 justified, 0 unjustified" in clean.format_report()


def test_the_toy_is_a_working_package(tmp_path):
    """The toy's host test program agrees with its test vectors (the toy is a real package, not a stub)."""
    exe = tmp_path / "test_rpo_toy"
    srcs = [str(TOY / n) for n in ("test_rpo_toy.c", *tools.flight_sources(TOY))]
    subprocess.run(["gcc", *tools.warning_flags("double"), "-o", str(exe), *srcs, "-lm"], check=True)
    out = subprocess.run([str(exe), str(TOY / "rpo_toy_vectors.txt")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "12 vectors, 0 mismatches"


def test_the_single_precision_toy_passes_on_the_m4():
    r = checks.check_package(TOY_SINGLE, "single", DEVIATIONS_SINGLE)
    assert r.passed, r.format_report()
    assert set(r.json()["stack_bytes_per_step"]) == {"host-gcc", "cortex-m7", "cortex-m4"}
    assert "-Wdouble-promotion" in r.warnings.flags and "-Wconversion" in r.warnings.flags
    assert r.symbols["cortex-m4"].library == ["atan2f", "fmaxf", "fminf", "sqrtf"]


# ------------------------------------------------------------------------------------------------ warnings

UNUSED = """#include "rpo_toy_io.h"
int rpo_toy_unused(int x);
int rpo_toy_unused(int x) { int y; return x; }
"""


def test_a_warning_fails_with_each_compiler(tmp_path):
    r = checks.compile_warnings(toy(tmp_path, rpo_toy_extra__c=UNUSED))
    assert r.counts == {"gcc": 1, "clang": 1}
    assert {(f.file, f.line, f.rule) for f in r.findings} == {("rpo_toy_extra.c", 3, "-Wunused-variable")}


def test_the_host_test_program_is_compiled_too(tmp_path):
    text = (TOY / "test_rpo_toy.c").read_text().replace("    int lines = 0;\n", "    int lines = 0;\n    int spare;\n")
    r = checks.compile_warnings(toy(tmp_path, test_rpo_toy__c=text), compilers=("gcc",))
    assert r.total == 1 and r.findings[0].file == "test_rpo_toy.c"


def test_single_precision_warns_on_a_promotion_to_double(tmp_path):
    text = (TOY_SINGLE / "rpo_toy.c").read_text().replace("sqrtf(", "sqrt(")
    pkg = toy(tmp_path, TOY_SINGLE, rpo_toy__c=text)
    r = checks.compile_warnings(pkg, precision="single")
    assert r.counts["gcc"] >= 1 and r.counts["clang"] >= 1
    assert {"-Wdouble-promotion", "-Wfloat-conversion"} & {f.rule for f in r.findings}
    assert checks.compile_warnings(pkg, precision="double").total == 0   # not flagged without them
    m4 = checks.forbidden_symbols(pkg, "cortex-m4", "single")
    assert {f.message.split(":")[0] for f in m4.findings if f.rule == "double"} >= {"sqrt"}


def test_the_double_toy_is_not_a_single_precision_package():
    m4 = checks.forbidden_symbols(TOY, "cortex-m4", "single")
    names = {f.message.split(":")[0] for f in m4.findings if f.rule == "double"}
    assert {"sqrt", "atan2", "__aeabi_dmul"} <= names


# ------------------------------------------------------------------------------------------------- symbols

MALLOC = """#include <stdlib.h>
double *rpo_toy_buffer(unsigned n);
double *rpo_toy_buffer(unsigned n) { return (double *)malloc(n * sizeof(double)); }
"""
PRINTF = """#include <stdio.h>
void rpo_toy_log(double x);
void rpo_toy_log(double x) { printf("%f\\n", x); }
"""
GLOBAL = """double rpo_toy_last;
double rpo_toy_remember(double x);
double rpo_toy_remember(double x) { static int calls; calls++; rpo_toy_last = x; return x + calls; }
"""
EXIT = """#include <stdlib.h>
void rpo_toy_fail(int bad);
void rpo_toy_fail(int bad) { if (bad) { abort(); } }
"""


@pytest.mark.parametrize("target", ["host-gcc", "cortex-m7"])
def test_a_malloc_is_a_heap_symbol(tmp_path, target):
    r = checks.forbidden_symbols(toy(tmp_path, rpo_toy_extra__c=MALLOC), target)
    assert r.heap_symbols == 1 and [f.file for f in r.findings] == ["rpo_toy_extra.c"]


@pytest.mark.parametrize("target", ["host-gcc", "cortex-m7"])
def test_a_printf_an_abort_and_a_mutable_global_are_found(tmp_path, target):
    pkg = toy(tmp_path, rpo_toy_log__c=PRINTF, rpo_toy_fail__c=EXIT, rpo_toy_mem__c=GLOBAL)
    r = checks.forbidden_symbols(pkg, target)
    got = {(f.rule, f.message.split(":")[0]) for f in r.findings}
    assert ("io", "printf") in got and ("termination", "abort") in got
    assert ("mutable-data", "rpo_toy_last") in got
    assert any(rule == "mutable-data" and name.startswith("calls") for rule, name in got)   # a static local
    assert r.heap_symbols == 0


def test_check_package_counts_the_forbidden_symbols(tmp_path):
    pkg = toy(tmp_path, rpo_toy_extra__c=MALLOC, rpo_toy_log__c=PRINTF, rpo_toy_mem__c=GLOBAL)
    r = checks.check_package(pkg, deviations=DEVIATIONS)
    j = r.json()
    assert not r.passed
    assert j["heap_symbols"] == 1 and j["io_symbols"] == 1 and j["mutable_data_symbols"] == 2
    assert j["export_warnings"] == 0
    # MISRA says it too: 21.3 (malloc), 21.6 (stdio); 8.4, 10.4, 17.7 for the sloppy toy code
    assert {f.rule for f in r.misra.findings if not f.justified} == {"21.3", "21.6", "17.7", "8.4", "10.4"}
    assert "heap 1, I/O 1" in r.format_report()


# ------------------------------------------------------------------------------------ stack and recursion

CHAIN_H = """#ifndef RPO_CHAIN_H
#define RPO_CHAIN_H
void rpo_chain_step(double *x);
double rpo_chain_b(double x);
double rpo_chain_c(double x);
double rpo_chain_d(double x);
#endif
"""


def _frame(name: str, n: int, call: str) -> str:
    return (f'#include <math.h>\n#include "rpo_chain.h"\ndouble {name}(double x)\n{{\n'
            f"    volatile double buf[{n}];\n    int i;\n    for (i = 0; i < {n}; i++) {{ buf[i] = x * i; }}\n"
            f"    return {call}(buf[{n} - 1]) + buf[1];\n}}\n")


CHAIN = {
    "rpo_chain__h": CHAIN_H,
    "rpo_chain__c": '#include "rpo_chain.h"\nvoid rpo_chain_step(double *x)\n{\n    volatile double buf[8];\n'
                    "    buf[0] = x[0];\n    x[1] = rpo_chain_b(buf[0]) + rpo_chain_c(x[2]) + buf[0];\n}\n",
    "rpo_chain_b__c": _frame("rpo_chain_b", 48, "rpo_chain_d"),
    "rpo_chain_c__c": _frame("rpo_chain_c", 64, "sqrt"),
    "rpo_chain_d__c": _frame("rpo_chain_d", 32, "fabs"),
}


def _su(tmp_path: Path, pkg: Path, tgt: tools.Target) -> dict[str, int]:
    """Each function's frame from gcc's .su files, compiled here (independently of the check)."""
    out = tmp_path / f"su-{tgt.name}"
    out.mkdir()
    for src in sorted(pkg.glob("*.c")):
        subprocess.run([tgt.cc, *tgt.flags, "-fstack-usage", "-c", str(src), "-o", str(out / (src.stem + ".o"))],
                       check=True)
    frames = {}
    for su in out.glob("*.su"):
        for line in su.read_text().splitlines():
            where, size, kind = line.split("\t")
            assert kind == "static"
            frames[where.rsplit(":", 1)[1]] = int(size)
    return frames


@pytest.mark.parametrize("target", ["host-gcc", "cortex-m7", "cortex-m4"])
def test_the_stack_is_the_worst_path_of_a_known_chain(tmp_path, target):
    pkg = package(tmp_path, **CHAIN)
    f = _su(tmp_path, pkg, tools.TARGETS[target])
    r = checks.stack_usage(pkg, "rpo_chain_step", target)
    b_d, c = f["rpo_chain_b"] + f["rpo_chain_d"], f["rpo_chain_c"]
    assert b_d > c   # the deeper path is the worse one
    assert r.bytes == f["rpo_chain_step"] + b_d and r.findings == []
    assert r.path == ["rpo_chain_step", "rpo_chain_b", "rpo_chain_d"]
    library = [n for n in r.not_counted if not n.startswith("__aeabi_")]   # the M4's software doubles
    assert library in (["sqrt"], ["fabs", "sqrt"])   # fabs is an instruction on most targets


INDIRECT = """double rpo_ind_step(double (*f)(double), double x);
double rpo_ind_step(double (*f)(double), double x) { return f(x) + 1.0; }
"""
VLA = """void rpo_vla_step(int n, double *out);
void rpo_vla_step(int n, double *out)
{
    double v[n];
    int i;
    for (i = 0; i < n; i++) { v[i] = out[i]; }
    out[0] = v[n - 1];
}
"""
RECURSIVE = """double rpo_rec_step(int n);
double rpo_rec_odd(int n);
static double rpo_rec_fib(int n) { return (n < 2) ? 1.0 : (rpo_rec_fib(n - 1) + rpo_rec_fib(n - 2)); }
static double rpo_rec_even(int n) { return (n == 0) ? 1.0 : rpo_rec_odd(n - 1); }
double rpo_rec_odd(int n) { return (n == 0) ? 0.0 : rpo_rec_even(n - 1); }
double rpo_rec_step(int n) { return rpo_rec_fib(n) + rpo_rec_odd(n); }
"""


def test_an_indirect_call_leaves_the_stack_unknown(tmp_path):
    r = checks.stack_usage(package(tmp_path, rpo_ind__c=INDIRECT), "rpo_ind_step")
    assert r.bytes is None and [f.rule for f in r.findings] == ["indirect"]


@pytest.mark.parametrize("target", ["host-gcc", "cortex-m7"])
def test_a_vla_is_a_warning_and_a_dynamic_frame(tmp_path, target):
    pkg = package(tmp_path, rpo_vla__c=VLA)
    w = checks.compile_warnings(pkg)
    assert w.vla == 2 and w.counts == {"gcc": 1, "clang": 1}
    s = checks.stack_usage(pkg, "rpo_vla_step", target)
    assert s.bytes is None and [f.rule for f in s.findings] == ["dynamic"]


def test_recursion_is_found_and_leaves_the_stack_unknown(tmp_path):
    pkg = package(tmp_path, rpo_rec__c=RECURSIVE)
    r = checks.recursion(pkg)
    assert r.cycles == [["rpo_rec.c:rpo_rec_even", "rpo_rec_odd"], ["rpo_rec.c:rpo_rec_fib"]]
    assert [f.rule for f in r.findings] == ["17.2", "17.2"]
    s = checks.stack_usage(pkg, "rpo_rec_step")
    assert s.bytes is None and "recursion" in {f.rule for f in s.findings}


def test_the_bound_and_the_cycles_on_a_graph_by_hand():
    g = CallGraph({t: Frame(t, n, "static", "x.c", 1) for t, n in [("e", 10), ("a", 5), ("b", 7), ("c", 1)]},
                  {"e": ["a", "b", "sin"], "a": ["c"], "b": ["cos"], "c": []})
    r = stack_bound(g, "e")
    assert (r.bytes, r.path, r.not_counted) == (17, ["e", "b"], ["cos", "sin"])
    g.calls["c"] = ["a"]
    assert cycles(g) == [["a", "c"]]
    assert stack_bound(g, "e").bytes is None
    assert [f.rule for f in stack_bound(g, "nope").findings] == ["entry"]


# --------------------------------------------------------------------------------------------------- MISRA

GOTO = """#include "rpo_toy_math.h"
double rpo_toy_clip(double x);
double rpo_toy_clip(double x)
{
    double y = x;
    if (x > 1.0) {
        goto done;
    }
    y = rpo_toy_sq(x);
done:
    return y;
}
"""


def test_an_unjustified_misra_finding_fails(tmp_path):
    r = checks.misra(toy(tmp_path, rpo_toy_extra__c=GOTO), DEVIATIONS)
    assert r.unjustified == 1 and r.by_rule["15.1"] == 1
    bad = [f for f in r.findings if not f.justified]
    assert (bad[0].file, bad[0].line, bad[0].rule) == ("rpo_toy_extra.c", 7, "15.1")


def test_without_deviations_every_finding_is_unjustified():
    r = checks.misra(TOY)
    assert r.total == r.unjustified == 8


def _deviations(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "dev.toml"
    p.write_text(text)
    return p


def test_a_deviation_holds_only_for_its_files(tmp_path):
    dev = DEVIATIONS.read_text().replace('files = ["rpo_toy_math.c"]', 'files = ["rpo_toy.c"]')
    r = checks.misra(TOY, _deviations(tmp_path, dev))
    assert r.unjustified == 2 and {f.rule for f in r.findings if not f.justified} == {"19.2"}
    assert r.unused_deviations == ["19.2"]


def test_a_mandatory_rule_admits_no_deviation(tmp_path):
    dev = DEVIATIONS.read_text().replace('"19.2"\ncategory = "advisory"', '"19.2"\ncategory = "mandatory"')
    r = checks.misra(TOY, _deviations(tmp_path, dev))
    assert r.unjustified == 2 and r.refused_deviations == ["19.2"]
    assert all("no deviation permitted" in f.message for f in r.findings if f.rule == "19.2")
    assert cppcheck.Deviation("17.3", "x").mandatory and not cppcheck.Deviation("10.4", "x").mandatory


def test_cppcheck_findings_are_reported_and_can_be_justified(tmp_path):
    pick = ("double rpo_toy_pick(const double *a);\n"
            "double rpo_toy_pick(const double *a) { double t[3]; t[0] = a[0]; return t[0] + t[3]; }\n")
    pkg = toy(tmp_path, rpo_toy_pick__c=pick)
    r = checks.misra(pkg, DEVIATIONS)
    assert [(f.rule, f.file) for f in r.cppcheck] == [("arrayIndexOutOfBounds", "rpo_toy_pick.c")]
    assert r.cppcheck_unjustified == 1
    dev = DEVIATIONS.read_text() + '\n[[deviation]]\nrule = "arrayIndexOutOfBounds"\nreason = "a test"\n'
    assert checks.misra(pkg, _deviations(tmp_path, dev)).cppcheck_unjustified == 0


@pytest.mark.parametrize("text, says", [
    ('[[deviation]]\nrule = 19.2\nreason = "r"\n', "rule must be a non-empty string"),
    ('[[deviation]]\nrule = "19.2"\n', "reason must be a non-empty string"),
    ('[[deviation]]\nrule = "19.2"\nreason = "r"\ncategory = "optional"\n', "category must be one of"),
    ('[[deviation]]\nrule = "19.2"\nreason = "r"\nfile = ["x.c"]\n', "unknown key(s) file"),
    ('[[deviations]]\nrule = "19.2"\n', "unknown key(s) deviations"),
])
def test_a_malformed_deviations_file_is_an_error(tmp_path, text, says):
    with pytest.raises(ModelError, match=re.escape(says)):
        cppcheck.read_deviations(_deviations(tmp_path, text))


def test_the_misra_addon_not_running_is_an_error_not_a_pass(tmp_path, monkeypatch):
    """cppcheck stays silent when its addon cannot run (here: no python3 on PATH); the canary catches it."""
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    (bin_ / "cppcheck").symlink_to(shutil.which("cppcheck"))
    monkeypatch.setenv("PATH", str(bin_))
    with pytest.raises(ModelError, match="MISRA addon did not run"):
        checks.misra(TOY)


# ----------------------------------------------------------------------------------------- missing tools


@pytest.mark.parametrize("call, deb", [
    (lambda: checks.compile_warnings(TOY), "apt-get install gcc"),
    (lambda: checks.compile_warnings(TOY, compilers=("clang",)), "apt-get install clang"),
    (lambda: checks.stack_usage(TOY, "rpo_toy_step", "cortex-m7"), "apt-get install gcc-arm-none-eabi"),
    (lambda: checks.misra(TOY), "apt-get install cppcheck"),
])
def test_a_missing_tool_is_an_error_naming_its_debian_package(tmp_path, monkeypatch, call, deb):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(ModelError, match=re.escape(deb)) as e:
        call()
    assert "\n" not in str(e.value)


def test_the_prefix_and_the_bad_arguments():
    assert checks.package_prefix(TOY) == "rpo_toy" and checks.package_prefix(TOY_SINGLE) == "rpo_toy"
    with pytest.raises(ModelError, match="precision"):
        checks.compile_warnings(TOY, precision="half")
    with pytest.raises(ModelError, match="unknown flight target"):
        checks.stack_usage(TOY, "rpo_toy_step", "cortex-a53")
    with pytest.raises(ModelError, match="no flight package folder"):
        checks.misra(TOY / "missing")
