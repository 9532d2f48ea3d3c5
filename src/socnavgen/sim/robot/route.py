"""The scenario's route for a robot policy written in Python (the ORCA and DWA baselines, a user's policy):
its current waypoint, the point to head for (the global planner's carrot where the straight line is blocked:
robot.fields, robot.planner.carrot_at, the same plan the built-in robots follow), and the walls near it.

    route = Route(obs)              # in reset(obs)
    target, last = route.target(obs.position_c)

or, for a policy with a top speed and a braking rate toward the goal, subclass RouteFollower and ask
`self.way(obs)` each step (None: it has arrived).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen.sim.robot.fields import field_scale, route_fields
from socnavgen.sim.robot.planner import carrot_at
from socnavgen.sim.robot.policies import OCCUPIED_REACH, SWEPT_MARGIN
from socnavgen.sim.world.queries import path_clear

TOLERANCE = 0.4  # m: an intermediate waypoint this close counts as passed (the waypoints robot's)
RING = (0.0, 0.4, 0.8, 1.2)  # m: rings of points around the robot whose nearest wall points are gathered
RAYS = 16  # points per ring
NOBODY = np.zeros(0, complex)
PATIENCE = 5.0  # s standing face to face with someone standing before it makes way
STILL = 0.1  # m: moving less counts as standing
NEAR = 0.8  # m gap: someone this close holds it
BACK_OFF = 2.0  # m back along its own trail
MAKE_WAY = 4.0  # s making way
TRAIL_STEP = 0.2  # m between the points of its trail
ARRIVED = 0.05  # m from the goal: a RouteFollower stands


class Route:
    """Following the robot's waypoints (read once from `obs`) with the planner's fields."""

    def __init__(self, obs, tolerance: float = TOLERANCE, patience: float = PATIENCE) -> None:  # noqa: ANN001
        self.world, self.radius, self.tolerance, self.patience = obs.world, obs.radius, tolerance, patience
        self._trail: list[tuple[float, complex]] = []  # (t, point) every TRAIL_STEP m it drove, BACK_OFF m back
        self._still: tuple[float, complex] | None = None  # (since when, where) it has stood
        self._retreat_until = -math.inf
        self.waypoints = np.array(obs.waypoints_c, dtype=complex)
        self.index = min(1, len(self.waypoints) - 1)
        self.scale = field_scale(self.world)
        self.fields = route_fields(self.world, self.waypoints, self.radius) if len(self.waypoints) > 1 else None
        angles = np.exp(2j * np.pi * np.arange(RAYS) / RAYS)
        self._ring = np.concatenate([[0j], *[r * angles for r in RING if r > 0]])

    @property
    def goal(self) -> complex:
        return complex(self.waypoints[-1])

    def target(self, p: complex, people: np.ndarray = NOBODY, radii: np.ndarray = NOBODY,
               t: float | None = None) -> tuple[complex, bool]:
        """(the point to head for now, whether the current waypoint is the last), passing waypoints reached,
        and an intermediate waypoint someone stands on (`people`: complex positions, `radii`) once within
        OCCUPIED_REACH of it when the next one is in a clear line (as the built-in robots do). With the time
        `t`: making way (see _making_way), the point it drove by BACK_OFF m ago."""
        last = len(self.waypoints) - 1
        while self.index < last and (abs(self.waypoints[self.index] - p) <= self.tolerance
                                     or self._occupied(p, people, radii)):
            self.index += 1
        if t is not None and self._making_way(p, people, radii, t):
            return self._trail[0][1], False
        waypoint = complex(self.waypoints[self.index])
        if self.fields is None:
            return waypoint, True
        point = carrot_at(self.world.map, self.fields, self.index, waypoint, complex(p), self.radius, self.scale)
        return complex(point), self.index == last

    def _making_way(self, p: complex, people: np.ndarray, radii: np.ndarray, t: float) -> bool:
        """Whether to back off now: it has moved less than STILL m in `patience` s with someone within NEAR
        (gap) who stands too (a doorway where each waits for the other), then it heads back BACK_OFF m along its
        own trail for up to MAKE_WAY s (a recovery as the scripted robot's make way, not the papers')."""
        if t < self._retreat_until:
            return True
        if not self._trail or abs(self._trail[-1][1] - p) > TRAIL_STEP:
            self._trail.append((t, complex(p)))
            while len(self._trail) > 2 and abs(self._trail[1][1] - p) >= BACK_OFF:
                self._trail.pop(0)
        self._still = (t, complex(p)) if self._still is None or abs(self._still[1] - p) > STILL else self._still
        near = len(people) > 0 and bool((np.abs(people - p) - radii - self.radius < NEAR).any())
        if near and t - self._still[0] >= self.patience and abs(self.goal - p) > 1.0 and len(self._trail) > 1:
            self._retreat_until, self._still = t + MAKE_WAY, None
            return True
        return False

    def _occupied(self, p: complex, people: np.ndarray, radii: np.ndarray) -> bool:
        waypoint = self.waypoints[self.index]
        if len(people) == 0 or abs(waypoint - p) > OCCUPIED_REACH:
            return False
        if not (np.abs(people - waypoint) < radii + self.radius + SWEPT_MARGIN).any():
            return False
        return bool(path_clear(self.world.map, complex(p), complex(self.waypoints[self.index + 1]),
                               0.5 * self.radius + 0.05))

    def walls_near(self, p: complex, reach: float) -> np.ndarray:
        """Wall surface points within `reach` of p (complex, deduplicated to the map's cells): the nearest wall
        point of p and of RAYS points on each of the RING circles around it."""
        points, valid = self.world.nearest_obstacles(p + self._ring)
        points = points[valid & (np.abs(points - p) <= reach)]
        if points.size == 0:
            return points
        cells = np.round(points / self.world.map.mpp)
        _, keep = np.unique(np.stack([cells.real, cells.imag], axis=1), axis=0, return_index=True)
        return points[np.sort(keep)]

    def clearance(self, points: np.ndarray) -> np.ndarray:
        """Metres from each point to the nearest wall (0 off the map)."""
        return self.world.clearance_at(points)


class Way(NamedTuple):
    """Where a RouteFollower heads this step."""

    to: complex  # from the robot to the point to head for (Route.target)
    top: float  # the speed it may drive: its max_speed within the body's limit, braking toward the goal
    last: bool  # heading for the last waypoint


class RouteFollower:
    """What the Python baselines (ORCA, DWA) share: the route, made on reset (or on the first step), and each
    step the way to head and how fast. A subclass sets max_speed (m/s) and goal_decel (m/s^2: it brakes at
    this rate to stop at the goal)."""

    max_speed: float
    goal_decel: float
    route: Route | None = None

    def reset(self, obs) -> None:  # noqa: ANN001 - an Observation
        self.route = Route(obs)

    def way(self, obs) -> Way | None:  # noqa: ANN001 - an Observation
        """This step's Way (passing waypoints reached or occupied), None within ARRIVED of the goal."""
        if self.route is None:
            self.reset(obs)
        route, p = self.route, obs.position_c
        target, last = route.target(p, obs.human_positions_c, obs.human_radii, obs.t)
        to = target - p
        if last and abs(route.goal - p) <= ARRIVED:
            return None
        top = min(self.max_speed, obs.limits["max_speed"])
        return Way(to, arrive_speed(top, self.goal_decel, abs(to)) if last else top, last)


def arrive_speed(max_speed: float, decel: float, dist: float) -> float:
    """The speed from which braking at `decel` stops within `dist`, at most max_speed."""
    return min(max_speed, math.sqrt(2.0 * decel * max(dist, 0.0)))
