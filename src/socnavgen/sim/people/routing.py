"""Where a walking person heads this step, and how far they are from their target along the walkable way.

A leaf's walk command names a target and how to find the way there (`route`, people.state): straight at a
point (a side step), to the person's goal, to the robot, or to another person. The person heads straight at
the target when their body fits along the straight line; otherwise down the route field (world.routes) of a
landmark: their goal's, for the robot the nearer of the waypoints the robot is between, for another person
that person's goal. So people pass doorways and corners, and a follower walks around the wall between
them and the robot instead of into it. The decision is kept for ROUTE_EVERY steps while the target stays
where it was.

After every tree has ticked, `plan` gives each walker the point they head for and lets them steer around
the robot (people.avoid).
"""

from __future__ import annotations

import math

import numpy as np

from socnavgen.sim.jit import jit
from socnavgen.sim.people.avoid import steer_around_robot
from socnavgen.sim.people.spots import aim, passes_by
from socnavgen.sim.people.state import ROUTE_GOAL, ROUTE_ROBOT, ROUTE_STRAIGHT, pop_goal
from socnavgen.sim.world.routes import downhill, effort, field_of, walkable_straight

STRAIGHT_CLEARANCE = 0.35  # m: a straight way is walkable when it keeps this clearance (a 0.4 m body, 5 cm slack)
NEAR_TARGET = 0.5  # m: the last stretch before the target is not checked (a goal drawn near a wall)
ROUTE_EVERY = 4  # steps a decision is kept while the target stays put
TARGET_MOVED = 0.25  # m: a target that moved this far is looked at again
TIE = 1e-9


@jit
def project(p, a, b):  # noqa: ANN001, ANN201
    """(distance along the segment a->b of p's closest point, distance from p to it)."""
    ab = b - a
    length = abs(ab)
    unit = ab / length if length > 1e-9 else 0j
    along = min(max(((p - a) * unit.conjugate()).real, 0.0), length)
    return along, abs(p - (a + unit * along))


@jit
def robot_progress(s):  # noqa: ANN001, ANN201
    """(arc length, segment) of the robot's projection on its waypoint path, searched from the segment found
    last (a path may come back past the same place); computed once per step."""
    robot, wps = s.robot[0], s.waypoints
    if robot.progress_step == s.clock[0].step:
        return robot.progress, robot.progress_segment
    value, seg = 0.0, 0
    if wps.shape[0] >= 2:
        nearest = np.inf
        for j in range(robot.search_from, wps.shape[0] - 1):
            nearest = min(nearest, project(robot.pos, wps[j], wps[j + 1])[1])
        for j in range(robot.search_from, wps.shape[0] - 1):  # the first segment as near as the nearest
            along, dist = project(robot.pos, wps[j], wps[j + 1])
            if dist <= nearest + TIE:
                seg, value = j, s.offsets[j] + along
                break
        robot.search_from = seg
    robot.progress_step, robot.progress, robot.progress_segment = s.clock[0].step, value, seg
    return value, seg


@jit
def goal_mark(s, i):  # noqa: ANN001, ANN201
    """The landmark of person i's current goal (-1: it has none), looked up once per goal."""
    p = s.people[i]
    if not p.has_goal:
        return -1
    if p.goal_mark < 0 or p.goal_mark_of != p.goal:
        p.goal_mark, p.goal_mark_of = -1, p.goal
        points = s.routes.points
        for m in range(points.shape[0]):
            if points[m] == p.goal:
                p.goal_mark = m
                break
    return p.goal_mark


@jit
def consider(s, i, target, mark, best, best_mark):  # noqa: ANN001, ANN201
    """(effort, landmark) of the better of the best so far and going by `mark`'s field then straight on."""
    slot = field_of(s.routes, mark)
    if slot < 0:
        return best, best_mark
    value = effort(s.world, s.routes, slot, s.people[i].pos) + abs(target - s.routes.points[mark])
    return (value, mark) if value < best else (best, best_mark)


@jit
def decide(s, i, target, route):  # noqa: ANN001, ANN201
    """Straight at the target, or by which landmark's field (p.via_mark) and toward which point (p.via)."""
    p, step = s.people[i], s.clock[0].step
    p.via_for, p.via_until, p.via_mark, p.via = target, step + ROUTE_EVERY, -1, target
    if route == ROUTE_STRAIGHT or walkable_straight(s.world, p.pos, target, STRAIGHT_CLEARANCE, NEAR_TARGET):
        return
    best, mark = np.inf, -1
    if route == ROUTE_GOAL:
        best, mark = consider(s, i, target, goal_mark(s, i), best, mark)
    elif route == ROUTE_ROBOT:
        marks = s.routes.waypoint_marks
        _, seg = robot_progress(s)
        for k in range(seg, min(seg + 2, marks.shape[0])):
            best, mark = consider(s, i, target, marks[k], best, mark)
    elif 0 <= route < s.people.shape[0]:
        best, mark = consider(s, i, target, goal_mark(s, route), best, mark)
    if mark < 0 or not math.isfinite(best):
        p.via_until = step + 1  # its field comes before the next step: look again then
        return
    p.via_mark = mark
    p.via = downhill(s.world, s.routes, s.routes.slot_of[mark], p.pos, STRAIGHT_CLEARANCE)


@jit
def head(s, i, target, route):  # noqa: ANN001, ANN201
    """(the point person i heads for, their distance to `target` along the walkable way) this step."""
    p = s.people[i]
    if not (p.via_until > s.clock[0].step and abs(target - p.via_for) < TARGET_MOVED):
        decide(s, i, target, route)
    p.via_step = s.clock[0].step
    mark = p.via_mark
    slot = s.routes.slot_of[mark] if mark >= 0 else -1
    if slot < 0:
        p.via = target
        return target, abs(target - p.pos)
    return p.via, effort(s.world, s.routes, slot, p.pos) + abs(target - s.routes.points[mark])


@jit
def plan(s):  # noqa: ANN001, ANN201
    """Every walker's heading point this step (unless a leaf worked it out already), then steering around the
    robot. A point on a walker's way that the robot stands on is passed by (people.spots.passes_by)."""
    step = s.clock[0].step
    for i in range(s.people.shape[0]):
        p = s.people[i]
        if not p.walks:
            continue
        if p.to_goal and passes_by(s, i):  # a point on their way the robot stands on: on to the next goal
            pop_goal(s.people, s.goals, i, False)
        if p.via_step != step:
            head(s, i, aim(s, i) if p.to_goal else p.target, p.route)
        steer_around_robot(s, i)
