"""Two maps drawn in code (0.05 m per pixel) with rooms, furniture and corridors, for the person's-graph
comparison (tests/extract/data/person_graphs.json holds what a person drew on each).

    python -m tests.extract.drawn_maps OUT_DIR     # writes OUT_DIR/<name>/<name>.pgm + .yaml
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from tests.extract.synthetic_maps import blank, carve, write_map

UNKNOWN = 205


def furniture(img: np.ndarray, r0: int, r1: int, c0: int, c1: int) -> None:
    """A piece of furniture as a scanner sees it: an outline, unknown inside."""
    img[r0:r1, c0:c1] = 0
    if r1 - r0 > 4 and c1 - c0 > 4:
        img[r0 + 2:r1 - 2, c0 + 2:c1 - 2] = UNKNOWN


def office_map() -> np.ndarray:
    """20 m x 15 m: three offices north of a 2 m corridor, an open-plan office south-west, a kitchen
    south-east, and a corridor branch south to a dead end; desks, cabinets and a pillar."""
    img = blank(300, 400)
    carve(img, 150, 190, 5, 395)  # corridor
    for c0, c1, door in ((5, 130, 60), (135, 265, 200), (270, 395, 320)):  # north offices
        carve(img, 5, 145, c0, c1)
        carve(img, 145, 150, door, door + 18)
    carve(img, 195, 295, 5, 250)  # open-plan office
    carve(img, 190, 195, 100, 118)
    carve(img, 190, 295, 340, 380)  # corridor branch south
    carve(img, 195, 295, 255, 335)  # kitchen, door onto the branch
    carve(img, 250, 268, 335, 340)
    for r0, c0 in ((30, 20), (30, 80), (90, 150), (90, 215), (30, 300)):  # desks in the offices
        furniture(img, r0, r0 + 16, c0, c0 + 32)
    for r0, c0 in ((215, 20), (215, 80), (260, 20), (260, 80), (215, 170), (260, 170)):  # open-plan desks
        furniture(img, r0, r0 + 16, c0, c0 + 32)
    furniture(img, 238, 246, 140, 148)  # pillar
    furniture(img, 200, 212, 260, 330)  # kitchen counter
    furniture(img, 5, 14, 150, 250)  # shelf along a wall (touches nothing: a gap behind it)
    return img


def clinic_map() -> np.ndarray:
    """24 m x 16 m: an L-shaped 1.8 m corridor, a waiting room with rows of chairs entered through a
    1.2 m opening, two treatment rooms with beds, and a narrow 0.8 m, 7 m long service passage down to a
    store."""
    img = blank(320, 480)
    carve(img, 20, 56, 20, 460)  # north corridor (1.8 m)
    carve(img, 56, 300, 20, 56)  # west corridor going south
    carve(img, 61, 200, 61, 260)  # waiting room
    carve(img, 56, 61, 160, 184)  # its 1.2 m opening onto the north corridor
    for c in range(80, 245, 25):  # rows of chairs
        furniture(img, 110, 122, c, c + 12)
        furniture(img, 150, 162, c, c + 12)
    carve(img, 205, 300, 61, 200)  # treatment room 1 (door from the west corridor)
    carve(img, 250, 268, 56, 61)
    furniture(img, 250, 270, 130, 170)  # treatment bed
    carve(img, 61, 200, 300, 460)  # treatment room 2 (door from the north corridor)
    carve(img, 56, 61, 400, 418)
    furniture(img, 120, 140, 340, 400)
    carve(img, 61, 184, 270, 286)  # the service passage from the north corridor (0.8 m) ...
    carve(img, 56, 61, 270, 286)
    carve(img, 184, 200, 270, 295)  # ... with a niche at its foot ...
    carve(img, 205, 300, 265, 460)  # ... straight down into the store below treatment room 2
    carve(img, 200, 205, 270, 286)
    return img


DRAWN = {"office": office_map, "clinic": clinic_map}


def main(out: Path) -> None:
    for name, draw in DRAWN.items():
        print(write_map(out / name, draw(), name))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
