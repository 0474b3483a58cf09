"""The campaign files of scenarios/campaigns/: each loads, disperses enough and draws valid runs.

``load_campaign`` already validates the base scenario, every dispersion and the median draw; on
top of that the first 8 cases' scenarios (their actual draws) must validate as ``rpo run`` would,
so a dispersion too wide for a parameter's range shows here and not as invalid runs of a campaign.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from rpo.runtime.campaign import load_campaign
from rpo.runtime.scenario import validate_scenario

CAMPAIGNS = Path(__file__).resolve().parent.parent / "scenarios" / "campaigns"
FILES = sorted(CAMPAIGNS.glob("*.toml"))
#: One campaign per paper scenario (docs/campaign_scenarios.md).
REQUIRED = ("000_I_mc", "000_II_mc", "000_III_mc", "001_mc", "002_mc", "004_mc")


def test_every_paper_scenario_has_a_campaign():
    stems = {p.stem for p in FILES}
    assert set(REQUIRED) <= stems, f"missing: {sorted(set(REQUIRED) - stems)}"


def test_campaign_docs_list_every_file():
    doc = (CAMPAIGNS.parent.parent / "docs" / "campaign_scenarios.md").read_text()
    for p in FILES:
        assert f"scenarios/campaigns/{p.name}" in doc, f"{p.name} is not in docs/campaign_scenarios.md"


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_campaign_file_loads_and_draws_valid_cases(path, model):
    camp = load_campaign(path, model.manifest)
    assert camp.runs >= 1
    assert len(camp.dispersions) >= 3, f"{path.name}: only {len(camp.dispersions)} dispersions"
    assert camp.settings.description, f"{path.name}: campaign.description is empty"
    for case in range(min(8, camp.runs)):
        validate_scenario(camp.case_data(case), f"{path.name} case {case}", model.manifest)


def test_000_III_disperses_a_fault(model):
    camp = load_campaign(CAMPAIGNS / "000_III_mc.toml", model.manifest)
    keys = {d.key for d in camp.dispersions}
    assert {"faults.0.time", "faults.0.unit"} <= keys
    assert camp.runs == 1000
    units = {camp.draws(i)["faults.0.unit"] for i in range(32)}
    assert units <= {1, 2, 3, 4} and len(units) > 1
