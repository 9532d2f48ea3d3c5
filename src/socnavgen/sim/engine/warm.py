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
    from socnavgen.sim.robot.api import BUILTIN
    from socnavgen.sim.world.grid import empty_room

    # every built-in robot once (their options and fields are other types to compile), two people on a route
    # with a turn, so that a campaign's first episode compiles nothing more
    for policy in BUILTIN.values():
        humans = [HumanSpec(name=f"human{i}", start=(1.0 + i, 1.0), goals=[(3.0, 3.0)]) for i in (1, 2)]
        sim = Simulation(empty_room(5.0, 5.0, resolution=0.1), humans, [regular_walker_xml()] * 2,
                         [(1.0, 3.0), (2.5, 4.0), (4.0, 1.0)], policy(), SimConfig(timeout=0.2))
        sim.run()
    _WARM = True
