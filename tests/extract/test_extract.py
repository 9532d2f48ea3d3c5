"""`location extract` on maps drawn in the test: the graph has the expected topology and types,
every node stands in free space and every edge is a straight segment clear of walls."""

from __future__ import annotations

import json
import re
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from socnavgen.annotate.bridge import run_check
from socnavgen.location import load_location
from socnavgen.location.extract import ExtractOptions, extract_location, extract_scene_graph
from socnavgen.location.occupancy import occupancy_from_image
from socnavgen.location.traverse import edge_verdict
from tests.extract.synthetic_maps import RES, carve, ell_map, plus_map, ring_map, room_door_map


def extracted(map_factory, tmp_path: Path, img: np.ndarray, name: str, **opts):
    location, stats = extract_location(map_factory(img, name), tmp_path / name, ExtractOptions(seed=7, **opts))
    return location, stats


def assert_sound(location, robot_ways: bool = True) -> None:
    """Nodes on free pixels, straight edges over free pixels only, ids in the SocRATES format; with `robot_ways`
    False (a graph extracted with robot_width_m=0) the check may warn of edges too narrow for the robot only."""
    occ = location.occupancy
    graph = location.scene_graph
    ids = [n.id for n in graph.nodes]
    assert len(set(ids)) == len(ids) and all(re.fullmatch(r"[a-z0-9]{2}", i) for i in ids)
    for node in graph.nodes:
        assert not occ.is_blocked(*node.pos), f"node {node.id} at {node.pos} is on an obstacle"
        assert node.type in location.schema.node_types
    for edge in graph.links:
        a, b = graph.node(edge.source).pos, graph.node(edge.target).pos
        assert edge_verdict(occ.clearance_px, a, b, location.transform.meters_per_pixel).level == "ok", \
            f"edge {edge.source}-{edge.target} is not walkable"
        assert edge.type in location.schema.edge_types
    problems = run_check(location)
    if not robot_ways:
        problems = [p for p in problems if "not for the robot" not in p["message"]]
    assert problems == []


def degree(location, node_id: str) -> int:
    return location.graph.degree(node_id)


def test_plus_corridor_gives_one_four_way_intersection(map_factory, tmp_path: Path) -> None:
    location, _ = extracted(map_factory, tmp_path, plus_map(), "plus")
    assert_sound(location)
    crossings = [n for n in location.scene_graph.nodes if n.type == "INTERSECTION"]
    assert len(crossings) == 1
    assert degree(location, crossings[0].id) == 4
    assert np.allclose(crossings[0].pos, (150, 150), atol=4)
    assert Counter(n.type for n in location.scene_graph.nodes)["DEAD END"] == 4
    assert 5 <= len(location.scene_graph.nodes) <= 13


def test_l_corridor_has_a_blind_corner_at_the_turn(map_factory, tmp_path: Path) -> None:
    location, _ = extracted(map_factory, tmp_path, ell_map(), "ell")
    assert_sound(location)
    corners = [n for n in location.scene_graph.nodes if n.type == "BLIND CORNER"]
    assert len(corners) == 1
    assert np.allclose(corners[0].pos, (46, 254), atol=6)
    assert nx_is_path(location)


def nx_is_path(location) -> bool:
    import networkx as nx

    g = location.graph
    return nx.is_connected(g) and sorted(d for _, d in g.degree())[:2] == [1, 1] and max(d for _, d in g.degree()) == 2


def test_room_with_door_has_a_doorway_and_a_room_node(map_factory, tmp_path: Path) -> None:
    location, _ = extracted(map_factory, tmp_path, room_door_map(), "room")
    assert_sound(location)
    types = Counter(n.type for n in location.scene_graph.nodes)
    doors = [n for n in location.scene_graph.nodes if n.type == "DOORWAY"]
    assert len(doors) == 1
    assert 228 <= doors[0].pos[0] <= 242 and abs(doors[0].pos[1] - 150) <= 3  # in the door opening
    assert types["ROOM"] == 1 and types["INTERSECTION"] == 1  # the room is one node, not its skeleton
    near_door = {e.type for e in location.scene_graph.links if doors[0].id in (e.source, e.target)}
    assert near_door == {"NARROW PASSAGEWAY"}


def test_curved_corridor_is_cut_into_clear_straight_edges(map_factory, tmp_path: Path) -> None:
    location, _ = extracted(map_factory, tmp_path, ring_map(), "ring")
    assert_sound(location)
    g = location.graph
    assert len(g) >= 6 and all(d == 2 for _, d in g.degree())  # one closed loop of simple segments


def test_short_spurs_are_pruned_and_density_adds_nodes(tmp_path: Path) -> None:
    img = plus_map()
    carve(img, 120, 134, 60, 76)  # a 0.7 m deep alcove on one arm: skeleton noise, not a branch
    occ = occupancy_from_image(img)
    sparse, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1))
    assert Counter(n.type for n in sparse.nodes)["INTERSECTION"] == 1
    dense, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1, detail=3.0))
    assert len(dense.nodes) > len(sparse.nodes)
    kept, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1, min_spur_m=0.0))
    assert Counter(n.type for n in kept.nodes)["INTERSECTION"] >= 1


def test_nearby_junctions_are_merged(tmp_path: Path) -> None:
    img = plus_map()
    carve(img, 100, 200, 100, 200)  # a 5 m square hall at the crossing
    occ = occupancy_from_image(img)
    merged, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1, merge_m=3.0))
    centre = [n for n in merged.nodes if n.type in ("INTERSECTION", "OPEN AREA") and abs(n.pos[0] - 150) < 30]
    assert len(centre) == 1
    ids = {n.id for n in centre}
    assert sum(1 for e in merged.links if {e.source, e.target} & ids) == 4


def test_narrow_gaps_are_not_walkable(tmp_path: Path) -> None:
    img = blank_two_rooms()
    occ = occupancy_from_image(img)
    graph, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1))
    xs = [n.pos[0] for n in graph.nodes]
    assert max(xs) < 100 or min(xs) > 110  # the 0.2 m slit does not join the two rooms


def blank_two_rooms() -> np.ndarray:
    from tests.extract.synthetic_maps import blank

    img = blank(200, 220)
    carve(img, 20, 180, 20, 100)
    carve(img, 20, 180, 110, 200)
    carve(img, 95, 99, 100, 110)  # a 4 px (0.2 m) slit in the wall
    return img


def test_output_folder_is_a_complete_location(map_factory, tmp_path: Path) -> None:
    location, stats = extracted(map_factory, tmp_path, plus_map(), "folder")
    out = tmp_path / "folder"
    assert {p.name for p in out.iterdir()} >= {"location.yaml", "map.yaml", "folder.pgm", "scene_graph.json",
                                               "scene_graph.png"}
    reloaded = load_location(out)
    assert reloaded.config.nav2_map == "map.yaml"
    assert reloaded.transform.meters_per_pixel == pytest.approx(RES)
    assert "INTERSECTION" in reloaded.schema.node_types and "NARROW PASSAGEWAY" in reloaded.schema.edge_types
    assert "1 intersection" in reloaded.config.description
    data = json.loads((out / "scene_graph.json").read_text())
    assert data["directed"] is False and len(data["nodes"]) == stats.nodes
    assert all(isinstance(v, int) for n in data["nodes"] for v in n["pos"])
    with pytest.raises(Exception, match="already holds a location"):
        extract_location(map_factory(plus_map(), "folder"), out)


def test_result_opens_in_the_annotator(map_factory, tmp_path: Path) -> None:
    from starlette.testclient import TestClient

    from socnavgen.annotate.server import create_app

    location, stats = extracted(map_factory, tmp_path, room_door_map(), "annot")
    state = TestClient(create_app(tmp_path / "annot"), base_url="http://127.0.0.1:1").get("/api/location").json()
    assert len(state["graph"]["nodes"]) == stats.nodes and state["warnings"] == []


def noisy(img: np.ndarray, seed: int) -> np.ndarray:
    """Ragged wall edges and speckle, as a SLAM map has them."""
    from scipy import ndimage

    rng = np.random.default_rng(seed)
    free = img > 0
    edge = free ^ ndimage.binary_erosion(free)
    out = img.copy()
    out[edge & (rng.random(img.shape) < 0.3)] = 0
    out[free & (rng.random(img.shape) < 0.002)] = 0
    return out


@pytest.mark.parametrize("seed", [0, pytest.param(1, marks=pytest.mark.xfail(
    strict=True, reason="known gap: wall noise makes a spurious DOORWAY at the L's turn, hiding the BLIND CORNER")), 2])
def test_noise_does_not_add_junctions_or_hide_corners(seed: int) -> None:
    for img, wanted in ((plus_map(), "INTERSECTION"), (ell_map(), "BLIND CORNER")):
        occ = occupancy_from_image(noisy(img, seed))
        graph, _ = extract_scene_graph(occ, RES, ExtractOptions(seed=1))
        types = Counter(n.type for n in graph.nodes)
        assert types[wanted] == 1, types
        assert types["INTERSECTION"] == (1 if wanted == "INTERSECTION" else 0), types
        for e in graph.links:  # walkable by the one rule: speckle is stepped around, never a wall crossed
            assert edge_verdict(occ.clearance_px, graph.node(e.source).pos, graph.node(e.target).pos,
                                RES).level == "ok"
        assert not any(occ.is_blocked(*n.pos) for n in graph.nodes)
