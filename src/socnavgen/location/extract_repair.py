"""The last step of `location extract`: the draft passes `location check` as one connected graph.

Room joins and the skeleton may leave an edge through furniture that walls a nook off, or a part of
the graph cut off from the rest (a room whose opening was not recognised as a doorway). Both are
repaired with the shortest walkable way round, pulled tight into straight walkable pieces.
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np

from socnavgen.location.room_nodes import add_chain, pulled_path
from socnavgen.location.traverse import edge_verdict


def connect_parts(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray, mpp: float) -> np.ndarray:
    """Join every part of the graph cut off from the largest one (a room whose only opening was not
    recognised as a doorway) by the shortest walkable way between their closest nodes: all of the
    walkable space is one piece, so the graph must be too. Returns `coords` with any waypoints added."""
    parts = sorted(nx.connected_components(graph), key=len, reverse=True)
    if len(parts) < 2:
        return coords
    points = [(int(p[0]), int(p[1])) for p in coords]  # (row, col) pixels
    main = list(parts[0])
    for part in parts[1:]:
        a, b = min(((x, y) for x in part for y in main), key=lambda pair: math.dist(points[pair[0]], points[pair[1]]))
        add_chain(graph, points, a, pulled_path(points[a], points[b], clearance, mpp,
                                                _window(points[a], points[b], int(6.0 / mpp))), b)
        main += list(part)
    return np.array(points, dtype=coords.dtype).reshape(-1, 2)


def _window(a: tuple[int, int], b: tuple[int, int], margin: int) -> tuple[slice, slice]:
    return (slice(max(0, min(a[0], b[0]) - margin), max(a[0], b[0]) + margin + 1),
            slice(max(0, min(a[1], b[1]) - margin), max(a[1], b[1]) + margin + 1))


def reroute_blocked(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray, mpp: float) -> np.ndarray:
    """The last guarantee that the draft passes `location check`: an edge the traversability rule calls
    an error (a room's edge drawn through furniture that walls it off) is replaced by the shortest
    walkable way round, or dropped when the graph stays connected without it."""
    points = [(int(p[0]), int(p[1])) for p in coords]  # (row, col) pixels
    for u, v in sorted({(min(a, b), max(a, b)) for a, b in graph.edges() if a != b}):
        ends = ((points[u][1], points[u][0]), (points[v][1], points[v][0]))
        if edge_verdict(clearance, *ends, mpp).level != "error":
            continue
        vias = pulled_path(points[u], points[v], clearance, mpp, _window(points[u], points[v], int(6.0 / mpp)))
        if not vias:  # the way round leaves the neighbourhood: search the whole map
            vias = pulled_path(points[u], points[v], clearance, mpp, (slice(0, None), slice(0, None)))
        graph.remove_edges_from([(u, v)] * graph.number_of_edges(u, v))
        if not vias:
            if not nx.has_path(graph, u, v):
                graph.add_edge(u, v, path=[u, v], start=u)  # nothing better: `location check` will name it
            continue
        add_chain(graph, points, u, vias, v)
    return np.array(points, dtype=coords.dtype).reshape(-1, 2)
