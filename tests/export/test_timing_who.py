"""Whom the export's timing holds: only a person whose tree walks at the start (export.first_move), as the
simulator's pacing holds only RegularNav - a follower is not walked to a waiting spot of its own."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.export.as_target import target_twin, trace_as_target
from socnavgen.export.first_move import WALK, first_move
from socnavgen.export.scene import build_scene
from socnavgen.export.timing import holds
from socnavgen.run import HumanPlan, PathPlan
from tests.synthetic import walled_room, write_location

from .export_helpers import GIVE_WAY_TREE, REGULAR_TREE, build_run

# a 30 x 20 m hall (0.1 m/px): the robot drives west -> east through x; human1 walks south -> north through x,
# human2 starts north of x and follows her
NODES = {"w": (30, 100), "x": (150, 100), "e": (270, 100), "s": (150, 190), "n": (150, 10)}
EDGES = [("w", "x"), ("x", "e"), ("s", "x"), ("x", "n")]

FOLLOW_TREE = """<root main_tree_to_execute="FollowTree">
    <BehaviorTree ID="FollowTree">
        <FollowHuman agent_id="{id}" target_id="0" time_step="{dt}"/>
    </BehaviorTree>
</root>
"""

STAND_UNTIL_PHRASE_TREE = """<root main_tree_to_execute="StandTree">
    <include path="BTRegularNav.xml"/>
    <BehaviorTree ID="StandTree">
        <Fallback>
            <Sequence>
                <RobotSays agent_id="{id}" message="4"/>
                <SetBlackboard output_key="agentid" value="{id}"/>
                <SetBlackboard output_key="timestep" value="{dt}"/>
                <SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>
            </Sequence>
            <LookAtRobot agent_id="{id}"/>
        </Fallback>
    </BehaviorTree>
</root>
"""


@pytest.mark.parametrize(("tree", "moves"), [(REGULAR_TREE, WALK), (GIVE_WAY_TREE, WALK),
                                              (FOLLOW_TREE, "FollowHuman"),
                                              (STAND_UNTIL_PHRASE_TREE, "LookAtRobot")])
def test_the_first_move_is_what_the_tree_does_before_anything_happens(tree: str, moves: str) -> None:
    assert first_move(tree) == moves


def test_a_follower_follows_from_the_start_and_only_the_one_it_follows_waits(tmp_path: Path) -> None:
    hall = write_location(tmp_path / "hall", walled_room(200, 300, wall=2), NODES, EDGES, resolution=0.1,
                          origin=(0.0, 0.0), name="hall")
    plan = PathPlan(robot=["w", "x", "e"], humans=[
        HumanPlan(name="human1", path=["s", "x", "n"], interaction_point="x"),
        HumanPlan(name="human2", path=["n", "x"], interaction_point="x")])
    run = build_run(tmp_path / "run", hall, plan, {"human1": REGULAR_TREE, "human2": FOLLOW_TREE})
    scene, _ = build_scene(run)
    assert set(holds(scene)) == {"human1"}  # the follower's tree follows first: pacing never holds it
    trace = trace_as_target(target_twin(run, "socrates", tmp_path / "twin"), 1.0)
    pos = trace.humans[:, :, 0] + 1j * trace.humans[:, :, 1]
    gap = np.abs(pos[:, 0] - pos[:, 1])
    before = trace.robot[:, 0] < NODES["x"][0] * 0.1 - 3.0  # the robot is still west of x, coming
    still = (np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4]) < 0.05) & (trace.t > 3.0) & before
    assert still.sum() * trace.dt > 5.0  # she waits for the robot at her spot
    # while she waits, he has come to her (FollowHuman stops ~1.3 m from her), not to a spot 2 m north of x
    assert float(np.median(gap[still])) < 2.5, float(np.median(gap[still]))
