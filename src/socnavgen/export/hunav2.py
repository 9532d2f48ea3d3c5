"""Target `hunav2`: upstream HuNavSim 2.x (BT.CPP v4, reference §5 and §8.3).

Each human gets a self-contained `<base>__agent_<id>_bt.xml` (ids from 1, as HuNavSim numbers agents):
the tree translated node by node through `bt.library.HUNAV2` (each leaf becomes the 2.x composition
the table gives, with the reason it behaves the same), controls and built-ins under their row's `hunav2`
name (Sequence/Fallback become reactive so that gates are re-checked every tick while a stateful 2.x node
is RUNNING), SubTree remapping in v4 syntax, the RegularNavTree it uses inlined, goals
queued by `SetGoal` inside `RunOnce` as upstream's own scenario trees do, and a TreeNodesModel for
Groot2. With the run's scene, phrase conditions become the robot script's conditions (export.speech) and a
person who meets the robot waits for it (export.timing); the export's own latches keep their memory. A node
without a 2.x counterpart stops the export with every such node listed."""

from __future__ import annotations

import re
from dataclasses import dataclass
from xml.sax.saxutils import escape

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_MAX_SPEED, PERSON_RADIUS
from socnavgen.bt.expand import check_text
from socnavgen.bt.library import HUMAN_GESTURES, HUNAV2, HUNAV2_FIRST_AGENT_ID, NodeSpec
from socnavgen.bt.model import Node, SubTreeCall, literal_text
from socnavgen.bt.tree import BTElement, read_xml
from socnavgen.errors import ValidationFailed
from socnavgen.export.groot import model_block, tree_nodes_model_xml
from socnavgen.export.models import (
    HUMAN_Z,
    ExportedFile,
    ExportScene,
    HumanExport,
)
from socnavgen.export.readme import hunav2_readme
from socnavgen.export.robot_script import script_yaml
from socnavgen.export.socrates import check_trees
from socnavgen.export.speech import Spoken, rewrite_phrases
from socnavgen.export.targets import ExportTarget, register
from socnavgen.export.timing import Hold, hold_root, with_waiting_goals
from socnavgen.export.writer import dump_yaml, element_xml, metres, robot_poses_yaml

WRAPPER = "hunav_gazebo_wrapper"
SIMULATORS = ("Gazebo Classic", "Gazebo Fortress", "Isaac Sim", "Webots")
# behavior block of a 2.x agent: configuration 0 = the default factors below (reference §5)
BEHAVIOR_DEFAULTS = {"type": "Regular", "configuration": 0, "goal_force_factor": 2.0,
                     "obstacle_force_factor": 10.0, "social_force_factor": 5.0, "other_force_factor": 20.0}
# Queue the agent's goals once, as upstream's scenario trees do: RunOnce(SetGoal) per goal, the last one
# inverted so the Sequence fails the first tick and the Fallback moves on to the tree (its last child);
# afterwards every RunOnce is skipped.
GOAL_QUEUE = ('<Fallback name="QueueGoalsThenBehave"><Sequence name="SetGoals">{first}<Inverter>{last}</Inverter>'
              '</Sequence></Fallback>')
GOAL_SET = '<RunOnce><SetGoal agent_id="{{id}}" goal_id="{goal}"/></RunOnce>'


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


def _element(xml: str, line: int | None = None) -> BTElement:
    """A v4 element written as text (a translation template, the goal queue), with `line` on every node."""
    def relined(elem: BTElement) -> BTElement:
        return BTElement(elem.tag, elem.attrs, [relined(c) for c in elem.children], line)
    return relined(read_xml(xml, "bt.library.HUNAV2", tag=None))


class _Translator:
    """Our typed tree (v3 or v4) -> v4 with HuNavSim 2.x's nodes (the compositions of `bt.library.HUNAV2`);
    controls and built-ins take their `hunav2` name from the library row, except the controls in `keep` (the
    export's latches, which must remember their RUNNING child); 2.x nodes already in the tree (the export's
    own conditions) stay as they are; collects every refusal."""

    def __init__(self, source: str, keep: set[Node] | None = None) -> None:
        self.source = source
        self.keep = keep or set()
        self.problems: list[Untranslatable] = []
        self.used_leaves: set[str] = set()
        self.called: list[str] = []

    def node(self, node: Node) -> BTElement:
        spec = node.spec
        assert spec is not None  # a Document without problems, or a node the export built from the table
        if spec.kind in ("action", "condition"):
            return self.leaf(node, spec)
        attrs = {"name": node.label} if node.label is not None else {}
        if node.call is not None:
            attrs = {"ID": node.call.tree, **attrs, **self.remapping(node.call)}
            self.called.append(node.call.tree)
        else:
            attrs.update({k: literal_text(v) for k, v in node.ports.items()})
        name = node.name if node in self.keep else spec.hunav2 or spec.name
        return BTElement(name, attrs, [self.node(c) for c in node.children], node.line)

    def leaf(self, node: Node, spec: NodeSpec) -> BTElement:
        label = {"name": node.label} if node.label is not None else {}
        if spec.targets == {"hunav2"}:  # already a 2.x node
            self.used_leaves.add(node.name)
            return BTElement(node.name, {**label, **{k: literal_text(v) for k, v in node.ports.items()}}, [],
                             node.line)
        tr = HUNAV2.get(node.name)
        if tr is None or tr.template is None:
            why = "has no HuNavSim 2.x translation" if tr is None else tr.refusal or (
                "becomes the robot script's condition, which needs the run (export the run, not the tree alone)")
            self.problems.append(Untranslatable(self.source, node.line, node.name, f"cannot be exported: {why}"))
            return BTElement(node.name, {}, [], node.line)
        typed = {p.name: value for p in spec.ports if (value := node.value(p.name)) is not None}
        for port in tr.target_ports:  # literal agent ids: ours from 0, HuNavSim's from 1
            if isinstance(agent := typed.get(port), int):
                typed[port] = agent + HUNAV2_FIRST_AGENT_ID
        values = {k: literal_text(v) for k, v in typed.items()}
        if isinstance(message := typed.get("message"), int):
            values["message_word"] = HUMAN_GESTURES.get(message, values["message"])
        template = tr.template
        for port, choices in tr.by_value.items():
            template = choices.get(values.get(port, ""), template)
        out = _element(template.format(**{k: escape(v, {'"': "&quot;"}) for k, v in values.items()}), node.line)
        self.used_leaves.update(e.tag for e in out.walk())
        if label:  # the node's name, on the element that stands for it
            out.attrs = {**label, **out.attrs}
        return out

    @staticmethod
    def remapping(call: SubTreeCall) -> dict[str, str]:
        """v4 remapping: `{key}` names the caller's entry, a plain value is a constant; a v3 shared
        blackboard becomes v4's _autoremap (every key is the caller's of the same name)."""
        out = {k: literal_text(v) for k, v in call.remap.items()}
        if call.shared or call.autoremap:
            out["_autoremap"] = "true"
        return out


@dataclass
class Translated:
    """One person's 2.x tree file, what could not be translated, and the phrase conditions it approximates."""

    text: str
    problems: list[Untranslatable]
    spoken: list[Spoken]


def translate_person(human: HumanExport, goal_ids: list[int] | None, scene: ExportScene | None = None,
                     hold: Hold | None = None) -> Translated:
    """The person's tree (one bt check accepts) as one self-contained v4 file. With `scene`: phrase conditions
    made the robot script's (export.speech); with `hold`: the person timed (export.timing); without, the tree
    alone. `goal_ids` None: no goal queue (our simulator reads goals from paths.json)."""
    doc, instance, problems = check_text(human.tree_xml, human.tree_file)
    if doc is None or instance is None or doc.main_tree is None:
        return Translated("", [Untranslatable(human.tree_file, p.line, "tree", p.message) for p in problems], [])
    keep: set[Node] = set()
    roots = {tid: t.root for tid, t in doc.trees.items() if t.root is not None}
    spoken: list[Spoken] = []
    refused: list[Untranslatable] = []
    if scene is not None:
        roots, spoken = rewrite_phrases(doc, human, scene, keep)
        refused = [Untranslatable(human.tree_file, s.line, s.node, f"cannot be exported: {s.text}")
                   for s in spoken if s.refused]
    main = doc.main_tree
    if hold is not None:
        roots[main] = hold_root(roots[main], hold, keep)
    tr = _Translator(human.tree_file, keep)
    trees = {tid: tr.node(root) for tid, root in roots.items()}
    while missing := [tid for tid in tr.called if tid not in trees]:  # library trees, inlined
        for tid in missing:
            tree = doc.tree(tid)
            assert tree is not None and tree.root is not None
            trees[tid] = tr.node(tree.root)
    said = {(r.node, r.line) for r in refused}  # a refused phrase node stays in the tree: named once
    problems_out = refused + [p for p in tr.problems if (p.node, p.line) not in said]
    if problems_out:
        return Translated("", problems_out, spoken)
    if goal_ids:
        sets = [GOAL_SET.format(goal=g) for g in goal_ids]
        top = _element(GOAL_QUEUE.format(first="".join(sets[:-1]), last=sets[-1]))
        top.children.append(trees[main])
        trees[main] = top
    ordered = [main, *(tid for tid in trees if tid != main)]
    text = ('<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<root BTCPP_format="4" main_tree_to_execute="{main}">\n'
            + model_block("hunav2", tr.used_leaves | {"SetGoal"})
            + "".join(element_xml(BTElement("BehaviorTree", {"ID": tid}, [trees[tid]])) for tid in ordered)
            + "</root>\n")
    return Translated(text, [], spoken)


def translate_tree(human: HumanExport, goal_ids: list[int] | None) -> tuple[str, list[Untranslatable]]:
    """The human's tree alone (no timing, no phrase conditions: those need the run) as one self-contained v4
    file (text), plus what could not be translated."""
    out = translate_person(human, goal_ids)
    return out.text, out.problems


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
    scene, holds = with_waiting_goals(scene)
    table, goal_ids = global_goals(scene)
    files: list[ExportedFile] = []
    problems: list[Untranslatable] = []
    spoken: dict[str, list[Spoken]] = {}
    for human in scene.humans:
        out = translate_person(human, goal_ids[human.name], scene, holds.get(human.name))
        problems += out.problems
        spoken[human.name] = out.spoken
        files.append(ExportedFile(path=f"{WRAPPER}/behavior_trees/{base}__agent_{hunav_id(human)}_bt.xml",
                                  text=out.text))
    if problems:
        raise ValidationFailed(
            f"{len(problems)} node(s) have no HuNavSim 2.x equivalent:\n" + "\n".join(str(p) for p in problems),
            hint="export with --format socrates, or replace these nodes (socnavgen bt library shows the 2.x names)")
    files.append(ExportedFile(path=f"{WRAPPER}/behavior_trees/TreeNodesModel.xml", text=tree_nodes_model_xml("hunav2")))
    files.append(ExportedFile(path=f"{WRAPPER}/scenarios/{base}.yaml",
                              text=agents_yaml(scene, base, simulator, goal_ids, table)))
    files.append(ExportedFile(path="robot/robot_poses.yaml", text=robot_poses_yaml(scene.robot)))
    files.append(ExportedFile(path="robot/robot_script.yaml", text=script_yaml(scene)))
    files.append(ExportedFile(path="README.md", text=hunav2_readme(scene, base, simulator, spoken, holds)))
    return files


@register
class Hunav2Target(ExportTarget):
    name = "hunav2"
    summary = "upstream HuNavSim 2.x (BT.CPP v4, <base>__agent_<id>_bt.xml per agent, global_goals, ids from 1)"
    btcpp = "4"
    first_agent_id = HUNAV2_FIRST_AGENT_ID

    def build(self, scene: ExportScene, *, base: str, simulator: str) -> list[ExportedFile]:
        return build_hunav2(scene, base_name(base or f"socnavgen_{scene.run_name}"), simulator)
