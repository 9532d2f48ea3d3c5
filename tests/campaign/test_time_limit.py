"""A campaign gives each scenario the time its route needs: by default every episode gets the limit `simulate`
gives the default robot on that scenario (sim/engine/budget.py), the same for every policy. A fixed 60 s cut
the robots off on long routes (the warehouse's crowd-navigation is ~29 m: 48 s at 0.6 m/s before anyone is
met), and those cut-offs were counted as the planners' misses."""

from __future__ import annotations

import pytest

from socnavgen.campaign.runner import run_campaign, settings_of
from socnavgen.campaign.spec import parse_campaign
from socnavgen.campaign.store import read_episodes
from socnavgen.errors import InputFileError
from socnavgen.location import load_location
from socnavgen.sim.engine.budget import FLOOR
from tests.campaign.conftest import WAREHOUSE, campaign_yaml


def _default_yaml(cards: list[str], policies: list[str]) -> str:
    """campaign_yaml without a timeout: the campaign's own default."""
    return campaign_yaml(cards, policies, 1).replace("timeout: 40.0, ", "")


def test_without_a_timeout_every_policy_gets_the_time_its_route_needs(tmp_path) -> None:  # noqa: ANN001
    spec = parse_campaign(_default_yaml(["crowd-navigation"], ["scripted", "orca"]) + "verify: false\n")
    out = tmp_path / "o"
    run_campaign(spec, out, executor="inline")
    rows = read_episodes(out)[0].to_pylist()
    assert {r["policy"] for r in rows} == {"scripted", "orca"}
    for row in rows:
        assert row["reached_goal"], (row["policy"], row["end_reason"], row["final_distance_to_target"])
    # the default robot, which waits for the crowd, needs more than the old fixed 60 s on this route
    assert max(r["time_to_reach_goal"] for r in rows if r["policy"] == "scripted") > 60.0


def test_the_route_limit_is_the_one_simulate_gives_and_a_number_still_fixes_it(tmp_path) -> None:  # noqa: ANN001
    spec = parse_campaign(_default_yaml(["crowd-navigation"], ["scripted"]))
    assert spec.simulation.timeout == "route" and settings_of(spec).timeout is None
    from socnavgen.cards.generate import write_card_run
    from socnavgen.sim.engine.scenario import route_time_limit

    run = write_card_run("crowd-navigation", WAREHOUSE, tmp_path / "run", 0)
    limit = route_time_limit(run.root, load_location(WAREHOUSE))
    assert limit.seconds >= FLOOR and "m of route" in limit.why
    fixed = parse_campaign(campaign_yaml(["crowd-navigation"], ["scripted"], 1, timeout=45.0))
    assert settings_of(fixed).timeout == 45.0
    with pytest.raises(InputFileError):
        parse_campaign(campaign_yaml(["crowd-navigation"], ["scripted"], 1).replace("timeout: 40.0", "timeout: soon"))
