"""People sharing a goal in a place too small to stand round it at the standing gap - an elevator car, a small
bedroom - all go in, as people do in a lift: the first in goes deep, the next stands beside them a body off the walls,
and nobody takes a spot through the door (people.spots: tight, pick_tight, through_door). Round 31's hospital_01 and
round 35's hospital_27: visitors and porters told to get into the car stood in the lobby outside its 1.2 m door, the
first just inside it, drawn back out to the others by the group's forces."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN, PERSON_RADIUS
from socnavgen.sim import empty_room

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml

# A 12 x 6 m lobby; on its east side a car 1.9 m x 2 m inside (x 9.0-10.9, y 2.0-4.0), its 1.2 m door at y 2.4-3.6.
CAR = [(8.8, 1.8, 12.0, 2.0), (8.8, 4.0, 12.0, 4.2), (8.8, 1.8, 9.0, 2.4), (8.8, 3.6, 9.0, 4.2), (10.9, 1.8, 12.0, 4.2),
       (8.8, 0.0, 12.0, 1.8), (8.8, 4.2, 12.0, 6.0)]
CENTRE = (9.95, 3.0)


def _run(group: int):  # noqa: ANN202
    people = [human("human1", start=(4.0, 2.6), goals=[(7.0, 3.0), CENTRE], group_id=group),
              human("human2", start=(4.0, 3.5), goals=[(7.0, 3.0), CENTRE], group_id=group)]
    sim = make_sim(people, [tree_xml(REGULAR)] * 2, [(1.0, 1.0), (1.0, 5.0)], Stay(),
                   world=empty_room(12.0, 6.0, walls=CAR), timeout=30.0)
    return sim.run()


def _check(trace) -> None:  # noqa: ANN001
    end = trace.humans[-1, :, :2]
    assert (end[:, 0] > 9.0 + PERSON_RADIUS - 0.05).all(), end  # both inside the car, past its door
    gap = np.hypot(*(end[0] - end[1])) - 2 * PERSON_RADIUS
    assert gap > CONTACT_MARGIN, gap  # side by side, not pressed together


def test_two_people_sharing_a_goal_in_a_car_both_get_in() -> None:
    _check(_run(group=-1))


def test_a_group_of_two_both_get_into_the_car_and_stay() -> None:
    _check(_run(group=0))
