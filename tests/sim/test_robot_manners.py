"""The default robot's manners in a corridor (robot.polite): it passes a standing person at a social distance where
the corridor leaves room, slowly where it does not, and it waits beside the walkway, not in its middle."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import INTIMATE_SPACE
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.polite import CLOSE_SPEED
from tests.sim.simhelpers import human, make_sim, tree_xml

STAND = tree_xml('<LookAtRobot agent_id="{id}"/>')  # a person who never moves, only faces the robot


def _corridor(width: float, centre: float = 5.0):  # noqa: ANN202
    return empty_room(20.0, 10.0, walls=[(0.0, 0.0, 20.0, centre - width / 2), (0.0, centre + width / 2, 20.0, 10.0)])


def _gap_and_speed(trace) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    gap = np.hypot(*(trace.humans[:, 0, :2] - trace.robot[:, :2]).T) - trace.robot_radius - trace.human_radii[0]
    return gap, np.hypot(trace.robot[:, 3], trace.robot[:, 4])


def _pass(person_y: float):  # noqa: ANN202
    person = human(start=(10.0, person_y), goals=[(10.0, person_y)])
    return make_sim([person], [STAND], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), world=_corridor(3.0),
                    timeout=90).run()


def test_robot_passes_a_person_standing_in_a_3m_corridor_outside_their_intimate_space():
    trace = _pass(5.3)  # standing a little left of the corridor's middle: room on the right to pass
    gap, speed = _gap_and_speed(trace)
    assert trace.end_reason == "robot_goal"
    assert gap.min() >= INTIMATE_SPACE
    beside = np.abs(trace.robot[:, 0] - 10.0) < 1.5
    assert speed[beside].max() < 0.55  # slower than its cruise (0.6) within personal space


def test_robot_passes_slowly_where_the_corridor_leaves_no_social_distance():
    # a person (0.4 m) in the middle of a 3 m corridor leaves 1.1 m beside them: a 0.7 m robot cannot keep 0.45 m
    trace = _pass(5.0)
    gap, speed = _gap_and_speed(trace)
    assert trace.end_reason == "robot_goal" and gap.min() > 0.15  # it did pass, as far aside as the wall lets it
    assert speed[gap < INTIMATE_SPACE].max() <= CLOSE_SPEED + 0.02
    assert trace.robot[np.argmin(gap), 1] < 4.1  # on the right (south) side of the corridor


def test_waiting_robot_stands_beside_the_walkway_not_in_a_corridors_middle():
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="after", seconds=1.0), wait=8.0)])
    sim = make_sim([], [], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), world=_corridor(2.5), script=script,
                   timeout=60)
    trace = sim.run()
    waiting = (trace.t > 6.0) & (trace.t < 9.0)
    y = trace.robot[waiting, 1]
    assert (y < 5.0 - 0.5).all()  # to the right of its way (heading +x: right is -y), out of the middle
    assert (y - trace.robot_radius > 5.0 - 1.25).all()  # not into the wall
    x = trace.robot[waiting, 0]
    assert np.ptp(x) < 0.05  # it stood (no progress) while waiting
    assert trace.end_reason == "robot_goal"
