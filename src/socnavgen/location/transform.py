"""The one pixel <-> world conversion of the project.

nav2 / map_server convention: `origin` [x, y, yaw] is the world pose of the LOWER-LEFT corner of
the image, image rows count from the top, and a scene-graph `pos` names a pixel whose centre is
used. For an image of height H and resolution s, the pixel centre (px, py) is at local
(s*(px+0.5), s*(H-py-0.5)), then rotated by yaw and shifted by (ox, oy).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from socnavgen.limits import MAX_COORDINATE


class Transform:
    """Affine pixel->world map held as a 3x3 homogeneous matrix."""

    def __init__(self, matrix: Sequence[Sequence[float]] | np.ndarray) -> None:
        m = np.asarray(matrix, dtype=float)
        if m.shape != (3, 3):
            raise ValueError("transform must be 3x3")
        if not np.isfinite(m).all() or np.abs(m).max() > MAX_COORDINATE:
            raise ValueError(f"transform holds NaN, infinite or absurd values (|v| > {MAX_COORDINATE:g})")
        if abs(np.linalg.det(m[:2, :2])) < 1e-12:
            raise ValueError("transform is singular (its 2x2 part has zero determinant)")
        self.matrix = m
        self.inverse = np.linalg.inv(m)

    @classmethod
    def from_nav2(cls, resolution: float, origin: Sequence[float], image_height: int) -> Transform:
        ox, oy = float(origin[0]), float(origin[1])
        yaw = float(origin[2]) if len(origin) > 2 else 0.0
        s = float(resolution)
        pixel_to_local = np.array([[s, 0.0, 0.5 * s], [0.0, -s, (image_height - 0.5) * s], [0.0, 0.0, 1.0]])
        c, si = math.cos(yaw), math.sin(yaw)
        local_to_world = np.array([[c, -si, ox], [si, c, oy], [0.0, 0.0, 1.0]])
        return cls(local_to_world @ pixel_to_local)

    @property
    def meters_per_pixel(self) -> float:
        return math.sqrt(abs(np.linalg.det(self.matrix[:2, :2])))

    def pixel_to_world(self, px: float, py: float) -> tuple[float, float]:
        x, y, w = self.matrix @ np.array([px, py, 1.0])
        return float(x / w), float(y / w)

    def world_to_pixel(self, x: float, y: float) -> tuple[float, float]:
        px, py, w = self.inverse @ np.array([x, y, 1.0])
        return float(px / w), float(py / w)

    def pixels_to_world(self, points: np.ndarray) -> np.ndarray:
        """Vectorised pixel->world for an (N, 2) array."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        homo = np.hstack([pts, np.ones((len(pts), 1))]) @ self.matrix.T
        return homo[:, :2] / homo[:, 2:3]

    def worlds_to_pixel(self, points: np.ndarray) -> np.ndarray:
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        homo = np.hstack([pts, np.ones((len(pts), 1))]) @ self.inverse.T
        return homo[:, :2] / homo[:, 2:3]

    def world_heading(self, from_px: Sequence[float], to_px: Sequence[float]) -> float:
        """Yaw in the world frame of the direction between two pixels (honours flips and yaw)."""
        ax, ay = self.pixel_to_world(*from_px)
        bx, by = self.pixel_to_world(*to_px)
        return math.atan2(by - ay, bx - ax)
