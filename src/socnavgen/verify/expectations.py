"""Tree-level expectations: the interaction nodes of each behavior tree (and a scenario card's
`executes` criteria) must really run, after the conditions that gate them."""

from __future__ import annotations

from collections.abc import Iterable

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.bt.tree import BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.run.models import PathPlan
from socnavgen.verify.models import Expectation

# Actions that make a human interact with the robot (or another human): the tree's reason to exist.
INTERACTION_ACTIONS = ("GiveWaytoRobot", "BlockRobot", "FollowRobot", "LookAtRobot", "RunAwayFromRobot",
                       "FollowHuman", "MakeGesture")
# Conditions whose SUCCESS lets such an action run when they precede it in a Sequence.
GATING_CONDITIONS = ("RobotSays", "HumanSays", "IsRobotBlocking", "IsRobotVisible", "IsRobotNearby", "RobotMoved")
MESSAGE_GATES = ("RobotSays", "HumanSays")  # conditions whose `message` names the gesture they wait for
SEQUENCES = ("Sequence", "ReactiveSequence", "SequenceWithMemory", "SequenceStar")


def _gesture(elem: BTElement) -> int | None:
    try:
        return int(float(elem.attrs.get("message", "0")))
    except ValueError:
        return None  # a blackboard reference such as {msg}: cannot be checked statically


def _ports(elem: BTElement) -> str:
    shown = {k: v for k, v in elem.attrs.items() if k not in ("agent_id", "time_step", "name", "ts")}
    return ", ".join(f"{k}={v}" for k, v in shown.items())


def _is_key_action(elem: BTElement) -> bool:
    if elem.tag not in INTERACTION_ACTIONS:
        return False
    return elem.tag != "MakeGesture" or _gesture(elem) not in (0, None)


def _gates(path: list[BTElement], target: BTElement) -> list[BTElement]:
    """Conditions that must SUCCEED for `target` to run: direct condition children of a Sequence ancestor
    placed before the branch holding the target (an Inverter in between means 'must fail': not counted)."""
    gates: list[BTElement] = []
    chain = [*path, target]
    for depth, ancestor in enumerate(path):
        if ancestor.tag not in SEQUENCES:
            continue
        branch = chain[depth + 1]
        for child in ancestor.children:
            if child is branch:
                break
            if child.tag in GATING_CONDITIONS:
                gates.append(child)
    return gates


def _walk_with_path(elem: BTElement, path: list[BTElement]) -> Iterable[tuple[BTElement, list[BTElement]]]:
    yield elem, path
    for child in elem.children:
        yield from _walk_with_path(child, [*path, elem])


def tree_expectations(human: str, xml: str) -> list[Expectation]:
    """Key nodes of one human's tree: every interaction action, and the conditions gating them."""
    doc = parse_bt(xml, f"behaviors/{human}.xml")
    actions: dict[str, Expectation] = {}
    conditions: dict[str, Expectation] = {}
    for tree in doc.trees.values():
        for elem, path in _walk_with_path(tree, []):
            if not _is_key_action(elem):
                continue
            key = f"{elem.tag}({_ports(elem)})" if elem.tag == "MakeGesture" else elem.tag
            if key not in actions:
                kind = "gives_way_while_passing" if elem.tag == "GiveWaytoRobot" else "executes"
                name = (f"{human} gives way while the robot passes" if kind == "gives_way_while_passing"
                        else f"{human} executes {key}")
                actions[key] = Expectation(
                    kind=kind, name=name, source="tree", human=human, node=elem.tag,
                    message=_gesture(elem) if elem.tag == "MakeGesture" else None,
                    detail=f"{elem.tag} at line {elem.line} of {human}'s tree",
                    caused_by=[(g.tag, _gesture(g) if g.tag in MESSAGE_GATES else None)
                               for g in _gates(path, elem)])
            for gate in _gates(path, elem):
                label = f"{gate.tag}({_ports(gate)})"
                message = _gesture(gate) if gate.tag in MESSAGE_GATES else None
                key = gate.tag if message is None else f"{gate.tag}({message})"
                if key not in conditions:
                    shown = gate.tag if gate.tag != "RobotSays" else f"RobotSays({ROBOT_GESTURES.get(message, message)})"
                    conditions[key] = Expectation(
                        kind="executes", name=f"{human}: {shown} succeeds", source="tree", human=human,
                        node=gate.tag, message=message, detail=f"{label} at line {gate.line} gates {elem.tag}")
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
        kind = "gives_way_while_passing" if node == "GiveWaytoRobot" else "executes"
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
