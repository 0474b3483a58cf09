"""The papers' data, read from ``scenarios/*.toml`` (one place for each paper's gains and scenario data).

Claims that check a paper's published gains, bounds or initial state read them here instead of typing
them again, so a scenario file and the claims about it cannot drift apart.  The files are found from the
repository root (two levels above this package), ``extends = "<base>.toml"`` is followed as
``runtime/scenario.py`` does it (tables merged key by key, other values replaced), and nothing is
validated here: the scenario loader of the runtime owns that.
"""

from __future__ import annotations

import copy
import functools
import tomllib
from pathlib import Path

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else copy.deepcopy(v)
    return out


@functools.cache
def _read(path: Path, chain: tuple[Path, ...] = ()) -> dict:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    base = data.pop("extends", None)
    if base is None:
        return data
    base_path = (path.parent / base).resolve()
    if base_path in chain or base_path == path.resolve():
        raise ValueError(f"{path}: extends = {base!r}: the scenarios extend each other in a cycle")
    return _merge(_read(base_path, (*chain, path.resolve())), data)


def scenario(name: str) -> dict:
    """The table of ``scenarios/<name>.toml`` (``.toml`` optional), with ``extends`` resolved (a copy)."""
    file = name if name.endswith(".toml") else f"{name}.toml"
    return copy.deepcopy(_read((SCENARIOS / file).resolve()))


def controller_gains(name: str, controller: str) -> dict:
    """The ``[controller.<controller>]`` table of a scenario."""
    return scenario(name)["controller"][controller]
