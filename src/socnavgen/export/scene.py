"""Run folder + location -> ExportScene. The only place export turns node ids into metres, and it
does so only through `Location.node_world` (the location's transform)."""

from __future__ import annotations

import math
from pathlib import Path

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.export.models import (
    SKIN_COUNT,
    ExportScene,
    HumanExport,
    RobotExport,
    WorldPoint,
)
from socnavgen.location import Location
from socnavgen.run import PathPlan, RunFolder
from socnavgen.run.checks import plan_mistakes


def heading(a: tuple[float, float], b: tuple[float, float], default: float = 0.0) -> float:
    """Yaw of the world direction a->b (atan2 of the world delta); `default` if a == b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    if abs(dx) < 1e-12 and abs(dy) < 1e-12:
        return default
    return math.atan2(dy, dx)


def world_path(location: Location, nodes: list[str]) -> list[WorldPoint]:
    """Each node in metres; yaw = heading toward the next node (the last keeps the previous yaw)."""
    points = [location.node_world(n) for n in nodes]
    out: list[WorldPoint] = []
    yaw = 0.0
    for i, (node, p) in enumerate(zip(nodes, points, strict=True)):
        if i + 1 < len(points):
            yaw = heading(p, points[i + 1], yaw)
        out.append(WorldPoint(node=node, x=p[0], y=p[1], yaw=yaw))
    return out


def skin_for(agent_id: int) -> int:
    """Deterministic mesh per agent, so re-exports are identical and neighbours look different."""
    return agent_id % SKIN_COUNT


def _check_nodes(plan: PathPlan, location: Location, run: RunFolder) -> None:
    bad = plan_mistakes(plan, location.scene_graph, interaction_points=False)
    if bad:
        raise ValidationFailed("paths.json does not fit the location's scene graph: " + "; ".join(bad),
                               file=run.paths_path, hint="was the run generated on another location?")


def spawn_starts(location: Location, plan: PathPlan, seed: int) -> dict[str, tuple[float, float, float]]:
    """Where each human starts (x, y, yaw): exactly where `simulate --seed SEED` spawns it, by the simulator's
    own function (sim.spawn_points, with the same random generator and arguments), so that people
    sharing a first node stand apart in Gazebo as in our simulation; yaw toward the first goal, as simulated."""
    import numpy as np

    from socnavgen.sim import World, spawn_points

    humans = sorted(plan.humans, key=lambda h: h.agent_id)
    nodes = [complex(*location.node_world(h.path[0])) for h in humans]
    robot = complex(*location.node_world(plan.robot[0])) if plan.robot else None
    points = spawn_points(World.from_location(location), nodes, [h.group_id for h in humans], PERSON_RADIUS,
                          np.random.default_rng(seed), robot,
                          landmarks=[complex(*location.node_world(n)) for n in location.scene_graph.node_ids()])
    starts = {}
    for human, point in zip(humans, points, strict=True):
        goal = complex(*location.node_world(human.path[1] if len(human.path) > 1 else human.path[0])) - point
        starts[human.name] = (point.real, point.imag, math.atan2(goal.imag, goal.real) if abs(goal) > 1e-9 else 0.0)
    return starts


def build_scene(run_dir: Path | str, location_dir: Path | str | None = None, *,
                seed: int = 0) -> tuple[ExportScene, Location]:
    """Read request.json, paths.json and behaviors/*.xml; place every human and the robot in metres (humans
    where the simulator spawns them with `seed`)."""
    run = RunFolder(Path(run_dir))
    if not run.paths_path.is_file():
        raise InputFileError("this run has no paths.json yet", file=run.root,
                             hint="finish the run first (socnavgen generate ... or cards generate)")
    location = run.location(location_dir)
    plan = run.read_paths()
    _check_nodes(plan, location, run)
    trees = run.behaviors()
    missing = [h.name for h in plan.humans if h.name not in trees]
    if missing:
        raise InputFileError(f"no behavior tree for {', '.join(missing)}", file=run.behaviors_dir,
                             hint="every human in paths.json needs behaviors/<human>.xml")

    humans: list[HumanExport] = []
    starts = spawn_starts(location, plan, seed)
    for human in sorted(plan.humans, key=lambda h: h.agent_id):
        points = world_path(location, human.path)
        x, y, yaw = starts[human.name]
        start = WorldPoint(node=human.path[0], x=x, y=y, yaw=yaw)
        goals = points[1:] if len(points) > 1 else [points[0]]  # single node: walk to (stay at) it
        humans.append(HumanExport(
            name=human.name, agent_id=human.agent_id, group_id=human.group_id, skin=skin_for(human.agent_id),
            start=start, goals=goals, path=list(human.path), interaction_point=human.interaction_point,
            tree_xml=trees[human.name], tree_file=str(run.behaviors_dir / f"{human.name}.xml")))
    robot_points = world_path(location, plan.robot)
    robot = RobotExport(start=robot_points[0], waypoints=robot_points[1:], path=list(plan.robot))
    scene = ExportScene(run_name=run.root.resolve().name, location_name=location.name, humans=humans,
                        robot=robot, plan=plan, spec=run.read_spec(),
                        nodes={n: location.node_world(n) for n in location.scene_graph.node_ids()},
                        leads=door_leads(location, plan.robot, robot_points),
                        doors_after=doors_after(location, plan.robot, robot_points))
    return scene, location


DOOR_SAMPLE = 0.1  # m: a leg is looked at this finely for a door on it


def door_leads(location: Location, path: list[str], points: list[WorldPoint]) -> dict[str, float]:
    """The robot path's doors (pacing's door_lead, on the location's map): node -> lead (m), first visits only."""
    from socnavgen.sim.people.pacing import door_lead
    from socnavgen.sim.world.grid import World

    world = World.from_location(location)
    route = [complex(p.x, p.y) for p in points]
    out: dict[str, float] = {}
    for k in range(1, len(path)):
        if path[k] not in path[1:k]:
            lead = door_lead(world, route, k)
            if lead > 0:
                out[path[k]] = lead
    return out


def doors_after(location: Location, path: list[str], points: list[WorldPoint]) -> dict[str, str]:
    """Nodes of the robot's path (not doors themselves) whose next leg goes through a door - less than
    bodies.TOUCH_DISTANCE from it to a wall - within bodies.CLEAR_LEAD of the node: node -> the next node. A person
    who comes to the node along that leg (out of the elevator the robot enters) meets it face to face in that
    door unless they are through it first, as at a door on the node itself (timing: the same lead)."""
    from socnavgen.bodies import CLEAR_LEAD, TOUCH_DISTANCE
    from socnavgen.sim.world.grid import World

    world = World.from_location(location)
    route = [complex(p.x, p.y) for p in points]
    out: dict[str, str] = {}
    for k in range(1, len(path) - 1):
        here, there = route[k], route[k + 1]
        if path[k] in path[1:k] or world.clearance_at_point(here) < TOUCH_DISTANCE or abs(there - here) < 1e-9:
            continue
        reach = min(CLEAR_LEAD, abs(there - here))
        steps = max(2, int(reach / DOOR_SAMPLE) + 1)
        unit = (there - here) / abs(there - here)
        if any(world.clearance_at_point(here + unit * reach * j / (steps - 1)) < TOUCH_DISTANCE for j in range(steps)):
            out[path[k]] = path[k + 1]
    return out
