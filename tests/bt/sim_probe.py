"""Running a tree in the simulator through its public functions only (a Simulation of a tiny world, its
Trace), so the language tests keep working while the simulator's internals change."""

from __future__ import annotations

from importlib import import_module
from typing import Any

from socnavgen.bt.library import regular_walker_xml
from socnavgen.errors import SocnavgenError

DT = 0.25  # s: the steps of a probe are few, and 3 * DT is exact in binary
ME_AT, OTHER_AT, ROBOT_AT = (2.0, 5.0), (2.0, 8.0), (3.0, 5.0)  # the robot stands 1 m from the probed human
NEAR, FAR = 5.0, 0.5  # IsRobotNearby distances that succeed / fail


def public(name: str) -> Any:
    """`socnavgen.sim.<name>` (the simulator's public face)."""
    return getattr(import_module("socnavgen.sim"), name)


class Stay:
    """A robot that stands still."""

    def act(self, obs: Any) -> Any:
        return public("RobotAction")(0.0, 0.0)


def gestures(xml: str, steps: int = 3) -> tuple[int, ...] | str:
    """The gesture of human 0 (running `xml`; human 1 walks) after each of the first `steps` steps, or the
    simulator's message when it refuses the tree."""
    human = public("HumanSpec")
    people = [human(name="human1", start=ME_AT, goals=[(18.0, 5.0)]),
              human(name="human2", start=OTHER_AT, goals=[(18.0, 8.0)])]
    config = public("SimConfig")(dt=DT, timeout=steps * DT)
    try:
        sim = public("Simulation")(public("empty_room")(20.0, 10.0), people, [xml, regular_walker_xml()],
                                   [ROBOT_AT, (19.0, 5.0)], Stay(), config)
        trace = sim.run()
    except SocnavgenError as exc:
        return exc.message
    return tuple(int(g) for g in trace.human_gesture[1:steps + 1, 0])
