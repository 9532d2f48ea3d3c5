"""The robots' global planner: geodesic cost-to-go fields on the occupancy map, one per waypoint of the
robot's route (world.costfield: scikit-image's minimum-cost-path search, Dijkstra on the 8-connected grid
with diagonal steps costing sqrt(2)), under the robot's cell-cost rule (`rule`).

A cell's cost per metre is 1 where the robot's disc keeps SOFT metres more than its radius from every wall,
rising linearly to 1 + PENALTY at its radius (the planned way keeps to the middle of a corridor, not to a
wall); in a passage narrower than that the rise is counted from its middle (CellCost.along_middle), which
costs 1 per metre: a narrow aisle the robot fits through is not dearer than a detour twice as long round it.
A cell is impassable where the clearance is under INFLATE x radius (a doorway the robot just fits through
still counts). The field holds, per cell, the cost of the cheapest way from that cell to the
waypoint (about metres; inf where no way exists); the compiled planner (robot.planner) follows its steepest
descent. Fields are kept per World, goal cell and radius: a campaign's worker computes each once.
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.world.costfield import CellCost, CostField
from socnavgen.sim.world.grid import World

INFLATE = 0.9  # x robot radius: cells with less clearance are impassable
SOFT = 0.4  # m beyond the radius where walls start to cost
PENALTY = 3.0  # extra cost per metre right at the radius
MAX_CELLS = 1_500_000  # larger maps are planned on coarser cells (a whole number of map cells each)
GOAL_SEED = 0.3  # m: cells this close to a waypoint are passable whatever the walls (a waypoint at a wall)


def field_scale(world: World) -> int:
    """Map cells per planner cell along each axis (1 for maps up to MAX_CELLS cells)."""
    return max(1, math.ceil(math.sqrt(world.height * world.width / MAX_CELLS)))


def rule(radius: float) -> CellCost:
    """The planner's cell-cost rule for a robot of this radius."""
    radius = round(float(radius), 4)
    return CellCost(passable=INFLATE * radius, full=radius, comfort=radius + SOFT, extra=PENALTY, along_middle=True)


def cost_to_go(world: World, goal: complex, radius: float) -> np.ndarray:
    """(rows, cols) float32 cost of the cheapest way from each planner cell to `goal` (inf: none)."""
    grid = CostField.of(world, rule(radius), field_scale(world))
    rows, cols, inside = world.to_cells(np.array([goal]))
    if not inside[0]:
        return np.full(grid.shape, np.inf, np.float32)
    return grid.field(int(rows[0]) // grid.k, int(cols[0]) // grid.k, opened=GOAL_SEED)


def route_fields(world: World, waypoints: np.ndarray, radius: float) -> np.ndarray:
    """(W, rows, cols) float32: the cost-to-go field of each waypoint of a route (kept per route)."""
    key = ("route", tuple(complex(w) for w in waypoints), round(radius, 4))
    cache = getattr(world, "_planner_fields", None)
    if cache is None:
        cache = {}
        world._planner_fields = cache  # the World is never modified; this only memoises derived arrays
    if key not in cache:
        fields = np.stack([cost_to_go(world, complex(w), radius) for w in waypoints])
        cache[key] = fields
    return cache[key]


NO_FIELDS = np.zeros((1, 1, 1), np.float32)  # a policy that does not plan
