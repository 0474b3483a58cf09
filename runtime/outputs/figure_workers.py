"""Figures drawn by worker processes, off the data path.

:func:`start` launches ``python -m rpo.runtime.outputs.figure_workers`` processes (plain subprocesses, not
:mod:`multiprocessing`: that would import the caller's main script again in each child, which an
unguarded script or notebook does not survive).  The first worker imports matplotlib and draws a small
figure to load the fonts, then forks the others (a warm copy costs nothing; it is a clean process
with no threads, so forking is safe there, unlike in the caller).  Each reads jobs from its pipe:
one pickled ``(PlotData, folder, format, figure name)`` per job, answered by a pickled
``("ok", [file names])`` or ``("error", text)``.  The workers are started early (``rpo run`` does
it first thing, the runner again before simulating), are reused by later runs of the same process
(``rpo report``), and exit when their pipe closes (or are killed at exit, idle).

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
import signal
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
    """One worker's pipes: ``send`` carries jobs to it, ``recv`` its answers.  ``proc`` is the
    process for the first worker; the others are forked by it once it is warm (so matplotlib is
    imported once for all of them) and have no process object here."""

    def __init__(self, send: Any, recv: Any, proc: subprocess.Popen | None = None):
        self.send, self.recv, self.proc = send, recv, proc
        self.broken = False

    def alive(self) -> bool:
        return not self.broken and (self.proc is None or self.proc.poll() is None)

    def call(self, job: tuple) -> tuple[str, Any]:
        try:
            pickle.dump(job, self.send, protocol=pickle.HIGHEST_PROTOCOL)
            self.send.flush()
            return pickle.load(self.recv)
        except BaseException:
            self.broken = True
            raise

    def close(self) -> None:
        if self.proc is not None:
            # idle, or retired by Drawing.abandon (its folder is gone): nothing is lost.  Killed
            # first, so that a thread still reading its answer sees EOF at once (closing a pipe
            # that another thread reads waits for that read)
            self.proc.kill()
        for f in (self.send, self.recv):
            try:
                f.close()
            except OSError:
                pass
        if self.proc is not None:
            self.proc.wait()


def _launch(n: int) -> list[_Worker]:
    """The first worker as a subprocess, with pipes for the ``n - 1`` it forks when warm."""
    pairs = []  # (ours: send, recv), (its: jobs_r, results_w)
    for _ in range(n - 1):
        jobs_r, jobs_w = os.pipe()
        res_r, res_w = os.pipe()
        pairs.append(((jobs_w, res_r), (jobs_r, res_w)))
    theirs = [fd for _, t in pairs for fd in t]
    try:
        proc = subprocess.Popen([sys.executable, "-m", "rpo.runtime.outputs.figure_workers",
                                 *(f"{r},{w}" for _, (r, w) in pairs)],
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                pass_fds=theirs)
    finally:
        for fd in theirs:
            os.close(fd)
    assert proc.stdin is not None and proc.stdout is not None
    workers = [_Worker(proc.stdin, proc.stdout, proc)]
    workers += [_Worker(os.fdopen(w, "wb"), os.fdopen(r, "rb")) for (w, r), _ in pairs]
    return workers


def start(n: int | None = None) -> None:
    """Launch the workers if they are not running (non-blocking: they warm up on their own)."""
    n = WORKERS if n is None else n
    with _lock:
        if n <= 0 or (_workers and all(w.alive() for w in _workers)):
            return
        for w in _workers:
            w.close()
        _workers.clear()
        try:
            _workers.extend(_launch(n))
        except OSError:
            pass


def stop() -> None:
    with _lock:
        for w in _workers:
            w.close()
        _workers.clear()


atexit.register(stop)


def _draw_here(job: tuple) -> list[str]:
    from rpo.runtime.outputs.plots import render
    data, folder, fmt, name = job
    return render(data, folder, fmt, [name])


class Drawing:
    """Figures being drawn; :meth:`wait` returns ``({figure name: [files]}, first error text)``."""

    def __init__(self, jobs: Sequence[tuple]):
        self.results: dict[str, list[str]] = {}
        self.errors: list[str] = []
        self._cancelled = False
        self._jobs: queue.Queue[tuple] = queue.Queue()
        for job in jobs:
            self._jobs.put(job)
        start()
        with _lock:
            workers = list(_workers)
        self._workers = workers
        self._threads = [threading.Thread(target=self._serve, args=(w,), daemon=True) for w in workers]
        for t in self._threads:
            t.start()

    def _take(self) -> tuple | None:
        try:
            return self._jobs.get_nowait()
        except queue.Empty:
            return None

    def _serve(self, worker: _Worker | None) -> None:
        if threading.current_thread() is not threading.main_thread():
            # SIGINT/SIGTERM go to the main thread, which is waiting for us: delivered to this
            # thread, they would wake nothing until the figures were done
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        while (job := self._take()) is not None:
            name = job[3]
            try:
                if worker is not None:
                    try:
                        status, value = worker.call(job)
                    except (OSError, EOFError, ValueError, pickle.UnpicklingError):  # it died: draw here
                        worker = None
                        if self._cancelled:
                            return
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
        self._cancelled = True
        while self._take() is not None:
            pass
        for t in self._threads:
            t.join(timeout=60)

    def abandon(self) -> None:
        """Start no further figure and do not wait for those being drawn (the caller removes their
        folder): the workers drawing them are retired, so that a later drawing starts fresh ones
        and never reads an answer meant for this one."""
        self._cancelled = True
        while self._take() is not None:
            pass
        for w in self._workers:
            w.broken = True

    def wait(self) -> tuple[dict[str, list[str]], str]:
        for t in self._threads:
            t.join()
        self._serve(None)  # what no worker took (no workers, or all died)
        return self.results, (self.errors[0] if self.errors else "")


def draw(jobs: Sequence[tuple]) -> Drawing:
    """Start drawing ``jobs`` (``(PlotData, folder, format, figure name)``) in the workers."""
    return Drawing(jobs)


def _serve(jobs: Any, results: Any) -> int:  # pragma: no cover - runs in a worker process
    import traceback

    from rpo.runtime.outputs import plots
    while True:
        try:
            job = pickle.load(jobs)
        except EOFError:
            return 0
        try:
            data, folder, fmt, name = job
            reply: tuple[str, Any] = ("ok", plots.render(data, Path(folder), fmt, [name]))
        except Exception as exc:  # noqa: BLE001 - reported to the parent
            reply = ("error", f"{type(exc).__name__}: {exc} | {traceback.format_exc(limit=3)!r}")
        pickle.dump(reply, results, protocol=pickle.HIGHEST_PROTOCOL)
        results.flush()


def _main(argv: list[str]) -> int:  # pragma: no cover - runs in the worker process
    import warnings

    # Ctrl-C reaches the whole process group: the parent decides (it stops drawing and removes the
    # folder, or waits for the figures); a worker dying of it mid-figure would only make the parent
    # draw that figure itself.  The workers exit when their pipes close.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warnings.simplefilter("ignore")
    from rpo.runtime.outputs import plots
    fig = plots.Figure(figsize=(2, 1))  # fonts and the Agg canvas loaded before the first job
    fig.subplots().plot([0, 1], [0, 1], label="x")
    fig.legend()
    fig.canvas.draw()
    pairs = [tuple(int(x) for x in a.split(",")) for a in argv]
    for i, (jobs_r, res_w) in enumerate(pairs):
        if os.fork() == 0:  # a warm copy of this process for each further worker
            for j, (r, w) in enumerate(pairs):
                if j != i:
                    os.close(r)
                    os.close(w)
            null = os.open(os.devnull, os.O_RDWR)
            os.dup2(null, 0)
            os.dup2(null, 1)
            os._exit(_serve(os.fdopen(jobs_r, "rb"), os.fdopen(res_w, "wb")))
    for r, w in pairs:
        os.close(r)
        os.close(w)
    results = os.fdopen(os.dup(1), "wb")  # the protocol's own copy; a stray print goes to stderr (null)
    os.dup2(2, 1)
    return _serve(sys.stdin.buffer, results)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(_main(sys.argv[1:]))
