"""Where bodies may start (location/placement.py): starts that must be refused and starts that must pass."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.location.placement import Walker, route_problems, start_problems

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"


@pytest.fixture(scope="module")
def warehouse():
    return load_location(EXAMPLES / "warehouse")


def test_a_robot_whose_goal_is_its_start_goes_nowhere_unless_it_passes_other_nodes(warehouse) -> None:
    assert route_problems(["up", "up"]) and "goal is its start (up)" in route_problems(["up", "up"])[0]
    assert start_problems(warehouse, ["up", "up"], [])
    assert route_problems(["up", "ki"]) == []
    # a round trip ("patrol to ki and back") is a route; who starts on its start/goal is refused as ever
    assert route_problems(["up", "ki", "up"]) == [] and start_problems(warehouse, ["up", "ki", "up"], []) == []
    on = start_problems(warehouse, ["up", "ki", "up"], [Walker("human1", ["up", "sk"])])
    assert len(on) == 1 and "where the robot starts" in on[0]


def test_nobody_starts_on_or_against_the_robot(warehouse) -> None:
    on = start_problems(warehouse, ["up", "ki", "hd"], [Walker("human1", ["up", "sk"])])
    assert len(on) == 1 and "human1 starts at up, where the robot starts" in on[0]
    assert start_problems(warehouse, ["up", "ki", "hd"], [Walker("human1", ["sk", "up"])]) == []  # 4 m away


def test_two_people_on_one_node_are_refused_unless_they_are_a_group(warehouse) -> None:
    alone = [Walker("human1", ["sh", "ki"]), Walker("human2", ["sh", "sw"])]
    problems = start_problems(warehouse, ["up", "ki", "hd"], alone)
    assert len(problems) == 1 and "human1 and human2 start 0.00 m apart" in problems[0]
    group = [Walker("human1", ["sh", "ki"], 1), Walker("human2", ["sh", "ki"], 1)]
    assert start_problems(warehouse, ["up", "ki", "hd"], group) == []


def test_a_group_needs_room_for_its_circle_beside_the_robot(tmp_path: Path) -> None:
    from tests import synthetic

    # r0 -- p1 is 1.5 m (30 px at 0.05 m): room for one person beside the robot's start, not for a group's circle
    root = synthetic.write_location(tmp_path / "room", synthetic.walled_room(100, 200),
                                    {"r0": (40, 50), "p1": (70, 50), "far": (160, 50)}, [("r0", "p1"), ("p1", "far")])
    room = load_location(root)
    assert start_problems(room, ["r0", "p1", "far"], [Walker("human1", ["p1", "far"])]) == []
    group = start_problems(room, ["r0", "p1", "far"], [Walker("human1", ["p1"], 1), Walker("human2", ["p1"], 1)])
    assert len(group) == 2 and all("1.50 m from where the robot starts (r0)" in p for p in group)


def test_nobody_stands_on_the_robots_goal_but_someone_may_leave_it(warehouse) -> None:
    robot = ["up", "ki", "hd"]
    stays = start_problems(warehouse, robot, [Walker("human1", ["hd"])])
    assert len(stays) == 1 and "on the robot's goal hd, and does not walk away" in stays[0]
    comes_back = start_problems(warehouse, robot, [Walker("human1", ["hd", "zg", "hd"])])
    assert len(comes_back) == 1 and "(their path stays near it or ends there)" in comes_back[0]
    from socnavgen.location.placement import start_rule_text
    assert "unless their path walks away from it and ends elsewhere" in start_rule_text()  # what is checked
    assert start_problems(warehouse, robot, [Walker("human1", ["hd", "zg", "p0"])]) == []  # walks away from it


def test_unknown_nodes_are_left_to_the_path_checks(warehouse) -> None:
    assert start_problems(warehouse, ["up", "zz"], [Walker("human1", ["qq"])]) == []


@pytest.mark.parametrize("pixels, refused", [(24, False), (22, True)])  # 1.2 m and 1.1 m at 0.05 m/px
def test_the_start_rule_is_one_comparison_stated_as_it_is_checked(tmp_path: Path, pixels: int, refused: bool) -> None:
    """"At least 1.2 m" between a person's and the robot's start nodes, measured between their positions as
    the prompt shows them: exactly 1.2 m passes (a player's answer was refused there), 1.1 m does not."""
    from socnavgen.location.placement import node_distance, start_rule_text
    from tests import synthetic

    root = synthetic.write_location(tmp_path / "room", synthetic.walled_room(100, 200),
                                    {"r0": (40, 50), "p1": (40 + pixels, 50), "far": (160, 50)},
                                    [("r0", "p1"), ("p1", "far")])
    room = load_location(root)
    assert "a person starts at least 1.2 m from the robot's start" in start_rule_text()
    assert "a person exactly 1.2 m from the robot's start passes" in start_rule_text()
    problems = start_problems(room, ["r0", "far"], [Walker("human1", ["p1", "far"])])
    assert bool(problems) is refused, (node_distance(room, "r0", "p1"), problems)
    if refused:
        assert "1.10 m from where the robot starts (r0)" in problems[0] and "at least 1.2 m" in problems[0]
