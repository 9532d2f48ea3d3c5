"""The robot's part of a scenario, exported: `robot_script.yaml` (what the robot says and does, and when, in
world coordinates) in every export, and `ScriptPlayer`, which plays it from poses - the gesture the robot
makes now, from the robot's pose, the people's positions (and gestures) and the time.

The player runs the simulator's own script code (sim.gestures: RobotScriptRunner for spec.json's cues,
ScriptedGestures for paths.json's gesture rules), in the engine's order (a cue's phrase, else the first gesture
rule that holds, else none), on a view of the poses shaped like the simulation it reads. So the fork's ROS node
(ros/socnavgen_robot_gestures.py) publishes on /robot_gesture exactly what `socnavgen simulate` shows, and a
test replays a simulated trace through it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.errors import InputFileError
from socnavgen.export.models import ExportScene
from socnavgen.export.writer import dump_yaml, metres
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import RobotCue, RobotScript
from socnavgen.safeio import load_yaml_file

SCRIPT_FILE = "robot_script.yaml"
HEADER = ("# The robot's part of this scenario (socnavgen): what it says and does, and when. Metres and radians in\n"
          "# the map frame; gesture codes as on /robot_gesture (SocRATES fork). `cues` are spec.json's script,\n"
          "# `rules` paths.json's gesture rules; a cue's phrase wins over the rules. The fork's node\n"
          "# socnavgen_robot_gestures.py plays it; for other targets it tells the robot's operator what to do.\n")


class Place(BaseModel):
    model_config = ConfigDict(extra="forbid")
    node: str
    x: float
    y: float


class ScriptFile(BaseModel):
    """robot_script.yaml."""

    model_config = ConfigDict(extra="forbid")
    version: int = 1
    scenario: str = ""
    speed: float = Field(default=0.6, gt=0, le=2.0)
    misbehave: bool = False
    route: list[Place] = Field(default_factory=list, max_length=256)
    encounters: dict[str, Place] = Field(default_factory=dict)  # encounter id -> where (at_encounter cues)
    cues: list[RobotCue] = Field(default_factory=list, max_length=32)
    rules: list[RobotGestureRule] = Field(default_factory=list, max_length=32)
    nodes: dict[str, Place] = Field(default_factory=dict)  # the nodes the rules name (at_node)

    def script(self) -> RobotScript:
        return RobotScript(route=" -> ".join(p.node for p in self.route), speed=self.speed, cues=self.cues,
                           misbehave=self.misbehave)


def script_file(scene: ExportScene) -> ScriptFile:
    """The robot's part of the scene (its script, or none: then only the gesture rules of paths.json)."""
    spec = scene.spec
    script = spec.script if spec is not None else RobotScript()

    def place(node: str) -> Place:
        x, y = scene.nodes[node]
        return Place(node=node, x=metres(x), y=metres(y))

    encounters = {e.id: place(e.node) for e in (spec.encounters if spec else []) if e.node in scene.nodes}
    rules = list(scene.plan.robot_gestures)
    nodes = {r.node: place(r.node) for r in rules if r.node in scene.nodes}
    route = [scene.robot.start, *scene.robot.waypoints]
    return ScriptFile(scenario=scene.run_name, speed=script.speed, misbehave=script.misbehave,
                      route=[Place(node=p.node, x=metres(p.x), y=metres(p.y)) for p in route],
                      encounters=encounters, cues=list(script.cues), rules=rules, nodes=nodes)


def script_yaml(scene: ExportScene) -> str:
    """robot_script.yaml of the scene; each cue and rule also names its gesture code."""
    data = script_file(scene).model_dump(mode="json", exclude_defaults=False)
    codes = {name: code for code, name in ROBOT_GESTURES.items()}
    for cue in data["cues"]:
        cue["trigger"] = {k: v for k, v in cue["trigger"].items() if v is not None}
        if cue.get("say"):
            cue["gesture"] = codes[cue["say"]]
    for rule in data["rules"]:
        rule["say"] = ROBOT_GESTURES.get(rule["gesture"], str(rule["gesture"]))
    return HEADER + dump_yaml(data)


def load_script(path: Path | str) -> ScriptFile:
    """robot_script.yaml read back (its derived `gesture`/`say` keys are ignored); one message on any mistake."""
    data = load_yaml_file(Path(path))
    if not isinstance(data, dict):
        raise InputFileError("robot_script.yaml must be a mapping", file=path, hint="write it with socnavgen export")
    for cue in data.get("cues") or []:
        if isinstance(cue, dict):
            cue.pop("gesture", None)
    for rule in data.get("rules") or []:
        if isinstance(rule, dict):
            rule.pop("say", None)
    try:
        return ScriptFile.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        raise InputFileError(f"robot_script.yaml: {where}: {first['msg']}", file=path,
                             hint="write it with socnavgen export") from exc


class _Crowd:
    """The people as the script code reads them (sim.agents' crowd: n, pos, radius, gesture)."""

    def __init__(self) -> None:
        self.n = 0
        self.pos = np.zeros(0, dtype=complex)
        self.radius = np.zeros(0)
        self.gesture: list[int] = []


class _View:
    """What sim.gestures reads of a simulation, filled from poses."""

    def __init__(self) -> None:
        self.t = 0.0
        self.robot_pos = 0j
        self.robot_radius = ROBOT_RADIUS
        self.crowd = _Crowd()
        self._dir = 1 + 0j

    def robot_direction(self) -> complex:
        return self._dir


class ScriptPlayer:
    """Plays a robot script from poses, step by step (keep one per run: the cues remember what fired)."""

    def __init__(self, script: ScriptFile) -> None:
        from socnavgen.sim.gestures import RobotScriptRunner, ScriptedGestures

        encounters = {e: complex(p.x, p.y) for e, p in script.encounters.items()}
        self.runner = RobotScriptRunner(script.script(), encounters)
        self.rules = ScriptedGestures(script.rules, {n: complex(p.x, p.y) for n, p in script.nodes.items()})
        self.view = _View()

    def gesture(self, t: float, robot: tuple[float, float, float], people: list[tuple[float, float]],
                people_gestures: list[int] | None = None) -> int:
        """The robot's gesture at time `t` (seconds since the scenario started) with the robot at (x, y, yaw)
        - its direction of travel is its heading - and the people at `people` showing `people_gestures`."""
        v = self.view
        v.t = float(t)
        v.robot_pos = complex(robot[0], robot[1])
        v._dir = complex(math.cos(robot[2]), math.sin(robot[2]))
        crowd = v.crowd
        crowd.n = len(people)
        crowd.pos = np.array([complex(x, y) for x, y in people], dtype=complex)
        crowd.radius = np.full(crowd.n, PERSON_RADIUS)
        crowd.gesture = list(people_gestures) if people_gestures is not None else [0] * crowd.n
        cues = self.runner.update(v)
        if cues.say:
            return int(cues.say)
        return int(self.rules.gesture(v))


__all__ = ["SCRIPT_FILE", "ScriptFile", "ScriptPlayer", "load_script", "script_file", "script_yaml"]
