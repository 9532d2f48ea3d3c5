"""Several people walking to one goal point stand round it (sim.people.spots) instead of queueing in the
doorway before it; people do not walk into a robot that stands still (sim.people.avoid)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import PERSON_KEEP_GAP, PERSON_PASS_GAP
from socnavgen.sim import empty_room
from socnavgen.sim.people import spots
from socnavgen.sim.people.avoid import MIN_PASS_GAP

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml
from .test_people_spacing import pair_gaps

GOAL = 13.0 + 5.0j
# a room behind a 1.0 m doorway at x = 8 (y 4.5 - 5.5): the team comes down the corridor to one point inside
DOOR_WALLS = [(7.8, 0.0, 8.2, 4.5), (7.8, 5.5, 8.2, 10.0)]


def test_a_team_walking_to_one_point_stands_round_it_not_in_the_doorway():
    """Four people walk, one behind the other, through a doorway to one point (a team to a bed): the first stands
    on it, the others take free spots round it (in the room, off the walls, a gap from each other), so all four
    end inside the room on the first two rings of spots round the point and all count as arrived (on integ the third and fourth
    stood jammed in and before the doorway, 0.10 m apart, and the run went on to the time limit)."""
    people = [human(f"human{k + 1}", start=(6.5 - 1.2 * k, 5.0), goals=[(GOAL.real, GOAL.imag)]) for k in range(4)]
    trace = make_sim(people, [tree_xml(REGULAR)] * 4, [(18.0, 9.0), (18.5, 9.0)], Stay(),
                     world=empty_room(20.0, 10.0, walls=DOOR_WALLS), timeout=40).run()
    end = trace.humans[-1, :, 0] + 1j * trace.humans[-1, :, 1]
    assert np.all(end.real > 8.2 + 0.4), end  # everyone through the doorway
    assert np.all(np.abs(end - GOAL) <= 2 * spots.RING_STEP + 0.5), np.abs(end - GOAL)  # round the point
    assert pair_gaps(trace).min() >= PERSON_KEEP_GAP - 1e-3
    assert trace.end_reason == "all_done"


def robot_gaps(trace) -> np.ndarray:  # noqa: ANN001
    """(T, H) surface gaps between the robot and each person."""
    d = trace.humans[:, :, :2] - trace.robot[:, None, :2]
    return np.hypot(d[..., 0], d[..., 1]) - trace.human_radii[None, :] - trace.robot_radius


def test_a_walker_never_squeezes_past_a_standing_robot_closer_than_the_least_passing_gap():
    """A robot stands against one wall of a 1.65 m corridor, leaving a person room to pass it only 0.1-0.15 m
    from its body: the person coming down the corridor does not brush past it; they keep at least the least
    passing gap (avoid.MIN_PASS_GAP) from it. (This one passes on integ too: it guards the rule, it does not show
    the change.)"""
    walls = [(0.0, 0.0, 20.0, 3.5), (0.0, 5.15, 20.0, 10.0)]  # the corridor y 3.5 - 5.15
    people = [human("human1", start=(3.0, 4.5), goals=[(17.0, 4.5)])]
    trace = make_sim(people, [tree_xml(REGULAR)], [(10.0, 3.9), (10.5, 3.9)], Stay(),
                     world=empty_room(20.0, 10.0, walls=walls), timeout=20).run()
    assert robot_gaps(trace).min() >= MIN_PASS_GAP - 1e-3, robot_gaps(trace).min()


def test_a_walker_goes_round_a_standing_robot_with_room_and_arrives():
    """The same robot standing in a 3 m corridor: the person goes round it with the passing gap and arrives."""
    walls = [(0.0, 0.0, 20.0, 3.5), (0.0, 6.5, 20.0, 10.0)]
    people = [human("human1", start=(3.0, 4.2), goals=[(17.0, 4.2)])]
    trace = make_sim(people, [tree_xml(REGULAR)], [(10.0, 3.9), (10.5, 3.9)], Stay(),
                     world=empty_room(20.0, 10.0, walls=walls), timeout=25).run()
    assert robot_gaps(trace).min() >= PERSON_PASS_GAP - 0.15, robot_gaps(trace).min()
    assert trace.humans[-1, 0, 0] > 16.0
