"""The scene-graph tutorial: question/answer pairs generated FOR THIS MAP from its graph.

SocRATES hand-wrote its tutorial for one warehouse; here every answer is computed with networkx,
so the tutorial is true on any map a user annotates, and deterministic for a seed.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import networkx as nx


@dataclass(frozen=True)
class QA:
    question: str
    answer: str


def _label(graph: nx.Graph, node: str) -> str:
    return f"{node} ({graph.nodes[node].get('type', '?')})"


def _neighbours(graph: nx.Graph, node: str) -> list[str]:
    return sorted(graph.neighbors(node))


def _connected_pair(graph: nx.Graph, rng: random.Random) -> QA | None:
    edges = sorted(tuple(sorted(e)) for e in graph.edges)
    if not edges:
        return None
    a, b = rng.choice(edges)
    kind = graph.edges[a, b].get("type", "?")
    return QA(f"Is node {a} directly connected to node {b}?",
              f"Yes. An edge of type {kind} joins {_label(graph, a)} and {_label(graph, b)}, "
              f"so one can walk from {a} to {b} in one step.")


def _unconnected_pair(graph: nx.Graph, rng: random.Random) -> QA | None:
    nodes = sorted(graph.nodes)
    pairs = [(a, b) for i, a in enumerate(nodes) for b in nodes[i + 1:] if not graph.has_edge(a, b)]
    if not pairs:
        return None
    # Prefer a pair that is connected through others: the instructive case (close, but no edge).
    reachable = [(a, b) for a, b in pairs if nx.has_path(graph, a, b)]
    a, b = rng.choice(reachable or pairs)
    text = (f"No. The neighbours of {a} are {', '.join(_neighbours(graph, a)) or 'none'}; "
            f"{b} is not among them, so there is no edge between {a} and {b}.")
    if nx.has_path(graph, a, b):
        path = nx.shortest_path(graph, a, b)
        text += f" To go from {a} to {b} one must pass other nodes: {', '.join(path)}."
    else:
        text += f" {b} cannot be reached from {a} at all."
    return QA(f"Is node {a} directly connected to node {b}?", text)


def _neighbour_question(graph: nx.Graph, rng: random.Random) -> QA | None:
    candidates = sorted(n for n in graph.nodes if graph.degree(n) >= 2) or sorted(graph.nodes)
    if not candidates:
        return None
    node = rng.choice(candidates)
    parts = [f"{_label(graph, n)} by a {graph.edges[node, n].get('type', '?')} edge"
             for n in _neighbours(graph, node)]
    return QA(f"Which nodes can be reached from node {node} in one step?",
              f"{', '.join(parts) or 'None'}. Every other node needs more than one step.")


def _type_question(graph: nx.Graph, rng: random.Random) -> QA | None:
    types = sorted({str(graph.nodes[n].get("type", "?")) for n in graph.nodes})
    if not types:
        return None
    kind = rng.choice(types)
    members = sorted(n for n in graph.nodes if graph.nodes[n].get("type") == kind)
    return QA(f"Which nodes are of type {kind}?", f"{', '.join(members)}.")


def _far_pair(graph: nx.Graph, rng: random.Random) -> list[str] | None:
    """A shortest path between two nodes that are as far apart (in steps) as the graph allows."""
    best: list[tuple[str, str]] = []
    best_len = 1
    lengths = dict(nx.all_pairs_shortest_path_length(graph))
    for a in sorted(lengths):
        for b, d in sorted(lengths[a].items()):
            if a < b:
                if d > best_len:
                    best, best_len = [(a, b)], d
                elif d == best_len:
                    best.append((a, b))
    if not best or best_len < 2:
        return None
    a, b = rng.choice(best)
    return nx.shortest_path(graph, a, b)


def generate_tutorial(graph: nx.Graph, seed: int = 0) -> list[QA]:
    """Connectivity (true and false), neighbours, node types, a long valid path and an invalid one."""
    rng = random.Random(seed)
    items = [_connected_pair(graph, rng), _unconnected_pair(graph, rng), _neighbour_question(graph, rng),
             _type_question(graph, rng)]
    path = _far_pair(graph, rng)
    if path:
        a, b = path[0], path[-1]
        items.append(QA(f"Give a valid path from node {a} to node {b}.",
                        f"{', '.join(path)}. Each two consecutive nodes are joined by an edge; there is no shorter "
                        f"path."))
        skipped = [path[0], *path[2:]]
        items.append(QA(f"Why is the path {', '.join(skipped)} invalid?",
                        f"There is no edge between {path[0]} and {path[2]}: a person cannot jump between them. "
                        f"Going through {path[1]} fixes it: {', '.join(path)}."))
    return [item for item in items if item is not None]


def tutorial_text(items: list[QA]) -> str:
    return "\n".join(f"Q: {qa.question}\nA: {qa.answer}" for qa in items)
