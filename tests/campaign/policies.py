"""Robot policies for the campaign tests (loaded as `path/to/policies.py:Class`)."""

from __future__ import annotations

import contextlib
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


class RetriesForever:
    """Stuck inside act(), retrying whatever goes wrong (`except Exception`), as a client library would."""

    def act(self, obs):  # noqa: ANN001, ANN201
        while True:
            with contextlib.suppress(Exception):  # the point: it swallows every ordinary exception
                time.sleep(3600)


class SwallowsEverything:
    """Stuck inside act(), swallowing even BaseException: only stopping its process ends it."""

    def act(self, obs):  # noqa: ANN001, ANN201
        while True:
            with contextlib.suppress(BaseException):
                time.sleep(3600)


class ExitsHard:
    """Ends its process with os._exit one simulated second in (no exception, no cleanup)."""

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t > 1.0:
            import os

            os._exit(3)
        return RobotAction(0.0, 0.0)


class KilledLikeOOM:
    """Its process is killed with SIGKILL one simulated second in, as the kernel's OOM killer does."""

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t > 1.0:
            import os
            import signal

            os.kill(os.getpid(), signal.SIGKILL)
        return RobotAction(0.0, 0.0)


class TerminatedMidEpisode:
    """Its process receives SIGTERM one simulated second in (what Pool.terminate sends its workers)."""

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t > 1.0:
            import os
            import signal

            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
        return RobotAction(0.0, 0.0)


class CallsSysExit:
    """Raises SystemExit one simulated second in (sys.exit in a policy)."""

    def act(self, obs):  # noqa: ANN001, ANN201
        if obs.t > 1.0:
            raise SystemExit(4)
        return RobotAction(0.0, 0.0)


class BrokenConstructor:
    """Raises in its constructor."""

    def __init__(self) -> None:
        raise RuntimeError("no model weights at /nonexistent")

    def act(self, obs):  # noqa: ANN001, ANN201
        return RobotAction(0.0, 0.0)
