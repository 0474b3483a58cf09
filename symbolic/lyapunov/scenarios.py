"""The papers' data, read from the shipped ``scenarios/*.toml`` (one place for each paper's gains and scenario data).

Claims that check a paper's published gains, bounds or initial state read them here instead of typing
them again, so a scenario file and the claims about it cannot drift apart.  The files are read by rpo's
one scenario reader (``rpo.runtime.scenario.paper_data``: ``extends`` resolved, nothing validated), so
the claims see exactly the tables a run sees.  The checker imports the runtime's TOML reader, never the
other way round: the runtime still imports nothing from ``rpo.symbolic``.
"""

from __future__ import annotations

import copy
import functools


@functools.cache
def _read(file: str) -> dict:
    from rpo.runtime.scenario import paper_data

    return paper_data(file.removesuffix(".toml"))  # the shipped file (rpo.scenarios, in every install mode)


def scenario(name: str) -> dict:
    """The table of ``scenarios/<name>.toml`` (``.toml`` optional), with ``extends`` resolved (a copy)."""
    return copy.deepcopy(_read(name if name.endswith(".toml") else f"{name}.toml"))


def controller_gains(name: str, controller: str) -> dict:
    """The ``[controller.<controller>]`` table of a scenario."""
    return scenario(name)["controller"][controller]
