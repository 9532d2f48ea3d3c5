"""People who go into a room or an elevator car end inside it, never in its door (people.spots.through_door, issue
25). A car behind a thick-walled door and a bedroom off a hallway, as on the bundled hospital and home: round 31's
hospital_01 ended with the second visitor in the car's door (her spot's clearance was the door's, so the old test,
"narrower than both ends", saw no door between it and the car), and home_09's children, following the robot into
the bedroom, took spots round its goal in the hallway by the door's wall (both ends of their ways were no wider than
the 0.9 m door)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.sim import empty_room
from socnavgen.sim.people.spots import through_door
from socnavgen.sim.robot.api import ScriptedPolicy

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml
from .test_followers import FOLLOWS
from .test_grace import FOLLOW_ME

# A lobby (x < 14.9) and a car 1.8 m x 2.2 m inside (x 15.3-17.1, y 4.4-6.6) behind a 1.2 m door through a 0.4 m wall
# (x 14.9-15.3, y 4.9-6.1): the bundled hospital's north elevator.
CAR = [(14.9, 0.0, 20.0, 4.4), (14.9, 6.6, 20.0, 9.0), (14.9, 4.4, 15.3, 4.9), (14.9, 6.1, 15.3, 6.6),
       (17.1, 4.4, 20.0, 6.6)]
CAR_CENTRE = (16.2, 5.5)
CAR_INSIDE = 15.3 + PERSON_RADIUS - 0.05  # a centre beyond this is in the car, the body past the door

# A 1.2 m hallway (x 5.0-6.2) and a bedroom (x 6.35-10, y 4.5-9.5) off it behind a 0.9 m door in a 0.15 m wall
# (y 6.55-7.45): the bundled home's second bedroom and its doorway 2n.
BEDROOM = [(0.0, 0.0, 5.0, 10.0), (6.2, 0.0, 6.35, 6.55), (6.2, 7.45, 6.35, 10.0), (6.35, 0.0, 12.0, 4.5),
           (6.35, 9.5, 12.0, 10.0), (10.0, 4.5, 12.0, 9.5)]
ROOM_INSIDE = 6.35 + PERSON_RADIUS - 0.05


def _in_car(people: int):  # noqa: ANN202
    specs = [human(f"human{k + 1}", start=(11.0, 4.5 + 0.9 * k), goals=[(13.8, 5.5), CAR_CENTRE])
             for k in range(people)]
    sim = make_sim(specs, [tree_xml(REGULAR)] * people, [(2.0, 1.0), (2.0, 8.0)], Stay(),
                   world=empty_room(20.0, 9.0, walls=CAR), timeout=40.0)
    return sim.run()


def test_two_people_sharing_a_goal_in_a_car_behind_a_thick_door_both_get_in() -> None:
    """Two visitors sent into the car both stand in it when their walks end, neither in its door (before: the second's
    spot was in the door's mouth)."""
    end = _in_car(2).humans[-1, :, :2]
    assert (end[:, 0] > CAR_INSIDE).all(), end


def test_a_spot_in_a_doors_mouth_or_by_the_wall_beyond_a_door_is_through_it_a_corner_of_the_room_is_not() -> None:
    car = empty_room(20.0, 9.0, walls=CAR)
    centre = complex(*CAR_CENTRE)
    for spot in (14.7 + 5.5j, 15.0 + 5.5j, 13.8 + 5.5j):  # in front of the door, in it, in the lobby
        assert through_door(car.map, spot, centre), spot
    for spot in (16.6 + 4.9j, 16.7 + 6.1j, 15.7 + 4.9j, 15.7 + 5.5j):  # the car's corners, just inside its door
        assert not through_door(car.map, spot, centre), spot
    home = empty_room(12.0, 10.0, walls=BEDROOM)
    goal = 7.85 + 7.0j
    for spot in (5.3 + 7.9j, 5.3 + 6.2j, 5.6 + 7.0j):  # in the hallway beside the door, near its far wall
        assert through_door(home.map, spot, goal), spot
    for spot in (6.8 + 7.3j, 9.6 + 5.0j, 9.6 + 9.0j):  # in the room, one just past its door
        assert not through_door(home.map, spot, goal), spot


def test_two_followers_led_into_a_bedroom_off_a_narrow_hallway_end_in_the_room() -> None:
    """The robot leads two children up a 1.2 m hallway and into a bedroom through its 0.9 m door, its goal 1.5 m
    inside: both end in the room (before: both stood in the hallway by the door, on spots round its goal)."""
    people = [human("human1", start=(5.6, 2.3), goals=[(5.6, 7.0), (7.85, 7.0)]),
              human("human2", start=(5.6, 1.2), goals=[(5.6, 7.0), (7.85, 7.0)])]
    trace = make_sim(people, [FOLLOWS] * 2, [(5.6, 3.5), (5.6, 7.0), (7.85, 7.0)], ScriptedPolicy(),
                     world=empty_room(12.0, 10.0, walls=BEDROOM), script=FOLLOW_ME, timeout=90).run()
    assert trace.end_reason == "robot_goal"
    end = trace.humans[-1, :, :2]
    assert (end[:, 0] > ROOM_INSIDE).all(), end
    assert np.hypot(*(end - trace.robot[-1, :2]).T).min() > 2 * PERSON_RADIUS  # round the robot, not on it
