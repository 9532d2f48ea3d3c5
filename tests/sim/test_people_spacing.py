"""People keep a gap from each other's bodies (sim.people.spacing, physics' contact step): two walkers meeting
head-on pass each other, followers of one robot do not press together, and nobody stops for it."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN, PERSON_KEEP_GAP
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.people.state import QUEUE_REACH

from .simhelpers import REGULAR, Drive, Stay, human, make_sim, tree_xml


def pair_gaps(trace) -> np.ndarray:  # noqa: ANN001
    """(T, P) surface gaps of every pair of people."""
    i, j = np.triu_indices(trace.humans.shape[1], 1)
    d = trace.humans[:, i, :2] - trace.humans[:, j, :2]
    return np.hypot(d[..., 0], d[..., 1]) - (trace.human_radii[i] + trace.human_radii[j])[None, :]


def test_two_people_meeting_head_on_in_a_corridor_pass_each_other_with_a_gap():
    """A 3 m corridor, two walkers on one line toward each other: they keep to their right and pass with at
    least PERSON_KEEP_GAP between them (the social force alone met them face to face, gap 0.00 m), and both
    arrive."""
    walls = [(0.0, 0.0, 20.0, 3.5), (0.0, 6.5, 20.0, 10.0)]  # the corridor y 3.5 - 6.5
    people = [human("human1", start=(2.0, 5.0), goals=[(18.0, 5.0)]),
              human("human2", start=(18.0, 5.0), goals=[(2.0, 5.0)])]
    trace = make_sim(people, [tree_xml(REGULAR)] * 2, [(10.0, 9.0), (10.5, 9.0)], Stay(),
                     world=empty_room(20.0, 10.0, walls=walls), timeout=25).run()
    assert pair_gaps(trace).min() >= PERSON_KEEP_GAP - 1e-3
    assert trace.humans[-1, 0, 0] > 16.5 and trace.humans[-1, 1, 0] < 3.5  # both got past: nobody froze


def test_three_followers_of_one_robot_do_not_press_together():
    """Three people follow a robot that drives across the room and stops: they gather behind it without any
    two of them touching (they converged on one point behind the robot and stood pressed, gap 0.00 m), and all
    three did follow it."""
    follow = tree_xml('<FollowRobot agent_id="{id}" time_step="{dt}"/>')
    people = [human("human1", start=(2.0, 3.0)), human("human2", start=(2.0, 5.0)), human("human3", start=(2.0, 7.0))]
    trace = make_sim(people, [follow] * 3, [(4.0, 5.0), (14.0, 5.0)], load_policy("waypoints"), timeout=30).run()
    assert pair_gaps(trace).min() > CONTACT_MARGIN
    robot_x = trace.robot[-1, 0]
    assert all(trace.humans[-1, k, 0] > robot_x - 5.0 for k in range(3))  # they came along


def test_a_walker_steps_round_someone_standing_in_the_way_without_touching():
    """A person stands in the middle of the room; another walks straight at them to a goal beyond: they walk
    round them with a gap and arrive (not stop in front of them, not brush them)."""
    stand = tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/></Sequence>')
    people = [human("human1", start=(2.0, 5.0), goals=[(18.0, 5.0)]), human("human2", start=(10.0, 5.0), goals=[])]
    trace = make_sim(people, [tree_xml(REGULAR), stand], [(10.0, 9.0), (10.5, 9.0)], Stay(), timeout=25).run()
    assert pair_gaps(trace).min() >= PERSON_KEEP_GAP - 1e-3
    assert trace.humans[-1, 0, 0] > 16.5


def test_a_group_walking_together_keeps_a_spacing_and_arrives():
    """Three members of a group walk to one goal: the group force holds them together but they keep the gap
    between their bodies, and they arrive together."""
    people = [human(f"human{k + 1}", start=(2.0, 4.0 + k), goals=[(16.0, 5.0)], group_id=0) for k in range(3)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 3, [(10.0, 9.0), (10.5, 9.0)], Drive(0.0), timeout=25).run()
    assert pair_gaps(trace).min() >= PERSON_KEEP_GAP - 1e-3
    assert all(trace.humans[-1, k, 0] > 13.0 for k in range(3))


def test_a_walker_whose_goal_someone_stands_on_stops_short_of_them_and_has_arrived():
    """Someone stands on the very point another person walks to: the walker stops short of them, not pressed
    into them, and counts as arrived (state.queued_at): everyone is done and the run ends (on main they pressed
    round the one standing, gap 0.00 m, and walked on until the time limit)."""
    stand = tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/></Sequence>')
    people = [human("human1", start=(3.0, 5.0), goals=[(12.0, 5.0)]), human("human2", start=(12.0, 5.0), goals=[])]
    trace = make_sim(people, [tree_xml(REGULAR), stand], [(10.0, 9.0), (10.5, 9.0)], Stay(), timeout=20).run()
    assert pair_gaps(trace).min() >= PERSON_KEEP_GAP - 1e-3
    assert abs(complex(*trace.humans[-1, 0, :2]) - (12.0 + 5.0j)) <= QUEUE_REACH  # came up to them
    assert trace.end_reason == "all_done"


def test_a_walker_going_in_lets_the_one_standing_on_their_goal_out_of_a_strip_narrower_than_two_bodies():
    """A 1.4 m strip (two 0.8 m bodies do not fit side by side) leads from the room to a dead end. human2 stands at
    its end, where human1 walks to, and sets off out of it once human1 is in the strip: human1 lets them out
    (steps back out of the strip, then aside) and goes in after them (on main the two stood face to face, the one
    coming out swaying against the walls, until the time limit)."""
    walls = [(10.0, 0.0, 20.0, 4.3), (10.0, 5.7, 20.0, 10.0)]  # the strip y 4.3 - 5.7, x 10 - 20
    people = [human("human1", start=(4.0, 3.0), goals=[(18.0, 5.0)]),
              human("human2", start=(18.0, 5.0), goals=[(3.0, 8.0)], start_delay=9.0)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 2, [(2.0, 1.0), (2.5, 1.0)], Stay(),
                     world=empty_room(20.0, 10.0, walls=walls), timeout=60).run()
    held = np.argmax(trace.t >= 9.0)
    assert trace.humans[held, 0, 0] > 12.0  # human1 was in the strip when human2 set off toward them
    assert abs(complex(*trace.humans[-1, 1, :2]) - (3.0 + 8.0j)) < 1.0  # human2 got out
    assert abs(complex(*trace.humans[-1, 0, :2]) - (18.0 + 5.0j)) <= QUEUE_REACH  # human1 went in after them
    assert pair_gaps(trace).min() > CONTACT_MARGIN
