"""The default (scripted) robot keeps to its way: the planner takes a narrow aisle the robot fits through
rather than a detour twice as long round a block, a planned way that first leads away from the waypoint is
driven at speed (not crept along a wall), and a person walking ahead of it down an aisle is followed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from socnavgen.location import load_location
from socnavgen.sim import World, empty_room, load_policy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

ROOT = Path(__file__).resolve().parents[2]


def _path_length(trace) -> float:  # noqa: ANN001
    return float(np.abs(np.diff(trace.robot[:, 0] + 1j * trace.robot[:, 1])).sum())


def _creeping_seconds(trace) -> float:  # noqa: ANN001
    """Seconds the robot moved at 0.01-0.15 m/s (neither standing nor driving) with nobody within 2 m."""
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    if trace.humans.shape[1]:
        near = np.hypot(*(trace.humans[:, :, :2] - trace.robot[:, None, :2]).transpose(2, 0, 1)).min(axis=1) < 2.0
    else:
        near = np.zeros(len(speed), bool)
    return float(((speed > 0.01) & (speed < 0.15) & ~near).sum() * trace.dt)


def test_the_planner_takes_a_narrow_aisle_rather_than_a_detour_twice_as_long():
    # a 3 m x 10 m block; west of it an aisle 1.0 m wide (the 0.35 m robot fits, 0.15 m each side), east of it
    # one 3 m wide. The robot comes from the east along the top and goes down the west aisle: 12 m; round the
    # block through the wide aisle: ~19 m. The narrow aisle's near-wall cost made the planner pick the detour.
    world = empty_room(9.0, 14.0, walls=[(1.05, 2.0, 4.05, 12.0)])
    route = [(3.0, 13.0), (0.55, 12.8), (0.55, 1.0)]
    trace = make_sim([], [], route, load_policy("scripted"), world=world, timeout=90).run()
    assert trace.end_reason == "robot_goal"
    assert trace.robot[:, 0].max() < 4.0  # never east of the block's west face + its width: not round it
    assert _path_length(trace) < 16.0


def test_a_planned_way_leading_away_from_the_waypoint_is_driven_not_crept():
    # the waypoint (8, 2) is south-east beyond a wall (y = 3.5, x from 2 m east); the way round it leads first
    # west, away from the waypoint: the robot drove only the part of its planned way not away from the waypoint
    # (towards the wall), slowing to a creep along it
    world = empty_room(14.0, 8.0, walls=[(2.0, 3.45, 14.0, 3.55)])
    trace = make_sim([], [], [(4.0, 5.0), (8.0, 2.0)], load_policy("scripted"), world=world, timeout=90).run()
    assert trace.end_reason == "robot_goal"
    assert trace.t[-1] < 40.0  # ~12 m of way
    # the creep was metres along the wall at 0.03 m/s; what is left is its turns' slow-downs and starts, each through
    # the 0.01-0.15 m/s band (2.95 s braking at 2 m/s2, 3.05 s at the comfort limit: robot.brake)
    assert _creeping_seconds(trace) < 3.5


FOLLOWING = tree_xml(REGULAR)


def test_a_person_walking_down_the_aisle_ahead_is_followed_not_driven_round():
    # a 1 m aisle (x 0.05-1.05) along the west of a block; the robot enters it from the north behind a person
    # walking the same way, slower than the robot: it slows behind them and follows them down the aisle
    world = empty_room(9.0, 14.0, walls=[(1.05, 2.0, 4.05, 12.0)])
    person = human(start=(0.55, 11.0), goals=[(0.55, 1.0), (7.0, 1.0)], max_vel=0.3)  # on out east
    trace = make_sim([person], [FOLLOWING], [(3.0, 13.0), (0.55, 12.8), (0.55, 1.0)], load_policy("scripted"),
                     world=world, timeout=120).run()
    assert trace.end_reason == "robot_goal"
    assert trace.robot[:, 0].max() < 4.0  # down the aisle behind them, not round the block
    gap = np.abs((trace.humans[:, 0, 0] - trace.robot[:, 0]) + 1j * (trace.humans[:, 0, 1] - trace.robot[:, 1]))
    in_aisle = (trace.robot[:, 1] < 11.0) & (trace.robot[:, 1] > 3.0)
    assert in_aisle.any() and gap[in_aisle].min() > 0.6  # behind them, not on their heels


def test_on_the_bundled_warehouse_the_robot_turns_from_the_north_cross_aisle_down_the_westernmost_aisle():
    # the last legs of a recorded patrol (6r, hd, ki): east along the north cross aisle, then south down the 1 m
    # aisle to ki. The planner sent the robot from hd back west round the office block (~30 m), and it crept
    # along the wall at 0.03 m/s until the time ran out
    location = load_location(ROOT / "examples" / "locations" / "warehouse")
    route = [(5.025, 8.475), (7.525, 8.475), (7.525, -3.025)]
    trace = make_sim([], [], route, load_policy("scripted"), world=World.from_location(location), timeout=60).run()
    assert trace.end_reason == "robot_goal"
    assert trace.t[-1] < 40.0  # ~14 m of way
    assert trace.robot[:, 0].min() > 4.5  # never back west of 6r
