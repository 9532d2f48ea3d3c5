"""The range scan and the route ahead (robot.sensors) on a small map: a 10 x 6 m room with a wall from the floor
to 4 m high at x = 5 m, so the way from (2, 1) to (8, 1) leads over its top."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.sim.robot.fields import field_scale, route_fields
from socnavgen.sim.robot.sensors import beam_directions, range_scan, resample, route_ahead
from socnavgen.sim.world.grid import empty_room

START, GOAL = 2 + 1j, 8 + 1j


@pytest.fixture(scope="module")
def room():  # noqa: ANN201
    return empty_room(10, 6, walls=[(5.0, 0.0, 5.2, 4.0)])


def _surface(world, origin: complex, direction: complex) -> float:  # noqa: ANN001
    """Distance to the first blocked cell along a ray, found cell by cell (a reference for the scan)."""
    for d in np.arange(0.001, 20.0, 0.001):
        rows, cols, inside = world.to_cells(np.array([origin + d * direction]))
        if not inside[0] or world.blocked[rows[0], cols[0]]:
            return float(d)
    return np.inf


def test_the_scan_reads_each_wall_at_its_range(room) -> None:  # noqa: ANN001
    scan = range_scan(room, START, 0.0, 8, 8.0)
    assert scan.shape == (8,) and scan.dtype == np.float32
    for beam, direction in enumerate(beam_directions(0.0, 8)):
        assert abs(scan[beam] - _surface(room, START, direction)) <= 0.5 * room.mpp + 1e-6
    assert abs(scan[0] - 2.95) < 0.05  # the wall ahead (its face, rasterised, at x ~ 4.95)
    assert abs(scan[6] - 0.95) < 0.05  # the floor's wall 1 m below, beam 6 = 270 degrees
    # turned to face +y, beam 0 reads what beam 2 read (the scan is in the robot's frame)
    assert range_scan(room, START, np.pi / 2, 8, 8.0)[0] == pytest.approx(scan[2], abs=1e-6)
    # beyond the range: max_range
    assert range_scan(room, START, 0.0, 8, 2.0)[0] == pytest.approx(2.0)


def test_the_scan_sees_people_as_discs_in_front_of_walls(room) -> None:  # noqa: ANN001
    people, radii = np.array([3.5 + 1j, 2 + 1.5j, 2 - 3j]), np.array([0.3, 0.2, 0.3])
    scan = range_scan(room, START, 0.0, 8, 8.0, people, radii)
    alone = range_scan(room, START, 0.0, 8, 8.0)
    assert scan[0] == pytest.approx(1.2, abs=1e-5)  # 1.5 m ahead, radius 0.3
    assert scan[2] == pytest.approx(0.3, abs=1e-5)  # 0.5 m to its left, radius 0.2
    assert scan[6] == pytest.approx(alone[6])  # the third stands behind the wall below: the wall hides them
    assert np.allclose(np.delete(scan, [0, 2]), np.delete(alone, [0, 2]))
    inside = range_scan(room, START, 0.0, 8, 8.0, np.array([START + 0.1]), np.array([0.3]))
    assert np.all(inside[[0, 1, 7]] == 0.0)  # overlapping its centre: zero along the beams that cross them


def test_the_route_leads_around_the_wall(room) -> None:  # noqa: ANN001
    waypoints = np.array([START, GOAL])
    fields = route_fields(room, waypoints, 0.3)
    ahead = route_ahead(room, fields, field_scale(room), waypoints, 1, START, 40, 0.5)
    assert ahead.shape == (40,)
    assert np.allclose(np.abs(np.diff(np.concatenate([[START], ahead[:8]]))), 0.5, atol=0.08)  # spaced 0.5 m
    way = np.concatenate([[START], ahead])
    assert room.segments_clear(way[:-1], way[1:]).all()  # never through the wall
    assert (room.clearance_at(ahead) >= 0.27).all()  # a 0.3 m disc fits on every point (INFLATE x radius)
    passing = ahead[np.abs(ahead.real - 5.1) < 0.3]
    assert len(passing) and (passing.imag > 4.0).all()  # it crosses x = 5 above the wall's top
    assert abs(ahead[-1] - GOAL) < 1e-9 and ahead[0].real < 3.0  # ends at the goal, starts near the robot
    # the straight line would go through the wall: the first route points do not point at the goal
    first = ahead[3] - START
    assert np.angle(first) > np.pi / 5


def test_the_route_goes_through_every_remaining_waypoint(room) -> None:  # noqa: ANN001
    waypoints = np.array([START, 3 + 5j, GOAL])
    fields = route_fields(room, waypoints, 0.3)
    ahead = route_ahead(room, fields, field_scale(room), waypoints, 1, START, 60, 0.25)
    assert np.abs(ahead - (3 + 5j)).min() < 0.15  # passes the intermediate waypoint
    assert abs(ahead[-1] - GOAL) < 1e-9
    # past the first waypoint (index 2), it heads straight for the last
    later = route_ahead(room, fields, field_scale(room), waypoints, 2, 3 + 5j, 4, 0.5)
    assert np.abs(later - (3 + 5j)).max() <= 2.0 + 1e-6 and later[1].real > 3.0


def test_resample_repeats_the_end() -> None:
    points = resample(np.array([0j, 1 + 0j]), 4, 0.4)
    assert np.allclose(points, [0.4, 0.8, 1.0, 1.0])
    assert np.allclose(resample(np.array([2j]), 3, 1.0), 2j)
