"""Tree-level expectations: the interaction nodes of each behavior tree (and a scenario card's
`executes` criteria) must really run, after the conditions that gate them."""

from __future__ import annotations

from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.bt.model import Entry, Node, literal_text
from socnavgen.errors import ValidationFailed
from socnavgen.run.models import PathPlan
from socnavgen.verify.models import Expectation, ExpectationKind

# What makes a node key is in the library table: `interaction` actions are the tree's reason to exist,
# `gate` conditions let them run when they precede them in a sequence-like control; a `message` port
# names the gesture (MakeGesture's 0, "stop gesturing", is no interaction).


def _gesture(node: Node) -> int | None:
    message = node.value("message")
    return message if isinstance(message, int) and not isinstance(message, bool) else None  # {key}: unknown


def _ports(node: Node) -> str:
    spec = node.spec
    shown = {k: v for k, v in node.ports.items()
             if not isinstance(v, Entry) and (p := spec.port(k) if spec else None) is not None and p.reads_root is None}
    return ", ".join(f"{k}={literal_text(v)}" for k, v in shown.items())


def _is_key_action(node: Node) -> bool:
    spec = node.spec
    if spec is None or not spec.interaction:
        return False
    return spec.port("message") is None or _gesture(node) not in (0, None)


def _gates(path: tuple[Node, ...], target: Node) -> list[Node]:
    """Conditions that must SUCCEED for `target` to run: direct gate children of a sequence-like ancestor
    placed before the branch holding the target (an Inverter in between means 'must fail': not counted)."""
    gates: list[Node] = []
    chain = (*path, target)
    for depth, ancestor in enumerate(path):
        if ancestor.spec is None or ancestor.spec.flow != "sequence":
            continue
        branch = chain[depth + 1]
        for child in ancestor.children:
            if child is branch:
                break
            if child.spec is not None and child.spec.gate:
                gates.append(child)
    return gates


def _message_of(gate: Node) -> int | None:
    return _gesture(gate) if gate.spec is not None and gate.spec.port("message") is not None else None


def tree_expectations(human: str, xml: str) -> list[Expectation]:
    """Key nodes of one human's tree as it runs (SubTrees expanded): every interaction action, and the
    conditions gating them. Raises ValidationFailed (every problem named) for a tree bt check refuses."""
    instance = load_instance(xml, f"behaviors/{human}.xml")
    actions: dict[str, Expectation] = {}
    conditions: dict[str, Expectation] = {}
    for node, path in instance.root.walk_with_path():
        if not _is_key_action(node):
            continue
        gesture = _gesture(node) if node.spec is not None and node.spec.port("message") is not None else None
        key = f"{node.name}({_ports(node)})" if gesture is not None else node.name
        if key not in actions:
            kind: ExpectationKind = "gives_way_while_passing" if node.name == "GiveWaytoRobot" else "executes"
            name = (f"{human} gives way while the robot passes" if kind == "gives_way_while_passing"
                    else f"{human} executes {key}")
            actions[key] = Expectation(
                kind=kind, name=name, source="tree", human=human, node=node.name, message=gesture,
                detail=f"{node.name} at line {node.line} of {human}'s tree",
                caused_by=[(g.name, _message_of(g)) for g in _gates(path, node)])
        for gate in _gates(path, node):
            label = f"{gate.name}({_ports(gate)})"
            message = _message_of(gate)
            key = gate.name if message is None else f"{gate.name}({message})"
            if key not in conditions:
                shown = gate.name if gate.name != "RobotSays" else f"RobotSays({ROBOT_GESTURES.get(message, message) if message is not None else None})"
                conditions[key] = Expectation(
                    kind="executes", name=f"{human}: {shown} succeeds", source="tree", human=human,
                    node=gate.name, message=message, detail=f"{label} at line {gate.line} gates {node.name}")
    return [*actions.values(), *conditions.values()]


def card_tree_expectations(criteria: list[dict]) -> list[Expectation]:
    """The tree-level success criteria of a scenario card ({kind: executes, node: X}); the others (meets,
    group, goal) become spec criteria in verify/derive.py."""
    out: list[Expectation] = []
    for crit in criteria:
        if not isinstance(crit, dict) or crit.get("kind") not in ("executes", "gives_way_while_passing"):
            continue
        human = crit.get("human")
        label = ", ".join(f"{k}={v}" for k, v in crit.items() if k != "kind")
        node = str(crit.get("node") or "")
        within = crit.get("within")
        kind: ExpectationKind = "gives_way_while_passing" if node == "GiveWaytoRobot" else "executes"
        out.append(Expectation(kind=kind, name=f"card: {human or 'a human'} executes {node or '?'}", source="card",
                               human=human, node=node or None, detail=label,
                               within=float(within) if isinstance(within, int | float) else None))
    return out


def tree_checks(plan: PathPlan, trees: dict[str, str], card_criteria: list[dict] | None = None) -> list[Expectation]:
    """Every tree-level expectation of a run: key nodes of each human's tree, plus the card's."""
    out: list[Expectation] = []
    for human in plan.humans:
        if human.name in trees:
            try:
                out.extend(tree_expectations(human.name, trees[human.name]))
            except ValidationFailed as exc:  # reported as a failing finding, the other checks still run
                out.append(Expectation(kind="executes", name=f"{human.name}'s tree can be read", source="tree",
                                       human=human.name, node=None, detail=exc.render()))
    if card_criteria:
        out.extend(card_tree_expectations(card_criteria))
    return out
