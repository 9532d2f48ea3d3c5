"""Target `hunav2`: upstream HuNavSim 2.x (BT.CPP v4, reference §5 and §8.3).

Each human gets a self-contained `<base>__agent_<id>_bt.xml` (ids from 1, as HuNavSim numbers agents):
the tree translated node by node through `bt.library.HUNAV2` (each leaf becomes the 2.x composition
the table gives, with the reason it behaves the same), Sequence/Fallback made reactive so that gates
are re-checked every tick while a stateful 2.x node is RUNNING, the RegularNavTree it uses inlined, goals
queued by `SetGoal` inside `RunOnce` as upstream's own scenario trees do, and a TreeNodesModel for
Groot2. A node without a 2.x counterpart stops the export with every such node listed."""

from __future__ import annotations

import re
from dataclasses import dataclass

from defusedxml.ElementTree import fromstring

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_MAX_SPEED, PERSON_RADIUS
from socnavgen.bt.library import (
    HUMAN_GESTURES,
    HUNAV2,
    HUNAV2_FIRST_AGENT_ID,
    LIBRARY,
    LIBRARY_TREE_XML,
    LIBRARY_TREES,
)
from socnavgen.bt.tree import BTDocument, BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.export.groot import model_block, tree_nodes_model_xml
from socnavgen.export.models import (
    HUMAN_Z,
    ExportedFile,
    ExportScene,
    HumanExport,
)
from socnavgen.export.readme import hunav2_readme
from socnavgen.export.socrates import check_trees
from socnavgen.export.targets import ExportTarget, register
from socnavgen.export.writer import dump_yaml, element_xml, metres, robot_poses_yaml

WRAPPER = "hunav_gazebo_wrapper"
EXPLICIT = {"Action", "Condition", "Control", "Decorator"}  # <Action ID="X"/> form
NOT_NODES = {"TreeNodesModel"}
BLACKBOARD_REF = re.compile(r"^\{[^{}]+\}$")
SIMULATORS = ("Gazebo Classic", "Gazebo Fortress", "Isaac Sim", "Webots")
# behavior block of a 2.x agent: configuration 0 = the default factors below (reference §5)
BEHAVIOR_DEFAULTS = {"type": "Regular", "configuration": 0, "goal_force_factor": 2.0,
                     "obstacle_force_factor": 10.0, "social_force_factor": 5.0, "other_force_factor": 20.0}


@dataclass(frozen=True)
class Untranslatable:
    file: str
    line: int | None
    node: str
    why: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{where}: {self.node} {self.why}"


def hunav_id(human: HumanExport) -> int:
    """HuNavSim's id of a human (1-based; ours are 0-based)."""
    return human.agent_id + HUNAV2_FIRST_AGENT_ID


def base_name(text: str) -> str:
    """yaml_base_name must be a plain file stem: lowercase letters, digits, underscores."""
    stem = re.sub(r"[^a-z0-9_]+", "_", text.lower()).strip("_")
    return stem or "socnavgen"


def _node_name(elem: BTElement) -> str:
    return elem.attrs.get("ID", elem.tag) if elem.tag in EXPLICIT else elem.tag


CONTROL_V4 = {"Sequence": "ReactiveSequence", "Fallback": "ReactiveFallback"}


def _from_template(xml: str, line: int | None) -> BTElement:
    root = fromstring(xml)
    return BTElement(tag=root.tag, attrs=dict(root.attrib), children=[_from_template_el(c, line) for c in root],
                     line=line)


def _from_template_el(el, line: int | None) -> BTElement:  # noqa: ANN001 - ElementTree element
    return BTElement(tag=el.tag, attrs=dict(el.attrib), children=[_from_template_el(c, line) for c in el], line=line)


class _Translator:
    """v3 (our library) -> v4 (2.x compositions of `bt.library.HUNAV2`); collects every refusal."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.problems: list[Untranslatable] = []
        self.used_leaves: set[str] = set()
        self.subtrees: set[str] = set()

    def element(self, elem: BTElement) -> BTElement:
        name = _node_name(elem)
        spec = LIBRARY.get(name)
        children = [self.element(c) for c in elem.children if c.tag not in NOT_NODES]
        if spec is None:
            self.problems.append(Untranslatable(self.source, elem.line, name, "is not a library node"))
            return BTElement(tag=name, attrs={}, children=children, line=elem.line)
        attrs = {k: v for k, v in elem.attrs.items() if not (elem.tag in EXPLICIT and k == "ID")}
        if spec.kind in ("action", "condition"):
            return self.leaf(name, attrs, elem.line)
        if name == "SubTree":
            return BTElement(tag="SubTree", attrs=self.subtree_attrs(attrs), children=children, line=elem.line)
        return BTElement(tag=CONTROL_V4.get(name, name), attrs=attrs, children=children, line=elem.line)

    def leaf(self, name: str, attrs: dict[str, str], line: int | None) -> BTElement:
        tr = HUNAV2.get(name)
        if tr is None or tr.template is None:
            why = tr.refusal if tr is not None else "has no HuNavSim 2.x translation"
            self.problems.append(Untranslatable(self.source, line, name, f"cannot be exported: {why}"))
            return BTElement(tag=name, attrs={}, children=[], line=line)
        values = {p.name: p.default for p in LIBRARY[name].ports if p.default is not None}
        values.update({k: v.strip() for k, v in attrs.items()})
        for port in tr.target_ports:  # literal agent ids: ours from 0, HuNavSim's from 1
            if port in values and values[port].lstrip("-").isdigit():
                values[port] = str(int(values[port]) + HUNAV2_FIRST_AGENT_ID)
        template = tr.template
        for port, choices in tr.by_value.items():
            if values.get(port) in choices:
                template = choices[values[port]]
        if "message" in values and values["message"].isdigit():
            values["message_word"] = HUMAN_GESTURES.get(int(values["message"]), values["message"])
        try:
            out = _from_template(template.format(**{k: _attr_text(v) for k, v in values.items()}), line)
        except KeyError as missing:
            self.problems.append(Untranslatable(self.source, line, name, f"lacks port {missing}"))
            return BTElement(tag=name, attrs={}, children=[], line=line)
        self.used_leaves.update(e.tag for e in out.walk())
        return out

    def subtree_attrs(self, attrs: dict[str, str]) -> dict[str, str]:
        """v3 remaps a subtree port with a plain parent key (`id="agentid"`); v4 writes `{agentid}`."""
        out: dict[str, str] = {}
        for key, value in attrs.items():
            if key in ("ID", "name", "_autoremap") or BLACKBOARD_REF.match(value):
                out[key] = value
            else:
                out[key] = "{" + value + "}"
        self.subtrees.add(attrs.get("ID", ""))
        return out


def _attr_text(value: str) -> str:
    """A value placed inside a template's double-quoted attribute."""
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def _goal_prelude(goal_ids: list[int]) -> BTElement:
    """Queue the agent's goals once, as upstream's scenario trees do: RunOnce(SetGoal) per goal, the
    last one inverted so the Sequence fails the first tick and the Fallback moves on to walking;
    afterwards every RunOnce is skipped."""
    children = [BTElement("RunOnce", {}, [BTElement("SetGoal", {"agent_id": "{id}", "goal_id": str(g)})])
                for g in goal_ids]
    children[-1] = BTElement("Inverter", {}, [children[-1]])
    return BTElement("Sequence", {"name": "SetGoals"}, children)


def translate_tree(human: HumanExport, goal_ids: list[int] | None) -> tuple[str, list[Untranslatable]]:
    """The human's v3 tree as one self-contained v4 file (text), plus what could not be translated."""
    doc: BTDocument = parse_bt(human.tree_xml, human.tree_file)
    tr = _Translator(human.tree_file)
    problems: list[Untranslatable] = []
    main = doc.main_tree or next(iter(doc.trees), None)
    if main is None or main not in doc.trees:
        problems.append(Untranslatable(human.tree_file, doc.root.line, "root", f"main tree {main!r} not found"))
        return "", problems
    trees = {tid: BTElement("BehaviorTree", {"ID": tid}, [tr.element(c) for c in t.children], t.line)
             for tid, t in doc.trees.items()}
    library_ids = {tid: fname for fname, tid in LIBRARY_TREES.items()}
    for include in doc.includes:
        if include not in LIBRARY_TREE_XML:
            problems.append(Untranslatable(human.tree_file, doc.root.line, f"include {include!r}",
                                           "is not a library tree; 2.x files must be self-contained"))
    for tid in sorted(tr.subtrees - set(trees)):
        if tid in library_ids:
            lib = parse_bt(LIBRARY_TREE_XML[library_ids[tid]], library_ids[tid])
            trees[tid] = BTElement("BehaviorTree", {"ID": tid}, [tr.element(c) for c in lib.trees[tid].children])
        else:
            problems.append(Untranslatable(human.tree_file, None, f"SubTree {tid!r}", "names no known tree"))
    problems += tr.problems
    if problems:
        return "", problems
    if goal_ids:  # None: goals come from elsewhere (our simulator reads them from paths.json)
        body = trees[main].children[0]
        trees[main] = BTElement("BehaviorTree", {"ID": main}, [
            BTElement("Fallback", {"name": "QueueGoalsThenBehave"}, [_goal_prelude(goal_ids), body])])
    ordered = [trees[main]] + [t for tid, t in trees.items() if tid != main]
    text = ('<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<root BTCPP_format="4" main_tree_to_execute="{main}">\n'
            + model_block("hunav2", tr.used_leaves | {"SetGoal"})
            + "".join(element_xml(t) for t in ordered)
            + "</root>\n")
    return text, []


def global_goals(scene: ExportScene) -> tuple[dict[int, dict[str, float]], dict[str, list[int]]]:
    """One global goal per scene-graph node (ids 1.. in first-use order); each human's goal ids."""
    ids: dict[str, int] = {}
    table: dict[int, dict[str, float]] = {}
    per_human: dict[str, list[int]] = {}
    for human in scene.humans:
        per_human[human.name] = []
        for goal in human.goals:
            if goal.node not in ids:
                ids[goal.node] = len(ids) + 1
                table[ids[goal.node]] = {"x": metres(goal.x), "y": metres(goal.y)}
            per_human[human.name].append(ids[goal.node])
    return table, per_human


def agents_yaml(scene: ExportScene, base: str, simulator: str, goal_ids: dict[str, list[int]],
                table: dict[int, dict[str, float]]) -> str:
    params: dict = {"yaml_base_name": base, "simulator": simulator, "map": scene.location_name,
                    "publish_people": True, "global_goals": table, "agents": [h.name for h in scene.humans]}
    for h in scene.humans:
        params[h.name] = {
            "id": hunav_id(h), "group_id": h.group_id, "skin": h.skin, "max_vel": PERSON_MAX_SPEED,
            "radius": PERSON_RADIUS, "goal_radius": PERSON_GOAL_RADIUS, "cyclic_goals": False,
            "init_pose": {"x": metres(h.start.x), "y": metres(h.start.y), "z": HUMAN_Z, "h": metres(h.start.yaw)},
            "behavior": dict(BEHAVIOR_DEFAULTS),
            "goals": goal_ids[h.name],
        }
    return dump_yaml({"hunav_loader": {"ros__parameters": params}})


def build_hunav2(scene: ExportScene, base: str, simulator: str = "Gazebo Classic") -> list[ExportedFile]:
    if simulator not in SIMULATORS:
        raise ValidationFailed(f"unknown simulator {simulator!r}", hint="one of: " + ", ".join(SIMULATORS))
    check_trees(scene)
    table, goal_ids = global_goals(scene)
    files: list[ExportedFile] = []
    problems: list[Untranslatable] = []
    for human in scene.humans:
        text, bad = translate_tree(human, goal_ids[human.name])
        problems += bad
        files.append(ExportedFile(path=f"{WRAPPER}/behavior_trees/{base}__agent_{hunav_id(human)}_bt.xml",
                                  text=text))
    if problems:
        raise ValidationFailed(
            f"{len(problems)} node(s) have no HuNavSim 2.x equivalent:\n" + "\n".join(str(p) for p in problems),
            hint="export with --format socrates, or replace these nodes (socnavgen bt library shows the 2.x names)")
    files.append(ExportedFile(path=f"{WRAPPER}/behavior_trees/TreeNodesModel.xml", text=tree_nodes_model_xml("hunav2")))
    files.append(ExportedFile(path=f"{WRAPPER}/scenarios/{base}.yaml",
                              text=agents_yaml(scene, base, simulator, goal_ids, table)))
    files.append(ExportedFile(path="robot/robot_poses.yaml", text=robot_poses_yaml(scene.robot)))
    files.append(ExportedFile(path="README.md", text=hunav2_readme(scene, base, simulator)))
    return files


@register
class Hunav2Target(ExportTarget):
    name = "hunav2"
    summary = "upstream HuNavSim 2.x (BT.CPP v4, <base>__agent_<id>_bt.xml per agent, global_goals, ids from 1)"
    btcpp = "4"
    first_agent_id = HUNAV2_FIRST_AGENT_ID

    def build(self, scene: ExportScene, *, base: str, simulator: str) -> list[ExportedFile]:
        return build_hunav2(scene, base_name(base or f"socnavgen_{scene.run_name}"), simulator)
