"""The nearer free spot round an occupied goal, compiled: the ONE rule for where the polite robot stops short of
someone standing at its goal (robot.policies), when the simulator ends such a run (people.make_room.stopped_short)
and when the metrics and the verifier count it as arrived (sim.arrival.no_nearer_spot)."""

from __future__ import annotations

import math

from socnavgen.proxemics import GOAL_STOP_GAP, GOAL_STOP_SLACK, NEARER_SPOT, SPOT_GRID
from socnavgen.sim.jit import jit
from socnavgen.sim.world.queries import clearance_at, line_of_sight


@jit
def nearer_spot(world, goal, robot, robot_radius, people):  # noqa: ANN001, ANN201
    """(found, spot): the spot nearest `goal`, on a SPOT_GRID grid within arrival reach of it (robot_radius + the
    largest person's radius + GOAL_STOP_GAP + GOAL_STOP_SLACK), at least NEARER_SPOT nearer the goal than the robot
    at `robot`, where it would keep at least as far from everyone as it does now (its smallest gap, at most
    GOAL_STOP_GAP), clear of walls by its radius and in sight of the goal (`world`: a WorldMap; walls only when it
    has obstacles). `people`: records with `pos` (complex) and `radius`."""
    n = people.shape[0]
    if n == 0:
        return False, goal
    own, top = math.inf, 0.0
    for k in range(n):
        own = min(own, abs(people[k].pos - robot) - people[k].radius - robot_radius)
        top = max(top, people[k].radius)
    keep = min(own, GOAL_STOP_GAP) - 1e-9
    reach = robot_radius + top + GOAL_STOP_GAP + GOAL_STOP_SLACK
    limit = min(reach, abs(robot - goal) - NEARER_SPOT)
    if limit < 0:
        return False, goal
    m = int(limit / SPOT_GRID + 1e-9)
    found, spot, best = False, goal, math.inf
    for iy in range(-m, m + 1):
        for ix in range(-m, m + 1):
            c = goal + complex(ix * SPOT_GRID, iy * SPOT_GRID)
            d = abs(c - goal)
            if d > limit + 1e-9 or d >= best:
                continue
            roomy = True
            for k in range(n):
                if abs(people[k].pos - c) - people[k].radius - robot_radius < keep:
                    roomy = False
                    break
            if not roomy:
                continue
            if world.has_obstacles and (clearance_at(world, c) < robot_radius or not line_of_sight(world, goal, c)):
                continue
            found, spot, best = True, c, d
    return found, spot
