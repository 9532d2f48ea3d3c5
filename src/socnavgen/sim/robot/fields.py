"""The robots' global planner: geodesic cost-to-go fields on the occupancy map, one per waypoint of the
robot's route (scikit-image's minimum-cost-path search, `skimage.graph.MCP_Geometric`: Dijkstra on the
8-connected grid with diagonal steps costing sqrt(2)).

A cell's cost per metre is 1 where the robot's disc keeps SOFT metres more than its radius from every wall,
rising linearly to 1 + PENALTY at its radius (the planned way keeps to the middle of a corridor, not to a
wall), and the cell is impassable where the clearance is under INFLATE x radius (a doorway the robot just
fits through still counts). The field holds, per cell, the cost of the cheapest way from that cell to the
waypoint (about metres; inf where no way exists); the compiled planner (robot.planner) follows its steepest
descent. Fields are kept per World, goal cell and radius: a campaign's worker computes each once.
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.world.grid import World

INFLATE = 0.9  # x robot radius: cells with less clearance are impassable
SOFT = 0.4  # m beyond the radius where walls start to cost
PENALTY = 3.0  # extra cost per metre right at the radius
MAX_CELLS = 1_500_000  # larger maps are planned on coarser cells (a whole number of map cells each)
GOAL_SEED = 0.3  # m: cells this close to a waypoint are passable whatever the walls (a waypoint at a wall)


def field_scale(world: World) -> int:
    """Map cells per planner cell along each axis (1 for maps up to MAX_CELLS cells)."""
    return max(1, math.ceil(math.sqrt(world.height * world.width / MAX_CELLS)))


def _cache(world: World) -> dict:
    cache = getattr(world, "_planner_fields", None)
    if cache is None:
        cache = {}
        world._planner_fields = cache  # the World is never modified; this only memoises derived arrays
    return cache


def _costs(world: World, radius: float, scale: int) -> np.ndarray:
    key = ("costs", round(radius, 4), scale)
    cache = _cache(world)
    if key not in cache:
        clearance = world.clearance
        if scale > 1:  # the worst cell of each block decides
            rows, cols = -(-world.height // scale) * scale, -(-world.width // scale) * scale
            padded = np.zeros((rows, cols))
            padded[:world.height, :world.width] = clearance
            clearance = padded.reshape(rows // scale, scale, cols // scale, scale).min(axis=(1, 3))
        costs = 1.0 + PENALTY * np.clip((radius + SOFT - clearance) / SOFT, 0.0, 1.0)
        costs[clearance < INFLATE * radius] = np.inf
        cache[key] = costs
    return cache[key]


def cost_to_go(world: World, goal: complex, radius: float) -> np.ndarray:
    """(rows, cols) float32 cost of the cheapest way from each planner cell to `goal` (inf: none)."""
    from skimage.graph import MCP_Geometric

    scale = field_scale(world)
    rows, cols, inside = world.to_cells(np.array([goal]))
    cell = (int(rows[0]) // scale, int(cols[0]) // scale)
    key = ("field", cell, round(radius, 4), scale)
    cache = _cache(world)
    if key not in cache:
        costs = _costs(world, radius, scale).copy()
        seed = max(1, int(math.ceil(GOAL_SEED / (world.mpp * scale))))
        r0, c0 = max(cell[0] - seed, 0), max(cell[1] - seed, 0)
        block = costs[r0:cell[0] + seed + 1, c0:cell[1] + seed + 1]
        block[~np.isfinite(block)] = 1.0 + PENALTY
        costs[~np.isfinite(costs)] = -1.0  # MCP: negative = impassable
        found, _ = MCP_Geometric(costs, fully_connected=True).find_costs([cell])
        found = np.where(np.isfinite(found) & (costs >= 0), found * (world.mpp * scale), np.inf)
        cache[key] = found.astype(np.float32) if inside[0] else np.full(costs.shape, np.inf, np.float32)
    return cache[key]


def route_fields(world: World, waypoints: np.ndarray, radius: float) -> np.ndarray:
    """(W, rows, cols) float32: the cost-to-go field of each waypoint of a route (kept per route)."""
    key = ("route", tuple(complex(w) for w in waypoints), round(radius, 4))
    cache = _cache(world)
    if key not in cache:
        fields = np.stack([cost_to_go(world, complex(w), radius) for w in waypoints])
        cache[key] = fields
    return cache[key]


NO_FIELDS = np.zeros((1, 1, 1), np.float32)  # a policy that does not plan
