"""Routes on the map: which way a walking person heads when a wall stands between them and where they go.

People walk straight at their target when their body fits along the straight line (as HuNavSim's social
force model does). When it does not (a door jamb, a rack, a room's wall between a follower and the robot),
they follow a route field (world.costfield): the walking effort from every cell of a coarse grid (ROUTE_CELL) to a
fixed point, grown over the floor where a person's centre fits (clearance at least SQUEEZE) with a cost that
rises near walls (people keep to the middle of a door or corridor; the PEOPLE cell-cost rule). Going downhill on it leads through doorways and
around corners; a person heads for the farthest point down the field they can walk to in a straight line.

The points with a field are the simulation's landmarks: every person's goals and the robot's waypoints (a
follower reaches the robot by way of the robot's own waypoints). Fields are made on demand: the compiled step
asks for a landmark's field (RouteMap.wanted) and walks straight meanwhile; at the start of the next step the
episode hands control to Python, which grows the field (scikit-image's minimum-cost path, kept per World so a
campaign grows each field once per process) into a slot of the pool.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen.memo import kept
from socnavgen.sim.jit import jit
from socnavgen.sim.world.costfield import CellCost, CostField, cells_per_side
from socnavgen.sim.world.queries import clearance_at, lowest_around

ROUTE_CELL = 0.1  # m: side of the coarse cells of a route field
SQUEEZE = 0.3  # m: the least clearance a person's centre passes (a 0.6 m gap, sideways)
COMFORT = 0.6  # m: from this clearance on the floor costs the same everywhere
NEAR_WALL_COST = 3.0  # extra cost of a cell at SQUEEZE clearance (falling linearly to 0 at COMFORT)
POOL_CELLS = 8_000_000  # cells of the pool of fields one simulation keeps (32 MB of float32)
MAX_FIELDS = 512  # fields kept per World across simulations (a campaign's worker)
LOOKAHEAD = 40  # cells followed downhill when looking for the farthest point walkable straight (4 m)


PEOPLE = CellCost(passable=SQUEEZE, full=SQUEEZE, comfort=COMFORT, extra=NEAR_WALL_COST)  # a person's floor


class RouteGrid:
    """The coarse grid of one World and its route fields (Python side, world.costfield under the PEOPLE rule),
    built once per World."""

    def __init__(self, world) -> None:  # noqa: ANN001
        self.world = world
        self.grid = CostField.of(world, PEOPLE, cells_per_side(world, ROUTE_CELL), MAX_FIELDS)
        self.k, self.shape, self.cost, self.size = self.grid.k, self.grid.shape, self.grid.cost, self.grid.size

    @classmethod
    def of(cls, world) -> RouteGrid:  # noqa: ANN001
        return kept(world, "routes", lambda: cls(world))

    def cell(self, point: complex) -> tuple[int, int]:
        """The coarse cell of a world point where a person fits: its own, else the nearest passable one
        within 1 m (a goal drawn against a wall), else its own (its field is then unreachable)."""
        rows, cols = self.grid.snap(*self.grid.cells(np.array([point])), within=1.0)
        return int(rows[0]), int(cols[0])

    def field(self, point: complex) -> np.ndarray:
        """Walking effort (metres on open floor, more near walls) from every coarse cell to `point` (inf where
        a person cannot get there)."""
        return self.grid.field(*self.cell(point))


class RouteMap(NamedTuple):
    """What the compiled step reads of the routes: the landmarks, which of their fields are loaded where, and
    which are wanted."""

    points: np.ndarray  # (L,) complex: the landmarks
    slot_of: np.ndarray  # (L,) int64: the pool slot holding a landmark's field, -1 none yet
    wanted: np.ndarray  # (L,) bool: the step asked for this field
    pending: np.ndarray  # (1,) int64: how many are wanted
    pool: np.ndarray  # (slots, rows, cols) float32
    loaded: np.ndarray  # (L,) int64: when each field was loaded (the oldest slot is reused first)
    waypoint_marks: np.ndarray  # (W,) int64: the landmark of each robot waypoint
    chain: np.ndarray  # (LOOKAHEAD, 2) int64: scratch of `downhill`
    to_world: np.ndarray  # (3, 3) pixel -> world
    k: int  # pixels per coarse cell


def landmarks_of(goals: list[list[complex]], waypoints: list[complex]) -> tuple[list[complex], list[int]]:
    """(the distinct points among everyone's goals and the robot's waypoints, the landmark of each waypoint)."""
    index: dict[complex, int] = {}
    for point in [g for person in goals for g in person] + list(waypoints):
        index.setdefault(complex(point), len(index))
    return list(index), [index[complex(w)] for w in waypoints]


def route_map(world, landmarks: list[complex], waypoint_marks: list[int]) -> RouteMap:  # noqa: ANN001
    """The routes of a simulation whose goals and waypoints are `landmarks` (no field loaded yet)."""
    grid = RouteGrid.of(world)
    count = len(landmarks)
    slots = min(count, max(4, POOL_CELLS // max(grid.cost.size, 1)))
    return RouteMap(np.array(landmarks, dtype=complex).reshape(-1), np.full(count, -1, np.int64),
                    np.zeros(count, bool), np.zeros(1, np.int64),
                    np.zeros((slots, *grid.shape) if count else (0, 1, 1), np.float32), np.zeros(count, np.int64),
                    np.array(waypoint_marks, dtype=np.int64).reshape(-1), np.zeros((LOOKAHEAD, 2), np.int64),
                    np.ascontiguousarray(world.transform.matrix, dtype=float), grid.k)


def load_wanted(routes: RouteMap, world) -> None:  # noqa: ANN001
    """Grow every wanted field into the pool; when the pool is full, the slot loaded longest ago is reused
    (its landmark asks again if it needs it)."""
    grid = RouteGrid.of(world)
    for mark in np.flatnonzero(routes.wanted):
        held = np.flatnonzero(routes.slot_of >= 0)
        if len(held) < routes.pool.shape[0]:
            slot = len(held)
        else:
            victim = held[np.argmin(routes.loaded[held])]
            slot = int(routes.slot_of[victim])
            routes.slot_of[victim] = -1
        routes.pool[slot] = grid.field(complex(routes.points[mark]))
        routes.slot_of[mark] = slot
        routes.loaded[mark] = routes.loaded.max(initial=0) + 1
        routes.wanted[mark] = False
    routes.pending[0] = 0


# ---- compiled side ---------------------------------------------------------------------------------------
@jit(inline=True)
def coarse_cell(world, routes, p):  # noqa: ANN001, ANN201
    """(row, col) of the coarse cell holding world point p, clamped to the grid."""
    a = world.affine
    col = int(math.floor(a[0, 0] * p.real + a[0, 1] * p.imag + a[0, 2] + 0.5)) // routes.k
    row = int(math.floor(a[1, 0] * p.real + a[1, 1] * p.imag + a[1, 2] + 0.5)) // routes.k
    rows, cols = routes.pool.shape[1], routes.pool.shape[2]
    return min(max(row, 0), rows - 1), min(max(col, 0), cols - 1)


@jit(inline=True)
def cell_centre(routes, row, col):  # noqa: ANN001, ANN201
    """World point of a coarse cell's centre."""
    half = 0.5 * (routes.k - 1)
    px, py = col * routes.k + half, row * routes.k + half
    m = routes.to_world
    return complex(m[0, 0] * px + m[0, 1] * py + m[0, 2], m[1, 0] * px + m[1, 1] * py + m[1, 2])


@jit
def field_of(routes, mark):  # noqa: ANN001, ANN201
    """The pool slot of landmark `mark`'s field, or -1 (then it is asked for: loaded before the next step)."""
    if mark < 0:
        return -1
    slot = routes.slot_of[mark]
    if slot < 0 and not routes.wanted[mark]:
        routes.wanted[mark] = True
        routes.pending[0] += 1
    return slot


@jit
def effort(world, routes, slot, p):  # noqa: ANN001, ANN201
    """The field's value at p (its cell, else the best of the cells around it within 3 cells: a person
    pressed against a wall stands in a cell too narrow to pass); inf when unreachable."""
    row, col = coarse_cell(world, routes, p)
    field = routes.pool[slot]
    best = field[row, col]
    if math.isfinite(best):
        return best
    for dr in range(-3, 4):
        for dc in range(-3, 4):
            r, c = row + dr, col + dc
            if 0 <= r < field.shape[0] and 0 <= c < field.shape[1] and field[r, c] < best:
                best = field[r, c] + ROUTE_CELL * math.sqrt(dr * dr + dc * dc)
    return best


@jit
def walkable_straight(world, a, b, clearance, near_end):  # noqa: ANN001, ANN201
    """A body keeping `clearance` from walls can walk the segment a-b (checked every 0.1 m from a on; a
    itself is where the person already stands), up to `near_end` metres before b."""
    d = b - a
    length = abs(d)
    n = max(1, int(length / 0.1))
    for k in range(1, n + 1):
        if length * (1.0 - k / n) < near_end:
            break
        if clearance_at(world, a + d * (k / n)) < clearance:
            return False
    return True


@jit
def downhill(world, routes, slot, p, clearance):  # noqa: ANN001, ANN201
    """The farthest point down the field from p, within LOOKAHEAD cells, that a body keeping `clearance` from
    walls walks to in a straight line (the first cell down the field when none is)."""
    field, chain = routes.pool[slot], routes.chain
    row, col = coarse_cell(world, routes, p)
    count = 0
    value = field[row, col]
    for _ in range(LOOKAHEAD):
        reach = 1 if math.isfinite(value) else 3  # off the passable floor: step back onto it first
        br, bc, best = lowest_around(field, row, col, reach)
        if br == row and bc == col:
            break
        row, col, value = br, bc, best
        chain[count, 0], chain[count, 1] = row, col
        count += 1
    if count == 0:
        return p
    for j in range(count - 1, -1, -1):
        q = cell_centre(routes, chain[j, 0], chain[j, 1])
        if walkable_straight(world, p, q, clearance, 0.0):
            return q
    return cell_centre(routes, chain[0, 0], chain[0, 1])
