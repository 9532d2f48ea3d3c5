"""The default robot passes a person only with its social gap (bodies.ROBOT_SOCIAL_GAP): held back by someone standing
it waits behind them, settling for the smaller POLITE_GAP only while people press on it (robot.polite.social_clear),
and behind someone walking its way with no room to overtake it follows (follow_speed); with room it passes."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import ROBOT_SOCIAL_GAP
from socnavgen.sim import empty_room
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.polite import FALL_BACK, PINNED_PATIENCE, POLITE_GAP, follow_speed, social_clear
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

WALK = tree_xml(REGULAR)
MOVING = 0.05  # m/s: the robot drives


def _corridor(width: float):  # noqa: ANN202
    """A corridor along x, `width` wide, centred on y = 5."""
    return empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, 5.0 - width / 2), (0.0, 5.0 + width / 2, 20.0, 10.0)])


def _gaps(trace) -> np.ndarray:  # noqa: ANN001
    """(T,) the robot's gap to the (one) person."""
    return np.hypot(*(trace.humans[:, 0, :2] - trace.robot[:, :2]).T) - trace.robot_radius - trace.human_radii[0]


def _driving(trace) -> np.ndarray:  # noqa: ANN001
    return np.hypot(trace.robot[:, 3], trace.robot[:, 4]) > MOVING


def _robot_facing(person_at: complex, person_vel: complex = 0j):  # noqa: ANN202
    """A simulation's state with the default robot at (8, 5), heading +x, and one person at `person_at` walking
    with `person_vel`."""
    sim = make_sim([human(start=(person_at.real, person_at.imag), goals=[(19.0, 5.0)])], [WALK],
                   [(8.0, 5.0), (18.0, 5.0)], ScriptedPolicy())
    s = sim.state
    s.robot[0].pos, s.people[0].pos, s.people[0].vel = 8.0 + 5.0j, person_at, person_vel
    return s


def _held_for(s, seconds: float) -> complex:  # noqa: ANN001
    """social_clear's answer to a 0.6 m/s wish straight ahead (+x) after asking it for `seconds`."""
    out = 0j
    for _ in range(int(seconds / s.clock[0].dt) + 1):
        out = social_clear(s, 0.6 + 0j)
    return out


def test_robot_held_back_by_someone_standing_waits_behind_them_however_long():
    s = _robot_facing(8.0 + 0.35 + 0.4 + ROBOT_SOCIAL_GAP + 0.005 + 5.0j)  # just outside its gap, straight ahead
    assert abs(_held_for(s, 3 * PINNED_PATIENCE)) < 1e-9  # the old fallback drove on at POLITE_GAP after 4 s
    assert s.policy[0].guard == pytest.approx(ROBOT_SOCIAL_GAP)  # its body's field keeps the same gap


@pytest.mark.parametrize("gap, vel", [(ROBOT_SOCIAL_GAP - 0.05, 0j),  # someone who came inside its gap
                                      (ROBOT_SOCIAL_GAP + 0.005, -0.5 + 0j)])  # someone walking at it
def test_robot_pressed_by_people_settles_for_the_polite_gap_after_its_patience(gap, vel):
    s = _robot_facing(8.0 + 0.35 + 0.4 + gap + 5.0j, vel)
    assert abs(_held_for(s, 0.5 * PINNED_PATIENCE)) < 1e-9  # not yet
    out = _held_for(s, PINNED_PATIENCE)
    assert out.real > 0.1  # on, toward them, down to POLITE_GAP
    assert s.policy[0].guard == pytest.approx(POLITE_GAP)


@pytest.mark.parametrize("where, vel, top", [
    (9.5 + 5.2j, 0.3 + 0j, 0.3),  # ahead, a little aside, walking its way: no faster than them
    (8.7 + 6.1j, 0.3 + 0j, FALL_BACK * 0.3),  # abreast, less than PASS_GAP aside (0.55 m away): it falls back
    (8.2 + 5.9j, 0.3 + 0j, 0.0),  # abreast within intimate space (0.17 m): it stops and lets them ahead
    (8.2 + 5.9j, 0.1 + 0j, 0.0),  # ... at any pace (two crawling abreast each held back for the other)
    (9.5 + 6.4j, 0.3 + 0j, float("inf")),  # far enough aside to pass them with room
    (11.0 + 5.0j, 0.3 + 0j, float("inf")),  # beyond personal space ahead: look-ahead's business
    (9.5 + 5.0j, -0.3 + 0j, float("inf")),  # walking toward it
    (7.0 + 5.0j, 0.3 + 0j, float("inf")),  # behind it
    (9.5 + 5.0j, 0j, float("inf")),  # standing
])
def test_robot_drives_no_faster_than_someone_walking_its_way_it_has_no_room_to_overtake(where, vel, top):
    s = _robot_facing(where, vel)
    assert follow_speed(s, 1.0 + 0j) == pytest.approx(top)


def _behind_someone_walking(world):  # noqa: ANN001, ANN202
    """A slow walker (0.3 m/s) 3 m ahead of the robot, going its way; the robot cruises at 0.6 m/s."""
    person = human(start=(5.0, 5.0), goals=[(19.5, 5.0)], max_vel=0.3)
    return make_sim([person], [WALK], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), world=world, timeout=70).run()


def test_robot_follows_someone_walking_its_way_in_a_corridor_too_narrow_to_overtake_them_with_its_gap():
    trace = _behind_someone_walking(_corridor(1.8))
    ahead = trace.humans[:, 0, 0] - trace.robot[:, 0]
    assert ahead.min() > trace.robot_radius + trace.human_radii[0]  # always behind them, never abreast
    assert _gaps(trace)[_driving(trace)].min() >= ROBOT_SOCIAL_GAP - 0.01
    late = trace.t > 20.0
    assert np.abs(trace.robot[late, 3]).mean() < 0.4  # at their pace, not its 0.6 m/s cruise


def test_robot_overtakes_someone_walking_its_way_where_there_is_room():
    trace = _behind_someone_walking(empty_room(20.0, 10.0))
    ahead = trace.humans[:, 0, 0] - trace.robot[:, 0]
    assert ahead.min() < -1.0  # it went past them
    assert trace.end_reason == "robot_goal"
    assert _gaps(trace)[_driving(trace)].min() >= ROBOT_SOCIAL_GAP - 0.01
