"""Someone squeezed nearer a wall than their body's radius (pushed into a corner by the people beside them) still
finds a side step: the directions that open up away from the wall are walkable from where they stand, and a spot
counts only where their body has its room (side_step.side_spot, queries.free_opening). Before, every direction was
blocked at the start itself, no spot was found and they waited in the robot's way (home_05: a guest pushed into a
corner 0.35 m from the wall, 0.72 m off the robot's route, waited there until the robot had crept past her)."""

from __future__ import annotations

import numpy as np

from socnavgen import proxemics
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.people.side_step import plan_side_step
from socnavgen.sim.world.queries import clearance_at
from tests.sim.simhelpers import give_way_tree, human, make_sim
from tests.sim.test_give_way import to_path

PATH = [(1.5, 1.1), (18.5, 1.1)]  # the robot's way along a 4 m wide corridor, 1.05 m off its south wall
SQUEEZED = 0.35  # m from the wall to the person's centre: less than their radius (0.4)
GATE = '<IsRobotNearby agent_id="{id}" distance="6.0"/>'


def corridor_sim(robot_x: float):  # noqa: ANN201
    """The corridor with one person squeezed against its south wall at x = 10, the robot on its way at robot_x."""
    world = empty_room(20.0, 4.0)
    y = next(y for y in np.arange(0.2, 1.0, 0.005) if clearance_at(world.map, complex(10.0, y)) >= SQUEEZED)
    sim = make_sim([human("human1", start=(10.0, float(y)), goals=[(10.0, float(y))])], [give_way_tree(GATE)],
                   [(robot_x, 1.1), PATH[1]], policy=load_policy("waypoints"), world=world, timeout=40)
    return sim, world


def corridor_width(sim) -> float:  # noqa: ANN001
    return float(sim.people[0].radius + sim.robot.radius + proxemics.WAY_MARGIN_VERIFY)


def test_a_squeezed_person_plans_a_spot_out_of_the_robots_way():
    """Planned from where they stand (nearer the wall than their radius, inside the robot's corridor): the spot
    is out of the corridor, and their body has its room there. Before: the spot was where they stood."""
    sim, world = corridor_sim(6.0)
    p = complex(sim.people[0].pos)
    assert clearance_at(world.map, p) < float(sim.people[0].radius)  # squeezed, as meant
    assert to_path(np.array([p]), np.array([complex(*w) for w in PATH]))[0][0] < corridor_width(sim)  # in its way
    plan_side_step(sim.state, 0)
    spot = complex(sim.people[0].aside)
    assert to_path(np.array([spot]), np.array([complex(*w) for w in PATH]))[0][0] >= corridor_width(sim), spot
    assert clearance_at(world.map, spot) >= float(sim.people[0].radius), spot


def test_a_squeezed_person_gets_out_of_the_robots_corridor_before_it_comes_by():
    """The robot comes along the corridor (4 m off, 6 m or less: they give way): while it comes up within 2 m of
    them, they stand out of its corridor (as the verifier's inway judges it), and it gets through. Before: they
    waited 0.7 m off its way."""
    sim, _ = corridor_sim(6.0)
    trace = sim.run()
    robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    person = trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1]
    near = (np.abs(robot - person) <= 2.0) & (robot.real <= person.real)  # coming up to them, not yet by
    assert near.any()
    off = to_path(person[near], np.array([complex(*w) for w in PATH]))[0]
    assert off.min() >= corridor_width(sim) - 1e-6, off.min()
    assert abs(robot[-1] - complex(*PATH[1])) < 0.5, robot[-1]  # through to its goal
