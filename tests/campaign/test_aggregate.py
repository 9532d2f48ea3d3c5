"""campaign.aggregate on a hand-made episode table (no simulation): the ranking, per-location estimates, the
expected-behaviour checks, the TTC distribution, timeouts, and worst episodes that are failures only."""

from __future__ import annotations

import json

import pyarrow as pa
import pyarrow.compute as pc

from socnavgen.campaign.aggregate import RANKING, aggregate, worst_episodes


def _row(policy: str, scenario: str, location: str, seed: int, *, success: bool, reached: bool | None = None,
         status: str = "ok", end: str = "robot_goal", collisions: int = 0, gap: float = 1.0,
         checks: list[dict] | None = None) -> dict:
    reached = success if reached is None else reached
    return {"episode": f"{scenario}|{policy}|{seed}", "scenario": scenario, "location": location,
            "card": scenario.split("@")[0], "policy": policy, "seed": seed, "status": status, "end_reason": end,
            "failure_reason": None if success else "goal not reached", "verified": success,
            "success": None if status != "ok" else success, "reached_goal": None if status != "ok" else reached,
            "time_to_goal": 20.0 + seed if success else None, "walkable_path_efficiency": 0.9 if reached else None,
            "intimate_space_seconds": 0.5 * collisions, "intimate_approach_seconds": 0.2 * collisions,
            "expected_behaviour": 1.0 if success else 0.0,
            "collisions": collisions, "minimum_distance_to_people": gap,
            "ttc_seconds": [1.0, 0.0, 0.0, 0.0, 0.0, 9.0],
            "expected_checks": json.dumps(checks or [{"check": "slows_at_corner", "value": 0.3, "passed": success},
                                                     {"check": "keeps_right", "value": None, "passed": None}]),
            "people_traits": json.dumps({"h1": {"speed": 1.0 + 0.1 * seed, "personal_space": 1.0,
                                               "start_delay": 0.0}})}


def _table() -> pa.Table:
    rows = []
    for seed in range(4):
        for scenario, location in (("blind-corner@warehouse", "warehouse"), ("doorway@home", "home")):
            rows.append(_row("good", scenario, location, seed, success=True))
            # `bad` reaches its goal on the warehouse but touches people; times out at home; crashes once
            if location == "warehouse":
                rows.append(_row("bad", scenario, location, seed, success=False, reached=True, collisions=5 + seed,
                                 gap=0.0))
            elif seed == 3:
                rows.append(_row("bad", scenario, location, seed, success=False, status="failed", end="error"))
            else:
                rows.append(_row("bad", scenario, location, seed, success=False, end="timeout", gap=0.6))
    return pa.Table.from_pylist(rows)


def test_the_ranking_puts_the_better_policy_first_with_per_location_estimates() -> None:
    agg = aggregate(_table(), resamples=200)
    assert agg.policies == ["good", "bad"]  # whatever order the rows came in
    assert agg.ranking == list(RANKING)
    assert agg.per_policy["good"]["success"].mean == 1.0
    assert agg.per_policy["bad"]["success"].mean == 0.0  # the crash counts as a failure, not as missing
    assert agg.per_policy["bad"]["reached_goal"].mean == 0.5
    assert agg.per_policy["bad"]["success"].n == 8
    # time to goal over successes only: bad never succeeded, so it has no time, not a timeout's 60 s
    assert agg.per_policy["bad"]["time_to_goal"].n == 0
    assert agg.per_policy["good"]["time_to_goal"].mean == 21.5
    assert agg.per_policy["bad"]["timeout"].mean == 3 / 8
    assert agg.locations == ["home", "warehouse"]
    assert agg.per_location[("warehouse", "bad")]["reached_goal"].mean == 1.0
    assert agg.per_location[("home", "bad")]["reached_goal"].mean == 0.0
    assert agg.scenario_location["doorway@home"] == "home"
    assert agg.failed == {"good": 0, "bad": 1}
    assert agg.seeds == 4 and agg.episodes == 16
    assert agg.speeds == (1.0, 1.3)


def test_checks_count_only_where_they_applied_and_ttc_sums_seconds() -> None:
    agg = aggregate(_table(), resamples=200)
    assert agg.checks[("slows_at_corner", "good")].mean == 1.0
    assert agg.checks[("slows_at_corner", "good")].n == 8
    assert ("keeps_right", "good") not in agg.checks  # never applied: no score, not a zero
    assert agg.ttc["good"] == [8.0, 0.0, 0.0, 0.0, 0.0, 72.0]


def test_the_report_names_each_check_readably_with_its_column_name_in_the_glossary() -> None:
    from socnavgen.campaign.report import _sections

    table = _table().drop_columns(["expected_checks"]).append_column("expected_checks", pa.array(
        [json.dumps([{"check": "slow_near_place", "value": 0.3, "passed": True}])] * _table().num_rows))
    sections = {title: rows for title, _, rows, _ in _sections(aggregate(table, resamples=200))}
    checks = next(rows for title, rows in sections.items() if title.startswith("Expected behaviour per check"))
    assert checks[0][0] == "Slow on its approach to the place" and checks[0][1] == "8"  # per policy
    glossary = [r for r in sections["Metrics"] if r[1] == "expected_checks: slow_near_place"]
    assert glossary and glossary[0][0] == "Check: Slow on its approach to the place" and "mean speed" in glossary[0][3]


def test_paired_differences_are_on_the_same_scenario_and_seed() -> None:
    agg = aggregate(_table(), resamples=200, baseline="good")
    paired = agg.paired["bad"]["collisions"]
    assert paired.losses == 4 and paired.wins == 0  # more contact on each warehouse pair, equal at home
    assert paired.difference.mean > 0


def test_worst_episodes_are_failures_only_worst_first() -> None:
    table = _table()
    worst = worst_episodes(table, 50)
    assert worst and all(r["policy"] == "bad" for r in worst)  # never padded with the good policy's successes
    assert len(worst) == 8
    assert worst[0]["status"] == "failed"  # the crash first
    assert [r["collisions"] for r in worst[1:5]] == [8, 7, 6, 5]  # then the most contact
    assert worst_episodes(table.filter(pc.equal(table.column("policy"), "good")), 5) == []


def test_a_reach_with_a_wall_contact_is_not_a_contact_free_success() -> None:
    """A robot that scrapes a wall on its way to the goal reached it but is not a contact-free success, also in a
    table written before the rows counted walls (its `success` column says True there)."""
    rows = []
    for seed in range(4):
        clean = _row("clean", "narrow@warehouse", "warehouse", seed, success=True)
        scraper = _row("scraper", "narrow@warehouse", "warehouse", seed, success=True)
        clean["static_obstacle_collisions"], scraper["static_obstacle_collisions"] = 0, 1 + seed
        rows += [scraper, clean]
    agg = aggregate(pa.Table.from_pylist(rows), resamples=200)
    assert agg.policies == ["clean", "scraper"]
    assert agg.per_policy["scraper"]["reached_goal"].mean == 1.0
    assert agg.per_policy["scraper"]["success"].mean == 0.0
    assert agg.per_policy["scraper"]["time_to_goal"].n == 0  # time to goal over contact-free successes only
    assert agg.per_policy["clean"]["success"].mean == 1.0 and agg.per_policy["clean"]["time_to_goal"].n == 4
