"""Small campaigns shared by the campaign tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.campaign.spec import CampaignSpec, parse_campaign

HERE = Path(__file__).resolve().parent
POLICIES = HERE / "policies.py"
WAREHOUSE = HERE.parents[1] / "examples" / "locations" / "warehouse"


def campaign_yaml(cards: list[str], policies: list[str], seeds: int, timeout: float = 40.0,
                  wall_timeout: float = 20.0) -> str:
    listed = "\n".join(f"  - {p}" for p in policies)
    return (f"name: test\nscenarios:\n  - cards: [{', '.join(cards)}]\n    locations: [{WAREHOUSE}]\n"
            f"policies:\n{listed}\nseeds: {seeds}\n"
            f"simulation: {{timeout: {timeout}, wall_timeout: {wall_timeout}}}\n")


@pytest.fixture
def small_spec() -> CampaignSpec:
    """2 scenarios x 2 policies (the default scripted robot and the bad `straight` one) x 2 seeds. Scenarios where
    the rude robot meets people who cannot see it coming in time (a blind corner, an intersection between racks):
    people step round a robot they see, so in parallel traffic (they overtake the slow robot and keep off it)
    the straight robot touched nobody and its rudeness did not show."""
    text = campaign_yaml(["blind-corner", "intersection-no-gesture"], ["scripted", "{name: bad, robot: straight}"], 2)
    return parse_campaign(text)
