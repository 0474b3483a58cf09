"""Options shared by the commands that read a scenario."""

from __future__ import annotations

from typing import Any

import click

#: ``--set KEY=VALUE`` (runtime/scenario/overrides.py), on every command that reads a scenario
_SET = click.option("--set", "sets", multiple=True, metavar="KEY=VALUE",
                    help="Change one value of the scenario (repeatable), validated as if written in the file: "
                         "--set chaser.mass=90.0 --set relative.position=[60,0,25].")


def _source(scenario: str, sets: tuple[str, ...]) -> Any:
    """SCENARIO as a path, or (with --set) as read and changed: runtime/scenario/overrides.py."""
    if not sets:
        return scenario
    from rpo.runtime.scenario import read_scenario
    from rpo.runtime.scenario.overrides import parse_sets, with_sets
    return with_sets(read_scenario(scenario), parse_sets(sets))
