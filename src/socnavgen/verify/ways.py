"""Walkable distances between the robot and the people of a trace: along the map's free space, never through a
wall (sim/world/walkable.py is the one implementation).

* walkable: the whole run, `way_<human>` (how far a follower is from whom it follows).
* start_apart: how far apart the robot and a person start, the distance a meeting's approach counts from
  (closer_<human>): two who start in rooms side by side are not together there. A teenager bursting out of the
  bathroom next to the bedroom the robot had just left crossed 1.9 m in front of it, 2.06 m from it through their
  wall at the start, and the meeting was refused as no approach (home_13 / home_16 of the new-request suite).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from socnavgen.verify.thresholds import FAR


class Signals(Protocol):
    """What of verify.signals.Signals this module reads (signals imports this module: no import back)."""

    def keep(self, key: object, build: Callable[[], Any]) -> Any: ...
    def need_world(self, what: str) -> Any: ...
    def pos(self, who: str) -> np.ndarray: ...
    def get(self, name: str) -> np.ndarray: ...


def _between(s: Signals, a: str, b: str, steps: slice) -> np.ndarray:
    from socnavgen.sim.world.walkable import WalkableDistance

    ways = WalkableDistance.of(s.need_world("walkable distance"))
    pa, pb = s.pos(a)[steps], s.pos(b)[steps]
    return ways.between(pa[:, 0] + 1j * pa[:, 1], pb[:, 0] + 1j * pb[:, 1], FAR)


def walkable(s: Signals, a: str, b: str) -> np.ndarray:
    """(T,) walkable distance between `a` and `b` (the robot or a human); FAR where no way joins them."""
    return s.keep(("walkable", a, b), lambda: _between(s, a, b, slice(None)))


def start_apart(s: Signals, human: str) -> float:
    """How far apart the robot and `human` start: the walkable distance at the first step (one geodesic field,
    not the run's), or the straight one without a map or where no way joins them."""
    straight = float(s.get(f"dist_{human}")[0])
    try:
        way = float(s.keep(("walkable_start", human), lambda: _between(s, "robot", human, slice(0, 1))[0]))
    except ValueError:  # signals.UnknownSignal: no map for this run (imported there, not here: no cycle)
        return straight
    return way if way < FAR else straight
