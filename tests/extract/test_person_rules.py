"""Where a person puts nodes that the skeleton alone misses or misplaces: a corridor opening into a
hall through both walls' ends is a doorway (an alcove off one wall is not), a corridor's dead end is
measured to its wall, a passage leading off a junction is named by its middle, a walled entrance
recess is a place, a closet is a room, and a room's node stands in its open middle, not by its door.
Each map is drawn in code at 0.05 m per pixel."""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

import numpy as np

from socnavgen.location.extract import ExtractOptions, extract_location
from tests.extract.synthetic_maps import blank, carve
from tests.extract.test_extract import assert_sound


def extracted(map_factory, tmp_path: Path, img: np.ndarray, name: str):
    location, _ = extract_location(map_factory(img, name), tmp_path / name, ExtractOptions(seed=5))
    assert_sound(location)
    return location


def near(location, x: float, y: float, radius_px: float) -> Counter:
    return Counter(n.type for n in location.scene_graph.nodes if math.dist(n.pos, (x, y)) <= radius_px)


def lobby_map() -> np.ndarray:
    """A 1.8 m corridor running 14 m east into a 6 x 9 m hall whose walls stand back 3.6 m on both
    sides of it, with a 5 x 4 m alcove opening off the corridor's south wall halfway along."""
    img = blank(260, 520)
    carve(img, 111, 147, 20, 300)  # the corridor: rows 111-147 (1.8 m), cols 20-300
    carve(img, 40, 220, 300, 420)  # the hall: 9 x 6 m
    carve(img, 147, 227, 110, 210)  # the alcove, open along 5 m of the corridor's south wall
    return img


def test_a_corridor_opens_into_a_hall_through_a_doorway_but_not_into_an_alcove(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, lobby_map(), "lobby")
    assert near(location, 300, 129, 20)["DOORWAY"] == 1, near(location, 300, 129, 30)  # where both walls end
    hall = Counter(n.type for n in location.scene_graph.nodes if n.pos[0] > 305)
    assert hall["ROOM"] == 1, hall
    alcove_mouth = [n for n in location.scene_graph.nodes if 100 <= n.pos[0] <= 220 and 100 <= n.pos[1] <= 160]
    assert not any(n.type == "DOORWAY" for n in alcove_mouth), alcove_mouth  # one wall goes on: no door
    assert any(n.type in {"OPEN AREA", "ROOM"} for n in location.scene_graph.nodes
               if 110 <= n.pos[0] <= 210 and 147 <= n.pos[1] <= 227), "the alcove has no node of its own"


def stub_map() -> np.ndarray:
    """A 1.8 m corridor 14 m long with a 1.8 m side corridor leaving it; the main corridor goes on 2.6 m
    past the junction's centre to its end wall (its skeleton stops 0.9 m short of that wall)."""
    img = blank(200, 400)
    carve(img, 20, 56, 20, 332)  # main corridor, ends at col 332
    carve(img, 56, 180, 262, 298)  # side corridor from the junction at col ~280
    return img


def test_a_corridor_end_2_6_m_past_a_junction_is_a_dead_end(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, stub_map(), "stub")
    ends = [n for n in location.scene_graph.nodes if n.type == "DEAD END" and n.pos[0] > 295]
    assert ends and all(abs(n.pos[1] - 38) <= 6 for n in ends), location.scene_graph.nodes


def passage_map() -> np.ndarray:
    """A corridor along the top; off its junction a 1 m passage runs 8 m south into a room."""
    img = blank(330, 300)
    carve(img, 20, 56, 20, 280)  # corridor
    carve(img, 56, 216, 130, 150)  # the passage: 1 m wide, 8 m long
    carve(img, 216, 310, 40, 260)  # the room it leads to
    return img


def test_a_narrow_passage_off_a_junction_is_named_by_its_middle(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, passage_map(), "passage")
    inside = [n for n in location.scene_graph.nodes if n.type == "NARROW PASSAGE" and 120 <= n.pos[0] <= 160]
    assert any(100 <= n.pos[1] <= 170 for n in inside), inside  # the middle is row ~136
    assert not any(n.pos[1] < 75 for n in inside), inside  # not 1 m from the junction


def entrance_map() -> np.ndarray:
    """A 2.2 m wide corridor with a 2 m wide, 0.75 m deep entrance recess in its south wall."""
    img = blank(200, 420)
    carve(img, 40, 84, 20, 400)  # rows 40-84 (2.2 m)
    carve(img, 84, 99, 180, 220)  # the recess: 2 m wide, 0.75 m deep
    return img


def test_a_walled_entrance_recess_is_a_dead_end(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, entrance_map(), "entrance")
    assert near(location, 200, 88, 16)["DEAD END"] == 1, near(location, 200, 88, 40)


def test_a_closet_behind_a_door_is_a_room_however_narrow(tmp_path) -> None:
    """The bundled hospital's two elevators: 1.8 x 2.2 m pockets behind 1.2 m openings. The door's cut
    leaves a piece whose spine is as narrow as a corridor; it is still a room, not a corridor's end."""
    from tests.extract.person_graphs import person_map

    pm = person_map("hospital", tmp_path)
    location, _ = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=5))
    pockets = [n.type for n in location.scene_graph.nodes if n.pos[0] >= 545]
    assert sorted(pockets) == ["ROOM", "ROOM"], pockets


def classroom_map() -> np.ndarray:
    """A 12 x 8 m classroom with two rows of six 1 m desks and one door at its north-east corner."""
    img = blank(240, 320)
    carve(img, 40, 200, 20, 260)  # rows 40-200 (8 m), cols 20-260 (12 m)
    for col in range(50, 230, 30):
        img[90:110, col:col + 20] = 0
        img[130:150, col:col + 20] = 0
    carve(img, 22, 40, 230, 250)  # door in the north wall
    carve(img, 4, 22, 20, 300)  # corridor
    return img


def test_a_rooms_node_stands_in_its_open_middle_not_at_its_door(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, classroom_map(), "classroom")
    (room,) = [n for n in location.scene_graph.nodes if n.type == "ROOM"]
    assert math.dist(room.pos, (140, 120)) * 0.05 <= 2.5, room.pos  # the room's middle
    assert math.dist(room.pos, (240, 40)) * 0.05 >= 4.0, room.pos  # not by the door


def slot_map() -> np.ndarray:
    """A 1.6 m corridor with a 0.5 m wide, 2 m deep slot between two cabinets in its south wall (a scan's
    gap between beds): walkable for the skeleton, but nobody's place."""
    img = blank(200, 400)
    carve(img, 40, 72, 20, 380)  # corridor rows 40-72
    carve(img, 72, 112, 195, 205)  # the slot: 10 px (0.5 m) wide, 40 px (2 m) deep
    return img


def test_a_dead_end_gap_nobody_fits_in_gets_no_node(map_factory, tmp_path) -> None:
    location = extracted(map_factory, tmp_path, slot_map(), "slot")
    assert not [n for n in location.scene_graph.nodes if n.pos[1] > 76], location.scene_graph.nodes
    assert "INTERSECTION" not in {n.type for n in location.scene_graph.nodes}  # no junction for it either
