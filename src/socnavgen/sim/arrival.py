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
    simulator ends a run): a robot pausing there for a moment and driving off again has not arrived."""
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
    return _stood(out, trace)


def _stood(short: np.ndarray, trace: Trace) -> np.ndarray:
    """Only the runs of `short` lasting proxemics.GOAL_STOP_DWELL or reaching the trace's end."""
    out = np.zeros_like(short)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], short.astype(np.int8), [0]])))
    times = np.asarray(trace.t, dtype=float)
    for start, stop in zip(edges[::2], edges[1::2], strict=True):
        if stop == len(short) or times[stop - 1] - times[start] >= proxemics.GOAL_STOP_DWELL - 1e-6:
            out[start:stop] = True
    return out
