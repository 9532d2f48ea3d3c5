"""Tree checks on hand-built traces: key nodes must really run, after their cause, and a gesture counts only
where it is shown (the 'MakeGesture(WAIT) first at t=0.1 s' bug)."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.expectations import tree_expectations
from socnavgen.verify.models import Expectation

from .verify_builders import GIVE_WAY_XML, build_trace, crossing_trace

WAIT_TREE = """<root main_tree_to_execute="T"><BehaviorTree ID="T"><Fallback>
  <Sequence><IsRobotNearby agent_id="{id}" distance="2.0"/><MakeGesture agent_id="{id}" message="1"/></Sequence>
  <MakeGesture agent_id="{id}" message="0"/>
</Fallback></BehaviorTree></root>"""


def _verdicts(exps, trace):  # noqa: ANN001, ANN202
    return {e.name: f for e, (f, _) in zip(exps, evaluate(exps, trace), strict=True)}


def test_tree_nodes_fire_after_their_cause() -> None:
    trace = crossing_trace()
    exps = tree_expectations("human1", GIVE_WAY_XML)
    found = _verdicts(exps, trace)
    give = found["human1 gives way while the robot passes"]
    # GiveWaytoRobot runs t 3.5..5.0; within 2.5 m of the robot from t = 4.0 (stepping aside: hypot(2, 0.5) = 2.06 m)
    assert give.passed and give.time == pytest.approx(4.0) and give.distance == pytest.approx(2.06)
    assert found["human1: IsRobotVisible succeeds"].passed
    says = found["human1: RobotSays(EXCUSE ME) succeeds"]
    assert says.passed and says.time == pytest.approx(3.5) and "4 steps" in says.evidence


def test_give_way_never_triggered_when_robot_stays_silent() -> None:
    trace = crossing_trace(say_excuse_me=False)
    found = _verdicts(tree_expectations("human1", GIVE_WAY_XML), trace)
    assert found["human1: IsRobotVisible succeeds"].passed
    says = found["human1: RobotSays(EXCUSE ME) succeeds"]
    assert not says.passed and "the robot's gestures were none" in says.evidence
    give = found["human1 gives way while the robot passes"]
    assert not give.passed and "never ran" in give.evidence and "mostly ran RegularNav" in give.evidence


def test_make_gesture_wait_is_timed_by_the_gesture_not_by_makegesture_zero() -> None:
    # MakeGesture(0) runs from t = 0.1; WAIT (1) is shown only from t = 21.85 s.
    t = np.round(np.arange(0, 23.0, 0.05), 3)
    n = len(t)
    gest = np.zeros((n, 1), np.int8)
    gest[t >= 21.85] = 1
    actions = {(k, 0): "MakeGesture" for k in range(2, n)}
    fired = {(k, 0): ["IsRobotNearby"] for k in range(n) if t[k] >= 21.8}
    names = ["MakeGesture", "IsRobotNearby"]
    trace = build_trace(t, np.zeros((n, 2)), np.ones((n, 1, 2)), dt=0.05, node_names=names, actions=actions,
                        fired=fired, human_gesture=gest)
    exps = tree_expectations("human1", WAIT_TREE)
    wait = _verdicts(exps, trace)["human1 executes MakeGesture(message=1)"]
    assert wait.passed and wait.time == pytest.approx(21.85)
    assert "MakeGesture(WAIT) first at t=21.85 s" in wait.evidence
    # the same run on a copy where WAIT can never fire: only MakeGesture(0) runs
    silent = build_trace(t, np.zeros((n, 2)), np.ones((n, 1, 2)), dt=0.05, node_names=names, actions=actions,
                         fired=fired)
    never = _verdicts(exps, silent)["human1 executes MakeGesture(message=1)"]
    assert not never.passed and "MakeGesture(WAIT) never ran" in never.evidence


def test_reaction_before_its_cause_fails() -> None:
    # GiveWaytoRobot runs at t = 2..3 (the robot 6 m away: a wide passing distance lets it count);
    # its causes IsRobotVisible (within 4 m, head-on) and RobotSays(4) hold only from t = 3.0 and 3.5.
    trace = crossing_trace()
    for k in (4, 5, 6):
        trace.action[k, 0] = trace.node_names.index("GiveWaytoRobot")
    exp = next(e for e in tree_expectations("human1", GIVE_WAY_XML) if e.node == "GiveWaytoRobot")
    exp = exp.model_copy(update={"within": 10.0})
    ((finding, before),) = evaluate([exp], trace)
    assert not finding.passed and before
    assert "first at t=2.00 s, before its cause IsRobotVisible held (first at t=3.0 s)" in finding.evidence


def test_give_way_far_from_the_robot_is_not_passing() -> None:
    t = np.arange(5) * 0.5
    trace = build_trace(t, np.stack([t, 0 * t], 1), np.stack([10 - 0 * t, 0 * t], 1)[:, None, :],
                        actions={(k, 0): "GiveWaytoRobot" for k in range(3)})
    exp = Expectation(kind="gives_way_while_passing", name="gw", source="tree", human="human1", node="GiveWaytoRobot")
    ((f, _),) = evaluate([exp], trace)
    assert not f.passed and "GiveWaytoRobot with the robot within 2.5 m never ran" in f.evidence


def test_any_gesture_card_criterion() -> None:
    t = np.arange(4) * 0.5
    gest = np.array([[0], [3], [3], [0]])
    trace = build_trace(t, np.zeros((4, 2)), np.ones((4, 1, 2)), human_gesture=gest)
    anyg = Expectation(kind="executes", name="g", source="card", human="human1", node="MakeGesture")
    assert evaluate([anyg], trace)[0][0].passed
    silent = build_trace(t, np.zeros((4, 2)), np.ones((4, 1, 2)), actions={(k, 0): "MakeGesture" for k in range(4)})
    ((f0, _),) = evaluate([anyg], silent)
    assert not f0.passed and "MakeGesture(any gesture) never ran" in f0.evidence
