"""A person who walks to its waiting spot is released by the robot's distance only there: the target measures
the distance from where the person is, and the export's distances are the spot's (export.timing.hold_root)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.export.as_target import target_twin, trace_as_target
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import holds
from socnavgen.run import HumanPlan, PathPlan
from tests.synthetic import walled_room, write_location

from .export_helpers import REGULAR_TREE, build_run

# a 30 x 20 m hall (0.1 m/px): the robot drives west -> east through x; the person starts 2 m from the robot's
# start (a), walks round by s and crosses x south -> north
NODES = {"w": (30, 100), "x": (150, 100), "e": (270, 100), "s": (150, 190), "n": (150, 10), "a": (40, 110)}
EDGES = [("w", "x"), ("x", "e"), ("a", "s"), ("s", "x"), ("x", "n")]


@pytest.fixture(scope="module")
def near_start(tmp_path_factory) -> Path:  # noqa: ANN001
    root = Path(tmp_path_factory.mktemp("near_start"))
    hall = write_location(root / "hall", walled_room(200, 300, wall=2), NODES, EDGES, resolution=0.1,
                          origin=(0.0, 0.0), name="hall")
    plan = PathPlan(robot=["w", "x", "e"], humans=[HumanPlan(name="human1", path=["a", "s", "x", "n"],
                                                             interaction_point="x")])
    return build_run(root / "run", hall, plan, {"human1": REGULAR_TREE})


@pytest.mark.parametrize("target", ["socrates", "hunav2"])
def test_a_robot_near_where_the_person_starts_does_not_release_it_on_its_way(
        near_start: Path, tmp_path: Path, target: str) -> None:
    scene, _ = build_scene(near_start)
    hold = holds(scene)["human1"]
    start = complex(scene.humans[0].start.x, scene.humans[0].start.y)
    robot = complex(scene.robot.start.x, scene.robot.start.y)
    assert hold.goals_first and abs(start - robot) < hold.release_distance  # the robot starts within it of her
    assert abs(complex(*hold.wait_at) - robot) > hold.release_distance  # not of her spot
    twin = target_twin(near_start, target, tmp_path / target)
    trace = trace_as_target(twin, 1.0)
    pos = trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]
    spot = complex(*hold.wait_at)
    stood = (np.abs(pos - spot) < 0.3) & (np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4]) < 0.05)
    assert stood.sum() * trace.dt > 1.0, "she never waited at her spot"  # she set off on her way there
    node = complex(NODES["x"][0] * 0.1, scene.robot.start.y)  # x, on the robot's line
    robot_at = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    k = int(np.argmin(np.abs(robot_at - node)))  # the robot at x: she is there with it, waiting or crossing
    assert abs(pos[k] - robot_at[k]) < 2.5, abs(pos[k] - robot_at[k])  # (let go from her start: 6 m on, north)
