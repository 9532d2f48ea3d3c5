"""The one cost-to-go field (sim/world/costfield.py) that the walkable distances, the people's routes and the
robot's planner share: its cell-cost rule, its fields on small rooms worked out by hand, and that each of the
three users reads the same fields."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.sim.robot import fields as planner_fields
from socnavgen.sim.world import empty_room
from socnavgen.sim.world.costfield import CellCost, CostField
from socnavgen.sim.world.routes import PEOPLE, RouteGrid
from socnavgen.sim.world.walkable import WalkableDistance

# a 10 m x 6 m room split at x = 5 by a wall with a 1 m door at y 4.5-5.5
DOOR = [(4.95, 0.0, 5.05, 4.5), (4.95, 5.5, 5.05, 6.0)]


def test_the_cell_cost_rule_walls_the_narrow_cells_and_ramps_the_cost_near_walls() -> None:
    rule = CellCost(passable=0.3, full=0.3, comfort=0.6, extra=3.0)
    cost = rule.costs(np.array([0.0, 0.2, 0.3, 0.45, 0.6, 2.0]))
    assert np.isinf(cost[:2]).all()
    assert cost[2:].tolist() == pytest.approx([4.0, 2.5, 1.0, 1.0])
    plain = CellCost().costs(np.array([0.0, 0.05, 1.0]))  # only the walls themselves
    assert np.isinf(plain[0]) and plain[1:].tolist() == [1.0, 1.0]


def test_a_field_measures_metres_around_the_wall_and_nothing_through_a_closed_one() -> None:
    world = empty_room(10.0, 6.0, walls=DOOR)
    grid = CostField.of(world, CellCost(), 2)
    (r0,), (c0,) = grid.cells(np.array([4 + 1j]))
    (r1,), (c1,) = grid.cells(np.array([6 + 1j]))
    (r2,), (c2,) = grid.cells(np.array([1 + 1j]))
    field = grid.field(int(r0), int(c0))
    assert field[r0, c0] == 0
    assert field[r2, c2] == pytest.approx(3.0, abs=0.11)  # open floor: the straight distance
    around = 2 * math.hypot(0.9, 3.55) + 0.2  # through the door, any-angle
    assert around <= field[r1, c1] <= around * 1.12  # 8-connected on 0.1 m cells: a little longer
    closed = empty_room(10.0, 6.0, walls=[(4.95, 0.0, 5.05, 6.0)])
    grid = CostField.of(closed, CellCost(), 2)
    (r0,), (c0,) = grid.cells(np.array([4 + 1j]))
    (r1,), (c1,) = grid.cells(np.array([6 + 1j]))
    assert np.isinf(grid.field(int(r0), int(c0))[r1, c1])


def test_the_near_wall_cost_makes_the_way_along_a_wall_dearer_and_a_body_that_does_not_fit_has_none() -> None:
    world = empty_room(10.0, 6.0, walls=DOOR)
    plain, careful = CostField.of(world, CellCost(), 2), CostField.of(world, PEOPLE, 2)
    (r0,), (c0,) = plain.cells(np.array([4.6 + 0.2j]))  # pressed against the wall and the floor's edge
    (r1,), (c1,) = plain.cells(np.array([4.6 + 3.0j]))
    along_wall = plain.field(int(r1), int(c1))[r0, c0], careful.field(int(r1), int(c1))[r0, c0]
    assert np.isfinite(along_wall[0]) and np.isinf(along_wall[1])  # 0.15 m clearance: no person's centre
    (r0,), (c0,) = plain.cells(np.array([4.4 + 1.0j]))  # 0.45 m from the wall: half the extra cost
    assert careful.field(int(r1), int(c1))[r0, c0] > 2.0 * plain.field(int(r1), int(c1))[r0, c0]
    wide = CostField.of(world, CellCost(passable=0.6), 2)  # a door 1 m wide has no cell 0.6 m from both jambs
    (r2,), (c2,) = wide.cells(np.array([6 + 1j]))
    assert np.isinf(wide.field(int(r1), int(c1))[r2, c2])


def test_snapping_reaches_the_nearest_passable_cell_only_within_the_distance_given() -> None:
    world = empty_room(10.0, 6.0, walls=[(3.0, 2.0, 7.0, 4.0)])  # a 4 m x 2 m block
    grid = CostField.of(world, CellCost(), 2)
    rows, cols = grid.cells(np.array([5 + 2.2j, 5 + 3.0j]))
    assert not grid.passable[rows, cols].any()
    near_r, near_c = grid.snap(rows, cols, within=0.5)
    assert grid.passable[near_r[0], near_c[0]]  # 0.2 m inside the block: the floor below it
    assert (near_r[1], near_c[1]) == (rows[1], cols[1])  # 1 m inside: left where it is
    assert np.isinf(grid.field(int(rows[1]), int(cols[1]))).all()  # a field from a wall leads nowhere


def test_an_opened_source_lets_a_goal_drawn_against_a_wall_be_reached() -> None:
    world = empty_room(10.0, 6.0)
    rule = planner_fields.rule(0.3)
    grid = CostField.of(world, rule, 1)
    (r0,), (c0,) = grid.cells(np.array([5 + 0.1j]))  # 0.1 m from the wall: no 0.3 m robot fits
    (r1,), (c1,) = grid.cells(np.array([5 + 3j]))
    assert np.isinf(grid.field(int(r0), int(c0))[r1, c1])
    assert np.isfinite(grid.field(int(r0), int(c0), opened=planner_fields.GOAL_SEED)[r1, c1])


def test_the_three_users_read_one_kind_of_field() -> None:
    world = empty_room(10.0, 6.0, walls=DOOR)
    ways = WalkableDistance.of(world)
    (r,), (c,) = ways.cells(np.array([6 + 1j]))
    assert ways.field(int(r), int(c)) is CostField.of(world, CellCost(), ways.k).field(int(r), int(c))
    people = RouteGrid.of(world)
    assert people.field(6 + 1j) is CostField.of(world, PEOPLE, people.k).field(*people.cell(6 + 1j))
    robot = planner_fields.cost_to_go(world, 6 + 1j, 0.3)
    grid = CostField.of(world, planner_fields.rule(0.3), planner_fields.field_scale(world))
    (r,), (c,) = grid.cells(np.array([6 + 1j]))
    assert robot is grid.field(int(r), int(c), opened=planner_fields.GOAL_SEED)


def test_along_the_middle_a_narrow_passage_costs_its_length_and_its_sides_still_cost_more() -> None:
    # a 1 m aisle (clearance 0.5 m at its middle on 5 cm cells) for a 0.35 m robot: comfort is 0.75 m, so every
    # cell of the aisle paid the near-wall cost (its middle 2.9 per metre); counted from the middle, the middle
    # costs 1 as open floor does
    world = empty_room(6.0, 4.0, walls=[(0.0, 0.0, 6.0, 1.45), (0.0, 2.55, 6.0, 4.0)])
    radius = 0.35
    flat, middle = (CellCost(passable=0.9 * radius, full=radius, comfort=radius + 0.4, extra=3.0, along_middle=m)
                    for m in (False, True))
    cell = 0.05
    clearance = np.asarray(world.clearance)
    rows, cols, _ = world.to_cells(np.array([3 + 2j, 3 + 2.1j, 3 + 2.15j]))  # the middle, 10 and 15 cm off it
    old, new = flat.costs(clearance, cell)[rows, cols], middle.costs(clearance, cell)[rows, cols]
    assert clearance[rows[0], cols[0]] == pytest.approx(0.5, abs=0.06)  # the middle (map cells of 5 cm)
    assert old[0] > 2.5 and new[0] == pytest.approx(1.0)
    assert 1.0 < new[1] < new[2] <= old[2]  # off the middle it still costs more the nearer the wall
    open_room = np.asarray(empty_room(6.0, 6.0).clearance)  # on open floor the two rules agree
    assert np.allclose(flat.costs(open_room, cell), middle.costs(open_room, cell))
    assert planner_fields.rule(radius).along_middle  # the robot's planner counts along the middle
