"""A small synthetic location for the annotator tests: a 200x150 px room with a wall block."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from PIL import Image

from socnavgen.location.extract import start_location_folder
from socnavgen.location.models import Schema

WIDTH, HEIGHT = 200, 150
WALL = (90, 110, 20, 100)  # x0, x1, y0, y1 of an obstacle block in the middle
SCHEMA = Schema(node_types=["INTERSECTION", "BLIND CORNER", "OPEN AREA"], edge_types=["PASSAGEWAY", "NARROW"])


def draw_map(folder: Path) -> Path:
    img = np.full((HEIGHT, WIDTH), 254, np.uint8)
    img[:3, :] = img[-3:, :] = 0
    img[:, :3] = img[:, -3:] = 0
    x0, x1, y0, y1 = WALL
    img[y0:y1, x0:x1] = 0
    folder.mkdir(parents=True, exist_ok=True)
    Image.fromarray(img).save(folder / "room.pgm")
    (folder / "room.yaml").write_text(yaml.safe_dump(
        {"image": "room.pgm", "resolution": 0.05, "origin": [0.0, 0.0, 0.0], "negate": 0,
         "occupied_thresh": 0.65, "free_thresh": 0.196}))
    return folder / "room.yaml"


@pytest.fixture
def room_location(tmp_path: Path) -> Path:
    map_yaml = draw_map(tmp_path / "src")
    return start_location_folder(map_yaml, tmp_path / "room", name="room", schema=SCHEMA)
