"""Following the robot is trailing it: walking after it while it drives, not ahead of it along its route (home_19,
round 27: toddlers who walked up to the robot from in front and stood beside it passed as "following right behind
it"). A follow that lasts a while (its part has `lasts`) is judged over that while, not to the run's end: toddlers who
trail the robot 16 s and then go back to the sofa followed it (home_19's player had to give up follows_robot, judged
to the end, for a criterion that passed the toddlers who never trailed)."""

from __future__ import annotations

from pathlib import Path

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace
from socnavgen.verify.way_end import follows_robot_to_the_end

from .corpus import Scene, build, make_corner_location, write_case_run

# The robot stands at the corner (5.775, 1.625) saying FOLLOW ME 0.2-3 s, then drives east from 6 s to (11, 1.5).
ROBOT = [(0.0, 5.775, 1.625), (6.0, 5.775, 1.625), (15.0, 11.0, 1.5), (25.0, 11.0, 1.5)]
BEHIND = [(0.0, 4.8, 1.6), (6.5, 4.8, 1.6), (15.5, 9.8, 1.6), (25.0, 9.8, 1.6)]  # ~1 m behind it all the way
IN_FRONT = [(0.0, 7.3, 1.6), (6.0, 7.3, 1.6), (13.0, 11.0, 1.6), (15.0, 11.6, 0.7), (25.0, 11.6, 0.7)]  # ~1.3 m ahead
TURNS_BACK = [(0.0, 4.8, 1.6), (6.5, 4.8, 1.6), (14.0, 9.0, 1.6), (15.0, 9.0, 1.6), (25.0, 4.8, 1.6)]  # trails 8 s


def _spec(lasts: float | None = None) -> ScenarioSpec:
    return ScenarioSpec(script=RobotScript(route="corner to east"), encounters=[
        Encounter(id="e1", place="BLIND CORNER", node="corner", within=1.5, humans=[
            HumanPart(human="human1", trigger="robot_says", phrase="FOLLOW ME", reaction="follow", latch=True,
                      lasts=lasts)])],
        criteria=[Criterion(id="c1", kind="follows_robot", human="human1", encounter="e1", phrase="FOLLOW ME",
                            distance=2.5, seconds=5.0, text="the worker follows the robot")])


def _finding(tmp_path: Path, walk: list[tuple[float, float, float]], lasts: float | None = None):  # noqa: ANN202
    plan = PathPlan(robot=["corner", "east"], humans=[HumanPlan(name="human1", path=["corner", "east"],
                                                                 interaction_point="corner")])
    scene = Scene(robot=ROBOT, humans={"human1": walk}, robot_says=[(0.2, 3.0, 5)], human_says={},
                  actions={"human1": [(0.0, 25.0, "FollowRobot")]}, goal=(11.0, 1.5), duration=25.0)
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), _spec(lasts), plan)
    return next(f for f in verify_trace(run, build(scene)).findings if f.criterion == "c1")


def test_a_follower_behind_the_robot_follows(tmp_path: Path) -> None:
    found = _finding(tmp_path, BEHIND)
    assert found.passed, found.evidence


def test_one_who_walks_in_front_of_the_driving_robot_does_not_follow_it(tmp_path: Path) -> None:
    found = _finding(tmp_path, IN_FRONT)  # within 2.5 m and walking all along: only where they walk is wrong
    assert not found.passed, found.evidence


def test_a_follow_that_lasts_a_while_is_judged_over_that_while(tmp_path: Path) -> None:
    assert not _finding(tmp_path / "a", TURNS_BACK).passed  # judged to the end: they went back, 6 m off
    found = _finding(tmp_path / "b", TURNS_BACK, lasts=9.0)  # the follow ends after 9 s: trailing 4.5 s is enough
    assert found.passed, found.evidence


def test_a_follow_that_lasts_a_while_does_not_end_with_the_robot() -> None:
    assert follows_robot_to_the_end(_spec(), "human1")
    assert not follows_robot_to_the_end(_spec(lasts=16.0), "human1")  # the toddlers go back to the sofa
