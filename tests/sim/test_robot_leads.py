"""The default robot with the people who go with it: a guide leads its followers on (it never makes way for them,
stops without stepping off the line of one walking up to it, and slows for one falling behind), and a
`wait_until_clear` robot holds in front of someone walking out to block it until they leave (not veering beside
them)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.people.state import ROUTE_GOAL, ROUTE_ROBOT
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.lead import goes_with_robot
from socnavgen.sim.robot.polite import coming_through, yield_to
from tests.sim.simhelpers import REGULAR, human, make_sim, nav_tree, tree_xml

WALK = tree_xml(REGULAR)
LOOK = tree_xml('<Sequence><LookAtRobot agent_id="{id}"/></Sequence>')
# walks out to block the robot once it is within 4 m, for 10 s; else walks to (stays at) its goal
BLOCKS = nav_tree('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="5.0"/>'
                  '<Inverter><TimeExpiredCondition seconds="10.0" ts="{dt}" only_once="true"/></Inverter>'
                  '<BlockRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                  '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Fallback>')


def _state(people: list[tuple[complex, complex]], goal: complex = 2.0 + 5.0j):  # noqa: ANN202
    """A state with the default robot at (8, 5) heading +x along its route, people at (pos, vel) whose goal is
    `goal` (behind the robot: their way lies through it)."""
    specs = [human(f"human{k + 1}", start=(p.real, p.imag), goals=[(goal.real, goal.imag)])
             for k, (p, _) in enumerate(people)]
    sim = make_sim(specs, [WALK] * len(people), [(2.0, 5.0), (8.0, 5.0), (18.0, 5.0)], ScriptedPolicy())
    s = sim.state
    s.robot[0].pos, s.policy[0].waypoint = 8.0 + 5.0j, 2
    for k, (p, v) in enumerate(people):
        s.people[k].pos, s.people[k].vel, s.people[k].goal, s.people[k].has_goal = p, v, goal, True
        s.people[k].route = ROUTE_GOAL
    return s


def test_who_goes_with_the_robot_follows_a_chain_of_followers_to_it():
    s = _state([(9.5 + 5.0j, 0j), (10.5 + 5.0j, 0j), (11.5 + 5.0j, 0j)])
    s.people[0].route, s.people[1].route, s.people[2].route = ROUTE_ROBOT, 0, ROUTE_GOAL
    assert goes_with_robot(s, 0) and goes_with_robot(s, 1)  # following it; following its follower
    assert not goes_with_robot(s, 2)  # walking to their own goal
    s.people[1].route = 2  # following someone who walks their own way
    assert not goes_with_robot(s, 1)
    s.people[0].route, s.people[1].route = 1, 0  # two following each other: a loop ends, nobody goes with it
    assert not goes_with_robot(s, 0)


def test_robot_makes_way_for_a_walker_whose_way_lies_through_it_but_never_for_its_follower():
    s = _state([(9.3 + 5.0j, 0j)])  # face to face, 0.6 m gap, their goal behind the robot
    assert coming_through(s, 1.0 + 0j, 1.5, True)[0] == 0  # a walker: it may back off for them (make_way)
    s.people[0].route = ROUTE_ROBOT  # the same person following it (FOLLOW ME): they go where it goes
    assert coming_through(s, 1.0 + 0j, 1.5, True)[0] == -1
    assert coming_through(s, 1.0 + 0j, 2.5, False)[0] == -1


def test_robot_steps_off_the_line_of_a_walker_coming_at_it_not_of_a_follower_walking_up_to_it():
    s = _state([(9.6 + 5.0j, -0.8 + 0j)])  # 0.7 m gap ahead, walking straight at it
    v, stops = yield_to(s)
    assert stops and abs(v.imag) > 0.1  # it stops and steps sideways off their line
    s.people[0].route = ROUTE_ROBOT  # a follower or blocker walking up to it stops short of it: it only stops
    assert yield_to(s) == (0j, True)
    s.people[0].pos = 8.0 + 0.35 + 0.25 + 0.2 + 5.0j  # ... unless they close in within YIELD_GAP
    v, stops = yield_to(s)
    assert stops and abs(v) > 0.1


def _follow_me_sim():  # noqa: ANN202
    """The robot at (2, 5) says FOLLOW ME at once to three people standing round it; its route runs east and
    their own goals lie behind it (west): they follow it, it leads them 12 m along a 3 m corridor."""
    follow = tree_xml('<Sequence><RobotSaid agent_id="{id}" message="{m}"/><FollowRobot agent_id="{id}" '
                      'time_step="{dt}"/></Sequence>')
    from socnavgen.bt.library import ROBOT_GESTURES

    code = next(k for k, v in ROBOT_GESTURES.items() if v == "FOLLOW ME")
    tree = follow.replace("{m}", str(code))
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="start"), say="FOLLOW ME", hold=3.0, wait=2.0)])
    corridor = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 3.5), (0.0, 6.5, 20.0, 10.0)])
    people = [human(f"human{k + 1}", start=p, goals=[(0.5, 5.0)])
              for k, p in enumerate([(3.2, 5.9), (3.4, 4.2), (1.0, 5.0)])]
    return make_sim(people, [tree] * 3, [(2.0, 5.0), (6.0, 5.0), (14.0, 5.0)], ScriptedPolicy(), world=corridor,
                    script=script, timeout=90)


def test_guide_leads_its_followers_along_a_corridor_to_its_goal():
    sim = _follow_me_sim()
    trace = sim.run()
    assert trace.end_reason == "robot_goal" and trace.t[-1] < 60.0
    end = trace.humans[-1, :, 0]
    assert (end > 10.0).all()  # every follower came along behind it


def test_wait_until_clear_holds_in_front_of_someone_walking_out_to_block_it_until_they_leave():
    """A worker steps out of a side aisle 2 m beside the route to block the robot (the cue fires while they are
    still beside its route, walking into it): the robot stands where it asked, does not veer beside them, and
    drives on once they have gone; a silent cue waits as long as one that asks (8 s block here)."""
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=3.0), wait_until_clear=True)])
    aisle = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 3.5), (0.0, 6.5, 9.0, 10.0), (10.0, 6.5, 20.0, 10.0)])
    worker = human(start=(9.5, 6.8), goals=[(9.5, 6.8)])  # in the side aisle; afterwards goes back there
    sim = make_sim([worker], [BLOCKS], [(2.0, 5.0), (16.0, 5.0)], ScriptedPolicy(), world=aisle, script=script,
                   timeout=80, idle_end=80)
    trace = sim.run()
    fired = [t for t, text in sim.cues.fired if text.startswith("blocked")]
    assert fired, sim.cues.fired
    k = np.searchsorted(trace.t, fired[0] + 0.5)
    hold = np.flatnonzero(np.hypot(trace.robot[:, 3], trace.robot[:, 4]) > 0.05)
    moved_after = hold[hold > k]
    assert moved_after.size, "the robot never drove on"
    first_move = trace.t[moved_after[0]]
    assert first_move - fired[0] > 6.0  # stood in front of them while they blocked
    held = trace.robot[k:moved_after[0], :2]
    assert np.ptp(held, axis=0).max() < 0.05  # stood where it stopped: did not veer beside them
    ahead = trace.humans[k:moved_after[0], 0, 0] - held[:, 0]
    assert (ahead > 0.0).all()  # they stood in front of it
    assert all("stop waiting" not in text for _, text in sim.cues.fired)  # the silent cue did not give up at 8 s
    assert trace.end_reason == "robot_goal"


def test_guide_slows_for_a_follower_falling_behind_but_never_stops_for_them():
    from socnavgen.sim.robot.lead import LEAD_EASE, LEAD_LOST, LEAD_SLOWEST, lead_speed

    s = _state([(8.0 - LEAD_EASE - 0.5 + 5.0j, 0.8 + 0j)])
    q, robot = s.people[0], s.robot[0]
    q.walks, q.route, q.target = True, ROUTE_ROBOT, robot.pos  # walking after it (FollowRobot)
    share = 1.0 - 0.5 / (LEAD_LOST - LEAD_EASE)
    assert lead_speed(s, 0.6, 1.0 + 0j) == pytest.approx(0.6 * share)
    q.pos = 8.0 - LEAD_LOST - 3.0 + 5.0j  # far behind: it creeps on, it does not wait for them for good
    assert lead_speed(s, 0.6, 1.0 + 0j) == pytest.approx(0.6 * LEAD_SLOWEST)
    q.pos = 8.0 - 2.0 + 5.0j  # keeping up
    assert lead_speed(s, 0.6, 1.0 + 0j) == math.inf
    q.pos = 8.0 + LEAD_LOST + 5.0j  # coming to it from ahead: not falling behind
    assert lead_speed(s, 0.6, 1.0 + 0j) == math.inf
    q.pos, q.target = 8.0 - LEAD_LOST + 5.0j, robot.pos + 1.5  # coming to block it (a point ahead of it)
    assert lead_speed(s, 0.6, 1.0 + 0j) == math.inf
    q.target, q.route = robot.pos, ROUTE_GOAL  # walking their own way
    assert lead_speed(s, 0.6, 1.0 + 0j) == math.inf
