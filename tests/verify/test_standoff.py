"""Blame that names the standoff (issue 25, home_02 and home_06 of the new-request suite):

- a robot circling for 100 s in front of a 0.9 m bedroom door, where the resident stands just past the route's
  turn, is held up by her (on its route just ahead, round the bend) and deadlocked: the old `holding_up` looked
  along the robot's heading and the current leg only and saw nobody, and the failed goal was blamed "check the
  robot path" for a valid path;
- a deadlock the spec itself sets up (the robot's wait_until_clear cue fired with the person in its way; the
  person's encounter has it stop while the robot is there, with no `lasts`) is blamed on the spec, naming who,
  where, the gap and how long; a person whose spec reaction is to give way but who stays in the way is still the
  tree's fault.
"""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import CueTrigger, Encounter, HumanPart, RobotCue, RobotScript, ScenarioSpec
from socnavgen.verify.blame import blame_criterion
from socnavgen.verify.criteria import compile_criterion
from socnavgen.verify.models import VerifySettings
from socnavgen.verify.route import ahead_on_route
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace

T = np.arange(0, 40.0 + 1e-9, 0.5)
ROUTE = [(1.0, 3.0), (4.0, 3.0), (4.0, 7.0)]  # east along a hall, then north through a door at (4, 4)


def _circling(person: tuple[float, float], says: tuple[float, float] | None = None) -> object:
    """The robot drives east to (3.6, 3) by t = 5 s, then circles there (0.15 m radius) to the end, saying EXCUSE
    ME during `says` (from, to); the person stands at `person` the whole run."""
    x = np.interp(T, [0.0, 5.0], [1.0, 3.6])
    wiggle = np.where(T > 5.0, 0.15, 0.0)
    robot = np.stack([x + wiggle * np.cos(T), 3.0 + wiggle * np.sin(T)], 1)
    lo, hi = says or (-1.0, -1.0)
    times = T
    gesture = np.where((times >= lo) & (times <= hi), 4, 0)
    trace = build_trace(T, robot, np.tile([person], (len(T), 1))[:, None], goal=ROUTE[-1], robot_gesture=gesture)
    trace.robot_waypoints = list(ROUTE)
    trace.humans[:, :, 2] = -np.pi / 2  # facing the robot
    return trace


def _signals(trace: object) -> Signals:
    return Signals(trace, goal_radius=0.3, places={f"node_{n}": p for n, p in zip("abc", ROUTE, strict=True)})


def test_someone_on_the_route_just_past_its_turn_holds_the_robot_up() -> None:
    in_door = _signals(_circling((4.0, 4.3)))  # 1.3 m from the robot, off its heading and its current leg
    assert in_door.in_way(0)[20:].mean() < 0.5  # along its heading only now and then, as it circles
    assert in_door.get("deadlock").max() >= 30.0
    beside = _signals(_circling((5.4, 4.3)))  # as far, but 1.4 m beside the route: nobody in its way
    assert beside.get("deadlock").max() < 10.0  # held up only when the circling robot faces it, never for long
    far = ahead_on_route(np.array([2.6]), np.array([[4.0, 6.9]]), ROUTE, 0.85, 3.0, 0.35)  # on the route, 4.3 m on
    level = ahead_on_route(np.array([2.6]), np.array([[2.7, 3.8]]), ROUTE, 0.85, 3.0, 0.35)  # beside it, 0.1 m on
    assert not far.any() and not level.any()


def _spec(part: HumanPart, wait_until_clear: bool = False) -> ScenarioSpec:
    cues = [RobotCue(trigger=CueTrigger(when="blocked", distance=2.0), say="EXCUSE ME", wait_until_clear=True)] \
        if wait_until_clear else []
    return ScenarioSpec(script=RobotScript(cues=cues), encounters=[
        Encounter(id="e1", place="DOORWAY", node="b", within=1.5, humans=[part])])


def _blame(spec: ScenarioSpec, kind: str = "no_deadlock",
           says: tuple[float, float] | None = None) -> tuple[str, str | None, str]:
    s = _signals(_circling((4.0, 4.3), says))
    from socnavgen.run.spec import Criterion

    cc = compile_criterion(Criterion(id="c", kind=kind, text="t"), spec, VerifySettings(), 0.3)
    return blame_criterion(cc, s, spec, None, 10.0)


def test_a_standoff_the_spec_sets_up_is_blamed_on_the_spec_with_who_where_and_how_long() -> None:
    stops = _spec(HumanPart(human="human1", trigger="robot_blocking", distance=2.0, reaction="stop"))
    for kind in ("no_deadlock", "robot_reaches_goal"):
        blame, who, reason = _blame(stops, kind)
        assert blame == "spec", reason
        assert "human1" in reason and "node b" in reason and "gap" in reason and "s from t=" in reason
        assert "check the robot path" not in reason
    # home_06: she is to walk past a robot that waits until nobody is in its way (in a 1.2 m hallway)
    waits = _spec(HumanPart(human="human1", trigger="robot_blocking", distance=2.5, reaction="walk_past"),
                  wait_until_clear=True)
    blame, _, reason = _blame(waits, says=(4.5, 6.0))  # EXCUSE ME as the robot starts waiting
    assert blame == "spec" and "wait_until_clear" in reason, reason
    assert _blame(waits, says=(0.0, 0.5))[0] == "behaviors"  # said long before: that wait was over


def test_a_person_meant_to_give_way_who_stays_in_the_way_is_the_trees_fault() -> None:
    gives = _spec(HumanPart(human="human1", trigger="robot_blocking", reaction="give_way"))
    assert _blame(gives)[:2] == ("behaviors", "human1")
    lasting = _spec(HumanPart(human="human1", trigger="robot_blocking", reaction="stop", lasts=3.0))
    assert _blame(lasting)[:2] == ("behaviors", "human1")  # her stop ends after 3 s by the spec; the tree holds on


def _make_way(back_at: float | None) -> object:
    """human1 stands at (5, 3) on the robot's route (0, 3) -> (14, 3); the robot drives east, stops at x = 3.2 and
    says EXCUSE ME (5-6 s); human1 steps 1.2 m north from 6.5 s; the robot drives on from 8 s; `back_at`: human1
    steps back onto the route then (the robot stands again once it is 1.8 m short of her while she is there)."""
    t = np.arange(0, 40.0 + 1e-9, 0.25)
    hy = 3.0 + np.clip(0.6 * (t - 6.5), 0.0, 1.2)
    if back_at is not None:
        hy = np.where(t >= back_at, np.maximum(4.2 - 0.6 * (t - back_at), 3.0), hy)
    rx, x = np.zeros_like(t), 0.0
    for k in range(len(t)):
        blocked = hy[k] < 3.9 and x >= 5.0 - 1.8 - 1e-9 and x < 5.0
        if not blocked and not (x >= 3.2 and t[k] < 8.0):
            x = min(x + 0.5 * 0.25, 14.0)
        rx[k] = x
    trace = build_trace(t, np.stack([rx, np.full_like(t, 3.0)], 1), np.stack([np.full_like(t, 5.0), hy], 1)[:, None],
                        dt=0.25, goal=(14.0, 3.0), robot_gesture=np.where((t >= 5.0) & (t <= 6.0), 4, 0))
    trace.robot[:, 2] = 0.0
    trace.robot_waypoints = [(0.0, 3.0), (14.0, 3.0)]
    return trace


def test_giving_way_lets_the_robot_through() -> None:
    """hospital_08: a step aside undone by stepping back onto the robot's route before it got past is no giving
    way; stepping aside and staying there, or coming back once it has passed, is."""
    from socnavgen.run.spec import Criterion
    from socnavgen.verify.evidence import evidence
    from socnavgen.verify.stl import monitor

    def judged(trace: object) -> tuple[bool, str]:
        c = Criterion(id="c", kind="reacts_after_phrase", human="human1", phrase="EXCUSE ME", reaction="give_way",
                      text="t")
        cc = compile_criterion(c, ScenarioSpec(), VerifySettings(), 0.5)
        s = Signals(trace, goal_radius=0.5)
        return monitor(cc.formula, s).passed, evidence(cc, s)[0]

    assert judged(_make_way(None))[0]
    assert judged(_make_way(25.0))[0]  # back on the route once the robot is past her (x = 5 at about 12 s)
    passed, text = judged(_make_way(9.0))
    assert not passed
    assert "stepped aside at t=" in text and "back in the robot's way at t=9" in text, text


def test_a_goal_missed_by_a_slow_robot_says_so_not_check_the_path() -> None:
    """hospital_06: a patrol too long for the run; the robot never stopped and nobody held it up."""
    from socnavgen.run.spec import Criterion

    t = np.arange(0, 30.0 + 1e-9, 0.5)
    trace = build_trace(t, np.stack([0.3 * t, np.full_like(t, 3.0)], 1), np.tile([[5.0, 9.0]], (len(t), 1))[:, None],
                        goal=(20.0, 3.0), end_reason="timeout")
    trace.robot_waypoints = [(0.0, 3.0), (20.0, 3.0)]
    spec = ScenarioSpec()
    cc = compile_criterion(Criterion(id="g", kind="robot_reaches_goal", text="t"), spec, VerifySettings(), 0.3)
    blame, _, reason = blame_criterion(cc, Signals(trace, goal_radius=0.3), spec, None, 10.0)
    assert blame == "paths" and "still on its way" in reason and "11.0 m of its route left" in reason, reason


def test_a_person_meant_to_give_way_after_the_phrase_is_not_a_spec_standoff() -> None:
    """The robot waits until clear after EXCUSE ME, and the spec has the person give way to it: a person who stays
    is the tree's fault, not the spec's (tests/verify/corpus.py `deadlock`)."""
    waits = _spec(HumanPart(human="human1", trigger="robot_says", phrase="EXCUSE ME", reaction="give_way"),
                  wait_until_clear=True)
    assert _blame(waits, says=(4.5, 6.0))[:2] == ("behaviors", "human1")


def test_a_run_ending_with_someone_in_the_way_names_them() -> None:
    """The run ends 8 s into a wait (under the 10 s deadlock limit) with the resident on the route just past the
    turn: the goal's blame names her and the spec's stop rule, not the path."""
    from socnavgen.run.spec import Criterion

    trace = _circling((4.0, 4.3))
    short = trace.__class__(**{**trace.__dict__})
    n = int(np.searchsorted(T, 13.0))
    for name in ("t", "robot", "humans", "action", "succeeded", "human_gesture", "robot_gesture", "behavior_state"):
        setattr(short, name, getattr(trace, name)[:n])
    spec = _spec(HumanPart(human="human1", trigger="robot_blocking", distance=2.0, reaction="stop"))
    cc = compile_criterion(Criterion(id="g", kind="robot_reaches_goal", text="t"), spec, VerifySettings(), 0.3)
    blame, _, reason = blame_criterion(cc, _signals(short), spec, None, 10.0)
    assert blame == "spec" and "human1" in reason and "node b" in reason, reason


def test_a_robot_edging_about_at_the_timeout_was_stuck_not_slow() -> None:
    """hospital_10 (round 14): the robot edged about 0.4 m from a junction for its last 100 s, a family of four
    round it but none in its way by the verifier's notion; told "its route takes longer than the run" (the route
    was 19 s of a 120 s run). Stuck for its last 20 s with people beside it: the reason says so and names them."""
    from socnavgen.run.spec import Criterion

    t = np.arange(0, 30.0 + 1e-9, 0.5)
    x = np.interp(t, [0.0, 10.0], [0.0, 3.0]) + np.where(t > 10.0, 0.1 * np.sin(t), 0.0)
    people = np.stack([np.tile([[3.5, 4.2]], (len(t), 1)), np.tile([[4.8, 2.0]], (len(t), 1))], 1)
    trace = build_trace(t, np.stack([x, np.full_like(t, 3.0)], 1), people, goal=(20.0, 3.0), end_reason="timeout")
    trace.robot_waypoints = [(0.0, 3.0), (20.0, 3.0)]
    spec = ScenarioSpec()
    cc = compile_criterion(Criterion(id="g", kind="robot_reaches_goal", text="t"), spec, VerifySettings(), 0.3)
    blame, _, reason = blame_criterion(cc, Signals(trace, goal_radius=0.3), spec, None, 10.0)
    assert "no progress along its route for its last 20 s" in reason and "still on its way" not in reason, reason
    assert "human1" in reason and "human2" in reason, reason
