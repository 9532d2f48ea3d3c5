"""The scene-graph tutorial is generated from the map's graph, so every answer must be TRUE there."""

from __future__ import annotations

import re

import networkx as nx
import pytest

from socnavgen.location import load_location
from socnavgen.proposal.tutorial import generate_tutorial, tutorial_text

CONNECTED_Q = re.compile(r"Is node (\w+) directly connected to node (\w+)\?")


def assert_tutorial_true(graph: nx.Graph, seed: int) -> None:
    items = generate_tutorial(graph, seed)
    kinds = {"yes": 0, "no": 0, "neighbours": 0, "type": 0, "path": 0, "invalid": 0}
    for qa in items:
        if m := CONNECTED_Q.match(qa.question):
            a, b = m.groups()
            assert qa.answer.startswith("Yes") == graph.has_edge(a, b), qa
            kinds["yes" if graph.has_edge(a, b) else "no"] += 1
        elif qa.question.startswith("Which nodes can be reached from node"):
            node = qa.question.split()[-4]
            named = set(re.findall(r"\b(\w\w) \(", qa.answer))
            assert named == set(graph.neighbors(node)), qa
            kinds["neighbours"] += 1
        elif qa.question.startswith("Which nodes are of type"):
            kind = qa.question.removeprefix("Which nodes are of type ").removesuffix("?")
            named = set(qa.answer.rstrip(".").split(", "))
            assert named == {n for n in graph.nodes if graph.nodes[n]["type"] == kind}, qa
            kinds["type"] += 1
        elif qa.question.startswith("Give a valid path"):
            path = qa.answer.split(".")[0].split(", ")
            assert all(graph.has_edge(a, b) for a, b in zip(path, path[1:], strict=False)), qa
            assert len(path) - 1 == nx.diameter(graph) if nx.is_connected(graph) else len(path) >= 3
            kinds["path"] += 1
        elif qa.question.startswith("Why is the path"):
            a, b = re.search(r"no edge between (\w+) and (\w+)", qa.answer).groups()
            assert not graph.has_edge(a, b), qa
            kinds["invalid"] += 1
    assert all(kinds.values()), kinds  # true AND false connectivity cases, and every other kind


def test_tutorial_answers_are_true_on_the_mini_map(mini_location):
    graph = load_location(mini_location).graph
    for seed in range(5):
        assert_tutorial_true(graph, seed)


def test_tutorial_is_deterministic_for_a_seed(mini_location):
    graph = load_location(mini_location).graph
    assert tutorial_text(generate_tutorial(graph, 3)) == tutorial_text(generate_tutorial(graph, 3))
    texts = {tutorial_text(generate_tutorial(graph, s)) for s in range(6)}
    assert len(texts) > 1  # the seed really picks different questions


def test_tutorial_on_the_bundled_warehouse(warehouse_dir):
    if not (warehouse_dir / "location.yaml").is_file():
        pytest.fail("examples/locations/warehouse is not there yet")
    graph = load_location(warehouse_dir).graph
    for seed in range(3):
        assert_tutorial_true(graph, seed)


def test_tutorial_survives_tiny_graphs():
    graph = nx.Graph()
    graph.add_node("aa", type="ROOM")
    assert [qa.question for qa in generate_tutorial(graph)] == ["Which nodes can be reached from node aa in one step?",
                                                                "Which nodes are of type ROOM?"]
    graph.add_edge("aa", "bb")
    graph.nodes["bb"]["type"] = "ROOM"
    assert generate_tutorial(graph)  # no crash without non-edges or long paths
