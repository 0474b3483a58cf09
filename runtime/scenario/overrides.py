"""``--set KEY=VALUE``: one value of a scenario changed from the command line, then validated with the
rest of the file exactly as if it had been written there.

The value is read as a TOML value (``--set chaser.mass=90.0``, ``--set relative.position=[60, 0, 25]``,
``--set environment.j2=false``); anything that is not one is taken as a string
(``--set simulation.controller=c004``).  Nothing is evaluated: a TOML parser reads the value, never
``eval`` or SymPy.  The copy of the scenario a run writes starts with the overrides as comments.
"""

from __future__ import annotations

import copy
import re
import tomllib
from collections.abc import Iterable, Mapping
from typing import Any

from rpo.runtime.errors import ScenarioError
from rpo.runtime.scenario.loader import ScenarioSource

_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*(\.[A-Za-z_][A-Za-z0-9_-]*)*$")


def parse_sets(items: Iterable[str]) -> dict[str, Any]:
    """``["a.b=1", ...]`` -> ``{"a.b": 1, ...}`` (later items win); a malformed item is a ScenarioError."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not _KEY.match(key):
            raise ScenarioError(f"--set {item!r}: expected KEY=VALUE with KEY a dotted scenario key "
                                "(e.g. chaser.mass=90.0; the keys: docs/scenarios.md)")
        text = text.strip()
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text  # a bare word: a string
        out[key] = value
    return out


def apply_sets(data: Mapping[str, Any], sets: Mapping[str, Any]) -> dict[str, Any]:
    """A copy of the scenario table ``data`` with each dotted key of ``sets`` set (tables made as needed)."""
    out = copy.deepcopy(dict(data))
    for key, value in sets.items():
        node = out
        parts = key.split(".")
        for i, part in enumerate(parts[:-1]):
            nxt = node.setdefault(part, {})
            if not isinstance(nxt, dict):
                raise ScenarioError(f"--set {key}: {'.'.join(parts[:i + 1])} is a value, not a table")
            node = nxt
        if isinstance(node.get(parts[-1]), dict):
            raise ScenarioError(f"--set {key}: {key} is a table; set one of its keys ({key}.<name>=...)")
        node[parts[-1]] = value
    return out


def with_sets(src: ScenarioSource, sets: Mapping[str, Any]) -> ScenarioSource:
    """The scenario ``src`` with ``sets`` applied; its text (the copy a run writes) names them first."""
    if not sets:
        return src
    lines = [f"# {k} = {v!r}  (rpo --set, applied over the table below)" for k, v in sets.items()]
    return ScenarioSource(src.source, "\n".join(lines) + "\n" + src.text, apply_sets(src.data, sets), src.bases)
