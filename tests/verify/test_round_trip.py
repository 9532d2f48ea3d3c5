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


def _led_home(follower_stops: bool) -> object:
    """The robot drives out to x = 10 and back along y = 5 at 1 m/s (t 0-8 s out, 8-16 s back, then stands), a
    person walking 1 m behind it on the way back (hospital_06: the robot leading a patient home). `follower_stops`:
    the robot instead stands at x = 6 on the way back from t = 12 s, the person 1 m AHEAD of it (west) there."""
    from .verify_builders import build_trace

    t = np.arange(0, 30.0 + 1e-9, 0.5)
    back = [12.0, 6.0] if follower_stops else [16.0, 2.0]
    rx = np.interp(t, [0, 8, back[0], 30], [2.0, 10.0, back[1], back[1]])
    robot = np.stack([rx, np.full_like(t, 5.0)], 1)
    hx = np.interp(t, [0, 8, 30], [12.0, 11.0, 11.0]) if not follower_stops else np.full_like(t, 5.0)
    if not follower_stops:
        hx = np.where(t >= 8.0, rx + 1.0, hx)
    trace = build_trace(t, robot, np.stack([hx, np.full_like(t, 5.0)], 1)[:, None], goal=(2.0, 5.0))
    trace.robot[:, 2] = np.where(t < 8.0, 0.0, np.pi)  # facing the way it drives
    trace.robot_waypoints = list(ROUND_TRIP)
    return trace


def test_the_way_back_is_progress_and_a_follower_behind_is_not_in_the_way() -> None:
    s = Signals(_led_home(False))
    progress = s.route()[0]
    assert progress[-1] > 15.5 and np.all(np.diff(progress) >= -1e-9)  # 8 m out, 8 m back: never backwards
    assert s.get("deadlock").max() == 0.0
    assert not s.holding_up()[s.t > 8.5, 0].any()  # the follower is behind it the whole way back


def test_standing_on_the_way_back_behind_someone_is_still_a_deadlock() -> None:
    s = Signals(_led_home(True))
    assert s.holding_up()[s.t > 12.5, 0].all()  # the person 1 m ahead of it on the way back
    assert s.get("deadlock").max() >= 17.0


def _turned_short(backs_off: float = 0.0) -> np.ndarray:
    """(T, 2) a robot driving the round trip's far leg but turning 0.5 m short of x = 10 through a 0.6 m loop off
    the line (hospital_07: it turned round 0.3 m before the nurse station's node), then back along y = 5; with
    `backs_off` it first backs that many metres east on the way back (making way), then drives on west."""
    out = np.stack([np.linspace(2.0, 9.5, 76), np.full(76, 5.0)], 1)
    loop = np.array([[9.6, 5.3], [9.5, 5.6], [9.2, 5.4], [9.0, 5.0]])
    home = np.stack([np.linspace(8.9, 2.0, 70), np.full(70, 5.0)], 1)
    if backs_off:
        k = 20
        back = np.stack([np.linspace(home[k, 0], home[k, 0] + backs_off, 5), np.full(5, 5.0)], 1)
        home = np.concatenate([home[:k + 1], back, home[k + 1:] + 0.0])
    return np.concatenate([out, loop, home])


def test_a_robot_turning_short_of_its_turning_point_makes_progress_on_the_way_back() -> None:
    from socnavgen.verify.route import route_progress

    progress = route_progress(_turned_short(), ROUND_TRIP)[0]
    assert progress[-1] > 15.5  # back at its start: 16 m of route covered, not read as the way out driven back
    assert np.all(np.diff(progress[90:]) > 0)  # every step home is progress
    backing = route_progress(_turned_short(backs_off=0.2), ROUND_TRIP)[0]
    assert backing[-1] > 15.5 and np.diff(backing).min() > -0.25  # backing off 0.2 m stays on its leg (no jump)
