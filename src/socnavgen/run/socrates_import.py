"""A SocRATES user's scenarios as socnavgen run folders: read what SocRATES saved (the combined
`<experiment>_response_traj.json` / `scenarios/*.json`: scenario, groupids, trajectories, interaction_points,
behavior_trees; or a folder of its separate response files: the scenario reply, the trajectory reply, the
behavior-tree replies or LLMBT_<i>.xml) and write a run folder on the location it was made for, checked
like a generated run (paths on the scene graph, trees on the node library), so it simulates, verifies and
exports like any run. Human keys are normalised as SocRATES does ("Human 1", "HUMAN_1" -> human1)."""

from __future__ import annotations

import datetime as dt
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from socnavgen import __version__
from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.run.checks import plan_mistakes
from socnavgen.run.folder import RunFolder
from socnavgen.run.models import HumanPlan, Manifest, PathPlan, ScenarioProposal, ScenarioRequest, StageRecord
from socnavgen.safeio import load_json_file, parse_json_text, read_text_limited

MAX_FILES = 64  # files looked at in a folder of response files
LLMBT = re.compile(r"LLMBT_(\d{1,3})\.xml")
BT_REPLY = re.compile(r".*bt_?(\d{1,3})\.json")


@dataclass
class SocratesScenario:
    """What SocRATES saved, keys normalised to human1..humanN / robot."""

    source: Path
    description: str = ""
    behaviors: dict[str, str] = field(default_factory=dict)
    expected_robot: str = ""
    reasoning: str = ""
    trajectories: dict[str, list[str]] = field(default_factory=dict)
    groupids: dict[str, int] = field(default_factory=dict)
    interaction_points: dict[str, str] = field(default_factory=dict)
    trees: dict[str, str] = field(default_factory=dict)


def agent_key(key: object, where: Path) -> str:
    """"Human 1" / "HUMAN_1" / "human1" -> human1; "ROBOT" -> robot (SocRATES lowercases and drops spaces and
    underscores); anything else is refused by name."""
    text = re.sub(r"[\s_]", "", str(key).lower())
    if text == "robot" or re.fullmatch(r"human[1-9]\d{0,3}", text):
        return text
    raise InputFileError(f"{str(key)[:40]!r} is neither the robot nor a human (Human 1, human2, ...)", file=where)


def _text(value: Any) -> str:
    if isinstance(value, dict):
        return " ".join(f"{k}: {_text(v)}" for k, v in value.items())
    if isinstance(value, list):
        return " ".join(_text(v) for v in value)
    return str(value) if value is not None else ""


def _scenario(data: Any, sc: SocratesScenario, where: Path) -> None:
    if isinstance(data, str):  # the combined file stores the scenario reply as a JSON string
        try:
            data = parse_json_text(data)
        except ValueError:
            sc.description = data
            return
    if not isinstance(data, dict):
        raise InputFileError("the scenario is neither an object nor JSON text", file=where)
    sc.description = _text(data.get("scenariodescription", sc.description))
    sc.expected_robot = _text(data.get("expectedrobotbehavior", sc.expected_robot))
    behaviors = data.get("humanbehavior") or {}
    if isinstance(behaviors, list):  # [{"name": "Human 1", "behavior": "..."}]
        behaviors = {b.get("name"): b.get("behavior") for b in behaviors if isinstance(b, dict)}
    if isinstance(behaviors, dict):
        sc.behaviors.update({agent_key(k, where): _text(v) for k, v in behaviors.items()})


def _strings(data: Any, what: str, where: Path) -> dict[str, Any]:
    if not isinstance(data, dict):
        raise InputFileError(f"{what} is not an object", file=where)
    return {agent_key(k, where): v for k, v in data.items()}


def _trajectories(data: dict, sc: SocratesScenario, where: Path) -> None:
    for name, nodes in _strings(data["trajectories"], "trajectories", where).items():
        if not (isinstance(nodes, list) and all(isinstance(n, str) for n in nodes)):
            raise InputFileError(f"the trajectory of {name} is not a list of node ids", file=where)
        sc.trajectories[name] = list(nodes)
    for name, group in _strings(data.get("groupids") or {}, "groupids", where).items():
        if isinstance(group, bool) or not isinstance(group, int) or not -1 <= group <= 1000:
            raise InputFileError(f"the group id of {name} is {group!r}, not an integer", file=where)
        sc.groupids[name] = group
    for name, node in _strings(data.get("interaction_points") or {}, "interaction_points", where).items():
        if isinstance(node, str) and node:
            sc.interaction_points[name] = node
    if isinstance(data.get("reasoning"), str):
        sc.reasoning = data["reasoning"]


def _trees(data: Any, sc: SocratesScenario, where: Path) -> None:
    for name, xml in _strings(data, "behavior_trees", where).items():
        if not isinstance(xml, str):
            raise InputFileError(f"the behavior tree of {name} is not XML text", file=where)
        sc.trees[name] = xml


def _take(data: Any, path: Path, sc: SocratesScenario) -> bool:
    """Fold one JSON file into the scenario by what it holds; False when it is none of SocRATES's files."""
    if not isinstance(data, dict):
        return False
    if "trajectories" in data:
        _trajectories(data, sc, path)
        if "scenario" in data:
            _scenario(data["scenario"], sc, path)
        if "behavior_trees" in data:
            _trees(data["behavior_trees"], sc, path)
        return True
    if "scenariodescription" in data:
        _scenario(data, sc, path)
        return True
    if isinstance(data.get("tree"), str):  # one behavior-tree reply, reponse_bt_<n>.json (n from 1)
        match = BT_REPLY.fullmatch(path.name)
        if match is None:
            raise InputFileError("a behavior-tree reply whose file name does not say which human it is for",
                                 file=path, hint="name it like SocRATES does: reponse_bt_<n>.json (n = 1, 2, ...)")
        sc.trees[f"human{int(match.group(1))}"] = data["tree"]
        return True
    if data and all(isinstance(v, str) and v.lstrip().startswith("<") for v in data.values()):
        _trees(data, sc, path)  # the bt_file: {human: xml}
        return True
    return False


def read_socrates(source: Path | str) -> SocratesScenario:
    """One combined scenario file, or a folder of SocRATES's response files."""
    source = Path(source)
    sc = SocratesScenario(source=source)
    if source.is_file():
        if not _take(load_json_file(source), source, sc):
            raise InputFileError("not a SocRATES scenario (no trajectories)", file=source,
                                 hint="pass a scenarios/*.json or *_response_traj.json file, or a folder of replies")
    elif source.is_dir():
        entries = sorted(p for p in source.iterdir() if p.suffix in (".json", ".xml") and p.is_file())
        if len(entries) > MAX_FILES:
            raise InputFileError(f"{len(entries)} files: more than the {MAX_FILES} a scenario folder holds",
                                 file=source)
        for path in entries:
            match = LLMBT.fullmatch(path.name)
            if match:
                sc.trees.setdefault(f"human{int(match.group(1)) + 1}", read_text_limited(path))
            elif path.suffix == ".json":
                _take(load_json_file(path), path, sc)
    else:
        raise InputFileError("not found", file=source, hint="pass a SocRATES scenario file or folder")
    if not sc.trajectories:
        raise InputFileError("no trajectories found (SocRATES's trajectory reply)", file=source,
                             hint="the file or folder must hold SocRATES's `trajectories` reply")
    return sc


def to_plan(sc: SocratesScenario, graph: Any) -> tuple[PathPlan, list[str]]:
    """The PathPlan of a SocRATES scenario, checked on `graph` (every mistake listed); notes on what changed."""
    notes: list[str] = []
    if "robot" not in sc.trajectories:
        raise ValidationFailed("the trajectories have no robot", file=sc.source)
    humans = sorted((n for n in sc.trajectories if n != "robot"), key=lambda n: int(n[5:]))
    missing = [n for n in humans if n not in sc.trees]
    if missing:
        raise ValidationFailed(f"no behavior tree for {', '.join(missing)}", file=sc.source,
                               hint="SocRATES's behavior_trees (or its bt replies / LLMBT_<i>.xml) must cover "
                                    "every human with a trajectory")
    plans = []
    robot = sc.trajectories["robot"]
    for name in humans:
        point = sc.interaction_points.get(name)
        if point is not None and (point not in sc.trajectories[name] or point not in robot):
            notes.append(f"{name}'s interaction point {point} is not on both its trajectory and the robot's: "
                         "dropped")
            point = None
        plans.append(HumanPlan(name=name, path=sc.trajectories[name], group_id=sc.groupids.get(name, -1),
                               interaction_point=point))
    plan = PathPlan(reasoning=sc.reasoning, robot=robot, humans=plans)
    mistakes = plan_mistakes(plan, graph)
    if mistakes:
        raise ValidationFailed("the trajectories do not fit this location's scene graph: " + "; ".join(mistakes[:8]),
                               file=sc.source, hint="was the scenario made for another location? pass its "
                                                    "--location (socnavgen location import-socrates converts "
                                                    "SocRATES's annotator folder)")
    return plan, notes


def import_socrates_run(source: Path | str, location_dir: Path | str, out: Path | str) -> tuple[RunFolder, list[str]]:
    """Read a SocRATES scenario and write it as the run folder `out` on the location at `location_dir`."""
    from socnavgen.bt.validate import format_problems, validate_bt_text
    from socnavgen.location import load_location

    sc = read_socrates(source)
    location = load_location(Path(location_dir))
    plan, notes = to_plan(sc, location.scene_graph)
    ids = {h.agent_id for h in plan.humans}
    problems = []
    for human in plan.humans:
        problems += validate_bt_text(sc.trees[human.name], f"{sc.source}:{human.name}", target="socrates",
                                     human_ids=ids, agent_id=human.agent_id)
    if problems:
        raise ValidationFailed("behavior trees are not valid for the SocRATES node library:\n"
                               + format_problems(problems), file=sc.source,
                               hint="fix them in the SocRATES files (socnavgen bt check FILE checks one tree)")
    folder = RunFolder(Path(out))
    if folder.root.exists() and any(folder.root.iterdir()):
        raise InputFileError("the run folder exists and is not empty", file=folder.root,
                             hint="choose a new folder with -o")
    folder.root.mkdir(parents=True, exist_ok=True)
    extra = [n for n in sc.trees if n not in {h.name for h in plan.humans}]
    if extra:
        notes.append(f"trees without a trajectory ignored: {', '.join(sorted(extra))}")
    folder.write_request(ScenarioRequest(location=str(location.root), context=f"imported from SocRATES ({sc.source.name})",
                                         task=sc.expected_robot or "(not given by the SocRATES files)",
                                         llm="import:socrates"))
    folder.write_scenario(ScenarioProposal(
        scenario_description=sc.description or "(no scenario description in the SocRATES files)",
        number_of_humans=len(plan.humans),
        human_behaviors={h.name: sc.behaviors.get(h.name, "") for h in plan.humans},
        expected_robot_behavior=sc.expected_robot))
    folder.write_paths(plan)
    for human in plan.humans:
        folder.write_behavior(human.name, sc.trees[human.name].rstrip() + "\n")
    folder.write_manifest(Manifest(socnavgen_version=__version__, created=dt.datetime.now(dt.UTC).isoformat(),
                                   llm="import:socrates", status="done",
                                   stages={"import": StageRecord(status="done")},
                                   message=f"imported from SocRATES: {sc.source}"))
    return folder, notes
