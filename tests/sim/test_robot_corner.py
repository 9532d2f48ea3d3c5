"""The scripted robot with a corner_speed approaches a blind turn of its route slowly (polite.corner_speed): a
turn round a wall corner it cannot see past, not one in the open."""

from __future__ import annotations

import numpy as np

from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.robot.polite import CORNER_SPEED
from tests.sim.simhelpers import make_sim

ROUTE = [(1.5, 7.2), (9.2, 7.2), (9.2, 1.5)]
TURN = 9.2 + 7.2j


def _top_speed_near_turn(world) -> tuple[float, str]:  # noqa: ANN001
    robot = load_policy("scripted", {"corner_speed": CORNER_SPEED})
    trace = make_sim([], [], ROUTE, robot, world=world, timeout=60).run()
    pos = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    return float(speed[np.abs(pos - TURN) <= 2.0].max()), trace.end_reason


def test_scripted_robot_slows_at_a_blind_corner_and_not_at_an_open_turn():
    blind = empty_room(20.0, 10.0, walls=[(0.0, 0.0, 8.5, 6.5)])  # the wall corner hides the leg after the turn
    top, end = _top_speed_near_turn(blind)
    assert end == "robot_goal" and top <= CORNER_SPEED + 0.02  # the card's slow_near_place wants <= 0.4 m/s
    top_open, end = _top_speed_near_turn(empty_room(20.0, 10.0))
    assert end == "robot_goal" and top_open > 0.45
