"""`location extract` on the three bundled maps: it finds the junctions a person annotated by hand,
passes `location check`, and stays within a sensible size."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.location.check import check_location
from socnavgen.location.extract import ExtractOptions, extract_location
from tests.extract.test_extract import assert_sound

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"


@pytest.mark.parametrize("name", ["warehouse", "hospital", "home"])
def test_extract_finds_the_hand_annotated_junctions(name: str, tmp_path: Path) -> None:
    hand = load_location(EXAMPLES / name)
    location, stats = extract_location(EXAMPLES / name / "map.yaml", tmp_path / name, ExtractOptions(seed=3))
    assert_sound(location)
    report = check_location(tmp_path / name)
    assert report.problems == [], [p.message for p in report.problems]

    mpp = hand.transform.meters_per_pixel
    junction_like = [n for n in location.scene_graph.nodes
                     if n.type in ("INTERSECTION", "OPEN AREA") or location.graph.degree(n.id) >= 3]
    hand_junctions = [n for n in hand.scene_graph.nodes
                      if hand.graph.degree(n.id) >= 3 and n.type != "OPEN AREA"]
    assert hand_junctions, "the bundled graph should have junctions to compare with"
    for n in hand_junctions:
        nearest = min(math.dist(n.pos, m.pos) for m in junction_like) * mpp
        assert nearest <= 2.0, f"hand junction {n.id} ({n.type}) at {n.pos}: nearest extracted is {nearest:.1f} m"
    assert 0.8 * len(hand.scene_graph.nodes) <= stats.nodes <= 2.5 * len(hand.scene_graph.nodes)


def test_warehouse_aisles_are_narrow_and_the_l_corridor_has_blind_corners(tmp_path: Path) -> None:
    location, _ = extract_location(EXAMPLES / "warehouse" / "map.yaml", tmp_path / "w", ExtractOptions(seed=3))
    types = [n.type for n in location.scene_graph.nodes]
    assert types.count("BLIND CORNER") >= 2
    assert sum(e.type == "NARROW PASSAGEWAY" for e in location.scene_graph.links) >= 8  # 4 aisles x >= 2 edges


def test_hospital_room_doors_become_doorways(tmp_path: Path) -> None:
    location, _ = extract_location(EXAMPLES / "hospital" / "map.yaml", tmp_path / "h", ExtractOptions(seed=3))
    hand = load_location(EXAMPLES / "hospital")
    mpp = hand.transform.meters_per_pixel
    doors = [n for n in location.scene_graph.nodes if n.type == "DOORWAY"]
    hand_doors = [n for n in hand.scene_graph.nodes if n.type == "DOORWAY"]
    found = sum(1 for h in hand_doors if min(math.dist(h.pos, d.pos) for d in doors) * mpp <= 0.5)
    assert found >= 0.75 * len(hand_doors), f"{found} of {len(hand_doors)} hand-marked doorways found"
