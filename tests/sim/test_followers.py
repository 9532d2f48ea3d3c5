"""People told FOLLOW ME fall in behind the robot at once: a follower who stood aside for it (it came at them)
follows as soon as it has come level with them, without waiting for its other followers to go by first (the
older child stood 12 s aside while the robot crept past and her sibling followed it: home_09); a give-way begun
by another leaf before the robot spoke does not hold a follower for a robot that drives away from them (the
second guest stood 8 s at the front door: home_03)."""

from __future__ import annotations

import numpy as np

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import human, make_sim, tree_xml

FOLLOW_ME = next(k for k, v in ROBOT_GESTURES.items() if v == "FOLLOW ME")
WALKING = 0.3  # m/s: a person faster than this walks
MOVES = 0.1  # m/s: a follower faster than this has set off (behind a robot creeping at 0.35 m/s they walk its pace)
FOLLOWS = tree_xml(f'<Fallback><Sequence><RobotSaid agent_id="{{id}}" message="{FOLLOW_ME}"/>'
                   '<FollowRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                   '<MakeGesture agent_id="{id}" message="0"/></Fallback>')
# home_03's second guest: lets the robot come up while it is near and has not spoken yet, follows once told
GIVES_WAY_UNTIL_TOLD = tree_xml(f'<Fallback><Sequence><RobotSaid agent_id="{{id}}" message="{FOLLOW_ME}"/>'
                                '<FollowRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                                '<Sequence><IsRobotNearby agent_id="{id}" distance="3.5"/>'
                                '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                                '<MakeGesture agent_id="{id}" message="0"/></Fallback>')


def _speeds(trace, k: int) -> np.ndarray:  # noqa: ANN001
    return np.hypot(trace.humans[:, k, 3], trace.humans[:, k, 4])


def test_a_follower_who_stood_aside_falls_in_once_the_robot_is_level_not_after_the_other_follower():
    """The robot (2, 5) says FOLLOW ME and creeps east at 0.35 m/s; one follower stands ahead of it 0.8 m off its
    line (in its way: she steps aside), the other behind it. She sets off within 3 s of the robot coming level
    with her (the time for it to get her following distance ahead), while the other follower is still behind her,
    and both follow it down the room untouched."""
    script = RobotScript(speed=0.35, cues=[RobotCue(trigger=CueTrigger(when="start"), say="FOLLOW ME", hold=2.0,
                                                    wait=1.0)])
    people = [human("human1", start=(3.9, 4.2), goals=[(3.9, 4.2)]),
              human("human2", start=(0.6, 5.0), goals=[(0.6, 5.0)])]
    sim = make_sim(people, [FOLLOWS] * 2, [(2.0, 5.0), (14.0, 5.0)], ScriptedPolicy(), world=empty_room(20.0, 10.0),
                   script=script, timeout=60)
    trace = sim.run()
    assert (trace.behavior_state[:, 0] == 2).any()  # she was in its way and stood aside
    aside = int(np.flatnonzero(trace.behavior_state[:, 0] == 2)[-1])
    level = int(np.flatnonzero(trace.robot[:, 0] >= trace.humans[aside, 0, 0])[0])  # robot abreast of her
    walks = np.flatnonzero((_speeds(trace, 0) > MOVES) & (np.arange(trace.steps) > level))
    assert walks.size, "she never followed"
    first = int(walks[0])
    assert trace.t[first] - trace.t[level] < 3.0, (trace.t[level], trace.t[first])
    assert trace.humans[first, 1, 0] < trace.humans[first, 0, 0]  # the other follower has not gone by her yet
    assert trace_gaps(trace).min() > 0.05  # nobody touched the robot
    end = trace.humans[-1, :, :2] - trace.robot[-1, :2]
    assert trace.end_reason == "robot_goal" and (np.hypot(end[:, 0], end[:, 1]) < 4.0).all()  # both came along


def test_a_give_way_begun_before_follow_me_does_not_hold_a_follower_the_robot_drives_away_from():
    """A guest 2.5 m behind the robot's start gives way while it is near and silent; it says FOLLOW ME at once
    and leads away from her after a 4 s wait: she sets off within 1.5 s of being told, not when it has driven
    a metre away."""
    script = RobotScript(speed=0.5, cues=[RobotCue(trigger=CueTrigger(when="start"), say="FOLLOW ME", hold=3.0,
                                                   wait=4.0)])
    people = [human("human1", start=(3.5, 5.0), goals=[(3.5, 5.0)])]
    sim = make_sim(people, [GIVES_WAY_UNTIL_TOLD], [(6.0, 5.0), (16.0, 5.0)], ScriptedPolicy(),
                   world=empty_room(20.0, 10.0), script=script, timeout=60)
    trace = sim.run()
    said = np.flatnonzero(trace.robot_gesture == FOLLOW_ME)
    assert said.size
    walks = np.flatnonzero(_speeds(trace, 0) > WALKING)
    assert walks.size and trace.t[walks[0]] - trace.t[said[0]] < 1.5, (trace.t[said[0]], trace.t[walks[:1]])
    robot_moved = np.flatnonzero(np.hypot(trace.robot[:, 0] - 6.0, trace.robot[:, 1] - 5.0) > 0.3)
    assert walks[0] < robot_moved[0]  # she came while the robot still waited


def test_followers_of_the_robot_line_up_behind_each_other_at_the_standing_gap():
    """A follower walking up behind another follower of the robot (walking or standing behind it) keeps the standing
    gap and is not sent round them (home_03's second guest walked back and forth 4 s in the doorway behind the
    first); someone standing who does not follow the robot is passed at the walking gap, as before."""
    from socnavgen.bodies import PERSON_KEEP_GAP, PERSON_STAND_GAP
    from socnavgen.sim.people.spacing import fellow_followers, keep_gap
    from socnavgen.sim.people.state import ROUTE_GOAL, ROUTE_ROBOT

    sim = make_sim([human("human1", start=(2.0, 5.0)), human("human2", start=(3.2, 5.0))], [FOLLOWS] * 2,
                   [(6.0, 5.0), (16.0, 5.0)])
    p, q = sim.state.people[0], sim.state.people[1]
    p.route, p.behavior, q.route, q.behavior = ROUTE_ROBOT, 1, ROUTE_ROBOT, 1
    end = 6.0 + 5.0j  # p walks to the robot, 4 m ahead
    assert fellow_followers.py_func(p, q)
    assert keep_gap.py_func(p, q, end) == PERSON_STAND_GAP
    q.route, q.behavior = ROUTE_GOAL, 0  # q stands there on their own way
    assert not fellow_followers.py_func(p, q)
    assert keep_gap.py_func(p, q, end) == PERSON_KEEP_GAP
