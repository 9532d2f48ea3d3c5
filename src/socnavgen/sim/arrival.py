"""Arriving short of a goal someone stands at, on a whole trace: proxemics.short_of_goal at every step (the
rule the simulator ends a run by), for the metrics (success, reached_goal, time_to_goal) and the verifier's
`short_of_goal` signal - one rule, one implementation."""

from __future__ import annotations

from typing import Any

import numpy as np

from socnavgen import proxemics
from socnavgen.sim.trace import VX, VY, Trace, X, Y


def short_of_goal_steps(trace: Trace, goal: tuple[float, float] | None = None, world: Any = None) -> np.ndarray:
    """(T,) bool: the robot stands short of its goal (`goal`, default its last waypoint) at a social distance
    from someone standing on or next to it whom it sees (`world`: its walls; None: no walls known), as
    proxemics.short_of_goal says, and stood so for proxemics.GOAL_STOP_DWELL or until the run ended (as the
    simulator ends a run): a robot pausing there for a moment and driving off again has not arrived; and only where
    the people there leave no nearer free spot (no_nearer_spot)."""
    out = np.zeros(trace.steps, dtype=bool)
    goal = goal if goal is not None else trace.robot_goal
    if goal is None or trace.steps == 0 or trace.humans.shape[1] == 0:
        return out
    robot = trace.robot[:, X] + 1j * trace.robot[:, Y]
    target = complex(goal[0], goal[1])
    robot_to_goal, robot_speed = np.abs(robot - target), np.hypot(trace.robot[:, VX], trace.robot[:, VY])
    radii = np.asarray(trace.human_radii, dtype=float)
    for k in range(trace.humans.shape[1]):
        person = trace.humans[:, k, X] + 1j * trace.humans[:, k, Y]
        gap = np.abs(person - robot) - radii[k] - float(trace.robot_radius)
        speed = np.hypot(trace.humans[:, k, VX], trace.humans[:, k, VY])
        seen = world.segments_clear(robot, person) if world is not None else np.ones(trace.steps, dtype=bool)
        out |= proxemics.short_of_goal(robot_to_goal, np.abs(person - target), gap, speed, robot_speed,
                                       float(trace.robot_radius), float(radii[k]), seen.astype(float))
    return _stood(out & no_nearer_spot(trace, target, out, world), trace)


CHUNK = 256  # steps worked out at once (a chunk's gaps: CHUNK x spots x people floats)


def no_nearer_spot(trace: Trace, goal: complex, steps: np.ndarray, world: Any = None) -> np.ndarray:
    """(T,) bool, on the `steps` asked (False elsewhere): no free spot proxemics.NEARER_SPOT nearer the goal than the
    robot where it would keep at least as far from everyone (its own smallest gap, at most GOAL_STOP_GAP): clear of
    walls by the robot's radius and in sight of the goal (`world`: its walls; None: no walls known). Spots are tried
    on a proxemics.SPOT_GRID grid within the arrival reach of the goal."""
    out = np.zeros(trace.steps, dtype=bool)
    ks = np.flatnonzero(steps)
    if not len(ks):
        return out
    radii = np.asarray(trace.human_radii, dtype=float)
    rr = float(trace.robot_radius)
    reach = rr + float(radii.max()) + proxemics.GOAL_STOP_GAP + proxemics.GOAL_STOP_SLACK
    axis = np.arange(-reach, reach + 1e-9, proxemics.SPOT_GRID)
    spots = (goal + axis[None, :] + 1j * axis[:, None]).ravel()
    spots = spots[np.abs(spots - goal) <= reach]
    if world is not None:
        spots = spots[(world.clearance_at(spots) >= rr) & world.segments_clear(np.full(spots.shape, goal), spots)]
    robot = trace.robot[ks, X] + 1j * trace.robot[ks, Y]
    people = trace.humans[ks][:, :, X] + 1j * trace.humans[ks][:, :, Y]  # (K, H)
    own = (np.abs(people - robot[:, None]) - radii[None, :] - rr).min(axis=1)  # (K,)
    keep = np.minimum(own, proxemics.GOAL_STOP_GAP)
    spot_to_goal = np.abs(spots - goal)
    for a in range(0, len(ks), CHUNK):  # (steps, spots, people) gaps, a chunk of steps at a time
        gaps = np.abs(spots[None, :, None] - people[a:a + CHUNK, None, :]) - radii[None, None, :] - rr
        roomy = gaps.min(axis=2) >= keep[a:a + CHUNK, None] - 1e-9
        nearer = spot_to_goal[None, :] <= np.abs(robot[a:a + CHUNK] - goal)[:, None] - proxemics.NEARER_SPOT
        out[ks[a:a + CHUNK]] = ~(roomy & nearer).any(axis=1)
    return out


def _stood(short: np.ndarray, trace: Trace) -> np.ndarray:
    """Only the runs of `short` lasting proxemics.GOAL_STOP_DWELL or reaching the trace's end."""
    out = np.zeros_like(short)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], short.astype(np.int8), [0]])))
    times = np.asarray(trace.t, dtype=float)
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        if stop == len(short) or times[stop - 1] - times[start] >= proxemics.GOAL_STOP_DWELL - 1e-6:
            out[start:stop] = True
    return out
