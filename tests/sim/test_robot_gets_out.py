"""A way the default robot stood for good short of its goal (issue 29, the README ranking's timeouts): it counted
itself arrived short of someone standing beside its goal who was no nearer the goal than it (the run's rule,
proxemics.short_of_goal, did not: card narrow-hallway [warehouse])."""

from __future__ import annotations

import cmath
import math

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import ROBOT_GOAL_TOLERANCE
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

STAND = tree_xml(REGULAR)  # their only goal is where they stand
RR, PR = 0.35, 0.4  # the default robot's and a person's radii


def test_robot_nearer_its_goal_than_the_person_standing_beside_it_drives_on_to_it():
    """The person stands 1.18 m from the goal, the robot 1.14 m on the other side, a hair inside the social distance
    it keeps from someone at its goal (the point at that distance lies 0.08 m behind it, within its arrival
    tolerance). She is not nearer the goal than the robot, so it has not arrived short of her: it must drive on. The
    old rule measured the stop point, not the robot, and stood there for good."""
    goal = 8.0 + 5.0j
    theta = math.acos(1.0 - ((RR + PR + proxemics.GOAL_STOP_GAP - 0.08) ** 2) / (2 * 1.18 * 1.14))
    person = goal + 1.18 * cmath.exp(1j * theta)
    start = goal + 1.14
    sim = make_sim([human(start=(person.real, person.imag), goals=[(person.real, person.imag)])], [STAND],
                   [(start.real, start.imag), (goal.real, goal.imag)], ScriptedPolicy(), timeout=30.0)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    robot = trace.robot[:, 0] + 1j * trace.robot[:, 1]
    assert abs(robot[-1] - goal) <= ROBOT_GOAL_TOLERANCE
    gaps = np.abs(trace.humans[:, 0, 0] + 1j * trace.humans[:, 0, 1] - robot) - RR - PR
    assert gaps.min() > 0.0  # it never touched her

