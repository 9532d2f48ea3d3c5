"""The maps with a person's scene graph (tests/extract/data/person_graphs.json): the bundled example
locations and the maps of drawn_maps.py. Used by the tests and by benchmarks/extract_bench.py."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from socnavgen.location import load_location
from socnavgen.location.location import read_nav2_yaml
from socnavgen.location.models import Node, SceneGraph
from socnavgen.location.scene_graph import read_scene_graph
from tests.extract.drawn_maps import DRAWN
from tests.extract.synthetic_maps import RES, write_map

ROOT = Path(__file__).resolve().parents[2]
DATA = json.loads((Path(__file__).parent / "data" / "person_graphs.json").read_text())
NAMES = ["home", "hospital", "warehouse", "office", "clinic"]  # the maps of the "done when"
SOCRATES = ["socrates_hospital", "socrates_arena", "socrates_small_warehouse"]  # SocRATES's maps and graphs (Apache-2.0, see NOTICE)


@dataclass
class PersonMap:
    name: str
    map_yaml: Path
    graph: SceneGraph
    meters_per_pixel: float
    aliases: dict[str, str] = field(default_factory=dict)
    rooms: list[tuple[float, float]] = field(default_factory=list)  # a point inside every room
    partial: str = ""  # the part of the map the person drew on, when not all of it


def person_map(name: str, workdir: Path) -> PersonMap:
    """The map (drawn maps are written under `workdir`) and the graph a person drew on it."""
    entry = DATA[name]
    if name in DRAWN:
        map_yaml = write_map(workdir / f"drawn_{name}", DRAWN[name](), name)
        nodes = [Node(id=f"p{i}" if i < 10 else f"{chr(97 + i - 10)}q", type=t, pos=(x, y))
                 for i, (t, x, y) in enumerate(entry["nodes"])]
        return PersonMap(name, map_yaml, SceneGraph(nodes=nodes), RES,
                         rooms=[tuple(p) for p in entry["rooms"]])
    if name in SOCRATES:
        folder = Path(__file__).parent / "data" / name
        graph = read_scene_graph(folder / "scene_graph.json")
        nav2 = read_nav2_yaml(folder / "map.yaml")
        return PersonMap(name, folder / "map.yaml", graph, float(nav2.resolution), aliases=entry["aliases"],
                         partial=entry.get("partial", ""))
    hand = load_location(ROOT / "examples" / "locations" / name)
    return PersonMap(name, hand.root / "map.yaml", hand.scene_graph, hand.transform.meters_per_pixel,
                     aliases=entry["aliases"], rooms=[tuple(p) for p in entry["rooms"]])
