"""An example robot policy for campaigns (`robot: examples/campaigns/straight_robot.py:StraightThrough`):
a deliberately bad robot that drives its waypoints at full speed and ignores people. Any class with
`act(observation) -> RobotAction` works the same way (see RobotPolicy in docs/simulator.md)."""

from __future__ import annotations

from socnavgen.sim import RobotAction

SPEED = 0.6  # m/s, the cruise speed of the other robots: the only difference is that it ignores people
REACHED = 0.3  # m


class StraightThrough:
    def __init__(self) -> None:
        self.index = 1

    def act(self, obs):  # noqa: ANN001, ANN201 - Observation -> RobotAction
        waypoints = obs.waypoints_c
        while self.index < len(waypoints) - 1 and abs(waypoints[self.index] - obs.position_c) < REACHED:
            self.index += 1
        to = waypoints[min(self.index, len(waypoints) - 1)] - obs.position_c
        if abs(to) < 0.05:
            return RobotAction(0.0, 0.0)
        v = to / abs(to) * SPEED
        return RobotAction(v.real, v.imag)
