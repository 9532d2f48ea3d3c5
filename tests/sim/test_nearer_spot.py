"""world.spots.nearer_spot: the one rule for where the polite robot stops short of someone at its goal, when the
run ends so and when the verifier counts it as arrived (sim.arrival.no_nearer_spot)."""

from __future__ import annotations

import numpy as np

from socnavgen import proxemics
from socnavgen.sim.arrival import NO_WALLS
from socnavgen.sim.world.spots import nearer_spot

RR, PR = 0.35, 0.4  # robot and person radii


def _people(*points: complex) -> np.recarray:
    out = np.zeros(len(points), dtype=[("pos", "c16"), ("radius", "f8")]).view(np.recarray)
    out.pos[:] = points
    out.radius[:] = PR
    return out


def test_a_free_room_round_the_goal_leaves_a_nearer_spot():
    """A person standing just beside the goal, the robot 2 m off on the other side: a spot at least NEARER_SPOT nearer
    the goal that keeps the robot as far from them exists (it must go on; stopping here is not arriving)."""
    goal, robot = 0j, -2.0 + 0j
    found, spot = nearer_spot(NO_WALLS, goal, robot, RR, _people(0.9 + 0j))
    assert found
    assert abs(spot - goal) <= abs(robot - goal) - proxemics.NEARER_SPOT + 1e-9
    own = abs(0.9 - robot) - PR - RR
    assert abs(spot - 0.9) - PR - RR >= min(own, proxemics.GOAL_STOP_GAP) - 1e-9


def test_someone_on_the_goal_with_the_robot_at_a_social_distance_leaves_none():
    """The person stands on the goal and the robot already stands GOAL_STOP_GAP from them: every spot nearer the goal
    is nearer them, so there is none (it has arrived short of them)."""
    goal = 0j
    robot = -(RR + PR + proxemics.GOAL_STOP_GAP) + 0j
    found, _ = nearer_spot(NO_WALLS, goal, robot, RR, _people(goal))
    assert not found


def test_a_robot_near_the_goal_has_no_nearer_spot_to_go_to():
    found, _ = nearer_spot(NO_WALLS, 0j, 0.3 + 0j, RR, _people(3.0 + 0j))
    assert not found  # it is within NEARER_SPOT of the goal already
