"""Leniencies found by eye on scenarios nobody here wrote (issue 25, eval-074), each as a trace the old verifier
passed and that must FAIL:

- a robot standing 24 s in front of a person who never steps aside, 2 m away (the script's `wait_until_clear`
  waits for exactly such a person) is deadlocked: "held up" is one notion, proxemics.HELD_UP_DISTANCE, not a
  1 m gap for the verifier and 3 m for the script;
- a person whose GiveWaytoRobot node ran after EXCUSE ME but whose body stayed in the robot's way did not give
  way (reacts_after_phrase with reaction give_way, and the tree check without spec.json, are judged by `aside`,
  what the body did); a stop lasts 1 s; a robot turning toward someone already off its route does not undo their
  step aside.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from socnavgen import proxemics
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.sim.robot import script
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.evaluate import evaluate
from socnavgen.verify.models import Expectation, VerifySettings
from socnavgen.verify.signals import Signals, aside
from socnavgen.verify.stl import monitor

from .verify_builders import build_trace

T = np.arange(0, 30.0 + 1e-9, 0.5)


def _judge(kind: str, trace, **fields) -> bool:  # noqa: ANN001
    c = Criterion(id="c", kind=kind, text="t", **fields)
    cc = compile_criterion(c, ScenarioSpec(), VerifySettings(), 0.5)
    return monitor(cc.formula, Signals(trace, goal_radius=0.5)).passed


def _standoff(person_x: float) -> object:
    """The robot drives +x from x = 1 for 2 s, then stands at x = 3 for 28 s; human1 stands at (person_x, 3)
    the whole run, straight ahead on the robot's route to (11, 3)."""
    rx = np.interp(T, [0, 2, 30], [1.0, 3.0, 3.0])
    robot = np.stack([rx, np.full_like(T, 3.0)], 1)
    human = np.tile([[person_x, 3.0]], (len(T), 1))[:, None]
    trace = build_trace(T, robot, human, goal=(11.0, 3.0))
    trace.robot[:, 2] = 0.0  # facing +x, also while standing
    trace.humans[:, :, 2] = np.pi  # facing the robot
    trace.robot_waypoints = [(1.0, 3.0), (11.0, 3.0)]
    return trace


def test_script_and_verifier_share_one_held_up_distance() -> None:
    assert not hasattr(script, "CLEAR_DISTANCE") and not hasattr(proxemics, "BLOCK_GAP_VERIFY")
    assert "proxemics.HELD_UP_DISTANCE" in Path(script.__file__).read_text(encoding="utf-8")


def test_standing_28_s_two_metres_short_of_someone_in_the_way_is_a_deadlock() -> None:
    """Centres 2 m apart (gap 1.25 m: the old verifier's 1 m gap saw nobody holding the robot up)."""
    trace = _standoff(5.0)
    dead = Signals(trace, goal_radius=0.5).get("deadlock")
    assert dead.max() >= 27.5
    assert not _judge("no_deadlock", trace, seconds=20.0)


def test_someone_beyond_the_held_up_distance_holds_nobody_up() -> None:
    trace = _standoff(3.0 + proxemics.HELD_UP_DISTANCE + 0.5)
    assert Signals(trace, goal_radius=0.5).get("deadlock").max() == 0.0
    assert _judge("no_deadlock", trace, seconds=20.0)


def _phrase_trace(steps_aside: bool) -> object:
    """The robot stands at x = 3 facing +x, says EXCUSE ME (code 4) from t = 2 to 5 s; human1 stands in its way at
    (4.5, 3) and its GiveWaytoRobot node runs from t = 2.5 to 3.5 s. `steps_aside`: it then walks 1 m off the
    route (y 3 -> 4) between t = 3 and 5 s; else its body stays where it was."""
    robot = np.stack([np.full_like(T, 3.0), np.full_like(T, 3.0)], 1)
    hy = np.interp(T, [0, 3, 5, 30], [3.0, 3.0, 4.0, 4.0]) if steps_aside else np.full_like(T, 3.0)
    human = np.stack([np.full_like(T, 4.5), hy], 1)[:, None]
    gesture = np.where((T >= 2.0) & (T <= 5.0), 4, 0)
    actions = {(k, 0): "GiveWaytoRobot" if 2.5 <= T[k] <= 3.5 else "RegularNav" for k in range(len(T))}
    trace = build_trace(T, robot, human, actions=actions, robot_gesture=gesture, goal=(11.0, 3.0))
    trace.robot[:, 2] = 0.0
    trace.robot_waypoints = [(3.0, 3.0), (11.0, 3.0)]
    return trace


def test_a_give_way_node_without_the_body_moving_is_no_reaction() -> None:
    assert not _judge("reacts_after_phrase", _phrase_trace(False), human="human1", phrase="EXCUSE ME",
                      reaction="give_way")


def test_stepping_off_the_route_after_the_phrase_is_the_reaction() -> None:
    assert _judge("reacts_after_phrase", _phrase_trace(True), human="human1", phrase="EXCUSE ME",
                  reaction="give_way")


def _walker(stop: tuple[float, float]) -> object:
    """The robot stands at (3, 3) and says EXCUSE ME (code 4) from t = 2 to 5 s; human1 walks north at 0.5 m/s
    along x = 6 from (6, -2), and stands still (velocity zero, position held) from stop[0] to stop[1] s."""
    robot = np.tile([[3.0, 3.0]], (len(T), 1))
    walked = 0.5 * (T - np.clip(T - stop[0], 0.0, stop[1] - stop[0]))  # metres walked by each time
    human = np.stack([np.full_like(T, 6.0), -2.0 + walked], 1)[:, None]
    gesture = np.where((T >= 2.0) & (T <= 5.0), 4, 0)
    trace = build_trace(T, robot, human, robot_gesture=gesture, goal=(11.0, 3.0))
    still = np.abs(T - 0.5 * (stop[0] + stop[1])) <= 0.5 * (stop[1] - stop[0]) + 1e-9
    trace.humans[still, 0, 3:5] = 0.0
    return trace


def test_a_one_step_dip_in_speed_is_no_stop() -> None:
    """A stop must last STOP_HOLD (1 s): zero speed on one 0.5 s step after EXCUSE ME is no reaction."""
    assert not _judge("reacts_after_phrase", _walker((4.0, 4.0)), human="human1", phrase="EXCUSE ME",
                      reaction="stop")
    assert _judge("reacts_after_phrase", _walker((4.0, 6.0)), human="human1", phrase="EXCUSE ME", reaction="stop")


def test_the_tree_check_gives_way_needs_the_body_out_of_the_way() -> None:
    """Without spec.json the tree check 'gives way while the robot passes' is required: a GiveWaytoRobot node
    that ran while the body stayed in the robot's way is no giving way (the old check counted the node)."""
    exp = Expectation(kind="gives_way_while_passing", name="gw", source="tree", human="human1", node="GiveWaytoRobot")
    ((stayed, _),) = evaluate([exp], _phrase_trace(False))
    assert not stayed.passed and "never got out of the robot's way" in stayed.evidence
    ((stepped, _),) = evaluate([exp], _phrase_trace(True))
    assert stepped.passed


def _route_trace(human_xy: np.ndarray, robot_x: np.ndarray, yaw: np.ndarray) -> object:
    robot = np.stack([robot_x, np.full_like(T, 3.0)], 1)
    trace = build_trace(T, robot, human_xy[:, None], goal=(11.0, 3.0))
    trace.robot[:, 2] = yaw
    trace.robot_waypoints = [(1.0, 3.0), (11.0, 3.0)]
    return trace


def test_a_robot_turning_toward_someone_who_stepped_off_its_route_does_not_undo_the_step() -> None:
    """human1 stands on the route at (6, 3), steps 1.2 m off it (y 4.2) at t 3-4 s; the robot, stopped at x = 3.5,
    turns toward them (yaw 25 degrees) from t = 6 to 8 s, then back along its route: while it faces them they are
    ahead of it, once it faces its route again they are aside again (the old signal lost them for good)."""
    human = np.stack([np.full_like(T, 6.0), np.interp(T, [0, 3, 4, 30], [3.0, 3.0, 4.2, 4.2])], 1)
    yaw = np.where((T >= 6.0) & (T < 8.0), np.radians(25.0), 0.0)
    out = aside(Signals(_route_trace(human, np.interp(T, [0, 3, 30], [1.0, 3.5, 3.5]), yaw)), "human1")
    assert out[(T >= 4.0) & (T < 6.0)].all() and out[T >= 8.0].all() and not out[T < 3.0].any()


def _walk_trace(walks: bool) -> object:
    """The robot stands at (3, 3) and says EXCUSE ME from t = 2 to 5 s; human1 at (4.5, 3) runs RegularNav from
    t = 2.5 s (LookAtRobot before); `walks`: it walks off north at 0.5 m/s from 2.5 s, else it stays put."""
    robot = np.tile([[3.0, 3.0]], (len(T), 1))
    hy = 3.0 + (0.5 * np.clip(T - 2.5, 0.0, None) if walks else 0.0 * T)
    human = np.stack([np.full_like(T, 4.5), hy], 1)[:, None]
    actions = {(k, 0): "RegularNav" if T[k] >= 2.5 else "IsRobotVisible" for k in range(len(T))}
    return build_trace(T, robot, human, actions=actions, robot_gesture=np.where((T >= 2.0) & (T <= 5.0), 4, 0),
                       goal=(11.0, 3.0))


def test_a_walking_reaction_needs_the_body_to_walk() -> None:
    """walk_past (and follow, join, avoid) count their node only while the body walks (> 0.3 m/s): a RegularNav
    that stands still after EXCUSE ME is no walking on (the old verifier counted the node)."""
    assert not _judge("reacts_after_phrase", _walk_trace(False), human="human1", phrase="EXCUSE ME",
                      reaction="walk_past")
    assert _judge("reacts_after_phrase", _walk_trace(True), human="human1", phrase="EXCUSE ME", reaction="walk_past")


def _ran_in_then_blocked(reacts_after: bool) -> object:
    """human1 runs in (RegularNav, walking 1 m/s) for 2 s, then stands in front of the robot (IsRobotVisible);
    the robot says EXCUSE ME from t = 4 to 6 s; `reacts_after`: human1 walks off (RegularNav) from 5 s, else it
    stays put."""
    robot = np.tile([[3.0, 3.0]], (len(T), 1))
    run_in = np.clip(T, 0.0, 2.0)
    off = 0.8 * np.clip(T - 5.0, 0.0, None) if reacts_after else 0.0 * T
    human = np.stack([np.full_like(T, 4.5), 1.0 + run_in + off], 1)[:, None]
    walking = (T < 2.0) | ((T >= 5.0) & reacts_after)
    actions = {(k, 0): "RegularNav" if walking[k] else "IsRobotVisible" for k in range(len(T))}
    return build_trace(T, robot, human, actions=actions, robot_gesture=np.where((T >= 4.0) & (T <= 6.0), 4, 0),
                       goal=(11.0, 3.0))


def test_a_reaction_to_a_phrase_is_judged_at_the_phrase_not_from_the_start() -> None:
    """Walking before the robot spoke (a child who ran in, then stood in its way) is no reaction to EXCUSE ME;
    walking off after it is. Walking on through the phrase without stopping is no reaction to it either."""
    assert _judge("reacts_after_phrase", _ran_in_then_blocked(True), human="human1", phrase="EXCUSE ME",
                  reaction="walk_past")
    assert not _judge("reacts_after_phrase", _ran_in_then_blocked(False), human="human1", phrase="EXCUSE ME",
                      reaction="walk_past")
    robot = np.tile([[3.0, 3.0]], (len(T), 1))
    human = np.stack([np.full_like(T, 4.5), 0.5 + 0.6 * T], 1)[:, None]  # walks past the whole time
    through = build_trace(T, robot, human, actions={(k, 0): "RegularNav" for k in range(len(T))},
                          robot_gesture=np.where((T >= 4.0) & (T <= 6.0), 4, 0), goal=(11.0, 3.0))
    assert not _judge("reacts_after_phrase", through, human="human1", phrase="EXCUSE ME", reaction="walk_past")


def _child_trace(stands_at: float | None) -> object:
    """The robot stands at (3, 3) and says EXCUSE ME from t = 4 to 7 s; human1 walks (RegularNav, 0.5 m/s) from
    (7, 3) toward it until t = 2.5 s (to 5.75, 3); `stands_at`: it stands there until this time,
    (standing: MakeGesture) then walks off north; None: it never stops (walks north from t = 2.5 s, through the phrase)."""
    stop = 2.5 if stands_at is None else stands_at
    hx = np.interp(T, [0.0, 2.5], [7.0, 5.75])
    hy = 3.0 + 0.5 * np.clip(T - stop, 0.0, None) * (T >= 2.5)
    human = np.stack([hx, hy], 1)[:, None]
    standing = stands_at is not None
    actions = {(k, 0): "MakeGesture" if standing and 2.5 <= T[k] < stop else "RegularNav" for k in range(len(T))}
    return build_trace(T, np.tile([[3.0, 3.0]], (len(T), 1)), human, actions=actions,
                       robot_gesture=np.where((T >= 4.0) & (T <= 7.0), 4, 0), goal=(11.0, 3.0))


def test_walking_on_after_the_phrase_is_judged_at_the_phrase() -> None:
    """walk_past after EXCUSE ME "and not before": a child who walked to its place, stood in the robot's way and
    walked off after the phrase reacted after it (the old formula counted its walk to the place at t = 0 as
    walking on before the phrase); one who was walking when the robot spoke, or left before it, did not."""
    judge = {"human": "human1", "phrase": "EXCUSE ME", "reaction": "walk_past"}
    assert _judge("reacts_after_phrase", _child_trace(5.0), **judge)
    assert not _judge("reacts_after_phrase", _child_trace(None), **judge)  # walking through the phrase
    assert not _judge("reacts_after_phrase", _child_trace(3.5), **judge)  # left before the robot spoke
    assert not _judge("reacts_after_phrase", _child_trace(12.0), **judge)  # stood until 8 s after it: too late


def test_a_phrase_said_at_the_start_is_a_cause_too() -> None:
    """A cue at the start (FOLLOW ME at t = 0.1 s) leaves no quiet second before the phrase: a reaction 0.2 s after
    it is after it; one already going on from t = 0 is not."""
    robot = np.stack([np.clip(T, 0.0, 20.0) * 0.5 + 3.0, np.full_like(T, 3.0)], 1)
    gesture = np.where((T >= 0.1) & (T <= 3.0), 5, 0)  # FOLLOW ME

    def walker(from_t: float) -> object:
        hx = 1.0 + 0.5 * np.clip(T - from_t, 0.0, None)
        human = np.stack([hx, np.full_like(T, 3.0)], 1)[:, None]
        actions = {(k, 0): "RegularNav" if T[k] >= from_t else "IsRobotVisible" for k in range(len(T))}
        return build_trace(T, robot, human, actions=actions, robot_gesture=gesture, goal=(14.0, 3.0))

    judge = {"human": "human1", "phrase": "FOLLOW ME", "reaction": "walk_past"}
    assert _judge("reacts_after_phrase", walker(0.5), **judge)
    assert not _judge("reacts_after_phrase", walker(0.0), **judge)



def test_a_start_cue_follow_me_with_the_follower_going_0_2_s_later_passes() -> None:
    """hospital_07 (issue 25): the prompt's own example, a start cue saying FOLLOW ME (t = 0.1 s), the patient's
    FollowRobot walking from 0.3 s: after the phrase. A follower already walking at t = 0 did not react to it."""
    t = np.round(np.arange(0, 20.0 + 1e-9, 0.1), 2)
    robot = np.stack([t * 0.5 + 3.0, np.full_like(t, 3.0)], 1)
    gesture = np.where((t >= 0.1) & (t <= 3.0), 5, 0)  # FOLLOW ME

    def follower(from_t: float) -> object:
        hx = 1.0 + 0.5 * np.clip(t - from_t, 0.0, None)
        human = np.stack([hx, np.full_like(t, 3.0)], 1)[:, None]
        actions = {(k, 0): "FollowRobot" if t[k] >= from_t else "IsRobotVisible" for k in range(len(t))}
        return build_trace(t, robot, human, dt=0.1, node_names=["FollowRobot", "IsRobotVisible"], actions=actions,
                           robot_gesture=gesture, goal=(14.0, 3.0))

    judge = {"human": "human1", "phrase": "FOLLOW ME", "reaction": "follow"}
    assert _judge("reacts_after_phrase", follower(0.3), **judge)
    assert not _judge("reacts_after_phrase", follower(0.0), **judge)
