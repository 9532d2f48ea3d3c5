"""A run as an export target runs it, in our simulator: the proof that an export's timing (export.timing)
and phrase conditions (export.speech) make the scenario happen without anything of ours around it.

`target_twin(run, target, work)` writes a copy of the run whose behaviors are the target's exported trees
(socrates: LLMBT_<i>.xml as exported; hunav2: the 2.x translation, its goal prelude left out because the
simulator takes goals from paths.json) and whose paths carry the waiting goals the export adds (as nodes of an
in-memory copy of the location; hunav1, which loads only its built-in behaviors, runs a tree the export accepts
as it is, without timing, and refuses the rest); `run_as_target(twin, speed)` simulates it with our pacing off (socrates:
the fork's wrapper's own pause rule on, for the people it still pauses), a waypoint robot at `speed` times the
script's cruise speed, the robot's script speaking (the fork's people hear it through the gesture topic;
2.x trees have no phrase condition left to hear it with), and judges the trace against the ORIGINAL run.
The robot is the simulator's built-in waypoints robot, started when the script's start wait is over, at the
speed asked, and (`robot="careful"`) never moving closer than KEEP_GAP to a person (its keep_gap: what nav2's
costmap or a teleoperator does; the plain waypoints robot, `robot="waypoints"`, pushes into people after its
patience runs out, with our own pacing and trees too). `robot="script"` also plays the robot's part, as the operator
plays the exported robot_script.yaml: the scripted robot with the careful gap, its script's speeds scaled
(`at_speed`): the criteria on what the robot itself does need it."""

from __future__ import annotations

import json
import math
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from socnavgen.bodies import CONTACT_MARGIN
from socnavgen.bt.expand import load_instance
from socnavgen.bt.hunav2_facts import HUNAV2_REGISTERED
from socnavgen.bt.library import HUNAV2, LIBRARY
from socnavgen.errors import SocnavgenError
from socnavgen.export.hunav1 import builtin_behavior
from socnavgen.export.hunav2 import translate_person
from socnavgen.export.models import ExportScene
from socnavgen.export.scene import build_scene
from socnavgen.export.socrates import check_trees, interaction_point_for_wrapper, timed_tree
from socnavgen.export.timing import Hold, start_wait, with_waiting_goals
from socnavgen.location import Location, load_location
from socnavgen.location.models import Edge
from socnavgen.location.models import Node as GraphNode
from socnavgen.location.scene_graph import to_networkx
from socnavgen.run import LoadedRun, load_run
from socnavgen.run.spec import RobotScript
from socnavgen.sim import BUILTIN, ThrottleConfig, Trace, simulate_run
from socnavgen.sim.engine.budget import FLOOR
from socnavgen.verify.runner import verify_trace

SPEEDS = (0.5, 1.0, 1.5)  # robot speed / the script's cruise speed
KEEP_GAP = CONTACT_MARGIN + 0.03  # m: the careful robot's own moves never bring it this close to a person
TIMED_TARGETS = ("socrates", "hunav2")  # the targets that run our trees, with the export's timing
AS_TARGETS = ("socrates", "hunav1", "hunav2")  # hunav1 runs its built-in behaviors only: no timing, no script
WAIT_NODE_TYPE = "WAITING SPOT"


ROBOTS = {"careful": KEEP_GAP, "waypoints": math.nan, "script": KEEP_GAP}  # the proof's robots: the gap each keeps
PLAYS_SCRIPT = {"script"}  # the robots that play the robot's part (robot_script.yaml), as their operator does
MAX_SCRIPT_SPEED = 2.0  # m/s: the highest cruise speed a script may ask (run.spec.RobotScript.speed)
TIMEOUT = FLOOR  # s: a run at the nominal speed or faster ends after this long (the simulator's shortest limit)


def timeout_for(speed: float) -> float:
    """How long a run with the robot at `speed` x its cruise speed lasts: a slower robot gets the time it needs
    to drive the same path (the simulator's 120 s, divided by the speed below 1x)."""
    return TIMEOUT / min(speed, 1.0)


def waypoint_robot(robot: str, max_speed: float, delay: float = 0.0) -> Any:
    """The built-in robot of the proof: `robot` one of ROBOTS, at `max_speed` m/s, started `delay` s late
    (its script's start wait: when its operator starts it). A robot of PLAYS_SCRIPT is the scripted robot (its
    speeds are the script's: run it on `at_speed`'s copy of the run)."""
    if robot in PLAYS_SCRIPT:
        return BUILTIN["scripted"](start_delay=delay, keep_gap=ROBOTS[robot])
    return BUILTIN["waypoints"](max_speed=max_speed, start_delay=delay, keep_gap=ROBOTS[robot])


def scaled_script(script: RobotScript, factor: float) -> RobotScript:
    """The robot's script as an operator plays it `factor` x faster: its cruise speed and every speed a cue asks
    scaled (at most MAX_SCRIPT_SPEED); its waits, phrases and places as they are."""
    cues = [c if c.speed is None else c.model_copy(update={"speed": min(c.speed * factor, MAX_SCRIPT_SPEED)})
            for c in script.cues]
    return script.model_copy(update={"speed": min(script.speed * factor, MAX_SCRIPT_SPEED), "cues": cues})


def at_speed(run: LoadedRun, robot: str, factor: float) -> LoadedRun:
    """The run a robot of `robot` drives at `factor` x its script's speed: for a robot that plays the script, a
    copy beside it (`<folder>@<factor>x`) whose spec.json has the script scaled (scaled_script); else the run."""
    spec = run.spec()
    if robot not in PLAYS_SCRIPT or spec is None or factor == 1.0:
        return run
    out = run.root.with_name(f"{run.root.name}@{factor:g}x")
    if out.exists():
        shutil.rmtree(out)
    shutil.copytree(run.root, out, ignore=shutil.ignore_patterns("sim"))
    scaled = spec.model_copy(update={"script": scaled_script(spec.script, factor)})
    copy = load_run(out)
    copy.folder.write_spec(scaled)
    return copy


@dataclass
class Twin:
    """A run as `target` runs it (or why the target refuses it)."""

    original: LoadedRun
    target: str
    run: LoadedRun | None = None
    location: Location | None = None
    robot_speed: float = 0.6
    start_wait: float = 0.0  # s: the script's wait at the start (when the robot's operator starts it)
    refused: str = ""
    stands_for: list[dict[str, str]] = field(default_factory=list)  # per human: 2.x node -> library node


def stands_for(tree_xml: str) -> dict[str, str]:
    """2.x node -> the library node of this tree it translates (the 2.x node recording that action)."""
    out: dict[str, str] = {}
    for node in load_instance(tree_xml, "t").root.walk():
        tr = HUNAV2.get(node.name)
        if tr is None or tr.template is None or node.name not in LIBRARY:
            continue
        templates = [tr.template] + [t for c in tr.by_value.values() for t in c.values()]
        for template in templates:  # a composition stands for the node with each of its actions
            names = re.findall(r"<(\w+)", template)
            actions = [n for n in names if n in HUNAV2_REGISTERED and HUNAV2_REGISTERED[n].kind == "Action"]
            for name in actions or [names[-1] if names[0] == "Sequence" else names[0]]:
                out.setdefault(name, node.name)
    return out


def relabel(trace: Trace, per_human: list[dict[str, str]]) -> Trace:
    """The hunav2 trace with each 2.x node's actions and successes recorded under the library node it
    stands for, so the run's own expectations ("human1 executes FollowRobot") apply to it."""
    names = trace.node_names
    action, succeeded = trace.action.copy(), trace.succeeded.copy()
    for h, mapping in enumerate(per_human):
        for native, ours in mapping.items():
            a, b = names.index(native), names.index(ours)
            action[trace.action[:, h] == a, h] = b
            fired = (trace.succeeded[:, h] >> a) & 1
            succeeded[:, h] |= fired << b
    trace.action, trace.succeeded = action, succeeded
    return trace


def _trees(scene: ExportScene, holds: dict[str, Hold], target: str) -> dict[str, str]:
    """Each person's tree as the target gets it (raises SocnavgenError when the target refuses it)."""
    check_trees(scene)
    if target == "hunav1":  # a tree the export accepts IS a built-in behavior: it runs as it is, untimed
        refusals = [str(r) for h in scene.humans for r in builtin_behavior(h)[1]]
        if refusals:
            raise SocnavgenError("HuNavSim 1.x runs only its built-in behaviors; refused: " + "; ".join(refusals))
        return {h.name: h.tree_xml for h in scene.humans}
    if target == "socrates":
        return {h.name: timed_tree(h, holds.get(h.name)) for h in scene.humans}
    out, problems = {}, []
    for h in scene.humans:
        done = translate_person(h, None, scene, holds.get(h.name))
        problems += done.problems
        out[h.name] = done.text
    if problems:
        raise SocnavgenError("; ".join(str(p) for p in problems))
    return out


def _twin_location(location_dir: Path, scene: ExportScene, holds: dict[str, Hold]) -> tuple[Location, dict]:
    """The location with every added waiting goal as a node on the leg it lies on; person -> its path with it."""
    location = load_location(location_dir)
    graph = location.scene_graph.model_copy(deep=True)
    paths = {}
    for h in scene.humans:
        hold = holds.get(h.name)
        path = list(h.path)
        if hold is not None and hold.wait_goal is not None:
            wait = hold.wait_goal
            px, py = location.transform.world_to_pixel(wait.x, wait.y)
            graph.nodes.append(GraphNode(type=WAIT_NODE_TYPE, pos=(px, py), id=wait.node))
            before, after = path[hold.wait_index], path[hold.wait_index + 1]
            graph.links += [Edge(type="WAIT", source=before, target=wait.node),
                            Edge(type="WAIT", source=wait.node, target=after)]
            path.insert(hold.wait_index + 1, wait.node)
        paths[h.name] = path
    location.__dict__["scene_graph"] = graph  # the cached properties of this copy only
    location.__dict__["graph"] = to_networkx(graph)
    return location, paths


def target_twin(run_dir: Path | str, target: str, work: Path | str, *, timing: bool = True) -> Twin:
    """The run as `target` runs it, written under `work` (replaced if there). `timing=False`: the exported
    trees without their timing (to run with our pacing instead: what the translation alone does)."""
    original = load_run(run_dir)
    scene, _ = build_scene(original.root)
    twin = Twin(original=original, target=target, robot_speed=scene.robot_speed, start_wait=start_wait(scene))
    timed_scene, holds = with_waiting_goals(scene) if timing and target in TIMED_TARGETS else (scene, {})
    try:
        trees = _trees(timed_scene, holds, target)
    except SocnavgenError as exc:
        twin.refused = exc.message
        return twin
    out = Path(work)
    if out.exists():
        shutil.rmtree(out)
    shutil.copytree(original.root, out, ignore=shutil.ignore_patterns("sim"))
    for name, text in trees.items():
        (out / "behaviors" / f"{name}.xml").write_text(text, encoding="utf-8")
    location, paths = _twin_location(original.location().root, scene, holds)
    plan = json.loads((out / "paths.json").read_text(encoding="utf-8"))
    for human in plan["humans"]:
        human["path"] = paths[human["name"]]
        if target == "socrates":  # the wrapper pauses only the people the trees do not time
            point = interaction_point_for_wrapper(scene, next(h for h in scene.humans if h.name == human["name"]))
            human["interaction_point"] = point or None
    (out / "paths.json").write_text(json.dumps(plan), encoding="utf-8")
    twin.run, twin.location = load_run(out), location
    if target == "hunav2":
        twin.stands_for = [stands_for(h.tree_xml) for h in scene.humans]
    return twin


def trace_as_target(twin: Twin, speed: float, robot: str = "careful", seed: int = 0, pacing: bool = False) -> Trace:
    """The twin simulated with the robot at `speed` x its cruise speed (`pacing`: our simulator's pacing on, a
    reference, with a twin made with timing=False); a hunav2 trace relabelled to the library's nodes."""
    assert twin.run is not None, twin.refused
    if pacing:
        throttle = ThrottleConfig()
    else:
        throttle = ThrottleConfig(rule="socrates") if twin.target == "socrates" else ThrottleConfig(enabled=False)
    policy = waypoint_robot(robot, twin.robot_speed * speed, twin.start_wait)
    trace = simulate_run(at_speed(twin.run, robot, speed), robot=policy, location=twin.location,
                         timeout=timeout_for(speed), seed=seed, throttle=throttle, save=False)
    return relabel(trace, twin.stands_for) if twin.stands_for else trace


def run_as_target(twin: Twin, speed: float, robot: str = "careful", seed: int = 0,  # noqa: ANN201 - VerifyReport
                  pacing: bool = False):
    """trace_as_target's verdict on the ORIGINAL run."""
    return verify_trace(twin.original, trace_as_target(twin, speed, robot, seed, pacing))


__all__ = ["AS_TARGETS", "PLAYS_SCRIPT", "ROBOTS", "at_speed", "scaled_script", "SPEEDS", "TIMED_TARGETS", "Twin", "waypoint_robot", "relabel", "run_as_target",
           "stands_for", "target_twin", "timeout_for", "trace_as_target"]
