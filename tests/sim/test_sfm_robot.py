"""The social-force robot (`sfm`, robot.social_force) on the classic cases of issue 29: an aisle barely wider than
the robot straight through, a door off the straight line, a person head-on and one crossing; it arrives in bounded
time without contact. With the pedestrians' one-point wall term (the nearest wall point, which jumps from one wall
to the other at an aisle's middle) it rocked from side to side in the aisle and crawled (~4 m in 40 s on the
warehouse's narrow hallway). And the border term itself: zero in the middle of a symmetric aisle, restoring and
continuous across it, bounded, damped."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import ROBOT_RADIUS
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.contact import trace_gaps
from socnavgen.sim.robot.social_force import across_walls
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

WALK = tree_xml(REGULAR)


def aisle(free: float) -> list[tuple[float, float, float, float]]:
    """Two shelves 14 m long (x 3..17) leaving an aisle of `free` m of free cells about y = 5 (a wall box also
    takes the cell its edge falls in: drawn 0.1 m farther apart)."""
    return [(3.0, 0.0, 17.0, 4.95 - free / 2), (3.0, 5.05 + free / 2, 17.0, 10.0)]


def _sfm(walls, people=(), timeout: float = 60.0, route=((2.0, 5.0), (18.0, 5.0))):  # noqa: ANN001, ANN202
    people = list(people)
    return make_sim(people, [WALK] * len(people), list(route), load_policy("sfm"),
                    world=empty_room(20.0, 10.0, walls=walls), timeout=timeout).run()


@pytest.mark.parametrize("free", [0.8, 1.0])
def test_sfm_drives_straight_through_an_aisle_barely_wider_than_itself(free: float) -> None:
    """0.8 m (the SocRATES small warehouse's passages) and 1.0 m aisles for the 0.7 m robot: 16 m at its 0.6 m/s
    take ~27 s; it keeps to the middle (no rocking from wall to wall) and never slows down in the aisle."""
    assert pytest.approx(0.7) == 2 * ROBOT_RADIUS
    trace = _sfm(aisle(free), timeout=35.0)
    assert trace.end_reason == "robot_goal", trace.robot[-1, :2]
    x, y = trace.robot[:, 0], trace.robot[:, 1]
    inside = (x > 4.0) & (x < 16.0)
    assert np.abs(y[inside] - np.median(y[inside])).max() < 0.04
    speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    assert speed[inside].min() > 0.5  # in the aisle (not only on average): no crawl


def test_sfm_goes_through_a_door_off_its_straight_line() -> None:
    """A wall across the room with a 1.0 m door 3.5 m off the straight line from start to goal."""
    walls = [(9.8, 0.0, 10.2, 6.0), (9.8, 7.0, 10.2, 10.0)]
    trace = _sfm(walls, timeout=40.0, route=((3.0, 3.0), (17.0, 3.0)))
    assert trace.end_reason == "robot_goal", trace.robot[-1, :2]
    assert trace.t[-1] < 30.0


def test_sfm_passes_a_person_head_on_in_a_corridor() -> None:
    """A 2.4 m corridor (room for the robot and a person side by side): they meet in the middle."""
    walls = [(3.0, 0.0, 17.0, 3.8), (3.0, 6.2, 17.0, 10.0)]
    trace = _sfm(walls, [human(start=(16.0, 5.0), goals=[(2.0, 5.0)])], timeout=60.0)
    gaps = trace_gaps(trace)
    assert trace.end_reason == "robot_goal", trace.robot[-1, :2]
    assert trace.t[-1] < 40.0
    assert 0.05 < gaps.min() < 1.0


def test_sfm_lets_a_crossing_person_by_and_arrives() -> None:
    """Someone crosses the robot's way in the open as it gets there."""
    trace = _sfm([], [human(start=(10.0, 1.5), goals=[(10.0, 11.0)], start_delay=11.5)], timeout=60.0,
                 route=((3.0, 5.0), (17.0, 5.0)))
    gaps = trace_gaps(trace)
    assert trace.end_reason == "robot_goal", trace.robot[-1, :2]
    assert trace.t[-1] < 40.0
    assert 0.05 < gaps.min() < 1.0


def _border_force(width: float, y: float, vy: float = 0.0) -> complex:
    sim = make_sim([], [], [(2.0, 5.0), (18.0, 5.0)], load_policy("sfm"), world=empty_room(20.0, 10.0, walls=aisle(width)))
    robot = sim.state.robot[0]
    robot.pos, robot.vel = complex(10.0, y), complex(1.0, vy)
    return complex(across_walls(sim.state, 1 + 0j, 1.0))


def test_border_force_balances_in_the_middle_of_an_aisle_and_restores_continuously() -> None:
    """Helbing & Molnar's sum over both walls: pointing back to the middle from either side, falling across
    the aisle in steps of the map's 5 cm cells, never a jump (the one-point term flips by ~8 m/s2 at the
    middle), across the way only, bounded by the robot's drive (k_des v0 / tau = 4 m/s2) even against a wall."""
    ys = np.arange(4.9, 5.1001, 0.01)
    forces = np.array([_border_force(1.0, y) for y in ys])
    assert np.abs(forces.real).max() < 1e-9  # across the way (x) only
    assert forces[0].imag > 0 > forces[-1].imag
    assert np.all(np.diff(forces.imag) < 0.2)  # falling, up to the cells' rounding of the two distances
    assert np.abs(np.diff(forces.imag)).max() < 1.5
    assert abs(_border_force(0.8, 5.04)) <= 4.0 + 1e-9
    assert abs(_border_force(1.0, 5.14)) <= 4.0 + 1e-9


def test_border_force_damps_sideways_motion_in_an_aisle() -> None:
    """Drifting across the aisle at its middle, the robot is held back against the drift (the critical damping of the
    walls' spring); in the open nothing acts."""
    assert _border_force(1.0, 5.0, vy=0.2).imag < -0.5
    assert _border_force(1.0, 5.0, vy=-0.2).imag > 0.5
    assert _border_force(9.0, 5.0, vy=0.2) == 0


def test_sfm_backs_out_of_a_corridor_too_narrow_to_pass_a_person_head_on() -> None:
    """A 1.3 m corridor (the robot's 0.7 m and a person's 0.8 m do not fit side by side), a person walking the
    other way to beyond the robot's start: after standing face to face for its patience the robot backs out of
    the corridor, lets them by, and drives on to its goal (on main they stood face to face, their social forces
    balancing, until the time limit)."""
    walls = [(3.0, 0.0, 17.0, 4.35), (3.0, 5.65, 17.0, 10.0)]  # 14 m long: too far for the person to back out
    trace = _sfm(walls, [human(start=(15.5, 5.0), goals=[(1.0, 8.0)])], timeout=120.0)
    assert trace.end_reason == "robot_goal", trace.robot[-1, :2]
    assert abs(complex(*trace.humans[-1, 0, :2]) - (1.0 + 8.0j)) < 1.0  # the person got through too
    assert trace_gaps(trace).min() > 0.0
