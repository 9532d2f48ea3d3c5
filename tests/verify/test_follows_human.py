"""A person who follows another person (reaction follow_human) is judged against the one they follow, never
against the robot (warehouse_10 of round 13: a worker filing behind another past the robot was measured 21.84 m
from the ROBOT, so the criterion stage 1 asked for could never pass); a follower of the robot is unchanged."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, Encounter, HumanPart, RobotScript, ScenarioSpec
from socnavgen.verify import verify_trace
from socnavgen.verify.blame import contradictions

from .corpus import DOCK, EAST, Scene, build, make_corner_location, write_case_run

# The robot drives along the bottom corridor dock -> east; from beside the corner (their encounter) human1 walks up
# the open side north (x 6.3), human2 behind it, 1.2 m back the whole way, far from the robot once it drove on.
LEADER = [(0.0, 6.3, 3.8), (2.0, 6.3, 3.8), (10.0, 6.3, 7.0), (20.0, 6.3, 7.0)]
FOLLOWER = [(0.0, 6.3, 2.6), (2.0, 6.3, 2.6), (10.0, 6.3, 5.8), (20.0, 6.3, 5.8)]
STAYS = [(0.0, 6.3, 2.6), (20.0, 6.3, 2.6)]


def _scene(follower: list[tuple[float, float, float]]) -> Scene:
    return Scene(robot=[(0.0, *DOCK), (18.0, *EAST), (20.0, *EAST)],
                 humans={"human1": LEADER, "human2": follower}, robot_says=[], human_says={},
                 actions={"human1": [(0.0, 20.0, "RegularNav")], "human2": [(0.0, 20.0, "FollowHuman")]})


def _spec(kind: str, reaction: str = "follow_human") -> ScenarioSpec:
    other = "human1" if reaction == "follow_human" else None
    return ScenarioSpec(script=RobotScript(route="dock to east"), encounters=[
        Encounter(id="e1", place="AISLE END", node="corner", within=2.0, humans=[
            HumanPart(human="human1", reaction="walk_past"),
            HumanPart(human="human2", reaction=reaction, other=other)])],
        criteria=[Criterion(id="c1", kind=kind, human="human2", encounter="e1", distance=2.0,
                            text="the second worker walks in single file right behind the first")])


def _plan() -> PathPlan:
    return PathPlan(robot=["dock", "corner", "east"], humans=[
        HumanPlan(name="human1", path=["corner", "north"], interaction_point="north"),
        HumanPlan(name="human2", path=["corner", "north"], interaction_point="north")])


def _finding(tmp_path: Path, spec: ScenarioSpec, scene: Scene):  # noqa: ANN202
    run = write_case_run(tmp_path / "run", make_corner_location(tmp_path / "loc"), spec, _plan())
    report = verify_trace(run, build(scene))
    return next(f for f in report.findings if f.criterion == "c1")


def test_a_follower_of_a_person_who_follows_passes_far_from_the_robot(tmp_path: Path) -> None:
    found = _finding(tmp_path, _spec("follows_human"), _scene(FOLLOWER))
    assert found.passed, found.evidence
    assert "human1" in found.evidence and "farthest 1.20 m from human1" in found.evidence, found.evidence


def test_a_follower_of_a_person_who_stays_behind_fails_measured_from_that_person(tmp_path: Path) -> None:
    found = _finding(tmp_path, _spec("follows_human"), _scene(STAYS))
    assert not found.passed
    assert "from human1" in found.evidence and "farthest 4.40 m" in found.evidence, found.evidence
    assert found.blame == "behaviors" and found.blame_human == "human2", found.blame_reason
    assert "human1" in found.blame_reason and "robot came near" not in found.blame_reason, found.blame_reason


def test_a_follower_of_a_person_who_walks_off_alone_fails(tmp_path: Path) -> None:
    """Near the leader at the start, then left behind: within D at some moment is not following."""
    alone = [(0.0, 6.3, 2.6), (2.0, 6.3, 2.6), (3.0, 6.3, 3.4), (20.0, 6.3, 3.4)]
    assert not _finding(tmp_path, _spec("follows_human"), _scene(alone)).passed


def test_a_follower_standing_beside_a_leader_who_stands_is_no_following(tmp_path: Path) -> None:
    standing = replace(_scene(STAYS), humans={"human1": [(0.0, 6.3, 3.8), (20.0, 6.3, 3.8)], "human2": STAYS})
    found = _finding(tmp_path, _spec("follows_human"), standing)
    assert not found.passed and (found.blame, found.blame_human) == ("behaviors", "human1"), found.blame_reason


def test_a_follower_of_the_robot_is_still_judged_against_the_robot(tmp_path: Path) -> None:
    """follows_robot keeps its meaning (within D of the robot), whatever the reaction: human2 trails human1 up
    north while the robot drives east."""
    found = _finding(tmp_path, _spec("follows_robot"), _scene(FOLLOWER))
    assert not found.passed and "farthest" in found.evidence and "from the robot" in found.evidence, found.evidence


@pytest.mark.parametrize(("reaction", "contradicts"), [("follow_human", False), ("follow", True), ("walk_past", True)])
def test_follows_human_is_only_for_a_follower_of_a_person(reaction: str, contradicts: bool) -> None:
    """Stage 1 refuses (and the verifier blames the spec for) follows_human of someone who follows nobody."""
    spec = _spec("follows_human", reaction)
    assert bool(contradictions(spec.criteria[0], spec)) is contradicts


def test_stage_one_tells_how_a_follower_of_a_person_is_stated_and_measured() -> None:
    """The prompt that told a capable model "follow_human: follows_robot" (then measured from the robot) now
    names the kind that measures from whom they follow, in the words of facts.follows_human_text."""
    from socnavgen.proposal.facts import follows_human_text
    from socnavgen.proposal.scenario import spec_help_text

    text = spec_help_text()
    assert "follow_human: follows_human or follows_robot" in text
    assert f"follows_human: {follows_human_text()}" in text and "not the robot" in follows_human_text()
    assert "not the robot" in follows_human_text(False) or "from whom `human` follows" in follows_human_text(False)
