"""Someone who stands out of the robot's way (outside the corridor its body sweeps, as the verifier's inway and
aside judge it: proxemics.WAY_MARGIN_VERIFY) yet near enough its path to step farther off never walks back into
that corridor on the way to their spot: across the robot's path in front of it is no way out of its way
(warehouse_22: a worker 0.87 m off the robot's next leg crossed it to its far side as the robot turned onto it)."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen import proxemics
from socnavgen.sim import empty_room, load_policy
from socnavgen.sim.people.side_step import GIVE_WAY_MARGIN, plan_side_step
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml
from tests.sim.test_give_way import ROOMS, to_path


@pytest.mark.parametrize("seed", range(2))
def test_a_person_out_of_the_robots_way_never_walks_back_into_it(seed: int):
    """In a room where the robot's path turns twice, everyone standing just outside its corridor plans a side
    step (each from where they stand, the robot somewhere on its first leg): the walk to the spot (by way of where
    they back out to, if they do) keeps out of the corridor all the way."""
    rng = np.random.default_rng(seed)
    width, height, walls, path = ROOMS["room"]
    world = empty_room(width, height, walls=walls)
    waypoints = np.array([complex(*w) for w in path])
    judged = 0
    for _ in range(15):
        people = [human(f"human{k + 1}", start=(float(rng.uniform(0.8, width - 0.8)),
                                                float(rng.uniform(0.7, height - 0.7)))) for k in range(10)]
        sim = make_sim(people, [tree_xml(REGULAR)] * 10, path, policy=load_policy("waypoints"), world=world)
        robot = waypoints[0] + (waypoints[1] - waypoints[0]) * rng.uniform(0.05, 0.95)
        sim.robot.pos = robot
        upcoming = np.concatenate([[robot], waypoints[1:]])
        for i in range(10):
            p, radius = complex(sim.people[i].pos), float(sim.people[i].radius)
            corridor = radius + float(sim.robot.radius) + proxemics.WAY_MARGIN_VERIFY
            (here,), _ = to_path(np.array([p]), upcoming)
            if not corridor <= here < radius + float(sim.robot.radius) + GIVE_WAY_MARGIN:
                continue
            judged += 1
            plan_side_step(sim.state, i)
            via, spot = complex(sim.people[i].aside_via), complex(sim.people[i].aside)
            walk = np.concatenate([p + (via - p) * np.linspace(0, 1, 30), via + (spot - via) * np.linspace(0, 1, 30)])
            assert to_path(walk, upcoming)[0].min() >= corridor - 1e-6, (p, via, spot)
    assert judged >= 8
