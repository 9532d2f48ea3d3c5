"""Extracted graphs against the graphs a person drew (bundled maps and two drawn maps): size within
0.5-2x, every room gets a ROOM node, every node the person drew has a compatible extracted node within
2 m (recall 1.0, the issue's "done when"), and precision stays above its measured floor."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.location.extract import ExtractOptions, extract_location
from socnavgen.location.extract_score import rooms_with_room_node, score
from socnavgen.location.render import render_location_with_layout
from tests.extract.person_graphs import NAMES, person_map

# Precision measured (benchmarks/extract_bench.py: 1.0 / 0.93 / 0.79 / 0.89 / 0.94); lower is a regression.
PRECISION_FLOORS = {"home": 0.9, "hospital": 0.85, "warehouse": 0.7, "office": 0.8, "clinic": 0.85}


@pytest.mark.parametrize("name", NAMES)
def test_extracted_graph_is_close_to_the_persons(name: str, tmp_path: Path) -> None:
    pm = person_map(name, tmp_path)
    location, _ = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=1))
    s = score(pm.graph, location.scene_graph, pm.meters_per_pixel, aliases=pm.aliases)
    assert 0.5 <= s.size_ratio <= 2.0, (s.extracted_nodes, s.person_nodes)
    assert s.recall == 1.0, s.missed
    assert s.precision >= PRECISION_FLOORS[name], s.precision
    _, layout = render_location_with_layout(location)  # the picture: labels never overlap
    boxes = sorted(layout.boxes.values())
    assert not any(a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
                   for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert len(boxes) + len(layout.thinned) == len(location.scene_graph.nodes)
    found = rooms_with_room_node(location.scene_graph, pm.rooms, location.occupancy.blocked,
                                 pm.meters_per_pixel)
    assert found == len(pm.rooms), f"{found} of {len(pm.rooms)} rooms have a ROOM node"


def test_score_counts_a_missing_node_and_a_wrong_type() -> None:
    from socnavgen.location.models import Node, SceneGraph

    person = SceneGraph(nodes=[Node(id="aa", type="ROOM", pos=(0, 0)), Node(id="bb", type="DOORWAY", pos=(100, 0))])
    extracted = SceneGraph(nodes=[Node(id="cc", type="OPEN AREA", pos=(10, 0)),
                                  Node(id="dd", type="DEAD END", pos=(100, 5))])
    s = score(person, extracted, 0.05)
    assert s.recall == 0.5 and s.precision == 0.5 and s.missed[0].startswith("bb DOORWAY")
    assert score(person, extracted, 0.05, aliases={"DOORWAY": "DEAD END"}).recall == 1.0


def test_socrates_hospital_picture_stays_readable(tmp_path: Path) -> None:
    """SocRATES's scanned hospital still gives more nodes than a person would draw (see the report),
    but its picture has no overlapping label: the crowded ones are moved aside or thinned."""
    pm = person_map("socrates_hospital", tmp_path)
    location, stats = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=1))
    _, layout = render_location_with_layout(location)
    boxes = sorted(layout.boxes.values())
    assert not any(a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
                   for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert stats.rooms >= 10 and len(boxes) >= 0.8 * stats.nodes


def test_a_partial_graph_is_compared_where_the_person_drew() -> None:
    """A person who drew one corridor is compared with the nodes near that corridor, not the whole map."""
    from socnavgen.location.extract_score import within_drawn_part
    from socnavgen.location.models import Edge, Node, SceneGraph

    person = SceneGraph(nodes=[Node(id="aa", type="CORNER", pos=(0, 0)), Node(id="bb", type="CORNER", pos=(200, 0))],
                        links=[Edge(source="aa", target="bb", type="PASSAGEWAY")])
    extracted = SceneGraph(nodes=[Node(id="cc", type="SIMPLE NODE", pos=(100, 30)),  # 1.5 m off the corridor
                                  Node(id="dd", type="ROOM", pos=(100, 50)),  # 2.5 m off: another room
                                  Node(id="ee", type="DEAD END", pos=(230, 0))])  # 1.5 m past its end
    kept = within_drawn_part(person, extracted, 0.05)
    assert [n.id for n in kept.nodes] == ["cc", "ee"]


def test_socrates_small_warehouse_is_drawn_as_aisles_not_one_room(tmp_path: Path) -> None:
    """SocRATES's small warehouse (a 13.5 x 20 m floor of racks and shelf rows, the person's graph covers
    all of it): a floor that large is not one place, so its lanes are drawn (it was one ROOM and five
    OPEN AREA nodes for the person's 18); size within 0.5-2x, recall above its measured 0.67."""
    pm = person_map("socrates_small_warehouse", tmp_path)
    assert not pm.partial
    location, stats = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=1))
    s = score(pm.graph, location.scene_graph, pm.meters_per_pixel, aliases=pm.aliases)
    assert 0.5 <= s.size_ratio <= 2.0, (s.extracted_nodes, s.person_nodes)
    assert stats.rooms == 0 and stats.types.get("INTERSECTION", 0) >= 5, stats.types
    assert s.recall >= 0.65, s.missed
