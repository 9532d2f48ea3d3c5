"""What the simulator asks the map, one point or one segment at a time (compiled): clearance, the nearest
wall point, line of sight, free room along a direction. The World (world.grid) answers batches of points
with the same functions.

The map travels as a WorldMap: distances from each cell centre to the nearest blocked cell (metres), the
blocked cells, each cell's nearest blocked cell centre (world point), and the world -> pixel transform.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen.sim.jit import jit


class WorldMap(NamedTuple):
    clearance: np.ndarray  # (rows, cols) metres from each cell centre to the nearest blocked cell
    blocked: np.ndarray  # (rows, cols) bool
    obstacles: np.ndarray  # (rows, cols) complex: world point of each cell's nearest blocked cell
    affine: np.ndarray  # (3, 3) world -> pixel
    mpp: float  # metres per pixel
    obstacle_range: float  # m: walls farther than this exert no force (the Gazebo wrapper's 10 m)
    has_obstacles: bool


@jit(inline=True)
def cell_of(world, p):  # noqa: ANN001, ANN201
    """(row, col) of the pixel holding world point p (may lie outside the map)."""
    a = world.affine
    col = int(math.floor(a[0, 0] * p.real + a[0, 1] * p.imag + a[0, 2] + 0.5))
    row = int(math.floor(a[1, 0] * p.real + a[1, 1] * p.imag + a[1, 2] + 0.5))
    return row, col


@jit(inline=True)
def inside(world, row, col):  # noqa: ANN001, ANN201
    return 0 <= row < world.blocked.shape[0] and 0 <= col < world.blocked.shape[1]


@jit(inline=True)
def clearance_at(world, p):  # noqa: ANN001, ANN201
    """Metres from p's cell to the nearest wall (0 outside the map)."""
    row, col = cell_of(world, p)
    return world.clearance[row, col] if inside(world, row, col) else 0.0


@jit(inline=True)
def nearest_obstacle(world, p):  # noqa: ANN001, ANN201
    """(the nearest wall point, whether it is within the obstacle range): the nearest blocked cell's centre
    (p's cell clamped to the map) moved half a cell toward p, i.e. on the wall's surface."""
    if not world.has_obstacles:
        return 0j, False
    row, col = cell_of(world, p)
    row = min(max(row, 0), world.blocked.shape[0] - 1)
    col = min(max(col, 0), world.blocked.shape[1] - 1)
    o = world.obstacles[row, col]
    d = p - o
    dist = abs(d)
    if dist > 0.5 * world.mpp:
        o = o + d * (0.5 * world.mpp / dist)
    return o, abs(p - o) <= world.obstacle_range


@jit
def line_of_sight(world, a, b):  # noqa: ANN001, ANN201
    """No blocked cell (and no point off the map) between a and b, sampled every half pixel or closer; the
    two end samples are not looked at: they hold the two bodies themselves (one may touch a wall)."""
    if not world.has_obstacles:
        return True
    d = b - a
    count = max(2, int(math.ceil(abs(d) / (0.5 * world.mpp))) + 1)
    step = 1.0 / (count - 1)
    for k in range(1, count - 1):
        row, col = cell_of(world, a + d * (k * step))
        if not inside(world, row, col) or world.blocked[row, col]:
            return False
    return True


@jit
def free_along(world, start, direction, max_distance, radius):  # noqa: ANN001, ANN201
    """How far one can move from `start` along the unit `direction` keeping `radius` from walls (checked
    every half pixel; at most max_distance)."""
    steps = max(2, int(max_distance / (0.5 * world.mpp)) + 1)
    step = max_distance / (steps - 1)
    for k in range(steps):
        if clearance_at(world, start + direction * (k * step)) < radius:
            return (k - 1) * step if k > 0 else 0.0
    return max_distance


@jit
def free_opening(world, start, direction, max_distance, radius):  # noqa: ANN001, ANN201
    """free_along for a start that may itself be closer than `radius` to a wall (a body squeezed into a corner by
    others): how far one moves from `start` along the unit `direction` never coming closer to walls than they have
    been on the way, up to `radius` (the same as free_along from a start with that much room; from a squeezed
    one, the directions that open up are free, those that squeeze them further are not)."""
    steps = max(2, int(max_distance / (0.5 * world.mpp)) + 1)
    step = max_distance / (steps - 1)
    floor = min(radius, clearance_at(world, start))
    for k in range(steps):
        room = clearance_at(world, start + direction * (k * step))
        if room < floor:
            return (k - 1) * step if k > 0 else 0.0
        floor = max(floor, min(room, radius))
    return max_distance


@jit
def path_clear(world, a, b, clearance):  # noqa: ANN001, ANN201
    """Every point of the segment a-b (checked every <= 0.1 m) keeps `clearance` from walls."""
    n = max(2, int(abs(b - a) / 0.1) + 1)
    d = b - a
    for k in range(n):
        if clearance_at(world, a + d * (1.0 if k == n - 1 else k / (n - 1))) < clearance:
            return False
    return True


@jit
def swept_clear(world, a, b, clearance):  # noqa: ANN001, ANN201
    """A disc moving from a to b keeps `clearance` from walls all the way (checked every half pixel): a
    fast move cannot jump across a thin wall."""
    n = max(2, int(math.ceil(abs(b - a) / (0.5 * world.mpp))) + 1)
    d = b - a
    for k in range(1, n):  # noqa: SIM110 - a loop: numba compiles no generator inside all()
        if clearance_at(world, a + d * (k / (n - 1))) < clearance:
            return False
    return True


# ---- batches (the World's vectorised queries) ------------------------------------------------------
@jit
def clearances(world, points, out):  # noqa: ANN001, ANN201
    for k in range(points.shape[0]):
        out[k] = clearance_at(world, points[k])


@jit
def nearest_obstacles(world, points, out, valid):  # noqa: ANN001, ANN201
    for k in range(points.shape[0]):
        out[k], valid[k] = nearest_obstacle(world, points[k])


@jit
def segments_clear(world, a, b, out):  # noqa: ANN001, ANN201
    for k in range(a.shape[0]):
        out[k] = line_of_sight(world, a[k], b[k])


@jit(inline=True)
def lowest_around(field, row, col, reach):  # noqa: ANN001, ANN201
    """One step down a cost field (a 2D array): (row, col, value) of the lowest cell within `reach` cells of
    (row, col) along both axes, strictly lower than it (the first such in row order wins a tie), or (row, col)
    itself and its value when none is lower. The people's routes (world.routes.downhill) and the robot's
    planner (robot.planner.carrot_at) both walk their fields with it."""
    rows, cols = field.shape
    br, bc, best = row, col, field[row, col]
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            r, c = row + dr, col + dc
            if 0 <= r < rows and 0 <= c < cols and field[r, c] < best:
                br, bc, best = r, c, field[r, c]
    return br, bc, best
