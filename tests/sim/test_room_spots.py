"""People who go into a room or an elevator car end inside it, never in its door (people.spots.through_door, issue
25). The bundled hospital's elevator car, and a car behind a thick-walled door and a bedroom off a hallway drawn like
the bundled hospital's and home's: round 31's hospital_01 ended with the second visitor in the car's door (her spot's
clearance was the door's, so the old test, "narrower than both ends", saw no door between it and the car), and
home_09's children, following the robot into the bedroom, took spots round its goal in the hallway by the door's wall
(both ends of their ways were no wider than the 0.9 m door)."""

from __future__ import annotations

from pathlib import Path

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.location import load_location
from socnavgen.sim import World, empty_room
from socnavgen.sim.people.spots import through_door

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml

ROOT = Path(__file__).resolve().parents[2]

# A lobby (x < 14.9) and a car 1.8 m x 2.2 m inside (x 15.3-17.1, y 4.4-6.6) behind a 1.2 m door through a 0.4 m wall
# (x 14.9-15.3, y 4.9-6.1): the bundled hospital's north elevator.
CAR = [(14.9, 0.0, 20.0, 4.4), (14.9, 6.6, 20.0, 9.0), (14.9, 4.4, 15.3, 4.9), (14.9, 6.1, 15.3, 6.6),
       (17.1, 4.4, 20.0, 6.6)]
CAR_CENTRE = (16.2, 5.5)

# A 1.2 m hallway (x 5.0-6.2) and a bedroom (x 6.35-10, y 4.5-9.5) off it behind a 0.9 m door in a 0.15 m wall
# (y 6.55-7.45): the bundled home's second bedroom and its doorway 2n.
BEDROOM = [(0.0, 0.0, 5.0, 10.0), (6.2, 0.0, 6.35, 6.55), (6.2, 7.45, 6.35, 10.0), (6.35, 0.0, 12.0, 4.5),
           (6.35, 9.5, 12.0, 10.0), (10.0, 4.5, 12.0, 9.5)]


def test_two_visitors_sent_into_the_bundled_hospitals_elevator_car_both_end_inside_it() -> None:
    """Two visitors (alone or as a group) walk from the lobby (8r) past the door's front (8z) into the north elevator
    car (lc): both stand in the car when their walks end, neither in its door (before: the second's spot was in the
    door's mouth, and she ended at x 15.1-15.2, in the 0.4 m-thick door)."""
    hospital = load_location(ROOT / "examples" / "locations" / "hospital")

    def at(node: str) -> tuple[float, float]:
        return tuple(hospital.node_world(node))

    inside = 15.3 + PERSON_RADIUS - 0.05  # the car's inner wall face is at x 15.3: a centre beyond this is in the car
    for group in (-1, 0):
        specs = [human("human1", start=(12.3, 3.6), goals=[at("8z"), at("lc")], group_id=group),
                 human("human2", start=(12.9, 3.0), goals=[at("8z"), at("lc")], group_id=group)]
        trace = make_sim(specs, [tree_xml(REGULAR)] * 2, [at("cs"), at("zs")], Stay(),
                         world=World.from_location(hospital), timeout=40.0).run()
        end = trace.humans[-1, :, :2]
        assert (end[:, 0] > inside).all(), (group, end)


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
