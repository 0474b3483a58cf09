"""Reading scenario files: the one TOML reader of rpo, with ``extends`` resolved.

A variant names its base file (relative to itself) with ``extends = "<base>.toml"`` and gives only
what differs: tables are merged key by key, any other value replaces the base's.  Bases may extend
further bases; a cycle is an error.  Tables listed in :data:`OWN_TABLES` belong to the file that
writes them and are not inherited (a variant's ``[reproduction]`` table declares the variant's
own runs, not its base's again).
"""

from __future__ import annotations

import copy
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import RpoError, ScenarioError

#: Top-level tables that a variant does not inherit from its base.
OWN_TABLES = ("reproduction",)


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


def read_text(path: Path, what: str = "the scenario", error: type[RpoError] = ScenarioError) -> str:
    """A UTF-8 file's text; a missing or unreadable file is a one-line ``error``."""
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise error(f"{path}: cannot read {what}: {reason}") from None


def read_scenario(path: str | Path) -> ScenarioSource:
    """Text and table of a scenario file, with ``extends`` resolved (not validated)."""
    path = Path(path)
    text, data, bases = _read(path, ())
    return ScenarioSource(str(path), text, data, bases)


def _read(path: Path, chain: tuple[Path, ...]) -> tuple[str, dict[str, Any], tuple[Path, ...]]:
    src = str(path)
    text = read_text(path)
    data = parse_toml(text, src)
    base_name = data.pop("extends", None)
    if base_name is None:
        return text, data, ()
    if not isinstance(base_name, str):
        raise ScenarioError(f"{src}: extends = {base_name!r}: must be the file name of a base scenario")
    base_path = (path.parent / base_name).resolve()
    if base_path in chain or base_path == path.resolve():
        raise ScenarioError(f"{src}: extends = {base_name!r}: the scenarios extend each other in a cycle")
    _base_text, base, further = _read(base_path, (*chain, path.resolve()))
    for table in OWN_TABLES:
        base.pop(table, None)
    return text, merge(base, data), (base_path, *further)


def merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``base`` with ``over`` merged in: tables key by key, other values replaced."""
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else copy.deepcopy(v)
    return out
