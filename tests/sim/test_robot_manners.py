"""The default robot's manners in a corridor (robot.polite): it passes a standing person at a social distance where
the corridor leaves room, slowly where it does not, and it waits beside the walkway, not in its middle."""

from __future__ import annotations

import numpy as np

from socnavgen.bodies import INTIMATE_SPACE
from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.robot.api import ScriptedPolicy
from socnavgen.sim.robot.polite import CLOSE_SPEED
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

STAND = tree_xml('<LookAtRobot agent_id="{id}"/>')  # a person who never moves, only faces the robot
WALK = tree_xml(REGULAR)


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
    trace = _pass(5.5)  # standing left of the corridor's middle: room on the right to pass
    gap, speed = _gap_and_speed(trace)
    assert trace.end_reason == "robot_goal"
    assert gap.min() >= INTIMATE_SPACE
    approaching = (trace.robot[:, 0] < 10.0) & (gap < 1.0)
    assert speed[approaching].max() < 0.55  # slower than its cruise (0.6) within personal space


def test_robot_passes_slowly_where_the_corridor_leaves_no_social_distance():
    # a person (0.4 m) in the middle of a 3 m corridor leaves 1.1 m beside them: a 0.7 m robot cannot keep 0.45 m
    trace = _pass(5.0)
    gap, speed = _gap_and_speed(trace)
    assert trace.end_reason == "robot_goal" and gap.min() > 0.15  # it did pass, as far aside as the wall lets it
    approaching = (trace.robot[:, 0] < 10.0) & (gap < INTIMATE_SPACE)
    assert approaching.any() and speed[approaching].max() <= CLOSE_SPEED + 0.02
    assert trace.robot[np.argmin(gap), 1] < 4.1  # on the right (south) side of the corridor


def _waiting(people: list) -> tuple:  # noqa: ANN001
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="after", seconds=1.0), wait=12.0)])
    sim = make_sim(people, [WALK] * len(people), [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), world=_corridor(2.5),
                   script=script, timeout=60)
    trace = sim.run()
    return trace, (trace.t > 2.0) & (trace.t < 12.5)


def test_waiting_robot_stands_beside_the_walkway_not_in_a_corridors_middle():
    trace, waiting = _waiting([human(start=(17.0, 5.0), goals=[(1.0, 5.0)])])  # someone walking down the corridor
    gap, _ = _gap_and_speed(trace)
    abreast = waiting & (np.abs(trace.humans[:, 0, 0] - trace.robot[:, 0]) < 0.5)
    assert abreast.any()  # they came past while it waited
    assert (trace.robot[abreast, 1] < 5.0 - 0.5).all()  # to the right of its way (heading +x: -y), not in the middle
    assert (trace.robot[waiting, 1] - trace.robot_radius > 5.0 - 1.25).all()  # not into the wall
    assert np.ptp(trace.robot[waiting, 0]) < 0.1  # no progress along its way while it waited
    assert trace.end_reason == "robot_goal"


def test_waiting_robot_with_nobody_coming_stays_on_its_route():
    trace, waiting = _waiting([])
    assert np.abs(trace.robot[waiting, 1] - 5.0).max() < 0.05
