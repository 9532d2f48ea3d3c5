"""Compile (or load from numba's cache) the simulator in this process now, on a tiny built-in scenario:
campaign workers call it before their first episode, so that numba's first compile (about a minute on a
new machine) is not counted against an episode's wall-clock limit."""

from __future__ import annotations

_WARM = False


def warm_up() -> None:
    global _WARM
    if _WARM:
        return
    from socnavgen.bt.library import regular_walker_xml
    from socnavgen.sim.engine.simulation import SimConfig, Simulation
    from socnavgen.sim.people.state import HumanSpec
    from socnavgen.sim.robot.api import WaypointsPolicy
    from socnavgen.sim.world.grid import empty_room

    sim = Simulation(empty_room(4.0, 4.0, resolution=0.1), [HumanSpec(name="human1", start=(1.0, 1.0),
                                                                       goals=[(3.0, 3.0)])],
                     [regular_walker_xml()], [(1.0, 3.0), (3.0, 1.0)], WaypointsPolicy(), SimConfig(timeout=0.1))
    sim.run()
    _WARM = True
