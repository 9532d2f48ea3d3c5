"""A round trip [A, B, A] ("patrol to the door and back"): the run does not end at t = 0 because the robot starts
on its goal, and the verifier's robot_reaches_goal counts the goal only after the robot came near B."""

from __future__ import annotations

import numpy as np

from socnavgen.sim import load_policy
from socnavgen.verify.signals import Signals
from tests.sim.simhelpers import INSTANT, make_sim

ROUND_TRIP = [(2.0, 5.0), (10.0, 5.0), (2.0, 5.0)]


def test_a_round_trip_ends_back_at_its_start_after_its_far_end() -> None:
    trace = make_sim([], [], ROUND_TRIP, load_policy("waypoints"), timeout=60, body=INSTANT).run()
    assert trace.end_reason == "robot_goal"
    assert trace.robot[:, 0].max() > 9.0  # it went to the far end
    assert trace.steps * trace.dt > 8.0  # ... and back: not the first step
    done = Signals(trace).get("route_done")
    assert done[0] == 0 and done[-1] == 1


def test_standing_on_a_round_trips_goal_is_not_arriving() -> None:
    trace = make_sim([], [], ROUND_TRIP, timeout=3).run()  # a robot that never moves
    signals = Signals(trace)
    assert np.all(signals.get("robot_to_goal") < 0.1)  # at its goal the whole time ...
    assert not signals.get("route_done").any()  # ... but never past its far end: not arrived
