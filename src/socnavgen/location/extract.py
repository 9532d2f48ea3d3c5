"""Suggest a scene graph from an occupancy map alone.

Free space -> skeleton (thin centre lines of the walkable area) -> topological graph (junctions and
ends become nodes, skeleton branches become edges) -> cleaned (short spurs pruned, close nodes
merged) -> doorways inserted at clearance bottlenecks -> every edge made a straight segment that
keeps clear of walls (curved branches split, adding SIMPLE NODEs) -> repaired until it passes `location check`
as one connected graph (extract_repair.py) -> edges the robot's body cannot pass dropped (routes go round
them; a part reached only through such a gap goes too) -> nodes and edges typed from geometry (degree,
clearance, turn angle, line of sight). The result is a draft for the annotator.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from pathlib import Path

import networkx as nx
import numpy as np
import yaml
from scipy import ndimage
from skimage.draw import line as raster_line
from skimage.draw import polygon as draw_polygon
from skimage.morphology import skeletonize

from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.location.doorways import add_exits, insert_doorways, split_at
from socnavgen.location.extract_repair import connect_parts, reroute_blocked
from socnavgen.location.extract_types import (  # noqa: F401  (the vocabulary is re-exported from here)
    BLIND_CORNER,
    CORNER,
    DEAD_END,
    DOORWAY,
    EXTRACT_SCHEMA,
    INTERSECTION,
    NARROW_PASSAGE,
    NARROW_PASSAGEWAY,
    OPEN_AREA,
    PASSAGEWAY,
    ROOM,
    SIMPLE_NODE,
    ExtractOptions,
    Geometry,
    type_edge,
    type_node,
)
from socnavgen.location.location import (
    LOCATION_FILE,
    SCENE_GRAPH_FILE,
    SCENE_GRAPH_IMAGE,
    Location,
    load_location,
    read_nav2_yaml,
)
from socnavgen.location.models import DESCRIBE_ME, Edge, Node, SceneGraph, Schema
from socnavgen.location.occupancy import OccupancyGrid, clearance_from
from socnavgen.location.rooms import big_blocks, furniture_mask, replace_rooms
from socnavgen.location.scene_graph import ID_ALPHABET, write_scene_graph
from socnavgen.location.traverse import edge_verdict, required_clearance_px, robot_fits_along
from socnavgen.safeio import (
    MAX_IMAGE_BYTES,
    atomic_write_bytes,
    atomic_write_text,
    contained_path,
    load_yaml_file,
)

SQRT2 = math.sqrt(2.0)


@dataclass
class ExtractStats:
    skeleton_pixels: int = 0
    raw_nodes: int = 0
    nodes: int = 0
    edges: int = 0
    rooms: int = 0
    types: dict[str, int] = field(default_factory=dict)


# ---------------------------------------------------------------- skeleton and pixel graph
def walkable_space(occ: OccupancyGrid, gap_r: float, keep_all: bool) -> np.ndarray:
    """Free pixels a disc of radius gap_r can sweep (morphological opening), main component only."""
    core = occ.clearance_px >= gap_r
    opened = ndimage.distance_transform_edt(~core) <= gap_r
    opened &= ~occ.blocked
    if keep_all:
        return opened
    labels, count = ndimage.label(opened, structure=np.ones((3, 3)))
    if count <= 1:
        return opened
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))


def without_specks(blocked: np.ndarray, max_area: int) -> np.ndarray:
    """`blocked` minus obstacles of at most `max_area` pixels: sensor noise should not make a corridor
    look narrow or hide a corner, though edges still avoid every real blocked pixel."""
    labels, count = ndimage.label(blocked, structure=np.ones((3, 3)))
    if count == 0:
        return blocked
    sizes = np.bincount(labels.ravel())
    small = sizes <= max_area
    small[0] = False
    return blocked & ~small[labels]


def skeleton_adjacency(skel: np.ndarray) -> tuple[np.ndarray, list[list[int]]]:
    """Skeleton pixels (N, 2 as row, col) and their neighbour lists. A diagonal step is dropped when
    an L of two orthogonal steps joins the same pixels, so staircases do not look like junctions."""
    coords = np.argwhere(skel)
    index = np.full(skel.shape, -1, dtype=np.int64)
    index[coords[:, 0], coords[:, 1]] = np.arange(len(coords))
    padded = np.pad(skel, 1)
    pairs = []
    r, c = coords[:, 0] + 1, coords[:, 1] + 1
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        ok = padded[r + dr, c + dc]
        if dr and dc:
            ok &= ~padded[r, c + dc] & ~padded[r + dr, c]
        src = np.nonzero(ok)[0]
        dst = index[coords[src, 0] + dr, coords[src, 1] + dc]
        pairs.append(np.stack([src, dst], axis=1))
    adjacency: list[list[int]] = [[] for _ in range(len(coords))]
    for a, b in np.concatenate(pairs).tolist():
        adjacency[a].append(b)
        adjacency[b].append(a)
    return coords, adjacency


def trace_branches(coords: np.ndarray, adjacency: list[list[int]]) -> nx.MultiGraph:
    """Topological graph: pixels of degree != 2 are nodes; each chain of degree-2 pixels between them
    is an edge whose `path` lists the pixel indices from its `start` node to the other end."""
    graph = nx.MultiGraph()
    is_node = [len(nb) != 2 for nb in adjacency]
    done: set[tuple[int, int]] = set()

    def walk(start: int, first: int) -> None:
        path, prev, cur = [start, first], start, first
        done.add((min(start, first), max(start, first)))
        while not is_node[cur]:
            nxt = adjacency[cur][0] if adjacency[cur][0] != prev else adjacency[cur][1]
            done.add((min(cur, nxt), max(cur, nxt)))
            path.append(nxt)
            prev, cur = cur, nxt
        graph.add_edge(start, cur, path=path, start=start)

    for p, nbs in enumerate(adjacency):
        if is_node[p]:
            graph.add_node(p)
            for q in nbs:
                if (min(p, q), max(p, q)) not in done:
                    walk(p, q)
    for p, nbs in enumerate(adjacency):  # closed loops with no junction: cut them at one pixel
        if nbs and (min(p, nbs[0]), max(p, nbs[0])) not in done:
            is_node[p] = True
            graph.add_node(p)
            walk(p, nbs[0])
    nx.set_node_attributes(graph, {n: tuple(coords[n]) for n in graph.nodes}, "rc")
    return graph


# ---------------------------------------------------------------- graph clean-up
def _oriented(data: dict, from_node: int) -> list[int]:
    return data["path"] if data["start"] == from_node else data["path"][::-1]


def _length(path: list[int], coords: np.ndarray) -> float:
    if len(path) < 2:
        return 0.0
    steps = np.abs(np.diff(coords[path], axis=0)).sum(axis=1)
    return float(np.where(steps == 2, SQRT2, 1.0).sum())


def dissolve_chains(graph: nx.MultiGraph, keep: set[int]) -> None:
    """Join the two branches at every plain degree-2 node into one branch."""
    for n in list(graph.nodes):
        if n in keep or graph.degree(n) != 2 or graph.number_of_edges(n, n):
            continue
        (_, a, da), (_, b, db) = list(graph.edges(n, data=True))
        if a == n or b == n:
            continue
        path = _oriented(da, a) + _oriented(db, n)[1:]
        graph.remove_node(n)
        graph.add_edge(a, b, path=path, start=a)


def _is_recess(coords: np.ndarray, tip: int, junction: int, length: float, clearance: np.ndarray,
               real: np.ndarray | None, geo: Geometry) -> bool:
    """Whether the dead-end branch junction -> tip runs into a walled recess a person can step into (an
    entrance, a bay): it reaches well past the wall it opens from, and is wide at its tip, where a branch
    into a wall corner narrows to nothing and one beside a desk is narrowed by the desk (`real`)."""
    (rj, cj), (rt, ct) = coords[junction], coords[tip]
    at_tip = clearance[rt, ct]
    return bool(at_tip >= geo.recess_width / 2 and length + at_tip - clearance[rj, cj] >= geo.recess_depth
                and (real is None or real[rt, ct] >= at_tip - 1.0))


def prune_spurs(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray, geo: Geometry,
                real: np.ndarray | None = None) -> bool:
    """Drop dead-end branches shorter than the local width (skeleton noise toward wall corners), but not
    one into a walled recess (`real`: the clearance from every obstacle, furniture included)."""
    changed = False
    for n in [n for n in graph.nodes if graph.degree(n) == 1]:
        if n not in graph or graph.degree(n) != 1:
            continue
        _, other, data = next(iter(graph.edges(n, data=True)))
        if graph.degree(other) < 3:
            continue
        length, rc = _length(data["path"], coords), coords[other]
        far = coords[_oriented(data, other)[len(data["path"]) // 2:]]  # the branch's outer half
        slot = real is not None and np.median(real[far[:, 0], far[:, 1]]) < geo.slot_half  # nobody fits in
        if slot or length < max(geo.min_spur, 1.5 * clearance[rc[0], rc[1]]) \
                and not _is_recess(coords, n, other, length, clearance, real, geo):
            graph.remove_node(n)
            changed = True
    return changed


def merge_close(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray, geo: Geometry,
                real: np.ndarray | None = None) -> bool:
    """Contract branches shorter than the merge distance (a dead end's measured to the wall ahead; one
    into a walled recess is kept), keeping the node with more clearance."""
    changed = False
    for u, v, key, data in sorted(graph.edges(keys=True, data=True), key=lambda e: len(e[3]["path"])):
        if u == v or u not in graph or v not in graph or not graph.has_edge(u, v, key):
            continue
        data = graph.edges[u, v, key]  # the snapshot may be stale after earlier merges
        ru, rv = coords[u], coords[v]
        # a dead end's skeleton stops half a corridor short of the wall: a person measures to the wall
        reach = sum(float(clearance[r[0], r[1]]) for n, r in ((u, ru), (v, rv)) if graph.degree(n) == 1)
        length = _length(data["path"], coords)
        if length + reach >= geo.merge or any(graph.degree(a) == 1 and graph.degree(b) >= 3 and _is_recess(
                coords, a, b, length, clearance, real, geo) for a, b in ((u, v), (v, u))):
            continue
        keep, drop = (u, v) if clearance[ru[0], ru[1]] >= clearance[rv[0], rv[1]] else (v, u)
        bridge = _oriented(data, keep)  # keep -> drop
        graph.remove_edge(u, v, key)
        for _, other, d in list(graph.edges(drop, data=True)):
            path = bridge + _oriented(d, drop)[1:]
            if other == drop:  # a loop at the dropped node comes back to it: return to `keep`
                path += bridge[::-1][1:]
            graph.add_edge(keep, keep if other == drop else other, path=path, start=keep)
        graph.remove_node(drop)
        changed = True
    for u, v, key, data in list(graph.edges(keys=True, data=True)):  # tiny loops left by merging
        if u == v and _length(data["path"], coords) < 4 * geo.merge:
            graph.remove_edge(u, v, key)
    return changed


def drop_noise_loops(graph: nx.MultiGraph, coords: np.ndarray, walls: np.ndarray) -> bool:
    """Remove a branch that, with a parallel one, only encircles speckle (no real wall inside): the
    skeleton splits around every noise pixel, a person does not."""
    changed = False
    for u, v in {(min(a, b), max(a, b)) for a, b, k in graph.edges(keys=True) if k > 0 or a == b}:
        branches = sorted(graph.get_edge_data(u, v).items(), key=lambda kv: len(kv[1]["path"]))
        base = _oriented(branches[0][1], u)
        for key, data in (branches if u == v else branches[1:]):
            ring = coords[(base if u != v else []) + _oriented(data, v)[::-1 if u != v else 1]]
            rows, cols = draw_polygon(ring[:, 0], ring[:, 1], walls.shape)
            if not walls[rows, cols].any():
                graph.remove_edge(u, v, key)
                changed = True
    return changed


# ---------------------------------------------------------------- straight, clear edges
def chord_ok(a: np.ndarray, b: np.ndarray, clearance: np.ndarray, need: float) -> bool:
    """Clearance along the rasterised segment, drawn both ways (Bresenham is not symmetric and
    `location check` may draw it from either end)."""
    for (r0, c0), (r1, c1) in ((a, b), (b, a)):
        rows, cols = raster_line(int(r0), int(c0), int(r1), int(c1))
        if not (clearance[rows, cols] >= need).all():
            return False
    return True


def straighten(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray, geo: Geometry) -> None:
    """Split every branch until each piece is a straight chord clear of walls and not too long, and
    no two branches join the same two nodes (node-link JSON is a simple graph)."""
    for _ in range(20):
        for u, v, key, data in list(graph.edges(keys=True, data=True)):
            path = data["path"]
            cuts = _cuts(coords[path], clearance, geo, 0, len(path) - 1)
            if u == v and not cuts and len(path) > 2:
                cuts = [len(path) // 2]
            if cuts:
                graph.remove_edge(u, v, key)
                split_at(graph, data, cuts)
        parallel = {(min(a, b), max(a, b)) for a, b, k in graph.edges(keys=True) if k > 0}
        if not parallel:
            return
        for u, v in parallel:  # the second branch between two nodes gets a midpoint node
            for key, data in sorted(graph.get_edge_data(u, v).items())[1:]:
                graph.remove_edge(u, v, key)
                if len(data["path"]) > 2:
                    split_at(graph, data, [len(data["path"]) // 2])


def _cuts(pts: np.ndarray, clearance: np.ndarray, geo: Geometry, i: int, j: int) -> list[int]:
    if j - i < 2:
        return []
    seg = pts[i:j + 1]
    a, b = (float(pts[i][1]), float(pts[i][0])), (float(pts[j][1]), float(pts[j][0]))
    need = required_clearance_px(clearance, a, b, geo.mpp)
    steps = np.abs(np.diff(seg, axis=0)).sum(axis=1)
    arc = np.concatenate([[0.0], np.cumsum(np.where(steps == 2, SQRT2, 1.0))])
    parts = math.ceil(arc[-1] / geo.max_edge)
    # clear of walls (specks aside) and of specks too, or (for a piece short enough to keep) a person
    # steps around the speck it touches: the rule's detour search, costly, so only then
    walls_ok = chord_ok(pts[i], pts[j], geo.wall_clearance if geo.wall_clearance is not None else clearance, need)
    clear = walls_ok and chord_ok(pts[i], pts[j], clearance, need)
    if walls_ok and (clear or parts > 1 or edge_verdict(clearance, a, b, geo.mpp).level == "ok"):
        if parts <= 1:
            return []
        marks = sorted({i + int(np.searchsorted(arc, arc[-1] * k / parts)) for k in range(1, parts)} - {i, j})
        bounds, out = [i, *marks, j], list[int]()
        for lo, hi in zip(bounds, bounds[1:], strict=False):  # a piece of a curved branch has its own chord
            out += _cuts(pts, clearance, geo, lo, hi) + ([hi] if hi != j else [])
        return out
    d = pts[j] - pts[i]
    rel = seg - pts[i]
    dev = np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]) / max(1e-9, math.hypot(*d))
    m = i + int(np.argmax(dev[1:-1])) + 1 if j - i > 1 else (i + j) // 2
    return _cuts(pts, clearance, geo, i, m) + [m] + _cuts(pts, clearance, geo, m, j)


# ---------------------------------------------------------------- the whole pipeline
def extract_scene_graph(occ: OccupancyGrid, meters_per_pixel: float,
                        options: ExtractOptions | None = None) -> tuple[SceneGraph, ExtractStats]:
    """A draft scene graph (SocRATES node-link model, integer pixel positions) and statistics."""
    opts = options or ExtractOptions()
    geo = Geometry(opts, meters_per_pixel)
    clearance = occ.clearance_px  # real obstacles: what edges must avoid
    furniture = furniture_mask(occ.blocked, meters_per_pixel) if opts.rooms else np.zeros_like(occ.blocked)
    structure = OccupancyGrid(occupied=occ.occupied & ~furniture, unknown=occ.unknown & ~furniture)
    speck = max(2, int((0.25 / meters_per_pixel) ** 2))  # pixels: an obstacle this small is sensor noise
    walls = without_specks(structure.blocked, speck)
    wall_clearance = clearance_from(walls)  # what a person perceives: width, doors
    geo.wall_clearance = wall_clearance
    free = walkable_space(structure, geo.gap_r, opts.keep_all_components)  # rooms are cut from this
    walk = walkable_space(occ, geo.gap_r, opts.keep_all_components)
    skel = skeletonize(walk)  # edges must stay walkable
    coords, adjacency = skeleton_adjacency(skel)
    stats = ExtractStats(skeleton_pixels=len(coords))
    graph = trace_branches(coords, adjacency)
    stats.raw_nodes = graph.number_of_nodes()
    graph.remove_nodes_from([n for n in list(graph.nodes) if graph.degree(n) == 0 and len(graph) > 1])
    for _ in range(50):
        changed = prune_spurs(graph, coords, wall_clearance, geo, clearance)
        dissolve_chains(graph, keep=set())
        changed |= merge_close(graph, coords, wall_clearance, geo, clearance)
        changed |= drop_noise_loops(graph, coords, walls)
        dissolve_chains(graph, keep=set())
        if not changed:
            break
    doors, mouths = insert_doorways(graph, coords, wall_clearance, geo)
    room_nodes: set[int] = set()
    extra_nodes: set[int] = set()
    if opts.rooms:
        rooms = replace_rooms(graph, coords, doors | mouths, free, walls, wall_clearance, clearance, meters_per_pixel,
                              geo.room_cover_m, big_blocks(furniture, meters_per_pixel))
        coords, room_nodes, extra_nodes = rooms.coords, rooms.room_nodes, rooms.extra_nodes
        doors -= rooms.false_doors
        mouths -= rooms.false_doors
        dissolve_chains(graph, keep=set(graph.nodes) - rooms.false_doors)
        stats.rooms = len(room_nodes)
        _drop_orphans(graph, keep=room_nodes | extra_nodes)
    coords, exits = add_exits(graph, coords, walk, occ.blocked, clearance, geo.mpp)
    coords = connect_parts(graph, coords, clearance, geo.mpp)
    straighten(graph, coords, clearance, geo)
    coords = reroute_blocked(graph, coords, clearance, geo.mpp)
    if opts.robot_width_m > 0:
        # every real obstacle (furniture too) narrows the robot's way; sensor specks do not, as for people
        keep_robot_ways(graph, coords, without_specks(occ.blocked, speck), geo.mpp, opts.robot_width_m)

    def node_type(n: int) -> str:
        if n in exits:
            return DOORWAY
        if n in room_nodes:
            return ROOM
        if n in extra_nodes:
            return OPEN_AREA
        if n in mouths:
            return NARROW_PASSAGE
        return type_node(graph, n, coords, walls, wall_clearance, geo, doors)

    ids = _random_ids(sorted(graph.nodes), opts.seed)
    nodes = [Node(id=ids[n], type=node_type(n), pos=(int(coords[n][1]), int(coords[n][0])))
             for n in sorted(graph.nodes)]
    links = [Edge(source=ids[u], target=ids[v], type=type_edge(coords[u], coords[v], wall_clearance, geo))
             for u, v in sorted({(min(a, b), max(a, b)) for a, b in graph.edges() if a != b})]
    stats.nodes, stats.edges = len(nodes), len(links)
    for node in nodes:
        stats.types[node.type] = stats.types.get(node.type, 0) + 1
    return SceneGraph(nodes=nodes, links=links), stats


def keep_robot_ways(graph: nx.MultiGraph, coords: np.ndarray, blocked: np.ndarray, mpp: float, width_m: float) -> None:
    """Drop every edge the robot's body (`width_m` wall to wall) cannot pass, then the nodes left on none and all
    but the largest connected part: the scene graph is where scenarios route the robot as well as people, and a
    route through a gap the robot only fills (a 0.6 m slot past shelves) held every planner at its walls."""
    cut: set[int] = set()
    for u, v, key in list(graph.edges(keys=True)):
        a, b = (float(coords[u][1]), float(coords[u][0])), (float(coords[v][1]), float(coords[v][0]))
        if u != v and not robot_fits_along(blocked, a, b, mpp, width_m):
            graph.remove_edge(u, v, key)
            cut |= {u, v}
    graph.remove_nodes_from([n for n in cut if graph.degree(n) == 0])  # a lone room's only node stays
    parts = sorted(nx.connected_components(graph), key=len, reverse=True)
    for part in parts[1:]:
        graph.remove_nodes_from(part)


def _drop_orphans(graph: nx.MultiGraph, keep: set[int]) -> None:
    """Nodes left without edges once rooms replaced their skeleton (a doorway onto nothing)."""
    graph.remove_nodes_from([n for n in list(graph.nodes) if graph.degree(n) == 0 and n not in keep])


def _random_ids(nodes: list[int], seed: int | None) -> dict[int, str]:
    """Distinct random 2-character ids (the SocRATES format allows at most 36*36 nodes)."""
    capacity = len(ID_ALPHABET) ** 2
    if len(nodes) > capacity:
        raise ValidationFailed(f"the extracted graph has {len(nodes)} nodes; 2-character ids allow {capacity}",
                               hint="lower --detail, raise --min-spur, or crop the map to the area you need")
    tokens = random.Random(seed).sample(range(capacity), len(nodes))
    return {n: ID_ALPHABET[t // len(ID_ALPHABET)] + ID_ALPHABET[t % len(ID_ALPHABET)]
            for n, t in zip(nodes, tokens, strict=True)}


def describe(stats: ExtractStats, width_m: float, height_m: float, free_m2: float) -> str:
    """A factual starting description for location.yaml (the user should rewrite it)."""
    counts = ", ".join(f"{k} {t.lower()}{'s' if k != 1 else ''}" for t, k in sorted(stats.types.items()))
    return (f"An indoor area of about {width_m:.0f} m x {height_m:.0f} m with {free_m2:.0f} m2 of walkable "
            f"floor. Its scene graph (extracted automatically from the occupancy map) has {counts}. "
            + DESCRIBE_ME)


# ---------------------------------------------------------------- location folders
def start_location_folder(map_yaml: Path, out_dir: Path, *, name: str | None = None, description: str = "",
                          schema: Schema | None = None) -> Path:
    """Make `out_dir` a location folder for a nav2 map: the map image and yaml copied beside a new
    location.yaml. Refuses to replace an existing location.yaml."""
    nav2 = read_nav2_yaml(map_yaml)
    image_src = contained_path(map_yaml.parent, nav2.image) if not Path(nav2.image).is_absolute() \
        else Path(nav2.image)
    if not image_src.is_file():
        raise InputFileError(f"map image {nav2.image!r} not found", file=map_yaml, hint="check `image:` in the yaml")
    if image_src.stat().st_size > MAX_IMAGE_BYTES:
        raise InputFileError("map image is too large", file=image_src)
    out_dir = Path(out_dir)
    if (out_dir / LOCATION_FILE).exists():
        raise InputFileError(f"{out_dir / LOCATION_FILE} already exists", file=out_dir / LOCATION_FILE,
                             hint="open it with `socnavgen annotate DIR` (without --map), or pick a new folder")
    out_dir.mkdir(parents=True, exist_ok=True)
    image_name, yaml_name = image_src.name, "map.yaml" if image_src.name != "map.yaml" else "nav2_map.yaml"
    if image_src.resolve() != (out_dir / image_name).resolve():
        atomic_write_bytes(out_dir / image_name, image_src.read_bytes())
    data = load_yaml_file(map_yaml)
    data["image"] = image_name
    if map_yaml.resolve() != (out_dir / yaml_name).resolve():
        atomic_write_text(out_dir / yaml_name, yaml.safe_dump(data, sort_keys=False))
    schema = schema or EXTRACT_SCHEMA
    config = {"name": name or out_dir.resolve().name, "description": description or DESCRIBE_ME,
              "map": image_name, "nav2_map": yaml_name,
              "schema": {"node_types": list(schema.node_types), "edge_types": list(schema.edge_types)}}
    atomic_write_text(out_dir / LOCATION_FILE, yaml.safe_dump(config, sort_keys=False, allow_unicode=True, width=100))
    return out_dir


def extract_location(map_yaml: Path, out_dir: Path, options: ExtractOptions | None = None, *,
                     name: str | None = None, force: bool = False) -> tuple[Location, ExtractStats]:
    """`socnavgen location extract`: a complete location folder with a suggested scene graph."""
    map_yaml, out_dir = Path(map_yaml), Path(out_dir)
    if (out_dir / LOCATION_FILE).exists():
        if not force:
            raise InputFileError(f"{out_dir} already holds a location", file=out_dir / LOCATION_FILE,
                                 hint="use --force to replace its scene graph, or choose another -o folder")
    else:
        start_location_folder(map_yaml, out_dir, name=name)
    location = load_location(out_dir)
    graph, stats = extract_scene_graph(location.occupancy, location.transform.meters_per_pixel, options)
    mpp = location.transform.meters_per_pixel
    width, height = location.image_size
    free_m2 = float((~location.occupancy.blocked).sum()) * mpp * mpp
    data = load_yaml_file(out_dir / LOCATION_FILE)
    data["description"] = describe(stats, width * mpp, height * mpp, free_m2)
    data["schema"] = {"node_types": list(EXTRACT_SCHEMA.node_types), "edge_types": list(EXTRACT_SCHEMA.edge_types)}
    atomic_write_text(out_dir / LOCATION_FILE, yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=100))
    write_scene_graph(graph, out_dir / SCENE_GRAPH_FILE)
    location = load_location(out_dir)
    from socnavgen.location.render import png_bytes, render_location

    atomic_write_bytes(out_dir / SCENE_GRAPH_IMAGE, png_bytes(render_location(location)))
    return location, stats
