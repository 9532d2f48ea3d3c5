"""The social metrics (sim/social_metrics.py) and the shortest walkable path they read (sim/world/walkable.py),
on small worlds and traces whose values are worked out by hand in each test."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim.social_metrics import TTC_EDGES, mean_jerk, social_metrics
from socnavgen.sim.world import empty_room
from socnavgen.sim.world.walkable import WalkableDistance
from tests.verify.verify_builders import build_trace

# A 10 m x 6 m room split by a wall at x = 5 with a 1 m door at y 4.5-5.5. On the map's 5 cm grid the wall
# fills x 4.9-5.1 up to y 4.55 (its raster), so the shortest way from (4, 1) to (6, 1) for a point bends at
# (4.9, 4.55) and (5.1, 4.55): 2 x sqrt(0.9^2 + 3.55^2) + 0.2 = 7.525 m.
DOOR = [(4.95, 0.0, 5.05, 4.5), (4.95, 5.5, 5.05, 6.0)]
AROUND = 2 * math.hypot(0.9, 3.55) + 0.2


def test_the_shortest_walkable_path_bends_at_the_walls_corners_not_at_cell_centres() -> None:
    ways = WalkableDistance(empty_room(10.0, 6.0, walls=DOOR))
    assert ways.shortest_length(4 + 1j, 6 + 1j) == pytest.approx(AROUND, rel=0.005)  # any-angle, not 8-connected
    assert ways.shortest_length(1 + 5j, 9 + 5j) == pytest.approx(8.0)  # straight through the open door
    body = WalkableDistance.of(empty_room(10.0, 6.0, walls=DOOR), 0.35)
    assert body.shortest_length(4 + 1j, 6 + 1j) > AROUND + 0.2  # a 0.35 m disc keeps off the wall's end


def test_a_route_passes_its_waypoints_within_the_slack_and_a_closed_wall_has_no_way() -> None:
    room = WalkableDistance(empty_room(10.0, 6.0))
    assert room.route_length([1 + 1j, 5 + 3j, 9 + 1j]) == pytest.approx(2 * abs(4 + 2j))
    assert room.route_length([1 + 1j, 5 + 3j, 9 + 1j], 0.4) == pytest.approx(2 * abs(4 + 1.6j), rel=0.002)
    assert room.route_length([1 + 1j, 5 + 3j, 1 + 1j], 0.4) == pytest.approx(2 * (abs(4 + 2j) - 0.4), rel=0.01)
    closed = WalkableDistance(empty_room(10.0, 6.0, walls=[(4.95, 0.0, 5.05, 6.0)]))
    assert closed.shortest_path(4 + 1j, 6 + 1j) is None
    assert closed.shortest_length(4 + 1j, 6 + 1j) == math.inf


def _drive(points: list[complex], speed: float = 1.0, dt: float = 0.1, goal: complex | None = None,
           humans: np.ndarray | None = None, waypoints: list[complex] | None = None):  # noqa: ANN202
    """A trace of the robot driving the polyline at `speed` (then standing 1 s), humans (T, H, 2) optional."""
    legs = np.abs(np.diff(points))
    s = np.arange(0, legs.sum() + 1.0 * speed + 1e-9, speed * dt)
    at = np.concatenate([[0], np.cumsum(legs)])
    xy = np.interp(np.minimum(s, at[-1]), at, np.real(points)) + 1j * np.interp(np.minimum(s, at[-1]), at,
                                                                                np.imag(points))
    t = np.arange(len(xy)) * dt
    hum = np.zeros((len(t), 0, 2)) if humans is None else humans[:len(t)]
    end = points[-1] if goal is None else goal
    trace = build_trace(t, np.stack([xy.real, xy.imag], 1), hum, dt=dt, goal=(end.real, end.imag))
    trace.robot_waypoints = [(p.real, p.imag) for p in (waypoints or [points[0], points[-1]])]
    trace.meta = {"robot_goal_radius": 0.2}
    return trace


def test_path_efficiency_is_measured_against_the_walkable_path_not_the_line_through_the_wall() -> None:
    world = empty_room(10.0, 6.0, walls=DOOR)
    body = WalkableDistance.of(world, 0.35)
    best = body.shortest_path(4 + 1j, 6 + 1j)
    through_door = social_metrics(_drive(list(best)), world, success=True)
    assert through_door["walkable_path_efficiency"] == pytest.approx(1.0, abs=0.01)
    assert through_door["route_length_walkable"] == pytest.approx(float(np.abs(np.diff(best)).sum()), rel=1e-6)
    detour = [4 + 1j, 4 + 5.8j, 6 + 5.8j, 6 + 1j]  # up to the far wall and back down: 11.6 m, arrived 0.2 m short
    long_way = social_metrics(_drive(detour), world, success=True)
    assert long_way["walkable_path_efficiency"] == pytest.approx(through_door["route_length_walkable"] / 11.4,
                                                                 rel=0.01)
    assert social_metrics(_drive(detour, goal=9 + 5j), world)["walkable_path_efficiency"] is None  # not reached
    assert social_metrics(_drive(detour), None)["walkable_path_efficiency"] is None  # no map, no reference


def test_time_to_goal_counts_successes_only() -> None:
    trace = _drive([1 + 1j, 5 + 1j], speed=0.5)
    assert social_metrics(trace, success=True)["time_to_goal"] == pytest.approx((4 - 0.2) / 0.5, abs=0.11)
    failed = social_metrics(trace, success=False)
    assert failed["reached_goal"] is True and failed["time_to_goal"] is None
    lost = social_metrics(_drive([1 + 1j, 5 + 1j], goal=9 + 1j), success=False)
    assert lost["reached_goal"] is False and lost["time_to_goal"] is None


def test_seconds_in_intimate_and_personal_space_and_the_ttc_distribution() -> None:
    """The robot stands at (0, 0) for 10 s (dt 0.1); a person (radius 0.4, robot 0.35) stands 1.05 m away
    (gap 0.3: intimate) for the first 4 s, then 1.75 m away (gap 1.0: personal) for 6 s. Nobody moves, so
    every TTC is infinite: all the time lands in the last bin and none under 1 s."""
    t = np.arange(101) * 0.1
    person = np.where(t < 4 - 1e-9, 1.05, 1.75)
    trace = build_trace(t, np.zeros((101, 2)), np.stack([person, np.zeros(101)], 1)[:, None, :], dt=0.1,
                        goal=(5.0, 0.0))
    trace.humans[:, :, 3:5] = 0.0  # standing, whatever the finite differences say at the jump
    m = social_metrics(trace)
    assert m["intimate_space_seconds"] == pytest.approx(4.0)
    assert m["personal_space_seconds"] == pytest.approx(6.0)
    assert m["ttc_under_1s"] == 0.0
    assert m["ttc_seconds"][-1] == pytest.approx(10.0) and sum(m["ttc_seconds"]) == pytest.approx(10.0)


def test_closing_in_counts_the_robot_walking_into_intimate_space_not_a_person_walking_up_to_it() -> None:
    """dt 0.1, 10 s each. (a) The robot stands at (0, 0); a person walks from x = 3 to x = 1.05 (gap 0.3) at
    0.5 m/s and stands there: intimate time, none of it the robot's. (b) The mirror: the person stands at x = 3,
    the robot drives from 0 to 1.95 and stops: the robot closed in for the steps inside 0.45 m while it still
    moved (gap 0.45 -> 0.3 at 0.5 m/s: ~0.3 s), then stood beside them (intimate, not closing). (c) The robot
    backs away from a person at gap 0.3: intimate time, not closing in."""
    t = np.arange(101) * 0.1
    walk = np.maximum(3.0 - 0.5 * t, 1.05)
    up = build_trace(t, np.zeros((101, 2)), np.stack([walk, np.zeros(101)], 1)[:, None, :], dt=0.1, goal=(-5.0, 0.0))
    m = social_metrics(up)
    assert m["intimate_space_seconds"] > 6.0 and m["intimate_approach_seconds"] == 0.0
    drive = np.minimum(0.5 * t, 1.95)
    robot_in = build_trace(t, np.stack([drive, np.zeros(101)], 1), np.tile([3.0, 0.0], (101, 1))[:, None, :],
                           dt=0.1, goal=(9.0, 9.0))
    m = social_metrics(robot_in)
    assert m["intimate_space_seconds"] > 6.0
    assert 0.2 <= m["intimate_approach_seconds"] <= 0.5
    back = np.stack([-0.05 * t, np.zeros(101)], 1)
    away = build_trace(t, back, np.tile([1.05, 0.0], (101, 1))[:, None, :], dt=0.1, goal=(-5.0, 0.0))
    m = social_metrics(away)
    assert m["intimate_space_seconds"] > 1.0 and m["intimate_approach_seconds"] == 0.0


def test_a_head_on_approach_fills_the_short_ttc_bins() -> None:
    """Robot at 1 m/s toward a person walking at 1 m/s the other way: closing 2 m/s, contact at centre distance
    0.75; starting 8.75 m apart, TTC falls from 4 s to 0 over 4 s: 0.5 s in [0, 0.5), 0.5 s in [0.5, 1), 1 s in
    [1, 2) ..."""
    t = np.arange(41) * 0.1
    trace = build_trace(t, np.stack([t, np.zeros(41)], 1), np.stack([8.75 - t, np.zeros(41)], 1)[:, None, :],
                        dt=0.1, goal=(20.0, 0.0))
    bins = social_metrics(trace)["ttc_seconds"]
    assert len(bins) == len(TTC_EDGES) - 1
    assert bins[0] == pytest.approx(0.5, abs=0.11) and bins[1] == pytest.approx(0.5, abs=0.11)
    assert bins[2] == pytest.approx(1.0, abs=0.11) and bins[3] == pytest.approx(1.0, abs=0.11)
    assert social_metrics(trace)["ttc_under_1s"] == pytest.approx(1.0, abs=0.11)


def test_jerk_is_zero_at_constant_velocity_and_measures_a_change_of_acceleration() -> None:
    t = np.arange(50) * 0.1
    steady = build_trace(t, np.stack([t, np.zeros(50)], 1), np.zeros((50, 0, 2)), dt=0.1)
    assert mean_jerk(steady) == pytest.approx(0.0, abs=1e-9)
    v = np.where(t < 2.45, 0.0, 1.0)  # the velocity jumps by 1 m/s once: acceleration 10 for one step, jerk +-100
    jolt = build_trace(t, np.zeros((50, 2)), np.zeros((50, 0, 2)), dt=0.1)
    jolt.robot[:, 3] = v
    assert mean_jerk(jolt) == pytest.approx(2 * 100 / 48, rel=1e-6)  # two jerk samples of 100 over 48
