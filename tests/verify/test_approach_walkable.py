"""A meeting needs an approach (closer_<human> >= APPROACH), and where the two start is measured along the way
one would walk to the other, never through a wall (issue 25, home_13 / home_16 of the new-request suite: a
teenager bursting out of the bathroom crossed 1.9 m in front of the robot that had just left the bedroom next
door, 2.06 m from it through their wall at the start, and the meeting was refused as "no approach").

Location "corner" (tests/verify/corpus.py): a thin wall (y 3.0-3.1, x >= 9.0) closes a room in the north-east.
The same motion (start 2.075 m apart, closest 1.6-1.75 m: less than 0.5 m closer in a straight line) is a meeting when
the wall stood between them at the start, and none on open floor, where they were that near from the start."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace

from .corpus import Scene, build, make_corner_location, write_case_run

# (start of the robot, start of the person, where the person walks to): the person ends 1.6-1.75 m from the robot
THROUGH_WALL = ((10.5, 1.525), (10.5, 3.6), [(2.0, 8.6, 3.6), (4.0, 9.0, 2.4)])  # in the room, out round its wall
OPEN_FLOOR = ((7.0, 1.0), (7.0, 3.075), [(4.0, 7.6, 2.5)])  # the same distances, nothing between them


def _spec() -> ScenarioSpec:
    return ScenarioSpec(script=RobotScript(route="stands"), encounters=[], criteria=[
        Criterion(id="c1", kind="meets", human="human1", distance=2.0, text="they meet")])


@pytest.mark.parametrize("case, passes", [(THROUGH_WALL, True), (OPEN_FLOOR, False)])
def test_an_approach_counts_from_the_walkable_distance_at_the_start(tmp_path: Path, case, passes: bool) -> None:  # noqa: ANN001
    robot, person, walk = case
    scene = Scene(robot=[(0.0, *robot), (8.0, *robot)], humans={"human1": [(0.0, *person), *walk, (8.0, *walk[-1][1:])]},
                  robot_says=[], human_says={}, actions={"human1": [(0.0, 8.0, "RegularNav")]}, duration=8.0,
                  goal=robot)
    plan = PathPlan(robot=["east", "corner"], humans=[HumanPlan(name="human1", path=["north", "corner"])])
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), _spec(), plan)
    trace = build(scene)
    start = ((robot[0] - person[0]) ** 2 + (robot[1] - person[1]) ** 2) ** 0.5
    assert start == pytest.approx(2.075, abs=0.01)  # the same straight-line start in both cases
    found = {f.criterion: f for f in verify_trace(run, trace).findings}
    assert found["c1"].passed is passes, found["c1"].evidence
    if not passes:
        assert "closer than at the start" in found["c1"].evidence
