"""Who holds the robot up: the verifier's side of the ONE "in the robot's way" (proxemics.in_way).

A person holds the robot up when they stand within proxemics.HELD_UP_DISTANCE of it (centres) and inside the
corridor its body sweeps (proxemics.in_way, WAY_MARGIN_VERIFY) along one of the ways it may be going:
- its body's heading;
- its route's leg (the waypoints' straight line), up to that leg's turn;
- its route just ahead, round bends (route.ahead_on_route);
- its planned way: toward the point a planning robot steers for on its way to the waypoint it heads for
  (sim.robot.planner.carrot_at on the route's cost-to-go fields, sim.robot.fields), the way round walls that
  the straight leg cuts through. The built-in robots stop for someone in their swept path along exactly this
  direction (sim.robot.policies.look_ahead, WAY_MARGIN_DRIVE <= WAY_MARGIN_VERIFY), so a robot that waits for
  a person is never judged to stand "with its way clear" (issue 26: home_10's robot waited 22 s before friends
  who had stopped below the bedroom door, its route's leg to the door cutting through the jamb, and the verifier
  blamed the simulator for idling).
The planned way needs the run's map; without one (a bare trace) the other three ways are all.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from socnavgen import proxemics
from socnavgen.sim.trace import YAW, Trace
from socnavgen.verify.route import ahead_on_route, leg_left

WAYPOINT_REACH = 0.4  # m: a waypoint this near along the route counts as reached (the built-in robots' tolerance,
# sim.robot.api's waypoint_tolerance): the robot heads for the next one


class _Signals(Protocol):  # what of verify.signals.Signals this reads (it imports this module)
    trace: Trace

    def distances(self) -> np.ndarray: ...
    def route(self) -> tuple[np.ndarray, np.ndarray]: ...
    def need_world(self, what: str) -> object: ...


def heading_to(waypoints: list[tuple[float, float]], progress: np.ndarray) -> np.ndarray:
    """(N,) index of the waypoint the robot heads for at each route progress: the end of the leg it is on, the
    next one once within WAYPOINT_REACH of that end (the last waypoint at most)."""
    pts = np.asarray(waypoints, dtype=float).reshape(-1, 2)
    ends = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    at = np.searchsorted(ends, np.asarray(progress, dtype=float) + WAYPOINT_REACH, side="right")
    return np.clip(at, 1, len(pts) - 1)


def planned_directions(world: object, robot_xy: np.ndarray, waypoints: list[tuple[float, float]],
                       progress: np.ndarray, radius: float) -> np.ndarray:
    """(N, 2) unit direction from each robot position toward the point a planning robot of `radius` steers for
    on its way to the waypoint it heads for (heading_to); zeros at the waypoint itself. Where the straight line to
    that waypoint keeps the planner's clearance it is that line (planner.carrot_at's own first test), so the
    cost-to-go field (a search over the whole map) is worked out only for waypoints the robot cannot see clear, once
    per World (memo.kept)."""
    from socnavgen.memo import kept
    from socnavgen.sim.robot.fields import cost_to_go, field_scale
    from socnavgen.sim.robot.planner import LINE_CLEAR, carrot_at
    from socnavgen.sim.world.queries import clearance_at, path_clear

    pts = np.asarray(waypoints, dtype=float).reshape(-1, 2)
    out = np.zeros((len(robot_xy), 2))
    if len(pts) < 2 or not len(robot_xy):
        return out
    wps = pts[:, 0] + 1j * pts[:, 1]
    grid = world.map  # type: ignore[attr-defined]
    here = robot_xy[:, 0] + 1j * robot_xy[:, 1]
    target = heading_to(waypoints, progress)
    carrots = wps[target].copy()
    bent = [n for n in range(len(here))
            if not path_clear(grid, here[n], wps[target[n]], min(LINE_CLEAR * radius, clearance_at(grid, here[n])))]
    if bent:
        needed = sorted({int(target[n]) for n in bent})
        first = kept(world, "verify_field", lambda: cost_to_go(world, wps[needed[0]], radius),  # type: ignore[arg-type]
                     (complex(wps[needed[0]]), round(radius, 4)))
        fields = np.full((len(wps), *first.shape), np.inf, np.float32)
        for k in needed:
            fields[k] = kept(world, "verify_field", lambda k=k: cost_to_go(world, wps[k], radius),  # type: ignore[arg-type,misc]
                             (complex(wps[k]), round(radius, 4)))
        scale = field_scale(world)  # type: ignore[arg-type]
        for n in bent:
            k = int(target[n])
            carrots[n] = carrot_at(grid, fields, k, wps[k], here[n], radius, scale)
    to = carrots - here
    length = np.abs(to)
    moving = length > 1e-9
    out[moving, 0] = to[moving].real / length[moving]
    out[moving, 1] = to[moving].imag / length[moving]
    return out


def holding_up(s: _Signals) -> np.ndarray:
    """(T, H) bool: where each human holds the robot up (the module's docstring). The way is only worked out for
    the (step, human) pairs within HELD_UP_DISTANCE."""
    trace = s.trace
    close = s.distances() <= proxemics.HELD_UP_DISTANCE
    out = np.zeros(close.shape, dtype=bool)
    if not close.any():
        return out
    k, i = np.nonzero(close)
    rx, ry, yaw = trace.robot[k, 0], trace.robot[k, 1], trace.robot[k, YAW]
    px, py = trace.humans[k, i, 0], trace.humans[k, i, 1]
    robot_radius = float(trace.robot_radius)
    radius = np.asarray(trace.human_radii, dtype=float)[i]
    progress, tangents = s.route()
    waypoints = list(trace.robot_waypoints)

    def way(hx: np.ndarray, hy: np.ndarray) -> np.ndarray:
        return proxemics.in_way(rx, ry, hx, hy, px, py, robot_radius, radius, proxemics.WAY_MARGIN_VERIFY)

    tx, ty = tangents[k, 0], tangents[k, 1]
    half = robot_radius + radius + proxemics.WAY_MARGIN_VERIFY
    leg = leg_left(progress, waypoints)[k]  # route direction: up to its next turn
    on_leg = (px - rx) * tx + (py - ry) * ty <= leg + robot_radius + radius  # (hospital_04)
    held = way(np.cos(yaw), np.sin(yaw)) | (way(tx, ty) & ((tx != 0) | (ty != 0)) & on_leg) | ahead_on_route(
        progress[k], np.stack([px, py], 1), waypoints, half, proxemics.HELD_UP_DISTANCE, robot_radius)
    if len(waypoints) >= 2:
        try:
            world = s.need_world("the robot's planned way")
        except ValueError:  # a bare trace: no map, no planned way
            world = None
        if world is not None:
            steps = np.unique(k)
            planned = np.zeros((trace.steps, 2))
            planned[steps] = planned_directions(world, trace.robot[steps, :2], waypoints, progress[steps],
                                                robot_radius)
            hx, hy = planned[k, 0], planned[k, 1]
            held |= way(hx, hy) & ((hx != 0) | (hy != 0))
    out[k, i] = held
    return out
