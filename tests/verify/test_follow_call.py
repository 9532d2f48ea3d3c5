"""A follower called by the robot's phrase from farther than its encounter's reach (warehouse_03, round 14: a crew
at a pallet 6 m from the robot saying FOLLOW ME) walks up and falls in within S s of the phrase: that is following,
after its cause, from its place. One who never comes, or comes only long after the phrase, is not."""

from __future__ import annotations

from pathlib import Path

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace

from .corpus import Scene, build, make_corner_location, write_case_run

# The robot stands at the corner (5.775, 1.625) saying FOLLOW ME 0.2-3 s, then drives east from 6 s to (11, 1.5).
ROBOT = [(0.0, 5.775, 1.625), (6.0, 5.775, 1.625), (15.0, 11.0, 1.5), (25.0, 11.0, 1.5)]


def _follower(sets_off: float) -> list[tuple[float, float, float]]:
    """From `north` (4.4 m up the side passage, beyond 1.5 + 2 m of the corner) down at 1 m/s from `sets_off`,
    then 1.2 m behind the robot to the end (when the robot has left by then, as far behind as the walk makes it)."""
    down = sets_off + 3.0  # at (6.3, 3.0), 1.5 m from the corner
    return [(0.0, 6.3, 6.0), (sets_off, 6.3, 6.0), (down, 6.3, 3.0), (down + 2.5, 5.9, 1.6),
            (down + 9.5, 9.8, 1.6), (25.0, 9.8, 1.6)]


def _finding(tmp_path: Path, follower: list[tuple[float, float, float]]):  # noqa: ANN202
    spec = ScenarioSpec(script=RobotScript(route="corner to east"), encounters=[
        Encounter(id="e1", place="BLIND CORNER", node="corner", within=1.5, humans=[
            HumanPart(human="human1", trigger="robot_says", phrase="FOLLOW ME", reaction="follow")])],
        criteria=[Criterion(id="c1", kind="follows_robot", human="human1", encounter="e1", phrase="FOLLOW ME",
                            distance=2.0, seconds=5.0, text="the worker comes and follows the robot")])
    plan = PathPlan(robot=["corner", "east"], humans=[HumanPlan(name="human1", path=["north", "corner", "east"],
                                                                 interaction_point="corner")])
    scene = Scene(robot=ROBOT, humans={"human1": follower}, robot_says=[(0.2, 3.0, 5)], human_says={},
                  actions={"human1": [(0.0, 25.0, "FollowRobot")]}, goal=(11.0, 1.5), duration=25.0)
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), spec, plan)
    return next(f for f in verify_trace(run, build(scene)).findings if f.criterion == "c1")


def test_a_follower_called_from_across_the_room_who_walks_up_and_falls_in_follows(tmp_path: Path) -> None:
    found = _finding(tmp_path, _follower(2.5))  # 3.9 m from the corner when the phrase ends, near it at ~4 s
    assert found.passed, found.evidence


def test_a_follower_who_comes_only_long_after_the_phrase_does_not(tmp_path: Path) -> None:
    found = _finding(tmp_path, _follower(8.0))  # near the corner only at ~10.5 s, 7.5 s after the phrase
    assert not found.passed
    assert found.blame == "paths" and "within 5 s after the robot said FOLLOW ME" in found.blame_reason, \
        found.blame_reason


def test_a_follower_who_never_comes_does_not(tmp_path: Path) -> None:
    found = _finding(tmp_path, [(0.0, 6.3, 6.0), (25.0, 6.3, 6.0)])
    assert not found.passed and found.blame == "paths", found.blame_reason
