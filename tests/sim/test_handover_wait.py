"""A robot standing for its script is not "arrived short of its goal" (engine.step.ending): round 22's first-aid
kit run ended 5 s into the robot's 10 s handover wait, when the colleague coming to take the kit stood between it
and its goal (proxemics.short_of_goal held), so the handover, the wait and the robot's last metre never happened."""

from __future__ import annotations

import numpy as np

from socnavgen.run.spec import CueTrigger, RobotCue, RobotScript
from socnavgen.sim.robot.api import ScriptedPolicy

from .simhelpers import human, make_sim, nav_tree

GOAL = (12.0, 5.0)
WAIT = 10.0
# the colleague stands off until the robot is near, then walks up to 0.4 m short of the robot's goal and stands
COMES_UP = nav_tree('<IsRobotNearby agent_id="{id}" distance="4.5"/>'
                    '<SubTree ID="RegularNavTree" id="agentid" dt="timestep"/>')


def _run(wait: float):  # noqa: ANN202
    script = RobotScript(speed=0.6, cues=[RobotCue(trigger=CueTrigger(when="at_encounter", encounter="e1",
                                                                      distance=1.8), wait=wait)])
    sim = make_sim([human(start=(14.0, 5.0), goals=[(11.6, 5.0)])], [COMES_UP], [(2.0, 5.0), GOAL],
                   policy=ScriptedPolicy(), script=script, encounters={"e1": complex(*GOAL)}, timeout=60)
    return sim.run()


def test_the_run_goes_on_while_the_robot_stands_for_its_wait() -> None:
    trace = _run(WAIT)
    robot_speed = np.hypot(trace.robot[:, 3], trace.robot[:, 4])
    stopped = int(np.argmax((trace.t > 1.0) & (robot_speed < 0.02)))  # the wait's first step
    to_goal = np.hypot(trace.robot[stopped, 0] - GOAL[0], trace.robot[stopped, 1] - GOAL[1])
    assert 1.5 < to_goal < 2.1, to_goal  # it stood for its cue short of the goal, the colleague coming up
    person_gap = np.hypot(*(trace.humans[-1, 0, :2] - trace.robot[-1, :2])) - 0.75
    assert person_gap < 1.35  # the colleague came up close: short of the goal, as proxemics.short_of_goal counts it
    assert trace.end_reason == "robot_goal"
    fired = trace.meta["script_cues_fired"][0][0]  # when the cue's wait began
    assert fired <= trace.t[stopped] and trace.t[-1] >= fired + WAIT - 0.1, (fired, trace.t[-1])
