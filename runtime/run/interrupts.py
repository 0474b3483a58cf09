"""SIGINT and SIGTERM as exceptions a run can act on: stop and keep what was computed, or leave
nothing at all; never swallowed.

:func:`handling` (the runner, and ``rpo`` from the start of its ``main``) installs one handler for
both signals in the main thread.  By default a signal raises :class:`Interrupted` where the main
thread is (a subclass of :class:`KeyboardInterrupt`, so every existing ``except KeyboardInterrupt``
sees it; ``exit_code`` 130 for SIGINT, 143 for SIGTERM, 128 + the signal number as shells report it).
Two scopes change that:

* :func:`deferred`: a signal is held until the block ends and raised then (the creation and removal
  of a temporary folder, the final move of a results folder: they are never cut in half);
* :func:`stop_request`: the first signal only sets :attr:`StopRequest.signum` (the simulation
  looks at it after each chunk and ends early with what it has); a second one raises.

Signals arriving in another thread are handled by Python in the main thread, so the scopes are
process-wide.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from types import FrameType

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """A run was interrupted by ``signum``; ``exit_code`` is what the process exits with."""

    def __init__(self, signum: int, message: str | None = None):
        self.signum = int(signum)
        self.exit_code = 128 + self.signum
        super().__init__(message or f"interrupted by {signal_name(signum)}")


def signal_name(signum: int) -> str:
    """``SIGINT``, ``SIGTERM``, ... (the number for an unknown one)."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return str(signum)


@dataclass
class StopRequest:
    """The first signal received in a :func:`stop_request` scope (None: none yet)."""

    signum: int | None = None

    def requested(self) -> bool:
        return self.signum is not None


_defer_depth = 0
_pending: list[int] = []
_stop: StopRequest | None = None


def _handler(signum: int, frame: FrameType | None) -> None:
    if _defer_depth > 0:
        if not _pending:
            _pending.append(signum)
        return
    if _stop is not None and _stop.signum is None:
        _stop.signum = signum  # the simulation ends at its next chunk; the folder is written marked
        return
    raise Interrupted(signum)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextmanager
def handling() -> Iterator[None]:
    """Install the handler for SIGINT and SIGTERM for the block (main thread only; elsewhere, and
    when it is installed already, nothing changes)."""
    if not _main_thread() or signal.getsignal(signal.SIGINT) is _handler:
        yield
        return
    before = {s: signal.getsignal(s) for s in SIGNALS}
    for s in SIGNALS:
        signal.signal(s, _handler)
    try:
        yield
    finally:
        for s, h in before.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)


def install() -> None:
    """Install the handler for the rest of the process (the ``rpo`` command: from its first line)."""
    if _main_thread():
        for s in SIGNALS:
            signal.signal(s, _handler)


@contextmanager
def deferred() -> Iterator[None]:
    """Hold SIGINT/SIGTERM for the block, then raise :class:`Interrupted` for one that came.

    Installs the handler for the block when it is not installed (a library caller), so that the
    default SIGINT handler cannot cut the block either."""
    global _defer_depth
    with handling():
        _defer_depth += 1
        try:
            yield
        finally:
            _defer_depth -= 1
            if _defer_depth == 0 and _pending:
                signum = _pending.pop()
                _pending.clear()
                raise Interrupted(signum)


@contextmanager
def stop_request() -> Iterator[StopRequest]:
    """A scope in which the first signal asks the work to stop (:meth:`StopRequest.requested`)
    instead of raising; a second one raises :class:`Interrupted`."""
    global _stop
    req = StopRequest()
    with handling():
        outer, _stop = _stop, req
        try:
            yield req
        finally:
            _stop = outer
