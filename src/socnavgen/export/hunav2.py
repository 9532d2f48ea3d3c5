"""Target `hunav2`: upstream HuNavSim 2.x (BT.CPP v4, reference §5 and §8.3).

Each human gets a self-contained `<base>__agent_<id>_bt.xml` (ids from 1, as HuNavSim numbers agents):
the tree translated node by node through `bt.library.HUNAV2` (each leaf becomes the 2.x composition
the table gives, with the reason it behaves the same), Sequence/Fallback made reactive so that gates
are re-checked every tick while a stateful 2.x node is RUNNING, the RegularNavTree it uses inlined, goals
queued by `SetGoal` inside `RunOnce` as upstream's own scenario trees do, and a TreeNodesModel for
Groot2. A node without a 2.x counterpart stops the export with every such node listed."""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from defusedxml.ElementTree import fromstring

from socnavgen.bodies import PERSON_GOAL_RADIUS, PERSON_MAX_SPEED, PERSON_RADIUS
from socnavgen.bt.library import (
    HUMAN_GESTURES,
    HUNAV2,
    HUNAV2_FIRST_AGENT_ID,
    LIBRARY,
)
from socnavgen.bt.model import BLACKBOARD_REF, Node, Ref, Value, literal_text
from socnavgen.bt.parse import parse_document
from socnavgen.bt.write import document_xml, node
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
from socnavgen.export.writer import dump_yaml, metres, robot_poses_yaml

WRAPPER = "hunav_gazebo_wrapper"
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


CONTROL_V4 = {"Sequence": "ReactiveSequence", "Fallback": "ReactiveFallback"}


def _from_template(el, line: int | None) -> Node:  # noqa: ANN001 - ElementTree element
    """A filled-in template element as a typed node (2.x names; port texts kept as written)."""
    spec = LIBRARY.get(el.tag)
    ports: dict[str, Value] = {k: Ref(v[1:-1]) if BLACKBOARD_REF.match(v) else v for k, v in el.attrib.items()}
    return Node(el.tag, spec.kind if spec is not None else "action", ports,
                tuple(_from_template(c, line) for c in el), line)


class _Translator:
    """A typed v3 tree of our library -> the 2.x compositions of `bt.library.HUNAV2`; collects every refusal.
    Sequence/Fallback become reactive, except the controls in `keep` (the export's own latches, which must
    remember their RUNNING child)."""

    def __init__(self, source: str, keep: set[Node]) -> None:
        self.source, self.keep = source, keep
        self.problems: list[Untranslatable] = []
        self.used_leaves: set[str] = set()
        self.subtrees: set[str] = set()

    def node(self, n: Node) -> Node:
        spec = n.spec
        if spec is None or n.kind == "unknown":
            self.problems.append(Untranslatable(self.source, n.line, n.name, "is not a library node"))
            return n
        if n.call is not None:
            self.subtrees.add(n.call.tree)
            return n
        if spec.kind in ("action", "condition"):
            if spec.targets == {"hunav2"}:  # already a 2.x node (the export's own conditions)
                self.used_leaves.add(n.name)
                return n
            return self.leaf(n)
        name = n.name if n in self.keep else CONTROL_V4.get(n.name, n.name)
        return replace(n, name=name, children=tuple(self.node(c) for c in n.children))

    def leaf(self, n: Node) -> Node:
        tr = HUNAV2.get(n.name)
        if tr is None or tr.template is None:
            why = "has no HuNavSim 2.x translation" if tr is None else tr.refusal or (
                "becomes the robot script's condition, which needs the run (export the run, not the tree alone)")
            self.problems.append(Untranslatable(self.source, n.line, n.name, f"cannot be exported: {why}"))
            return n
        values = {p.name: p.default for p in LIBRARY[n.name].ports if p.default is not None}
        values.update({k: literal_text(v).strip() for k, v in n.ports.items()})
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
            out = _from_template(fromstring(template.format(**{k: _attr_text(v) for k, v in values.items()})),
                                 n.line)
        except KeyError as missing:
            self.problems.append(Untranslatable(self.source, n.line, n.name, f"lacks port {missing}"))
            return n
        self.used_leaves.update(x.name for x in out.walk())
        return replace(out, label=n.label)


def _attr_text(value: str) -> str:
    """A value placed inside a template's double-quoted attribute."""
    return value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")


def _goal_prelude(goal_ids: list[int]) -> Node:
    """Queue the agent's goals once, as upstream's scenario trees do: RunOnce(SetGoal) per goal, the
    last one inverted so the Sequence fails the first tick and the Fallback moves on to walking;
    afterwards every RunOnce is skipped. (SetGoal and RunOnce are 2.x / BT.CPP 4 nodes our library lacks.)"""
    children = [Node("RunOnce", "decorator", {}, (Node("SetGoal", "action", {"agent_id": Ref("id"), "goal_id": g}),))
                for g in goal_ids]
    children[-1] = node("Inverter", children[-1])
    return Node("Sequence", "control", {}, tuple(children), label="SetGoals")


@dataclass
class Translated:
    """One person's 2.x tree file, what could not be translated, and the phrase conditions it approximates."""

    text: str
    problems: list[Untranslatable]
    spoken: list[Spoken]


def translate_person(human: HumanExport, goal_ids: list[int] | None, scene: ExportScene | None = None,
                     hold: Hold | None = None) -> Translated:
    """The person's tree as one self-contained v4 file. With `scene`: phrase conditions made geometric
    (export.speech); with `hold`: the person timed (export.timing); without, the tree alone (as written)."""
    doc, parse_problems = parse_document(human.tree_xml, human.tree_file)
    if doc is None or parse_problems or doc.main is None or doc.main.root is None:
        why = "; ".join(p.message for p in parse_problems) or f"main tree {doc and doc.main_tree!r} not found"
        return Translated("", [Untranslatable(human.tree_file, doc.line if doc else None, "root", why)], [])
    keep: set[Node] = set()
    roots = {tid: t.root for tid, t in doc.trees.items() if t.root is not None}
    spoken: list[Spoken] = []
    problems: list[Untranslatable] = []
    if scene is not None:
        roots, spoken = rewrite_phrases(doc, human, scene, keep)
        problems += [Untranslatable(human.tree_file, s.line, s.node, f"cannot be exported: {s.text}")
                     for s in spoken if s.refused]
    if hold is not None:
        roots[doc.main_tree] = hold_root(roots[doc.main_tree], hold, keep)
    tr = _Translator(human.tree_file, keep)
    trees = {tid: tr.node(root) for tid, root in roots.items()}
    for tid in sorted(tr.subtrees - set(trees)):
        tree = doc.included.get(tid)
        if tree is not None and tree.root is not None:
            trees[tid] = tr.node(tree.root)
        else:
            problems.append(Untranslatable(human.tree_file, None, f"SubTree {tid!r}", "names no known tree"))
    problems += tr.problems
    if problems:
        return Translated("", problems, spoken)
    main = doc.main_tree
    if goal_ids:  # None: goals come from elsewhere (our simulator reads them from paths.json)
        trees[main] = Node("Fallback", "control", {}, (_goal_prelude(goal_ids), trees[main]),
                           label="QueueGoalsThenBehave")
    text = document_xml(doc, version=4, roots=trees, includes=(),
                        head=model_block("hunav2", tr.used_leaves | {"SetGoal"}))
    return Translated('<?xml version="1.0" encoding="UTF-8"?>\n' + text, [], spoken)


def translate_tree(human: HumanExport, goal_ids: list[int] | None) -> tuple[str, list[Untranslatable]]:
    """The person's tree alone, translated (no timing, no phrase conditions): (text, what could not be)."""
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
