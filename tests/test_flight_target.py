"""The processor-in-the-loop target (rpo.runtime.flight): the toy package of tests/pil_toy/ built for
QEMU's Cortex-M7 (double) and Cortex-M4F (float), against the same package compiled for the host.

Needs gcc-arm-none-eabi, libnewlib-arm-none-eabi and qemu-system-arm (Debian packages): without
them these tests skip, except under CI (the environment variable CI set), where they fail.
"""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.build import adapter_header, build_firmware, check_tools, qemu_path, read_package
from rpo.runtime.flight.target import Firmware, PilTarget, StepResult
from rpo.runtime.model.toolchain import csrc_dir

pytestmark = pytest.mark.flight

HERE = Path(__file__).resolve().parent
TOY = HERE / "pil_toy"
HOST_DRIVER = HERE / "csrc" / "pil_host_driver.c"
#: kp, kd, ki, dt, u_max: the command saturates for about half of the random inputs below
PARAMS = np.array([0.8, 1.7, 0.05, 0.1, 4.0])
N_STEPS = 300


@functools.cache
def _missing_tool() -> str | None:
    """The one-line error of the first missing tool, or None."""
    try:
        check_tools("m7")
        check_tools("m4f")
    except ModelError as exc:
        return str(exc)
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        return "no host C compiler (cc, gcc) for the reference build: install gcc"
    return None


def needs_tools(test):
    """The test fails (CI set) or skips (else) when a tool is missing: in the test, not in a fixture,
    so that under CI it is reported as failed.  The fixtures that build give None then."""

    @functools.wraps(test)
    def run(*args, **kwargs):
        missing = _missing_tool()
        if missing is not None:
            if os.environ.get("CI"):
                pytest.fail(f"CI is set and a PIL tool is missing: {missing}")
            pytest.skip(missing)
        return test(*args, **kwargs)

    return run


@pytest.fixture(scope="session")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("pil-cache")


def _float_copy(dest: Path) -> Path:
    shutil.copytree(TOY, dest)
    h = dest / "rpo_toy.h"
    text = h.read_text()
    assert "typedef double rpo_toy_real_t;" in text
    h.write_text(text.replace("typedef double rpo_toy_real_t;", "typedef float rpo_toy_real_t;"))
    return dest


@pytest.fixture(scope="session")
def toy_float(tmp_path_factory):
    return _float_copy(tmp_path_factory.mktemp("toy-float") / "pkg")


@pytest.fixture(scope="session")
def fw_m7(cache):
    return None if _missing_tool() else build_firmware(TOY, cache=cache)


@pytest.fixture(scope="session")
def fw_m4f(cache, toy_float):
    return None if _missing_tool() else build_firmware(toy_float, cache=cache)


@pytest.fixture
def m7(fw_m7):
    if fw_m7 is None:
        yield None
        return
    with PilTarget(fw_m7) as target:
        yield target


def _inputs(seed: int, n: int = N_STEPS) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.hstack([rng.normal(0.0, 3.0, (n, 3)), rng.normal(0.0, 1.0, (n, 3))])


def _host_run(package: Path, tmp: Path, params: np.ndarray, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The host build's initial state and its (outputs, state) rows, from the same hex lines."""
    pkg = read_package(package)
    dtype = np.dtype(">f8" if pkg.real == "double" else ">f4")
    (tmp / "pil_adapter.h").write_text(adapter_header(pkg))
    exe = tmp / "host_driver"
    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc is not None
    subprocess.run([cc, "-std=c99", "-O2", "-ffp-contract=off", "-I", str(tmp), "-I", str(package), str(HOST_DRIVER),
                    *(str(package / n) for n in pkg.sources), "-lm", "-o", str(exe)], check=True)

    def line(cmd: str, values: np.ndarray) -> str:
        hexa, d = values.astype(dtype).tobytes().hex(), 2 * dtype.itemsize
        return cmd + "".join(" " + hexa[i:i + d] for i in range(0, len(hexa), d)) + "\n"

    text = line("P", params) + "".join(line("S", row) for row in inputs)
    out = subprocess.run([str(exe)], input=text, capture_output=True, text=True, check=True, timeout=60).stdout
    rows = [np.frombuffer(bytes.fromhex("".join(ln.split()[1:])), dtype).astype(np.float64) for ln in out.splitlines()]
    return rows[0], np.array(rows[1:])


def _bits(a: np.ndarray) -> np.ndarray:
    return np.asarray(a, np.float64).view(np.uint64)


# --------------------------------------------------------------------------- results against the host


@needs_tools
def test_double_package_on_the_m7_gives_the_host_bits(m7, tmp_path):
    inputs = _inputs(1)
    state0 = m7.init(PARAMS)
    rows = [m7.step(x) for x in inputs]
    target = np.array([np.concatenate([r.outputs, r.state]) for r in rows])
    host0, host = _host_run(TOY, tmp_path, PARAMS, inputs)
    assert np.array_equal(_bits(state0), _bits(host0))
    assert np.array_equal(_bits(target), _bits(host))
    saturated = target[:, -1]
    assert 0.2 < saturated.mean() < 0.8, "both branches of the saturation are exercised"


@needs_tools
def test_float_package_on_the_m4f_agrees_with_a_host_float_build(fw_m4f, toy_float, tmp_path):
    """Tolerance: none.  The toy uses only correctly rounded operations (+ - * /, sqrt), in float
    with the FPU of the M4F and in double (sqrt) with libgcc's software IEEE double there, so the
    target and an x86-64 float build (SSE, -ffp-contract=off) agree bit for bit.  A package that
    calls libm's transcendental functions would agree only to a few ulp (newlib against glibc)."""
    inputs = _inputs(2)
    with PilTarget(fw_m4f) as target:
        assert fw_m4f.core == "m4f" and fw_m4f.machine == "mps2-an386" and fw_m4f.real_bytes == 4
        state0 = target.init(PARAMS)
        rows = [target.step(x) for x in inputs]
    got = np.array([np.concatenate([r.outputs, r.state]) for r in rows])
    host0, host = _host_run(toy_float, tmp_path, PARAMS, inputs)
    assert np.array_equal(_bits(state0), _bits(host0))
    assert np.array_equal(_bits(got), _bits(host))
    # and the values are float32 values: the widening to float64 is exact
    assert np.array_equal(got.astype(np.float32).astype(np.float64), got)


@needs_tools
def test_the_counts_of_the_io_header_come_with_the_ready_line(m7):
    assert (m7.n_params, m7.n_inputs, m7.n_outputs, m7.n_state) == (5, 6, 4, 4)
    assert m7.firmware.machine == "mps2-an500" and m7.core == "m7" and m7.stack_size == 64 * 1024


@needs_tools
def test_rpos_own_math_gives_the_host_bits_on_the_m7(cache, tmp_path):
    """rpo_math.h (runtime/csrc), which the generated code is compiled with, on the M7 against the
    host: the same bits for sin ... atan, where newlib's libm and glibc's differ in the last bit for
    several percent of these points (sin, cos, tan, atan, atan2, asin, acos; measured)."""
    pkg = tmp_path / "mt"
    shutil.copytree(HERE / "pil_math", pkg)
    for name in ("rpo_math.h", "rpo_math_scalar.h"):
        shutil.copy(csrc_dir() / name, pkg / name)
    rng = np.random.default_rng(5)
    inputs = np.hstack([rng.uniform(-50, 50, (200, 1)), rng.uniform(-5, 5, (200, 3))])
    with PilTarget(build_firmware(pkg, cache=cache)) as target:
        target.init(np.ones(1))
        got = np.array([target.step(x).outputs for x in inputs])
    _, host = _host_run(pkg, tmp_path, np.ones(1), inputs)
    assert np.array_equal(_bits(got), _bits(host[:, :12]))


# --------------------------------------------------------------------------- measurements


@needs_tools
def test_the_instruction_count_of_a_loop_of_known_length_is_exact(m7):
    for n in (1, 2, 10, 1000, 123_457):
        assert m7.calibrate(n) == 2 * n + 4


@needs_tools
def test_instruction_counts_are_positive_and_repeatable(m7, fw_m7):
    x = _inputs(3, 1)[0]
    m7.init(PARAMS)
    first = m7.step(x)
    m7.init(PARAMS)
    again = m7.step(x)
    assert first.instructions > 20
    assert (again.instructions, again.stack_bytes) == (first.instructions, first.stack_bytes)
    assert np.array_equal(_bits(again.state), _bits(first.state))
    with PilTarget(fw_m7) as other:  # another emulator process: the same counts
        other.init(PARAMS)
        r = other.step(x)
    assert (r.instructions, r.stack_bytes) == (first.instructions, first.stack_bytes)


@needs_tools
def test_the_stack_high_water_is_positive_and_sane(m7):
    m7.init(PARAMS)
    used = {m7.step(x).stack_bytes for x in _inputs(4, 20)}
    # the toy's frames: rpo_toy_step 48 and rpo_toy_saturate_norm 24 bytes by -fstack-usage (-O2)
    assert all(0 < s <= 256 for s in used), used


# --------------------------------------------------------------------------- misuse and failures


@needs_tools
def test_wrong_sizes_raise_and_name_the_expected_size(m7):
    with pytest.raises(ModelError, match="params must be a 1-D array of 5 values"):
        m7.init(PARAMS[:4])
    with pytest.raises(ModelError, match="before init"):
        m7.step(np.zeros(6))
    m7.init(PARAMS)
    with pytest.raises(ModelError, match="inputs must be a 1-D array of 6 values"):
        m7.step(np.zeros(7))
    with pytest.raises(ModelError, match="6 values"):
        m7.step(np.zeros((2, 3)))
    assert isinstance(m7.step(np.zeros(6)), StepResult), "a size error is caught on the host: the target lives on"


@needs_tools
def test_a_protocol_error_ends_the_target_with_its_message(m7):
    t0 = time.monotonic()
    m7._send_line(b"S 0123\n")  # a line the host never sends: a step before P, with a bad value
    with pytest.raises(ModelError, match=r"reported an error .*S before P.*exit status 2"):
        m7.calibrate(1)
    assert time.monotonic() - t0 < 5
    assert not m7.alive
    with pytest.raises(ModelError, match="closed"):
        m7.init(PARAMS)


@needs_tools
def test_a_malformed_line_is_refused_by_the_target(m7):
    m7.init(PARAMS)
    m7._send_line(b"S " + b"00" * 8 + b"\n")  # one value for six
    with pytest.raises(ModelError, match="wrong number of values"):
        m7.calibrate(1)


@needs_tools
def test_a_dead_target_raises_without_hanging(m7):
    m7.init(PARAMS)
    m7._proc.kill()
    t0 = time.monotonic()
    with pytest.raises(ModelError, match="PIL target (ended|did not|exited|reported)"):
        for _ in range(3):
            m7.step(np.zeros(6))
    assert time.monotonic() - t0 < 5


@needs_tools
def test_a_fault_in_the_step_is_reported(cache, tmp_path):
    """An integer division by zero (trapped: CCR.DIV_0_TRP) ends the target with its fault line."""
    pkg = tmp_path / "pkg"
    shutil.copytree(TOY, pkg)
    c = pkg / "rpo_toy.c"
    c.write_text(c.read_text().replace(
        "    out->u_norm =",
        "    if (in->r[0] > 1e300) {\n        volatile int one = 1, zero = 0;\n"
        "        state->z[0] = one / zero;\n    }\n    out->u_norm ="))
    with PilTarget(build_firmware(pkg, cache=cache)) as target:
        target.init(PARAMS)
        target.step(np.ones(6))
        with pytest.raises(ModelError, match=r"fault: exception 0x00000006.*exit status 3: fault on the target"):
            target.step(np.array([1e301, 0, 0, 0, 0, 0]))


def _fake(script: str) -> list[str]:
    return [sys.executable, "-c", script]


@pytest.fixture
def fake_fw(tmp_path):
    """A firmware record for a fake target (a Python script in place of QEMU): no tools needed."""
    return Firmware(tmp_path / "none.elf", "toy", "double", "m7", "mps2-an500", 65536, "0" * 64)


def test_garbage_from_the_target_raises_naming_it(fake_fw):
    t0 = time.monotonic()
    with pytest.raises(ModelError, match=r"unexpected line at start-up: 'Hello, world'.*last output: Hello, world"):
        PilTarget(fake_fw, command=_fake("print('Hello, world', flush=True); import time; time.sleep(60)"))
    assert time.monotonic() - t0 < 10


def test_a_silent_target_times_out(fake_fw):
    t0 = time.monotonic()
    with pytest.raises(ModelError, match="did not answer within 0.5 s at start-up"):
        PilTarget(fake_fw, startup_timeout=0.5, command=_fake("import time; time.sleep(60)"))
    assert time.monotonic() - t0 < 5


def test_a_target_that_stops_answering_mid_run_times_out(fake_fw):
    script = ("import sys, time\nprint('READY 1 5 6 4 4 8 65536', flush=True)\nsys.stdin.readline()\n"
              "print('INIT' + ' 0000000000000000' * 4, flush=True)\ntime.sleep(60)\n")
    with PilTarget(fake_fw, timeout=0.5, command=_fake(script)) as target:
        assert np.array_equal(target.init(PARAMS), np.zeros(4))
        t0 = time.monotonic()
        with pytest.raises(ModelError, match="did not answer within 0.5 s after the inputs"):
            target.step(np.zeros(6))
        assert time.monotonic() - t0 < 5


def test_a_bad_value_in_a_reply_is_garbage(fake_fw):
    script = ("import sys\nprint('READY 1 5 6 4 4 8 65536', flush=True)\nsys.stdin.readline()\n"
              "print('INIT' + ' 000000000000000g' * 4, flush=True)\nsys.stdin.readline()\n")
    with pytest.raises(ModelError, match="not 16 hex digits in a INIT line"):
        with PilTarget(fake_fw, command=_fake(script)) as target:
            target.init(PARAMS)


# --------------------------------------------------------------------------- the build and its cache


def test_test_programs_of_the_package_are_not_firmware():
    pkg = read_package(TOY)
    assert pkg.name == "toy" and pkg.real == "double"
    assert "test_rpo_toy.c" not in pkg.sources and {"rpo_toy.c", "rpo_toy_io.c", "rpo_toy_math.c"} <= set(pkg.sources)


@needs_tools
def test_a_stale_build_is_never_reused(tmp_path):
    pkg = tmp_path / "pkg"
    shutil.copytree(TOY, pkg)
    cache = tmp_path / "cache"
    built: list[str] = []
    first = build_firmware(pkg, cache=cache, log=built.append)
    again = build_firmware(pkg, cache=cache, log=built.append)
    assert again == first and len(built) == 1

    # a host test program is no input of the firmware
    (pkg / "test_rpo_toy.c").write_text((pkg / "test_rpo_toy.c").read_text() + "\n/* edited */\n")
    assert build_firmware(pkg, cache=cache, log=built.append).key == first.key and len(built) == 1

    # an edit of any package file gives another key, another ELF, and the new code runs
    math = pkg / "rpo_toy_math.c"
    math.write_text(math.read_text().replace("return n * scale;", "return 2 * n * scale;"))
    edited = build_firmware(pkg, cache=cache, log=built.append)
    assert edited.key != first.key and edited.elf != first.elf and len(built) == 2
    x = np.array([0.1, 0, 0, 0, 0, 0])
    with PilTarget(first) as old, PilTarget(edited) as new:
        old.init(PARAMS)
        new.init(PARAMS)
        assert new.step(x).outputs[3] == 2 * old.step(x).outputs[3]

    header = pkg / "rpo_toy_math.h"
    header.write_text(header.read_text() + "\n/* a header counts too */\n")
    assert build_firmware(pkg, cache=cache).key != edited.key
    assert build_firmware(pkg, "m4f", cache=cache).key != build_firmware(pkg, "m7", cache=cache).key

    # a cached ELF that no longer matches its seal is rebuilt, never run
    elf = build_firmware(pkg, cache=cache).elf
    elf.write_bytes(elf.read_bytes()[:100])
    built.clear()
    assert build_firmware(pkg, cache=cache, log=built.append).elf == elf and built
    assert elf.stat().st_size > 100


@needs_tools
def test_two_builds_at_once_make_one_elf(tmp_path):
    cache = tmp_path / "cache"
    built: list[str] = []
    results: list[Path] = []

    def build() -> None:
        results.append(build_firmware(TOY, cache=cache, log=built.append).elf)

    threads = [threading.Thread(target=build) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 2 and results[0] == results[1] and len(built) == 1
    assert sorted(p.name for p in cache.iterdir() if p.suffix == ".elf") == [results[0].name]


def test_a_missing_tool_names_its_debian_package(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    for call in (lambda: build_firmware(TOY, cache=tmp_path), qemu_path, check_tools):
        with pytest.raises(ModelError) as err:
            call()
        assert "\n" not in str(err.value)
    with pytest.raises(ModelError, match="install the Debian package gcc-arm-none-eabi"):
        build_firmware(TOY, cache=tmp_path)
    with pytest.raises(ModelError, match="install the Debian package qemu-system-arm"):
        qemu_path()

    # a cross compiler without newlib: -print-file-name answers with the bare name
    gcc = tmp_path / "arm-none-eabi-gcc"
    gcc.write_text('#!/bin/sh\ncase "$*" in\n  *-print-file-name=*) echo "${*##*=}" ;;\n'
                   '  *) echo "arm-none-eabi-gcc (fake) 0.0" ;;\nesac\n')
    gcc.chmod(0o755)
    with pytest.raises(ModelError, match="install the Debian package libnewlib-arm-none-eabi"):
        build_firmware(TOY, cache=tmp_path)


def test_bad_arguments_of_the_build(tmp_path):
    with pytest.raises(ModelError, match="has no rpo_toy.h"):
        (tmp_path / "rpo_toy_io.h").write_text("")
        read_package(tmp_path)
    with pytest.raises(ModelError, match="exactly one rpo_<name>_io.h"):
        read_package(HERE)
    with pytest.raises(ModelError, match="unknown PIL core"):
        build_firmware(TOY, "m0", cache=tmp_path)
    with pytest.raises(ModelError, match="stack_size"):
        build_firmware(TOY, stack_size=100, cache=tmp_path)


def test_the_target_imports_neither_sympy_nor_casadi():
    code = "import sys, rpo.runtime.flight.target; sys.exit(bool({'sympy', 'casadi'} & set(sys.modules)))"
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0
