"""`location check`: every problem of a location folder at once, each with what to do about it.

Rules (see docs/locations.md):
- files: location.yaml, the map image, the nav2 yaml it names, scene_graph.json must exist and parse;
- node ids: unique, 2 lowercase letters/digits; types inside the schema;
- edges: both ends exist, no self loop, no duplicate (the graph is undirected);
- geometry: a node lies inside the image on free space; an edge is judged by the one traversability
  rule of location/traverse.py (a person-sized disc walks it or a short detour beside it: fine; the
  line is free but the disc does not fit: warning; otherwise error; occupied and unknown both block); an edge a
  person walks but the robot's body (bodies.ROBOT_PASSAGE_WIDTH) does not fit along: warning;
- the graph is connected (a warning: an unreachable part is legal but usually a mistake).
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

import networkx as nx
import yaml
from pydantic import ValidationError

from socnavgen.bodies import ROBOT_PASSAGE_WIDTH
from socnavgen.errors import SocnavgenError
from socnavgen.location.location import (
    LOCATION_FILE,
    SCENE_GRAPH_FILE,
    SCENE_GRAPH_IMAGE,
    Location,
    load_location,
)
from socnavgen.location.models import NODE_ID_PATTERN, SceneGraph
from socnavgen.location.traverse import edge_verdict, robot_fits_along
from socnavgen.safeio import load_json_file, read_text_limited

Level = Literal["error", "warning"]


@dataclass
class Problem:
    """One finding. `nodes` / `edge` name what to highlight (the annotator colours them)."""

    level: Level
    message: str
    hint: str
    file: str
    line: int | None = None
    nodes: list[str] = field(default_factory=list)
    edge: tuple[str, str] | None = None

    @property
    def severity(self) -> Level:
        return self.level

    @property
    def where(self) -> str:
        return self.file + (f":{self.line}" if self.line else "")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class CheckReport:
    root: Path
    problems: list[Problem]
    nodes: int = 0
    edges: int = 0

    @property
    def errors(self) -> list[Problem]:
        return [p for p in self.problems if p.level == "error"]

    @property
    def warnings(self) -> list[Problem]:
        return [p for p in self.problems if p.level == "warning"]

    @property
    def ok(self) -> bool:
        return not self.errors

    def __iter__(self) -> Iterator[Problem]:
        return iter(self.problems)

    def __len__(self) -> int:
        return len(self.problems)


def check_location(target: Path | str | Location) -> CheckReport:
    """Load what can be loaded and report every problem; never raises for a bad folder.

    Given a loaded `Location` whose scene graph was edited in memory (the annotator), the edited graph
    is checked; line numbers then refer to nothing and are left out.
    """
    root = target.root if isinstance(target, Location) else Path(target)
    in_memory = (isinstance(target, Location) and "scene_graph" in target.__dict__
                 and not _same_as_file(target.scene_graph, root / SCENE_GRAPH_FILE))
    report = CheckReport(root=root, problems=[])
    problems = report.problems
    if not root.is_dir():
        problems.append(Problem("error", "location folder not found", "give the folder holding location.yaml",
                                str(root)))
        return report
    if isinstance(target, Location):
        location = target
    else:
        try:
            location = load_location(root)
        except SocnavgenError as exc:
            problems.append(_from_error(exc, root / LOCATION_FILE,
                                        _yaml_key_line(root / LOCATION_FILE, exc.message)))
            _check_scene_graph_file_only(root, problems)
            return report

    map_ok = _check_map(location, problems)
    graph = location.scene_graph if in_memory else _load_graph(root / SCENE_GRAPH_FILE, problems)
    if graph is None:
        return report
    report.nodes, report.edges = len(graph.nodes), len(graph.links)
    lines = _GraphLines(None if in_memory else root / SCENE_GRAPH_FILE, root / SCENE_GRAPH_FILE)
    _check_ids(graph, lines, problems)
    _check_types(location, graph, lines, problems)
    _check_edges(graph, lines, problems)
    if map_ok:
        _check_geometry(location, graph, lines, problems)
    _check_connected(graph, lines, problems)
    if not (root / SCENE_GRAPH_IMAGE).is_file():
        problems.append(Problem("warning", f"{SCENE_GRAPH_IMAGE} is missing",
                                f"render it: socnavgen location show {root} -o {root / SCENE_GRAPH_IMAGE}",
                                str(root / SCENE_GRAPH_IMAGE)))
    return report


# ------------------------------------------------------------------------------------------------ files
def _same_as_file(graph: SceneGraph, path: Path) -> bool:
    """True when an in-memory graph equals the file, so file line numbers still apply."""
    try:
        return SceneGraph.model_validate(load_json_file(path)) == graph
    except (SocnavgenError, ValidationError):
        return False


def _from_error(exc: SocnavgenError, default_file: Path, line: int | None = None) -> Problem:
    return Problem("error", exc.message, exc.hint or "fix the file", exc.file or str(default_file), exc.line or line)


def _yaml_key_line(path: Path, message: str) -> int | None:
    """Line of the first top-level key named in a validation message (best effort, for the user's eye)."""
    try:
        node = yaml.compose(read_text_limited(path))
    except Exception:
        return None
    if not isinstance(node, yaml.MappingNode):
        return None
    for key, _value in node.value:
        if re.search(rf"\b{re.escape(str(key.value))}\b", message):
            return key.start_mark.line + 1
    return None


def _check_scene_graph_file_only(root: Path, problems: list[Problem]) -> None:
    """When location.yaml is broken the scene graph can still be read and its own faults reported."""
    graph = _load_graph(root / SCENE_GRAPH_FILE, problems)
    if graph is not None:
        lines = _GraphLines(root / SCENE_GRAPH_FILE, root / SCENE_GRAPH_FILE)
        _check_ids(graph, lines, problems)
        _check_edges(graph, lines, problems)
        _check_connected(graph, lines, problems)


def _check_map(location: Location, problems: list[Problem]) -> bool:
    cfg_file = str(location.root / LOCATION_FILE)
    try:
        _ = location.map_gray
        _ = location.transform
        _ = location.occupancy
    except SocnavgenError as exc:
        in_config = exc.file in (None, cfg_file)
        problems.append(_from_error(exc, Path(cfg_file),
                                    _yaml_key_line(Path(cfg_file), exc.message) if in_config else None))
        return False
    if location.nav2 is not None:
        expected = Path(location.nav2.image).name
        if expected != Path(location.config.map).name and not location.config.occupancy_image:
            problems.append(Problem("warning", f"map is {location.config.map} but the nav2 yaml names {expected}",
                                    "point `map` at the image the nav2 yaml describes", cfg_file))
    return True


def _load_graph(path: Path, problems: list[Problem]) -> SceneGraph | None:
    if not path.is_file():
        problems.append(Problem("error", f"{SCENE_GRAPH_FILE} is missing",
                                "draw one with `socnavgen annotate` or `socnavgen location extract`", str(path)))
        return None
    from socnavgen.safeio import contained_path  # (kept out of the module imports: fewer merge conflicts)

    try:
        data = load_json_file(contained_path(path.parent, path.name))  # a symlink may not leave the folder
    except SocnavgenError as exc:
        problems.append(_from_error(exc, path))
        return None
    try:
        graph = SceneGraph.model_validate(data)
    except ValidationError as exc:
        lines = _GraphLines(path, path)
        for err in exc.errors():
            loc = err["loc"]
            line = lines.element(str(loc[0]), loc[1]) if len(loc) > 1 and isinstance(loc[1], int) else None
            where = ".".join(str(p) for p in loc) or "(top)"
            problems.append(Problem("error", f"{where}: {err['msg']}",
                                    'nodes are {"id", "type", "pos": [x, y]}, links {"source", "target", "type"}',
                                    str(path), line))
        return None
    if graph.directed or graph.multigraph:
        problems.append(Problem("warning", "scene graph is marked directed or multigraph",
                                'set "directed": false and "multigraph": false; edges are walked both ways',
                                str(path), 1))
    return graph


class _GraphLines:
    """Line numbers of the elements of "nodes" and "links" in scene_graph.json, for file:line messages."""

    def __init__(self, path: Path | None, file: Path) -> None:
        self.file = str(file)
        try:
            text = read_text_limited(path) if path is not None else ""
        except SocnavgenError:
            text = ""
        self._lines = {key: _array_element_lines(text, key) for key in ("nodes", "links")}

    def element(self, key: str, index: int) -> int | None:
        lines = self._lines.get(key, [])
        return lines[index] if 0 <= index < len(lines) else None


def _array_element_lines(text: str, key: str) -> list[int]:
    match = re.search(rf'"{key}"\s*:\s*\[', text)
    if not match:
        return []
    decoder, i = json.JSONDecoder(), match.end()
    lines: list[int] = []
    try:
        while True:
            while text[i] in " \t\r\n,":
                i += 1
            if text[i] == "]":
                return lines
            lines.append(text.count("\n", 0, i) + 1)
            _, i = decoder.raw_decode(text, i)
    except (IndexError, ValueError):
        return lines


# ------------------------------------------------------------------------------------------------ graph
def _check_ids(graph: SceneGraph, lines: _GraphLines, problems: list[Problem]) -> None:
    seen: dict[str, int] = {}
    for i, node in enumerate(graph.nodes):
        line = lines.element("nodes", i)
        if node.id in seen:
            problems.append(Problem("error", f"duplicate node id {node.id!r} (nodes {seen[node.id]} and {i})",
                                    "give every node its own id; `socnavgen annotate` picks free ones",
                                    lines.file, line, nodes=[node.id]))
        else:
            seen[node.id] = i
        if not NODE_ID_PATTERN.fullmatch(node.id):
            problems.append(Problem("error", f"node id {node.id!r} is not 2 lowercase letters or digits",
                                    "use a random 2-character id such as 'k3' (no order, no meaning)",
                                    lines.file, line, nodes=[node.id]))


def _check_types(location: Location, graph: SceneGraph, lines: _GraphLines, problems: list[Problem]) -> None:
    node_types, edge_types = location.schema.node_types, location.schema.edge_types
    for i, node in enumerate(graph.nodes):
        if node.type not in node_types:
            problems.append(Problem("error", f"node {node.id} has type {node.type!r}, not in the schema",
                                    f"use one of {', '.join(node_types)} or add it to schema.node_types "
                                    "in location.yaml", lines.file, lines.element("nodes", i), nodes=[node.id]))
    for i, edge in enumerate(graph.links):
        if edge.type not in edge_types:
            problems.append(Problem("error", f"edge {edge.source}-{edge.target} has type {edge.type!r}, "
                                    "not in the schema",
                                    f"use one of {', '.join(edge_types)} or add it to schema.edge_types "
                                    "in location.yaml", lines.file, lines.element("links", i),
                                    edge=(edge.source, edge.target)))


def _check_edges(graph: SceneGraph, lines: _GraphLines, problems: list[Problem]) -> None:
    ids = set(graph.node_ids())
    seen: dict[frozenset[str], int] = {}
    for i, edge in enumerate(graph.links):
        line = lines.element("links", i)
        for end in (edge.source, edge.target):
            if end not in ids:
                problems.append(Problem("error", f"edge {edge.source}-{edge.target} names unknown node {end!r}",
                                        "add the node or fix the id in the edge", lines.file, line,
                                        edge=(edge.source, edge.target)))
        if edge.source == edge.target:
            problems.append(Problem("error", f"edge {edge.source}-{edge.target} is a self loop",
                                    "remove it: an edge must join two different nodes", lines.file, line,
                                    nodes=[edge.source]))
            continue
        pair = frozenset((edge.source, edge.target))
        if pair in seen:
            problems.append(Problem("error", f"duplicate edge {edge.source}-{edge.target} (links {seen[pair]} "
                                    f"and {i}; edges are undirected)", "keep one of them", lines.file, line,
                                    edge=(edge.source, edge.target)))
        else:
            seen[pair] = i


def _check_geometry(location: Location, graph: SceneGraph, lines: _GraphLines, problems: list[Problem]) -> None:
    occupancy, transform = location.occupancy, location.transform
    w, h = occupancy.width, occupancy.height
    placed: dict[str, tuple[float, float]] = {}
    for i, node in enumerate(graph.nodes):
        x, y = node.pos
        line = lines.element("nodes", i)
        if not occupancy.inside(x, y):
            problems.append(Problem("error", f"node {node.id} at pixel ({x:g}, {y:g}) is outside the "
                                    f"{w}x{h} map image", "move it onto the map", lines.file, line, nodes=[node.id]))
            continue
        placed.setdefault(node.id, (x, y))
        wx, wy = transform.pixel_to_world(x, y)
        what = "an occupied" if occupancy.occupied[int(y), int(x)] else "an unknown"
        if occupancy.is_blocked(x, y):
            problems.append(Problem("error", f"node {node.id} at pixel ({x:g}, {y:g}) = world ({wx:.2f}, {wy:.2f}) m "
                                    f"is on {what} pixel", "move it onto free (white) floor", lines.file, line,
                                    nodes=[node.id]))
    for i, edge in enumerate(graph.links):
        if edge.source not in placed or edge.target not in placed or edge.source == edge.target:
            continue
        a, b = placed[edge.source], placed[edge.target]
        if occupancy.is_blocked(*a) or occupancy.is_blocked(*b):
            continue  # already reported on the node; the edge message would only repeat it
        verdict = edge_verdict(occupancy.clearance_px, a, b, transform.meters_per_pixel)
        if verdict.level == "ok":
            if not robot_fits_along(occupancy.blocked, a, b, transform.meters_per_pixel):
                problems.append(Problem(
                    "warning", f"edge {edge.source}-{edge.target} is wide enough for a person but not for the robot "
                    f"({ROBOT_PASSAGE_WIDTH:.2f} m wall to wall): a robot route along it scrapes the walls or stalls",
                    "keep it if only people use it (a person-only passage); otherwise move the edge where the way is "
                    "wider or remove it", lines.file, lines.element("links", i), edge=(edge.source, edge.target)))
            continue
        px, py = verdict.tight_at or (int(a[0]), int(a[1]))
        wx, wy = transform.pixel_to_world(px, py)
        name, line = f"edge {edge.source}-{edge.target}", lines.element("links", i)
        if verdict.level == "warning":
            problems.append(Problem(
                "warning", f"{name} is narrower than a person ({2 * verdict.need_m:.2f} m) at pixel ({px}, {py}) "
                f"= world ({wx:.2f}, {wy:.2f}) m and there is no way round close beside it",
                "people must squeeze through: move the edge where it is wider, or accept it",
                lines.file, line, edge=(edge.source, edge.target)))
            continue
        blocked = occupancy.segment_blocked_pixels(a, b)
        if blocked:
            px, py = blocked[0]
            wx, wy = transform.pixel_to_world(px, py)
        what = ("a wall (occupied)" if occupancy.occupied[py, px] else "unmapped (unknown) space") if blocked \
            else f"a gap narrower than {2 * verdict.need_m:.2f} m"
        problems.append(Problem(
            "error", f"{name} crosses {what}: {len(blocked)} blocked pixel(s), first at pixel ({px}, {py}) = world "
            f"({wx:.2f}, {wy:.2f}) m, with no short way around close beside the line",
            "people walk along edges in a straight line: add a node to go around the obstacle",
            lines.file, line, edge=(edge.source, edge.target)))


def _check_connected(graph: SceneGraph, lines: _GraphLines, problems: list[Problem]) -> None:
    g = nx.Graph()
    g.add_nodes_from(graph.node_ids())
    g.add_edges_from((e.source, e.target) for e in graph.links if e.source in g and e.target in g)
    if g.number_of_nodes() == 0:
        problems.append(Problem("error", "the scene graph has no nodes", "annotate the map first", lines.file))
        return
    components = sorted((sorted(c) for c in nx.connected_components(g)), key=lambda c: (-len(c), c))
    if len(components) > 1:
        rest = "; ".join("{" + ", ".join(c[:8]) + (", ..." if len(c) > 8 else "") + "}" for c in components[1:])
        problems.append(Problem("warning", f"the graph has {len(components)} disconnected parts: the largest has "
                                f"{len(components[0])} nodes, cut off: {rest}",
                                "connect them with an edge, or paths between the parts are impossible",
                                lines.file, nodes=[n for c in components[1:] for n in c]))
