"""Target `socrates`: the SocRATES fork of HuNavSim and its Gazebo wrapper, the system the paper ran.

BT.CPP v3 trees `LLMBT_<i>.xml` selected by `behavior: 7+i` (reference §2.8), the fork's agents
file (§8.1, the same loader as 1.x), and the wrapper's `robot_poses.yaml`, `trajectory.json` and
`launch_params.yaml` (§9.4, §11)."""

from __future__ import annotations

import json

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_MAX_SPEED, PERSON_RADIUS
from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import LIBRARY_TREE_XML
from socnavgen.bt.validate import format_problems, validate_bt_text
from socnavgen.bt.write import document_xml
from socnavgen.errors import ValidationFailed
from socnavgen.export.groot import tree_nodes_model_xml
from socnavgen.export.models import (
    HUMAN_Z,
    ExportedFile,
    ExportScene,
    HumanExport,
)
from socnavgen.export.readme import socrates_readme
from socnavgen.export.robot_script import script_yaml
from socnavgen.export.targets import ExportTarget, register
from socnavgen.export.timing import Hold, hold_root, timed, with_waiting_goals
from socnavgen.export.writer import dump_yaml, metres, robot_poses_yaml

FIRST_LLM_BEHAVIOR = 7  # behavior 7+i -> LLMBT_<i>.xml in the fork
TREES_DIR = "hunav_agent_manager/behavior_trees"
AGENTS_FILE = "hunav_agent_manager/config/custom_agents.yaml"  # what the wrapper's launch file loads
WRAPPER_CONFIG = "hunav_gazebo_wrapper/config"
GESTURE_NODE = "hunav_gazebo_wrapper/scripts/socnavgen_robot_gestures.py"  # publishes the script's gestures


def gesture_node_text() -> str:
    """The fork's small ROS 2 node (export/ros/), written into every socrates export."""
    from importlib.resources import files

    return files("socnavgen.export.ros").joinpath("socnavgen_robot_gestures.py").read_text(encoding="utf-8")


def fork_agent_entry(human: HumanExport, behavior: int, goal_prefix: str, first_goal: int, first_id: int = 0) -> dict:
    """One agent block of the 1.x / fork loader: pose, SFM parameters, named goals {x, y, h}.
    `first_id`: the fork numbers agents from 0 (LLMBT_<id>), upstream 1.x from 1."""
    names = [f"{goal_prefix}{first_goal + k}" for k in range(len(human.goals))]
    entry: dict = {
        "id": human.agent_id + first_id,
        "skin": human.skin,
        "behavior": behavior,
        "group_id": human.group_id,
        "max_vel": PERSON_MAX_SPEED,
        "radius": PERSON_RADIUS,
        "init_pose": {"x": metres(human.start.x), "y": metres(human.start.y), "z": HUMAN_Z,
                      "h": metres(human.start.yaw)},
        "goal_radius": PERSON_GOAL_RADIUS,
        "cyclic_goals": False,
        "goals": names,
    }
    for name, goal in zip(names, human.goals, strict=True):
        entry[name] = {"x": metres(goal.x), "y": metres(goal.y), "h": metres(goal.yaw)}
    return entry


def fork_agents_yaml(scene: ExportScene, behaviors: dict[str, int], goal_prefix: str, first_goal: int,
                     first_id: int = 0) -> str:
    params: dict = {"map": scene.location_name, "publish_people": True, "agents": [h.name for h in scene.humans]}
    for human in scene.humans:
        params[human.name] = fork_agent_entry(human, behaviors[human.name], goal_prefix, first_goal, first_id)
    return dump_yaml({"hunav_loader": {"ros__parameters": params}})


def check_trees(scene: ExportScene, target: str = "socrates") -> None:
    """Every tree must be valid for the fork's node library; list ALL problems of all humans."""
    ids = {h.agent_id for h in scene.humans}
    problems = []
    for human in scene.humans:
        problems += validate_bt_text(human.tree_xml, human.tree_file, target=target, human_ids=ids,
                                     agent_id=human.agent_id)
    if problems:
        raise ValidationFailed("behavior trees are not valid for the SocRATES node library:\n"
                               + format_problems(problems),
                               hint="fix them (socnavgen bt check FILE) or regenerate the behaviors stage")


def interaction_point_for_wrapper(scene: ExportScene, human: HumanExport) -> str:
    """The wrapper looks every human up in interaction_points and indexes the robot's goals with it
    (§11): a missing key or a node the robot never heads to crashes it. An empty string never
    matches a node, so such a human is simply never paused - nor is a person whose own tree carries its
    timing (export.timing): the wrapper's pause, on the whole leg before the node until the robot heads for
    it, would hold that person a second time, far from where its tree waits."""
    ip = human.interaction_point
    if ip and ip in scene.robot.path[1:] and not timed(human, scene):
        return ip
    return ""


def timed_tree(human: HumanExport, hold: Hold | None) -> str:
    """The person's v3 tree, with its timing (export.timing) around it when it is timed."""
    if hold is None:
        return human.tree_xml.rstrip() + "\n"
    doc = load_instance(human.tree_xml, human.tree_file).document  # valid: check_trees ran first
    assert doc.main is not None and doc.main.root is not None
    root = hold_root(doc.main.root, hold, set())
    return document_xml(doc, roots={doc.main.id: root})


def trajectory_json(scene: ExportScene) -> str:
    data = {
        "groupids": {h.name: h.group_id for h in scene.humans},
        "trajectories": {**{h.name: h.path for h in scene.humans}, "robot": scene.robot.path},
        "interaction_points": {h.name: interaction_point_for_wrapper(scene, h) for h in scene.humans},
    }
    return json.dumps(data) + "\n"


def build_socrates(scene: ExportScene) -> list[ExportedFile]:
    check_trees(scene)
    scene, holds = with_waiting_goals(scene)
    files: list[ExportedFile] = []
    behaviors: dict[str, int] = {}
    for human in scene.humans:
        doc = load_instance(human.tree_xml, human.tree_file).document  # checked above
        if doc.format_version != 3:
            raise ValidationFailed("the SocRATES fork runs BT.CPP v3 trees; this one says BTCPP_format=\"4\"",
                                   file=human.tree_file, line=doc.line)
        behaviors[human.name] = FIRST_LLM_BEHAVIOR + human.agent_id
        files.append(ExportedFile(path=f"{TREES_DIR}/LLMBT_{human.agent_id}.xml", text=timed_tree(human, holds.get(human.name))))
    for name, xml in LIBRARY_TREE_XML.items():
        files.append(ExportedFile(path=f"{TREES_DIR}/{name}", text=xml))
    files.append(ExportedFile(path=f"{TREES_DIR}/TreeNodesModel.xml", text=tree_nodes_model_xml("socrates")))
    files.append(ExportedFile(path=AGENTS_FILE, text=fork_agents_yaml(scene, behaviors, "g", 1)))
    files.append(ExportedFile(path=f"{WRAPPER_CONFIG}/robot_poses.yaml", text=robot_poses_yaml(scene.robot)))
    files.append(ExportedFile(path=f"{WRAPPER_CONFIG}/trajectory.json", text=trajectory_json(scene)))
    files.append(ExportedFile(path=f"{WRAPPER_CONFIG}/launch_params.yaml", text=dump_yaml({
        "robot_poses": "config/robot_poses.yaml", "scenario": "config/trajectory.json",
        "world_name": scene.location_name})))
    files.append(ExportedFile(path=f"{WRAPPER_CONFIG}/robot_script.yaml", text=script_yaml(scene)))
    files.append(ExportedFile(path=GESTURE_NODE, text=gesture_node_text()))
    files.append(ExportedFile(path="README.md", text=socrates_readme(scene, holds)))
    return files


@register
class SocratesTarget(ExportTarget):
    name = "socrates"
    summary = "the SocRATES fork of HuNavSim (BT.CPP v3, LLMBT_<i>.xml, behavior 7+i, ids from 0)"
    btcpp = "3.8"
    first_agent_id = 0

    def build(self, scene: ExportScene, *, base: str, simulator: str) -> list[ExportedFile]:
        return build_socrates(scene)
