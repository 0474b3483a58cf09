"""runtime/csrc/rpo_math.h: lane-width bit identity, accuracy against mpmath, C99 special values.

A C harness (tests/csrc/lane_math_harness.c) evaluates every function over an input array, fed
RPO_LANES consecutive elements per vector.  It is compiled for RPO_LANES = 1, 2, 4, 8, at -O2 and
at -O3 -march=native (when the compiler accepts it), and in the long run also for AVX2 and AVX-512
where this CPU runs them; every build must give the same bits.  No C compiler is a failure, not a
skip.
"""

from __future__ import annotations

import functools
import hashlib
import math
import os
import shutil
import subprocess
import tempfile
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mpmath
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
CSRC = ROOT / "runtime" / "csrc"
HARNESS = ROOT / "tests" / "csrc" / "lane_math_harness.c"

LANES = (1, 2, 4, 8)
BASE_FLAGS = ["-ffp-contract=off", "-Wall", "-Wno-psabi", "-std=gnu99"]
UNARY = ["sin", "cos", "tan", "exp", "log", "atan", "asin", "acos", "sinh", "cosh", "tanh", "expm1"]
TRIG_LIMIT = 1647099.0
#: max ulp error accepted per function (what rpo_math.h's header states)
ULP_BOUND = {
    "sin": 1.0, "cos": 1.0, "tan": 1.0, "exp": 1.0, "log": 1.0, "atan": 1.0, "expm1": 1.0,
    "atan2": 2.0, "asin": 2.0, "acos": 2.0, "sinh": 2.0, "cosh": 2.0, "tanh": 2.0,
}  # fmt: skip


def _compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        pytest.fail("no C compiler (cc/gcc) found: rpo_math.h cannot be tested")
    return cc


@functools.cache
def _accepts(cc: str, flag: str) -> bool:
    r = subprocess.run([cc, flag, "-x", "c", "-c", "-o", os.devnull, "-"], input="int x;\n",
                       capture_output=True, text=True)  # fmt: skip
    return r.returncode == 0


#: instruction-set flags of the slow builds -> the CPU feature their code needs to run
FEATURE_OF = {"-mavx2": "avx2", "-mavx512f": "avx512f"}


@functools.cache
def _cpu_runs(cc: str, flag: str) -> bool:
    """This CPU executes code built with ``flag`` (an AVX-512 build dies with SIGILL on an AVX2-only
    host): GCC's __builtin_cpu_supports, compiled and run once; False where the probe cannot be
    built (another architecture, where the flag is not accepted either)."""
    feature = FEATURE_OF.get(flag)
    if feature is None:
        return True
    with tempfile.TemporaryDirectory() as d:
        exe = Path(d) / "probe"
        src = f'int main(void) {{ __builtin_cpu_init(); return __builtin_cpu_supports("{feature}") ? 0 : 1; }}\n'
        r = subprocess.run([cc, "-x", "c", "-o", str(exe), "-"], input=src, capture_output=True, text=True)
        return r.returncode == 0 and subprocess.run([str(exe)]).returncode == 0


def _flag_sets(cc: str, slow: bool) -> list[list[str]]:
    sets = [["-O2"]]
    if _accepts(cc, "-march=native"):
        sets.append(["-O3", "-march=native"])
    if slow:
        sets += [["-O3"], ["-O2", "-march=native"]]
        # the explicit vector units this CPU can run (the machines here have AVX2, some AVX-512 too)
        sets += [fs for fs in (["-O2", "-mavx2"], ["-O3", "-mavx512f"]) if _cpu_runs(cc, fs[1])]
        sets = [s for s in sets if all(_accepts(cc, f) for f in s)]
    return sets


@functools.cache
def _cc_version(cc: str) -> str:
    return subprocess.run([cc, "--version"], capture_output=True, text=True).stdout


def _build(cc: str, lanes: int, flags: list[str]) -> Path:
    """the harness built for (lanes, flags); cached in the temp directory under a hash of the
    sources, the compiler and the command, so a rerun of the tests does not recompile"""
    cmd = [cc, *flags, *BASE_FLAGS, f"-DRPO_LANES={lanes}", f"-I{CSRC}", str(HARNESS), "-lm"]
    h = hashlib.sha256()
    for part in (" ".join(cmd), _cc_version(cc), *(p.read_text() for p in (HARNESS, CSRC / "rpo_math.h"))):
        h.update(part.encode())
    out = Path(tempfile.gettempdir()) / f"rpo_lane_math-{h.hexdigest()[:20]}"
    if out.exists():
        return out
    tmp = out.with_name(f"{out.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    r = subprocess.run([*cmd, "-o", str(tmp)], capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}\n{r.stderr}"
    assert "warning" not in r.stderr, r.stderr
    os.replace(tmp, out)
    return out


def _builds(slow: bool) -> dict[tuple[int, str], Path]:
    cc = _compiler()
    jobs = {}
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as ex:
        for flags in _flag_sets(cc, slow):
            for lanes in LANES:
                jobs[(lanes, " ".join(flags))] = ex.submit(_build, cc, lanes, flags)
        return {k: f.result() for k, f in jobs.items()}


@pytest.fixture(scope="module")
def builds():
    return _builds(slow=False)


@functools.cache
def _names(exe: Path) -> tuple[str, ...]:
    return tuple(subprocess.run([str(exe), "--names"], capture_output=True, text=True, check=True).stdout.split())


def _run(exe: Path, a: np.ndarray, b: np.ndarray, tmp: Path) -> dict[str, np.ndarray]:
    a = np.ascontiguousarray(a, np.float64)
    b = np.ascontiguousarray(b, np.float64)
    inp, out = tmp / f"{exe.name}.in", tmp / f"{exe.name}.out"
    with open(inp, "wb") as f:
        np.array([a.size], np.int64).tofile(f)
        a.tofile(f)
        b.tofile(f)
    subprocess.run([str(exe), str(inp), str(out)], check=True)
    res = np.fromfile(out, np.float64)
    inp.unlink()
    out.unlink()
    names = _names(exe)
    assert res.size == len(names) * a.size
    return {n: res[i * a.size : (i + 1) * a.size] for i, n in enumerate(names)}


# ------------------------------------------------------------------------------------------------
# inputs
# ------------------------------------------------------------------------------------------------
def _bits(x):
    return np.asarray(x, np.float64).view(np.uint64)


def _neighbours(x: np.ndarray, k: int) -> np.ndarray:
    """x and its k next doubles either side"""
    bits = _bits(x).astype(np.int64)
    steps = np.arange(-k, k + 1)
    return (bits[:, None] + steps[None, :]).ravel().view(np.float64)


def _stress_inputs(n: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    parts = [
        rng.choice([-1.0, 1.0], n // 4) * 10.0 ** rng.uniform(-300, 300, n // 4),  # all magnitudes
        rng.uniform(-10, 10, n // 8),
        rng.uniform(-1.2, 1.2, n // 16),
        _neighbours(np.arange(-200, 201) * (np.pi / 2), 8),  # near multiples of pi/2
        _neighbours(np.round(rng.uniform(-2**20, 2**20, 300)) * (np.pi / 2), 3),
        _neighbours(np.array([TRIG_LIMIT, -TRIG_LIMIT, 2**20 * np.pi / 2]), 30),  # the reduction limit
        rng.uniform(TRIG_LIMIT * 0.999, TRIG_LIMIT * 1.001, 1000) * rng.choice([-1, 1], 1000),
        rng.choice([-1.0, 1.0], n // 16) * 10.0 ** rng.uniform(6, 22, n // 16),  # above the limit
        rng.uniform(-750, 750, n // 16),  # exp / sinh / cosh thresholds
        _neighbours(np.array([709.782712893384, -745.1332191019411, -708.3964185322641, 710.4758600739439,
                              -710.4758600739439, 22.0, -22.0, 1.0, -1.0, 0.5, -0.5, 0.975, -0.975,
                              0.34657359027997264, 38.816242111356935, -38.816242111356935, 2.0**-28,
                              0.4375, 0.6875, 1.1875, 2.4375, 2.0**66, 0.6744]), 20),
        rng.uniform(-1, 1, 2000) * 2.0**-1022,  # subnormals
        np.array([0.0, -0.0, np.inf, -np.inf, np.nan, -np.nan, 5e-324, -5e-324, 2.2250738585072014e-308,
                  1.7976931348623157e308, -1.7976931348623157e308]),
    ]  # fmt: skip
    x = np.concatenate(parts)
    return x[rng.permutation(x.size)]


def _pair_inputs(x: np.ndarray, seed: int = 2) -> np.ndarray:
    """second arguments: a shuffle of x, with some equal to x, -x, +-0, +-inf"""
    rng = np.random.default_rng(seed)
    y = x[rng.permutation(x.size)].copy()
    pick = rng.integers(0, 8, x.size)
    y[pick == 0] = x[pick == 0]
    y[pick == 1] = -x[pick == 1]
    specials = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1.0])
    sel = pick == 2
    y[sel] = rng.choice(specials, sel.sum())
    return y


# ------------------------------------------------------------------------------------------------
# bit identity
# ------------------------------------------------------------------------------------------------
def _check_identity(builds, n, tmp):
    a = _stress_inputs(n)
    b = _pair_inputs(a)
    # a, b swapped too, so special values appear as either argument of atan2/fmin/fmax
    a2, b2 = np.concatenate([a, b]), np.concatenate([b, a])
    outs = {k: _run(exe, a2, b2, tmp) for k, exe in builds.items()}
    ref_key = (1, "-O2")
    ref = outs[ref_key]
    for key, out in outs.items():
        for name in ref:
            same = _bits(out[name]) == _bits(ref[name])
            if not same.all():
                i = np.flatnonzero(~same)[0]
                pytest.fail(f"{name}: RPO_LANES={key[0]} {key[1]} differs from {ref_key} at a={a2[i]!r} "
                            f"b={b2[i]!r}: {out[name][i]!r} vs {ref[name][i]!r} ({(~same).sum()} inputs)")  # fmt: skip
    return a2, b2, ref


def test_lane_widths_bit_identical(builds, tmp_path):
    assert len(builds) >= 4
    _check_identity(builds, 50_000, tmp_path)  # 1e5 inputs: (a, b) and (b, a)


def test_sincos_is_sin_and_cos(builds, tmp_path):
    a = _stress_inputs(100_000)
    for exe in builds.values():
        out = _run(exe, a, a, tmp_path)
        assert np.array_equal(_bits(out["sincos_s"]), _bits(out["sin"]))
        assert np.array_equal(_bits(out["sincos_c"]), _bits(out["cos"]))


# ------------------------------------------------------------------------------------------------
# accuracy against mpmath
# ------------------------------------------------------------------------------------------------
MP = {
    "sin": mpmath.sin, "cos": mpmath.cos, "tan": mpmath.tan, "exp": mpmath.exp, "log": mpmath.log,
    "atan": mpmath.atan, "asin": mpmath.asin, "acos": mpmath.acos, "sinh": mpmath.sinh,
    "cosh": mpmath.cosh, "tanh": mpmath.tanh, "expm1": mpmath.expm1,
}  # fmt: skip


def _ulp_err(got: float, exact) -> float:
    """|got - exact| in units of the last place of the double nearest exact"""
    if exact == 0:
        return 0.0 if got == 0 else math.inf
    e = int(mpmath.floor(mpmath.log(abs(exact), 2)))
    if e >= 1024:  # overflows: inf is right
        return 0.0 if math.isinf(got) and (got > 0) == (exact > 0) else math.inf
    if not math.isfinite(got):
        return math.inf
    ulp = mpmath.ldexp(1, max(e - 52, -1074))
    return float(abs(mpmath.mpf(got) - exact) / ulp)


def _accuracy_inputs(name: str, n: int, rng) -> np.ndarray:
    def logu(lo, hi, m):
        return rng.choice([-1.0, 1.0], m) * 10.0 ** rng.uniform(lo, hi, m)

    if name in ("sin", "cos", "tan"):
        near = np.round(rng.uniform(-(2**20), 2**20, n // 8)) * (np.pi / 2)
        x = np.concatenate([logu(-300, math.log10(TRIG_LIMIT), n // 2), rng.uniform(-7, 7, n // 4),
                            _neighbours(near, 1), _neighbours(np.arange(1, 64) * np.pi / 2, 2)])  # fmt: skip
        return x[np.abs(x) < TRIG_LIMIT]
    if name == "exp":
        return np.concatenate([rng.uniform(-745.2, 709.79, n // 2), logu(-300, 2.8, n // 2)])
    if name == "expm1":
        return np.concatenate([rng.uniform(-40, 709.7, n // 2), logu(-300, 1.5, n // 2)])
    if name == "log":
        return np.concatenate([10.0 ** rng.uniform(-323, 308, n // 2), rng.uniform(0.5, 2, n // 4),
                               1 + logu(-16, -1, n // 4)])  # fmt: skip
    if name == "atan":
        return logu(-300, 300, n)
    if name in ("asin", "acos"):
        return np.concatenate([rng.uniform(-1, 1, n // 2), logu(-300, 0, n // 4),
                               rng.choice([-1, 1], n // 4) * (1 - 10.0 ** rng.uniform(-16, -1, n // 4))])  # fmt: skip
    if name in ("sinh", "cosh"):
        return np.concatenate([rng.uniform(-710.4, 710.4, n // 3), rng.uniform(-25, 25, n // 3), logu(-300, 0, n // 3)])
    if name == "tanh":
        return np.concatenate([rng.uniform(-25, 25, n // 2), logu(-300, 0.5, n // 2)])
    raise KeyError(name)


def _max_ulp(exe: Path, n: int, tmp: Path, seed: int = 7) -> dict[str, tuple[float, float, int]]:
    rng = np.random.default_rng(seed)
    res = {}
    with mpmath.workprec(160):
        for name in UNARY:
            x = _accuracy_inputs(name, n, rng)
            got = _run(exe, x, x, tmp)[name]
            errs = [_ulp_err(float(g), MP[name](mpmath.mpf(float(v)))) for v, g in zip(x, got, strict=True)]
            i = int(np.argmax(errs))
            res[name] = (errs[i], float(x[i]), len(x))
        y = np.concatenate([rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-30, 30, n)])
        x = rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-30, 30, n)
        x[: n // 4] = rng.uniform(-2, 2, n // 4)
        y[: n // 4] = rng.uniform(-2, 2, n // 4)
        got = _run(exe, y, x, tmp)["atan2"]
        errs = [_ulp_err(float(g), mpmath.atan2(mpmath.mpf(float(b)), mpmath.mpf(float(a))))
                for b, a, g in zip(y, x, got, strict=True)]  # fmt: skip
        i = int(np.argmax(errs))
        res["atan2"] = (errs[i], float(y[i]), n)
    return res


def test_accuracy_against_mpmath(builds, tmp_path):
    res = _max_ulp(builds[(1, "-O2")], 2000, tmp_path)
    bad = {k: v for k, v in res.items() if not v[0] <= ULP_BOUND[k]}
    assert not bad, f"max ulp error above bound (err, at x, points): {bad}"


# ------------------------------------------------------------------------------------------------
# special values and exact functions
# ------------------------------------------------------------------------------------------------
def _same(got, want):
    """bitwise equal, except that any NaN matches any NaN"""
    got, want = np.asarray(got, np.float64), np.asarray(want, np.float64)
    both_nan = np.isnan(got) & np.isnan(want)
    return both_nan | (_bits(got) == _bits(want))


SPECIAL = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 5e-324, -5e-324, 1e-310, -1e-310, 1.0, -1.0,
                    1.0000000000000002, -1.0000000000000002, 2.0, -2.0, 710.0, -710.0, 746.0, -746.0,
                    1e300, -1e300, 1.7976931348623157e308, -1.7976931348623157e308])  # fmt: skip

NP_REF = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log, "atan": np.arctan,
    "asin": np.arcsin, "acos": np.arccos, "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh,
    "expm1": np.expm1,
}  # fmt: skip


def test_special_values(builds, tmp_path):
    out = _run(builds[(1, "-O2")], SPECIAL, SPECIAL, tmp_path)
    with np.errstate(all="ignore"):
        for name, ref in NP_REF.items():
            want = ref(SPECIAL)
            got = out[name]
            # non-finite / zero results and signs must match C99 (numpy's libm follows it); finite
            # nonzero results are the accuracy test's business
            exactish = ~np.isfinite(want) | (want == 0) | (np.abs(want) == 1) | (np.abs(SPECIAL) < 1e-300)
            exactish &= ~((np.abs(want) > 1e300) & np.isfinite(want))
            ok = _same(got, want) | ~exactish
            assert ok.all(), f"{name}: x={SPECIAL[~ok]} got {got[~ok]} want {want[~ok]}"
            # tiny arguments: f(x) = x (odd functions) exactly
        tiny = np.array([5e-324, -5e-324, 1e-310, -1e-310, 1e-200, -1e-200, 0.0, -0.0])
        o = _run(builds[(1, "-O2")], tiny, tiny, tmp_path)
        for name in ("sin", "tan", "atan", "asin", "sinh", "tanh", "expm1"):
            assert _same(o[name], tiny).all(), (name, o[name])
        assert (o["cos"] == 1).all() and (o["cosh"] == 1).all() and (o["exp"] == 1).all()
        assert _same(o["acos"], np.full(tiny.size, np.pi / 2)).all()


def test_atan2_special_values(builds, tmp_path):
    vals = np.array([0.0, -0.0, 1.0, -1.0, 2.5, -2.5, 1e-310, -1e-310, 1e300, -1e300, np.inf, -np.inf, np.nan])
    y, x = (v.ravel() for v in np.meshgrid(vals, vals, indexing="ij"))
    out = _run(builds[(1, "-O2")], y, x, tmp_path)
    want = np.arctan2(y, x)
    got = out["atan2"]
    special = ~np.isfinite(y) | ~np.isfinite(x) | (y == 0) | (x == 0)
    ok = _same(got, want) | ~special
    assert ok.all(), list(zip(y[~ok], x[~ok], got[~ok], want[~ok], strict=True))
    close = np.abs(got - want) <= 2 * np.spacing(np.abs(want))
    assert (close | np.isnan(want)).all()


def test_exact_functions(builds, tmp_path):
    a = _stress_inputs(20_000, seed=3)
    b = _pair_inputs(a, seed=4)
    out = _run(builds[(1, "-O2")], a, b, tmp_path)
    with np.errstate(all="ignore"):
        assert _same(out["sqrt"], np.sqrt(a)).all()
        assert _same(out["floor"], np.floor(a)).all()
        assert _same(out["ceil"], np.ceil(a)).all()
        assert np.array_equal(_bits(out["fabs"]), _bits(np.abs(a)))
        sign = np.where(a < 0, -1.0, np.where(a > 0, 1.0, a))
        assert _same(out["sign"], sign).all()
        nz = ~((a == 0) & (b == 0))
        assert _same(out["fmin"][nz], np.fmin(a, b)[nz]).all()
        assert _same(out["fmax"][nz], np.fmax(a, b)[nz]).all()
        assert _same(out["select_lt"], np.where(a < b, a, b)).all()
        for name, op in (("lt", np.less), ("le", np.less_equal), ("gt", np.greater), ("ge", np.greater_equal),
                         ("eq", np.equal), ("ne", np.not_equal)):  # fmt: skip
            assert np.array_equal(_bits(out[name]), _bits(op(a, b).astype(np.float64))), name
        assert np.array_equal(out["mand"], ((a < b) & (a > 0)).astype(float))
        assert np.array_equal(out["mor"], ((a < b) | (a > 0)).astype(float))
        assert np.array_equal(out["mnot"], (~(a < b)).astype(float))
    # the signed-zero rule: fmin(+-0, -+0) = -0, fmax = +0, in either order
    z = np.array([0.0, -0.0, 0.0, -0.0])
    w = np.array([-0.0, 0.0, 0.0, -0.0])
    o = _run(builds[(1, "-O2")], z, w, tmp_path)
    assert np.array_equal(_bits(o["fmin"]), _bits(np.array([-0.0, -0.0, 0.0, -0.0])))
    assert np.array_equal(_bits(o["fmax"]), _bits(np.array([0.0, 0.0, 0.0, -0.0])))
    # fmin/fmax with NaN: the other argument
    o = _run(builds[(1, "-O2")], np.array([np.nan, 1.0, np.nan]), np.array([2.0, np.nan, np.nan]), tmp_path)
    assert o["fmin"][0] == 2 and o["fmin"][1] == 1 and np.isnan(o["fmin"][2])
    assert o["fmax"][0] == 2 and o["fmax"][1] == 1 and np.isnan(o["fmax"][2])


def test_refuses_fast_math_and_bad_lanes(tmp_path):
    cc = _compiler()
    src = tmp_path / "t.c"
    src.write_text('#include "rpo_math.h"\nint main(void) { return 0; }\n')
    for flags in (["-ffast-math"], ["-DRPO_LANES=3"]):
        r = subprocess.run([cc, *flags, f"-I{CSRC}", str(src), "-o", str(tmp_path / "t")], capture_output=True)
        assert r.returncode != 0, flags


def test_scalar_header_replaces_libm_calls(tmp_path):
    """gcc -include rpo_math_scalar.h: a file calling sin() etc. gets rpo_sin() etc."""
    cc = _compiler()
    src = tmp_path / "gen.c"
    src.write_text(
        "#include <math.h>\n#include <stdio.h>\n"
        "int main(void) { volatile double x = 0.7, y = -1.3;\n"
        '  printf("%a %a %a %a %a %a %a %a %a %a %a %a %a %a\\n", sin(x), cos(x), tan(x), exp(x), log(x),\n'
        "         atan(x), atan2(x, y), asin(x), acos(x), sinh(x), cosh(x), tanh(x), fmin(x, y), fmax(x, y));\n"
        "  return 0; }\n"
    )
    exe = tmp_path / "gen"
    r = subprocess.run([cc, "-O2", *BASE_FLAGS, "-include", str(CSRC / "rpo_math_scalar.h"), f"-I{CSRC}",
                        str(src), "-o", str(exe), "-lm"], capture_output=True, text=True)  # fmt: skip
    assert r.returncode == 0, r.stderr
    got = [float.fromhex(s) for s in subprocess.run([str(exe)], capture_output=True, text=True).stdout.split()]
    src2 = tmp_path / "ref.c"
    src2.write_text(
        '#include "rpo_math.h"\n#include <stdio.h>\n'
        "int main(void) { volatile double x = 0.7, y = -1.3;\n"
        '  printf("%a %a %a %a %a %a %a %a %a %a %a %a %a %a\\n", rpo_sin(x), rpo_cos(x), rpo_tan(x),\n'
        "         rpo_exp(x), rpo_log(x), rpo_atan(x), rpo_atan2(x, y), rpo_asin(x), rpo_acos(x),\n"
        "         rpo_sinh(x), rpo_cosh(x), rpo_tanh(x), rpo_fmin(x, y), rpo_fmax(x, y));\n"
        "  return 0; }\n"
    )
    r = subprocess.run([cc, "-O2", *BASE_FLAGS, f"-I{CSRC}", str(src2), "-o", str(exe) + "2", "-lm"],
                       capture_output=True, text=True)  # fmt: skip
    assert r.returncode == 0, r.stderr
    want = [float.fromhex(s) for s in subprocess.run([str(exe) + "2"], capture_output=True, text=True).stdout.split()]
    assert got == want and len(got) == 14
    # and the macros really are in place
    r = subprocess.run([cc, "-E", "-dM", "-include", str(CSRC / "rpo_math_scalar.h"), f"-I{CSRC}", "-x", "c",
                        os.devnull], capture_output=True, text=True, check=True)  # fmt: skip
    for f in ("sin", "cos", "tan", "exp", "log", "atan", "atan2", "asin", "acos", "sinh", "cosh", "tanh",
              "fmin", "fmax"):  # fmt: skip
        assert f"#define {f}(" in r.stdout, f


# ------------------------------------------------------------------------------------------------
# slow: many more points, more flag sets
# ------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_lane_widths_bit_identical_many(tmp_path):
    builds = _builds(slow=True)
    for seed in range(4):  # 4e6 inputs x 24 builds: about 100 s on 2 cores
        a = _stress_inputs(1_000_000, seed=100 + seed)
        b = _pair_inputs(a, seed=200 + seed)
        outs = [_run(exe, a, b, tmp_path) for exe in builds.values()]
        for out in outs[1:]:
            for name in outs[0]:
                assert np.array_equal(_bits(out[name]), _bits(outs[0][name])), name


@pytest.mark.slow
def test_accuracy_against_mpmath_many(builds, tmp_path):
    res = _max_ulp(builds[(1, "-O2")], 100_000, tmp_path, seed=11)
    print({k: (round(v[0], 3), v[1], v[2]) for k, v in res.items()})
    bad = {k: v for k, v in res.items() if not v[0] <= ULP_BOUND[k]}
    assert not bad, bad


def test_cpu_probe_agrees_with_the_kernel():
    """The probe that picks the long run's AVX2 / AVX-512 builds says what /proc/cpuinfo says
    (where the kernel lists x86 flags), so that a build this CPU can run is never left out."""
    info = Path("/proc/cpuinfo")
    text = info.read_text() if info.exists() else ""
    line = next((ln for ln in text.splitlines() if ln.startswith("flags")), None)
    if line is None:  # not x86 Linux: the flags are not accepted, the probe says False
        assert not any(_cpu_runs(_compiler(), f) and not _accepts(_compiler(), f) for f in FEATURE_OF)
        return
    flags = set(line.split(":", 1)[1].split())
    for flag, feature in FEATURE_OF.items():
        assert _cpu_runs(_compiler(), flag) == (feature in flags), flag
