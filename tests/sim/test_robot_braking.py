"""The default robot brakes within the comfort limit (bodies.COMFORT_DECELERATION) where a comfortable stop keeps it
clear of people, and harder only when a collision is imminent (issue 29: its smooth_braking check passed in 22 % of the
acceptance campaign's episodes, against 60 % for the deliberately rude robot)."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import COMFORT_DECELERATION, CONTACT_MARGIN
from socnavgen.sim import empty_room
from socnavgen.sim.behaviour_checks import ExpectedCheck, Situation, smooth_braking
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

WALK = tree_xml(REGULAR)
STAND = tree_xml('<LookAtRobot agent_id="{id}"/>')


def _braking(trace) -> tuple[bool, float]:  # noqa: ANN001
    """(within the comfort limit?, the hardest deceleration in m/s2) as the campaign's smooth_braking check says."""
    outcome = smooth_braking(Situation(trace, None, None), ExpectedCheck(check="smooth_braking"))
    return outcome.passed, outcome.value


def _gaps(trace) -> np.ndarray:  # noqa: ANN001
    d = np.hypot(trace.humans[:, :, 0] - trace.robot[:, None, 0], trace.humans[:, :, 1] - trace.robot[:, None, 1])
    return (d - trace.robot_radius - trace.human_radii[None, :]).min(axis=1)


def test_robot_meeting_a_walker_head_on_or_a_person_standing_brakes_comfortably():
    cases = {"head-on": (human(start=(16.0, 5.0), goals=[(2.0, 5.0)]), WALK),
             "head-on, a little left": (human(start=(16.0, 5.4), goals=[(2.0, 5.4)]), WALK),
             "standing on its line": (human(start=(10.0, 5.0), goals=[(10.0, 5.0)]), STAND)}
    for name, (person, tree) in cases.items():
        trace = make_sim([person], [tree], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), timeout=90).run()
        assert trace.end_reason == "robot_goal", name
        assert _gaps(trace).min() > CONTACT_MARGIN, name
        smooth, top = _braking(trace)
        assert smooth and top <= COMFORT_DECELERATION + 1e-6, (name, top)


def test_robot_brakes_hard_when_someone_steps_out_right_in_front_of_it():
    # a person steps out of a door in a wall 0.5 m beside the robot's line just as it comes by: a comfortable stop
    # would take it into them; it brakes harder and touches nobody
    world = empty_room(20.0, 10.0, walls=[(0.0, 5.9, 9.5, 6.1), (10.5, 5.9, 20.0, 6.1)])
    person = human(start=(10.0, 7.0), goals=[(10.0, 2.0)], start_delay=10.0)
    trace = make_sim([person], [WALK], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), world=world, timeout=90).run()
    assert _gaps(trace).min() > CONTACT_MARGIN
    assert _braking(trace)[1] > COMFORT_DECELERATION  # it had to brake harder than comfortable
