"""Where a person puts nodes across whole halls and houses (each map drawn in code at 0.05 m per pixel):
the ground outside a building gets none and its entrance a doorway; an open-plan floor gets a node in
each of its wings, even when the far end of one is hidden behind furniture; a room seen at a glance
stays one place; a long dead-end aisle is not a closet; a floor holding shelves is drawn as lanes."""

from __future__ import annotations

import math
from collections import Counter

import numpy as np

from tests.extract.synthetic_maps import FREE, WALL, blank, carve
from tests.extract.test_person_rules import extracted, near


def building_map(door: int = 22) -> np.ndarray:
    """A 10 x 8 m building, walls 0.15 m thick, in a strip of free ground 0.3 m wide reaching the
    image's edge (as `location from-world` leaves around a building), with a `door`-pixel gap in its
    south wall (none when 0)."""
    img = np.full((172, 212), FREE, np.uint8)
    img[6:166, 6:206] = WALL
    carve(img, 9, 163, 9, 203)  # the floor inside
    if door:
        img[163:166, 40:40 + door] = FREE
    return img


def outside(location) -> list:
    """Nodes on the ground strip, outside the walls' box."""
    return [n for n in location.scene_graph.nodes if not (9 <= n.pos[0] < 203 and 9 <= n.pos[1] < 166)]


def test_the_ground_around_a_building_gets_no_node_and_its_door_is_a_doorway(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, building_map(), "building")
    assert outside(location) == []
    doors = [n for n in location.scene_graph.nodes if n.type == "DOORWAY"]
    assert len(doors) == 1 and math.dist(doors[0].pos, (51, 160)) * 0.05 <= 1.0, doors
    assert Counter(n.type for n in location.scene_graph.nodes)["ROOM"] == 1


def test_a_closed_building_or_a_gap_nobody_fits_through_has_no_doorway(map_factory, tmp_path) -> None:
    for door in (0, 8):  # no opening; a 0.4 m gap
        location = extracted(map_factory, tmp_path, building_map(door), f"closed{door}")
        assert outside(location) == []
        assert not [n for n in location.scene_graph.nodes if n.type == "DOORWAY"], door


def open_plan_map(wardrobe: bool = True) -> np.ndarray:
    """An open-plan flat: a 14 x 4 m living area, a 5 x 5 m wing opening off its west end to the south
    (the study) and one off its east end to the north (the gym), both behind wall stubs; a wardrobe
    stands across the living area's east end, hiding it from the middle."""
    img = blank(300, 360)
    carve(img, 110, 190, 40, 320)  # the living area: rows 110-190 (4 m), cols 40-320 (14 m)
    carve(img, 190, 290, 40, 140)  # the study, south of the west end
    carve(img, 10, 110, 220, 320)  # the gym, north of the east end
    img[190:194, 110:140] = WALL  # stubs narrowing the wings' openings
    img[106:110, 220:250] = WALL
    if wardrobe:
        img[122:178, 278:290] = WALL  # 0.6 x 2.8 m, free of the walls: furniture
    return img


WINGS = {"study": (90, 240), "gym": (270, 60), "living room's east part": (250, 150)}


def test_every_wing_of_an_open_plan_floor_gets_a_node(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, open_plan_map(), "flat")
    for wing, (x, y) in WINGS.items():
        nearest = min(math.dist(n.pos, (x, y)) for n in location.scene_graph.nodes) * 0.05
        assert nearest <= 2.0, f"the {wing} has no node within 2 m (nearest {nearest:.1f} m)"
    assert Counter(n.type for n in location.scene_graph.nodes)["ROOM"] == 1  # one room, named once


def furnished_room_map() -> np.ndarray:
    """A 9 x 7 m room (one space seen at a glance: its corners 5.7 m from its middle) with two rows of
    four 0.8 m desks either side of a middle aisle, its door in the north wall off a corridor."""
    img = blank(220, 260)
    carve(img, 60, 200, 40, 220)  # rows 60-200 (7 m), cols 40-220 (9 m)
    for row in (100, 150):
        for col in (50, 80, 160, 190):
            img[row:row + 16, col:col + 16] = WALL
    carve(img, 42, 60, 120, 140)  # the door
    carve(img, 10, 42, 20, 240)  # the corridor
    return img


def test_a_room_seen_at_a_glance_is_one_place_over_its_desks(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, furnished_room_map(), "office")
    inside = Counter(n.type for n in location.scene_graph.nodes if n.pos[1] >= 62)
    assert inside == Counter({"ROOM": 1}), inside


def aisle_map() -> np.ndarray:
    """A 10 x 6 m hall with a 1 m wide, 4.5 m long dead-end aisle off its east wall (between racks)."""
    img = blank(200, 400)
    carve(img, 40, 160, 20, 220)  # the hall
    carve(img, 90, 110, 220, 310)  # the aisle: rows 90-110 (1 m), cols 220-310 (4.5 m)
    return img


def test_a_long_dead_end_aisle_is_not_a_closet(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, aisle_map(), "aisle")
    aisle = Counter(n.type for n in location.scene_graph.nodes if n.pos[0] > 225)
    assert aisle["ROOM"] == 0 and aisle["DEAD END"] == 1, aisle
    assert near(location, 300, 100, 30)["DEAD END"] == 1  # at its end, by the wall


def store_map(shelves: int) -> np.ndarray:
    """A 12 x 11 m floor (132 m2) with `shelves` free-standing 2 x 1.8 m shelves (3.6 m2 each)."""
    img = blank(260, 280)
    carve(img, 20, 240, 20, 260)
    for k in range(shelves):
        r, c = 60 + 100 * (k // 2), 60 + 120 * (k % 2)
        img[r:r + 36, c:c + 40] = WALL
    return img


def test_a_floor_holding_shelves_is_drawn_as_lanes_a_room_with_a_bed_is_a_room(map_factory, tmp_path) -> None:
    store = Counter(n.type for n in extracted(map_factory, tmp_path, store_map(4), "store").scene_graph.nodes)
    assert store["ROOM"] == 0 and store.total() >= 5, store  # lanes round the shelves
    bedroom = Counter(n.type for n in extracted(map_factory, tmp_path, store_map(1), "bed").scene_graph.nodes)
    assert bedroom["ROOM"] == 1, bedroom
