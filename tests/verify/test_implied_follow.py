"""A follow to the end is judged as one even when the spec names no follows_* criterion (derive.implied_follows), and
a follower who stood where the robot was going is blamed on the paths (blame rule F2). Round 35's home_27: the guest
told to follow the robot for good started at its goal, stepped back after FOLLOW ME and stood; the spec's criteria
(she stood near it, stayed within 3.5 m, was within 3 m at its goal) passed, and the player, told only "did not react
as asked" when follows_robot failed, had swapped it for them."""

from __future__ import annotations

from pathlib import Path

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace
from socnavgen.verify.derive import with_implied
from socnavgen.verify.models import VerifySettings

from .corpus import Scene, build, make_corner_location, write_case_run

# As test_follow_trail: the robot says FOLLOW ME at the corner 0.2-3 s, then drives east from 6 s to (11, 1.5).
ROBOT = [(0.0, 5.775, 1.625), (6.0, 5.775, 1.625), (15.0, 11.0, 1.5), (25.0, 11.0, 1.5)]
BEHIND = [(0.0, 4.8, 1.6), (6.5, 4.8, 1.6), (15.5, 9.8, 1.6), (25.0, 9.8, 1.6)]  # ~1 m behind it all the way
AT_ITS_GOAL = [(0.0, 9.0, 1.6), (25.0, 9.0, 1.6)]  # stands on its way 3.2 m past the corner the whole run


def _spec(lasts: float | None = None, criteria: list[Criterion] | None = None, followers: int = 1,
          phrase: bool = True) -> ScenarioSpec:
    cause = {"trigger": "robot_says", "phrase": "FOLLOW ME"} if phrase else {"trigger": "robot_near", "distance": 5.0}
    parts = [HumanPart(human=f"human{k}", reaction="follow", latch=True, lasts=lasts, **cause)
             for k in range(1, followers + 1)]
    return ScenarioSpec(script=RobotScript(route="corner to east"), encounters=[
        Encounter(id="e1", place="BLIND CORNER", node="corner", within=1.5, humans=parts)],
        criteria=criteria or [Criterion(id="c1", kind="stl", formula="eventually (dist_human1 < 3.0)",
                                        text="the worker is near the robot")])


def _implied(spec: ScenarioSpec) -> list[Criterion]:
    return [c for c, source in with_implied(spec, VerifySettings()) if source == "implied" and c.kind == "follows_robot"]


def test_a_follow_to_the_end_implies_follows_robot() -> None:
    (c,) = _implied(_spec())
    assert (c.human, c.encounter, c.distance) == ("human1", "e1", 2.0)
    assert [c.distance for c in _implied(_spec(followers=2))] == [3.2, 3.2]  # a file of two: one a body farther back


def test_no_implied_follow_for_a_timed_follow_or_one_the_spec_judges() -> None:
    assert _implied(_spec(lasts=8.0)) == []  # come to the robot for a handover: the spec's own criteria judge it
    own = Criterion(id="c1", kind="follows_robot", human="human1", encounter="e1", distance=2.5, text="follows")
    assert _implied(_spec(criteria=[own])) == []


def _finding(tmp_path: Path, walk: list[tuple[float, float, float]], phrase: bool = True):  # noqa: ANN202
    plan = PathPlan(robot=["corner", "east"], humans=[HumanPlan(name="human1", path=["corner", "east"],
                                                                 interaction_point="corner")])
    scene = Scene(robot=ROBOT, humans={"human1": walk}, robot_says=[(0.2, 3.0, 5)], human_says={},
                  actions={"human1": [(0.0, 25.0, "FollowRobot")]}, goal=(11.0, 1.5), duration=25.0)
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), _spec(phrase=phrase), plan)
    return next(f for f in verify_trace(run, build(scene)).findings if f.criterion == "follow_human1_e1")


def test_the_implied_follow_passes_a_follower(tmp_path: Path) -> None:
    found = _finding(tmp_path, BEHIND)
    assert found.passed and found.source == "implied", found.evidence


def test_one_standing_where_the_robot_goes_fails_and_the_paths_are_blamed(tmp_path: Path) -> None:
    found = _finding(tmp_path, AT_ITS_GOAL)
    assert not found.passed
    assert found.blame == "paths" and "ahead of the robot along its way when it set off" in (found.blame_reason or ""), found.blame_reason


def test_one_waiting_on_its_route_for_the_robot_to_come_is_no_follower_placed_ahead(tmp_path: Path) -> None:
    """A follow the robot's coming starts (robot_near): someone waiting on its route who is to fall in behind once it
    has passed (round 29's hospital_19, a lost visitor tailing the robot) is not told to start behind it."""
    found = _finding(tmp_path, AT_ITS_GOAL, phrase=False)
    assert not found.passed
    assert "ahead of the robot along its way when it set off" not in (found.blame_reason or ""), found.blame_reason
