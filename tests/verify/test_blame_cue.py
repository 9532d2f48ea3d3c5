"""Rule N3's cue (verify/blame_cue.py): a person's trigger on where the robot is that never held says how close it
came, and one missed by a hair is the spec's trigger to change, not the paths (issue 25: warehouse_04's 5 s stand
on "robot ahead within 4.5 m" missed first by 0.06 m, then by a degree of IsRobotBlocking's cone)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.run.spec import HumanPart, ScenarioSpec
from socnavgen.verify import verify_trace
from socnavgen.verify.blame_cue import advised

from .corpus import (
    DOCK,
    EAST,
    _h1,
    _robot,
    base_scene,
    base_spec,
    build,
    make_corner_location,
    write_case_run,
)


@pytest.fixture(scope="module")
def corner(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_corner_location(tmp_path_factory.mktemp("cue") / "corner")


def _reacts_to(spec: ScenarioSpec, trigger: str, distance: float) -> ScenarioSpec:
    """e1's human1 stops when the robot is where `trigger` says (no phrase)."""
    e1 = spec.encounters[0]
    part = HumanPart(human="human1", trigger=trigger, distance=distance, reaction="stop")
    return spec.model_copy(update={"encounters": [e1.model_copy(update={"humans": [part]}), *spec.encounters[1:]]})


STROLL = [(0.0, 7.0, 3.3), (20.0, 10.6, 3.3)]  # east along y 3.3 at 0.18 m/s (never stops, never turns)
BEHIND_WALL = [(0.0, 9.4, 3.3), (10.0, 11.2, 3.3), (20.0, 9.4, 3.3)]  # in the room, behind its wall


def _stop_finding(tmp: Path, corner: Path, trigger: str, distance: float, walks: list = STROLL):  # noqa: ANN202
    """human1 strolls; the robot drives east along y 1.5, passing 1.78 m from her: her trigger decides whether she
    had anything to stop for (c3: stops_near_robot 2 m)."""
    scene = _h1(_robot(base_scene(), [(0.0, *DOCK), (12.0, *EAST), (20.0, *EAST)]), walks, actions=[], says=[])
    report = verify_trace(write_case_run(tmp, corner, _reacts_to(base_spec(), trigger, distance)), build(scene))
    return next(f for f in report.findings if f.criterion == "c3")


def test_robot_blocking_that_the_robot_beside_her_never_meets_is_the_specs(tmp_path: Path, corner: Path) -> None:
    """Within 3 m the robot is at least ~37 degrees off her heading, outside IsRobotBlocking's 28.6 (the simulator's
    leaf): her tree had nothing to react to. Before, the verifier's own 45-degree `ahead` said the trigger held and
    blamed her tree ("did not react as asked"), which no tree can fix."""
    stop = _stop_finding(tmp_path / "r", corner, "robot_blocking", 3.0)
    assert not stop.passed and stop.blame == "spec", (stop.blame, stop.blame_reason)
    assert "degrees off the way human1 faced" in stop.blame_reason and "28.6" in stop.blame_reason
    assert "robot_visible 3 m" in stop.blame_reason


def test_a_distance_missed_by_a_hair_is_the_specs_with_one_that_holds(tmp_path: Path, corner: Path) -> None:
    """robot_visible 1.6 m: the robot passes 1.78 m from her in the open, missing it by 0.18 m: the trigger's
    distance is the fix (advised: the closest plus a margin), not where they meet."""
    stop = _stop_finding(tmp_path / "r", corner, "robot_visible", 1.6)
    assert not stop.passed and stop.blame == "spec", (stop.blame, stop.blame_reason)
    assert "missed by 0.18 m" in stop.blame_reason and "give it 2.5 m or more" in stop.blame_reason


@pytest.mark.parametrize(("trigger", "distance", "walks", "words"), [
    ("robot_near", 0.7, STROLL, "closest 1.78 m"),  # missed by over a metre: they never came near enough
    ("robot_visible", 3.0, BEHIND_WALL, "always with a wall between them"),  # within 3 m only behind the wall
])
def test_a_cue_missed_by_far_or_behind_a_wall_stays_the_paths(tmp_path: Path, corner: Path, trigger: str,
                                                              distance: float, walks: list, words: str) -> None:
    stop = _stop_finding(tmp_path / "r", corner, trigger, distance, walks)
    assert not stop.passed and stop.blame == "paths" and words in stop.blame_reason, (stop.blame, stop.blame_reason)


def test_the_advised_distance_is_the_closest_plus_a_margin() -> None:
    """Sanity of the rounding: the advised distance is the closest plus 0.5 m, up to the next half metre."""
    assert advised(2.77, 2.7) == 3.5 and advised(1.0, 3.0) == 3.0 and advised(1.78, 1.6) == 2.5
    assert np.isclose(advised(2.0, 1.0), 2.5)
