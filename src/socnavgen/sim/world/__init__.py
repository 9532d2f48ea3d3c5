"""The map in metres: the World (walls, clearance, line of sight) and the compiled per-point queries the
simulator asks it."""

from socnavgen.sim.world.grid import World, empty_room

__all__ = ["World", "empty_room"]
