"""The world in metres: nearest obstacle points, clearance, line of sight, all through the transform."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.location.occupancy import OccupancyGrid
from socnavgen.location.transform import Transform
from socnavgen.sim import World, empty_room


def test_nearest_obstacle_is_on_the_wall_surface():
    world = empty_room(20.0, 10.0, resolution=0.05)  # walls are the border cells
    points = np.array([3 + 1j, 10 + 5j, 18.5 + 9j])
    obs, ok = world.nearest_obstacles(points)
    assert ok.all()
    # the bottom wall's inner surface is at y = 0.05 (one cell), the top one at y = 9.95, right at x = 19.95
    assert obs[0].imag == pytest.approx(0.05, abs=0.03) and obs[0].real == pytest.approx(3.0, abs=0.03)
    assert obs[2].imag == pytest.approx(9.95, abs=0.03)
    assert np.abs(points[1] - obs[1]) == pytest.approx(4.95, abs=0.03)


def test_obstacle_range_and_clearance():
    world = empty_room(40.0, 40.0, resolution=0.1)
    _, ok = world.nearest_obstacles(np.array([20 + 20j, 5 + 20j]))
    assert ok.tolist() == [False, True]  # the centre is more than 10 m from every wall
    assert world.clearance_at(np.array([20 + 20j]))[0] == pytest.approx(19.9, abs=0.11)
    assert world.clearance_at(np.array([-5 + 0j]))[0] == 0.0  # outside the map
    assert world.clearance_at_point(20 + 20j) == world.clearance_at(np.array([20 + 20j]))[0]
    grid = np.array([[5 + 5j, 5 + 0.02j], [39.99 + 20j, 50 + 50j]])
    assert world.clearance_at(grid).shape == (2, 2)  # any shape in, the same shape out


def test_line_of_sight_on_a_flipped_rotated_transform():
    occ = np.zeros((100, 100), dtype=bool)
    occ[:, 50] = True  # a wall down the middle column of the image
    # rotated 90 degrees: image columns run along world y
    transform = Transform([[0.0, -0.1, 10.0], [0.1, 0.0, 0.0], [0.0, 0.0, 1.0]])
    world = World(OccupancyGrid(occupied=occ, unknown=np.zeros_like(occ)), transform)
    a = complex(*transform.pixel_to_world(20, 40))
    b = complex(*transform.pixel_to_world(80, 40))
    c = complex(*transform.pixel_to_world(20, 90))
    assert world.line_of_sight(a, np.array([b, c])).tolist() == [False, True]
    assert world.free_along(a, (b - a) / abs(b - a), 6.0, 0.3) == pytest.approx(2.7, abs=0.1)


def test_segments_clear_draws_each_segment_as_line_of_sight_draws_it_alone():
    """The verifier's batched sight test gives, for each segment, the answer of the one-segment test, whatever
    the other segments in the batch; a segment is blocked exactly when a sample between its ends falls on a
    blocked cell (checked against a brute-force walk along it)."""
    world = empty_room(12.0, 8.0, walls=[(3.0, 2.0, 3.4, 6.0), (7.0, 0.0, 7.3, 5.0), (5.0, 6.5, 5.05, 6.55)])
    rng = np.random.default_rng(7)
    a = rng.uniform(0.3, 11.7, 400) + 1j * rng.uniform(0.3, 7.7, 400)
    b = a + (rng.uniform(-1, 1, 400) + 1j * rng.uniform(-1, 1, 400)) * rng.choice([0.05, 0.5, 4.0, 12.0], 400)
    batched = world.segments_clear(a, b)
    one_by_one = [bool(world.line_of_sight(complex(p), complex(q))[0]) for p, q in zip(a, b, strict=True)]
    assert batched.tolist() == one_by_one
    assert 20 < sum(one_by_one) < 380  # both answers occur

    def brute(p: complex, q: complex) -> bool:  # every 1 mm, the two end bodies' cells left out
        count = max(2, int(np.ceil(abs(q - p) / 0.025)) + 1)
        inner = p + (q - p) * np.linspace(0, 1, count)[1:-1]
        return bool(world.clearance_at(inner).min(initial=1.0) > 0) if len(inner) else True

    agree = sum(brute(complex(p), complex(q)) == clear for p, q, clear in zip(a, b, one_by_one, strict=True))
    assert agree == len(a)


def test_free_along_stops_before_a_wall():
    world = empty_room(10.0, 4.0, walls=[(6.0, 0.0, 6.5, 4.0)])
    assert world.free_along(2 + 2j, 1 + 0j, 10.0, 0.4) == pytest.approx(6.0 - 0.4 - 2.0, abs=0.08)
    assert world.free_along(2 + 2j, -1 + 0j, 1.0, 0.4) == 1.0  # room for the whole distance
    assert world.free_along(6.2 + 2j, 1 + 0j, 1.0, 0.4) == 0.0  # already inside a wall
