"""A waypoint the robot has gone past counts as reached: the default robot that drove round someone 0.45 m off an
intermediate waypoint turned back to it, toward the peer who had just fallen in beside it to follow it, and
stood facing them until the run timed out (card accompanying-peer [warehouse]: 100 s at (14.93, -3.09))."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.policies import PASSED_REACH, track
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

# the card's peer: follows the robot while it is visible within 6 m, else walks their own path
PEER = tree_xml('<Fallback><Sequence><IsRobotVisible agent_id="{id}" distance="6.0"/>'
                '<FollowRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                '<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                '<SetBlackboard output_key="timestep" value="{dt}"/>'
                '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence></Fallback>')
ROUTE_Y = 2.45  # m: the cross aisle's route, 1.45 m from its south wall and 1.58 m from the racks' ends
STANDS = 0.05  # m/s: a robot slower than this stands
LONGEST_STAND = 3.0  # s


def test_robot_walks_on_with_a_peer_who_joins_it_from_a_side_aisle_and_follows():
    """The card's situation on its own: a 3 m cross aisle, racks to the north with a 1.1 m aisle between them at
    x 15-16; the robot comes from the east along the cross aisle through the aisle's mouth (a waypoint) and on
    west; the peer starts 1.9 m up the side aisle, walks down to join it and follows it. The robot reaches its goal
    without ever standing more than LONGEST_STAND, with the peer following, untouched."""
    world = empty_room(22.0, 8.0, walls=[(0.0, ROUTE_Y + 1.58, 14.95, 8.0), (16.05, ROUTE_Y + 1.58, 22.0, 8.0),
                                         (0.0, 0.0, 22.0, 1.0)])
    route = [(18.5, ROUTE_Y), (15.5, ROUTE_Y), (11.5, ROUTE_Y), (2.0, ROUTE_Y)]
    peer = human("human1", start=(15.5, ROUTE_Y + 1.9), goals=route[1:])
    sim = make_sim([peer], [PEER], route, ScriptedPolicy(), world=world, script=RobotScript(speed=0.6), timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal", (trace.end_reason, trace.robot[-1, :2])
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    still, longest = 0.0, 0.0
    for k in range(1, trace.steps - 1):  # not its start, nor its end at the goal
        still = still + float(trace.t[k] - trace.t[k - 1]) if speed[k] < STANDS else 0.0
        longest = max(longest, still)
    assert longest <= LONGEST_STAND, longest
    assert np.hypot(*(trace.humans[-1, 0, :2] - trace.robot[-1, :2])) < 4.0  # the peer came along
    assert trace_gaps(trace).min() > 0.05


def _robot_at(pos: complex, route: list[tuple[float, float]]):  # noqa: ANN202
    sim = make_sim([human(start=(1.0, 1.0), goals=[(1.0, 1.0)])], [tree_xml(REGULAR)], route, ScriptedPolicy())
    s = sim.state
    s.robot[0].pos, s.policy[0].waypoint = pos, 1
    return s


def test_a_waypoint_counts_as_passed_only_beyond_it_along_both_legs_and_near_it():
    """Waypoint (10, 5) of a route from (4, 5) on to (16, 5): 0.45 m off it sideways and 0.3 m past it (beyond
    its tolerance) it is passed; as far off but 0.3 m short of it it is not, nor farther off than PASSED_REACH.
    At a turn back (on to (4, 5.5)), it is never passed short of its tolerance."""
    straight = [(4.0, 5.0), (10.0, 5.0), (16.0, 5.0)]
    wps_next = complex(*straight[2])
    assert track(_robot_at(10.3 + 5.45j, straight), False)[0] == wps_next
    assert track(_robot_at(9.7 + 5.45j, straight), False)[0] == 10.0 + 5.0j
    far = 10.0 + PASSED_REACH + 0.1 + 5.0j
    assert track(_robot_at(far, straight), False)[0] == 10.0 + 5.0j
    back = [(4.0, 5.0), (10.0, 5.0), (4.0, 5.5)]
    assert track(_robot_at(10.3 + 5.45j, back), False)[0] == 10.0 + 5.0j
    assert track(_robot_at(9.7 + 5.45j, back), False)[0] == 10.0 + 5.0j
