"""ORCA, Optimal Reciprocal Collision Avoidance (van den Berg, Guy, Lin, Manocha, "Reciprocal n-body
collision avoidance", Robotics Research, ISRR 2009 / STAR 70, Springer 2011): `--robot orca`.

Our own implementation of the paper's sections 4 (ORCA for two agents) and 5 (n agents, static obstacles,
linear programming), written for this simulator (no RVO2 code; tested against RVO2 through the `pyrvo`
bindings: the same velocity within float32 precision on random crowds). Every step each neighbour B (a
person, or a wall point within reach) gives a half-plane of permitted velocities

    ORCA_{A|B}^tau = { v | (v - (v_A^opt + c u)) . n >= 0 }                                  (paper, section 4)

where u is the vector from the relative velocity v_A^opt - v_B^opt to the closest point on the boundary of
the truncated velocity obstacle VO_{A|B}^tau (a cone cut off by the disc of radius (r_A + r_B) / tau around
(p_B - p_A) / tau), n its outward normal, and c the share of the avoidance A takes on: 1/2 toward another
agent (reciprocity); 1 toward a wall point, which never moves (static obstacles, section 5, with `tau_obst`).
Bodies already overlapping use the velocity obstacle of one time step (v_opt = the current velocity). The new
velocity is the one closest to the preferred velocity inside every half-plane and the disc of max speed,
found with the paper's randomised incremental 2-D linear program (section 5, after Seidel and de Berg et
al.); when the half-planes leave nothing, the velocity that violates them least (the paper's 3-D program for
densely packed conditions).

The preferred velocity points (turned BIAS to the right, to break symmetric deadlocks) at the route's current
target (robot.route: the waypoint, or the global planner's carrot where the line to it is blocked) at the
robot's max speed, slowing down for the goal. People are not ORCA agents here: they are treated as
reciprocating (c = 1/2, as the paper's experiments and the usual ORCA baselines do; `responsibility` sets
it). On a differential-drive body the velocity is tracked by the body (robot.body: it turns toward it), as
ORCA's holonomic velocity usually is on a wheeled robot.
"""

from __future__ import annotations

import math

from socnavgen.sim.robot.api import RobotAction
from socnavgen.sim.robot.route import Route, RouteFollower

EPS = 1e-9
WALL_SLACK = 0.01  # m: already within the safety margin of a wall point, it keeps this much of the gap it has
BIAS = complex(math.cos(0.1), -math.sin(0.1))  # the preferred velocity turned 0.1 rad clockwise: symmetric
# head-on meetings (a person standing dead ahead) otherwise leave ORCA stuck, the paper's examples perturb it


def _det(a: complex, b: complex) -> float:
    return a.real * b.imag - a.imag * b.real


def _dot(a: complex, b: complex) -> float:
    return a.real * b.real + a.imag * b.imag


def half_plane(rel_pos: complex, rel_vel: complex, radius: float, tau: float, dt: float) -> tuple[complex, complex]:
    """(u, direction) of the velocity obstacle of a neighbour at `rel_pos` moving at minus `rel_vel` relative to
    us, combined `radius`: u the smallest change of the relative velocity out of VO^tau (section 4), the
    half-plane's boundary line running along `direction` (permitted: to its left)."""
    dist_sq = abs(rel_pos) ** 2
    r_sq = radius * radius
    if dist_sq > r_sq:
        w = rel_vel - rel_pos / tau  # from the cut-off disc's centre to the relative velocity
        w_sq = abs(w) ** 2
        dot1 = _dot(w, rel_pos)
        if dot1 < 0.0 and dot1 * dot1 > r_sq * w_sq:  # nearest boundary: the cut-off disc
            w_len = math.sqrt(w_sq)
            unit = w / w_len
            return (radius / tau - w_len) * unit, complex(unit.imag, -unit.real)
        leg = math.sqrt(dist_sq - r_sq)  # nearest boundary: one of the cone's legs
        if _det(rel_pos, w) > 0.0:  # the left leg
            direction = complex(rel_pos.real * leg - rel_pos.imag * radius,
                                rel_pos.real * radius + rel_pos.imag * leg) / dist_sq
        else:  # the right leg
            direction = -complex(rel_pos.real * leg + rel_pos.imag * radius,
                                 -rel_pos.real * radius + rel_pos.imag * leg) / dist_sq
        return _dot(rel_vel, direction) * direction - rel_vel, direction
    w = rel_vel - rel_pos / dt  # overlapping: the velocity obstacle of one time step
    w_len = max(abs(w), EPS)
    unit = w / w_len
    return (radius / dt - w_len) * unit, complex(unit.imag, -unit.real)


def _lp1(lines: list[tuple[complex, complex]], k: int, radius: float, opt: complex, direction_opt: bool,
         ) -> complex | None:
    """The best point on line k that keeps lines[:k] and the disc of `radius` (None: none)."""
    point, d = lines[k]
    dot = _dot(point, d)
    disc = dot * dot + radius * radius - abs(point) ** 2
    if disc < 0.0:
        return None
    root = math.sqrt(disc)
    left, right = -dot - root, -dot + root
    for i in range(k):
        p_i, d_i = lines[i]
        denominator = _det(d, d_i)
        numerator = _det(d_i, point - p_i)
        if abs(denominator) <= EPS:
            if numerator < 0.0:
                return None
            continue
        t = numerator / denominator
        if denominator >= 0.0:
            right = min(right, t)
        else:
            left = max(left, t)
        if left > right:
            return None
    if direction_opt:
        t = right if _dot(opt, d) > 0.0 else left
    else:
        t = min(max(_dot(d, opt - point), left), right)
    return point + t * d


def solve(lines: list[tuple[complex, complex]], radius: float, opt: complex, direction_opt: bool = False,
          ) -> tuple[int, complex]:
    """(number of lines kept, velocity): the velocity nearest `opt` keeping every half-plane (left of each
    (point, direction) line) and |v| <= radius (the paper's 2-D program, section 5). Fewer lines kept than given:
    the first one it failed on."""
    if direction_opt:
        result = opt * radius
    elif abs(opt) > radius:
        result = opt / abs(opt) * radius
    else:
        result = opt
    for k, (point, d) in enumerate(lines):
        if _det(d, point - result) > 0.0:  # result is on the wrong side of line k
            found = _lp1(lines, k, radius, opt, direction_opt)
            if found is None:
                return k, result
            result = found
    return len(lines), result


def least_violation(lines: list[tuple[complex, complex]], walls: int, start: int, radius: float,
                    result: complex) -> complex:
    """No velocity keeps every half-plane: the one that moves least into the people's half-planes, keeping
    the first `walls` (the walls', which never give way) - the paper's 3-D program (section 5), projected to 2-D."""
    distance = 0.0
    for i in range(start, len(lines)):
        point, d = lines[i]
        if _det(d, point - result) <= distance:
            continue
        projected = list(lines[:walls])
        for j in range(walls, i):
            p_j, d_j = lines[j]
            determinant = _det(d, d_j)
            if abs(determinant) <= EPS:
                if _dot(d, d_j) > 0.0:
                    continue
                p = 0.5 * (point + p_j)
            else:
                p = point + (_det(d_j, point - p_j) / determinant) * d
            projected.append((p, (d_j - d) / max(abs(d_j - d), EPS)))
        kept, candidate = solve(projected, radius, complex(-d.imag, d.real), True)
        if kept == len(projected):
            result = candidate
        distance = _det(d, point - result)
    return result


class ORCAPolicy(RouteFollower):
    """`--robot orca`: ORCA toward the route's target (see the module's docstring). Parameters (a campaign's
    `params:`): max_speed (m/s), tau (s: the time horizon toward people), tau_obst (s: toward walls),
    neighbour_dist (m: people farther are not looked at), wall_reach (m: wall points within this are
    obstacles), safety (m added to the radii), responsibility (share of the avoidance toward people)."""

    def __init__(self, max_speed: float = 0.6, tau: float = 3.0, tau_obst: float = 1.0, neighbour_dist: float = 5.0,
                 wall_reach: float = 1.2, safety: float = 0.1, responsibility: float = 0.5,
                 goal_decel: float = 0.8) -> None:
        self.max_speed, self.tau, self.tau_obst = float(max_speed), float(tau), float(tau_obst)
        self.neighbour_dist, self.wall_reach, self.safety = float(neighbour_dist), float(wall_reach), float(safety)
        self.responsibility, self.goal_decel = float(responsibility), float(goal_decel)
        self.route: Route | None = None

    def act(self, obs) -> RobotAction:  # noqa: ANN001 - an Observation
        way = self.way(obs)
        if way is None:
            return RobotAction(0.0, 0.0)
        assert self.route is not None  # way() made it
        p, v, speed = obs.position_c, obs.velocity_c, way.top
        preferred = way.to / max(abs(way.to), EPS) * speed * BIAS  # a hair to the right: no deadlock dead ahead
        lines, walls = self._walls(obs, self.route, p, v)
        lines += self._people(obs, p, v)
        kept, result = solve(lines, speed, preferred)
        if kept < len(lines):
            result = least_violation(lines, walls, kept, speed, result)
        return RobotAction(result.real, result.imag)

    def _walls(self, obs, route: Route, p: complex, v: complex) -> tuple[list, int]:  # noqa: ANN001
        """The half-planes of the wall points near the robot (c = 1: a wall does not move), nearest first."""
        points = route.walls_near(p, self.wall_reach + obs.radius)
        lines = []
        for q in sorted(points, key=lambda q: abs(q - p)):
            # the safety margin shrinks to what is left where the robot is already nearer the wall than it (a
            # passage barely wider than the robot): it may drive along or away from the wall, not closer
            reach = max(obs.radius, min(obs.radius + 0.5 * self.safety, abs(q - p) - WALL_SLACK))
            u, d = half_plane(q - p, v, reach, self.tau_obst, obs.dt)
            lines.append((v + u, d))
        return lines, len(lines)

    def _people(self, obs, p: complex, v: complex) -> list:  # noqa: ANN001
        """The half-planes of the people within neighbour_dist, nearest first (c = responsibility)."""
        near = []
        for q, w, r in zip(obs.human_positions_c, obs.human_velocities_c, obs.human_radii, strict=True):
            if abs(q - p) - r <= self.neighbour_dist:
                near.append((abs(q - p), complex(q), complex(w), float(r)))
        lines = []
        for _, q, w, r in sorted(near, key=lambda item: item[0]):
            u, d = half_plane(q - p, v - w, obs.radius + r + self.safety, self.tau, obs.dt)
            lines.append((v + self.responsibility * u, d))
        return lines
