"""The map's segment checks (line of sight, a body's straight walk, free room along a direction) skip the samples
their first reads prove clear (world.queries.sure_clear); their answers must be those of reading every sample, on
any map: walls inside and none, free cells on the map's border (a segment that leaves the map), a rotated map."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.location.occupancy import OccupancyGrid
from socnavgen.location.transform import Transform
from socnavgen.sim import World, empty_room
from socnavgen.sim.world import queries
from socnavgen.sim.world.routes import walkable_straight


def _every_sample_clear(world, points, clearance) -> bool:  # noqa: ANN001
    return all(queries.clearance_at(world, complex(p)) >= clearance for p in points)


def _line_of_sight(world, a, b) -> bool:  # noqa: ANN001
    if not world.has_obstacles:
        return True
    count = max(2, int(math.ceil(abs(b - a) / (0.5 * world.mpp))) + 1)
    for k in range(1, count - 1):
        row, col = queries.cell_of(world, a + (b - a) * (k * (1.0 / (count - 1))))
        if not (0 <= row < world.blocked.shape[0] and 0 <= col < world.blocked.shape[1]) or world.blocked[row, col]:
            return False
    return True


def _walkable_straight(world, a, b, clearance, near_end) -> bool:  # noqa: ANN001
    d, n = b - a, max(1, int(abs(b - a) / 0.1))
    points = [a + d * (k / n) for k in range(1, n + 1) if not abs(d) * (1.0 - k / n) < near_end]
    return _every_sample_clear(world, points, clearance)


def _path_clear(world, a, b, clearance) -> bool:  # noqa: ANN001
    n = max(2, int(abs(b - a) / 0.1) + 1)
    return _every_sample_clear(world, [a + (b - a) * (1.0 if k == n - 1 else k / (n - 1)) for k in range(n)], clearance)


def _swept_clear(world, a, b, clearance) -> bool:  # noqa: ANN001
    n = max(2, int(math.ceil(abs(b - a) / (0.5 * world.mpp))) + 1)
    return _every_sample_clear(world, [a + (b - a) * (k / (n - 1)) for k in range(1, n)], clearance)


def _free_along(world, start, direction, max_distance, radius) -> float:  # noqa: ANN001
    steps = max(2, int(max_distance / (0.5 * world.mpp)) + 1)
    step = max_distance / (steps - 1)
    for k in range(steps):
        if queries.clearance_at(world, start + direction * (k * step)) < radius:
            return (k - 1) * step if k > 0 else 0.0
    return max_distance


def _worlds() -> dict[str, World]:
    rng = np.random.default_rng(7)
    blobs = np.zeros((160, 200), dtype=bool)  # walls scattered inside, the border free (segments leave the map)
    for _ in range(25):
        r, c = rng.integers(0, 160), rng.integers(0, 200)
        blobs[r:r + rng.integers(1, 12), c:c + rng.integers(1, 12)] = True
    rotated = Transform([[0.0, -0.1, 10.0], [0.1, 0.0, 0.0], [0.0, 0.0, 1.0]])
    return {"walled room with boxes": empty_room(12.0, 9.0, 0.05, walls=[(3.0, 2.0, 4.0, 7.0), (7.0, 0.0, 7.2, 5.0)]),
            "no walls at all": World(OccupancyGrid(occupied=np.zeros((90, 120), bool), unknown=np.zeros((90, 120), bool)),
                                     Transform.from_nav2(0.1, [0.0, 0.0, 0.0], 90)),
            "free border, scattered walls": World(OccupancyGrid(occupied=blobs, unknown=np.zeros_like(blobs)),
                                                  Transform.from_nav2(0.05, [-1.0, 2.0, 0.0], 160)),
            "rotated map": World(OccupancyGrid(occupied=blobs, unknown=np.zeros_like(blobs)), rotated)}


@pytest.mark.parametrize("name", list(_worlds()))
def test_segment_checks_answer_as_reading_every_sample(name: str) -> None:
    world = _worlds()[name]
    corners = world.transform.pixels_to_world(np.array([[0, 0], [world.width, world.height]], dtype=float))
    lo, hi = corners.min(axis=0) - 1.0, corners.max(axis=0) + 1.0  # a metre beyond the map on every side
    rng = np.random.default_rng(hash(name) % 2**32)
    m, answers = world.map, set()
    for _ in range(400):
        a, b = (complex(*rng.uniform(lo, hi)) for _ in range(2))
        clearance = float(rng.choice([0.0, 0.05, 0.35, 0.6, 1.5]))
        near_end = float(rng.choice([0.0, 0.5]))
        unit = (b - a) / abs(b - a)
        cases = [(queries.line_of_sight(m, a, b), _line_of_sight(m, a, b)),
                 (walkable_straight(m, a, b, clearance, near_end), _walkable_straight(m, a, b, clearance, near_end)),
                 (queries.path_clear(m, a, b, clearance), _path_clear(m, a, b, clearance)),
                 (queries.swept_clear(m, a, b, clearance), _swept_clear(m, a, b, clearance)),
                 (queries.free_along(m, a, unit, abs(b - a), clearance), _free_along(m, a, unit, abs(b - a), clearance))]
        for got, want in cases:
            assert got == want, (name, a, b, clearance)
        answers.add(tuple(bool(g) for g, _ in cases[:4]))
    assert len(answers) > 1 or name == "no walls at all"  # the segments met walls and open floor both
