"""The facts behind "did not react as asked" (verify/blame_tree.py): which actions ran and which conditions held
while the robot was near, and a gate that only ever held together with its veto (round 22's warehouse_17: the
shift leader's IsRobotBlocking held only while RobotMoved did, so `Inverter(RobotMoved)` never let him wait)."""

from __future__ import annotations

import numpy as np

from socnavgen.verify.blame_tree import tree_activity
from socnavgen.verify.signals import Signals

from .verify_builders import NODE_NAMES, build_trace

T = np.arange(0, 10.0 + 1e-9, 0.5)  # 21 steps


def _signals(fired: dict[int, list[str]], moving_until: float = 10.0) -> Signals:
    """The robot drives east toward a person standing at x = 6 and stops at x = 4.5 at `moving_until`."""
    robot_x = np.interp(T, [0.0, moving_until, 10.0], [0.0, 4.5, 4.5])
    robot = np.stack([robot_x, np.zeros_like(T)], 1)
    human = np.tile([6.0, 0.0], (len(T), 1))[:, None]
    actions = {(k, 0): "RegularNav" for k in range(len(T))}
    return Signals(build_trace(T, robot, human, actions=actions, node_names=[*NODE_NAMES, "IsRobotBlocking", "RobotMoved"],
                               fired={(k, 0): names for k, names in fired.items()}))


def test_a_gate_that_holds_only_with_its_veto_is_named() -> None:
    near_steps = range(12, 21)  # robot within 3 m of the person from x ~ 3 on (t >= 6 s)
    s = _signals({k: ["IsRobotBlocking", "RobotMoved"] for k in near_steps})
    near = s.get("dist_human1") <= 3.0
    text = tree_activity(s, "human1", near, 3.0)
    assert "RegularNav" in text and "IsRobotBlocking" in text and "RobotMoved" in text
    assert "held on every step" in text, text


def test_conditions_that_hold_apart_are_listed_without_a_veto() -> None:
    s = _signals({**{k: ["IsRobotBlocking"] for k in range(12, 21)}, **{k: ["RobotMoved"] for k in range(0, 14)}})
    near = s.get("dist_human1") <= 3.0
    text = tree_activity(s, "human1", near, 3.0)
    assert "IsRobotBlocking" in text and "held on every step" not in text, text


def test_a_condition_that_never_held_near_the_robot_is_not_claimed() -> None:
    s = _signals({k: ["IsRobotVisible"] for k in range(0, 5)})  # only while the robot was still far
    near = s.get("dist_human1") <= 3.0
    text = tree_activity(s, "human1", near, 3.0)
    assert "conditions that held then: none" in text, text
    assert tree_activity(s, "human1", np.zeros(len(T), dtype=bool), 3.0) == ""


def test_the_loop_compares_findings_without_the_tree_facts() -> None:
    """A changed tree changes what its tree did, not what happened: the --verify loop's "the same findings came
    back" (which sends them on to stage 1) must not see the facts, and must still see a changed outcome."""
    from socnavgen.proposal.verify_loop import same_findings
    from socnavgen.verify.blame_tree import FACTS_CLOSE, FACTS_OPEN

    def finding(closest: float, facts: str) -> str:
        return (f"gives way (human2): closest {closest} m at t=11.9 s - fix: the robot came near human2 but human2 did "
                f"not react as asked (gives_way){FACTS_OPEN}{facts}{FACTS_CLOSE}")

    one = finding(1.18, "while the robot was within 2 m (t=7.0-15.9 s) its tree ran GiveWaytoRobot 9.0 s")
    other = finding(1.18, "while the robot was within 2 m (t=6.1-12.0 s) its tree ran RegularNav 5.9 s, LookAtRobot 1 s")
    assert same_findings([one], [other])
    assert not same_findings([one], [finding(2.6, "while the robot was within 2 m its tree ran RegularNav 5.9 s")])
