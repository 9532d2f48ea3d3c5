"""Expectations derived from paths, trees and cards."""

from __future__ import annotations

import pytest

from socnavgen.location import load_location
from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.expectations import card_expectations, derive_expectations, tree_expectations

from .verify_builders import GIVE_WAY_XML, NODE_WORLD, REGULAR_XML, crossing_trace


def test_give_way_tree_key_nodes() -> None:
    exps = tree_expectations("human1", GIVE_WAY_XML)
    by_node = {e.node: e for e in exps}
    # the interaction action, checked while the robot passes, plus the two conditions gating it
    assert by_node["GiveWaytoRobot"].kind == "gives_way_while_passing"
    assert by_node["IsRobotVisible"].kind == "executes"
    assert "distance=4.0" in by_node["IsRobotVisible"].detail and "GiveWaytoRobot" in by_node["RobotSays"].detail
    # MakeGesture(0) is not an interaction; IsRobotNearby sits under an Inverter (must FAIL): not expected
    assert set(by_node) == {"GiveWaytoRobot", "IsRobotVisible", "RobotSays"}
    assert all(e.human == "human1" and e.source == "tree" and e.stage == "behaviors" for e in exps)


def test_gesture_and_block_tree() -> None:
    xml = """<root main_tree_to_execute="T"><BehaviorTree ID="T"><Fallback>
      <Sequence><IsRobotBlocking agent_id="{id}" distance="1.5"/><MakeGesture agent_id="{id}" message="3"/>
        <BlockRobot agent_id="{id}" time_step="{dt}"/></Sequence>
      <Sequence><HumanSays agent_id="{id}" target_id="1" message="1"/><LookAtRobot agent_id="{id}"/></Sequence>
    </Fallback></BehaviorTree></root>"""
    exps = tree_expectations("human2", xml)
    names = {e.name for e in exps}
    assert "human2 executes MakeGesture(message=3)" in names
    gesture = next(e for e in exps if e.node == "MakeGesture")
    assert gesture.message == 3
    assert {e.node for e in exps} == {"MakeGesture", "BlockRobot", "LookAtRobot", "IsRobotBlocking", "HumanSays"}


def test_regular_tree_has_no_key_nodes() -> None:
    assert tree_expectations("human1", REGULAR_XML) == []


def test_path_expectations(tiny_location) -> None:
    loc = load_location(tiny_location)
    plan = PathPlan(robot=["a1", "b2", "c3"], humans=[
        HumanPlan(name="human1", path=["c3", "b2"], interaction_point="b2"),
        HumanPlan(name="human2", path=["d4", "b2"], group_id=1),
        HumanPlan(name="human3", path=["d4", "b2"], group_id=1),
        HumanPlan(name="human4", path=["a1", "b2"])])
    exps = derive_expectations(plan, {"human1": GIVE_WAY_XML, "human4": REGULAR_XML}, loc)
    kinds = [e.kind for e in exps]
    assert kinds.count("meets_human") == 1  # only the human with an interaction point
    meet = next(e for e in exps if e.kind == "meets_human")
    assert meet.human == "human1" and meet.point == pytest.approx(NODE_WORLD["b2"])
    group = next(e for e in exps if e.kind == "group_together")
    assert group.human == "human2,human3"
    goal = next(e for e in exps if e.kind == "robot_reaches_goal")
    assert goal.point == pytest.approx(NODE_WORLD["c3"]) and goal.stage == "paths"
    assert "gives_way_while_passing" in kinds


def test_card_criteria_become_expectations(tiny_location) -> None:
    loc = load_location(tiny_location)
    plan = PathPlan(robot=["a1", "c3"], humans=[HumanPlan(name="human1", path=["c3", "a1"], interaction_point="b2")])
    exps = card_expectations([{"kind": "meets_human", "within": 2.0}, {"kind": "executes", "node": "GiveWaytoRobot"},
                              {"kind": "group_together"}, {"kind": "robot_reaches_goal"}, {"kind": "dances"}],
                             plan, loc)
    assert [e.kind for e in exps] == ["meets_human", "gives_way_while_passing", "group_together",
                                      "robot_reaches_goal", "executes"]
    assert exps[0].within == 2.0 and exps[0].human == "human1" and exps[0].point == pytest.approx(NODE_WORLD["b2"])
    assert exps[1].human is None  # any human
    assert all(e.source == "card" for e in exps)
    assert exps[-1].node is None and "dances" in exps[-1].name


def test_unreadable_tree_becomes_a_failing_expectation(tiny_location) -> None:
    plan = PathPlan(robot=["a1", "c3"], humans=[HumanPlan(name="human1", path=["c3", "a1"])])
    exps = derive_expectations(plan, {"human1": "<root><BehaviorTree ID='x'><Sequence></root>"},
                               load_location(tiny_location))
    broken = next(e for e in exps if e.human == "human1")
    (finding,) = evaluate([broken], crossing_trace())
    assert not finding.passed and "does not parse" in finding.evidence and finding.stage == "behaviors"
