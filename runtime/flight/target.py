"""Processor-in-the-loop target: one exported controller package running on an emulated Cortex-M
(QEMU), driven one step at a time from Python through a pipe.

::

    from rpo.runtime.flight.target import PilTarget, build_firmware

    fw = build_firmware("out/c001")                 # m7 (mps2-an500) for a double package
    with PilTarget(fw) as target:
        state0 = target.init(params)                # flat params -> the state after initialize
        r = target.step(inputs)                     # StepResult(outputs, state, instructions, stack_bytes)

The firmware (``runtime/flight/firmware/``, built by :mod:`rpo.runtime.flight.build`) speaks a line
protocol over ARM semihosting on QEMU's stdin/stdout; every real value travels as the hexadecimal
IEEE bit pattern of the package's real type, so a double package's results are the target's bits.
"""

from __future__ import annotations

import queue
import re
import subprocess
import threading
import time
import weakref
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import IO, Any, NoReturn

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.build import (
    CORES,
    ICOUNT_SHIFT,
    PROTOCOL_VERSION,
    Firmware,
    build_firmware,
    check_tools,
    qemu_path,
)

__all__ = ["PilTarget", "StepResult", "build_firmware", "check_tools", "qemu_command", "Firmware"]

#: the longest line read from the target (bytes): a longer one is garbage, not a reply
_LINE_LIMIT = 1 << 20
#: lines of the target's stdout and stderr kept for error messages
_TAIL = 6
#: QEMU's warning for the board's Ethernet controller left without a network (as asked: -nic none)
_QEMU_NO_NETWORK = "has no peer"
_HEX = re.compile(r"[0-9a-fA-F]*")

#: the exit statuses of the harness (pil_harness.c, pil_startup.c) and of QEMU itself
_EXIT_MEANING = {0: "normal exit", 1: "QEMU error", 2: "the harness stopped on an error", 3: "fault on the target",
                 4: "no semihosting console"}


@dataclass(frozen=True)
class StepResult:
    """One step on the target: the outputs and the state after the step (float64, exact also for a
    float package), the instructions the step executed, the stack bytes it used."""

    outputs: np.ndarray
    state: np.ndarray
    instructions: int
    stack_bytes: int


def qemu_command(fw: Firmware, qemu: str | None = None) -> list[str]:
    """The emulator command line of ``fw``: its machine, no display, no default devices (no serial
    port or monitor on stdio, no network), semihosting on QEMU's stdin/stdout, -icount for exact
    instruction counts, no reboot (a reset request ends QEMU instead of starting the firmware again)."""
    return [qemu or qemu_path(), "-M", fw.machine, "-nographic", "-nodefaults", "-nic", "none", "-no-reboot",
            "-semihosting-config", "enable=on,target=native", "-icount", f"shift={ICOUNT_SHIFT}",
            "-kernel", str(fw.elf)]


def _pump(stream: IO[bytes], lines: queue.Queue[bytes | None] | None, tail: deque[str]) -> None:
    """Read ``stream`` line by line until its end (a thread): each line into ``lines``, the last ones
    into ``tail``; None at the end."""
    try:
        while True:
            line = stream.readline(_LINE_LIMIT)
            if not line:
                break
            text = line.decode("ascii", "replace").rstrip("\r\n")
            if lines is None and text.endswith(_QEMU_NO_NETWORK):
                continue  # what -nic none makes QEMU say: no news
            tail.append(text[:160])
            if lines is not None:
                lines.put(line)
    except (OSError, ValueError):
        pass
    finally:
        if lines is not None:
            lines.put(None)
        stream.close()  # the thread owns its pipe: closed here, never under a blocked read


def _kill(proc: subprocess.Popen[bytes]) -> None:
    """Kill the emulator (if it still runs) and close its stdin; the reader threads end at the EOF."""
    if proc.poll() is None:
        proc.kill()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:  # pragma: no cover - a process that survives SIGKILL
            pass
    try:
        if proc.stdin is not None:
            proc.stdin.close()
    except OSError:
        pass


class PilTarget:
    """A controller package running on QEMU's Cortex-M, one step per call (a context manager).

    ``init(params)`` initializes (again: terminate, then initialize) and returns the state;
    ``step(inputs)`` runs one step and returns a :class:`StepResult`; ``close()`` terminates the
    package and waits for the target's exit status 0.  The arrays are flat, in the package's
    ``*_from_array`` / ``*_to_array`` order, of the sizes its ``RPO_<NAME>_N_*`` macros give
    (:attr:`n_params` ...); a float package's inputs and parameters are rounded to float32 (as a C
    cast would), its outputs and state are widened to float64 exactly.

    Instructions per step: QEMU runs with ``-icount shift=10`` (its virtual clock advances 1024 ns per
    guest instruction); the harness reads the 25 MHz CMSDK timer before and after the call of the
    step (25.6 ticks per instruction) and subtracts the cost of the reads and the call, measured with
    an empty function at boot.  Resolution: one instruction, exact (the firmware refuses to start
    unless a loop of known length counts exactly; :meth:`calibrate` runs it again).  It counts
    instructions executed from the step's first instruction to its return, callees included, not
    cycles: QEMU models no pipeline, cache, wait states or FPU latencies.

    Stack bytes per step: the stack below the harness's SP is painted before the call and scanned
    after it; the figure is the SP at the call minus the lowest word changed (the high-water
    mark), an independent check of a static ``-fstack-usage`` bound.

    Every read has a timeout (``timeout`` seconds per reply, ``startup_timeout`` for the READY line);
    a target that dies, hangs, reports an error or prints anything unexpected is killed and a
    :class:`ModelError` names what happened with the last lines it printed.  After that the target
    is closed: every call raises.

    Cost (measured on a shared 2-core x86-64 VM, QEMU 7.2, the toy package of the tests: 5 params,
    6 inputs, 4 outputs, 4 state): 0.18-0.26 ms of wall time per step round trip with the default
    64 KiB stack region (0.15 ms with 4 KiB: the paint and scan; the rest is the pipe, the two
    semihosting calls and the hex text), about 30 ms to start QEMU and boot, 4 ms to close.

    ``command`` replaces the emulator's command line (:func:`qemu_command`), e.g. to run it under
    a debugger or, in the tests, a fake target.
    """

    def __init__(self, firmware: Firmware, *, timeout: float = 10.0, startup_timeout: float = 30.0,
                 command: Sequence[str] | None = None) -> None:
        self.firmware = firmware
        self.timeout = float(timeout)
        self._dtype = np.dtype(">f8" if firmware.real_bytes == 8 else ">f4")
        self._digits = 2 * firmware.real_bytes
        self._out_tail: deque[str] = deque(maxlen=_TAIL)
        self._err_tail: deque[str] = deque(maxlen=_TAIL)
        self._lines: queue.Queue[bytes | None] = queue.Queue()
        self._closed = False
        self._initialized = False
        cmd = list(command) if command is not None else qemu_command(firmware)
        if command is None and not Path(firmware.elf).is_file():
            raise ModelError(f"the PIL firmware {firmware.elf} does not exist: build it with build_firmware")
        try:
            self._proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                          stderr=subprocess.PIPE, bufsize=0)
        except OSError as exc:
            raise ModelError(f"cannot start the PIL target ({cmd[0]}): {exc.strerror or exc}") from None
        self._finalizer = weakref.finalize(self, _kill, self._proc)
        self._threads = [
            threading.Thread(target=_pump, args=(self._proc.stdout, self._lines, self._out_tail), daemon=True),
            threading.Thread(target=_pump, args=(self._proc.stderr, None, self._err_tail), daemon=True),
        ]
        for t in self._threads:
            t.start()
        # the threads read the pipes; only the writes to stdin are this object's
        tokens = self._expect("READY", 8, "at start-up", startup_timeout)
        counts = [self._int(t, "READY") for t in tokens[1:]]
        version, self.n_params, self.n_inputs, self.n_outputs, self.n_state, real_bytes, self.stack_size = counts
        if version != PROTOCOL_VERSION or real_bytes != firmware.real_bytes:
            self._fail(f"the PIL target speaks protocol {version} with {real_bytes}-byte reals, expected "
                       f"{PROTOCOL_VERSION} with {firmware.real_bytes}-byte reals (a stale firmware?)")

    # ------------------------------------------------------------------ public

    def init(self, params: np.ndarray | Sequence[float]) -> np.ndarray:
        """Initialize the package with these parameters; the state after ``_initialize``."""
        self._send("P", self._values(params, self.n_params, "params"))
        tokens = self._expect("INIT", 1 + self.n_state, "after the parameters (P)")
        self._initialized = True
        return self._decode(tokens[1:], "INIT")

    def start(self, inputs: np.ndarray | Sequence[float]) -> np.ndarray:
        """Start the design's states from a measurement (``rpo_<name>_start``); the state after it."""
        if not self._initialized:
            raise ModelError("PilTarget.start before init: send the parameters first")
        self._send("I", self._values(inputs, self.n_inputs, "the start inputs"))
        return self._decode(self._expect("INIT", 1 + self.n_state, "after the start inputs (I)")[1:], "INIT")

    def step(self, inputs: np.ndarray | Sequence[float]) -> StepResult:
        """One step of the package on the target."""
        if not self._initialized and not self._closed:
            raise ModelError("PilTarget.step before init: send the parameters first")
        self._send("S", self._values(inputs, self.n_inputs, "inputs"))
        tokens = self._expect("STEP", 3 + self.n_outputs + self.n_state, "after the inputs (S)")
        values = self._decode(tokens[3:], "STEP")
        return StepResult(values[:self.n_outputs], values[self.n_outputs:], self._int(tokens[1], "STEP"),
                          self._int(tokens[2], "STEP"))

    def calibrate(self, n: int) -> int:
        """The instructions the harness counts for its loop of known length, which executes exactly
        ``2 n + 4`` instructions (1 <= n <= 10**8): a check of the counting method."""
        if not 1 <= int(n) <= 100_000_000:
            raise ModelError(f"calibrate takes n from 1 to 100000000, got {n}")
        self._send_line(f"C {int(n)}\n".encode())
        return self._int(self._expect("CAL", 3, "after C")[1], "CAL")

    def close(self) -> None:
        """Terminate the package and wait for the target's exit status 0 (idempotent).  A target
        that is already dead or closed is only cleaned up."""
        if self._closed:
            return
        try:
            self._send_line(b"Q\n")
            self._expect("BYE", 1, "after Q")
            try:
                rc = self._proc.wait(timeout=self.timeout)
            except subprocess.TimeoutExpired:
                self._fail(f"the PIL target did not exit within {self.timeout:g} s after Q")
            if rc != 0:
                self._fail(f"the PIL target exited with status {rc} ({_EXIT_MEANING.get(rc, 'unknown')}) after Q")
        finally:
            self._shutdown()

    def __enter__(self) -> PilTarget:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if exc_type is None:
            self.close()
        else:
            self._shutdown()

    @property
    def alive(self) -> bool:
        return not self._closed and self._proc.poll() is None

    @property
    def core(self) -> str:
        return self.firmware.core

    def __repr__(self) -> str:
        state = "closed" if self._closed else "running"
        return (f"PilTarget(rpo_{self.firmware.package} on {CORES[self.firmware.core].machine}, "
                f"{self.firmware.real}, {state})")

    # ------------------------------------------------------------------ private

    def _shutdown(self) -> None:
        self._closed = True
        self._finalizer()
        for t in self._threads:
            t.join(timeout=2)

    def _tails(self) -> str:
        out = " | ".join(self._out_tail) or "(nothing)"
        err = " | ".join(self._err_tail)
        return f"last output: {out}" + (f"; stderr: {err}" if err else "")

    def _fail(self, what: str) -> NoReturn:
        """Kill the target, close this object, raise a ModelError naming ``what`` and the last output."""
        self._shutdown()
        raise ModelError(f"{what} ({self.firmware.machine}, rpo_{self.firmware.package}); {self._tails()}")

    def _values(self, values: np.ndarray | Sequence[float], n: int, what: str) -> np.ndarray:
        try:
            a = np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ModelError(f"{what} must be {n} numbers: {exc}") from None
        if a.ndim != 1 or a.size != n:
            raise ModelError(f"{what} must be a 1-D array of {n} values (rpo_{self.firmware.package}), "
                             f"got shape {a.shape}")
        with np.errstate(over="ignore"):  # float32: a value beyond its range becomes inf, as in C
            return a.astype(self._dtype)

    def _send(self, cmd: str, values: np.ndarray) -> None:
        hexa = values.tobytes().hex()
        d = self._digits
        self._send_line((cmd + "".join(" " + hexa[i:i + d] for i in range(0, len(hexa), d)) + "\n").encode())

    def _send_line(self, line: bytes) -> None:
        if self._closed:
            raise ModelError(f"the PIL target of rpo_{self.firmware.package} is closed")
        stdin = self._proc.stdin
        assert stdin is not None
        try:
            stdin.write(line)
            stdin.flush()
        except (BrokenPipeError, OSError, ValueError):
            self._dead("while the host was writing to it")

    def _dead(self, when: str, error: str | None = None) -> NoReturn:
        """The target ended (or said it will, with ``error``): its exit status, its error line (also
        one still queued, when the host found the pipe closed first) and its last lines."""
        try:
            rc: int | None = self._proc.wait(timeout=2)
        except subprocess.TimeoutExpired:
            rc = None
        for t in self._threads:
            t.join(timeout=1)
        while error is None:
            try:
                line = self._lines.get_nowait()
            except queue.Empty:
                break
            if line is not None and line.startswith(b"ERR "):
                error = line[4:].decode("ascii", "replace").rstrip("\r\n")
        if rc is None:
            status = "did not exit"
        elif rc < 0:
            status = f"killed by signal {-rc}"
        else:
            status = f"exit status {rc}: {_EXIT_MEANING.get(rc, 'unknown')}"
        if error is not None:
            self._fail(f"the PIL target reported an error {when}: {error} ({status})")
        self._fail(f"the PIL target ended {when} ({status})")

    def _next_line(self, what: str, timeout: float) -> str:
        deadline = time.monotonic() + timeout
        try:
            line = self._lines.get(timeout=max(0.0, deadline - time.monotonic()))
        except queue.Empty:
            self._fail(f"the PIL target did not answer within {timeout:g} s {what} (hung or too slow)")
        if line is None:
            self._dead(what)
        if not line.endswith(b"\n"):
            self._fail(f"the PIL target printed an unterminated line or one over {_LINE_LIMIT} bytes {what}")
        try:
            return line.decode("ascii").rstrip("\r\n")
        except UnicodeDecodeError:
            self._fail(f"the PIL target printed non-ASCII bytes {what}")

    def _expect(self, word: str, n_tokens: int, what: str, timeout: float | None = None) -> list[str]:
        """The next line, which must be ``word`` and n_tokens - 1 more tokens; else the target fails."""
        if self._closed:
            raise ModelError(f"the PIL target of rpo_{self.firmware.package} is closed")
        text = self._next_line(what, self.timeout if timeout is None else timeout)
        tokens = text.split(" ")
        if tokens[0] == "ERR":
            self._dead(what, text[4:])
        if tokens[0] != word or len(tokens) != n_tokens:
            self._fail(f"the PIL target printed an unexpected line {what}: {text[:120]!r} "
                       f"(expected {word} and {n_tokens - 1} values)")
        return tokens

    def _int(self, token: str, what: str) -> int:
        if not token.isdigit() or not token.isascii():
            self._fail(f"the PIL target printed a bad counter {token[:40]!r} in a {what} line")
        return int(token)

    def _decode(self, tokens: list[str], what: str) -> np.ndarray:
        joined = "".join(tokens)
        if any(len(t) != self._digits for t in tokens) or not _HEX.fullmatch(joined):
            self._fail(f"the PIL target printed a value that is not {self._digits} hex digits in a {what} line")
        raw = bytes.fromhex(joined)
        return np.frombuffer(raw, dtype=self._dtype).astype(np.float64)

    @classmethod
    def from_package(cls, package: Path | str, core: str | None = None, **kwargs: Any) -> PilTarget:
        """Build (or reuse from the cache) the firmware of ``package`` and start it."""
        return cls(build_firmware(package, core), **kwargs)
