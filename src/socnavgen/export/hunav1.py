"""Target `hunav1`: upstream HuNavSim 1.x, which loads only its built-in trees (behavior 1..6).

A human can be exported only when its tree IS one of those built-in behaviors, compared after
normalising what does not change meaning (names, SetBlackboard copies for the RegularNavTree
subtree, nested Sequences). Anything else is refused, naming the human and the node."""

from __future__ import annotations

from dataclasses import dataclass

from socnavgen.bt.library import HUNAV2_FIRST_AGENT_ID, LIBRARY, LIBRARY_TREE_XML, LIBRARY_TREES
from socnavgen.bt.tree import BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.export.models import ExportedFile, ExportScene, HumanExport
from socnavgen.export.readme import hunav1_readme
from socnavgen.export.robot_script import script_yaml
from socnavgen.export.socrates import check_trees, fork_agents_yaml
from socnavgen.export.targets import ExportTarget, register
from socnavgen.export.writer import robot_poses_yaml

EXPLICIT = {"Action", "Condition", "Control", "Decorator"}
SUBTREE_COPIES = {("agentid", "{id}"), ("timestep", "{dt}")}
OWN_PORTS = {("agent_id", "{id}"), ("time_step", "{dt}")}  # always the same; not part of a pattern

# The built-in 1.x behaviors (reference §2.8, §3.7) written with OUR node names: Regular is the
# goal-walking loop; the others react to a visible robot for a limited time, else walk regularly.
REGULAR = ("Fallback", (), (("Sequence", (), (("Inverter", (), (("IsGoalReached", (), ()),)),
                                              ("RegularNav", (), ()))),
                            ("UpdateGoal", (), ())))


def _reactive(distance: float, seconds: float, only_once: bool, action: str) -> tuple:
    return ("Fallback", (), (
        ("Sequence", (), (
            ("IsRobotVisible", (("distance", distance),), ()),
            ("Inverter", (), (("TimeExpiredCondition", (("only_once", only_once), ("seconds", seconds),
                                                        ("ts", "{dt}")), ()),)),
            (action, (), ()))),
        REGULAR[2][0], REGULAR[2][1]))


BUILTIN: dict[int, tuple[str, tuple]] = {
    1: ("REGULAR", REGULAR),
    3: ("SURPRISED", _reactive(4.0, 30.0, True, "LookAtRobot")),
    4: ("SCARED", _reactive(3.0, 40.0, False, "RunAwayFromRobot")),
    5: ("CURIOUS", _reactive(10.0, 30.0, True, "FollowRobot")),
    6: ("THREATENING", _reactive(4.0, 40.0, True, "BlockRobot")),
}


@dataclass(frozen=True)
class Refusal:
    human: str
    file: str
    line: int | None
    why: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{self.human} ({where}): {self.why}"


def _literal(value: str) -> object:
    text = value.strip()
    if text in ("true", "True", "TRUE"):
        return True
    if text in ("false", "False", "FALSE"):
        return False
    try:
        return float(text)
    except ValueError:
        return text


def _canonical(elem: BTElement, trees: dict[str, BTElement]) -> tuple | None:
    """(name, ports, children) with meaning-free details removed; None for nodes that vanish."""
    name = elem.attrs.get("ID", elem.tag) if elem.tag in EXPLICIT else elem.tag
    if name == "SetBlackboard" and (elem.attrs.get("output_key"), elem.attrs.get("value")) in SUBTREE_COPIES:
        return None
    if name == "SubTree":
        target = trees.get(elem.attrs.get("ID", ""))
        return _canonical(target.children[0], trees) if target is not None and target.children else ("SubTree", (), ())
    ports = tuple(sorted((k, _literal(v)) for k, v in elem.attrs.items()
                         if k not in ("name", "ID") and (k, v) not in OWN_PORTS))
    children: list[tuple] = []
    for child in elem.children:
        c = _canonical(child, trees)
        if c is None:
            continue
        if c[0] == name and name in ("Sequence", "Fallback"):  # nested same control = one level
            children.extend(c[2])
        else:
            children.append(c)
    if name in ("Sequence", "Fallback") and len(children) == 1:
        return children[0]
    return (name, ports, tuple(children))


def builtin_behavior(human: HumanExport) -> tuple[int | None, list[Refusal]]:
    """The 1.x behavior code this human's tree is, or the reasons it is none."""
    doc = parse_bt(human.tree_xml, human.tree_file)
    refusals = []
    for elem in doc.root.walk():
        name = elem.attrs.get("ID", elem.tag) if elem.tag in EXPLICIT else elem.tag
        spec = LIBRARY.get(name)
        if spec is not None and spec.kind in ("action", "condition") and spec.hunav1 is None:
            refusals.append(Refusal(human.name, human.tree_file, elem.line,
                                    f"node {name} does not exist in HuNavSim 1.x"))
    if refusals:
        return None, refusals
    trees = dict(doc.trees)
    for fname, tid in LIBRARY_TREES.items():
        trees.setdefault(tid, parse_bt(LIBRARY_TREE_XML[fname], fname).trees[tid])
    main = trees.get(doc.main_tree or "")
    shape = _canonical(main.children[0], trees) if main is not None and main.children else None
    for code, (_, pattern) in BUILTIN.items():
        if shape == pattern:
            return code, []
    names = ", ".join(f"{code} {label}" for code, (label, _) in BUILTIN.items())
    return None, [Refusal(human.name, human.tree_file, main.line if main is not None else None,
                          f"the tree is not one of the built-in 1.x behaviors ({names}); "
                          "HuNavSim 1.x cannot load custom trees")]


def build_hunav1(scene: ExportScene) -> list[ExportedFile]:
    check_trees(scene)
    behaviors: dict[str, int] = {}
    refusals: list[Refusal] = []
    for human in scene.humans:
        code, why = builtin_behavior(human)
        refusals += why
        if code is not None:
            behaviors[human.name] = code
    if refusals:
        raise ValidationFailed("HuNavSim 1.x runs only its built-in behaviors; refused:\n"
                               + "\n".join(str(r) for r in refusals),
                               hint="export with --format socrates (the SocRATES fork runs any library tree)")
    return [
        ExportedFile(path="hunav_agent_manager/config/agents.yaml",
                     text=fork_agents_yaml(scene, behaviors, "g", 0, first_id=HUNAV2_FIRST_AGENT_ID)),
        ExportedFile(path="robot/robot_poses.yaml", text=robot_poses_yaml(scene.robot)),
        ExportedFile(path="robot/robot_script.yaml", text=script_yaml(scene)),
        ExportedFile(path="README.md", text=hunav1_readme(scene, behaviors)),
    ]


@register
class Hunav1Target(ExportTarget):
    name = "hunav1"
    summary = "upstream HuNavSim 1.x: built-in behaviors only (refuses custom trees), ids from 1"
    btcpp = "3.8"
    first_agent_id = HUNAV2_FIRST_AGENT_ID

    def build(self, scene: ExportScene, *, base: str, simulator: str) -> list[ExportedFile]:
        return build_hunav1(scene)
