"""Finding places by type keywords (schemas differ per map) and by geometry alone."""

from __future__ import annotations

from pathlib import Path

from socnavgen.cards.generate import place_card
from socnavgen.cards.library import get_card
from socnavgen.location import load_location
from socnavgen.location.places import PlaceFinder, type_matches

from .cards_helpers import cross, l_corridor


def test_keyword_families_use_whole_words_and_exclusions() -> None:
    assert type_matches("BLIND CORNER", "blind_corner")
    assert type_matches("ENTRANCE/EXIT", "doorway")
    assert type_matches("Elevator", "elevator")
    assert not type_matches("ELEVATOR LOBBY", "elevator")  # a hall in front of elevators
    assert type_matches("ELEVATOR LOBBY", "open_area")
    assert not type_matches("HALLWAY", "open_area")  # 'hall' is a word, 'hallway' is a corridor
    assert type_matches("LIVING ROOM", "room") and type_matches("BATHROOM", "room")
    assert type_matches("NARROW AISLE", "narrow_edge") and type_matches("THROUGH DOOR", "narrow_edge")


def test_blind_corner_found_by_geometry(tmp_path: Path) -> None:
    finder = PlaceFinder(load_location(l_corridor(tmp_path / "ell")))
    corners = finder.candidates("blind_corner")
    assert [c.node for c in corners] == ["tt"]
    assert "cannot see each other" in corners[0].evidence
    fit = place_card(get_card("blind-corner"), finder.location)
    assert fit.fits
    robot, human = fit.placement.robot, fit.placement.humans[0]
    assert "tt" in robot[1:-1] and human.path[1:] == robot[::-1] and human.meets_at == "tt"
    assert human.path[0] not in robot  # starts past the robot's goal, not on it


def test_intersection_and_narrow_edge_found_by_geometry(tmp_path: Path) -> None:
    finder = PlaceFinder(load_location(cross(tmp_path / "plus")))
    assert [c.node for c in finder.candidates("intersection")] == ["xx"]
    narrow = {(c.node, c.other) for c in finder.candidates("narrow_passage")}
    assert ("e1", "e2") in narrow and ("xx", "w1") not in narrow
    assert finder.candidates("blind_corner") == []  # straight corridors only


def test_crossing_human_uses_a_branch_the_robot_does_not(tmp_path: Path) -> None:
    location = load_location(cross(tmp_path / "plus"))
    fit = place_card(get_card("intersection-no-gesture"), location)
    robot = fit.placement.robot
    human = fit.placement.humans[0].path
    assert robot.index("xx") not in (0, len(robot) - 1)
    i = human.index("xx")
    assert {human[i - 1], human[i + 1]}.isdisjoint({robot[robot.index("xx") - 1], robot[robot.index("xx") + 1]}) \
        or human[i + 1] in robot[:robot.index("xx")]  # a T-crossing may turn toward where the robot came from
    assert human[i - 1] not in robot


def test_missing_features_are_explained(tmp_path: Path) -> None:
    location = load_location(l_corridor(tmp_path / "ell"))
    fit = place_card(get_card("entering-elevator"), location)
    assert not fit.fits
    assert "ELEVATOR" in fit.reason and "schema has none" in fit.reason and "NODE" in fit.reason
    fit = place_card(get_card("intersection-wait"), location)
    assert not fit.fits and "three or more edges" in fit.reason
