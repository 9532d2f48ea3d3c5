"""Derive checkable expectations from what the run PROMISES: interaction points in paths.json, the
interaction nodes of each behavior tree, groups, the robot's goal, and (when the run came from a scenario
card) the card's success criteria."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from socnavgen.bt.tree import BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.run.models import PathPlan
from socnavgen.verify.models import Expectation

# Actions that make a human interact with the robot (or another human): the tree's reason to exist.
INTERACTION_ACTIONS = ("GiveWaytoRobot", "BlockRobot", "FollowRobot", "LookAtRobot", "RunAwayFromRobot",
                       "FollowHuman", "MakeGesture")
# Conditions whose SUCCESS lets such an action run when they precede it in a Sequence.
GATING_CONDITIONS = ("RobotSays", "HumanSays", "IsRobotBlocking", "IsRobotVisible", "IsRobotNearby", "RobotMoved")
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
                    detail=f"{elem.tag} at line {elem.line} of {human}'s tree")
            for gate in _gates(path, elem):
                label = f"{gate.tag}({_ports(gate)})"
                if gate.tag not in conditions:
                    conditions[gate.tag] = Expectation(
                        kind="executes", name=f"{human}: {gate.tag} succeeds", source="tree", human=human,
                        node=gate.tag, detail=f"{label} at line {gate.line} gates {elem.tag}")
    return [*actions.values(), *conditions.values()]


def path_expectations(plan: PathPlan, location: Any) -> list[Expectation]:
    """Meetings at interaction points, groups staying together, the robot reaching its goal."""
    out: list[Expectation] = []
    for human in plan.humans:
        if not human.interaction_point:
            continue
        try:
            point = location.node_world(human.interaction_point) if location is not None else None
        except KeyError:
            point = None
        out.append(Expectation(kind="meets_human", name=f"robot meets {human.name} at {human.interaction_point}",
                               source="paths", human=human.name, point=point, point_id=human.interaction_point,
                               detail=f"interaction point {human.interaction_point} in paths.json"))
    groups: dict[int, list[str]] = {}
    for human in plan.humans:
        if human.group_id != -1:
            groups.setdefault(human.group_id, []).append(human.name)
    for gid, members in sorted(groups.items()):
        if len(members) > 1:
            out.append(Expectation(kind="group_together", name=f"group {gid} stays together", source="paths",
                                   detail=", ".join(members), human=",".join(members)))
    if plan.humans:
        out.append(Expectation(kind="no_collision", name="robot never collides with a human", source="paths",
                               detail="a scenario is not its intended interaction if the robot runs into someone"))
    if plan.robot:
        out.append(Expectation(kind="robot_reaches_goal", name=f"robot reaches its goal {plan.robot[-1]}",
                               source="paths", point_id=plan.robot[-1],
                               point=location.node_world(plan.robot[-1]) if location is not None else None))
    return out


def card_expectations(criteria: list[dict], plan: PathPlan, location: Any) -> list[Expectation]:
    """Scenario-card success criteria ({kind: meets_human, within: 2.0}, {kind: executes, node: X}, ...)."""
    out: list[Expectation] = []
    for crit in criteria:
        if not isinstance(crit, dict):
            continue
        kind = str(crit.get("kind", ""))
        human = crit.get("human")
        within = crit.get("within")
        within = float(within) if isinstance(within, int | float) else None
        label = ", ".join(f"{k}={v}" for k, v in crit.items() if k != "kind")
        if kind == "meets_human":
            targets = [human] if human else [h.name for h in plan.humans if h.interaction_point] or [None]
            for name in targets:
                plan_h = next((h for h in plan.humans if h.name == name), None)
                point_id = plan_h.interaction_point if plan_h else None
                point = location.node_world(point_id) if (point_id and location is not None) else None
                who = name or "a human"
                out.append(Expectation(kind="meets_human", name=f"card: robot meets {who}", source="card",
                                       human=name, within=within, point=point, point_id=point_id, detail=label))
        elif kind in ("executes", "gives_way_while_passing") and crit.get("node"):
            node = str(crit["node"])
            kind = "gives_way_while_passing" if node == "GiveWaytoRobot" else "executes"
            out.append(Expectation(kind=kind, name=f"card: {human or 'a human'} executes {node}", source="card",
                                   human=human, node=node, within=within, detail=label))
        elif kind == "group_together":
            groups = sorted({h.group_id for h in plan.humans if h.group_id != -1})
            for gid in groups or [None]:
                members = [h.name for h in plan.humans if gid is not None and h.group_id == gid]
                out.append(Expectation(kind="group_together", name=f"card: group {gid} stays together",
                                       source="card", human=",".join(members) or None, within=within, detail=label))
        elif kind == "robot_reaches_goal" and plan.robot:
            out.append(Expectation(kind="robot_reaches_goal", name="card: robot reaches its goal", source="card",
                                   point_id=plan.robot[-1], within=within, detail=label,
                                   point=location.node_world(plan.robot[-1]) if location is not None else None))
        else:
            out.append(Expectation(kind="executes", name=f"card: unknown criterion {kind!r}", source="card",
                                   node=None, detail=label))
    return out


def derive_expectations(plan: PathPlan, trees: dict[str, str], location: Any,
                        card_criteria: list[dict] | None = None) -> list[Expectation]:
    """Everything the run should show, from paths, trees and the optional card."""
    out = path_expectations(plan, location)
    for human in plan.humans:
        if human.name in trees:
            try:
                out.extend(tree_expectations(human.name, trees[human.name]))
            except ValidationFailed as exc:  # reported as a failing finding, the other checks still run
                out.append(Expectation(kind="executes", name=f"{human.name}'s tree can be read", source="tree",
                                       human=human.name, node=None, detail=exc.render()))
    if card_criteria:
        out.extend(card_expectations(card_criteria, plan, location))
    return out
