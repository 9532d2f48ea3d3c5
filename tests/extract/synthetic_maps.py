"""Synthetic occupancy maps drawn in code (0.05 m per pixel): corridors, rooms and doors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yaml
from PIL import Image

RES = 0.05
FREE, WALL = 254, 0


def blank(h: int, w: int) -> np.ndarray:
    return np.full((h, w), WALL, np.uint8)


def carve(img: np.ndarray, r0: int, r1: int, c0: int, c1: int) -> None:
    img[r0:r1, c0:c1] = FREE


def plus_map() -> np.ndarray:
    """Two 1.6 m corridors crossing in the middle of a 15 m square."""
    img = blank(300, 300)
    carve(img, 134, 166, 20, 280)
    carve(img, 20, 280, 134, 166)
    return img


def ell_map() -> np.ndarray:
    """An L-shaped 1.6 m corridor: 12 m down, then 12 m right."""
    img = blank(300, 300)
    carve(img, 30, 270, 30, 62)
    carve(img, 238, 270, 30, 270)
    return img


def room_door_map() -> np.ndarray:
    """A 10 m x 12 m room opening through a 0.9 m door in a 0.5 m wall onto a 1.6 m corridor."""
    img = blank(300, 400)
    carve(img, 30, 270, 30, 230)
    carve(img, 141, 159, 230, 240)
    carve(img, 30, 270, 240, 272)
    return img


def ring_map() -> np.ndarray:
    """A circular 1.5 m corridor around a round block: every straight edge must be cut short."""
    yy, xx = np.mgrid[:300, :300]
    r = np.hypot(yy - 150, xx - 150)
    img = blank(300, 300)
    img[(r > 90) & (r < 120)] = FREE
    return img


def write_map(folder: Path, img: np.ndarray, name: str = "m") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    Image.fromarray(img).save(folder / f"{name}.pgm")
    (folder / f"{name}.yaml").write_text(yaml.safe_dump(
        {"image": f"{name}.pgm", "resolution": RES, "origin": [-2.0, -3.0, 0.0], "negate": 0,
         "occupied_thresh": 0.65, "free_thresh": 0.196}))
    return folder / f"{name}.yaml"


