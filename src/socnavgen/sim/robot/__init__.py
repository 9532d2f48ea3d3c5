"""The robot: what a policy observes and answers and how one is loaded (api), the built-in robots compiled
into the step (policies), and the script it plays - cues and gesture rules (script).

`from socnavgen.sim.robot import RobotAction` keeps working for policy files written against it; new code
imports from `socnavgen.sim`."""

from socnavgen.sim.robot.api import Observation, RobotAction, RobotPolicy

__all__ = ["Observation", "RobotAction", "RobotPolicy"]
