"""Two followers of the robot in a stated order (issue 25, home_09 of round 14): the stl criterion the order check
asks for (proposal/prose_checks.person_order_mistakes) fails when they follow in the reverse order, which two
follows_robot criteria cannot see, and passes in the text's order."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace

from .corpus import Scene, build, make_corner_location, write_case_run

Y = 1.525  # the bottom corridor
ROBOT = [(0.0, 4.4, Y), (2.0, 4.4, Y), (14.0, 10.4, Y), (20.0, 10.4, Y)]


def _behind(gap: float) -> list[tuple[float, float, float]]:
    return [(0.0, 4.4 - gap, Y), (2.0, 4.4 - gap, Y), (14.0, 10.4 - gap, Y), (20.0, 10.4 - gap, Y)]


def _spec() -> ScenarioSpec:
    follow = [HumanPart(human=h, trigger="robot_says", phrase="FOLLOW ME", reaction="follow", latch=True)
              for h in ("human1", "human2")]
    return ScenarioSpec(script=RobotScript(route="dock to east"), encounters=[
        Encounter(id="e1", place="CORRIDOR", node="dock", within=3.0, humans=follow)], criteria=[
        *(Criterion(id=f"c{k}", kind="follows_robot", human=h, encounter="e1", distance=3.0, text=f"{h} follows")
          for k, h in enumerate(("human1", "human2"), 1)),
        Criterion(id="order", kind="stl", formula=f"eventually (always (way_human2 >= way_human1 + {PERSON_RADIUS:g}))",
                  text="human2 walks behind human1")])


def _plan() -> PathPlan:
    return PathPlan(robot=["dock", "corner", "east"], humans=[
        HumanPlan(name=h, path=["dock", "corner", "east"], interaction_point="dock") for h in ("human1", "human2")])


@pytest.mark.parametrize("first, second, passes", [(1.2, 2.4, True), (2.4, 1.2, False)])
def test_the_order_of_two_followers_is_seen(tmp_path: Path, first: float, second: float, passes: bool) -> None:
    scene = Scene(robot=ROBOT, humans={"human1": _behind(first), "human2": _behind(second)}, robot_says=[(0.0, 2.0, 5)],
                  human_says={}, actions={h: [(0.0, 20.0, "FollowRobot")] for h in ("human1", "human2")})
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), _spec(), _plan())
    report = verify_trace(run, build(scene))
    found = {f.criterion: f for f in report.findings}
    assert found["c1"].passed and found["c2"].passed  # each within 3 m of the robot either way round
    assert found["order"].passed is passes, found["order"].evidence
    if not passes:
        assert "way_human2" in found["order"].evidence and "way_human1" in found["order"].evidence
