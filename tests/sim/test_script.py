"""The robot plays its script (spec.json cues), never pushes into people; bodies do not interpenetrate;
RobotSaid latches; the straight robot is rude on purpose; humans are paced to meet at their node."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bt.library import LIBRARY, ROBOT_GESTURES
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import BUILTIN, DEFAULT_ROBOT, PacingPlan, ThrottleConfig, load_policy
from socnavgen.sim.contact import overlapping
from socnavgen.sim.robot.api import ScriptedPolicy, StraightPolicy
from tests.sim.simhelpers import REGULAR, Drive, Stay, human, make_sim, nav_tree, tree_xml

EXCUSE_ME = next(k for k, v in ROBOT_GESTURES.items() if v == "EXCUSE ME")
FOLLOW_ME = next(k for k, v in ROBOT_GESTURES.items() if v == "FOLLOW ME")
STANDING = tree_xml('<Sequence><LookAtRobot agent_id="{id}"/></Sequence>')


def _gaps(sim_trace) -> np.ndarray:  # noqa: ANN001
    from socnavgen.sim.contact import trace_gaps

    return trace_gaps(sim_trace)


def _run(sim, steps: int) -> list[tuple[float, int, complex]]:  # noqa: ANN001
    out = []
    for _ in range(steps):
        sim.step()
        out.append((sim.t, int(sim.robot.gesture), complex(sim.robot.pos)))
    return out


def test_registry_has_the_four_robots_and_scripted_is_default():
    assert set(BUILTIN) >= {"scripted", "waypoints", "sfm", "straight"}
    assert DEFAULT_ROBOT == "scripted"
    assert isinstance(load_policy("straight"), StraightPolicy)


def test_cue_says_phrase_when_a_human_comes_within_distance_and_holds_it():
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_within", distance=3.0), say="EXCUSE ME",
                                        hold=2.0)])
    sim = make_sim([human(start=(10.0, 5.0), goals=[(10.0, 5.0)])], [STANDING], [(2.0, 5.0), (18.0, 5.0)],
                   policy=ScriptedPolicy(), script=script)
    rows = _run(sim, 400)
    said = [(t, abs(p - complex(10.0, 5.0))) for t, g, p in rows if g == EXCUSE_ME]
    assert said, "the robot never said EXCUSE ME"
    first_t, first_d = said[0]
    assert first_d <= 3.0 + 0.05  # not before the human was within 3 m
    assert all(g != EXCUSE_ME for t, g, _ in rows if t < first_t)
    held = [t for t, _ in said]
    assert held[-1] - held[0] == pytest.approx(2.0, abs=0.1)  # held 2 s, once


def test_cue_fires_when_a_human_falls_farther_behind_than_its_distance():
    """A guide's cue (human_farther): nothing while the person is close, the phrase once they are farther."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_farther", human="human1", distance=4.0),
                                        say="FOLLOW ME", hold=1.0)])
    sim = make_sim([human(start=(2.0, 5.0), goals=[(2.0, 5.0)])], [STANDING], [(3.5, 5.0), (18.0, 5.0)],
                   policy=ScriptedPolicy(), script=script)
    rows = _run(sim, 300)
    said = [(t, abs(p - complex(2.0, 5.0))) for t, g, p in rows if g == FOLLOW_ME]
    assert said, "the robot never said FOLLOW ME"
    first_t, first_d = said[0]
    assert first_d > 4.0 and first_d < 4.0 + 0.1  # as soon as the person is farther than 4 m, not before
    assert all(g != FOLLOW_ME for t, g, _ in rows if t < first_t)


def test_wait_cue_stands_still_for_its_seconds_then_drives_on():
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="after", seconds=1.0), wait=2.0)])
    sim = make_sim([], [], [(2.0, 5.0), (18.0, 5.0)], policy=ScriptedPolicy(), script=script)
    rows = _run(sim, 120)
    x = {round(t, 2): p.real for t, _, p in rows}
    assert x[1.5] == pytest.approx(x[2.9], abs=1e-6)  # standing between 1 s and 3 s
    assert x[1.0] > 2.05 and x[5.0] > x[3.1] + 0.3  # drove before and after


def test_speed_cue_sets_the_cruise_speed():
    script = RobotScript(speed=0.3, cues=[RobotCue(trigger=CueTrigger(when="after", seconds=6.0), speed=0.8)])
    sim = make_sim([], [], [(1.0, 5.0), (19.0, 5.0)], policy=ScriptedPolicy(), script=script)
    _run(sim, 100)
    assert abs(sim.robot.vel) == pytest.approx(0.3, abs=0.02)
    _run(sim, 40)
    assert abs(sim.robot.vel) == pytest.approx(0.8, abs=0.02)


def test_scripted_robot_never_moves_into_a_person_walking_at_it():
    walker = human(start=(12.0, 5.0), goals=[(1.0, 5.0)])
    sim = make_sim([walker], [tree_xml(REGULAR)], [(2.0, 5.0), (18.0, 5.0)], policy=ScriptedPolicy(), timeout=40)
    trace = sim.run()
    assert not overlapping(_gaps(trace)).any()


def test_straight_robot_drives_through_a_standing_person():
    stander = human(start=(8.0, 5.0), goals=[(8.0, 5.0)])
    sim = make_sim([stander], [STANDING], [(2.0, 5.0), (14.0, 5.0)], policy=StraightPolicy(), timeout=40)
    trace = sim.run()
    assert overlapping(_gaps(trace)).any()  # the rude robot is caught as a collision
    assert trace.end_reason == "robot_goal"


def test_humans_walking_into_each_other_do_not_interpenetrate():
    a = human("human1", start=(3.0, 5.0), goals=[(17.0, 5.0)])
    b = human("human2", start=(17.0, 5.02), goals=[(3.0, 5.0)])
    sim = make_sim([a, b], [tree_xml(REGULAR)] * 2, [(1.0, 1.0)], timeout=20)
    trace = sim.run()
    d = np.abs((trace.humans[:, 0, 0] - trace.humans[:, 1, 0]) + 1j * (trace.humans[:, 0, 1] - trace.humans[:, 1, 1]))
    assert d.min() >= 0.8 - 1e-6


def test_a_shared_last_goal_does_not_stack_people():
    people = [human(f"human{k + 1}", start=(4.0 + k, 3.0 + 2 * k), goals=[(12.0, 5.0)]) for k in range(3)]
    sim = make_sim(people, [tree_xml(REGULAR)] * 3, [(1.0, 1.0)], timeout=30)
    trace = sim.run()
    last = trace.humans[-1, :, 0] + 1j * trace.humans[-1, :, 1]
    pair = np.abs(last[:, None] - last[None, :]) + np.eye(3) * 9
    assert pair.min() >= 0.8 - 1e-6  # two radii: touching at most


def test_a_human_does_not_walk_into_a_standing_robot():
    walker = human(start=(14.0, 5.0), goals=[(2.0, 5.0)])
    sim = make_sim([walker], [tree_xml(REGULAR)], [(8.0, 5.0)], policy=Stay(), timeout=20)
    assert not overlapping(_gaps(sim.run())).any()


def test_robot_said_latches_while_robot_says_does_not():
    assert "RobotSaid" in LIBRARY and LIBRARY["RobotSaid"].kind == "condition"
    follow = tree_xml(f'<Fallback><Sequence><RobotSaid agent_id="{{id}}" message="{FOLLOW_ME}"/>'
                      f'<MakeGesture agent_id="{{id}}" message="1"/></Sequence>'
                      f'<MakeGesture agent_id="{{id}}" message="0"/></Fallback>')
    now_only = tree_xml(f'<Fallback><Sequence><RobotSays agent_id="{{id}}" message="{FOLLOW_ME}"/>'
                        f'<MakeGesture agent_id="{{id}}" message="1"/></Sequence>'
                        f'<MakeGesture agent_id="{{id}}" message="0"/></Fallback>')

    class SayOnce:
        def act(self, obs):  # noqa: ANN001, ANN202
            return Drive(0.0, gesture=FOLLOW_ME if 0.5 <= obs.t < 1.0 else 0).act(obs)

    people = [human("human1", start=(5.0, 5.0), goals=[(5.0, 5.0)]), human("human2", start=(5.0, 8.0), goals=[(5.0, 8.0)])]
    sim = make_sim(people, [follow, now_only], [(2.0, 2.0)], policy=SayOnce())
    _run(sim, 5)
    assert list(sim.people.gesture) == [0, 0]  # not said yet
    _run(sim, 10)
    assert list(sim.people.gesture) == [1, 1]  # both react while it is said
    _run(sim, 40)
    assert sim.people[0].gesture == 1  # latched
    assert sim.people[1].gesture == 0  # RobotSays lets go


def test_paced_human_meets_the_robot_at_the_node():
    node = complex(10.0, 5.0)
    walker = human(start=(16.0, 5.4), goals=[(13.0, 5.4), (10.0, 5.4), (2.0, 5.4)])
    robot_nodes = ["r0", "r1", "n", "r3"]
    robot_points = [complex(1.0, 4.6), complex(5.0, 4.6), complex(10.0, 4.6), complex(18.0, 4.6)]
    pacing = PacingPlan(ThrottleConfig(), robot_nodes, [(0, ["h0", "h1", "n", "h3"], "n", -1)])
    sim = make_sim([walker], [tree_xml(REGULAR)], [(p.real, p.imag) for p in robot_points], policy=ScriptedPolicy(),
                   pacing=pacing, timeout=60)
    trace = sim.run()
    robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    person = trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]
    close = np.abs(robot - person) <= 2.0
    assert close.any()
    mid = (robot + person) / 2
    assert np.abs(mid[close] - node).min() <= 1.0
    # without pacing, the fast human would be far past the node when the robot arrives
    free = make_sim([human(start=(16.0, 5.4), goals=[(13.0, 5.4), (10.0, 5.4), (2.0, 5.4)])], [tree_xml(REGULAR)],
                    [(p.real, p.imag) for p in robot_points], policy=ScriptedPolicy(), timeout=60).run()
    r2 = free.robot[:, 0] + 1j * free.robot[:, 1]
    p2 = free.humans[:, 0, 0] + 1j * free.humans[:, 0, 1]
    c2 = np.abs(r2 - p2) <= 2.0
    assert not c2.any() or np.abs((r2 + p2)[c2] / 2 - node).min() > 1.0


def test_human_says_cue_and_wait_until_clear():
    """human1 says WAIT (gesture 1) at once; the robot's cue answers ACKNOWLEDGED and stands still until nobody
    is in its way; human1 stands in the way for 3 s, then walks off the robot's line."""
    says_wait = nav_tree('<Fallback><Sequence><Inverter><TimeExpiredCondition seconds="3.0" ts="{dt}" '
                         'only_once="true"/></Inverter><MakeGesture agent_id="{id}" message="1"/></Sequence>'
                         '<Sequence><MakeGesture agent_id="{id}" message="0"/>'
                         '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence></Fallback>')
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_says", human="human1", phrase="WAIT"),
                                        say="ACKNOWLEDGED", hold=1.0, wait_until_clear=True)])
    person = human(start=(4.5, 5.0), goals=[(4.5, 9.0)])
    sim = make_sim([person], [says_wait], [(2.0, 5.0), (12.0, 5.0)], policy=ScriptedPolicy(),
                   script=script)
    rows = _run(sim, 200)
    acknowledged = [t for t, g, _ in rows if g == 3]
    assert acknowledged and acknowledged[0] < 0.2  # answered at once
    x = {round(t, 2): p.real for t, _, p in rows}
    assert x[2.5] == pytest.approx(2.0, abs=0.05)  # stood while human1 was in its way
    assert x[10.0] > 4.0  # went on once the way was clear
    assert sim.cues.fired and sim.cues.fired[0][1].startswith("human_says")


def test_at_encounter_and_blocked_cues_fire_where_they_say():
    """`at_encounter`: when the robot comes within `distance` of the encounter's point; `blocked`: when a person
    stands ahead of the robot within `distance`, in its way (someone beside its path does not count)."""
    script = RobotScript(cues=[
        RobotCue(trigger=CueTrigger(when="at_encounter", encounter="e1", distance=2.0), say="PROCEED", hold=0.5),
        RobotCue(trigger=CueTrigger(when="blocked", distance=2.0), say="EXCUSE ME", hold=0.5)])
    beside = human("human1", start=(6.0, 7.0), goals=[(6.0, 7.0)])
    ahead = human("human2", start=(14.0, 5.0), goals=[(14.0, 5.0)])
    sim = make_sim([beside, ahead], [STANDING] * 2, [(2.0, 5.0), (18.0, 5.0)], policy=ScriptedPolicy(),
                   script=script, encounters={"e1": 9.0 + 5.0j}, timeout=30)
    rows = _run(sim, 500)
    fired = {text.split(":")[0]: t for t, text in sim.cues.fired}
    x_at = {round(t, 2): p.real for t, _, p in rows}
    assert abs(x_at[round(fired["at_encounter"], 2)] - 7.0) < 0.1  # 2 m before the point at x = 9
    assert 14.0 - 0.75 - 2.0 - 0.1 < x_at[round(fired["blocked"], 2)] < 14.0 - 0.75  # person 2 m ahead at most
    assert [g for _, g, p in rows if 5.0 < p.real < 7.0] == [0] * len([1 for _, _, p in rows if 5.0 < p.real < 7.0])


def test_an_at_node_cue_stands_the_robot_at_a_node_of_its_route_with_nobody_there():
    """Round 30's and 32's players: a robot that pulls in at a node of its route to wait (a pickup) had no trigger
    but a guessed time. `at_node` fires within `distance` of the node; its `wait` stands the robot there."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="at_node", node="pick", distance=0.3), wait=3.0)])
    sim = make_sim([human(start=(16.0, 8.0), goals=[(16.0, 8.0)])], [STANDING], [(2.0, 5.0), (8.0, 5.0), (14.0, 5.0)],
                   policy=ScriptedPolicy(), script=script, nodes={"pick": 8.0 + 5.0j}, timeout=40)
    rows = _run(sim, 500)
    fired = [t for t, text in sim.cues.fired if text.startswith("at_node")]
    assert len(fired) == 1
    still = [t for t, _, p in rows if abs(p - (8.0 + 5.0j)) <= 0.35]
    assert still[-1] - still[0] >= 3.0  # it stood at the node for the wait
    assert rows[-1][2].real > 12.0  # then drove on


def test_a_timed_wait_longer_than_the_idle_end_does_not_end_the_run():
    """Round 37's home_19: everybody had finished their walk and the robot stood for its 16 s wait at a bedroom door;
    the run ended "all_done" 10 s into the wait (nothing would change, it said), before the robot drove in."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="at_node", node="door", distance=0.3), wait=16.0)])
    sim = make_sim([human(start=(16.0, 8.0), goals=[(16.0, 8.0)])], [STANDING], [(2.0, 5.0), (8.0, 5.0), (14.0, 5.0)],
                   policy=ScriptedPolicy(), script=script, nodes={"door": 8.0 + 5.0j}, timeout=60)
    trace = sim.run()
    assert [text for _, text in sim.cues.fired if text.startswith("at_node")]
    assert trace.end_reason == "robot_goal"
    assert trace.t[-1] > 16.0 + 12.0 / 0.6 * 0.5  # the whole wait, then the drive on


def test_an_at_node_cue_names_its_node():
    with pytest.raises(ValueError, match="names the `node`"):
        CueTrigger(when="at_node", distance=0.5)


def test_waiting_until_clear_asks_again_then_gives_up():
    """Someone who never moves out of the way: the robot waits, says its phrase again twice (every 8 s), then
    stops waiting and goes around - the script never becomes a deadlock."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=2.5), say="EXCUSE ME", hold=1.0,
                                        wait_until_clear=True)])
    sim = make_sim([human(start=(8.0, 5.0), goals=[(8.0, 5.0)])], [STANDING], [(2.0, 5.0), (14.0, 5.0)],
                   policy=ScriptedPolicy(), script=script, timeout=60, idle_end=60)  # no early end while it waits
    trace = sim.run()
    events = [text for _, text in sim.cues.fired]
    assert events[0].startswith("blocked") and events[1:3] == ["still blocked: say EXCUSE ME again"] * 2
    assert events[3] == "still blocked: stop waiting, go around"
    times = [t for t, _ in sim.cues.fired]
    assert times[1] - times[0] == pytest.approx(8.0, abs=0.06) and times[3] - times[2] == pytest.approx(8.0, abs=0.06)
    assert trace.end_reason == "robot_goal"  # it went around
    said = trace.robot_gesture == EXCUSE_ME
    assert 2.9 <= said.sum() * trace.dt <= 3.2  # the phrase three times, 1 s each


def test_gesture_rules_hold_their_gesture_for_their_duration():
    from socnavgen.run.models import RobotGestureRule

    rules = [RobotGestureRule(gesture=2, when="near_human", distance=3.0, duration=1.0)]
    walker = human(start=(14.0, 5.0), goals=[(14.0, 9.5)])  # crosses near the robot's path, then away
    sim = make_sim([walker], [tree_xml(REGULAR)], [(11.5, 5.0), (19.0, 5.0)], policy=Stay(), rules=rules, timeout=8)
    trace = sim.run()
    near = np.hypot(*(trace.humans[:, 0, :2] - trace.robot[:, :2]).T) <= 3.0
    shown = trace.robot_gesture == 2
    last_near = np.flatnonzero(near)[-1]
    assert shown[near][1:].all()  # while someone is near
    assert shown[last_near + 1:last_near + 20].all() and not shown[last_near + 22:].any()  # then 1 s more


def test_waiting_until_clear_looks_along_the_route_round_its_corner():
    """`wait_until_clear` waits for people on the robot's route ahead (round its turn), not for someone standing
    straight ahead past the corner, beside the route (the elevator-door case: a visitor who stepped aside beyond
    the lobby node held the robot in the door for 24 s)."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), say="EXCUSE ME", hold=1.0,
                                        wait_until_clear=True)])
    route = [(6.0, 5.0), (8.0, 5.0), (8.0, 1.5)]
    past_corner = human(start=(8.9, 5.0), goals=[(8.9, 5.0)])  # 0.9 m off the second leg, 2.9 m straight ahead
    sim = make_sim([past_corner], [STANDING], route, policy=ScriptedPolicy(), script=script, timeout=20)
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 16.0  # never held up (giving up takes 24 s)
    assert [text for _, text in sim.cues.fired] == ["start: say EXCUSE ME, wait until clear"]
    on_route = human(start=(8.0, 4.2), goals=[(8.0, 4.2)])  # round the corner, on the second leg
    sim = make_sim([on_route], [STANDING], route, policy=ScriptedPolicy(), script=script, timeout=20)
    rows = _run(sim, 100)
    assert abs(rows[-1][2] - (6.0 + 5.0j)) < 0.05  # still waiting at 5 s: that person is in its way


def test_waiting_until_clear_squeezes_past_someone_just_beside_its_route_where_there_is_room():
    """Someone who stepped aside but could not get quite clear (cramped between furniture, 0.05 m inside the
    swept corridor) does not hold the robot "until clear" when it can pass them keeping its polite gap by edging
    a little aside (the party guest held the robot 24 s); in a corridor with a wall on that side they do."""
    from socnavgen.sim import empty_room

    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), say="EXCUSE ME", hold=1.0,
                                        wait_until_clear=True)])
    route = [(2.0, 2.0), (12.0, 2.0)]
    beside = human(start=(4.5, 2.0 - 0.65), goals=[(4.5, 2.0 - 0.65)])  # 0.65 m off: the swept corridor is 0.7
    room = empty_room(14.0, 5.0)
    sim = make_sim([beside], [STANDING], route, policy=ScriptedPolicy(), script=script, world=room, timeout=40)
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 30.0  # not held up (giving up takes 24 s)
    assert [text for _, text in sim.cues.fired] == ["start: say EXCUSE ME, wait until clear"]
    assert _gaps(trace).min() >= 0.1
    narrow = empty_room(14.0, 5.0, walls=[(0.0, 2.45, 14.0, 5.0)])  # a wall 0.45 m beside the route: no room
    sim = make_sim([beside], [STANDING], route, policy=ScriptedPolicy(), script=script, world=narrow, timeout=40)
    rows = _run(sim, 100)
    assert abs(rows[-1][2] - (2.0 + 2.0j)) < 0.05  # still waiting at 5 s


def test_waiting_until_clear_rounds_a_turn_past_someone_who_stepped_into_its_outer_corner():
    """Someone who stepped aside into the outer corner of the robot's turn (0.8 m from the turn's waypoint, beyond
    it and behind the next leg) does not hold the robot "until clear" when it can round the turn on the inner side
    keeping its polite gap (warehouse_07: the worker stepped into the corner pocket, the robot stood 2 m off for 25
    s, asked twice more, then squeezed past); someone standing on the turn itself still does."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), say="EXCUSE ME", hold=1.0,
                                        wait_until_clear=True)])
    route = [(6.0, 5.0), (8.0, 5.0), (8.0, 9.5)]  # east, then a left turn north (both within 3 m: held up)
    pocket = human(start=(8.49, 4.4), goals=[(8.49, 4.4)], radius=0.4)  # 0.77 m from the turn, outside it
    sim = make_sim([pocket], [STANDING], route, policy=ScriptedPolicy(), script=script, timeout=40, idle_end=40)
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 20.0  # not held up (giving up takes 24 s)
    assert [text for _, text in sim.cues.fired] == ["start: say EXCUSE ME, wait until clear"]
    assert _gaps(trace).min() >= 0.2  # it rounds them at its polite gap, no squeezing
    on_turn = human(start=(8.2, 4.9), goals=[(8.2, 4.9)], radius=0.4)  # on the turn itself: in its way
    sim = make_sim([on_turn], [STANDING], route, policy=ScriptedPolicy(), script=script, timeout=40, idle_end=40)
    rows = _run(sim, 100)
    assert abs(rows[-1][2] - (6.0 + 5.0j)) < 0.05  # still waiting at 5 s
