"""Occupancy grid of a location: which pixels a person can stand on, and straight-line clearance."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from PIL import Image

from socnavgen.errors import InputFileError
from socnavgen.safeio import MAX_IMAGE_BYTES, check_image_pixels


@dataclass
class Thresholds:
    """map_server thresholds: p = (255 - v)/255 (or v/255 with negate), occupied if p > occ, free if p < free."""

    occupied: float = 0.65
    free: float = 0.196
    negate: bool = False


@dataclass
class OccupancyGrid:
    """`occupied[row, col]` (row 0 = top of the image); unknown pixels count as not walkable."""

    occupied: np.ndarray
    unknown: np.ndarray

    @property
    def height(self) -> int:
        return int(self.occupied.shape[0])

    @property
    def width(self) -> int:
        return int(self.occupied.shape[1])

    @cached_property
    def blocked(self) -> np.ndarray:
        return self.occupied | self.unknown

    @cached_property
    def clearance_px(self) -> np.ndarray:
        """Distance in pixels from each pixel to the nearest blocked pixel or the map's edge (0 on obstacles)."""
        return clearance_from(self.blocked)

    def inside(self, px: float, py: float) -> bool:
        return 0 <= px < self.width and 0 <= py < self.height

    def is_blocked(self, px: float, py: float) -> bool:
        return bool(self.blocked[int(py), int(px)])

    def segment_blocked_pixels(self, a: tuple[float, float], b: tuple[float, float]) -> list[tuple[int, int]]:
        """Blocked pixels (x, y) on the rasterised straight segment a-b, in order from a to b."""
        from skimage.draw import line as raster_line  # lazy for the same reason as scipy

        rows, cols = raster_line(int(round(a[1])), int(round(a[0])), int(round(b[1])), int(round(b[0])))
        keep = (rows >= 0) & (rows < self.height) & (cols >= 0) & (cols < self.width)
        rows, cols = rows[keep], cols[keep]
        hit = self.blocked[rows, cols]
        return [(int(c), int(r)) for r, c in zip(rows[hit], cols[hit], strict=True)]

    def segment_clear(self, a: tuple[float, float], b: tuple[float, float]) -> bool:
        return not self.segment_blocked_pixels(a, b)


def clearance_from(blocked: np.ndarray) -> np.ndarray:
    """Distance in pixels from each pixel to the nearest blocked one, the space beyond the image counting
    as blocked: a map ends where nothing is known, so nobody walks past its edge (a strip of free ground
    left around a building is no walkway)."""
    from scipy import ndimage  # imported here: it costs ~0.3 s of start-up for every CLI command

    return ndimage.distance_transform_edt(np.pad(~blocked, 1))[1:-1, 1:-1]


def load_image_gray(path: Path) -> np.ndarray:
    path = Path(path)
    if not path.is_file():
        raise InputFileError("map image not found", file=path, hint="check `map` in location.yaml")
    if path.stat().st_size > MAX_IMAGE_BYTES:
        raise InputFileError("map image is too large", file=path)
    try:
        with Image.open(path) as img:
            check_image_pixels(*img.size, file=path)
            return np.asarray(img.convert("L"), dtype=np.uint8)
    except InputFileError:
        raise
    except Exception as exc:  # Pillow raises many types for corrupt files
        raise InputFileError(f"cannot read the map image: {exc}", file=path,
                             hint="use a PGM or PNG image") from exc


def occupancy_from_image(gray: np.ndarray, thresholds: Thresholds | None = None) -> OccupancyGrid:
    t = thresholds or Thresholds()
    values = gray.astype(float) / 255.0
    p = values if t.negate else 1.0 - values
    occupied = p > t.occupied
    free = p < t.free
    return OccupancyGrid(occupied=occupied, unknown=~(occupied | free))
