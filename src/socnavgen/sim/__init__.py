"""Headless 2D simulator: social-force pedestrians driven by the generated behavior trees, a robot plugin,
metrics and a trace the verifier reads.

The public face (import these from `socnavgen.sim`; the sub-packages world, people, robot, engine and
outputs are its parts):

    load_simulation(run, policy, config) -> Simulation     simulate_run(run, robot=...) -> Trace
    SimConfig, Simulation, Trace, RobotAction, RobotBody, Observation, load_policy, warm_up, World, empty_room, HumanSpec

Attributes load on first use, so `import socnavgen.sim.trace` (the verifier's) does not compile anything.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

_EXPORTS = {
    "load_simulation": "socnavgen.sim.engine.scenario", "simulate_run": "socnavgen.sim.engine.scenario",
    "SimConfig": "socnavgen.sim.engine.simulation", "Simulation": "socnavgen.sim.engine.simulation",
    "RobotSpeech": "socnavgen.sim.engine.simulation", "Trace": "socnavgen.sim.trace",
    "RobotAction": "socnavgen.sim.robot.api", "RobotBody": "socnavgen.sim.robot.body", "Observation": "socnavgen.sim.robot.api",
    "load_policy": "socnavgen.sim.robot.api", "robot_from": "socnavgen.sim.robot.api", "BUILTIN": "socnavgen.sim.robot.api",
    "DEFAULT_ROBOT": "socnavgen.sim.robot.api", "ThrottleConfig": "socnavgen.sim.people.pacing",
    "PacingPlan": "socnavgen.sim.people.pacing", "HumanSpec": "socnavgen.sim.people.state",
    "World": "socnavgen.sim.world.grid", "empty_room": "socnavgen.sim.world.grid",
    "warm_up": "socnavgen.sim.engine.warm", "cache_ready": "socnavgen.sim.jit", "COMPILING_NOTE": "socnavgen.sim.jit",
    "write_outputs": "socnavgen.sim.outputs.files", "spawn_points": "socnavgen.sim.engine.scenario",
    "MadeFrom": "socnavgen.sim.outputs.files", "folder_identity": "socnavgen.sim.outputs.files",
    "save_run_outputs": "socnavgen.sim.outputs.files", "stale_reason": "socnavgen.sim.outputs.files",
    "unrecorded": "socnavgen.sim.outputs.files", "recorded_options": "socnavgen.sim.outputs.files",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'socnavgen.sim' has no attribute {name!r}")
    value = getattr(import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value
