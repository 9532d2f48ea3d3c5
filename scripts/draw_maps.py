"""Draw the bundled example locations (warehouse, hospital, home) from our own geometry.

Run `python scripts/draw_maps.py` to (re)write examples/locations/<name>/ with map.pgm, map.yaml,
location.yaml, scene_graph.json and scene_graph.png. Output is byte-for-byte reproducible: the
geometry, the node ids and the rendering are all fixed. The script refuses to write a location
whose graph is unsound (node off free space, edge through a wall, disconnected graph).

Geometry is written in metres in the map's local frame (x right, y up from the lower-left corner
of the image), the same frame as a nav2 map before `origin` is applied.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path

import networkx as nx
import numpy as np
import yaml

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from socnavgen.location import load_location  # noqa: E402
from socnavgen.location.models import Edge, Node, SceneGraph  # noqa: E402
from socnavgen.location.render import write_location_png  # noqa: E402
from socnavgen.location.scene_graph import to_networkx, write_scene_graph  # noqa: E402
from socnavgen.safeio import atomic_write_bytes, atomic_write_text  # noqa: E402

FREE, OCCUPIED, UNKNOWN = 254, 0, 205  # map_server trinary values
WALL = 0.15  # m, wall thickness
MIN_NODE_CLEARANCE = 0.3  # m: a person standing on a node must not touch a wall


@dataclass
class MapDrawing:
    """A trinary occupancy image drawn in metres; rows of the array count from the top."""

    width_m: float
    height_m: float
    resolution: float
    grid: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.grid = np.full((self.rows, self.cols), UNKNOWN, dtype=np.uint8)

    @property
    def cols(self) -> int:
        return round(self.width_m / self.resolution)

    @property
    def rows(self) -> int:
        return round(self.height_m / self.resolution)

    def _box(self, x0: float, y0: float, x1: float, y1: float) -> tuple[slice, slice]:
        s = self.resolution
        c0, c1 = round(min(x0, x1) / s), round(max(x0, x1) / s)
        r0, r1 = self.rows - round(max(y0, y1) / s), self.rows - round(min(y0, y1) / s)
        return slice(max(r0, 0), min(r1, self.rows)), slice(max(c0, 0), min(c1, self.cols))

    def fill(self, x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        self.grid[self._box(x0, y0, x1, y1)] = value

    def free(self, x0: float, y0: float, x1: float, y1: float) -> None:
        self.fill(x0, y0, x1, y1, FREE)

    def wall(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """An axis-aligned wall of thickness WALL centred on the segment (x0, y0)-(x1, y1)."""
        t = WALL / 2
        if x0 == x1:
            self.fill(x0 - t, min(y0, y1) - t, x0 + t, max(y0, y1) + t, OCCUPIED)
        elif y0 == y1:
            self.fill(min(x0, x1) - t, y0 - t, max(x0, x1) + t, y0 + t, OCCUPIED)
        else:
            raise ValueError("walls are axis-aligned")

    def room(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """Free floor with walls around it."""
        self.free(x0, y0, x1, y1)
        self.wall(x0, y0, x1, y0)
        self.wall(x0, y1, x1, y1)
        self.wall(x0, y0, x0, y1)
        self.wall(x1, y0, x1, y1)

    def block(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """A solid object as a laser scanner maps it: an occupied outline around an unseen inside."""
        self.fill(x0, y0, x1, y1, OCCUPIED)
        inner = 2 * self.resolution
        if abs(x1 - x0) > 3 * inner and abs(y1 - y0) > 3 * inner:
            self.fill(min(x0, x1) + inner, min(y0, y1) + inner, max(x0, x1) - inner, max(y0, y1) - inner, UNKNOWN)

    def door(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """An opening cut through a wall; (x0, y0)-(x1, y1) spans the opening along the wall."""
        t = WALL
        if x0 == x1:
            self.free(x0 - t, y0, x0 + t, y1)
        else:
            self.free(x0, y0 - t, x1, y0 + t)

    def pixel(self, x: float, y: float) -> tuple[int, int]:
        """Integer pixel (x right, y down) whose centre is nearest the local point (x, y) in metres."""
        s = self.resolution
        return round(x / s - 0.5), round(self.rows - y / s - 0.5)


@dataclass
class Example:
    name: str
    description: str
    resolution: float
    origin: tuple[float, float, float]
    drawing: MapDrawing
    node_types: list[str]
    edge_types: list[str]
    nodes: list[tuple[str, str, float, float]]  # (id, type, x m, y m)
    edges: list[tuple[str, str, str]]  # (source, target, type)


# --------------------------------------------------------------------------------------------------
# Warehouse: 24 m x 16 m at 0.05 m/px (480 x 320 px), origin not centred.
# --------------------------------------------------------------------------------------------------
def warehouse() -> Example:
    d = MapDrawing(24.0, 16.0, 0.05)
    d.room(1, 1, 23, 15)
    d.door(3, 1, 5, 1)  # loading door in the south wall
    d.free(3, 0.3, 5, 0.9)  # apron just outside the door
    d.block(1, 10, 7, 15)  # office block (closed, its inside never scanned)
    d.block(2.5, 5, 9, 7.8)  # pallet stacks
    d.block(9, 5, 10, 13)  # tall rack
    for x0 in (11, 13, 15, 17, 19):  # five racks with 1 m aisles between them
        d.block(x0, 4, x0 + 1, 12)
    d.block(21.8, 6.0, 22.8, 7.2)  # pallet left in the staging area
    nodes = [
        ("sk", "ENTRANCE", 4.0, 1.8),
        ("up", "OPEN AREA", 5.5, 3.0),
        ("co", "CORNER", 1.75, 3.0),
        ("54", "BLIND CORNER", 1.75, 8.9),
        ("f7", "BLIND CORNER", 8.0, 8.9),
        ("6r", "BLIND CORNER", 8.0, 14.0),
        ("hd", "INTERSECTION", 10.5, 14.0),
        ("zg", "INTERSECTION", 14.5, 14.0),
        ("p0", "INTERSECTION", 18.5, 14.0),
        ("mq", "OPEN AREA", 21.5, 14.0),
        ("12", "AISLE END", 14.5, 11.6),
        ("qs", "AISLE END", 14.5, 4.4),
        ("xq", "AISLE END", 18.5, 11.6),
        ("yh", "AISLE END", 18.5, 4.4),
        ("ki", "INTERSECTION", 10.5, 2.5),
        ("sh", "INTERSECTION", 14.5, 2.5),
        ("sw", "INTERSECTION", 18.5, 2.5),
        ("vj", "OPEN AREA", 21.5, 2.5),
        ("9z", "OPEN AREA", 21.0, 8.5),
    ]
    edges = [
        ("sk", "up", "PASSAGEWAY"), ("up", "co", "PASSAGEWAY"), ("co", "54", "PASSAGEWAY"),
        ("54", "f7", "PASSAGEWAY"), ("f7", "6r", "PASSAGEWAY"), ("6r", "hd", "PASSAGEWAY"),
        ("hd", "zg", "PASSAGEWAY"), ("zg", "p0", "PASSAGEWAY"), ("p0", "mq", "PASSAGEWAY"),
        ("hd", "ki", "NARROW AISLE"),
        ("zg", "12", "PASSAGEWAY"), ("12", "qs", "NARROW AISLE"), ("qs", "sh", "PASSAGEWAY"),
        ("p0", "xq", "PASSAGEWAY"), ("xq", "yh", "NARROW AISLE"), ("yh", "sw", "PASSAGEWAY"),
        ("up", "ki", "PASSAGEWAY"), ("ki", "sh", "PASSAGEWAY"), ("sh", "sw", "PASSAGEWAY"),
        ("sw", "vj", "PASSAGEWAY"), ("vj", "9z", "OPEN SPACE"), ("9z", "mq", "OPEN SPACE"),
    ]
    description = (
        "A small warehouse, 22 m x 14 m inside. Goods come in through the loading door in the south "
        "wall (ENTRANCE) into an OPEN AREA. Five storage racks stand in a block in the middle with "
        "1 m wide aisles between them: an aisle is entered at an AISLE END and an edge of type "
        "NARROW AISLE runs through it, too narrow for a person and a robot to pass side by side. "
        "Cross aisles along the north and south ends of the racks meet the aisles at INTERSECTIONs. "
        "West of the racks a corridor runs in an L around a closed office block and pallet stacks; "
        "its turns are BLIND CORNERs, where the walls hide whoever comes from the other leg. A CORNER "
        "is a turn you can see around. East of the racks is an open staging area (OPEN AREA nodes, "
        "linked by OPEN SPACE edges) where pallets are packed; other edges are PASSAGEWAYs, about "
        "2 m wide. Workers walk, push carts and stop to pick goods from the racks."
    )
    return Example("warehouse", description, 0.05, (-3.0, -5.5, 0.0), d,
                   ["ENTRANCE", "INTERSECTION", "BLIND CORNER", "CORNER", "AISLE END", "OPEN AREA"],
                   ["PASSAGEWAY", "NARROW AISLE", "OPEN SPACE"], nodes, edges)


# --------------------------------------------------------------------------------------------------
# Hospital ward: 30 m x 14 m at 0.05 m/px (600 x 280 px).
# --------------------------------------------------------------------------------------------------
def hospital() -> Example:
    d = MapDrawing(30.0, 14.0, 0.05)
    d.room(1, 5.5, 22, 8)  # ward corridor
    room_edges = [1, 6.25, 11.5, 16.75, 22]
    for x0, x1 in zip(room_edges, room_edges[1:], strict=False):
        d.room(x0, 8, x1, 13)  # north rooms
        d.room(x0, 1, x1, 5.5)  # south rooms (the third is the nurse station)
    for x0, x1 in zip(room_edges, room_edges[1:], strict=False):
        mid = (x0 + x1) / 2
        d.door(mid - 0.6, 8, mid + 0.6, 8)
        if x0 != 11.5:
            d.door(mid - 0.6, 5.5, mid + 0.6, 5.5)
    d.door(12.0, 5.5, 16.25, 5.5)  # the nurse station is open to the corridor over its counter
    d.block(12.5, 2.2, 15.75, 3.0)  # nurse station desk
    for x0 in (1, 6.25, 16.75):  # beds in the south rooms
        d.block(x0 + 0.4, 1.4, x0 + 2.4, 2.6)
    for x0 in (1, 6.25, 11.5, 16.75):  # beds in the north rooms
        d.block(x0 + 0.4, 11.4, x0 + 2.4, 12.6)
    d.room(22, 2.5, 27, 11)  # elevator lobby
    d.door(22, 5.7, 22, 7.8)  # double doors between ward and lobby
    d.room(27, 7.8, 29, 10.2)  # elevator car A
    d.room(27, 3.3, 29, 5.7)  # elevator car B
    d.door(27, 8.4, 27, 9.6)
    d.door(27, 3.9, 27, 5.1)
    d.block(23.0, 9.9, 24.6, 10.6)  # waiting bench
    nodes = [
        ("ef", "CORRIDOR", 2.0, 6.75),
        ("ck", "CORRIDOR", 3.625, 6.75),
        ("i1", "CORRIDOR", 8.875, 6.75),
        ("zs", "CORRIDOR", 14.125, 6.75),
        ("1g", "CORRIDOR", 19.375, 6.75),
        ("0a", "DOORWAY", 3.625, 8.0),
        ("x5", "DOORWAY", 8.875, 8.0),
        ("rf", "DOORWAY", 14.125, 8.0),
        ("3e", "DOORWAY", 19.375, 8.0),
        ("g3", "ROOM", 4.5, 10.0),
        ("zx", "ROOM", 9.75, 10.0),
        ("sv", "ROOM", 15.0, 10.0),
        ("lw", "ROOM", 20.25, 10.0),
        ("mp", "DOORWAY", 3.625, 5.5),
        ("pf", "DOORWAY", 8.875, 5.5),
        ("0g", "DOORWAY", 19.375, 5.5),
        ("nt", "ROOM", 4.5, 3.5),
        ("tw", "ROOM", 9.75, 3.5),
        ("cn", "ROOM", 20.25, 3.5),
        ("cs", "NURSE STATION", 14.125, 4.2),
        ("cc", "DOORWAY", 22.0, 6.75),
        ("8r", "ELEVATOR LOBBY", 24.5, 6.75),
        ("lc", "ELEVATOR", 28.0, 9.0),
        ("jb", "ELEVATOR", 28.0, 4.5),
        ("8z", "ELEVATOR LOBBY", 25.8, 9.0),
        ("q9", "ELEVATOR LOBBY", 25.8, 4.5),
    ]
    edges = [
        ("ef", "ck", "CORRIDOR"), ("ck", "i1", "CORRIDOR"), ("i1", "zs", "CORRIDOR"), ("zs", "1g", "CORRIDOR"),
        ("1g", "cc", "CORRIDOR"), ("cc", "8r", "THROUGH DOOR"),
        ("ck", "0a", "THROUGH DOOR"), ("0a", "g3", "THROUGH DOOR"),
        ("i1", "x5", "THROUGH DOOR"), ("x5", "zx", "THROUGH DOOR"),
        ("zs", "rf", "THROUGH DOOR"), ("rf", "sv", "THROUGH DOOR"),
        ("1g", "3e", "THROUGH DOOR"), ("3e", "lw", "THROUGH DOOR"),
        ("ck", "mp", "THROUGH DOOR"), ("mp", "nt", "THROUGH DOOR"),
        ("i1", "pf", "THROUGH DOOR"), ("pf", "tw", "THROUGH DOOR"),
        ("1g", "0g", "THROUGH DOOR"), ("0g", "cn", "THROUGH DOOR"),
        ("zs", "cs", "OPEN SPACE"),
        ("8r", "8z", "OPEN SPACE"), ("8r", "q9", "OPEN SPACE"),
        ("8z", "lc", "THROUGH DOOR"), ("q9", "jb", "THROUGH DOOR"),
    ]
    description = (
        "A hospital ward: a 2.5 m wide corridor (CORRIDOR nodes joined by CORRIDOR edges) with patient "
        "ROOMs on both sides. Every room is entered through a DOORWAY about 1.2 m wide; an edge through "
        "a door is of type THROUGH DOOR, and people meet there face to face. Halfway down the corridor "
        "the NURSE STATION opens onto the corridor over a counter (an OPEN SPACE edge). At the east end "
        "double doors (a DOORWAY) lead into the ELEVATOR LOBBY, an open hall with a waiting bench; two "
        "ELEVATOR cars open onto the lobby, so people step out of an elevator without warning. Nurses, "
        "doctors, patients with walkers and visitors walk here; patients are slow and staff often hurry."
    )
    return Example("hospital", description, 0.05, (-12.0, -3.5, 0.0), d,
                   ["CORRIDOR", "DOORWAY", "ROOM", "NURSE STATION", "ELEVATOR LOBBY", "ELEVATOR"],
                   ["CORRIDOR", "THROUGH DOOR", "OPEN SPACE"], nodes, edges)


# --------------------------------------------------------------------------------------------------
# Home: 14 m x 10 m at 0.05 m/px (280 x 200 px).
# --------------------------------------------------------------------------------------------------
def home() -> Example:
    d = MapDrawing(14.0, 10.0, 0.05)
    d.room(1, 1, 13, 9)
    d.wall(1, 5, 13, 5)  # bedrooms and hallway (north) / living and kitchen (south)
    d.wall(5, 5, 5, 9)  # bedroom | bathroom
    d.wall(7.5, 5, 7.5, 9)  # bathroom | hallway
    d.wall(10, 5, 10, 9)  # hallway | second bedroom
    d.wall(7.5, 1, 7.5, 3)  # half wall between living room and kitchen
    d.door(3.5, 5, 4.4, 5)  # bedroom door
    d.door(5.9, 5, 6.8, 5)  # bathroom door
    d.door(8.2, 5, 9.4, 5)  # hallway opens onto the living area
    d.door(10, 6.5, 10, 7.4)  # second bedroom door
    d.door(8.3, 9, 9.3, 9)  # front door
    d.free(8.3, 9, 9.3, 9.8)  # doorstep outside
    d.block(8.0, 1.0, 13.0, 1.6)  # kitchen counter along the south wall
    d.block(12.4, 1.6, 13.0, 3.5)  # counter along the east wall
    d.block(9.5, 2.8, 11.3, 3.5)  # kitchen island
    d.block(1.2, 1.2, 3.8, 2.0)  # sofa
    d.block(2.0, 2.6, 3.2, 3.1)  # coffee table
    d.block(4.8, 1.4, 6.2, 2.4)  # dining table
    d.block(1.2, 6.6, 3.0, 8.8)  # bed
    d.block(11.2, 7.4, 12.8, 8.8)  # second bed
    d.block(5.2, 8.2, 6.0, 8.8)  # bath tub corner
    nodes = [
        ("g9", "ENTRANCE", 8.8, 8.3),
        ("i6", "HALLWAY", 8.8, 6.95),
        ("2n", "DOORWAY", 10.0, 6.95),
        ("1f", "BEDROOM", 11.5, 6.5),
        ("z2", "DOORWAY", 8.8, 5.0),
        ("vh", "LIVING ROOM", 8.8, 4.2),
        ("3y", "KITCHEN", 11.6, 4.3),
        ("2q", "KITCHEN", 11.8, 2.2),
        ("41", "LIVING ROOM", 5.5, 3.8),
        ("ai", "LIVING ROOM", 1.9, 3.9),
        ("a7", "DINING AREA", 6.7, 2.0),
        ("iq", "DOORWAY", 3.95, 5.0),
        ("lu", "BEDROOM", 4.0, 6.6),
        ("zv", "DOORWAY", 6.35, 5.0),
        ("h9", "BATHROOM", 6.35, 6.6),
    ]
    edges = [
        ("g9", "i6", "HALLWAY"), ("i6", "2n", "THROUGH DOOR"), ("2n", "1f", "THROUGH DOOR"),
        ("i6", "z2", "HALLWAY"), ("z2", "vh", "THROUGH DOOR"), ("vh", "3y", "OPEN SPACE"),
        ("3y", "2q", "OPEN SPACE"), ("vh", "41", "OPEN SPACE"), ("41", "ai", "OPEN SPACE"),
        ("41", "a7", "OPEN SPACE"), ("41", "iq", "THROUGH DOOR"), ("iq", "lu", "THROUGH DOOR"),
        ("41", "zv", "THROUGH DOOR"), ("zv", "h9", "THROUGH DOOR"),
    ]
    description = (
        "A one-floor home. The front door (ENTRANCE) opens into a narrow HALLWAY; from the hallway a "
        "DOORWAY leads into the second BEDROOM and another DOORWAY, an opening a little wider than a door, "
        "leads south into the open-plan LIVING ROOM, with a DINING AREA and, behind a half wall, the KITCHEN "
        "with its counters and island. From the living room doors lead north into the main BEDROOM and the "
        "BATHROOM. Every doorway lets only one person pass at a time: an edge through a door is THROUGH "
        "DOOR, the hallway edges are HALLWAY, and edges across a room are OPEN SPACE. Residents, children, "
        "guests and pets move between the rooms; furniture leaves little room to step aside."
    )
    return Example("home", description, 0.05, (-2.0, -1.5, 0.0), d,
                   ["ENTRANCE", "HALLWAY", "DOORWAY", "LIVING ROOM", "DINING AREA", "KITCHEN", "BEDROOM",
                    "BATHROOM"],
                   ["HALLWAY", "THROUGH DOOR", "OPEN SPACE"], nodes, edges)


EXAMPLES = {"warehouse": warehouse, "hospital": hospital, "home": home}


# --------------------------------------------------------------------------------------------------
def soundness_problems(example: Example) -> list[str]:
    """The rules `location check` enforces, plus a clearance margin only the drawings promise."""
    d = example.drawing
    blocked = d.grid != FREE
    from scipy import ndimage
    from skimage.draw import line as raster_line

    clearance_m = ndimage.distance_transform_edt(~blocked) * d.resolution
    problems = []
    pos = {}
    for node_id, _type, x, y in example.nodes:
        px, py = d.pixel(x, y)
        pos[node_id] = (px, py)
        if not (0 <= px < d.cols and 0 <= py < d.rows) or blocked[py, px]:
            problems.append(f"node {node_id} at ({x}, {y}) m is not on free space")
        elif clearance_m[py, px] < MIN_NODE_CLEARANCE:
            problems.append(f"node {node_id} at ({x}, {y}) m is {clearance_m[py, px]:.2f} m from a wall")
    for a, b, _type in example.edges:
        rows, cols = raster_line(pos[a][1], pos[a][0], pos[b][1], pos[b][0])
        if blocked[rows, cols].any():
            problems.append(f"edge {a}-{b} crosses an obstacle")
    graph = nx.Graph([(a, b) for a, b, _ in example.edges])
    graph.add_nodes_from(pos)
    if not nx.is_connected(graph):
        problems.append("graph is not connected")
    if len(pos) != len(example.nodes):
        problems.append("duplicate node id")
    return problems


def map_yaml(example: Example) -> str:
    ox, oy, yaw = example.origin
    return (f"image: map.pgm\nmode: trinary\nresolution: {example.resolution}\norigin: [{ox}, {oy}, {yaw}]\n"
            "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")


class _FoldedDumper(yaml.SafeDumper):
    """Writes long strings as folded blocks (`>`) so the description reads like the prose it is."""


_FoldedDumper.add_representer(
    str, lambda dumper, value: dumper.represent_scalar("tag:yaml.org,2002:str", value, style=">" if len(value) > 80
                                                       else None))


def location_yaml(example: Example) -> str:
    data = {"name": example.name, "description": example.description, "map": "map.pgm", "nav2_map": "map.yaml",
            "schema": {"node_types": example.node_types, "edge_types": example.edge_types}}
    return yaml.dump(data, Dumper=_FoldedDumper, sort_keys=False, width=100, allow_unicode=True)


def pgm_bytes(grid: np.ndarray) -> bytes:
    """Binary PGM (P5) exactly as map_saver writes it: header, then one byte per pixel, top row first."""
    h, w = grid.shape
    return f"P5\n{w} {h}\n255\n".encode("ascii") + grid.astype(np.uint8).tobytes()


def write_example(example: Example, out_root: Path) -> Path:
    problems = soundness_problems(example)
    if problems:
        raise SystemExit(f"{example.name}: refusing to write an unsound location:\n  " + "\n  ".join(problems))
    folder = out_root / example.name
    folder.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(folder / "map.pgm", pgm_bytes(example.drawing.grid))
    atomic_write_text(folder / "map.yaml", map_yaml(example))
    atomic_write_text(folder / "location.yaml", location_yaml(example))
    graph = SceneGraph(
        nodes=[Node(id=i, type=t, pos=example.drawing.pixel(x, y)) for i, t, x, y in example.nodes],
        links=[Edge(source=a, target=b, type=t) for a, b, t in example.edges],
    )
    assert len(to_networkx(graph).edges) == len(example.edges)
    write_scene_graph(graph, folder / "scene_graph.json")
    write_location_png(load_location(folder), folder / "scene_graph.png")
    return folder


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"locations to draw, any of {', '.join(EXAMPLES)} (default: all)")
    parser.add_argument("-o", "--out", type=Path, default=REPO / "examples" / "locations",
                        help="folder that receives one sub-folder per location")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.names) - set(EXAMPLES))
    if unknown:
        parser.error(f"unknown location(s) {', '.join(unknown)}; choose from {', '.join(EXAMPLES)}")
    for name in args.names or list(EXAMPLES):
        example = EXAMPLES[name]()
        folder = write_example(example, args.out)
        h, w = example.drawing.grid.shape
        print(f"{name}: {w}x{h} px, {len(example.nodes)} nodes, {len(example.edges)} edges -> {folder}")


if __name__ == "__main__":
    main()
