"""A person who stepped aside for the robot stays where they stepped until it has gone by, whatever leaf their tree
ticks meanwhile and however long their path: a friend chatting at a one-node path's node (home_10, round 17:
GiveWaytoRobot from 2.5 m, RunAwayFromRobot from 2.2 m) stepped aside, then the scared walk "still heading for the
goal" took him straight back into the robot's lane, 1.2 m in front of it."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.sim import RobotAction, empty_room
from socnavgen.sim.contact import trace_gaps
from tests.sim.simhelpers import human, make_sim, tree_xml

STEP_BACK = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="2.2"/>'
                     '<RunAwayFromRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                     '<Sequence><IsRobotNearby agent_id="{id}" distance="2.5"/>'
                     '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                     '<MakeGesture agent_id="{id}" message="0"/></Fallback>')
GIVES_WAY = tree_xml('<Fallback><Sequence><IsRobotNearby agent_id="{id}" distance="2.5"/>'
                     '<GiveWaytoRobot agent_id="{id}" time_step="{dt}"/></Sequence>'
                     '<MakeGesture agent_id="{id}" message="0"/></Fallback>')
LANE = 3.0  # the robot drives along y = 3 from x = 1 to x = 13
SPOT = (7.0, 3.2)  # where the person stands, at the end of a one-node path, on the robot's way


class Hesitant:
    """A robot driving slowly along y = LANE that stops 2 m short of the person for a few seconds (its script's
    slow approach and wait in home_10), then drives on."""

    def __init__(self, stop_x: float) -> None:
        self.stop_x, self.stopped = stop_x, None

    def act(self, obs):  # noqa: ANN001, ANN201
        x = float(obs.position[0])
        if x >= self.stop_x and self.stopped is None:
            self.stopped = obs.t
        if self.stopped is not None and obs.t < self.stopped + 6.0:
            return RobotAction(0.0, 0.0)
        return RobotAction(0.4, 0.0)


@pytest.mark.parametrize("tree", [STEP_BACK, GIVES_WAY], ids=["run-away-after-give-way", "give-way"])
def test_a_person_who_stepped_aside_stays_out_of_the_lane_until_the_robot_has_gone_by(tree: str):
    sim = make_sim([human(start=SPOT, goals=[SPOT])], [tree], [(1.0, LANE), (13.0, LANE)],
                   policy=Hesitant(SPOT[0] - 2.0), world=empty_room(14.0, 6.0), timeout=60)
    trace = sim.run()
    assert trace.end_reason == "robot_goal"
    x, y = trace.humans[:, 0, 0], trace.humans[:, 0, 1]
    lane = PERSON_RADIUS + ROBOT_RADIUS  # a body centre nearer the robot's line than this is in its lane
    out = np.abs(y - LANE) >= lane + 0.1
    assert out.any(), "never stepped aside"
    first = int(np.argmax(out))
    gone_by = trace.robot[:, 0] > x + lane + 0.3  # the robot's centre beyond them, with its body and a margin
    assert gone_by.any()
    until = int(np.argmax(gone_by))
    back_in = np.abs(y[first:until] - LANE) < lane
    assert not back_in.any(), f"back in the robot's lane at t={trace.t[first + int(np.argmax(back_in))]:.2f} s"
    assert trace_gaps(trace).min() > 0.05
