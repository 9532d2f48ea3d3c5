"""The static 2D world of a simulation: where the walls are, in metres.

Built once per location from its occupancy grid and transform (the only pixel <-> world conversion): a
distance transform gives every cell its clearance and its nearest wall cell, so each query is a table
lookup whatever the map's size. Queries on many points go through the compiled per-point functions of
world.queries, the ones the simulator itself asks.
"""

from __future__ import annotations

import numpy as np

from socnavgen.location.occupancy import OccupancyGrid
from socnavgen.location.transform import Transform
from socnavgen.memo import kept
from socnavgen.sim.world import queries

OBSTACLE_RANGE = 10.0  # m: the Gazebo wrapper sends each human the nearest obstacle point within 10 m


class World:
    """Occupancy in metres: nearest wall point, clearance, line of sight. Never modified once built."""

    def __init__(self, occupancy: OccupancyGrid, transform: Transform, obstacle_range: float = OBSTACLE_RANGE):
        self.occupancy = occupancy
        self.transform = transform
        self.obstacle_range = float(obstacle_range)
        self.blocked = np.ascontiguousarray(occupancy.blocked, dtype=bool)
        self.height, self.width = self.blocked.shape
        self.mpp = float(transform.meters_per_pixel)
        self.has_obstacles = bool(self.blocked.any())
        if self.has_obstacles:
            from scipy import ndimage

            dist_px, (rows, cols) = ndimage.distance_transform_edt(~self.blocked, return_indices=True)
            centres = transform.pixels_to_world(np.stack([cols.ravel(), rows.ravel()], axis=1))
            self.obstacle_table = (centres[:, 0] + 1j * centres[:, 1]).reshape(self.blocked.shape)
            self.clearance = dist_px * self.mpp  # metres from each cell centre to the nearest blocked cell
        else:
            self.obstacle_table = np.zeros((1, 1), dtype=complex)
            self.clearance = np.full(self.blocked.shape, np.inf)
        self.map = queries.WorldMap(np.ascontiguousarray(self.clearance, dtype=float), self.blocked,
                                    np.ascontiguousarray(self.obstacle_table, dtype=complex),
                                    np.ascontiguousarray(transform.inverse, dtype=float), self.mpp,
                                    self.obstacle_range, self.has_obstacles)

    @classmethod
    def from_location(cls, location, obstacle_range: float = OBSTACLE_RANGE) -> World:  # noqa: ANN001
        """The location's world, built once per Location object and range (simulation, metrics and the
        verifier all need it; campaigns ask for it thousands of times)."""
        return kept(location, "worlds", lambda: cls(location.occupancy, location.transform, obstacle_range),
                    float(obstacle_range))

    # -- queries on any number of complex world points ---------------------------------------------
    def to_cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rows, cols, inside) of complex world points, the cells queries.cell_of gives; points outside the
        map are clamped to its border (inside says which)."""
        points = np.asarray(points, dtype=complex)
        a = self.map.affine
        cols = np.floor(a[0, 0] * points.real + a[0, 1] * points.imag + a[0, 2] + 0.5).astype(np.intp)
        rows = np.floor(a[1, 0] * points.real + a[1, 1] * points.imag + a[1, 2] + 0.5).astype(np.intp)
        inside = (cols >= 0) & (cols < self.width) & (rows >= 0) & (rows < self.height)
        return np.clip(rows, 0, self.height - 1), np.clip(cols, 0, self.width - 1), inside

    def nearest_obstacles(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest wall point of each point (on the wall's surface) and whether it is within range."""
        flat = np.ascontiguousarray(np.asarray(points, dtype=complex).ravel())
        out, valid = np.zeros(flat.shape, dtype=complex), np.zeros(flat.shape, dtype=bool)
        queries.nearest_obstacles(self.map, flat, out, valid)
        return out.reshape(np.shape(points)), valid.reshape(np.shape(points))

    def clearance_at(self, points: np.ndarray | complex) -> np.ndarray:
        """Metres to the nearest wall (0 outside the map)."""
        flat = np.ascontiguousarray(np.atleast_1d(np.asarray(points, dtype=complex)).ravel())
        out = np.zeros(flat.shape)
        queries.clearances(self.map, flat, out)
        return out.reshape(np.atleast_1d(np.asarray(points)).shape)

    def clearance_at_point(self, point: complex) -> float:
        return float(queries.clearance_at(self.map, complex(point)))

    def is_free(self, point: complex, radius: float) -> bool:
        return self.clearance_at_point(point) >= radius

    def line_of_sight(self, a: complex, b: np.ndarray | complex) -> np.ndarray:
        """True where the straight segment a -> b crosses no blocked cell (one a, one or many b)."""
        b = np.atleast_1d(np.asarray(b, dtype=complex))
        return self.segments_clear(np.full(b.shape, complex(a)), b)

    def segments_clear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """line_of_sight for many segments a[k] -> b[k] at once (broadcast shapes): the verifier asks it for
        every step and person of a trace."""
        a, b = np.broadcast_arrays(np.asarray(a, dtype=complex), np.asarray(b, dtype=complex))
        out = np.ones(a.size, dtype=bool)
        if self.has_obstacles and a.size:
            queries.segments_clear(self.map, np.ascontiguousarray(a.ravel()), np.ascontiguousarray(b.ravel()), out)
        return out.reshape(a.shape)

    def free_along(self, start: complex, direction: complex, max_distance: float, radius: float) -> float:
        """How far one can move from `start` along the unit `direction` keeping `radius` clearance."""
        return float(queries.free_along(self.map, complex(start), complex(direction), float(max_distance),
                                        float(radius)))


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
