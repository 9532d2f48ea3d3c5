"""Target `hunav1`: upstream HuNavSim 1.x, which loads only its built-in trees (behavior 1..6).

A human can be exported only when its tree IS one of those built-in behaviors, compared after
normalising what does not change meaning (names, SetBlackboard copies for the RegularNavTree
subtree, nested Sequences). Anything else is refused, naming the human and the node."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from socnavgen.bt.expand import ROOT_DT, ROOT_ID, load_instance
from socnavgen.bt.library import HUNAV2_FIRST_AGENT_ID, LIBRARY, regular_nav_sequence, regular_walker_xml
from socnavgen.bt.model import Entry, Node, Value
from socnavgen.errors import ValidationFailed
from socnavgen.export.models import ExportedFile, ExportScene, HumanExport
from socnavgen.export.readme import hunav1_readme
from socnavgen.export.robot_script import script_yaml
from socnavgen.export.socrates import check_trees, fork_agents_yaml
from socnavgen.export.targets import ExportTarget, register
from socnavgen.export.writer import robot_poses_yaml


def _reacting(distance: float, seconds: float, only_once: bool, action: str) -> str:
    """A 1.x reactive behavior written as a tree of our library: while the robot is visible and for the
    first `seconds`, `action`; else walk regularly."""
    own = "".join(f' {p.name}="{{{p.reads_root}}}"' for p in LIBRARY[action].ports if p.reads_root)
    return ('<root main_tree_to_execute="B"><include path="BTRegularNav.xml"/><BehaviorTree ID="B"><Fallback>'
            f'<Sequence><IsRobotVisible agent_id="{{id}}" distance="{distance}"/><Inverter><TimeExpiredCondition '
            f'seconds="{seconds}" ts="{{dt}}" only_once="{str(only_once).lower()}"/></Inverter><{action}{own}/>'
            f'</Sequence>{regular_nav_sequence()}</Fallback></BehaviorTree></root>')


# The built-in 1.x behaviors (reference §2.8, §3.7) written with OUR nodes: Regular is the goal-walking
# loop; the others react to a visible robot for a limited time, else walk regularly.
BUILTIN: dict[int, tuple[str, str]] = {
    1: ("REGULAR", regular_walker_xml("B")),
    3: ("SURPRISED", _reacting(4.0, 30.0, True, "LookAtRobot")),
    4: ("SCARED", _reacting(3.0, 40.0, False, "RunAwayFromRobot")),
    5: ("CURIOUS", _reacting(10.0, 30.0, True, "FollowRobot")),
    6: ("THREATENING", _reacting(4.0, 40.0, True, "BlockRobot")),
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


def _value(value: Value) -> object:
    if isinstance(value, Entry):
        return {ROOT_ID: "{id}", ROOT_DT: "{dt}"}.get(value, ("entry", value.scope, value.key))
    return value


def shape(node: Node) -> tuple | None:
    """(name, ports, children) of a tree as it runs, with meaning-free details removed: labels, the
    copies of {id} / {dt} that feed SubTree calls, the ports that always read {id} / {dt}, controls
    nested in the same control or holding one child; ports left out count as their defaults. None for
    nodes that vanish."""
    spec = node.spec
    assert spec is not None
    if node.name == "SetBlackboard" and node.ports.get("value") in (ROOT_ID, ROOT_DT):
        return None
    ports = tuple(sorted((p.name, _value(v)) for p in spec.ports
                         if p.reads_root is None and (v := node.value(p.name)) is not None))
    children: list[tuple] = []
    for child in node.children:
        c = shape(child)
        if c is None:
            continue
        if c[0] == node.name and spec.kind == "control":  # nested same control = one level
            children.extend(c[2])
        else:
            children.append(c)
    if spec.kind == "control" and len(children) == 1:
        return children[0]
    return (node.name, ports, tuple(children))


@cache
def builtin_shapes() -> dict[tuple | None, int]:
    return {shape(load_instance(xml, f"hunav1 {label}").root): code for code, (label, xml) in BUILTIN.items()}


def builtin_behavior(human: HumanExport) -> tuple[int | None, list[Refusal]]:
    """The 1.x behavior code this human's tree (one bt check accepts) is, or the reasons it is none."""
    instance = load_instance(human.tree_xml, human.tree_file)
    refusals = [Refusal(human.name, node.source, node.line, f"node {node.name} does not exist in HuNavSim 1.x")
                for node in instance.root.walk()
                if node.kind in ("action", "condition") and node.spec is not None and node.spec.hunav1 is None]
    if refusals:
        return None, refusals
    code = builtin_shapes().get(shape(instance.root))
    if code is not None:
        return code, []
    names = ", ".join(f"{code} {label}" for code, (label, _) in BUILTIN.items())
    main = instance.document.main
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
