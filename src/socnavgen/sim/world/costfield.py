"""Cost-to-go fields on the occupancy map: the one implementation of "the cheapest way from every cell to a
point, never through a wall". The verifier's and the metrics' walkable distances (world.walkable), the
people's route fields through doors and to the robot (world.routes) and the robot planner's fields
(robot.fields) all grow their fields here, each with its own cell-cost rule.

A field lives on a grid of square cells of `k` map cells each (a cell takes the least clearance of its map
cells; cells past the map's edge count as walls). A cell's cost per metre follows a CellCost rule from its
clearance (metres to the nearest wall): impassable in a wall or under `passable`, else 1 + `extra` at
`full` falling linearly to 1 at `comfort` (a body keeps to the middle of a door). A rule `along_middle`
measures that fall from the middle of the passage instead: from the most clearance within comfort - full
metres, when that is less than `comfort`, so the middle of a passage narrower than 2 x comfort costs 1 per
metre as open floor does (a long aisle the body fits through is not dearer than a walk twice as long round
it) and its sides still cost more. The field is
scikit-image's minimum cost path (`MCP_Geometric`: Dijkstra on the 8-connected grid, a diagonal step
costing sqrt(2)) grown from one cell, in metres x cost (inf where no way leads). Fields are kept per World,
rule and grid (least recently used first out), so a campaign's worker grows each once.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any, NamedTuple

import numpy as np
from scipy import ndimage

from socnavgen.memo import kept

KEEP = 512  # fields kept per World, rule and grid


class CellCost(NamedTuple):
    """Cost per metre of a cell with clearance c: inf when c is 0 (a wall) or under `passable`; else
    1 + extra x clip((top - c) / (comfort - full), 0, 1), where top is `comfort`, or with `along_middle` the
    least of `comfort` and the most clearance within comfort - full metres of the cell (its passage's middle)."""

    passable: float = 0.0  # m: the least clearance of a passable cell (0: any cell outside a wall)
    full: float = 0.0  # m: the clearance at which the near-wall cost is all `extra`
    comfort: float = 0.0  # m: from this clearance on a cell costs 1
    extra: float = 0.0  # extra cost per metre at `full` clearance
    along_middle: bool = False  # the near-wall cost is counted from the passage's middle (see the module)

    def costs(self, clearance: np.ndarray, cell: float = 0.0) -> np.ndarray:
        """Cost per metre of cells of this clearance (inf: impassable); `cell`: metres per cell (along_middle)."""
        cost = np.ones(clearance.shape)
        if self.extra > 0 and self.comfort > self.full:
            top = np.full(clearance.shape, self.comfort)
            if self.along_middle and cell > 0:
                reach = int(np.ceil((self.comfort - self.full) / cell))
                top = np.minimum(top, ndimage.maximum_filter(clearance, size=2 * reach + 1, mode="nearest"))
            cost += self.extra * np.clip((top - clearance) / (self.comfort - self.full), 0.0, 1.0)
        cost[(clearance <= 0) | (clearance < self.passable)] = np.inf
        return cost


def coarse_clearance(world: Any, k: int) -> np.ndarray:
    """The least clearance (m) of each block of k x k map cells (0 past the map's edge; a map without
    walls has 1e9 everywhere)."""
    clearance = np.asarray(world.clearance, dtype=float)
    clearance = np.where(np.isfinite(clearance), clearance, 1e9)
    if k == 1:
        return clearance
    h, w = clearance.shape
    padded = np.zeros((-(-h // k) * k, -(-w // k) * k))
    padded[:h, :w] = clearance
    return padded.reshape(padded.shape[0] // k, k, padded.shape[1] // k, k).min(axis=(1, 3))


def cells_per_side(world: Any, metres: float) -> int:
    """Map cells per grid cell for grid cells of about `metres` (at least 1)."""
    return max(1, int(round(metres / float(world.mpp))))


class CostField:
    """The fields of one World under one cell-cost rule on a grid of k x k map cells."""

    def __init__(self, world: Any, rule: CellCost, k: int, keep: int = KEEP) -> None:
        self.world, self.rule, self.k, self.keep = world, rule, int(k), keep
        self.size = self.k * float(world.mpp)  # metres per grid cell
        self.cost = rule.costs(coarse_clearance(world, self.k), self.size)
        self.shape = self.cost.shape
        self.passable = np.isfinite(self.cost)
        self._snap: tuple[np.ndarray, np.ndarray] | None = None
        self._fields: OrderedDict[tuple, np.ndarray] = OrderedDict()

    @classmethod
    def of(cls, world: Any, rule: CellCost, k: int, keep: int = KEEP) -> CostField:
        """The World's CostField for this rule and grid, built once per World."""
        return kept(world, "costfields", lambda: cls(world, rule, k, keep), (rule, int(k)))

    def cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid cells (rows, cols) of complex world points (clamped to the map)."""
        rows, cols, _ = self.world.to_cells(np.asarray(points, dtype=complex))
        return np.asarray(rows) // self.k, np.asarray(cols) // self.k

    def snap(self, rows: np.ndarray, cols: np.ndarray, within: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
        """The nearest passable cell to each cell (a body pressed against a wall), when it is within `within`
        metres along both axes; the cell itself otherwise (and when nothing is passable)."""
        rows, cols = np.asarray(rows), np.asarray(cols)
        if not self.passable.any():
            return rows, cols
        if self._snap is None:
            _, (sr, sc) = ndimage.distance_transform_edt(~self.passable, return_indices=True)
            self._snap = (sr, sc)
        sr, sc = self._snap[0][rows, cols], self._snap[1][rows, cols]
        reach = within / self.size
        near = (np.abs(sr - rows) <= reach) & (np.abs(sc - cols) <= reach)
        return np.where(near, sr, rows), np.where(near, sc, cols)

    def field(self, row: int, col: int, opened: float = 0.0) -> np.ndarray:
        """(rows, cols) float32: metres x cost of the cheapest way from every cell to cell (row, col) (inf:
        none; all inf when that cell is impassable). `opened` > 0: cells within that many metres of it
        (along both axes) are passable at the rule's highest cost (a waypoint drawn at a wall)."""
        key = (int(row), int(col), float(opened))
        found = self._fields.get(key)
        if found is not None:
            self._fields.move_to_end(key)
            return found
        cost = self.cost
        if opened > 0:
            seed = max(1, int(np.ceil(opened / self.size)))
            cost = cost.copy()
            block = cost[max(key[0] - seed, 0):key[0] + seed + 1, max(key[1] - seed, 0):key[1] + seed + 1]
            block[~np.isfinite(block)] = 1.0 + self.rule.extra
        if np.isfinite(cost[key[:2]]):
            from skimage.graph import MCP_Geometric

            costs, _ = MCP_Geometric(cost, fully_connected=True).find_costs([key[:2]])
            found = (costs * self.size).astype(np.float32)
        else:
            found = np.full(self.shape, np.inf, dtype=np.float32)
        self._fields[key] = found
        if len(self._fields) > self.keep:
            self._fields.popitem(last=False)
        return found
