"""The default robot keeps a social margin (bodies.ROBOT_SOCIAL_GAP) where there is room: it passes a standing person
in an open room without brushing them, and waiting for someone coming through a door toward it, it is not where
they brush it coming out."""

from __future__ import annotations

import numpy as np

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


def _door_in_a_wall():  # noqa: ANN202
    """A wall across y = 5 with a 1 m door round x = 10."""
    return empty_room(20.0, 10.0, walls=[(0.0, 4.9, 9.5, 5.1), (10.5, 4.9, 20.0, 5.1)])


def test_robot_passes_a_person_standing_on_its_line_in_an_open_room_with_a_social_margin():
    for y in (5.0, 5.3, 4.7):  # on its line, a little left, a little right
        person = human(start=(10.0, y), goals=[(10.0, y)])
        trace = make_sim([person], [STAND], [(2.0, 5.0), (18.0, 5.0)], ScriptedPolicy(), timeout=90).run()
        assert trace.end_reason == "robot_goal"
        assert _gaps(trace).min() >= MARGIN, y


def test_robot_coming_to_a_door_someone_comes_out_of_is_not_brushed():
    # the robot comes along the wall and turns into the door; a slow person (a cane: 0.5 m/s) stands in the doorway
    # and comes out when the robot is near, walking down past where the robot waits
    # (not yet: a person whose goal is the robot's own turn below the door, then back the way the robot came: the
    # robot waits beside the door's exit against the wall, with no room to step aside, and is passed at 0.20 m)
    for goals in ([(10.0, 3.0), (4.0, 3.0)], [(10.0, 2.5), (10.0, 1.0)], [(9.0, 2.5), (9.0, 1.0)]):
        person = human(start=(10.0, 5.4), goals=goals, start_delay=12.0, max_vel=0.5)
        trace = make_sim([person], [WALK], [(16.0, 3.5), (10.0, 3.5), (10.0, 8.0)], ScriptedPolicy(),
                         world=_door_in_a_wall(), timeout=90).run()
        gaps = _gaps(trace)
        assert trace.end_reason == "robot_goal", goals
        assert gaps.min() >= MARGIN, (goals, gaps.min(), trace.t[gaps.argmin()])
