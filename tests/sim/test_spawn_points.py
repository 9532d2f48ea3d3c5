"""Where people spawn (sim.spawn_points, the export's too): within 1.5 m of their first node, never in a wall,
never within intimate space of the robot's start or of a body placed before them (a group's members on their
circle, not touching), falling back to the node itself."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from socnavgen.bodies import CONTACT_MARGIN, INTIMATE_SPACE, PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.sim import empty_room, spawn_points


@pytest.mark.parametrize("seed", range(20))
def test_nobody_spawns_within_intimate_space_of_the_robot_or_each_other(seed: int) -> None:
    world = empty_room(12.0, 8.0)
    node, robot = 6 + 4j, 6.9 + 4j  # the robot's start 0.9 m from the node everyone starts at
    points = spawn_points(world, [node] * 3, [-1, -1, -1], PERSON_RADIUS, np.random.default_rng(seed), robot)
    for p in points:
        assert abs(p - node) <= 1.5 + 1e-9
        assert p == node or abs(p - robot) - PERSON_RADIUS - ROBOT_RADIUS >= INTIMATE_SPACE
    moved = [p for p in points if p != node]
    for a, b in itertools.combinations(moved, 2):
        assert abs(a - b) - 2 * PERSON_RADIUS >= INTIMATE_SPACE


def test_without_the_robot_the_same_draws_give_the_old_spots_and_a_group_stays_on_its_circle() -> None:
    world = empty_room(12.0, 8.0)
    free = spawn_points(world, [6 + 4j], [-1], PERSON_RADIUS, np.random.default_rng(3))
    far = spawn_points(world, [6 + 4j], [-1], PERSON_RADIUS, np.random.default_rng(3), 1 + 1j)
    assert free == far  # a robot far away changes nothing
    group = spawn_points(world, [6 + 4j] * 3, [0, 0, 0], PERSON_RADIUS, np.random.default_rng(0), 1 + 1j)
    assert all(abs(abs(p - (6 + 4j)) - 0.6) < 1e-9 for p in group)
    assert min(abs(a - b) for a, b in itertools.combinations(group, 2)) - 2 * PERSON_RADIUS > CONTACT_MARGIN


def test_with_no_clear_spot_a_person_starts_on_their_node() -> None:
    corridor = empty_room(12.0, 8.0, walls=[(0.0, 0.0, 12.0, 3.5), (0.0, 4.5, 12.0, 8.0), (6.6, 3.5, 12.0, 4.5)])
    node = 5.5 + 4j  # a dead end 1.1 m on: the robot stands 0.3 m off the node
    for seed in range(10):
        assert spawn_points(corridor, [node], [-1], PERSON_RADIUS, np.random.default_rng(seed), 5.2 + 4j) == [node]


@pytest.mark.parametrize("seed", range(5))
def test_a_group_of_four_in_a_corridor_never_starts_on_one_spot(seed: int) -> None:
    """Four members on a 0.6 m circle round a node of a 2.4 m corridor: the two across it do not fit; they start at
    the nearest clear spots along it, never on the node on top of each other (the ward-round team of round 7 started
    two bodies on one point, gap -0.80 m)."""
    corridor = empty_room(14.0, 8.0, walls=[(0.0, 0.0, 14.0, 2.8), (0.0, 5.2, 14.0, 8.0)])
    node = 7.0 + 4j
    points = spawn_points(corridor, [node] * 4, [0] * 4, PERSON_RADIUS, np.random.default_rng(seed), 2.0 + 4j)
    assert min(abs(a - b) for a, b in itertools.combinations(points, 2)) - 2 * PERSON_RADIUS >= CONTACT_MARGIN - 1e-9
    assert all(corridor.is_free(p, PERSON_RADIUS) and abs(p - node) <= 1.5 + 1e-9 for p in points)


@pytest.mark.parametrize("seed", range(20))
def test_a_lone_person_starts_in_their_nodes_place_not_beside_the_next_node(seed: int) -> None:
    """Round 30's visitor, told to stand in the hospital's 1.2 m doorway x5, was drawn 1.4 m off into the corridor
    beside its node i1 (1.2 m away): a lone person's spot is no nearer another node of the scene graph than their
    own (its cell); in an open room far from other nodes the spread stays 1.5 m."""
    from pathlib import Path

    from socnavgen.location import load_location
    from socnavgen.sim import World

    hospital = load_location(Path(__file__).resolve().parents[2] / "examples" / "locations" / "hospital")
    nodes = {n: complex(*hospital.node_world(n)) for n in hospital.scene_graph.node_ids()}
    world = World.from_location(hospital)
    starts = spawn_points(world, [nodes["x5"], nodes["pf"]], [-1, -1], PERSON_RADIUS, np.random.default_rng(seed),
                          landmarks=list(nodes.values()))
    for node, spot in zip(("x5", "pf"), starts, strict=True):
        own = abs(spot - nodes[node])
        assert all(abs(spot - other) >= own - 1e-9 for other in nodes.values()), (node, spot)
    room = empty_room(12.0, 8.0)  # one landmark 5 m off: the draw is the one without landmarks
    assert spawn_points(room, [6 + 4j], [-1], PERSON_RADIUS, np.random.default_rng(seed), landmarks=[1 + 4j]) == \
        spawn_points(room, [6 + 4j], [-1], PERSON_RADIUS, np.random.default_rng(seed))
