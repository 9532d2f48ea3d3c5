"""Builders for card tests: tiny synthetic locations whose geometry alone (no helpful type names)
says where a blind corner, a narrow passage or an intersection is."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tests import synthetic

RES = 0.05


def write_location(root: Path, free: np.ndarray, nodes: dict[str, tuple[int, int]], edges: list[tuple[str, str]],
                   node_types: dict[str, str] | None = None, edge_types: dict[tuple[str, str], str] | None = None,
                   schema_nodes: list[str] | None = None) -> Path:
    """A location folder from a boolean free-space mask [row, col] and a node/edge list."""
    return synthetic.write_location(root, free, nodes, edges, resolution=RES, origin=(-1.0, 2.0),
                                    node_types=node_types, edge_types=edge_types, schema_nodes=schema_nodes)


def l_corridor(root: Path, width_px: int = 30) -> Path:
    """An L-shaped corridor (1.5 m wide): west leg along the top, then south. The turn node `tt`
    cannot see both legs' far nodes; every node is typed plain 'NODE'."""
    free = np.zeros((200, 200), dtype=bool)
    free[20:20 + width_px, 20:180] = True  # horizontal leg, rows 20..49
    free[20:180, 150:150 + width_px] = True  # vertical leg, cols 150..179
    c = 20 + width_px // 2
    nodes = {"a1": (30, c), "a2": (80, c), "a3": (120, c), "tt": (165, c), "b1": (165, 90), "b2": (165, 130),
             "b3": (165, 170)}
    edges = [("a1", "a2"), ("a2", "a3"), ("a3", "tt"), ("tt", "b1"), ("b1", "b2"), ("b2", "b3")]
    return write_location(root, free, nodes, edges)


def cross(root: Path) -> Path:
    """A plus-shaped crossing of two 2 m wide corridors; the centre node `xx` has four branches, the
    east arm narrows to 0.8 m between e1 and e2."""
    free = np.zeros((240, 240), dtype=bool)
    free[100:140, 10:230] = True
    free[10:230, 100:140] = True
    free[100:140, 175:200] = False
    free[112:128, 175:200] = True  # a 16 px = 0.8 m slot on the east arm
    nodes = {"xx": (120, 120), "w1": (70, 120), "w2": (25, 120), "n1": (120, 70), "n2": (120, 25),
             "s1": (120, 170), "s2": (120, 215), "e1": (160, 120), "e2": (215, 120)}
    edges = [("xx", "w1"), ("w1", "w2"), ("xx", "n1"), ("n1", "n2"), ("xx", "s1"), ("s1", "s2"), ("xx", "e1"),
             ("e1", "e2")]
    return write_location(root, free, nodes, edges)


def lift_corridor(root: Path, nodes_past_lift: int) -> Path:
    """A 2 m wide corridor running east from an elevator (node `el`, typed ELEVATOR) with `nodes_past_lift` nodes
    1 m apart along it (n1, n2, ...), then a dead end."""
    length = 20 * (nodes_past_lift + 1) + 20
    free = np.zeros((60, length + 20), dtype=bool)
    free[10:50, 10:10 + length] = True
    nodes = {"el": (20, 30), **{f"n{k}": (20 + 20 * k, 30) for k in range(1, nodes_past_lift + 1)}}
    names = list(nodes)
    return write_location(root, free, nodes, list(zip(names, names[1:], strict=False)),
                          node_types={"el": "ELEVATOR"})
