"""People step round a robot that stands still on their way, as people do (sim.people.spots.passes_by,
sim.people.avoid): in an open room and at a corridor junction they go round it on the free side with about the
social gap and walk on; only where there is truly no room (the robot standing in a 0.9 m door) do they wait. A
walker passing a waiting robot on the way to their next goal is not someone standing in its way
(sim.people.make_room)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.sim import empty_room
from socnavgen.sim.people.avoid import WAIT_GAP

from .simhelpers import REGULAR, Stay, human, make_sim, tree_xml
from .test_people_spots import robot_gaps

SOCIAL = 0.25  # m: the least gap a walker leaves passing a still robot where there is room


def walk(start, goals, robot, world=None, timeout=30.0, route_to=None):  # noqa: ANN001, ANN201
    """One RegularNav walker along `goals`; the robot stands at `robot` (its route goes on to `route_to`, by default
    0.5 m east)."""
    route = [robot, route_to or (robot[0] + 0.5, robot[1])]
    return make_sim([human(start=start, goals=goals)], [tree_xml(REGULAR)], route, Stay(), world=world,
                    timeout=timeout).run()


def arrived_at(trace, goal, within=0.6):  # noqa: ANN001, ANN201
    """The first time the walker is within `within` of `goal` (inf: never)."""
    d = np.hypot(trace.humans[:, 0, 0] - goal[0], trace.humans[:, 0, 1] - goal[1])
    return float(trace.t[np.argmax(d <= within)]) if (d <= within).any() else np.inf


def stood(trace) -> float:  # noqa: ANN001
    """Seconds the walker stood or dithered (slower than 0.2 m/s) before their last goal."""
    speed = np.hypot(trace.humans[:, 0, 3], trace.humans[:, 0, 4])
    moving_until = np.flatnonzero(speed > 0.2)
    last = moving_until[-1] if moving_until.size else 0
    return float((speed[:last] <= 0.2).sum() * trace.dt)


def test_a_walker_goes_round_a_robot_standing_on_a_point_of_their_way_in_an_open_room():
    """The robot stands on a point of a person's way across an open room (the neighbour of home_06 walking through
    the living-room centre it parked on): she goes round it with about the social gap, without stopping, and walks
    on to her goal. (This passes on main too, where she took a spot beside the point and set off from it: it guards
    the rule; main failed where the nearest free spot lay behind a doorway, as in home_06.)"""
    trace = walk((2.0, 5.0), [(10.0, 5.0), (18.0, 5.0)], (10.2, 5.1))
    assert robot_gaps(trace).min() >= SOCIAL, robot_gaps(trace).min()
    assert arrived_at(trace, (18.0, 5.0)) < 14.0  # 16 m at her 1.5 m/s and a step round the robot
    assert stood(trace) < 0.5, stood(trace)


JUNCTION_WALLS = [(0.0, 0.0, 20.0, 3.8),  # a corridor y 3.8 - 6.2 along x, a corridor x 8.8 - 11.2 north from it
                  (0.0, 6.2, 8.8, 10.0), (11.2, 6.2, 20.0, 10.0)]


def test_a_walker_goes_round_a_robot_standing_in_a_corridor_junction():
    """2.4 m corridors meet in a T; the robot stands in the junction, on the point where a worker turns north
    (warehouse_01's corner): the worker goes round it on the free side and up the north corridor, never within
    the social gap. (This guards the rule: it passes on main too.)"""
    world = empty_room(20.0, 10.0, walls=JUNCTION_WALLS)
    trace = walk((2.0, 5.0), [(10.0, 5.0), (10.0, 9.3)], (10.3, 4.6), world=world)
    assert robot_gaps(trace).min() >= SOCIAL, robot_gaps(trace).min()
    assert arrived_at(trace, (10.0, 9.3)) < 14.0, arrived_at(trace, (10.0, 9.3))


def test_a_walker_waits_for_a_robot_standing_in_a_door_too_narrow_to_pass():
    """The robot stands in a 0.9 m door that is on a person's way: there is no room to pass, so she stops short of
    it, never touching, and stays on her side."""
    walls = [(9.9, 0.0, 10.1, 4.55), (9.9, 5.45, 10.1, 10.0)]
    trace = walk((2.0, 5.0), [(10.0, 5.0), (16.0, 5.0)], (10.0, 5.0), world=empty_room(20.0, 10.0, walls=walls),
                 timeout=20)
    assert robot_gaps(trace).min() > CONTACT_MARGIN + 0.1, robot_gaps(trace).min()
    assert trace.humans[:, 0, 0].max() < 10.0 - 0.75  # never came through
    assert robot_gaps(trace)[-1, 0] < WAIT_GAP + 0.3  # waits close by, not somewhere else
    assert np.hypot(trace.humans[-1, 0, 3], trace.humans[-1, 0, 4]) < 0.05


def test_a_walker_passing_a_waiting_robot_on_the_way_to_their_next_goal_does_not_make_room():
    """The robot waits (stalled) on its route; a daughter crosses it 1.5 m ahead of it on her way to a doorway and
    on (home_07): the step her tree takes between the two goals, right in front of it, is no standing in its way:
    she walks on, never backing out (on main she backed out the way she came and waited there for a robot that
    never came, to the time limit)."""
    trace = walk((13.0, 1.0), [(13.0, 5.0), (13.0, 9.0)], (11.5, 5.0), timeout=15, route_to=(16.0, 5.0))
    assert not (trace.behavior_state[:, 0] == 2).any()  # never giving way
    assert np.diff(trace.humans[:, 0, 1]).min() > -0.01  # never back the way she came
    assert arrived_at(trace, (13.0, 9.0)) < 8.0
