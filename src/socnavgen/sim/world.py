"""The static 2D world of a simulation: where the walls are, in metres.

Built once per run from an occupancy grid and the location's transform (the only pixel<->world
conversion). Every per-step query is a vectorised table lookup, so the cost of obstacle forces
and visibility does not depend on the map size.
"""

from __future__ import annotations

import contextlib
import math

import numpy as np
from scipy import ndimage

from socnavgen.location.occupancy import OccupancyGrid
from socnavgen.location.transform import Transform
from socnavgen.sim import kernels

# The Gazebo wrapper sends at most one obstacle point per human, the nearest within 10 m.
OBSTACLE_RANGE = 10.0


class World:
    """Occupancy in metres: nearest-obstacle lookup, clearance and line of sight."""

    def __init__(self, occupancy: OccupancyGrid, transform: Transform, obstacle_range: float = OBSTACLE_RANGE):
        self.occupancy = occupancy
        self.transform = transform
        self.obstacle_range = float(obstacle_range)
        blocked = np.asarray(occupancy.blocked, dtype=bool)
        self.blocked = blocked
        self.height, self.width = blocked.shape
        self.mpp = transform.meters_per_pixel
        inv = transform.inverse
        # world -> pixel as complex-friendly affine pieces (hot path avoids building homogeneous arrays)
        self._inv = inv[:2, :2].copy()
        self._inv_t = inv[:2, 2].copy()
        # plain floats for the scalar lookups of the robot (numpy scalar arithmetic is slow in a hot loop)
        self._affine_floats = (float(self._inv[0, 0]), float(self._inv[0, 1]), float(self._inv_t[0]),
                               float(self._inv[1, 0]), float(self._inv[1, 1]), float(self._inv_t[1]))
        self.has_obstacles = bool(blocked.any())
        if self.has_obstacles:
            dist_px, (rows, cols) = ndimage.distance_transform_edt(~blocked, return_indices=True)
            centres = transform.pixels_to_world(np.stack([cols.ravel(), rows.ravel()], axis=1))
            self.obstacle_table = self._obstacle_point = (centres[:, 0] + 1j * centres[:, 1]).reshape(blocked.shape)
            self.clearance = dist_px * self.mpp  # metres from each pixel centre to the nearest blocked pixel
        else:
            self._obstacle_point = None
            self.clearance = np.full(blocked.shape, np.inf)

    @classmethod
    def from_location(cls, location, obstacle_range: float = OBSTACLE_RANGE) -> World:  # noqa: ANN001
        """The location's world, built once per Location object and range (simulation, metrics and the
        verifier all need it; campaigns ask for it thousands of times). A World is never modified."""
        cache = getattr(location, "_socnavgen_worlds", None)
        if cache is None:
            cache = {}
            with contextlib.suppress(AttributeError):  # a slotted stand-in: just do not cache
                location._socnavgen_worlds = cache
        key = float(obstacle_range)
        if key not in cache:
            cache[key] = cls(location.occupancy, location.transform, obstacle_range)
        return cache[key]

    # -- lookups --------------------------------------------------------------------------------
    def to_cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rows, cols, inside) for complex world points; outside points are clamped to the border."""
        x, y = points.real, points.imag
        px = self._inv[0, 0] * x + self._inv[0, 1] * y + self._inv_t[0]
        py = self._inv[1, 0] * x + self._inv[1, 1] * y + self._inv_t[1]
        cols = np.floor(px + 0.5).astype(np.intp)
        rows = np.floor(py + 0.5).astype(np.intp)
        inside = (cols >= 0) & (cols < self.width) & (rows >= 0) & (rows < self.height)
        np.minimum(np.maximum(cols, 0, out=cols), self.width - 1, out=cols)
        np.minimum(np.maximum(rows, 0, out=rows), self.height - 1, out=rows)
        return rows, cols, inside

    def nearest_obstacles(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nearest obstacle point (complex) for each complex position and a mask of those within range.

        The point is the nearest blocked pixel's centre moved half a pixel toward the agent, i.e. close to
        the obstacle's surface, so distances are not biased by the grid.
        """
        if self._obstacle_point is None:
            return np.zeros_like(points), np.zeros(points.shape, dtype=bool)
        rows, cols, _ = self.to_cells(points)
        obs = self._obstacle_point[rows, cols]
        d = points - obs
        dist = np.abs(d)
        safe = np.where(dist > 1e-9, dist, 1.0)
        obs = obs + d * (0.5 * self.mpp / safe) * (dist > 0.5 * self.mpp)
        return obs, np.abs(points - obs) <= self.obstacle_range

    def clearance_at(self, points: np.ndarray) -> np.ndarray:
        """Metres to the nearest obstacle (0 outside the map)."""
        rows, cols, inside = self.to_cells(np.atleast_1d(points))
        return np.where(inside, self.clearance[rows, cols], 0.0)

    def clearance_at_point(self, point: complex) -> float:
        """Scalar clearance_at for one complex point, without numpy overhead (robot wall check)."""
        a, b, c, d, e, f = self._affine_floats
        x, y = point.real, point.imag
        col = math.floor(a * x + b * y + c + 0.5)
        row = math.floor(d * x + e * y + f + 0.5)
        if not (0 <= col < self.width and 0 <= row < self.height):
            return 0.0
        return self.clearance.item(row, col)

    def is_free(self, point: complex, radius: float) -> bool:
        return bool(self.clearance_at(np.array([point]))[0] >= radius)

    def line_of_sight(self, a: complex, b: np.ndarray | complex, reference: bool = False) -> np.ndarray:
        """True where the straight segment a->b crosses no blocked cell (one a, one or many b). `reference`:
        the numpy path even where the compiled one exists (tests compare the two)."""
        b = np.atleast_1d(np.asarray(b, dtype=complex))
        if not self.has_obstacles:
            return np.ones(b.shape, dtype=bool)
        if b.size == 1 and kernels.AVAILABLE and not reference:  # one segment: sampled the same way, compiled
            return self.segments_clear(np.atleast_1d(np.asarray(a, dtype=complex)), b)
        length = np.abs(b - a)
        samples = max(2, int(np.ceil(length.max() / (0.5 * self.mpp))) + 1)
        frac = np.linspace(0.0, 1.0, samples)
        pts = a + np.outer(b - a, frac)  # (len(b), samples)
        rows, cols, inside = self.to_cells(pts)
        hit = self.blocked[rows, cols] | ~inside
        # the end cells hold the two bodies themselves; a body touching a wall must not hide the other
        return ~hit[:, 1:-1].any(axis=1)

    def segments_clear(self, a: np.ndarray, b: np.ndarray, chunk: int = 4096, reference: bool = False) -> np.ndarray:
        """line_of_sight for many segments a[k] -> b[k] at once (same shapes): the verifier asks it for every
        step and person of a trace. Compiled (sim.kernels) when numba is there; else (or with `reference`) numpy,
        in chunks that bound memory."""
        a, b = np.broadcast_arrays(np.asarray(a, dtype=complex), np.asarray(b, dtype=complex))
        flat_a, flat_b = a.ravel(), b.ravel()
        out = np.ones(flat_a.shape, dtype=bool)
        if not self.has_obstacles or flat_a.size == 0:
            return out.reshape(a.shape)
        if kernels.AVAILABLE and not reference:
            kernels.segments_clear(self.blocked, self.transform.inverse, np.ascontiguousarray(flat_a),
                                   np.ascontiguousarray(flat_b), 0.5 * self.mpp, out)
            return out.reshape(a.shape)
        # each segment is sampled as line_of_sight samples it alone (its own count, from its own length), all
        # segments' samples in one flat array: a batch of short segments does not pay for its longest one
        counts = np.maximum(2, np.ceil(np.abs(flat_b - flat_a) / (0.5 * self.mpp)).astype(np.intp) + 1)
        for lo in range(0, flat_a.size, chunk):
            c = counts[lo:lo + chunk]
            seg = np.repeat(np.arange(c.size), c)
            first = np.cumsum(c) - c
            k = np.arange(seg.size) - first[seg]
            frac = k * (1.0 / (c - 1))[seg]  # as np.linspace(0, 1, count) computes it ...
            frac[first + c - 1] = 1.0  # ... with its last sample exactly at the end
            pa, pb = flat_a[lo:lo + chunk][seg], flat_b[lo:lo + chunk][seg]
            rows, cols, inside = self.to_cells(pa + (pb - pa) * frac)
            hit = self.blocked[rows, cols] | ~inside
            hit[first] = False  # the end cells hold the two bodies themselves
            hit[first + c - 1] = False
            out[lo:lo + chunk] = ~np.logical_or.reduceat(hit, first)
        return out.reshape(a.shape)

    def free_along(self, start: complex, direction: complex, max_distance: float, radius: float) -> float:
        """How far one can move from `start` along the unit `direction` keeping `radius` clearance."""
        steps = max(2, int(max_distance / (0.5 * self.mpp)) + 1)
        s = np.linspace(0.0, max_distance, steps)
        ok = self.clearance_at(start + direction * s) >= radius
        if ok.all():
            return float(max_distance)
        first_bad = int(np.argmin(ok))
        return float(s[first_bad - 1]) if first_bad > 0 else 0.0


def empty_room(width_m: float = 20.0, height_m: float = 20.0, resolution: float = 0.05,
               walls: list[tuple[float, float, float, float]] | None = None) -> World:
    """A walled rectangular room with optional extra wall boxes (x0, y0, x1, y1) in metres; world origin at
    the lower-left corner. For tests and benchmarks that need no files."""
    w, h = int(round(width_m / resolution)), int(round(height_m / resolution))
    occ = np.zeros((h, w), dtype=bool)
    occ[0, :] = occ[-1, :] = True
    occ[:, 0] = occ[:, -1] = True
    transform = Transform.from_nav2(resolution, [0.0, 0.0, 0.0], h)
    for x0, y0, x1, y1 in walls or []:
        (c0, r0), (c1, r1) = transform.worlds_to_pixel(np.array([[x0, y1], [x1, y0]]))
        occ[max(0, int(np.floor(r0))):int(np.ceil(r1)) + 1, max(0, int(np.floor(c0))):int(np.ceil(c1)) + 1] = True
    return World(OccupancyGrid(occupied=occ, unknown=np.zeros_like(occ)), transform)
