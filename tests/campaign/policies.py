"""Robot policies for the campaign tests (loaded as `path/to/policies.py:Class`)."""

from __future__ import annotations

import time

from socnavgen.sim import RobotAction


class StraightThrough:
    """A deliberately bad robot: full speed along its waypoints, ignoring people."""

    def __init__(self) -> None:
        self.index = 1

    def act(self, obs):  # noqa: ANN001, ANN201
        wps = obs.waypoints_c
        while self.index < len(wps) - 1 and abs(wps[self.index] - obs.position_c) < 0.3:
            self.index += 1
        to = wps[min(self.index, len(wps) - 1)] - obs.position_c
        if abs(to) < 0.05:
            return RobotAction(0.0, 0.0)
        v = to / abs(to) * 1.2
        return RobotAction(v.real, v.imag)


class Crashes:
    """Raises one simulated second into the episode."""

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t > 1.0:
            raise ZeroDivisionError("policy bug")
        return RobotAction(0.0, 0.0)


class Hangs:
    """Never answers (stuck inside act)."""

    def act(self, obs):  # noqa: ANN001, ANN201
        time.sleep(3600)
