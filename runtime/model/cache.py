"""The compiled-object cache: content keys, file locks, sha256 sealing of cached libraries, atomic builds
(:func:`ensure_built`)."""

from __future__ import annotations

import hashlib
import json
import os
import platform
import sys
import tempfile
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from rpo.runtime.errors import ModelError
from rpo.runtime.model.toolchain import CFLAGS, headers_digest, scalar_cflags

#: Bump when the loop driver's calling convention or the library layout changes.
RUNTIME_ABI = 3


def cache_dir() -> Path:
    """Per-user build cache: $RPO_CACHE_DIR, else $XDG_CACHE_HOME/rpo, else ~/.cache/rpo."""
    if os.environ.get("RPO_CACHE_DIR"):
        return Path(os.environ["RPO_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "rpo"


def object_key(source: bytes, cc_id: str, flags: Iterable[str] = CFLAGS) -> str:
    """Cache key of one object file: the C source's bytes, the headers it includes, the compiler
    identity and the flags."""
    h = hashlib.sha256(source)
    h.update(json.dumps({"cc": cc_id, "flags": list(flags), "abi": RUNTIME_ABI, "platform": sys.platform,
                         "machine": platform.machine(), "headers": headers_digest()}, sort_keys=True).encode())
    return h.hexdigest()


def object_path(cache: Path, name: str, source: bytes, cc_id: str) -> Path:
    """The cached scalar object of the C file ``name`` (key: :func:`object_key` with its flags)."""
    return cache / "obj" / f"{Path(name).stem}-{object_key(source, cc_id, scalar_cflags(name))[:24]}.o"


@contextmanager
def file_lock(path: Path) -> Iterator[None]:
    """An exclusive advisory lock on ``path`` (created if missing) for the duration of the block."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - non-POSIX: rely on the atomic renames alone
        yield
        return
    with open(path, "a+") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def digest_path(lib: Path) -> Path:
    """The side file of a cached library: its name and the sha256 of its bytes (JSON)."""
    return lib.with_name(f".{lib.name}.sha256")


#: path -> (device, inode, size, mtime) of each library whose bytes matched its side file in this
#: process: a file is hashed once, and again only if it was replaced or touched since
_INTACT: dict[str, tuple[int, int, int, int]] = {}


def sha256_file(path: Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def library_intact(lib: Path) -> bool:
    """True if ``lib`` exists and its bytes and name match its side file (:func:`digest_path`).

    False for a missing side file (a library of an older rpo, or one that was not sealed), a
    truncated or corrupt file, and a library copied from another name (the side file names the
    library it was written for).  Hashes a file once per process, unless its identity changes.
    """
    try:
        st = lib.stat()
        rec = json.loads(digest_path(lib).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    ident = (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)
    if _INTACT.get(str(lib)) == ident:
        return True
    if not isinstance(rec, dict) or rec.get("name") != lib.name or rec.get("size") != st.st_size:
        return False
    try:
        ok = rec.get("sha256") == sha256_file(lib)
    except OSError:
        return False
    if ok:
        _INTACT[str(lib)] = ident
    return ok


def seal(tmp: Path, lib: Path) -> None:
    """Write ``lib``'s side file for the finished ``tmp``, then rename ``tmp`` to ``lib`` (both atomic).

    The side file goes first: a library under its final name always has the record it is checked
    against (a crash in between leaves a side file without a library, which the next build rewrites).
    """
    rec = {"name": lib.name, "size": tmp.stat().st_size, "sha256": sha256_file(tmp)}
    fd, side_tmp = tempfile.mkstemp(prefix=f".{lib.name}.", suffix=".sha256.part", dir=lib.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(rec, fh)
        os.replace(side_tmp, digest_path(lib))
    finally:
        if os.path.exists(side_tmp):
            os.unlink(side_tmp)
    os.replace(tmp, lib)
    st = lib.stat()
    _INTACT[str(lib)] = (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def ensure_built(lib: Path, build: Callable[[Path], None], what: str,
                 log: Callable[[str], None] | None = None) -> bool:
    """Make sure the cached library ``lib`` exists and is intact; return True if it was (re)built.

    ``build(tmp)`` writes the library into the temporary file ``tmp`` (in the cache folder).  An
    existing ``lib`` that fails :func:`library_intact` (truncated, corrupt, swapped, or unsealed) is
    removed and rebuilt under ``lib``'s lock; one that cannot be replaced is a :class:`ModelError`
    naming it (never loaded).
    """
    if library_intact(lib):
        return False
    with file_lock(lib.with_name(f".{lib.name}.lock")):
        if library_intact(lib):  # another process built it while we waited
            return False
        if lib.exists():
            if log:
                why = ("does not match its recorded name and sha256 (truncated, corrupt or replaced)"
                       if digest_path(lib).exists() else "has no recorded sha256 (an older rpo built it)")
                log(f"{lib} {why}: rebuilding {what}")
            try:
                lib.unlink()
            except OSError as exc:
                raise ModelError(f"cached {what} {lib} is corrupt and cannot be removed ({exc.strerror}): "
                                 "delete it or set RPO_CACHE_DIR to a writable folder") from None
        fd, tmp = tempfile.mkstemp(prefix=f".{lib.stem}.", suffix=f".tmp{lib.suffix}", dir=lib.parent)
        os.close(fd)
        try:
            build(Path(tmp))
            seal(Path(tmp), lib)
        except OSError as exc:
            raise ModelError(f"cannot write {what} into the cache {lib.parent} ({exc.strerror or exc}): set "
                             "RPO_CACHE_DIR to a writable folder") from None
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return True
