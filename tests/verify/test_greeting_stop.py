"""Stops for a greeting (issue 25, home_03 of the new-request suite): the robot stands still at a place
(`robot_stops`) and people stop beside each other (`stop_together`). home_03's robot only slowed to ~0.25 m/s
through its greeting stop, and the host stood ~2 m off while both guests were still in the hallway, turning back as
the first came out: nobody stopped to greet, and no criterion could see it."""

from __future__ import annotations

import re
from pathlib import Path

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace

from .corpus import DOCK, EAST, Scene, build, make_corner_location, write_case_run

STOPS = [(0.0, *DOCK), (4.0, 5.2, 1.525), (7.0, 5.2, 1.525), (12.0, *EAST), (20.0, *EAST)]  # 3 s at the corner
CREEPS = [(0.0, *DOCK), (3.0, 4.2, 1.525), (11.0, 6.2, 1.525), (16.0, *EAST), (20.0, *EAST)]  # 0.25 m/s past it
# stands 1.5 s, steps 0.3 m aside, stands 1.5 s more: a stand through its wait's step aside (it never advances)
SIDE_STEP = [(0.0, *DOCK), (4.0, 5.2, 1.525), (5.5, 5.2, 1.525), (5.8, 5.2, 1.825), (7.3, 5.2, 1.825),
             (12.0, *EAST), (20.0, *EAST)]
# stands 1.5 s, drives on 0.4 m, stands 1.5 s more: 3 s at the corner in all, never 2 s at once
BROKEN = [(0.0, *DOCK), (4.0, 5.2, 1.525), (5.5, 5.2, 1.525), (6.3, 5.6, 1.525), (7.8, 5.6, 1.525),
          (12.0, *EAST), (20.0, *EAST)]
STOPS_AT_START = [(0.0, *DOCK), (3.0, *DOCK), (8.0, *EAST), (20.0, *EAST)]  # stands 3 s, but at its start
HOST = [(0.0, 6.3, 6.0), (5.0, 6.3, 3.0), (10.0, 6.3, 3.0), (14.0, 6.3, 6.0), (20.0, 6.3, 6.0)]  # stands 5-10 s
HOST_TURNS_BACK = [(0.0, 6.3, 6.0), (5.0, 6.3, 3.0), (6.0, 6.3, 3.0), (9.0, 6.3, 6.0), (20.0, 6.3, 6.0)]
GUEST = [(0.0, 10.5, 1.6), (6.0, 7.3, 1.8), (10.0, 7.3, 1.8), (14.0, 10.5, 1.6), (20.0, 10.5, 1.6)]  # stands 6-10
GUEST_FAR = [(0.0, 10.5, 1.6), (6.0, 10.0, 1.6), (20.0, 10.0, 1.6)]  # stops at once, 4.7 m off, walked 0.5 m


def _spec(criterion: Criterion) -> ScenarioSpec:
    return ScenarioSpec(script=RobotScript(route="dock to east"), encounters=[
        Encounter(id="e1", place="AISLE END", node="corner", within=2.0, humans=[
            HumanPart(human="human1", reaction="stop"), HumanPart(human="human2", reaction="stop")])],
        criteria=[criterion])


def _plan() -> PathPlan:
    return PathPlan(robot=["dock", "corner", "east"], humans=[
        HumanPlan(name="human1", path=["north", "corner", "north"], interaction_point="corner"),
        HumanPlan(name="human2", path=["east", "corner", "east"], interaction_point="corner")])


def _finding(tmp_path: Path, criterion: Criterion, robot: list, host: list, guest: list):  # noqa: ANN202
    scene = Scene(robot=robot, humans={"human1": host, "human2": guest}, robot_says=[], human_says={}, actions={})
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), _spec(criterion), _plan())
    report = verify_trace(run, build(scene))
    return next(f for f in report.findings if f.criterion == "c1")


ROBOT_STOPS = Criterion(id="c1", kind="robot_stops", encounter="e1", seconds=2.0,
                        text="the robot stands still a few seconds at the corner for the greeting")
TOGETHER = Criterion(id="c1", kind="stop_together", humans=["human1", "human2"], encounter="e1",
                     text="the host and the guest stop to greet each other")


def test_a_robot_that_stands_still_at_the_place_passes(tmp_path: Path) -> None:
    found = _finding(tmp_path, ROBOT_STOPS, STOPS, HOST, GUEST)
    assert found.passed, found.evidence


def test_a_robot_that_only_slows_down_there_fails(tmp_path: Path) -> None:
    found = _finding(tmp_path, ROBOT_STOPS, CREEPS, HOST, GUEST)
    assert not found.passed
    assert "slowest within 2 m of corner: 0.25 m/s" in found.evidence, found.evidence
    assert found.blame == "robot_script"


def test_a_robot_that_steps_aside_in_its_stop_still_stops(tmp_path: Path) -> None:
    """A plain wait steps aside for someone coming past (sim.robot.wait_spot): the robot holds the place through it,
    never advancing (warehouse_17 and round 29's warehouse_21: their stops were failed for that step)."""
    found = _finding(tmp_path, ROBOT_STOPS, SIDE_STEP, HOST, GUEST)
    assert found.passed, found.evidence


def test_a_robot_whose_stop_is_broken_fails_and_is_told_so(tmp_path: Path) -> None:
    """Holding the place long enough in all but never the seconds at once (it drove on in between): the hint says the
    stand was broken, not that a cue must stop it (round 24's player had the wait cue already)."""
    found = _finding(tmp_path, ROBOT_STOPS, BROKEN, HOST, GUEST)
    assert not found.passed, found.evidence
    assert found.blame == "robot_script"
    total, once = re.search(r"held the place ([\d.]+) s in all but at most ([\d.]+) s at once \(needs 2 s at once\)",
                            found.blame_reason).groups()
    assert float(total) >= 2.0 > float(once), found.blame_reason
    creeps = _finding(tmp_path / "creeps", ROBOT_STOPS, CREEPS, HOST, GUEST)
    assert "a cue there must stop it" in creeps.blame_reason, creeps.blame_reason


def test_a_robot_that_stands_still_elsewhere_fails(tmp_path: Path) -> None:
    found = _finding(tmp_path, ROBOT_STOPS, STOPS_AT_START, HOST, GUEST)
    assert not found.passed, found.evidence


def test_people_who_stand_together_pass(tmp_path: Path) -> None:
    found = _finding(tmp_path, TOGETHER, STOPS, HOST, GUEST)
    assert found.passed, found.evidence


def test_a_host_who_turns_back_before_the_guest_comes_fails(tmp_path: Path) -> None:
    found = _finding(tmp_path, TOGETHER, STOPS, HOST_TURNS_BACK, GUEST)
    assert not found.passed
    assert found.blame == "behaviors" and found.blame_human == "human1", found
    assert "while all stood still, closest together" in found.evidence, found.evidence


def test_people_who_stand_still_far_apart_fail(tmp_path: Path) -> None:
    found = _finding(tmp_path, TOGETHER, STOPS, HOST, GUEST_FAR)
    assert not found.passed, found.evidence
