"""What the place checks ask for (proposal/place_checks.py) is seen on a trace: the robot waiting short of a place
until someone has gone by, and a person staying put while the robot passes. Round 21's lenient passes: hospital_04's
and warehouse_04's robots drove up to the place their text has them wait short of, home_10's friend "who does not
move away" walked 1.2 m off; the criteria the checks suggest must fail there and pass where the text happened."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace

from .corpus import Scene, build, make_corner_location, write_case_run

Y = 1.525  # the bottom corridor; the corner node is at x 5.8, the east node at x 11.0
HOLD = Criterion(id="hold", kind="stl", formula="(robot_to_node_corner >= 2.0) until (human1_to_node_east < 1.0)",
                 text="the robot waits about 3 m short of the corner until the worker has gone east")
STAYS = Criterion(id="stays", kind="stl", formula="always (moved_human2 < 0.5)", text="the friend stays where she is")


def _run(tmp_path: Path, robot_stops_at: float, friend_walks: bool) -> dict:
    spec = ScenarioSpec(script=RobotScript(route="dock to east"), encounters=[Encounter(
        id="e1", place="BLIND CORNER", node="corner", within=3.0, humans=[
            HumanPart(human="human1", trigger="always", reaction="walk_past"),
            HumanPart(human="human2", trigger="robot_near", reaction="look", distance=2.5)])], criteria=[HOLD, STAYS])
    plan = PathPlan(robot=["dock", "corner", "east"], humans=[
        HumanPlan(name="human1", path=["north", "corner", "east"], interaction_point="corner"),
        HumanPlan(name="human2", path=["east"], interaction_point="corner")])
    friend = [(0.0, 8.0, 2.3), (12.0, 8.0, 2.3), *([(14.0, 8.0, 3.5)] if friend_walks else []), (20.0, 8.0, 2.3)]
    scene = Scene(robot=[(0.0, 2.0, Y), (3.0, robot_stops_at, Y), (12.0, robot_stops_at, Y), (20.0, 10.9, Y)],
                  humans={"human1": [(0.0, 6.3, 6.0), (6.0, 6.3, Y), (11.0, 10.9, Y), (20.0, 10.9, Y)],
                          "human2": friend},
                  robot_says=[], human_says={}, actions={})
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), spec, plan)
    return {f.criterion: f for f in verify_trace(run, build(scene)).findings}


@pytest.mark.parametrize("stops_at, passes", [(3.4, True), (5.0, False)])
def test_a_robot_that_drives_up_to_the_place_it_should_wait_short_of_fails(tmp_path: Path, stops_at: float,
                                                                           passes: bool) -> None:
    found = _run(tmp_path, stops_at, friend_walks=False)
    assert found["hold"].passed is passes, found["hold"].evidence
    assert found["stays"].passed


def test_a_person_who_walks_off_while_the_text_has_her_stay_fails(tmp_path: Path) -> None:
    found = _run(tmp_path, 3.4, friend_walks=True)
    assert not found["stays"].passed and "moved_human2" in found["stays"].evidence
    assert found["hold"].passed
