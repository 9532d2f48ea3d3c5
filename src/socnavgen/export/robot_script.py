"""The robot's part of a scenario, exported: `robot_script.yaml` (what the robot says and does, and when, in
world coordinates) in every export, and `ScriptPlayer`, which plays it from poses - the gesture the robot
makes now, from the robot's pose, the people's positions (and gestures) and the time.

The player runs the simulator's own script code (sim.robot.script: the script lowered as a simulation lowers
it, and play_gesture - its cues, then a cue's phrase, else the first gesture rule that holds - on the part of
the state the script reads, filled from the poses). So the fork's ROS node
(ros/socnavgen_robot_gestures.py) publishes on /robot_gesture exactly what `socnavgen simulate` shows, and a
test replays a simulated trace through it."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.errors import InputFileError
from socnavgen.export.models import ExportScene
from socnavgen.export.writer import dump_yaml, metres
from socnavgen.limits import MAX_SIM_PEOPLE
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
    people: int = Field(default=0, ge=0, le=MAX_SIM_PEOPLE)  # the scenario's crowd (cues name person K of it)
    route: list[Place] = Field(default_factory=list, max_length=256)
    encounters: dict[str, Place] = Field(default_factory=dict)  # encounter id -> where (at_encounter cues)
    cues: list[RobotCue] = Field(default_factory=list, max_length=32)
    rules: list[RobotGestureRule] = Field(default_factory=list, max_length=32)
    nodes: dict[str, Place] = Field(default_factory=dict)  # the nodes the rules and cues name (at_node)

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
    nodes = {n: place(n) for n in [r.node for r in rules] + [c.trigger.node for c in script.cues if c.trigger.node]
             if n in scene.nodes}
    route = [scene.robot.start, *scene.robot.waypoints]
    return ScriptFile(scenario=scene.run_name, speed=script.speed, misbehave=script.misbehave, people=len(scene.humans),
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


class ScriptPlayer:
    """Plays a robot script from poses, step by step (keep one per run: the cues remember what fired)."""

    def __init__(self, script: ScriptFile) -> None:
        self.file = script
        self.state: Any = None  # the script lowered once the crowd's size is known (cues may name a person)
        self.poses: Any = None

    def _lowered(self, people: int) -> None:
        from socnavgen.sim.robot.script import lower_script, poses

        if self.state is None:
            script = self.file
            encounters = {e: complex(p.x, p.y) for e, p in script.encounters.items()}
            nodes = {n: complex(p.x, p.y) for n, p in script.nodes.items()}
            self.state = lower_script(script.script(), encounters, script.rules, nodes, script.people or people, 0)
        if self.poses is None or self.poses.people.shape[0] != people:
            self.poses = poses(people)
            self.poses.robot.radius = ROBOT_RADIUS

    def gesture(self, t: float, robot: tuple[float, float, float], people: list[tuple[float, float]],
                people_gestures: list[int] | None = None) -> int:
        """The robot's gesture at time `t` (seconds since the scenario started) with the robot at (x, y, yaw)
        - its direction of travel is its heading - and the people at `people` showing `people_gestures`."""
        from socnavgen.sim.robot.script import play_gesture

        self._lowered(len(people))
        s = self.poses
        s.clock.t = float(t)
        s.robot.pos = complex(robot[0], robot[1])
        s.robot.heading = complex(math.cos(robot[2]), math.sin(robot[2]))
        s.people.pos = [complex(x, y) for x, y in people]
        s.people.radius = PERSON_RADIUS
        s.people.gesture = list(people_gestures) if people_gestures is not None else 0
        return int(play_gesture(s, self.state))


__all__ = ["SCRIPT_FILE", "ScriptFile", "ScriptPlayer", "load_script", "script_file", "script_yaml"]
