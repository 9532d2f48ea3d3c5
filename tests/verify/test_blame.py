"""Blame rules not pinned by the corpus: each failing finding names what can fix it (docs/verify.md)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from socnavgen.run.models import HumanPlan
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify import VerifyReport, verify_trace
from socnavgen.verify.blame import spec_problem

from .corpus import (
    DOCK,
    EAST,
    STAYS,
    STUCK_ROBOT,
    _h1,
    _robot,
    base_plan,
    base_scene,
    base_spec,
    build,
    make_corner_location,
    write_case_run,
)


@pytest.fixture(scope="module")
def corner(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_corner_location(tmp_path_factory.mktemp("blame") / "corner")


def _verify(tmp: Path, corner: Path, spec: ScenarioSpec | None, scene, plan=None) -> VerifyReport:  # noqa: ANN001
    return verify_trace(write_case_run(tmp, corner, spec, plan), build(scene))


def _finding(report: VerifyReport, cid: str):  # noqa: ANN202
    return next(f for f in report.findings if f.criterion == cid)


def test_deadlock_behind_a_human_waiting_for_an_unsaid_phrase_is_the_scripts(tmp_path: Path, corner: Path) -> None:
    scene = _h1(_robot(base_scene(), STUCK_ROBOT, says=[(0.2, 2.0, 5)]), STAYS, [(5.5, 20.0, "LookAtRobot")])
    report = _verify(tmp_path / "r", corner, base_spec(), scene)
    dead = _finding(report, "c10")
    assert not dead.passed and dead.blame == "robot_script" and "EXCUSE ME" in dead.blame_reason
    # no progress along its route for 15.0 s (its last 0.25 m of progress at t = 5.0 s), limit 10 s
    assert dead.robustness == pytest.approx(10 - 15.0, abs=0.11)
    assert report.blamed_on("robot_script") and not report.blamed_on("paths")


def test_collision_wanted_by_a_misbehaving_script_is_the_specs(tmp_path: Path, corner: Path) -> None:
    spec = base_spec()
    spec = spec.model_copy(update={"script": spec.script.model_copy(update={"misbehave": True}),
                                   "criteria": [*spec.criteria, Criterion(id="c12", kind="no_collision")]})
    scene = _robot(base_scene(), [(0.0, *DOCK), (15.0, 10.975, 1.525), (20.0, 10.975, 1.525)])
    crash = _finding(_verify(tmp_path / "r", corner, spec, scene), "c12")
    assert not crash.passed and crash.blame == "spec"


def test_group_on_different_paths_is_the_paths(tmp_path: Path, corner: Path) -> None:
    plan = base_plan()
    plan.humans[2] = HumanPlan(name="human3", path=["dock", "corner", "north"], group_id=0)
    scene = replace(base_scene(), follow={"human2": (1.2, 1.525)})  # human3 stays at the dock
    group = _finding(_verify(tmp_path / "r", corner, base_spec(), scene, plan), "c8")
    assert not group.passed and group.blame == "paths" and "different paths" in group.blame_reason


@pytest.mark.parametrize(("criterion", "words"), [
    (Criterion(id="x", kind="stops_near_robot", human="human3"), "walk past"),
    (Criterion(id="x", kind="meets", human="human9"), "takes part in no encounter"),
    (Criterion(id="x", kind="meets", human="human1", encounter="e7"), "does not have"),
    (Criterion(id="x", kind="keeps_away", human="human1", distance=3.0), "asks them to meet within 2"),
    (Criterion(id="x", kind="follows_robot", human="human2", phrase="WAIT"), "reacts to FOLLOW ME"),
])
def test_criteria_contradicting_their_spec(criterion: Criterion, words: str) -> None:
    spec = base_spec()
    spec = spec.model_copy(update={"encounters": [spec.encounters[0], spec.encounters[1].model_copy(update={
        "humans": [spec.encounters[1].humans[0], spec.encounters[1].humans[1].model_copy(
            update={"reaction": "walk_past"})]})]})
    spec = spec.model_copy(update={"criteria": [*spec.criteria, criterion]})
    problem = spec_problem(criterion, spec)
    assert problem is not None and words in problem
    assert spec_problem(spec.criteria[0], spec) is None


def _looks_when_it_sees(spec: ScenarioSpec) -> ScenarioSpec:
    """e1's human1 reacts to the robot in sight within 3 m (home_08's couple at the stove), not to a phrase."""
    e1 = spec.encounters[0]
    part = e1.humans[0].model_copy(update={"trigger": "robot_visible", "phrase": None, "reaction": "look",
                                           "distance": 3.0})
    return spec.model_copy(update={"encounters": [e1.model_copy(update={"humans": [part]}), *spec.encounters[1:]]})


@pytest.mark.parametrize(("x0", "x1", "blame", "words"), [
    (9.4, 11.2, "paths", "always with a wall between them"),  # in the room, behind its wall (y 3.0-3.1, x >= 9)
    (7.0, 8.8, "behaviors", "did not react as asked"),  # in the open: the robot in sight, no stop
])
def test_a_look_whose_cue_never_held_is_the_paths(tmp_path: Path, corner: Path, x0: float, x1: float, blame: str,
                                                  words: str) -> None:
    """Rule N3: the robot passed within 1.8 m of human1 only with a wall between them, so human1's
    robot_visible cue never held and its tree had nothing to react to: the place is the paths' to change. The
    same walk in the open (the cue held, no stop) stays the tree's."""
    walks = [(0.0, x0, 3.3), (10.0, x1, 3.3), (20.0, x0, 3.3)]  # 0.18 m/s: never stops
    scene = _h1(_robot(base_scene(), [(0.0, *DOCK), (12.0, *EAST), (20.0, *EAST)]), walks, actions=[], says=[])
    stop = _finding(_verify(tmp_path / "r", corner, _looks_when_it_sees(base_spec()), scene), "c3")
    assert not stop.passed and stop.blame == blame and words in stop.blame_reason, stop.blame_reason
