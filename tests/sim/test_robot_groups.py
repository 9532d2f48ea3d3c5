"""The default robot and a group standing on its way: it does not creep up on them for ever.

The place (home_10's living room, in a plain room): three friends stand in a circle round a waypoint of the
robot's route, which turns there toward a door at the room's wall. The robot comes at the circle from the side
away from the door."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.contact import trace_gaps

from .simhelpers import human, make_sim, tree_xml

LOOK = tree_xml('<Fallback><Sequence><IsRobotVisible agent_id="{id}" distance="2.5"/>'
                '<LookAtRobot agent_id="{id}"/></Sequence><MakeGesture agent_id="{id}" message="0"/></Fallback>')
CENTRE = complex(4.0, 2.5)
ROUTE = [(9.0, 2.8), (CENTRE.real, CENTRE.imag), (2.0, 3.9)]  # the last: just inside the room's north wall
STARTS = [CENTRE + 0.6 * np.exp(1j * a) for a in (0.0, 2 * np.pi / 3, -2 * np.pi / 3)]  # east, north-west, south-west


def run(trees: list[str], timeout: float = 40.0):  # noqa: ANN201
    people = [human(f"human{k + 1}", start=(s.real, s.imag), goals=[(CENTRE.real, CENTRE.imag)], group_id=0)
              for k, s in enumerate(STARTS)]
    return make_sim(people, trees, ROUTE, policy=load_policy("scripted"), world=empty_room(10.0, 4.5),
                    timeout=timeout).run()


def test_the_robot_goes_round_a_group_standing_on_its_waypoint_and_leaves_them_be():
    """Friends who only look at it stand round the robot's waypoint, with room between them and the wall. Within
    OCCUPIED_REACH of the waypoint the robot heads on for the next one round them (as every built-in robot skips a
    waypoint someone stands on): it passes beside the circle, never into it, without stopping there long, and
    nobody has to make room. On main it crept up on the circle, waited, made all three step aside (make_room)
    and drove to their centre (home_10's robot crept 16 s 1 m short of the circle and broke it up)."""
    trace = run([LOOK] * 3)
    assert trace.end_reason == "robot_goal", trace.end_reason
    assert trace_gaps(trace).min() > CONTACT_MARGIN
    robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    assert np.abs(robot - CENTRE).min() > 0.6 + 0.35, np.abs(robot - CENTRE).min()  # never inside the circle
    people = trace.humans[:, :, 0] + 1j * trace.humans[:, :, 1]
    moved = np.abs(people - people[0]).max(axis=0)
    assert moved.max() < 0.1, moved  # nobody was made to step aside: the robot went round them
    assert not (trace.behavior_state == 2).any()
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    creeping = (speed > 0.01) & (speed < 0.1) & (trace_gaps(trace).min(axis=1) < 1.5)
    assert creeping.sum() * (trace.t[1] - trace.t[0]) < 3.0  # no inching along beside them
    assert trace.t[-1] < 25.0, trace.t[-1]


def test_the_robot_stops_short_of_someone_standing_on_its_way_instead_of_inching_up_on_them():
    """Someone stands looking at it in the middle of a 1.6 m passage, on the robot's way, with no room to pass them.
    The robot slows down as it comes and stops at its stop gap; it does not inch toward them at a few cm/s for
    seconds (the linear slow-down to the stop gap nears it exponentially, and a robot creeping so never counts as
    waiting: home_10's robot crept 8 s 1 m short of the circle before anyone made room)."""
    people = [human("human1", start=(10.0, 0.8), goals=[(10.0, 0.8)], yaw=np.pi)]
    trace = make_sim(people, [LOOK], [(2.0, 0.8), (18.0, 0.8)], policy=load_policy("scripted"),
                     world=empty_room(20.0, 1.6), timeout=30).run()
    gaps = trace_gaps(trace)[:, 0]
    assert gaps.min() > CONTACT_MARGIN
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    creeping = (speed > 0.01) & (speed < 0.08) & (gaps < 1.5)
    assert creeping.sum() * (trace.t[1] - trace.t[0]) < 1.0, creeping.sum() * (trace.t[1] - trace.t[0])
