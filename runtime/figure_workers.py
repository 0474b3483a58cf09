"""Figures drawn by worker processes, off the data path.

:func:`start` launches ``python -m rpo.runtime.figure_workers`` processes (plain subprocesses, not
:mod:`multiprocessing`: that would import the caller's main script again in each child, which an
unguarded script or notebook does not survive).  Each worker imports matplotlib and draws a small
figure to load the fonts, then reads jobs from its stdin: one pickled ``(PlotData, folder,
format, figure name)`` per job, answered on its stdout by a pickled ``("ok", [file names])`` or
``("error", text)``.  The workers are started early (the runner does it before simulating), are
reused by later runs of the same process (``rpo report``), and exit when their stdin closes.

:func:`draw` hands the figures to the workers from one thread per worker and returns a handle
whose :meth:`Drawing.wait` gives the files written; a worker that dies or cannot start is
replaced by drawing in this process (which then imports matplotlib).  ``RPO_FIGURE_WORKERS=0``
draws everything in this process.
"""

from __future__ import annotations

import atexit
import os
import pickle
import queue
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: Worker processes (``RPO_FIGURE_WORKERS``; 0: draw in the calling process).
WORKERS = int(os.environ.get("RPO_FIGURE_WORKERS", str(min(2, os.cpu_count() or 1))))

_workers: list[_Worker] = []
_lock = threading.Lock()


class _Worker:
    def __init__(self) -> None:
        self.proc = subprocess.Popen([sys.executable, "-m", "rpo.runtime.figure_workers"], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, close_fds=True)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def call(self, job: tuple) -> tuple[str, Any]:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        pickle.dump(job, self.proc.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        self.proc.stdin.flush()
        return pickle.load(self.proc.stdout)

    def close(self) -> None:
        try:
            if self.proc.stdin is not None:
                self.proc.stdin.close()
            self.proc.wait(timeout=5)
        except (OSError, subprocess.TimeoutExpired):
            self.proc.kill()


def start(n: int | None = None) -> None:
    """Launch the workers if they are not running (non-blocking: they warm up on their own)."""
    n = WORKERS if n is None else n
    with _lock:
        _workers[:] = [w for w in _workers if w.alive()]
        while len(_workers) < n:
            try:
                _workers.append(_Worker())
            except OSError:
                break


def stop() -> None:
    with _lock:
        for w in _workers:
            w.close()
        _workers.clear()


atexit.register(stop)


def _draw_here(job: tuple) -> list[str]:
    from .plots import render
    data, folder, fmt, name = job
    return render(data, folder, fmt, [name])


class Drawing:
    """Figures being drawn; :meth:`wait` returns ``({figure name: [files]}, first error text)``."""

    def __init__(self, jobs: Sequence[tuple]):
        self.results: dict[str, list[str]] = {}
        self.errors: list[str] = []
        self._jobs: queue.Queue[tuple] = queue.Queue()
        for job in jobs:
            self._jobs.put(job)
        start()
        with _lock:
            workers = list(_workers)
        self._threads = [threading.Thread(target=self._serve, args=(w,), daemon=True) for w in workers]
        for t in self._threads:
            t.start()

    def _take(self) -> tuple | None:
        try:
            return self._jobs.get_nowait()
        except queue.Empty:
            return None

    def _serve(self, worker: _Worker | None) -> None:
        while (job := self._take()) is not None:
            name = job[3]
            try:
                if worker is not None:
                    try:
                        status, value = worker.call(job)
                    except (OSError, EOFError, pickle.UnpicklingError):  # the worker died: draw here
                        worker = None
                        status, value = "ok", _draw_here(job)
                else:
                    status, value = "ok", _draw_here(job)
                if status == "ok":
                    self.results[name] = list(value)
                else:
                    self.errors.append(f"{name}: {value}")
            except Exception as exc:  # noqa: BLE001 - the data must survive a plotting bug
                self.errors.append(f"{name}: {type(exc).__name__}: {exc}")

    def cancel(self) -> None:
        """Start no further figure; wait for those being drawn."""
        while self._take() is not None:
            pass
        for t in self._threads:
            t.join(timeout=60)

    def wait(self) -> tuple[dict[str, list[str]], str]:
        for t in self._threads:
            t.join()
        self._serve(None)  # what no worker took (no workers, or all died)
        return self.results, (self.errors[0] if self.errors else "")


def draw(jobs: Sequence[tuple]) -> Drawing:
    """Start drawing ``jobs`` (``(PlotData, folder, format, figure name)``) in the workers."""
    return Drawing(jobs)


def _main() -> int:  # pragma: no cover - runs in the worker process
    import traceback
    import warnings

    warnings.simplefilter("ignore")
    from . import plots
    fig = plots.Figure(figsize=(2, 1))  # fonts and the Agg canvas loaded before the first job
    fig.subplots().plot([0, 1], [0, 1], label="x")
    fig.canvas.draw()
    stdin = sys.stdin.buffer
    stdout = os.fdopen(os.dup(1), "wb")  # the protocol's own copy; a stray print goes to stderr (null)
    os.dup2(2, 1)
    while True:
        try:
            job = pickle.load(stdin)
        except EOFError:
            return 0
        try:
            data, folder, fmt, name = job
            reply: tuple[str, Any] = ("ok", plots.render(data, Path(folder), fmt, [name]))
        except Exception as exc:  # noqa: BLE001 - reported to the parent
            reply = ("error", f"{type(exc).__name__}: {exc} | {traceback.format_exc(limit=3)!r}")
        pickle.dump(reply, stdout, protocol=pickle.HIGHEST_PROTOCOL)
        stdout.flush()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(_main())
