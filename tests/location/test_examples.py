"""The bundled locations make sense for scenarios, and scripts/draw_maps.py reproduces them exactly."""

from __future__ import annotations

import hashlib
import importlib.util
import math
import sys
from pathlib import Path

import networkx as nx
import pytest

from socnavgen.location import load_location
from socnavgen.location.models import NODE_ID_PATTERN
from tests.location.conftest import BUNDLED, EXAMPLES

REPO = Path(__file__).resolve().parents[2]


def _draw_maps():
    spec = importlib.util.spec_from_file_location("draw_maps", REPO / "scripts" / "draw_maps.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["draw_maps"] = module  # dataclasses look their module up while the class is built
    spec.loader.exec_module(module)
    return module


def test_draw_maps_reproduces_bundled_files_byte_for_byte(tmp_path: Path) -> None:
    _draw_maps().main(["-o", str(tmp_path)])
    for name in BUNDLED:
        for file in ("map.pgm", "map.yaml", "location.yaml", "scene_graph.json", "scene_graph.png"):
            fresh = hashlib.sha256((tmp_path / name / file).read_bytes()).hexdigest()
            bundled = hashlib.sha256((EXAMPLES / name / file).read_bytes()).hexdigest()
            assert fresh == bundled, f"{name}/{file} differs: re-run scripts/draw_maps.py"


@pytest.mark.parametrize("name", BUNDLED)
def test_map_is_nav2_trinary(name: str) -> None:
    raw = (EXAMPLES / name / "map.pgm").read_bytes()
    assert raw.startswith(b"P5\n")
    loc = load_location(EXAMPLES / name)
    assert set(loc.map_gray.ravel().tolist()) == {0, 205, 254}
    assert loc.map_gray[0, 0] == 205  # unknown outside the walls
    assert loc.nav2.resolution in (0.05, 0.1)


@pytest.mark.parametrize("name", BUNDLED)
def test_graph_size_ids_and_description(name: str) -> None:
    loc = load_location(EXAMPLES / name)
    ids = loc.scene_graph.node_ids()
    assert 12 <= len(ids) <= 30
    assert all(NODE_ID_PATTERN.match(i) for i in ids) and len(set(ids)) == len(ids)
    assert nx.is_connected(loc.graph)
    for kind in (*loc.schema.node_types, *loc.schema.edge_types):
        assert kind in loc.config.description, f"description does not name {kind}"
    used_nodes = {n.type for n in loc.scene_graph.nodes}
    used_edges = {e.type for e in loc.scene_graph.links}
    assert used_nodes == set(loc.schema.node_types) and used_edges == set(loc.schema.edge_types)


@pytest.mark.parametrize("name", BUNDLED)
def test_intersections_of_degree_three(name: str) -> None:
    assert max(d for _, d in load_location(EXAMPLES / name).graph.degree) >= 3


def test_warehouse_blind_corners_are_blind() -> None:
    """At a BLIND CORNER two neighbours cannot see each other: walls hide one leg from the other."""
    loc = load_location(EXAMPLES / "warehouse")
    corners = [n.id for n in loc.scene_graph.nodes if n.type == "BLIND CORNER"]
    assert len(corners) >= 2
    g = loc.graph
    for c in corners:
        legs = list(g.neighbors(c))
        assert any(not loc.occupancy.segment_clear(g.nodes[a]["pos"], g.nodes[b]["pos"])
                   for i, a in enumerate(legs) for b in legs[i + 1:]), c


def test_warehouse_narrow_aisles_are_about_one_metre() -> None:
    loc = load_location(EXAMPLES / "warehouse")
    g, res = loc.graph, loc.nav2.resolution
    aisles = [(a, b) for a, b, t in g.edges(data="type") if t == "NARROW AISLE"]
    assert len(aisles) >= 2
    for a, b in aisles:
        (ax, ay), (bx, by) = g.nodes[a]["pos"], g.nodes[b]["pos"]
        mid = (round((ax + bx) / 2), round((ay + by) / 2))
        width = 2 * loc.occupancy.clearance_px[mid[1], mid[0]] * res
        assert 0.8 <= width <= 1.3, (a, b, width)


def test_hospital_has_doorways_rooms_and_elevators() -> None:
    loc = load_location(EXAMPLES / "hospital")
    g = loc.graph
    types = {n.type for n in loc.scene_graph.nodes}
    assert {"ELEVATOR", "DOORWAY", "ROOM", "NURSE STATION", "ELEVATOR LOBBY"} <= types
    for node in loc.scene_graph.nodes:
        if node.type == "ROOM":  # every room is entered through a doorway
            assert any(g.nodes[m]["type"] == "DOORWAY" for m in g.neighbors(node.id)), node.id
        if node.type == "DOORWAY":  # a doorway is narrow: 1-2 m of free width
            width = 2 * loc.occupancy.clearance_px[int(node.pos[1]), int(node.pos[0])] * loc.nav2.resolution
            assert 0.8 <= width <= 2.2, (node.id, width)


def test_home_rooms() -> None:
    loc = load_location(EXAMPLES / "home")
    types = {n.type for n in loc.scene_graph.nodes}
    assert {"KITCHEN", "LIVING ROOM", "BEDROOM", "BATHROOM", "DOORWAY", "ENTRANCE"} <= types


@pytest.mark.parametrize("name", BUNDLED)
def test_edges_are_walkable_lengths(name: str) -> None:
    loc = load_location(EXAMPLES / name)
    for a, b in loc.graph.edges:
        metres = math.dist(loc.node_world(a), loc.node_world(b))
        assert 0.5 <= metres <= 15, (a, b, metres)
