"""The world in metres: nearest obstacle points, clearance, line of sight, all through the transform."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.location.occupancy import OccupancyGrid
from socnavgen.location.transform import Transform
from socnavgen.sim.world import World, empty_room


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


def test_segments_clear_agrees_with_line_of_sight_segment_by_segment():
    """The verifier's batched sight test draws each segment as the simulator's line_of_sight draws it
    alone, whatever the lengths of the other segments in the batch (short ones near walls included)."""
    world = empty_room(12.0, 8.0, walls=[(3.0, 2.0, 3.4, 6.0), (7.0, 0.0, 7.3, 5.0), (5.0, 6.5, 5.05, 6.55)])
    rng = np.random.default_rng(7)
    a = rng.uniform(0.3, 11.7, 400) + 1j * rng.uniform(0.3, 7.7, 400)
    b = a + (rng.uniform(-1, 1, 400) + 1j * rng.uniform(-1, 1, 400)) * rng.choice([0.05, 0.5, 4.0, 12.0], 400)
    batched = world.segments_clear(a, b, chunk=16, reference=True)
    one_by_one = [bool(world.line_of_sight(complex(p), complex(q), reference=True)[0]) for p, q in zip(a, b, strict=True)]
    assert batched.tolist() == one_by_one
    assert 20 < sum(one_by_one) < 380  # both answers occur
    # the compiled twins (numba) give the same answers, batched and one by one
    assert world.segments_clear(a, b).tolist() == one_by_one
    assert [bool(world.line_of_sight(complex(p), complex(q))[0]) for p, q in zip(a, b, strict=True)] == one_by_one


def test_compiled_sight_on_a_rotated_map_and_off_it():
    """Segments leaving the map or crossing a rotated grid: compiled and numpy sight agree sample for sample."""
    occ = np.zeros((60, 90), dtype=bool)
    occ[20:40, 40:44] = True
    transform = Transform.from_nav2(0.1, [-3.0, 2.0, 0.6], 60)
    world = World(OccupancyGrid(occupied=occ, unknown=np.zeros_like(occ)), transform)
    rng = np.random.default_rng(3)
    a = rng.uniform(-6, 8, 300) + 1j * rng.uniform(-2, 10, 300)
    b = a + rng.uniform(-6, 6, 300) + 1j * rng.uniform(-6, 6, 300)
    ref = world.segments_clear(a, b, reference=True)
    assert world.segments_clear(a, b).tolist() == ref.tolist()
    assert 10 < int(ref.sum()) < 290
