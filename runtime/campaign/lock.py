"""The lock of a campaign folder: one ``rpo mc run`` or ``rpo mc resume`` flies into a folder at a time.

Two commands flying the same folder would both fly its missing runs and append the same cases
twice.  The lock is an advisory ``flock`` on ``DIR/.lock`` (the file holds the pid of the holder,
for the message): the kernel releases it when the holder's last descriptor closes, so a command
that is killed leaves no stale lock to clean up (the file stays, unlocked).  Worker processes
forked by the holder inherit the descriptor: the folder stays locked while they may still write
into it.  The lock is re-entrant within a process (``run_campaign`` inside ``rpo mc run``).

A second command refuses at once, in one line naming the holder: it does not wait, so that a
script never hangs on a folder left in use.
"""

from __future__ import annotations

import errno
import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from rpo.runtime.errors import CampaignError

LOCK = ".lock"
#: folder (resolved) -> [descriptor, depth] of the locks this process holds
_HELD: dict[str, list[int]] = {}


def _holder(path: Path) -> str:
    try:
        pid = path.read_text().strip()
    except OSError:
        return ""
    return f" (pid {pid})" if pid.isdigit() else ""


@contextmanager
def folder_lock(folder: Path) -> Iterator[Path]:
    """Hold the lock of the campaign ``folder`` (an existing folder) for the block; refused with
    :class:`CampaignError` if another process holds it or it cannot be taken (read-only folder, a
    file system without locks), naming the path and what to do."""
    folder = Path(folder)
    key = os.path.realpath(folder)
    if key in _HELD:
        _HELD[key][1] += 1
        try:
            yield folder
        finally:
            _HELD[key][1] -= 1
        return
    path = folder / LOCK
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise CampaignError(f"{path}: cannot take the campaign folder's lock ({exc.strerror}): make {folder} "
                            "writable, then run the command again") from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        os.close(fd)
        if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
            raise CampaignError(f"{folder}: in use by another `rpo mc run` or `rpo mc resume`{_holder(path)}: wait "
                                f"for it to end, then `rpo mc resume {folder}` flies what is left") from None
        raise CampaignError(f"{path}: cannot lock the campaign folder ({exc.strerror}): use a folder on a "
                            "local file system") from None
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
    except OSError:  # the pid is for the message only: a full disk must not stop the lock
        pass
    _HELD[key] = [fd, 1]
    try:
        yield folder
    finally:
        del _HELD[key]
        os.close(fd)  # releases the flock (and the forked workers' copies are gone with them)
