"""`aside` (giving way) counts a stand on the robot's route round a bend only within proxemics.HELD_UP_DISTANCE
ahead along it (issue 25, hospital_01 of the new-request suite: a visitor who started on the route ~5 m ahead,
round the bend out of the elevator lobby, and walked off it to wait by the door was read as "stepping aside" at
t = 1.5 s, before the robot had said anything; reacts_after_phrase then failed her as reacting BEFORE the phrase).
Straight ahead along the robot's heading a stand still counts at any distance (a give-way asked at 6 m)."""

from __future__ import annotations

import numpy as np

from socnavgen import proxemics
from socnavgen.verify.signals import Signals, aside

from .verify_builders import build_trace

T = np.arange(0, 20.0 + 1e-9, 0.5)
BEND = [(1.0, 3.0), (5.0, 3.0), (5.0, 12.0)]  # east along y = 3, then north along x = 5


def _trace(robot_x: np.ndarray, human_xy: np.ndarray, waypoints: list[tuple[float, float]]) -> object:
    robot = np.stack([robot_x, np.full_like(T, 3.0)], 1)
    trace = build_trace(T, robot, human_xy[:, None], goal=waypoints[-1])
    trace.robot[:, 2] = 0.0  # facing +x (east) the whole run
    trace.robot_waypoints = waypoints
    return trace


def _walks_off(x0: float, y0: float, t0: float, t1: float) -> np.ndarray:
    """A person standing at (x0, y0) who walks 1 m east between t0 and t1 s and stays there."""
    return np.stack([np.interp(T, [0, t0, t1, 20], [x0, x0, x0 + 1.0, x0 + 1.0]), np.full_like(T, y0)], 1)


def test_walking_off_the_route_far_round_a_bend_is_no_step_aside() -> None:
    # the robot stands at x = 1; the person is on the route 4 + 3.5 = 7.5 m ahead along it (beyond the bend)
    out = aside(Signals(_trace(np.full_like(T, 1.0), _walks_off(5.0, 6.5, 0.0, 2.0), BEND)), "human1")
    assert not out.any()


def test_stepping_off_the_route_just_round_a_bend_is_a_step_aside() -> None:
    # the robot has driven to x = 4 by t = 4 s; the person stands on the route 1 + 1.2 m ahead along it and steps
    # 1 m off it from t = 6 to 8 s: aside from then on, not before
    robot_x = np.interp(T, [0, 4, 20], [1.0, 4.0, 4.0])
    ahead = 1.0 + 1.2
    assert ahead < proxemics.HELD_UP_DISTANCE
    out = aside(Signals(_trace(robot_x, _walks_off(5.0, 4.2, 6.0, 8.0), BEND)), "human1")
    assert not out[T < 6.0].any() and out[T >= 8.0].all()


def test_a_stand_straight_ahead_counts_at_any_distance() -> None:
    # a straight route; the person stands in the robot's heading 6 m ahead and steps off north at t = 2-4 s
    straight = [(1.0, 3.0), (12.0, 3.0)]
    human = np.stack([np.full_like(T, 7.0), np.interp(T, [0, 2, 4, 20], [3.0, 3.0, 4.0, 4.0])], 1)
    out = aside(Signals(_trace(np.full_like(T, 1.0), human, straight)), "human1")
    assert not out[T < 2.0].any() and out[T >= 4.0].all()


def _steps_aside_and_back(back_at: float) -> np.ndarray:
    """The robot drives +x along y = 3 from x = 1 at 0.5 m/s (at x = 6 by t = 10 s, x = 11 by t = 20 s); the person
    stands on the route at (6, 3), steps 1 m off it (y 4) at t = 2-4 s and walks back onto the route from
    t = back_at for 2 s (to the spot it left)."""
    straight = [(1.0, 3.0), (12.0, 3.0)]
    hy = np.interp(T, [0, 2, 4, back_at, back_at + 2, 20], [3.0, 3.0, 4.0, 4.0, 3.0, 3.0])
    human = np.stack([np.full_like(T, 6.0), hy], 1)
    signals = Signals(_trace(np.interp(T, [0, 20], [1.0, 11.0]), human, straight))
    return signals.get("aside_human1") > 0.5  # kept aside (verify/passing.kept_aside)


def test_walking_back_behind_the_robot_once_it_is_past_undoes_no_step_aside() -> None:
    out = _steps_aside_and_back(14.0)  # the robot passed x = 6 at t = 10 s; back on the spot at 16 s, behind it
    assert out[(T >= 4.0)].all()


def test_walking_back_into_the_way_before_the_robot_is_past_is_no_step_aside() -> None:
    out = _steps_aside_and_back(6.0)  # back on the route at 8 s, the robot 1 m short of her
    assert not out[(T >= 4.0) & (T < 6.0)].any() and not out[T >= 8.0].any()
