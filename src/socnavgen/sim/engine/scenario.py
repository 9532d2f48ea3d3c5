"""A Simulation from a run folder: location + paths.json + behaviors/*.xml (+ spec.json's robot script), in
world coordinates via Location.node_world, people spawned around their first node as SocRATES does
(reference §9.3); and `simulate_run`, one call from a run folder to its trace and output files."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from socnavgen.bodies import (
    CONTACT_MARGIN,
    INTIMATE_SPACE,
    PERSON_MAX_SPEED,
    PERSON_RADIUS,
    ROBOT_RADIUS,
    group_ring,
)
from socnavgen.bt.library import regular_walker_xml
from socnavgen.errors import ValidationFailed
from socnavgen.run import LoadedRun, load_run
from socnavgen.sim.engine.budget import TimeLimit, time_limit
from socnavgen.sim.engine.simulation import RobotSpeech, SimConfig, Simulation, cruise_speed
from socnavgen.sim.people.pacing import PacingPlan, ThrottleConfig
from socnavgen.sim.people.routing import project
from socnavgen.sim.people.state import HumanSpec
from socnavgen.sim.people.trees import lower_trees
from socnavgen.sim.robot.api import DEFAULT_ROBOT, load_policy
from socnavgen.sim.trace import Trace
from socnavgen.sim.world.grid import World

if TYPE_CHECKING:
    from socnavgen.location import Location

SPAWN_SPREAD = 1.5  # m: SocRATES places each person uniformly within 1.5 m of its first node
DEFAULT_TREE = regular_walker_xml()


def spawn_points(world: World, first_nodes: list[complex], group_ids: list[int], radius: float,
                 rng: np.random.Generator, robot_start: complex | None = None,
                 landmarks: Sequence[complex] = ()) -> list[complex]:
    """SocRATES spawn: a random point within 1.5 m of the first node (groups spread evenly on a circle of
    bodies.group_ring); a point inside a wall, or less than bodies.INTIMATE_SPACE from the robot at
    `robot_start` or from a body placed before (a group's own members: not touching), or (`landmarks`: every
    node of the scene graph) nearer another node than its own, is redrawn closer to the node each time, falling
    back to the node itself (placement keeps nodes clear of each other). A person starts at their node's place:
    round 30's visitor on the phone, told to stand in a 1.2 m doorway, was drawn 1.4 m off into the corridor,
    beside the next node."""
    members: dict[int, list[int]] = {}
    for k, g in enumerate(group_ids):
        if g != -1:
            members.setdefault(g, []).append(k)
    out: list[complex] = []

    def clear(spot: complex, g: int) -> bool:
        if robot_start is not None and abs(spot - robot_start) - radius - ROBOT_RADIUS < INTIMATE_SPACE:
            return False
        for j, other in enumerate(out):
            same_group = g != -1 and group_ids[j] == g
            if abs(spot - other) - 2 * radius < (CONTACT_MARGIN if same_group else INTIMATE_SPACE):
                return False
        return True

    def free_of_others(spot: complex, node: complex, g: int) -> bool:
        """Clear of everybody, and not reached from its node through the robot's body."""
        return clear(spot, g) and not (
            robot_start is not None and project(robot_start, spot, node)[1] < radius + ROBOT_RADIUS)

    for k, (node, g) in enumerate(zip(first_nodes, group_ids, strict=True)):
        if g != -1 and len(members[g]) > 1:  # a group stands together, evenly on a small circle
            angle = members[g].index(k) * 2 * math.pi / len(members[g])
            rho = group_ring(len(members[g]))
        else:
            angle = float(rng.uniform(0, 2 * math.pi))
            rho = float(rng.uniform(0, SPAWN_SPREAD))
        point = None
        alone = g == -1 or len(members[g]) == 1
        for attempt in range(12):
            spot = node + rho * (0.7 ** attempt) * complex(math.cos(angle), math.sin(angle))
            if (world.is_free(spot, radius) and world.line_of_sight(node, spot)[0] and clear(spot, g)
                    and (not alone or _in_cell(spot, node, landmarks))):
                point = spot
                break
        if point is None:  # no room where it was drawn (a group of four in a corridor): the nearest clear spot
            point = nearest_clear(world, node, radius, partial(free_of_others, node=node, g=g))
        out.append(point)
    return out


def _in_cell(spot: complex, node: complex, landmarks: Sequence[complex]) -> bool:
    """`spot` is no nearer any of `landmarks` than `node` (it lies in the node's Voronoi cell of the scene graph)."""
    own = abs(spot - node)
    return all(abs(spot - other) >= own for other in landmarks)


SPAWN_SEARCH = (np.arange(0.0, SPAWN_SPREAD + 1e-9, 0.1), 24)  # radii (m) and directions tried for a free spot


def nearest_clear(world: World, node: complex, radius: float, clear: Callable[[complex], bool]) -> complex:
    """The spot nearest `node` (in sight of it, off the walls) that `clear` accepts: bodies never start on each
    other; the node itself when there is none within SPAWN_SPREAD."""
    radii, directions = SPAWN_SEARCH
    for rho in radii:
        for k in range(directions if rho > 0 else 1):
            spot = node + rho * complex(math.cos(2 * math.pi * k / directions), math.sin(2 * math.pi * k / directions))
            if world.is_free(spot, radius) and world.line_of_sight(node, spot)[0] and clear(spot):
                return spot
    return node


def node_worlds(run: LoadedRun, location: Location) -> dict[str, tuple[float, float]]:
    """Location.node_world of every scene-graph node, worked out once per run and location (read only)."""
    return run.for_location("sim.node_worlds", location,
                            lambda: {n: location.node_world(n) for n in location.scene_graph.node_ids()})


def route_time_limit(run_dir: Path | str | LoadedRun, location: Any = None, dt: float = 0.05) -> TimeLimit:
    """The time limit `simulate` gives the default robot on this run (engine/budget.time_limit on the robot's
    route at its script's cruise speed, with the script's waits). A campaign gives every policy this one limit,
    so a scenario whose route is long gets the time it needs and no policy gets more than another."""
    run = load_run(run_dir)
    location = run.location(location)
    at = node_worlds(run, location)
    spec = run.spec()
    robot, body = load_policy(DEFAULT_ROBOT), SimConfig().body  # what Simulation reads of the default robot
    return time_limit([at[n] for n in run.paths().robot], cruise_speed(robot, body.max_speed),
                      spec.script if spec is not None else None,
                      float(getattr(robot, "start_delay", 0.0) or 0.0), dt)


def load_simulation(run_dir: Path | str | LoadedRun, policy: Any, config: SimConfig | None = None,
                    throttle: ThrottleConfig | None = None, location: Any = None, *,
                    world: World | None = None) -> Simulation:
    """A ready Simulation of a run. `run_dir`: a LoadedRun (its files are not read again: campaign workers
    keep one per scenario) or a run folder; `location`: a loaded Location (passed on, not re-read), a folder,
    or None for the one request.json names; `world`: an already built World of that location."""
    config = config or SimConfig()
    run = load_run(run_dir)
    location = run.location(location)
    plan = run.paths()
    world = world if world is not None else World.from_location(location)
    at = node_worlds(run, location)
    problems = run.plan_mistakes(location, interaction_points=False)
    humans = sorted(plan.humans, key=lambda h: h.agent_id)
    if problems:
        raise ValidationFailed("cannot simulate this run:\n  " + "\n  ".join(problems), file=run.folder.paths_path)
    rng = np.random.default_rng(config.seed)
    starts = spawn_points(world, [complex(*at[h.path[0]]) for h in humans], [h.group_id for h in humans],
                          PERSON_RADIUS, rng, complex(*at[plan.robot[0]]) if plan.robot else None,
                          landmarks=[complex(*xy) for xy in at.values()])
    spec = run.spec()
    traits = spec.people if spec is not None else {}
    specs = []
    for h, start in zip(humans, starts, strict=True):
        person = traits.get(h.name)
        speed = person.speed if person is not None and person.speed is not None else PERSON_MAX_SPEED
        goals = [at[n] for n in h.goals]
        first = complex(*goals[0]) - start
        specs.append(HumanSpec(name=h.name, start=(start.real, start.imag), goals=goals,
                               yaw=math.atan2(first.imag, first.real) if abs(first) > 1e-9 else 0.0,
                               group_id=h.group_id, path_nodes=list(h.path), max_vel=speed,
                               interaction_point=at.get(h.interaction_point) if h.interaction_point is not None else None))
    xmls = run.behaviors()
    trees: list[str] = []
    names, defaulted = [], []
    for h in humans:
        if h.name in xmls:
            trees.append(xmls[h.name])
            names.append(str(run.behavior_path(h.name)))
        else:
            trees.append(DEFAULT_TREE)
            names.append(f"<default RegularNav tree for {h.name}>")
            defaulted.append(h.name)
    node_points = {n: complex(*p) for n, p in at.items()}
    throttle = throttle or ThrottleConfig()
    speech = RobotSpeech(rules=list(plan.robot_gestures), node_points=node_points)
    if spec is not None:
        speech.script = spec.script
        speech.encounter_points = {e.id: node_points[e.node] for e in spec.encounters if e.node in node_points}
        throttle.robot_speed = spec.script.speed
    pacing = PacingPlan(throttle, list(plan.robot), [(h.agent_id, list(h.path), h.interaction_point, h.group_id)
                                                     for h in humans])
    meta = {
        "run": str(run.root), "location": location.name, "robot_nodes": list(plan.robot),
        "human_paths": {h.name: list(h.path) for h in humans},
        "interaction_points": {h.name: [*at[h.interaction_point]] for h in humans if h.interaction_point in at},
        "interaction_nodes": {h.name: h.interaction_point for h in humans if h.interaction_point},
        "default_trees": defaulted, "policy": type(policy).__name__, "throttle": throttle.__dict__,
        "spec": spec is not None,
    }
    program = run.derived(("sim.program", tuple(names)), lambda: lower_trees(trees, names))
    return Simulation(world, specs, trees, [at[n] for n in plan.robot], policy, config, speech=speech,
                      pacing=pacing, tree_names=names, meta=meta, program=program)


def simulate_run(run_dir: Path | str | LoadedRun, robot: str | Any = DEFAULT_ROBOT, location: Any = None,
                 dt: float = 0.05, timeout: float | None = None, seed: int = 0, throttle: bool | ThrottleConfig = True,
                 progress: Any = None, save: bool = True, plot: bool = True, gif: bool = False) -> Trace:
    """One call from a run folder to its trace. With `save` (default) it writes what `socnavgen simulate`
    writes: RUN/sim/trace.npz, metrics.json and (with `plot`) trajectories.png, (with `gif`) animation.gif.
    `robot` is a plugin spec (see load_policy) or a policy object; `location` a folder or a Location (a
    loaded Location is used as is: load it once when simulating many times)."""
    from socnavgen.sim.outputs.files import MadeFrom, folder_identity, save_run_outputs

    policy = load_policy(robot) if isinstance(robot, str) else robot
    if isinstance(throttle, bool):
        throttle = ThrottleConfig(enabled=throttle)
    run = load_run(run_dir)
    identity = folder_identity(run.root) if save else None
    loaded = run.location(location)
    sim = load_simulation(run, policy, SimConfig(dt=dt, timeout=timeout, seed=seed), throttle, loaded)
    sim.meta["robot_plugin"] = robot if isinstance(robot, str) else type(robot).__name__
    trace = sim.run(progress=progress)
    if save:  # the outputs carry what they were made from (sim/outputs.py)
        made = MadeFrom(sim.meta["robot_plugin"], dt, sim.timeout, seed, throttle.enabled)
        save_run_outputs(trace, loaded, run.root, made, identity=identity, plot=plot, gif=gif)
    return trace
