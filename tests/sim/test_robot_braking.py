"""The default robot brakes within the comfort limit (bodies.COMFORT_DECELERATION) where a comfortable stop keeps it
clear of people, and harder only when a collision is imminent (issue 29: its smooth_braking check passed in 22 % of the
acceptance campaign's episodes, against 60 % for the deliberately rude robot)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socnavgen.bodies import COMFORT_DECELERATION, CONTACT_MARGIN
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


@pytest.mark.parametrize(("gap", "speed", "toward", "hard"), [
    (1.0, 0.6, True, False),  # a comfortable stop (0.12 m) ends well short of its 0.3 m field
    (0.4, 0.6, True, True),  # it would end inside the field (0.4 - 0.3 - 0.03 m left, 0.12 m needed): imminent
    (0.4, 0.6, False, False),  # driving away from them
    (0.35, 0.2, True, False),  # slow: 1.3 cm to stop
])
def test_robot_brakes_harder_than_comfortable_only_when_a_comfortable_stop_would_take_it_into_someones_space(
        gap: float, speed: float, toward: bool, hard: bool):
    from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
    from socnavgen.sim.robot.brake import brake_limit

    person = human(start=(10.0, 5.0), goals=[(10.0, 5.0)])
    sim = make_sim([person], [STAND], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy())
    robot = sim.state.robot[0]
    robot.pos = complex(10.0 - PERSON_RADIUS - ROBOT_RADIUS - gap, 5.0)
    robot.vel = complex(speed if toward else -speed, 0.0)
    sim.state.policy[0].guard = 0.3
    limit = brake_limit(sim.state)
    assert math.isnan(limit) if hard else limit == COMFORT_DECELERATION


