"""A group asked to make way does it together, and the robot goes on once its way is clear.

- hospital_13: a slow family of three asked EXCUSE ME in a 2.6 m corridor stepped to both walls, each member on
  its own side, and the robot could pass on neither; behind them it swung from wall to wall for tens of seconds.
- home_05: a chatting pair gave way one after the other; the second took a spot beside the first's, which then
  could not be reached: the first stood short of it, 0.03 m inside the robot's lane, for 20 s, and the robot idled.
- hospital_10: a family of four in a doorway: the west visitor planned a spot 2.7 m away, across her mates, and
  stood 0.43 m from the robot's line, short of it, until the robot squeezed by.
- hospital_08: two nurses standing on the corridor's line: which wall they went to was a rounding error's (numba
  north, plain Python south); north, by a door that has room for one, the second stood 0.56 m off the robot's line.
- hospital_01: a visitor of a pair going to the elevator the robot came out of drifted back from it as it came (0.2
  m/s its way): taken for a group walking its way with no lane beside, the robot stopped moving aside for the pair.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.location import load_location
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.people.group_way import plan_aside
from socnavgen.sim.people.routing import robot_progress
from socnavgen.sim.people.side_step import GIVE_WAY_MARGIN, path_distance
from socnavgen.sim.robot.polite import pass_aside
from socnavgen.sim.world.grid import World
from tests.sim.simhelpers import give_way_tree, human, make_sim, tree_xml

HOSPITAL = Path(__file__).resolve().parents[2] / "examples" / "locations" / "hospital"

SAID_TREE = give_way_tree('<RobotSaid agent_id="{id}" message="4"/>'
                          '<Inverter><TimeExpiredCondition seconds="12" ts="{dt}" only_once="true"/></Inverter>')
EXCUSE_ME = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=3.0), say="EXCUSE ME", hold=2.0,
                                       wait_until_clear=True)])
LANE = PERSON_RADIUS + ROBOT_RADIUS  # a body centre nearer the robot's line than this is in its lane


def seen_within(distance: float) -> str:
    """home_05's pair: give way while the robot is visible within `distance`, else stand chatting."""
    return tree_xml(f'<Fallback><Sequence><IsRobotVisible agent_id="{{id}}" distance="{distance}"/>'
                    '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                    '<MakeGesture agent_id="{id}" message="0"/></Fallback>')


def test_a_slow_family_asked_to_make_way_in_a_corridor_steps_to_one_side_and_the_robot_overtakes():
    starts = [(6.0, 0.6), (6.6, 1.3), (6.0, 2.0)]  # a family of three abreast down a 2.6 m corridor, slowly east
    people = [human(f"human{k + 1}", start=s, goals=[(28.0, 1.3)], group_id=0, max_vel=0.45)
              for k, s in enumerate(starts)]
    trace = make_sim(people, [SAID_TREE] * 3, [(1.0, 1.3), (32.0, 1.3)], policy=load_policy("scripted"),
                     world=empty_room(34.0, 2.6), script=EXCUSE_ME, timeout=90).run()
    rx, hx, hy = trace.robot[:, 0], trace.humans[:, :, 0], trace.humans[:, :, 1]
    ahead = rx > hx.max(axis=1) + 0.5
    assert ahead.any(), "the robot never overtook the family"
    passed = int(np.argmax(rx > hx.mean(axis=1)))  # abreast of the family's middle
    sides = np.sign(hy[passed] - trace.robot[passed, 1])
    assert abs(sides.sum()) == 3, (hy[passed], trace.robot[passed, 1])  # all three on one side of it
    said = trace.t[int(np.argmax(trace.robot_gesture > 0))] if (trace.robot_gesture > 0).any() else None
    assert said is not None
    for k in range(3):  # nobody walks back toward the robot to get aside: they go on slowly or stand
        xs = hx[(trace.t >= said) & ~ahead, k]
        assert xs.min() > xs[0] - 0.3, (k, xs[0], xs.min())
    assert trace_gaps(trace).min() > 0.05  # nobody touched
    assert trace.end_reason == "robot_goal"


def test_a_robot_behind_a_group_it_cannot_pass_follows_on_its_line_instead_of_weaving():
    """Behind a family abreast across a 2.6 m corridor (no side has room to pass), the robot follows them on its
    line: it does not swing from wall to wall (hospital_13: y 1.8 <-> 3.8 for 36 s)."""
    starts = [(6.0, 0.6), (6.6, 1.3), (6.0, 2.0)]
    people = [human(f"human{k + 1}", start=s, goals=[(28.0, 1.3)], group_id=0, max_vel=0.45)
              for k, s in enumerate(starts)]
    trace = make_sim(people, [tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/>'
                                       '<SetBlackboard output_key="timestep" value="{dt}"/>'
                                       '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/></Sequence>')] * 3,
                     [(1.0, 1.3), (32.0, 1.3)], policy=load_policy("scripted"), world=empty_room(34.0, 2.6),
                     timeout=30).run()
    late = trace.t >= 10.0  # it has caught up with them
    ry = trace.robot[late, 1]
    assert ry.max() - ry.min() < 0.4, (ry.min(), ry.max())
    assert trace_gaps(trace).min() > 0.05


@pytest.mark.parametrize(("goal_x", "follows"), [(0.5, True), (11.5, False)])
def test_the_robot_follows_a_group_walking_its_way_but_moves_aside_for_one_backing_off_from_it(goal_x: float,
                                                                                            follows: bool):
    """A pair across a 2.6 m corridor 2 m ahead of the robot, drifting its way at 0.3 m/s; no side leaves a lane
    past both. Walking to a goal ahead of it (hospital_13's family), they are followed on the robot's line (no
    sideways move); backing off from it, their goal behind it (hospital_01's visitors, on their way to the elevator
    it came out of), they are not walking its way: it moves aside, which lets them by (it followed them instead)."""
    people = [human(f"human{k + 1}", start=(6.0, y), goals=[(goal_x, y)], group_id=0) for k, y in enumerate((0.7, 1.9))]
    sim = make_sim(people, [SAID_TREE] * 2, [(8.0, 1.3), (0.5, 1.3)], policy=load_policy("scripted"),
                   world=empty_room(12.0, 2.6))
    s = sim.state
    s.robot[0].pos = 8.0 + 1.3j
    for k in range(2):
        s.people[k].vel = -0.3 + 0j
    aside = pass_aside(s, -1.0 + 0j)
    assert (abs(aside) == 0.0) == follows, aside


@pytest.mark.parametrize("apart", [1.0, 1.2])
def test_a_pair_giving_way_one_after_the_other_both_clear_the_robots_lane_and_it_drives_on(apart: float):
    """home_05: a chatting pair stands on the robot's line, 1.6 m from a wall (too near for a body to stand clear
    of the robot's lane on that side); the near one gives way as soon as they see the robot 4 m off, the far one
    only at 3 m. Both end out of the robot's lane (their bodies clear of its swept width with a margin) when it
    comes level with them, and it is not held up for long: 10.5 m at 0.5 m/s take 17.6 s with nobody there."""
    line = 1.6
    people = [human("human1", start=(6.6, line), goals=[(6.6, line)], group_id=0),
              human("human2", start=(6.6 - apart, line - 0.05), goals=[(6.6 - apart, line - 0.05)], group_id=0)]
    trace = make_sim(people, [seen_within(4.0), seen_within(3.0)], [(11.0, line), (0.5, line)],
                     policy=load_policy("scripted"), world=empty_room(12.0, 5.0), timeout=60).run()
    assert trace.end_reason == "robot_goal", trace.end_reason
    rx, hx, hy = trace.robot[:, 0], trace.humans[:, :, 0], trace.humans[:, :, 1]
    for k in range(2):
        abreast = int(np.argmax(rx < hx[:, k]))  # the robot comes level with them
        assert abs(hy[abreast, k] - line) >= LANE + 0.1, (k, trace.t[abreast], hy[abreast, k])
    assert trace.t[-1] < 30.0, trace.t[-1]  # 10.5 m at 0.5 m/s with a pass: not idling behind them
    assert trace_gaps(trace).min() > 0.05


@pytest.mark.parametrize("off", [0.01, -0.01])
def test_a_group_standing_on_the_robots_line_makes_way_to_the_side_where_all_get_clear(off: float):
    """hospital_08's corridor (the hospital map): two nurses 1.2 m apart on the robot's line at the nurse station,
    1 cm to one side or the other; north a door beside them has room for one, south the station's open space for
    both. Whichever side they stand on by a hair, the group's one plan gives both a spot that leaves the robot its
    margin (on the north side the second got a spot 0.7 m off its path: a step too short)."""
    line = 3.275
    people = [human("human1", start=(2.725, line + off), goals=[(2.725, line + off)], group_id=0),
              human("human2", start=(1.525, line + off), goals=[(1.525, line + off)], group_id=0)]
    sim = make_sim(people, [SAID_TREE] * 2, [(-3.125, line), (2.125, line), (7.375, line)],
                   policy=load_policy("scripted"), world=World.from_location(load_location(HOSPITAL)))
    s = sim.state
    s.robot[0].pos = -0.378 + 2.713j  # coming up the corridor, 2.5 m short of them, as it said EXCUSE ME
    s.people[0].gives_way, s.people[0].behavior = True, 2
    plan_aside(s, 0, False)
    want = s.people[0].radius + s.robot[0].radius + GIVE_WAY_MARGIN
    _, seg = robot_progress(s)
    for k in range(2):
        assert path_distance(s, seg, False, s.people[k].aside) >= want - 1e-6, (k, s.people[k].aside)


def test_no_member_of_a_group_round_a_doorway_is_planned_a_spot_on_the_robots_way_through_it():
    """hospital_10's family of four round the corridor node in front of a 1.3 m patient's door, the robot's way
    turning north through it: the member in the door's mouth was planned a spot just inside the room 0.10 m off the
    robot's way (a lane beside it there, but none in the door), stood short of it in the door, and the robot waited
    100 s. Every member's planned spot leaves at least the robot's lane (their bodies apart with it on its way)."""
    line = 3.275
    starts = [(8.02, line), (7.38, 3.92), (6.74, line), (7.38, 2.64)]
    people = [human(f"human{k + 1}", start=p, goals=[p], group_id=0) for k, p in enumerate(starts)]
    sim = make_sim(people, [SAID_TREE] * 4, [(2.125, 0.675), (2.125, line), (7.375, line), (7.375, 4.475),
                                             (8.225, 6.475)],
                   policy=load_policy("scripted"), world=World.from_location(load_location(HOSPITAL)))
    s = sim.state
    s.robot[0].pos = 4.36 + 2.60j  # coming east along the corridor as it said EXCUSE ME
    s.people[0].gives_way, s.people[0].behavior = True, 2
    plan_aside(s, 0, False)
    _, seg = robot_progress(s)
    for k in range(4):
        if s.people[k].has_slot or k == 0:
            lane = s.people[k].radius + s.robot[0].radius
            assert path_distance(s, seg, False, s.people[k].aside) >= lane, (k, s.people[k].aside)
