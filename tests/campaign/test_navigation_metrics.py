"""The metrics HuNavSim's evaluator leaves as TODO, on hand-made traces whose values are known."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim.metrics import NAVIGATION_METRICS, navigation_metrics
from socnavgen.sim.trace import Trace
from socnavgen.sim.world import empty_room


def trace_of(xy: np.ndarray, yaw: np.ndarray | None = None, goal: tuple[float, float] | None = None,
             radius: float = 0.35) -> Trace:
    xy = np.asarray(xy, dtype=float)
    steps = len(xy)
    if yaw is None:
        d = np.diff(xy, axis=0, append=xy[-1:] + (xy[-1:] - xy[-2:-1]))
        yaw = np.arctan2(d[:, 1], d[:, 0])
    robot = np.zeros((steps, 6))
    robot[:, :2], robot[:, 2] = xy, yaw
    goal = goal or tuple(xy[-1])
    empty = np.zeros((steps, 0))
    return Trace(dt=0.1, t=np.arange(steps) * 0.1, robot=robot, humans=np.zeros((steps, 0, 6)), human_names=[],
                 group_ids=[], human_radii=np.zeros(0), robot_radius=radius, node_names=[],
                 action=empty.astype(np.int16), succeeded=empty.astype(np.int64), human_gesture=empty.astype(np.int8),
                 robot_gesture=np.zeros(steps, dtype=np.int8), behavior_state=empty.astype(np.int8),
                 robot_goal=goal, robot_waypoints=[tuple(xy[0]), goal], meta={"robot_goal_radius": 0.2})


def line(a: tuple[float, float], b: tuple[float, float], n: int) -> np.ndarray:
    return np.linspace(a, b, n)


ROOM = empty_room(10.0, 10.0, walls=[(4.8, 0.0, 5.2, 6.0)])  # a wall from the floor up to y = 6 at x = 5


def test_straight_drive_is_regular_and_efficient() -> None:
    m = navigation_metrics(trace_of(line((1, 8), (9, 8), 81)), ROOM)
    assert m["path_irregularity"] == pytest.approx(0.0, abs=1e-9)
    assert m["path_efficiency"] == pytest.approx(1.0)
    assert m["static_obstacle_collisions"] == 0
    assert m["min_obstacle_clearance"] == pytest.approx(1.0 - 0.05 - 0.35, abs=0.06)  # the side wall at x = 0


def test_zigzag_is_irregular_and_inefficient() -> None:
    xs = np.linspace(1, 9, 81)
    ys = 8 + 0.5 * np.sign(np.sin(np.arange(81) * math.pi / 4 + 0.1))
    m = navigation_metrics(trace_of(np.column_stack([xs, ys]), goal=(9.0, ys[-1])), ROOM)
    assert m["path_irregularity"] > 0.5
    assert m["path_efficiency"] < 0.9


def test_the_one_needed_turn_is_not_irregular() -> None:
    # facing away from the goal at the start: turning round once is necessary, not irregular
    xy = line((1, 8), (9, 8), 81)
    yaw = np.zeros(81)
    yaw[0] = math.pi
    m = navigation_metrics(trace_of(xy, yaw=yaw), ROOM)
    assert m["path_irregularity"] == pytest.approx(0.0, abs=1e-9)


def test_goal_not_reached_has_no_efficiency() -> None:
    m = navigation_metrics(trace_of(line((1, 8), (4, 8), 31), goal=(9.0, 8.0)), ROOM)
    assert m["path_efficiency"] is None
    assert m["path_irregularity"] == pytest.approx(0.0, abs=1e-9)


def test_driving_through_a_wall_counts_one_collision_per_contact() -> None:
    m = navigation_metrics(trace_of(line((1, 3), (9, 3), 161)), ROOM)
    assert m["static_obstacle_collisions"] == 1
    assert m["min_obstacle_clearance"] < 0
    # brushing the wall twice: two onsets
    there = line((4.55, 7), (4.55, 3), 41)
    away = line((4.55, 3), (3.0, 3), 41)
    back = line((3.0, 3), (4.55, 3), 41)
    twice = navigation_metrics(trace_of(np.vstack([there, away, back])), ROOM)
    assert twice["static_obstacle_collisions"] == 2


def test_without_walls_the_wall_metrics_are_undefined_and_every_metric_is_documented() -> None:
    m = navigation_metrics(trace_of(line((1, 8), (9, 8), 81)), None)
    assert m["static_obstacle_collisions"] is None and m["min_obstacle_clearance"] is None
    for name, definition in NAVIGATION_METRICS.items():
        assert name in m
        assert definition["unit"] and definition["formula"] and definition["meaning"]
