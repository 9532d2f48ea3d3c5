"""Metrics a social-navigation paper reports and HuNavSim's evaluator does not: honest path efficiency (against
the shortest WALKABLE path, not the straight line through walls), time to goal counted only where the robot
succeeded, comfort (jerk), the time-to-collision distribution, and the seconds spent in people's intimate and
personal space. Every one on every step of the trace (no sampling). Units, formulas and readable names:
sim/metric_definitions.py (the one table); the formulas are the code below.

The shortest walkable path is the robot's route (its start, then each waypoint in order, an intermediate one
passed within 0.4 m) the shortest way a disc of the robot's radius fits through (sim/world/walkable.py: geodesic
fields, pulled taut); computed once per route and World, so a campaign pays for it once per scenario and worker.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from socnavgen.bodies import INTIMATE_SPACE, PERSONAL_SPACE
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.trace import VX, VY, Trace, X, Y

# Time-to-collision bins (s): the time the robot spends with its smallest TTC in [edge_k, edge_k+1); the last
# bin also holds the steps where nobody is on a collision course (TTC infinite).
TTC_EDGES = (0.0, 0.5, 1.0, 2.0, 3.0, 5.0, math.inf)
WAYPOINT_SLACK = 0.4  # m: an intermediate waypoint counts as passed this close (the waypoints robot's tolerance)
TTC_CRITICAL = 1.0  # s: `ttc_under_1s` counts the time with a contact less than this far ahead
# m/s: the robot's own speed toward someone above which it is closing in on them (below: standing, creeping
# sideways, or edging off; a person walking up to a robot that stands is not the robot intruding)
CLOSING_SPEED = 0.05
SOCIAL_METRICS = ("reached_goal", "time_to_goal", "walkable_path_efficiency", "route_length_walkable",
                  "mean_jerk", "intimate_space_seconds", "intimate_approach_seconds", "personal_space_seconds",
                  "ttc_under_1s", "ttc_seconds")


def step_durations(t: np.ndarray) -> np.ndarray:
    """Seconds each step stands for: t[k+1] - t[k] (the last step, the end state, counts 0)."""
    t = np.asarray(t, dtype=float)
    return np.append(np.diff(t), 0.0) if len(t) else t


def goal_radius(trace: Trace) -> float:
    from socnavgen.sim.metrics import SUCCESS_GOAL_RADIUS

    return float(trace.meta.get("robot_goal_radius", SUCCESS_GOAL_RADIUS)) if isinstance(trace.meta, dict) \
        else SUCCESS_GOAL_RADIUS


def arrival_step(trace: Trace, world: Any = None) -> int | None:
    """The first step the robot is within the goal radius of its goal, or stands short of it at a social
    distance from someone standing there whom it sees (`world`: its walls; sim.arrival; None: never)."""
    from socnavgen.sim.arrival import short_of_goal_steps
    from socnavgen.sim.metrics import robot_goals

    goals = robot_goals(trace)
    if not goals or trace.steps == 0:
        return None
    gx, gy = goals[-1]
    near = np.hypot(trace.robot[:, X] - gx, trace.robot[:, Y] - gy) <= goal_radius(trace)
    near |= short_of_goal_steps(trace, goals[-1], world)
    return int(np.argmax(near)) if near.any() else None


def arrival_row(trace: Trace) -> int:
    """The row the simulator saw the robot arrive at in a run that went on for its followers (meta robot_arrived,
    s; people.grace); the trace's length when it did not go on."""
    arrived = trace.meta.get("robot_arrived") if isinstance(trace.meta, dict) else None
    if not isinstance(arrived, int | float) or trace.steps == 0:
        return trace.steps
    return min(int(np.searchsorted(np.asarray(trace.t, dtype=float) - float(trace.t[0]), float(arrived) - 1e-6)),
               trace.steps)


def closest_gaps(gaps: np.ndarray) -> np.ndarray:
    """(T,) smallest robot-person surface gap per step from contact.trace_gaps' (T, H) (inf without people)."""
    return gaps.min(axis=1) if gaps.shape[1] else np.full(gaps.shape[0], math.inf)


def robot_closing_in(trace: Trace, gaps: np.ndarray, gap: float = INTIMATE_SPACE) -> np.ndarray:
    """(T,) True where the robot itself moves toward someone whose gap to it (`gaps`: contact.trace_gaps) is under
    `gap`: its own velocity's component along the line to them exceeds CLOSING_SPEED. The robot's share of an
    intrusion: time in someone's intimate space that people made by walking up to a robot that stood (a handover,
    a crowd round it) is not."""
    if not trace.humans.shape[1]:
        return np.zeros(trace.steps, dtype=bool)
    dx = trace.humans[:, :, X] - trace.robot[:, None, X]
    dy = trace.humans[:, :, Y] - trace.robot[:, None, Y]
    with np.errstate(invalid="ignore", divide="ignore"):
        toward = (trace.robot[:, None, VX] * dx + trace.robot[:, None, VY] * dy) / np.hypot(dx, dy)
    return ((gaps < gap) & (np.nan_to_num(toward, nan=0.0) > CLOSING_SPEED)).any(axis=1)


def smallest_ttc(trace: Trace) -> np.ndarray:
    """(T,) smallest constant-velocity time to robot-person contact per step (0 in contact, inf: nobody on a
    collision course)."""
    from socnavgen.sim.metrics import time_to_collision

    if not trace.humans.shape[1]:
        return np.full(trace.steps, math.inf)
    rel_pos = trace.humans[:, :, [X, Y]] - trace.robot[:, None, [X, Y]]
    rel_vel = trace.humans[:, :, [VX, VY]] - trace.robot[:, None, [VX, VY]]
    radii = float(trace.robot_radius) + np.asarray(trace.human_radii, dtype=float)
    return time_to_collision(rel_pos, rel_vel, radii[None, :]).min(axis=1)


def ttc_histogram(ttc: np.ndarray, durations: np.ndarray) -> list[float]:
    """Seconds spent in each TTC_EDGES bin (the last bin holds the infinite ones)."""
    edges = np.array(TTC_EDGES[:-1])
    bins = np.clip(np.searchsorted(edges, ttc, side="right") - 1, 0, len(edges) - 1)
    return [float(v) for v in np.bincount(bins, weights=durations, minlength=len(edges))]


def mean_jerk(trace: Trace, end: int | None = None) -> float | None:
    """Mean magnitude of the robot's jerk (m/s^3): the velocity vector differentiated twice per step (steps before
    `end`; None: all)."""
    t = np.asarray(trace.t, dtype=float)[:end]
    if len(t) < 3:
        return None
    v = (trace.robot[:, VX] + 1j * trace.robot[:, VY])[:end]
    dt = np.diff(t)
    ok = dt > 0
    acc = np.diff(v)[ok] / dt[ok]
    mid = (t[1:][ok] + t[:-1][ok]) / 2
    dt2 = np.diff(mid)
    if not len(dt2) or not (dt2 > 0).all():
        return None
    return float(np.abs(np.diff(acc) / dt2).mean())


def route_reference(trace: Trace, world: Any) -> float | None:
    """Metres of the shortest walkable path along the robot's route (its start, then each waypoint in order,
    an intermediate one passed within WAYPOINT_SLACK), for a body of the robot's radius; a route no such body
    can walk is measured for a point instead (a squeeze the map still allows); None when no way joins two
    waypoints at all."""
    from socnavgen.sim.world.walkable import WalkableDistance

    if world is None or trace.steps == 0:
        return None
    route = [complex(trace.robot[0, X], trace.robot[0, Y]), *(complex(*w) for w in trace.robot_waypoints[1:])]
    if len(route) < 2:
        return None
    length = WalkableDistance.of(world, float(trace.robot_radius)).route_length(route, WAYPOINT_SLACK)
    if not math.isfinite(length):
        length = WalkableDistance.of(world).route_length(route, WAYPOINT_SLACK)
    return length if math.isfinite(length) else None


def social_metrics(trace: Trace, world: Any = None, *, success: bool | None = None) -> dict[str, Any]:
    """The metrics of SOCIAL_METRICS for one trace. `world` (a sim World) is needed for the walkable path
    efficiency (None without it); `success` (the row's success: goal reached without contact) decides whether
    `time_to_goal` counts: it is None for every episode that is not a success."""
    out: dict[str, Any] = dict.fromkeys(SOCIAL_METRICS)
    if trace.steps == 0:
        return out
    durations = step_durations(trace.t)
    arrived = arrival_step(trace, world)
    cut = arrival_row(trace)  # the robot's episode ends as it arrives: after it, its followers come in (people.grace)
    durations[cut:] = 0.0
    out["reached_goal"] = arrived is not None
    if arrived is not None and success is not False:
        out["time_to_goal"] = float(trace.t[arrived] - trace.t[0])
    xy = trace.robot[:, X] + 1j * trace.robot[:, Y]
    end = (arrived + 1) if arrived is not None else trace.steps
    length = float(np.abs(np.diff(xy[:end])).sum())
    reference = route_reference(trace, world)
    out["route_length_walkable"] = reference
    if arrived is not None and reference is not None and length > 1e-9:
        out["walkable_path_efficiency"] = min(1.0, reference / length)
    out["mean_jerk"] = mean_jerk(trace, cut + 1 if cut < trace.steps else None)
    pair_gaps = trace_gaps(trace)
    gaps = closest_gaps(pair_gaps)
    out["intimate_space_seconds"] = float(durations[gaps < INTIMATE_SPACE].sum())
    out["intimate_approach_seconds"] = float(durations[robot_closing_in(trace, pair_gaps)].sum())
    out["personal_space_seconds"] = float(durations[(gaps >= INTIMATE_SPACE) & (gaps < PERSONAL_SPACE)].sum())
    ttc = smallest_ttc(trace)
    out["ttc_under_1s"] = float(durations[ttc < TTC_CRITICAL].sum())
    out["ttc_seconds"] = ttc_histogram(ttc, durations)
    return out
