"""Expectations judged on hand-built traces: pass and fail cases, with the evidence."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.expectations import tree_expectations
from socnavgen.verify.models import Expectation, VerifySettings

from .verify_builders import GIVE_WAY_XML, NODE_WORLD, build_trace, crossing_trace


def meet(point=NODE_WORLD["b2"]) -> Expectation:
    return Expectation(kind="meets_human", name="meet", source="paths", human="human1", point=point, point_id="b2")


def goal() -> Expectation:
    return Expectation(kind="robot_reaches_goal", name="goal", source="paths", point=NODE_WORLD["c3"],
                       point_id="c3")


def test_meeting_at_the_interaction_point() -> None:
    # Closest approach: t = 5 s, both at x = 6.025 (b2), 1.0 m apart; first within 2.5 m at
    # |dx| = sqrt(2.5^2 - 1) = 2.29 -> dx = 10 - 2t <= 2.29 -> t >= 3.85 -> first step t = 4.0.
    (f,) = evaluate([meet()], crossing_trace())
    assert f.passed
    assert f.time == pytest.approx(5.0) and f.distance == pytest.approx(1.0)
    assert "met at t=4.0 s" in f.evidence and "interaction point b2" in f.evidence


def test_meeting_far_from_the_interaction_point_fails() -> None:
    # Same encounter but the point is d4 (2.25 m above b2)... still within 3 m of the midpoint (y 3.475):
    # distance 1.75 -> passes; with near = 1.0 it must fail and say how far the meeting was.
    exp = meet(point=NODE_WORLD["d4"]).model_copy(update={"point_id": "d4"})
    assert evaluate([exp], crossing_trace())[0].passed
    (f,) = evaluate([exp], crossing_trace(), VerifySettings(near=1.0))
    assert not f.passed
    assert "m from interaction point d4 (needs <= 1 m)" in f.evidence
    assert f.time == pytest.approx(5.0) and f.distance == pytest.approx(1.0)  # the closest approach overall


def test_robot_that_never_arrives_fails_with_evidence() -> None:
    # Robot stops at x = 1.5 (t 0.5); the human walks on to x = 1.025 and passes it at t = 9.5, 1.0 m apart.
    # Within 2.5 m needs |dx| <= 2.29, i.e. human x <= 3.79: midpoint x <= 2.65, >= 3.38 m from b2 (> 3 m).
    trace = crossing_trace(robot_stops_at=1.5)
    f_meet, f_goal = evaluate([meet(), goal()], trace)
    assert not f_meet.passed
    assert f_meet.time == pytest.approx(9.5) and f_meet.distance == pytest.approx(1.0)
    assert "closest approach 1.00 m" in f_meet.evidence and "robot came within 4.5 m of the point" in f_meet.evidence
    assert not f_goal.passed and f_goal.distance == pytest.approx(9.525, abs=0.006)
    assert "m from the goal" in f_goal.evidence and "timeout" in f_goal.evidence
    # finite-difference speed is 0 from t = 1.0 on; at t = 1.0 the human (x 10.025) is 8.6 m away: not blocked
    assert "stood still for the last 9.0 s, from t=1.0 s" in f_goal.evidence and "(blocked)" not in f_goal.evidence


def test_robot_reaches_goal_passes() -> None:
    (f,) = evaluate([goal()], crossing_trace())
    # x = 1.025 + t reaches 11.025 - 0.5 at t = 9.5
    assert f.passed and f.time == pytest.approx(9.5) and f.distance == pytest.approx(0.5)


def test_tree_nodes_fire() -> None:
    trace = crossing_trace()
    findings = {f.node: f for f in evaluate(tree_expectations("human1", GIVE_WAY_XML), trace)}
    # IsRobotVisible(4): dist = hypot(10 - 2t, 1) <= 4 from t = 3.5 (dx 3) to t = 6.5 -> 7 steps
    assert findings["IsRobotVisible"].passed and findings["IsRobotVisible"].time == pytest.approx(3.5)
    assert "7 steps" in findings["IsRobotVisible"].evidence
    # RobotSays(4) on t = 3.5 .. 5.0 (4 steps); GiveWay on the same steps, first at t 3.5, robot 3.16 m away
    # -> outside the 3 m passing distance, so the first PASSING step is t = 4.0 at hypot(2, 1) = 2.236 m.
    assert findings["RobotSays"].passed and "4 steps" in findings["RobotSays"].evidence
    give = findings["GiveWaytoRobot"]
    assert give.passed and give.time == pytest.approx(4.0) and give.distance == pytest.approx(2.24)


def test_give_way_never_triggered_when_robot_stays_silent() -> None:
    trace = crossing_trace(say_excuse_me=False)
    findings = {f.node: f for f in evaluate(tree_expectations("human1", GIVE_WAY_XML), trace)}
    assert findings["IsRobotVisible"].passed
    assert not findings["RobotSays"].passed
    assert "RobotSays never succeeded" in findings["RobotSays"].evidence
    assert "the robot's gestures were none" in findings["RobotSays"].evidence
    assert not findings["GiveWaytoRobot"].passed
    assert "human1: GiveWaytoRobot never ran" in findings["GiveWaytoRobot"].evidence
    assert "mostly ran RegularNav" in findings["GiveWaytoRobot"].evidence


def test_give_way_far_from_the_robot_is_not_passing() -> None:
    # GiveWaytoRobot executes only at t = 0 .. 1 (robot 8..10 m away): ran, but not while passing.
    t = np.arange(5) * 0.5
    trace = build_trace(t, np.stack([t, 0 * t], 1), np.stack([10 - 0 * t, 0 * t], 1)[:, None, :],
                        actions={(k, 0): "GiveWaytoRobot" for k in range(3)})
    exp = Expectation(kind="gives_way_while_passing", name="gw", source="tree", human="human1", node="GiveWaytoRobot")
    (f,) = evaluate([exp], trace)
    assert not f.passed and "3 steps but never with the robot within 3 m" in f.evidence
    assert f.distance == pytest.approx(9.0)  # closest while giving way: robot at x 1.0 (t 1.0)


def test_gesture_shown() -> None:
    t = np.arange(4) * 0.5
    gest = np.array([[0], [3], [3], [0]])
    trace = build_trace(t, np.zeros((4, 2)), np.ones((4, 1, 2)), human_gesture=gest)
    exp = Expectation(kind="executes", name="g", source="tree", human="human1", node="MakeGesture", message=3)
    (f,) = evaluate([exp], trace)
    assert f.passed and f.time == pytest.approx(0.5) and "EXCUSE ME" in f.evidence
    exp1 = exp.model_copy(update={"message": 1})
    assert not evaluate([exp1], trace)[0].passed
    # a card's "executes MakeGesture" (no code): any non-zero gesture; running MakeGesture(0) does not count
    anyg = exp.model_copy(update={"message": None})
    assert evaluate([anyg], trace)[0].passed
    silent = build_trace(t, np.zeros((4, 2)), np.ones((4, 1, 2)), actions={(k, 0): "MakeGesture" for k in range(4)})
    (f0,) = evaluate([anyg], silent)
    assert not f0.passed and "MakeGesture(any gesture) never ran" in f0.evidence


def test_group_together_and_apart() -> None:
    # two members 1 m apart for 8 of 10 samples, then 5 m apart: 80 % -> passes at fraction 0.8, fails at 0.9
    t = np.arange(10) * 1.0
    a = np.stack([t, np.zeros(10)], 1)
    b = a + np.array([0.0, 1.0])
    b[8:, 1] = 5.0
    trace = build_trace(t, np.zeros((10, 2)) - 20, np.stack([a, b], 1), groups=[1, 1])
    exp = Expectation(kind="group_together", name="grp", source="paths", human="human1,human2")
    (f,) = evaluate([exp], trace)
    assert f.passed and "80% of the time" in f.evidence and f.distance == pytest.approx(5.0)
    assert f.time == pytest.approx(8.0)
    assert not evaluate([exp], trace, VerifySettings(group_fraction=0.9))[0].passed


def test_any_human_card_criterion() -> None:
    # card "meets_human within 2.0" without a named human: passes when any human comes within 2 m
    trace = crossing_trace()
    exp = Expectation(kind="meets_human", name="card", source="card", human=None, within=2.0)
    (f,) = evaluate([exp], trace)
    assert f.passed and f.human == "human1" and f.distance == pytest.approx(1.0)
    tight = exp.model_copy(update={"within": 0.5})
    (f2,) = evaluate([tight], trace)
    assert not f2.passed and "closest approach 1.00 m" in f2.evidence


def test_robot_blocked_by_a_human() -> None:
    # The robot drives at 1 m/s from x = 3 to x = 5 (t = 2 s) and stays there; human1 stands at x = 6, 1.0 m
    # ahead; the goal is at x = 9 (4 m away at the end): not reached, the reason names the human and says blocked.
    t = np.arange(9) * 0.5
    rx = np.minimum(3 + t, 5.0)
    trace = build_trace(t, np.stack([rx, 0 * t], 1), np.stack([6 + 0 * t, 0 * t], 1)[:, None, :],
                        end_reason="timeout")
    exp = Expectation(kind="robot_reaches_goal", name="goal", source="paths", point=(9.0, 0.0))
    (f,) = evaluate([exp], trace)
    assert not f.passed and f.distance == pytest.approx(4.0)
    assert "1.00 m from human1 (blocked)" in f.evidence
