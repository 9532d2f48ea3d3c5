"""Arriving short of a goal someone stands at, on a whole trace: proxemics.short_of_goal at every step (the
rule the simulator ends a run by), for the metrics (success, reached_goal, time_to_goal) and the verifier's
`short_of_goal` signal - one rule, one implementation."""

from __future__ import annotations

from typing import Any

import numpy as np

from socnavgen import proxemics
from socnavgen.sim.trace import VX, VY, Trace, X, Y
from socnavgen.sim.world.queries import WorldMap
from socnavgen.sim.world.spots import nearer_spot

NO_WALLS = WorldMap(np.zeros((1, 1)), np.zeros((1, 1), dtype=bool), np.zeros((1, 1), dtype=complex), np.eye(3), 1.0,
                    0.0, False)  # a map without walls, for a trace whose walls are not known


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
        short = proxemics.short_of_goal(robot_to_goal, np.abs(person - target), gap, speed, robot_speed,
                                        float(trace.robot_radius), float(radii[k]), 1.0)
        ks = np.flatnonzero(short)  # `seen` only ANDs: the line of sight asked only where all else holds
        if world is not None and len(ks):
            short[ks] = world.segments_clear(robot[ks], person[ks])
        out |= short
    return _stood(out & no_nearer_spot(trace, target, out, world), trace)


def no_nearer_spot(trace: Trace, goal: complex, steps: np.ndarray, world: Any = None) -> np.ndarray:
    """(T,) bool, on the `steps` asked (False elsewhere): the people round the goal leave no free spot
    proxemics.NEARER_SPOT nearer it than the robot where it would keep at least as far from everyone (its own
    smallest gap, at most GOAL_STOP_GAP), clear of walls by the robot's radius and in sight of the goal (`world`: its
    walls; None: no walls known). The simulator's rule: world.spots.nearer_spot, step by step."""
    out = np.zeros(trace.steps, dtype=bool)
    ks = np.flatnonzero(steps)
    if not len(ks):
        return out
    people = np.zeros(trace.humans.shape[1], dtype=[("pos", "c16"), ("radius", "f8")]).view(np.recarray)
    people["radius"] = np.asarray(trace.human_radii, dtype=float)
    walls = world.map if world is not None else NO_WALLS
    rr = float(trace.robot_radius)
    for k in ks:
        people["pos"] = trace.humans[k, :, X] + 1j * trace.humans[k, :, Y]
        found, _ = nearer_spot(walls, complex(goal), complex(trace.robot[k, X], trace.robot[k, Y]), rr, people)
        out[k] = not found
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
