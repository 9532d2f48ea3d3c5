"""People who stand together keep a gap the eye does not read as touching (bodies.PERSON_STAND_GAP), a goal the
robot stands on is taken like one a person stands on (sim.people.spots), spots round a shared goal keep off the
robot's way, and a walker slowed by a crowd still steps round someone in their way (sim.people.spacing)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import PERSON_PASS_GAP, PERSON_STAND_GAP

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml
from .test_people_spacing import pair_gaps
from .test_people_spots import robot_gaps

STAND = tree_xml('<Sequence><SetBlackboard output_key="agentid" value="{id}"/></Sequence>')
TOLERANCE = 0.05  # m: two walking side by side the walking gap apart stand where their walks ended (0.27 m)


def test_people_gathering_at_one_point_stand_the_standing_gap_apart():
    """Four people walk to one point in an open room: once they all stand round it, no two of them stand closer
    than PERSON_STAND_GAP (on main the spots and the queue kept 0.10 m, which read as 'pressed together')."""
    goal = (10.0, 5.0)
    people = [human(f"human{k + 1}", start=(3.0, 2.5 + 1.6 * k), goals=[goal]) for k in range(4)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 4, [(18.0, 9.0), (18.5, 9.0)], Stay(), timeout=40).run()
    assert trace.end_reason == "all_done"
    assert pair_gaps(trace)[-1].min() >= PERSON_STAND_GAP - TOLERANCE, pair_gaps(trace)[-1]


def test_a_walker_whose_goal_someone_stands_on_stops_the_standing_gap_from_them():
    """Someone stands on the point another walks to: the walker stands beside them PERSON_STAND_GAP or more from
    their body (on main 0.10 m), and has arrived."""
    people = [human("human1", start=(3.0, 5.0), goals=[(12.0, 5.0)]), human("human2", start=(12.0, 5.0), goals=[])]
    trace = make_sim(people, [tree_xml(REGULAR), STAND], [(10.0, 9.0), (10.5, 9.0)], Stay(), timeout=20).run()
    assert trace.end_reason == "all_done"
    assert pair_gaps(trace)[-1].min() >= PERSON_STAND_GAP - TOLERANCE, pair_gaps(trace)[-1]
    assert abs(complex(*trace.humans[-1, 0, :2]) - (12.0 + 5.0j)) <= 2.0  # came up to them


def test_a_walker_whose_goal_the_robot_stands_on_stands_at_a_free_spot_beside_it():
    """The robot stands on a person's goal: the person walks up and stands at a free spot beside it, the passing
    gap off its body, and has arrived within a few seconds (on main they were held short of it, then squeezed on
    to the goal and stood against its body until the time limit)."""
    people = [human("human1", start=(3.0, 5.0), goals=[(12.0, 5.0)])]
    trace = make_sim(people, [tree_xml(REGULAR)], [(12.0, 5.0), (18.0, 5.0)], Stay(), timeout=30).run()
    assert trace.end_reason == "all_done"
    assert trace.t[-1] < 15.0, trace.t[-1]  # a 9 m walk, not the time limit
    assert robot_gaps(trace)[-1].min() >= PERSON_PASS_GAP - TOLERANCE, robot_gaps(trace)[-1]
    assert abs(complex(*trace.humans[-1, 0, :2]) - (12.0 + 5.0j)) <= 2.5  # beside it


def test_people_standing_round_a_shared_goal_keep_off_the_robots_way():
    """The robot's way runs 1.5 m north of a point four people walk to from the north: they stand round it on
    the side away from the robot's way (on main the nearest spots, on the way, were taken)."""
    goal = 10.0 + 5.0j
    people = [human(f"human{k + 1}", start=(7.0 + 2.0 * k, 9.0), goals=[(goal.real, goal.imag)]) for k in range(4)]
    route = [(2.0, 6.5), (18.0, 6.5)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 4, route, Stay(), timeout=40).run()
    assert trace.end_reason == "all_done"
    end = trace.humans[-1, :, 1]
    clear = trace.human_radii + trace.robot_radius  # the robot's body passing on y = 6.5 touches theirs at this
    assert np.all(6.5 - end >= clear - TOLERANCE), end


def test_a_walker_slowed_to_a_crawl_still_steps_round_someone_in_the_way():
    """A walker starts from rest right in front of someone standing between them and their goal (a crowd slowed
    them to a stop): they step round at a walking pace and arrive (on main the sidestep was a share of the
    walker's current speed, so from a crawl it stayed a crawl)."""
    people = [human("human1", start=(9.05, 5.0), goals=[(18.0, 5.0)]), human("human2", start=(10.0, 5.0), goals=[])]
    trace = make_sim(people, [tree_xml(REGULAR), STAND], [(10.0, 9.0), (10.5, 9.0)], Stay(), timeout=20).run()
    x = trace.humans[:, 0, 0]
    past = np.flatnonzero(x > 10.0 + 0.8)
    assert past.size and trace.t[past[0]] < 4.0, trace.t[past[0]] if past.size else "never got past"
