"""Blame goes where the fault is when the robot does not get to its goal (issue 25 part 3, round 10):

- hospital_04: a team of four whose paths end at the robot's goal stood round it, and the corrections asked one
  tree after the other to "let the robot through": a person standing at its own goal, at or next to the robot's
  goal, is the plan's (stage 2), never its tree's; a person standing in the robot's way mid-route still is;
- warehouse_07: the robot crept for 97 s with nobody near, and the correction blamed "a cue of its script" whose
  only cue has no wait: the script only when the trace's cue log shows a cue holding the robot then, else the
  simulator, which no stage can fix;
- hospital_06: a tree check said GiveWaytoRobot ran while its hint said the tree "never ran GiveWaytoRobot".
"""

from __future__ import annotations

import numpy as np

from socnavgen.run.models import HumanPlan, PathPlan
from socnavgen.run.spec import Criterion, CueTrigger, RobotCue, RobotScript, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.blame_tree import blame_tree_check
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace

T = np.arange(0, 40.0 + 1e-9, 0.5)
NODES = {"a": (0.0, 3.0), "m": (4.0, 3.0), "g": (8.0, 3.0), "far": (8.0, 9.0)}


def _held_short(person: tuple[float, float], node: str = "RegularNav") -> object:
    """The robot drives east from a (0, 3) toward its goal g (8, 3), reaches x = 5.5 at t = 11 s and stands there
    to the end, someone standing at `person` (in its way) the whole run, running `node`."""
    robot = np.stack([np.interp(T, [0.0, 11.0], [0.0, 5.5]), np.full_like(T, 3.0)], 1)
    trace = build_trace(T, robot, np.tile([person], (len(T), 1))[:, None], goal=NODES["g"],
                        actions={(k, 0): node for k in range(len(T))})
    trace.robot_waypoints = [NODES["a"], NODES["g"]]
    trace.robot[:, 2] = 0.0
    return trace


def _blame(trace: object, plan: PathPlan | None, spec: ScenarioSpec | None = None,
           kind: str = "no_deadlock") -> tuple[str, str | None, str]:
    spec = spec or ScenarioSpec()
    s = Signals(trace, goal_radius=0.3, places={f"node_{n}": p for n, p in NODES.items()})
    cc = compile_criterion(Criterion(id="c", kind=kind, text="t"), spec, VerifySettings(), 0.3)
    return blame_criterion(cc, s, spec, plan, 10.0)


def _plan(goal: str) -> PathPlan:
    return PathPlan(robot=["a", "m", "g"], humans=[HumanPlan(name="human1", path=["far", goal])])


def test_a_person_standing_at_its_own_goal_by_the_robots_goal_is_the_plans() -> None:
    for kind in ("no_deadlock", "robot_reaches_goal"):
        blame, who, reason = _blame(_held_short((6.8, 3.0)), _plan("g"), kind=kind)  # 1.2 m short of g, its goal
        assert (blame, who) == ("paths", None), reason
        assert "human1's path ends at g, on the robot's goal" in reason and "its own goal" in reason
        assert "no tree can change" in reason and "let the robot through" not in reason


def test_a_person_standing_in_the_robots_way_mid_route_is_still_the_trees() -> None:
    # the same person, the same place, but its path ends far off the robot's goal: standing here is its tree's doing
    blame, who, reason = _blame(_held_short((6.8, 3.0)), _plan("far"))
    assert (blame, who) == ("behaviors", "human1") and "let the robot through" in reason
    # ... and at the goal but held there by a node of its tree (a gesture), not by its walk: the tree's
    blame, who, _ = _blame(_held_short((6.8, 3.0), node="MakeGesture"), _plan("g"))
    assert (blame, who) == ("behaviors", "human1")


def _stands_alone(log: list | None, cues: list[RobotCue], speed: float = 0.5) -> tuple[str, str | None, str]:
    """The robot drives from a to 5.5 m by t = 11 s and stands there to t = 40 s, nobody anywhere near (one person
    far off the route); `log`: the trace's cue log (None: a trace without one)."""
    trace = _held_short((0.0, 9.0))
    if log is not None:
        trace.meta = {"script_cues_fired": log}
    spec = ScenarioSpec(script=RobotScript(speed=speed, cues=cues))
    return _blame(trace, _plan("far"), spec, kind="robot_reaches_goal")


ACK = RobotCue(trigger=CueTrigger(when="human_says", phrase="PROCEED"), say="ACKNOWLEDGED", hold=2.0)


def test_a_robot_standing_with_nobody_near_and_no_cue_holding_it_is_the_simulators() -> None:
    blame, _, reason = _stands_alone([[9.0, "human_says: say ACKNOWLEDGED"]], [ACK])
    assert blame == "simulator", reason
    assert "nobody in its way" in reason and "no cue of its script holding it" in reason
    assert "no stage of the model can fix it" in reason and "keeps it waiting" not in reason
    assert _stands_alone([], [ACK])[0] == "simulator"  # its cue never fired: nothing of the script held it


def test_a_cue_that_held_the_robot_then_is_the_scripts() -> None:
    wait = RobotCue(trigger=CueTrigger(when="after", seconds=9.0), wait=60.0)
    blame, _, reason = _stands_alone([[9.0, "after: wait 60 s"]], [wait])
    assert blame == "robot_script" and "cue 1" in reason and "waits until t=69.0 s" in reason, reason
    # a wait long over before the robot's last 10 s is not what holds it at the end
    short = RobotCue(trigger=CueTrigger(when="after", seconds=9.0), wait=5.0)
    assert _stands_alone([[9.0, "after: wait 5 s"]], [short])[0] == "simulator"
    # a cue that stops the robot (speed 0), the one that would set it going waiting for a phrase never said
    stop = RobotCue(trigger=CueTrigger(when="after", seconds=9.0), speed=0.0)
    go = RobotCue(trigger=CueTrigger(when="human_says", phrase="PROCEED"), speed=0.5)
    blame, _, reason = _stands_alone([[9.0, "after: speed 0"]], [stop, go])
    assert blame == "robot_script" and "set its speed to 0" in reason and "cue 2" in reason, reason


def test_without_a_cue_log_a_script_that_can_hold_the_robot_is_still_blamed() -> None:
    assert _stands_alone(None, [ACK])[0] == "robot_script"  # a trace from elsewhere: what the script could do
    assert _stands_alone(None, [])[0] == "paths"  # no cue can hold it: rule R2 as before


def test_a_give_way_that_ran_is_not_said_never_to_have_run() -> None:
    blame, who, reason = blame_tree_check("GiveWaytoRobot", None, "human1", None, False, ran_at=45.15)
    assert (blame, who) == ("behaviors", "human1")
    assert "ran GiveWaytoRobot (from t=45.1 s)" in reason and "never ran" not in reason
    assert blame_tree_check("GiveWaytoRobot", None, "human1", None, False)[2] == "human1's tree never ran GiveWaytoRobot"


def test_a_person_held_up_on_the_way_to_a_goal_behind_the_robot_is_not_at_its_goal() -> None:
    # home exiting-room: she stands in the door on her way to her goal g2 in the room behind the robot (the robot
    # between her and it, her goal within the area round the robot's goal): held up on her way, not arrived
    NODES["g2"] = (4.5, 3.0)
    try:
        blame, who, reason = _blame(_held_short((6.8, 3.0)), _plan("g2"))
    finally:
        del NODES["g2"]
    assert (blame, who) == ("behaviors", "human1"), reason
    assert "its own goal" not in reason


def test_a_robot_standing_short_of_its_goal_beside_someone_says_who_stands_there() -> None:
    """Round 30 (home_24): the robot froze short of a doorway 1.1 m from a child standing beside its approach, and the
    correction said 'nobody in its way ... check the route's last nodes', so the player re-planned the wrong thing.
    Someone within the held-up distance beside its way is named, with what to change; with nobody near, the route."""
    beside, reason = _blame(_held_short((6.2, 4.0)), _plan("far"), kind="robot_reaches_goal")[::2]
    assert beside == "paths" and "with human1 within 3 m of it, beside its way" in reason, reason
    assert "nobody" not in reason and "check the route's last nodes" not in reason
    alone, reason = _blame(_held_short((6.0, 9.0)), _plan("far"), kind="robot_reaches_goal")[::2]
    assert alone == "paths" and "nobody near it" in reason and "human1" not in reason, reason
