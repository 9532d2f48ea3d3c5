"""The default robot keeps a social margin (bodies.ROBOT_SOCIAL_GAP) where there is room: it passes a standing person
in an open room without brushing them, and waiting for someone coming through a door toward it, it is not where
they brush it coming out."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim import empty_room
from socnavgen.sim.robot.api import ScriptedPolicy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

STAND = tree_xml('<LookAtRobot agent_id="{id}"/>')  # a person who never moves, only faces the robot
WALK = tree_xml(REGULAR)
MARGIN = 0.25  # m: the gap asserted (the robot aims at ROBOT_SOCIAL_GAP; a person walking may close a little)


def _gaps(trace) -> np.ndarray:  # noqa: ANN001
    """(T,) the smallest robot-person gap per step."""
    d = np.hypot(trace.humans[:, :, 0] - trace.robot[:, None, 0], trace.humans[:, :, 1] - trace.robot[:, None, 1])
    return (d - trace.robot_radius - trace.human_radii[None, :]).min(axis=1)


def _door(width: float = 1.0):  # noqa: ANN202
    """Two 10 x 10 m rooms side by side, a wall at x = 10 with a door `width` wide round y = 5."""
    return empty_room(20.0, 10.0, walls=[(9.9, 0.0, 10.1, 5.0 - width / 2), (9.9, 5.0 + width / 2, 10.1, 10.0)])


def test_robot_passes_a_person_standing_on_its_line_in_an_open_room_with_a_social_margin():
    for y in (5.0, 5.3, 4.7):  # on its line, a little left, a little right
        person = human(start=(10.0, y), goals=[(10.0, y)])
        trace = make_sim([person], [STAND], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), timeout=90).run()
        assert trace.end_reason == "robot_goal"
        assert _gaps(trace).min() >= MARGIN, y


def test_robot_waiting_for_someone_coming_through_a_door_is_not_brushed():
    # the robot's way goes through the door; a person comes through it the other way; the robot waits until clear
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="blocked", distance=3.0), wait_until_clear=True)])
    for start in ((14.0, 5.0), (13.0, 6.5)):
        person = human(start=start, goals=[(3.0, 5.0)])
        trace = make_sim([person], [WALK], [(5.0, 5.0), (17.0, 5.0)], ScriptedPolicy(), world=_door(),
                         script=script, timeout=90).run()
        gaps = _gaps(trace)
        assert trace.humans[-1, 0, 0] < 9.0, start  # they came through
        assert trace.end_reason == "robot_goal", start
        assert gaps.min() >= MARGIN, (start, gaps.min(), trace.t[gaps.argmin()])


def test_robot_waiting_in_the_open_steps_away_from_someone_walking_at_it():
    # a timed wait in an open room; a person walks to a goal just past the robot's far side
    script = RobotScript(cues=[RobotCue(trigger=CueTrigger(when="after", seconds=0.5), wait=20.0)])
    person = human(start=(15.0, 5.2), goals=[(5.0, 5.2)])
    trace = make_sim([person], [WALK], [(9.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), script=script, timeout=60).run()
    assert trace.humans[-1, 0, 0] < 7.0
    assert _gaps(trace).min() >= MARGIN
