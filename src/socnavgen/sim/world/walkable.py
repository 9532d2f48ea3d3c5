"""Walkable distances on a map: along the free space, never through a wall. The one implementation of
geodesic distance: the verifier's "within d m along the walkable way" and the metrics' shortest walkable path
(path efficiency) both read it.

Geodesic fields are world.costfield's (scikit-image's minimum cost path over the free cells, 8-connected, on a
grid coarsened to about CELL metres, every free cell costing 1), grown from one point and kept per World (and
per clearance). A cell is free when no wall is in it (`clearance` 0: where a person's centre may be, the verifier's rule) or when every map cell in it is
at least `clearance` metres from the nearest wall (a body of that radius fits: the robot's reference path).

- `between(a, b)`: the distance between two moving points. Where the straight segment between them is free
  (line of sight) it is the straight one; elsewhere the field's value, grown from whichever of the two visits
  fewer cells (a follower stuck behind a wall costs one field for the whole run). An 8-connected path is at
  most ~8 % longer than the true one; the straight distance is a lower bound.
- `shortest_path(a, b)`: the shortest way itself, as a polyline: down the field from a to b, then pulled
  taut (each corner dropped while the straight cut keeps `clearance` from the walls), so its length is the
  any-angle shortest path to within about a coarse cell, not the 8-connected one.

Cost (hospital map, 600 x 280 px at 0.05 m): one field ~5 ms at 0.1 m cells.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from socnavgen.memo import kept
from socnavgen.sim.world.costfield import CellCost, CostField, cells_per_side

CELL = 0.1  # m: side of the coarse cells the fields are grown on
MAX_FIELDS = 256  # fields kept per World and clearance (about 42k cells x 4 bytes each on the bundled hospital)
_STEPS = [(dr, dc, math.hypot(dr, dc)) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if dr or dc]


class WalkableDistance:
    """Geodesic distances on one World's free space (World.blocked, World.clearance, World.to_cells,
    World.segments_clear), for bodies whose centre keeps `clearance` metres from every wall."""

    def __init__(self, world: Any, cell: float = CELL, clearance: float = 0.0) -> None:
        self.world = world
        self.clearance = float(clearance)
        self.grid = CostField.of(world, CellCost(passable=self.clearance), cells_per_side(world, cell), MAX_FIELDS)
        self.k = self.grid.k
        self.size = self.grid.size  # metres per coarse cell
        self.free = self.grid.passable
        self.routes: dict[tuple, float | None] = {}  # lengths of whole routes its users worked out, kept

    @classmethod
    def of(cls, world: Any, clearance: float = 0.0) -> WalkableDistance:
        """The World's WalkableDistance for this clearance, built once per World (campaign workers keep their
        worlds)."""
        return kept(world, "walkable", lambda: cls(world, clearance=float(clearance)), float(clearance))

    def cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Free coarse cells (rows, cols) of complex world points (the nearest free one to a point in a wall)."""
        return self.grid.snap(*self.grid.cells(points))

    def field(self, row: int, col: int) -> np.ndarray:
        """Metres along the free space from the coarse cell (row, col) to every coarse cell (inf: unreachable)."""
        return self.grid.field(row, col)

    def between(self, a: np.ndarray, b: np.ndarray, unreachable: float = math.inf) -> np.ndarray:
        """(T,) walkable distances between complex points a[k] and b[k] (`unreachable` where no way joins
        them)."""
        a, b = np.asarray(a, dtype=complex), np.asarray(b, dtype=complex)
        out = np.abs(b - a)
        if not self.free.any() or not len(out):
            return out
        hidden = ~self.world.segments_clear(a, b)
        if not hidden.any():
            return out
        steps = np.flatnonzero(hidden)
        ar, ac = self.cells(a[steps])
        br, bc = self.cells(b[steps])
        a_cells, b_cells = ar * self.free.shape[1] + ac, br * self.free.shape[1] + bc
        if len(np.unique(b_cells)) < len(np.unique(a_cells)):  # grow the fields from the side with fewer cells
            ar, ac, br, bc, a_cells = br, bc, ar, ac, b_cells
        geodesic = np.empty(len(steps))
        for cell in np.unique(a_cells):
            mask = a_cells == cell
            geodesic[mask] = self.field(*divmod(int(cell), self.free.shape[1]))[br[mask], bc[mask]]
        out[steps] = np.where(np.isfinite(geodesic), np.maximum(out[steps], geodesic), unreachable)
        return out

    # -- the shortest way itself -------------------------------------------------------------------
    def _centre(self, row: int, col: int) -> complex:
        """World point of a coarse cell's centre."""
        pixel = np.array([[col * self.k + (self.k - 1) / 2, row * self.k + (self.k - 1) / 2]])
        x, y = self.world.transform.pixels_to_world(pixel)[0]
        return complex(x, y)

    def _clear(self, a: complex, b: complex) -> bool:
        """The straight cut a-b keeps this clearance from every wall (line of sight when it is 0)."""
        if self.clearance > 0:
            from socnavgen.sim.world import queries

            return bool(queries.path_clear(self.world.map, complex(a), complex(b), self.clearance))
        return bool(self.world.segments_clear(np.array([a]), np.array([b]))[0])

    def _descend(self, a: complex, b: complex) -> list[complex] | None:
        """a, the centres of the coarse cells of a shortest 8-connected way down b's field, b (None: no way)."""
        if self._clear(a, b):
            return [a, b]
        if not self.free.any():
            return None
        (ar,), (ac,) = self.cells(np.array([a]))
        (br,), (bc,) = self.cells(np.array([b]))
        field = self.field(br, bc)
        if not np.isfinite(field[ar, ac]):
            return None
        cells = [(int(ar), int(ac))]
        rows, cols = field.shape
        while field[cells[-1]] > 0:  # down the field: each step to the neighbour on a shortest path
            r, c = cells[-1]
            best, here = None, float(field[r, c])
            for dr, dc, length in _STEPS:
                nr, nc = r + dr, c + dc
                if 0 <= nr < rows and 0 <= nc < cols and np.isfinite(field[nr, nc]):
                    value = float(field[nr, nc]) + length * self.size
                    if best is None or value < best[0]:
                        best = (value, (nr, nc))
            if best is None or field[best[1]] >= here:  # float32 ties at the source: done
                break
            cells.append(best[1])
        return [a, *(self._centre(r, c) for r, c in cells[1:-1]), b]

    def shortest_path(self, a: complex, b: complex) -> np.ndarray | None:
        """Complex points of the shortest way from a to b (both included), pulled taut; None when no way joins
        them. a and b themselves may lie where the body does not fit (a robot's start beside a wall): the way
        starts and ends at the nearest coarse cell where it does."""
        return self.route([a, b])

    def route(self, waypoints: list[complex], slack: float = 0.0) -> np.ndarray | None:
        """The shortest way from the first point through every other in order to the last, pulled taut, where
        an intermediate waypoint counts as passed within `slack` metres (a robot reaching its waypoints within
        0.4 m cuts their corners); None when no way joins two of them."""
        points: list[complex] = [complex(waypoints[0])]
        anchors: list[tuple[int, complex]] = []
        for a, b in zip(waypoints[:-1], waypoints[1:], strict=True):
            leg = self._descend(complex(a), complex(b))
            if leg is None:
                return None
            points += leg[1:]
            anchors.append((len(points) - 1, complex(b)))
        return np.array(self._pull(points, anchors[:-1], slack))

    def route_length(self, waypoints: list[complex], slack: float = 0.0) -> float:
        """Metres of `route` (inf when no way joins the waypoints), kept per route."""
        key = (tuple((round(complex(p).real, 3), round(complex(p).imag, 3)) for p in waypoints), round(slack, 3))
        if key not in self.routes:
            path = self.route(waypoints, slack)
            self.routes[key] = math.inf if path is None else float(np.abs(np.diff(path)).sum())
        return self.routes[key]

    def _near(self, u: complex, w: complex, centres: list[complex], slack: float) -> bool:
        """The segment u-w passes within `slack` of every centre."""
        d = w - u
        for c in centres:
            s = 0.0 if d == 0 else min(1.0, max(0.0, ((c - u) * d.conjugate()).real / abs(d) ** 2))
            if abs(u + s * d - c) > slack + 1e-9:
                return False
        return True

    def _pull(self, points: list[complex], anchors: list[tuple[int, complex]], slack: float) -> list[complex]:
        """Pull the polyline taut: from each kept point go as far along it as the straight cut stays clear
        (and passes within `slack` of every anchor it skips: (index in points, waypoint)); slide each corner
        toward the cut between its neighbours as far as that holds; then again on the result sampled every half
        cell, so corners settle on the walls' corners, not on cell centres."""
        out = points
        for _ in range(3):
            kept = [0]
            while kept[-1] < len(points) - 1:
                i, j = kept[-1], kept[-1] + 1
                while j + 1 < len(points) and self._clear(points[i], points[j + 1]) and self._near(
                        points[i], points[j + 1], [c for a, c in anchors if i < a < j + 1], slack):
                    j += 1
                kept.append(j)
            out = [points[k] for k in kept]
            # each anchor belongs to the corner at it or to the segment that skipped it
            owners = [int(np.searchsorted(kept, a, side="right")) - 1 for a, _ in anchors]
            for k in range(1, len(out) - 1):
                u, v, w = out[k - 1], out[k], out[k + 1]
                mine = [c for (_, c), m in zip(anchors, owners, strict=True) if m in (k - 1, k)]
                d = w - u
                s = 0.0 if d == 0 else min(1.0, max(0.0, ((v - u) * d.conjugate()).real / abs(d) ** 2))
                target, low, high = u + s * d, 0.0, 1.0
                for _ in range(8):  # bisection: the farthest slide that keeps both cuts clear
                    mid = (low + high) / 2
                    p = v + mid * (target - v)
                    ok = self._clear(u, p) and self._clear(p, w) and self._near(u, p, mine, slack) \
                        and self._near(p, w, mine, slack)
                    low, high = (mid, high) if ok else (low, mid)
                out[k] = v + low * (target - v)
            points, spans = [out[0]], [0]
            for u, w in zip(out[:-1], out[1:], strict=True):
                n = max(1, int(abs(w - u) / (self.size / 2)))
                points += [u + (w - u) * (m / n) for m in range(1, n + 1)]
                spans.append(len(points) - 1)
            moved = []
            for (_, c), m in zip(anchors, owners, strict=True):  # an anchor moves to its segment's nearest point
                lo, hi = spans[m], spans[min(m + 1, len(spans) - 1)]
                moved.append((lo + int(np.argmin([abs(points[q] - c) for q in range(lo, hi + 1)])), c))
            anchors = moved
        return out

    def shortest_length(self, a: complex, b: complex) -> float:
        """Metres of the shortest way from a to b (inf when none joins them)."""
        path = self.shortest_path(a, b)
        return math.inf if path is None else float(np.abs(np.diff(path)).sum())
