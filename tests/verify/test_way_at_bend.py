""""In the robot's way" along its route's direction stops at the route's next turn (issue 25, hospital_04 of the
new-request suite, first answer: the robot 0.24 m short of the junction where its route turns north into a
doorway; the nurse standing 1.4 m straight on beyond the junction, beside the doorway, was "holding it up" and was
blamed for a 97 s deadlock, while the doctor standing in the doorway it turns into was the one in its way)."""

from __future__ import annotations

import numpy as np

from socnavgen.verify.route import leg_left
from socnavgen.verify.signals import Signals

from .verify_builders import build_trace

T = np.arange(0, 10.0 + 1e-9, 0.5)
TURN = [(0.0, 3.0), (5.0, 3.0), (5.0, 8.0)]  # east along y = 3, then north at x = 5


def _held(person: tuple[float, float], robot_x: float = 4.75, yaw: float = np.pi / 2) -> bool:
    """The robot stands at (robot_x, 3) facing `yaw` (north: turning into the next leg), one person at `person`
    the whole run: whether that person holds it up (at every step)."""
    robot = np.tile([[robot_x, 3.0]], (len(T), 1))
    trace = build_trace(T, robot, np.tile([list(person)], (len(T), 1))[:, None], goal=TURN[-1])
    trace.robot[:, 2] = yaw
    trace.robot_waypoints = TURN
    held = Signals(trace).holding_up()[:, 0]
    assert held.all() or not held.any()
    return bool(held.all())


def test_someone_straight_on_beyond_the_turn_is_not_in_the_way() -> None:
    assert not _held((6.4, 3.0))  # 1.65 m on along y = 3, past the turn north at x = 5


def test_someone_on_the_leg_it_turns_into_is_in_the_way() -> None:
    assert _held((5.0, 4.4))  # in the doorway north of the turn


def test_someone_on_the_leg_before_the_turn_is_in_the_way_facing_elsewhere() -> None:
    # the robot 2 m before the turn, facing north-east (edging), the person on its leg 1.2 m ahead
    assert _held((4.2, 3.0), robot_x=3.0, yaw=np.pi / 4)


def test_the_leg_left_ends_at_the_next_waypoint_and_the_last_leg_has_no_end() -> None:
    left = leg_left(np.array([0.0, 4.75, 5.0, 6.0]), TURN)
    assert left[:3].tolist() == [5.0, 0.25, 0.0] and np.isinf(left[3])
