"""What GiveWaytoRobot's library row tells the model about a gate that stops holding (issue 25: players could not
tell whether a give-way walks on by itself, or what a tree that falls back to standing does): a give-way begun
goes on inside RegularNav until the robot has passed; a standing branch stops the person where they are."""

from __future__ import annotations

import numpy as np
import pytest

from socnavgen.sim import empty_room, load_policy
from tests.sim.simhelpers import REGULAR, human, make_sim, tree_xml

# GiveWaytoRobot for only 0.3 s once the robot is within 3 m (a phrase shown briefly, a distance left behind)
SHORT_GATE = ('<Sequence><IsRobotNearby agent_id="{id}" distance="3.0"/><Inverter><TimeExpiredCondition '
              'seconds="0.3" ts="{dt}" only_once="true"/></Inverter><GiveWaytoRobot agent_id="{id}" '
              'time_step="{dt}"/></Sequence>')
STAND = '<MakeGesture agent_id="{id}" message="0"/>'


def _aside(after: str) -> tuple[float, float]:
    """(how far off the robot's line the person stands 3 s after the gate held, the most they were off it by
    then): a person standing in the middle of a 3 m corridor, the robot's route straight through them (too
    narrow for it to pass them by, wide enough to step aside), who walks on west (toward it) when free."""
    tree = tree_xml(f"<Fallback>{SHORT_GATE}{after}</Fallback>")
    sim = make_sim([human(start=(9.0, 1.5), goals=[(9.0, 1.5), (3.0, 1.5)])], [tree], [(2.0, 1.5), (18.0, 1.5)],
                   policy=load_policy("scripted"), world=empty_room(20.0, 3.0), timeout=30)
    trace = sim.run()
    ran = np.flatnonzero(trace.executed(0, "GiveWaytoRobot"))
    assert len(ran), "the robot never came within 3 m"
    k = int(np.searchsorted(trace.t, trace.t[ran[0]] + 3.0))
    off = np.abs(trace.humans[:, 0, 1] - 1.5)
    return float(off[k]), float(off[: k + 1].max())


@pytest.mark.parametrize(("after", "aside"), [(REGULAR, True), (STAND, False)])
def test_a_give_way_whose_gate_stops_goes_on_while_walking_and_stops_while_standing(after: str, aside: bool) -> None:
    off, most = _aside(after)
    clear = 0.4 + 0.35  # the two radii: off the robot's line by less, they stand in its way
    if aside:
        assert off >= clear, off  # RegularNav kept them stepping aside, 0.3 s of GiveWaytoRobot was enough
    else:
        assert most < clear, most  # MakeGesture stood them where the 0.3 s left them: still in its way
