"""docs/scenarios.md is derived from the scenario files' comments and must be current."""

from __future__ import annotations

from pathlib import Path

from rpo.runtime.docgen.choices import collect, render, scenario_files

ROOT = Path(__file__).resolve().parents[1]


def test_collect_reads_inline_and_preceding_comments(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('[a]\nx = 1  # paper\n# chosen: because\n# of this\ny = "a#b"\nz = [1, 2]  # chosen: why\n'
                 '[b]\nw = 2\n')
    got = [(c.key, c.value, c.reason) for c in collect(f)]
    assert got == [("a.y", '"a#b"', "chosen: because of this"), ("a.z", "[1, 2]", "chosen: why")]


def test_every_scenario_records_its_choices_and_the_table_is_current():
    paths = scenario_files(ROOT / "scenarios")
    assert paths and all(collect(p) for p in paths)
    assert (ROOT / "docs" / "scenarios.md").read_text() == render(paths), \
        "docs/scenarios.md is stale: run `rpo choices --write docs/scenarios.md`"
