"""World coordinates and headings, checked against the hand formula on an off-centre map."""

from __future__ import annotations

import math

import pytest

from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.export.scene import build_scene
from socnavgen.run import HumanPlan, PathPlan

from .export_helpers import expected_world


def test_hand_computed_coordinates(make_run) -> None:
    scene, _ = build_scene(make_run())
    # hand values: cc = (50, 5) px -> (-3 + 0.05*50.5, 1.5 + 0.05*34.5) = (-0.475, 3.225)
    assert expected_world("cc") == pytest.approx((-0.475, 3.225))
    assert expected_world("aa") == pytest.approx((-2.475, 2.475))
    h1 = scene.humans[0]
    assert h1.start.node == "cc"  # spawned around cc as the simulator spawns (test_spawn.py)
    assert math.dist((h1.start.x, h1.start.y), (-0.475, 3.225)) <= 1.5
    assert [(g.node, g.x, g.y) for g in h1.goals] == [
        ("bb", pytest.approx(-0.475), pytest.approx(2.475)), ("ee", pytest.approx(-1.475), pytest.approx(2.475))]
    r = scene.robot
    assert (r.start.x, r.start.y) == pytest.approx((-2.475, 2.475))
    assert [w.node for w in r.waypoints] == ["ee", "bb", "cc"]


def test_headings_follow_world_not_image_axes(make_run) -> None:
    scene, _ = build_scene(make_run())
    h1 = scene.humans[0]
    # a human faces its first goal from where it spawns (bb lies DOWN the image from cc: toward -y)
    bb = expected_world("bb")
    assert h1.start.yaw == pytest.approx(math.atan2(bb[1] - h1.start.y, bb[0] - h1.start.x))
    assert math.sin(h1.start.yaw) < 0
    assert h1.goals[-1].yaw == pytest.approx(math.pi)  # bb -> ee is -x
    r = scene.robot
    assert r.start.yaw == pytest.approx(0.0)  # aa -> ee is +x
    assert r.waypoints[1].yaw == pytest.approx(math.pi / 2)  # bb -> cc: up the image = +y
    assert r.waypoints[-1].yaw == pytest.approx(math.pi / 2)  # last keeps the previous heading


def test_single_node_path_has_one_goal_at_that_node(make_run) -> None:
    scene, _ = build_scene(make_run())
    h2 = scene.humans[1]
    assert h2.agent_id == 1
    assert [g.node for g in h2.goals] == ["dd"]
    assert (h2.goals[0].x, h2.goals[0].y) == pytest.approx(expected_world("dd"))


def test_skins_are_deterministic(make_run) -> None:
    a, _ = build_scene(make_run(name="a"))
    b, _ = build_scene(make_run(name="b"))
    assert [h.skin for h in a.humans] == [h.skin for h in b.humans]
    assert a.humans[0].skin != a.humans[1].skin


def test_unknown_node_is_refused(make_run) -> None:
    plan = PathPlan(robot=["aa", "zz"], humans=[HumanPlan(name="human1", path=["cc"])])
    run = make_run(plan=plan, trees={"human1": open_tree()})
    with pytest.raises(ValidationFailed, match="zz"):
        build_scene(run)


def test_missing_tree_is_refused(make_run) -> None:
    run = make_run()
    (run / "behaviors" / "human2.xml").unlink()
    with pytest.raises(InputFileError, match="human2"):
        build_scene(run)


def open_tree() -> str:
    from .export_helpers import REGULAR_TREE
    return REGULAR_TREE
