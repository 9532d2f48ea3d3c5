"""Following the global planner (compiled): where to head for the current waypoint.

The straight line to the waypoint when the robot's disc keeps LINE_CLEAR x its radius from the walls all
along it (the scenario's route is the plan; the planner only gets the robot around what stands in the way);
otherwise the farthest point, up to LOOK metres along the steepest descent of the waypoint's cost-to-go field
(robot.fields), that the robot sees in such a clear line (a carrot, as in pure pursuit).
"""

from __future__ import annotations

import math

from socnavgen.sim.jit import jit
from socnavgen.sim.world.queries import cell_of, clearance_at, lowest_around, path_clear

LINE_CLEAR = 0.95  # x radius: a straight line to the waypoint keeping this from walls is taken as it is
LOOK = 2.5  # m along the planned way: the farthest carrot
CHECK_EVERY = 3  # planner cells between two line-of-sight checks


@jit(inline=True)
def cell_centre(world, row, col):  # noqa: ANN001, ANN201
    """World point of pixel (row, col)'s centre (the inverse of queries.cell_of)."""
    a = world.affine
    det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
    c, r = col - a[0, 2], row - a[1, 2]
    return complex((a[1, 1] * c - a[0, 1] * r) / det, (-a[1, 0] * c + a[0, 0] * r) / det)


@jit
def field_value(fields, k, scale, world, p):  # noqa: ANN001, ANN201
    """Field k's cost-to-go at point p (inf off the map)."""
    row, col = cell_of(world, p)
    fr, fc = row // scale, col // scale
    if row < 0 or col < 0 or fr >= fields.shape[1] or fc >= fields.shape[2]:
        return math.inf
    return fields[k, fr, fc]


@jit
def steer(s, fields, k, target):  # noqa: ANN001, ANN201
    """The point to head for to reach waypoint k at `target` (see the module's docstring)."""
    robot = s.robot[0]
    return carrot_at(s.world, fields, k, target, robot.pos, robot.radius, s.policy[0].field_scale)


@jit
def carrot_at(world, fields, k, target, p, radius, scale):  # noqa: ANN001, ANN201
    """steer for a robot of `radius` at `p` on `world` (a WorldMap), planner cells of `scale` map cells: what
    a policy of the user's calls (robot.route.Route) with the fields of robot.fields.route_fields."""
    clear = min(LINE_CLEAR * radius, clearance_at(world, p))  # never more than where it stands
    if fields.shape[1] == 1 or path_clear(world, p, target, clear):
        return target
    row, col = cell_of(world, p)
    fr, fc = row // scale, col // scale
    rows, cols = fields.shape[1], fields.shape[2]
    if not (0 <= fr < rows and 0 <= fc < cols):
        return target
    best = fields[k, fr, fc]
    if not math.isfinite(best):  # standing where the planner says no disc fits: the best cell around
        for dr in range(-3, 4):
            for dc in range(-3, 4):
                r2, c2 = fr + dr, fc + dc
                if 0 <= r2 < rows and 0 <= c2 < cols and fields[k, r2, c2] < best:
                    best, fr, fc = fields[k, r2, c2], r2, c2
        if not math.isfinite(best):
            return target
    step = world.mpp * scale
    half = 0.5 * (scale - 1)
    carrot, found = target, False
    for n in range(int(LOOK / step)):
        nr, nc, _ = lowest_around(fields[k], fr, fc, 1)
        if nr == fr and nc == fc:  # the waypoint's cell
            return carrot if found else target
        fr, fc = nr, nc
        if n % CHECK_EVERY == CHECK_EVERY - 1 or not found:
            point = cell_centre(world, fr * scale + half, fc * scale + half)
            if not found or path_clear(world, p, point, clear):
                carrot, found = point, True  # the first cell down the field is taken whatever its line
            elif n >= 2 * CHECK_EVERY:
                break
    return carrot
