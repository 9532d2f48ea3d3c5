"""One builder of synthetic location folders for every test package: a free-space mask, a resolution and
origin (nav2 map yaml), and a scene graph in pixels. Each test keeps its own geometry as data."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import yaml
from PIL import Image


def walled_room(height: int, width: int, wall: int = 3) -> np.ndarray:
    """A free-space mask [row, col]: a rectangle with `wall`-pixel walls all around."""
    free = np.zeros((height, width), dtype=bool)
    free[wall:height - wall, wall:width - wall] = True
    return free


def write_location(root: Path, free: np.ndarray, nodes: dict[str, tuple[float, float]],
                   edges: list[tuple[str, str]], *, resolution: float = 0.05,
                   origin: tuple[float, float] = (0.0, 0.0), name: str | None = None,
                   description: str = "synthetic test location", node_types: dict[str, str] | None = None,
                   default_type: str = "NODE", edge_types: dict[tuple[str, str], str] | None = None,
                   default_edge: str = "PATH", schema_nodes: list[str] | None = None,
                   image: str = "map.pgm") -> Path:
    """A location folder (location.yaml, map image + nav2 yaml, scene_graph.json) from a boolean free-space
    mask [row, col] and nodes given as pixel positions (x = column, y = row)."""
    root.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.where(free, 254, 0).astype(np.uint8)).save(root / image)
    (root / "map.yaml").write_text(yaml.safe_dump({
        "image": image, "resolution": resolution, "origin": [origin[0], origin[1], 0.0], "negate": 0,
        "occupied_thresh": 0.65, "free_thresh": 0.196}))
    types, etypes = node_types or {}, edge_types or {}
    schema = schema_nodes or sorted(set(types.values()) | {default_type})
    (root / "location.yaml").write_text(yaml.safe_dump({
        "name": name or root.name, "description": description, "map": image, "nav2_map": "map.yaml",
        "schema": {"node_types": schema, "edge_types": sorted(set(etypes.values()) | {default_edge})}}))
    graph = {"directed": False, "multigraph": False, "graph": {},
             "nodes": [{"type": types.get(n, default_type), "pos": list(p), "id": n} for n, p in nodes.items()],
             "links": [{"type": etypes.get((a, b), default_edge), "source": a, "target": b} for a, b in edges]}
    (root / "scene_graph.json").write_text(json.dumps(graph))
    return root
