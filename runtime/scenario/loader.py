"""Reading scenario files: the one TOML reader of rpo, with ``extends`` resolved.

A variant names its base file (relative to itself) with ``extends = "<base>.toml"`` and gives only
what differs: tables are merged key by key, any other value replaces the base's.  Bases may extend
further bases (at most :data:`MAX_EXTENDS_DEPTH` files); a cycle is an error.  Tables listed in
:data:`OWN_TABLES` belong to the file that writes them and are not inherited (a variant's
``[reproduction]`` table declares the variant's own runs, not its base's again).

Every file read (the scenario and each base) must be a regular file of at most
:data:`MAX_SCENARIO_BYTES`, in UTF-8: it is ``stat``-ed before it is opened, so a FIFO, a device
(``/dev/zero``), a socket or a folder is refused with one line instead of hanging or filling the
memory, and it is read through a non-blocking descriptor that is checked again after opening.
"""

from __future__ import annotations

import copy
import os
import stat
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rpo.runtime.errors import RpoError, ScenarioError
from rpo.runtime.scenario.messages import show

#: Top-level tables that a variant does not inherit from its base.
OWN_TABLES = ("reproduction",)
#: Largest scenario (or base) file read [bytes]: 1 MiB, 50 times the largest paper scenario; a
#: longer file is not a scenario typed by hand, and reading it whole must not exhaust memory.
MAX_SCENARIO_BYTES = 1 << 20
#: Most files an ``extends`` chain may name (a cycle is refused separately).
MAX_EXTENDS_DEPTH = 16


@dataclass(frozen=True)
class ScenarioSource:
    """A scenario file as read: ``source`` (the path as given, for messages), its own ``text``,
    the ``data`` table with ``extends`` resolved and ``bases``, the files it extends (nearest first)."""

    source: str
    text: str
    data: dict[str, Any]
    bases: tuple[Path, ...] = ()


def parse_toml(text: str, source: str, error: type[RpoError] = ScenarioError) -> dict[str, Any]:
    """Parse TOML text; a syntax error is a one-line ``error`` naming ``source``."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{source}: invalid TOML: {' '.join(str(exc).split())}") from None


def _not_regular(mode: int) -> str | None:
    """What a file that is not a regular file is (None for a regular file)."""
    if stat.S_ISREG(mode):
        return None
    for test, kind in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return kind
    return "not a regular file"


def read_text(path: Path, what: str = "the scenario", error: type[RpoError] = ScenarioError,
              max_bytes: int = MAX_SCENARIO_BYTES) -> str:
    """A UTF-8 regular file's text, at most ``max_bytes``; anything else is a one-line ``error``
    (missing, unreadable, a folder, FIFO, device or socket, too large, not UTF-8)."""
    path = Path(path)

    def fail(reason: str) -> RpoError:
        return error(f"{path}: cannot read {what}: {reason}")

    def refuse_kind(mode: int) -> None:
        kind = _not_regular(mode)
        if kind is not None:
            raise fail(f"it is {kind}, not a regular file")

    try:
        st = os.stat(path)  # before any open: opening a FIFO blocks until a writer comes
        refuse_kind(st.st_mode)
        if st.st_size > max_bytes:
            raise fail(f"{st.st_size} bytes, more than the limit of {max_bytes} bytes ({max_bytes / 2**20:g} MiB)")
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
        try:
            refuse_kind(os.fstat(fd).st_mode)  # the file may have been swapped since the stat
            chunks, size = [], 0
            while size <= max_bytes:
                chunk = os.read(fd, max_bytes + 1 - size)
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
        finally:
            os.close(fd)
    except OSError as exc:
        raise fail(exc.strerror or str(exc)) from None
    if size > max_bytes:
        raise fail(f"more than the limit of {max_bytes} bytes ({max_bytes / 2**20:g} MiB)")
    data = b"".join(chunks)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise fail(f"not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start})") from None


def read_scenario(path: str | Path) -> ScenarioSource:
    """Text and table of a scenario file, with ``extends`` resolved (not validated)."""
    path = Path(path)
    text, data, bases = _read(path, ())
    return ScenarioSource(str(path), text, data, bases)


def _read(path: Path, chain: tuple[Path, ...], via: str | None = None) -> tuple[str, dict[str, Any], tuple[Path, ...]]:
    src = str(path)
    text = read_text(path, "the scenario" if via is None else f"the base scenario (extends in {via})")
    data = parse_toml(text, src)
    base_name = data.pop("extends", None)
    if base_name is None:
        return text, data, ()
    if not isinstance(base_name, str) or not base_name.strip() or "\0" in base_name:
        raise ScenarioError(f"{src}: extends = {show(base_name)}: must be the file name of a base scenario")
    try:
        base_path = (path.parent / base_name).resolve()
    except (OSError, RuntimeError) as exc:  # a symlink loop
        raise ScenarioError(f"{src}: extends = {show(base_name)}: cannot resolve the path: {exc}") from None
    if base_path in chain or base_path == path.resolve():
        raise ScenarioError(f"{src}: extends = {show(base_name)}: the scenarios extend each other in a cycle")
    if len(chain) + 1 >= MAX_EXTENDS_DEPTH:
        raise ScenarioError(f"{src}: extends = {show(base_name)}: more than {MAX_EXTENDS_DEPTH} files in the "
                            "extends chain")
    _base_text, base, further = _read(base_path, (*chain, path.resolve()), via=src)
    for table in OWN_TABLES:
        base.pop(table, None)
    return text, merge(base, data), (base_path, *further)


def merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``base`` with ``over`` merged in: tables key by key, other values replaced."""
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else copy.deepcopy(v)
    return out
