"""The cell list of large crowds (sim/people/neighbours.py): the contact step and the social force find the
same pairs through it as over every pair, however the crowd is spread."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim import HumanSpec, empty_room
from socnavgen.sim.engine.state import ROBOT, singleton
from socnavgen.sim.people.neighbours import active, build, new_grid
from socnavgen.sim.people.physics import SFMParams, resolve_contacts, social_dense, social_grid
from socnavgen.sim.people.state import new_people


def people_at(points: np.ndarray):  # noqa: ANN201
    specs = [HumanSpec(name=f"human{k + 1}", start=(p.real, p.imag), goals=[(p.real, p.imag)])
             for k, p in enumerate(points)]
    people, _, _ = new_people(specs)
    people.walks = True
    return people


def contacts_after(points: np.ndarray, cells: bool) -> np.ndarray:
    """Positions after one contact step, with or without the cell list."""
    people = people_at(points)
    n = len(points)
    grid = new_grid(n, cells=cells)
    if cells:
        build(grid, people, SFMParams().cutoff)
    world = empty_room(2000.0, 2000.0, resolution=1.0).map
    robot = singleton(ROBOT, pos=-500 - 500j, radius=0.3, heading=1 + 0j)[0]
    resolve_contacts(people, robot, world, 0.0, people.pos.copy(), np.zeros(n, complex), grid)
    return people.pos.copy()


@pytest.mark.parametrize("spread", [6.0, 40.0, 1500.0])
def test_the_contact_step_separates_the_same_pairs_in_the_same_order(spread):
    """A crowd packed tightly enough that many pairs overlap (in chains), in a small square, a large one, and
    spread over more cells than were made (the cells grow): the very same positions as over every pair."""
    rng = np.random.default_rng(int(spread))
    n = 120
    points = 20 + rng.uniform(0, spread, n) + 1j * (20 + rng.uniform(0, spread, n))
    points[:10] = points[10] + 0.3 * np.arange(10)  # a chain of overlaps
    points[20] = points[21]  # two people at the same spot
    every, cells = contacts_after(points, False), contacts_after(points, True)
    assert not np.array_equal(every, points)  # someone was pushed apart
    assert np.array_equal(cells, every)


def test_the_cell_list_is_used_above_64_people_only():
    assert not active(new_grid(64), 64)
    assert active(new_grid(65), 65)


def test_a_crowd_spread_far_apart_gets_larger_cells_and_the_same_forces():
    """Two clusters 1 km apart: more cells than were made would be needed at the social force's cell size, so
    the cells grow; the forces still equal the sum over every pair (to rounding: the order of the sums differs)."""
    rng = np.random.default_rng(3)
    n = 100
    points = rng.uniform(0, 10, n) + 1j * rng.uniform(0, 10, n)
    points[n // 2:] += 1000 + 1000j
    people = people_at(points)
    people.vel = rng.normal(0, 0.7, n) + 1j * rng.normal(0, 0.7, n)
    grid = new_grid(n)
    build(grid, people, SFMParams().cutoff)
    dense, sparse = np.zeros(n, complex), np.zeros(n, complex)
    social_dense(people, SFMParams(), dense)
    social_grid(people, SFMParams(), grid, sparse)
    assert grid.dims[0] * grid.dims[1] <= grid.start.shape[0] - 1  # fits in the cells made
    assert np.abs(dense).max() > 0
    np.testing.assert_allclose(sparse, dense, rtol=0, atol=1e-12)
    assert math.isfinite(float(np.abs(sparse).sum()))
