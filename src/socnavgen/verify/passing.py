"""Giving way lets the robot through: a step aside counts only if the person stays out of the robot's way until
the robot has got past them (issue 25, hospital_08 of the new-request suite: three nurses stepped aside after
EXCUSE ME and closed up again round the robot while it was still in the gap; it had to back out and go round
them, and every give-way criterion passed on the step aside).

- back in the way: the person is again on the robot's route just ahead of it, in the corridor its body sweeps
  (route.ahead_on_route, within proxemics.HELD_UP_DISTANCE along it); without a route, ahead along its heading
  within that distance. The robot turning toward someone standing aside does not put them back in its way;
- past: the robot has come at least as far along its route as the person (without a route: the person is no
  longer ahead of the robot along its heading).

A step aside at step k is kept when, after k, the robot gets past the person before the person is back in its
way (or the person is never back in its way).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from socnavgen import proxemics
from socnavgen.sim.trace import YAW
from socnavgen.verify.route import ahead_on_route, route_progress

Signals = Any  # a verify.signals.Signals (which calls in here: importing it back would make a cycle)


def _next(mask: np.ndarray) -> np.ndarray:
    """(T,) for each step the first step at or after it where `mask` holds (T when none)."""
    n = len(mask)
    idx = np.where(mask, np.arange(n), n)
    return np.minimum.accumulate(idx[::-1])[::-1] if n else idx


def got_past(s: Signals, human: str) -> np.ndarray:
    """(T,) bool: the robot is level with or past `human` (along its route; else along its heading)."""
    p = s.pos(human)
    points = list(s.trace.robot_waypoints)
    if len(points) >= 2:
        return route_progress(p, points)[0] <= s.route()[0]
    rel = p - s.pos("robot")
    yaw = s.trace.robot[:, YAW]
    return rel[:, 0] * np.cos(yaw) + rel[:, 1] * np.sin(yaw) <= 0.0


def back_in_way(s: Signals, human: str) -> np.ndarray:
    """(T,) bool: `human` is on the robot's route just ahead of it (module doc)."""
    i = s.human(human)
    points = list(s.trace.robot_waypoints)
    if len(points) < 2:
        return s.in_way(i) & (s.distances()[:, i] <= proxemics.HELD_UP_DISTANCE)
    half = float(s.trace.robot_radius) + float(np.asarray(s.trace.human_radii, dtype=float)[i]) \
        + proxemics.WAY_MARGIN_VERIFY
    return ahead_on_route(s.route()[0], s.pos(human), points, half, proxemics.HELD_UP_DISTANCE,
                          float(s.trace.robot_radius))


def kept_aside(s: Signals, human: str, stepped: np.ndarray) -> np.ndarray:
    """`stepped` (signals.aside) on the steps after which the person stays out of the robot's way until it has got
    past them (module doc)."""
    stepped = np.asarray(stepped, dtype=bool)
    if not stepped.any():
        return stepped
    back = back_in_way(s, human)
    n = len(stepped)
    after = np.minimum(np.arange(n) + 1, n - 1)
    next_back, next_past = _next(back)[after], _next(got_past(s, human))[after]
    last = np.arange(n) == n - 1
    return stepped & (last | (next_back >= n) | (next_past < next_back))


def undone(s: Signals, human: str, stepped: np.ndarray) -> tuple[float, float] | None:
    """(when it first stepped aside, when it was back in the robot's way before it got past) for a person whose
    every step aside was undone, else None."""
    stepped = np.asarray(stepped, dtype=bool)
    if not stepped.any() or kept_aside(s, human, stepped).any():
        return None
    k = int(np.flatnonzero(stepped)[0])
    back = np.flatnonzero(back_in_way(s, human)[k:])
    return float(s.t[k]), float(s.t[k + int(back[0])]) if len(back) else float(s.t[-1])
