"""Giving way where there is no room beside the robot's path: in a 1 m aisle or a 0.9 m doorway a person told to
give way backs out along their way to the nearest place wide enough, waits there until the robot has passed, then
carries on; and one who stepped aside stays aside until it has passed, whatever their tree falls back to."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.contact import trace_gaps
from tests.sim.simhelpers import give_way_tree, human, make_sim, tree_xml

# gives way while the robot is near, else walks its path (the model's usual shape: nothing keeps it giving way)
GIVES_WAY_NEAR = give_way_tree('<IsRobotNearby agent_id="{id}" distance="2.5"/>')
EXCUSE_ME = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=2.5), say="EXCUSE ME", hold=1.0,
                                       wait_until_clear=True)])

NARROW = {  # (world walls, person's start and goal): a 1 m aisle 8 m long between racks; a 0.9 m door in a wall,
    # walked through slowly (a cane) and reached as the robot comes
    "aisle": ([(4.0, 0.0, 12.0, 3.0), (4.0, 4.0, 12.0, 7.0)], (9.0, 3.5), (1.5, 3.5)),
    "door": ([(7.9, 0.0, 8.1, 3.05), (7.9, 3.95, 8.1, 7.0)], (11.0, 3.5), (1.5, 3.5)),
}


def person_gaps(trace) -> np.ndarray:  # noqa: ANN001
    """Gaps between every two people's bodies at every step."""
    xy = trace.humans[:, :, 0] + 1j * trace.humans[:, :, 1]
    n = xy.shape[1]
    return np.array([np.abs(xy[:, a] - xy[:, b]) - 0.8 for a in range(n) for b in range(a + 1, n)]).T


@pytest.mark.parametrize("place", sorted(NARROW))
def test_a_person_met_where_there_is_no_room_backs_out_and_lets_the_robot_by(place: str):
    """Face to face with the robot in the aisle (the warehouse picker stood there 77 s) or the doorway (the home's
    resident with a cane): the person backs out to where there is room, the robot gets past without touching
    them, and the person then walks on toward their goal through the narrow part."""
    walls, start, goal = NARROW[place]
    slow = 0.8 if place == "aisle" else 0.4
    sim = make_sim([human(start=start, goals=[goal], max_vel=slow)], [GIVES_WAY_NEAR], [(1.0, 3.5), (22.0, 3.5)],
                   policy=load_policy("scripted"), world=empty_room(23.0, 7.0, walls=walls), script=EXCUSE_ME,
                   timeout=90)
    trace = sim.run()
    gaps = trace_gaps(trace)[:, 0]
    robot_x, person = trace.robot[:, 0], trace.humans[:, 0, :2]
    passed = int(np.argmax(robot_x > person[:, 0]))  # abreast
    assert robot_x[passed] > person[passed, 0], "the robot never got past the person"
    assert abs(person[passed, 1] - 3.5) > 1.0  # it passed them standing aside, off its lane
    assert person[:passed, 0].max() > 12.0 if place == "aisle" else person[:passed, 0].max() > 8.4  # backed out
    assert gaps.min() > 0.05  # nobody touched
    assert trace.end_reason == "robot_goal"
    back = 11.5 if place == "aisle" else 7.5  # resumed: walking home through the narrow part
    assert person[-1, 0] < back and abs(person[-1, 1] - 3.5) < 0.3


def test_people_giving_way_in_a_corridor_never_overlap():
    """Two people side by side walking toward the robot in a 2.2 m corridor give way: neither walks into the
    other (their bodies never overlap) and the robot gets by."""
    people = [human("human1", start=(9.0, 0.7), goals=[(1.5, 0.7)], max_vel=0.8),
              human("human2", start=(9.0, 1.5), goals=[(1.5, 1.5)], max_vel=0.8)]
    sim = make_sim(people, [GIVES_WAY_NEAR] * 2, [(1.0, 1.1), (15.0, 1.1)], policy=load_policy("scripted"),
                   world=empty_room(16.0, 2.2, walls=[(6.0, 0.0, 7.0, 0.2)]), script=EXCUSE_ME, timeout=90)
    trace = sim.run()
    assert person_gaps(trace).min() > -0.01
    assert trace_gaps(trace).min() > 0.0


def test_a_group_that_stepped_aside_stays_aside_until_the_robot_has_passed():
    """Three people chatting on the robot's way give way for 3 s (a one-shot timer, as the hospital's handover nurses'
    tree did) and then walk back to their places: they wait until the robot has gone through the gap they made
    instead of closing up around it (the nurses did, and the robot detoured through the nurse station)."""
    from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript

    gives_way_a_while = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="3.0"/>'
                                 '<Inverter><TimeExpiredCondition seconds="3" ts="{dt}" only_once="true"/></Inverter>'
                                 '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                                 '<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                                 '<SetBlackboard output_key="timestep" value="{dt}"/>'
                                 '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence></Fallback>')
    spots = [(7.7, 2.0), (6.8, 2.5), (6.8, 1.5)]
    group = [human(f"human{k + 1}", start=xy, goals=[xy], group_id=0) for k, xy in enumerate(spots)]
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=2.5), say="EXCUSE ME", hold=1.0,
                                        wait_until_clear=True)])
    sim = make_sim(group, [gives_way_a_while] * 3, [(1.0, 2.0), (13.0, 2.0)], policy=load_policy("scripted"),
                   world=empty_room(14.0, 4.0), script=script, timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    among = (trace.robot[:, 0] > 6.8 - 0.4) & (trace.robot[:, 0] < 7.7 + 0.4)  # the robot in the group's midst
    assert among.any() and trace.t[among][0] > 8.0  # it came after the 3 s of giving way were over
    assert np.abs(trace.humans[among, :, 1] - 2.0).min() > 0.9  # nobody walked back toward their place on its route
    assert trace_gaps(trace).min() > 0.05
    assert person_gaps(trace).min() > -0.01
