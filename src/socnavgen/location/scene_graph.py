"""Read and write scene graphs in the SocRATES node-link JSON, and view them as networkx graphs."""

from __future__ import annotations

import json
import math
import secrets
import string
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from pydantic import ValidationError

from socnavgen.errors import InputFileError
from socnavgen.location.models import SceneGraph
from socnavgen.safeio import atomic_write_text, load_json_file

if TYPE_CHECKING:
    import networkx as nx

ID_ALPHABET = string.ascii_lowercase + string.digits


def new_node_id(taken: Iterable[str]) -> str:
    """A random, unused 2-character id: random so a model reads no order into the names."""
    used = set(taken)
    if len(used) >= len(ID_ALPHABET) ** 2:
        raise ValueError("no free 2-character node id left (1296 nodes)")
    while True:
        candidate = secrets.choice(ID_ALPHABET) + secrets.choice(ID_ALPHABET)
        if candidate not in used:
            return candidate


def read_scene_graph(path: Path) -> SceneGraph:
    data = load_json_file(path)
    try:
        return SceneGraph.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise InputFileError(f"scene graph does not fit the node-link format at {where}: {first['msg']}",
                             file=path, hint='expected {"nodes": [{"id", "type", "pos"}], "links": '
                                             '[{"source", "target", "type"}]}') from exc


def scene_graph_json(graph: SceneGraph) -> str:
    """The exact layout SocRATES writes (json.dump indent=4, node keys type/pos/id)."""
    data = {
        "directed": graph.directed,
        "multigraph": graph.multigraph,
        "graph": graph.graph,
        "nodes": [{"type": n.type, "pos": [_num(n.pos[0]), _num(n.pos[1])], "id": n.id} for n in graph.nodes],
        "links": [{"type": e.type, "source": e.source, "target": e.target} for e in graph.links],
    }
    return json.dumps(data, indent=4)


def write_scene_graph(graph: SceneGraph, path: Path) -> None:
    atomic_write_text(path, scene_graph_json(graph))


def to_networkx(graph: SceneGraph) -> nx.Graph:
    """Undirected graph with node attrs type/pos and edge attrs type/length (pixels)."""
    import networkx as nx  # ~0.1 s: not imported by what only simulates

    g = nx.Graph()
    for n in graph.nodes:
        g.add_node(n.id, type=n.type, pos=tuple(n.pos))
    for e in graph.links:
        if e.source in g and e.target in g:
            a, b = g.nodes[e.source]["pos"], g.nodes[e.target]["pos"]
            g.add_edge(e.source, e.target, type=e.type, length=math.dist(a, b))
    return g


def _num(value: float) -> float | int:
    return int(value) if float(value).is_integer() else float(value)


def path_mistakes(graph: nx.Graph | SceneGraph, who: str, path: list[str]) -> list[str]:
    """THE check of a walk on the scene graph: unknown nodes, and consecutive nodes without an edge, each
    named exactly (the text goes back to a model as its correction, and to users as an error)."""
    mistakes = [f"{who}: node '{n}' is not in the scene graph" for n in dict.fromkeys(path) if n not in graph]
    for a, b in zip(path, path[1:], strict=False):
        if a not in graph or b not in graph:
            continue
        if a == b:
            mistakes.append(f"{who}: node {a} is repeated twice in a row; list each node once")
        elif not graph.has_edge(a, b):
            mistakes.append(f"{who}: there is no edge between {a} and {b}")
    return mistakes
