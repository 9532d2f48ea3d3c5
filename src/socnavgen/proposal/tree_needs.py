"""Stage 3 against the spec: a human's tree must contain what each of its encounter parts needs, the
conditions that DETECT the trigger gating the actions that REALIZE the reaction (bt.library's
TRIGGER_NODES / REACTION_NODES / PART_PORTS say which). E.g. trigger robot_says EXCUSE ME with reaction
give_way needs RobotSays(message=4) before GiveWaytoRobot in a Sequence (or, inverted, in an earlier
branch of a Fallback)."""

from __future__ import annotations

from dataclasses import dataclass

from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import (
    HUMAN_GESTURES,
    PART_PORTS,
    ROBOT_GESTURES,
    Target,
    nodes_for_reaction,
    nodes_for_trigger,
)
from socnavgen.bt.model import Node, literal_text
from socnavgen.errors import ValidationFailed
from socnavgen.run.spec import Encounter, HumanPart, ScenarioSpec


def _code(table: dict[int, str], phrase: str | None) -> str | None:
    return next((str(k) for k, v in table.items() if v == phrase), None)


def _agent_id(name: str | None) -> str | None:
    return str(int(name[5:]) - 1) if name else None


@dataclass(frozen=True)
class Need:
    """Nodes (any of) and the port values they must carry."""

    nodes: tuple[str, ...]
    ports: tuple[tuple[str, str], ...]

    def describe(self) -> str:
        ports = ", ".join(f"{k}='{v}'" for k, v in self.ports)
        names = " or ".join(f"{n}({ports})" if ports else n for n in self.nodes)
        return names


def _ports(role: str, value: str, part: HumanPart) -> tuple[tuple[str, str], ...]:
    wanted = PART_PORTS.get((role, value), {})
    out = []
    for port, source in wanted.items():
        if source == "robot_phrase":
            code = _code(ROBOT_GESTURES, part.phrase)
        elif source == "human_phrase":
            code = _code(HUMAN_GESTURES, part.says if role == "reaction" else part.phrase)
        else:
            code = _agent_id(part.other)
        if code is not None:
            out.append((port, code))
    return tuple(out)


def trigger_need(part: HumanPart, target: Target = "socrates") -> Need | None:
    nodes = nodes_for_trigger(part.trigger, target)
    return Need(tuple(nodes), _ports("trigger", part.trigger, part)) if nodes else None


def reaction_need(part: HumanPart, target: Target = "socrates") -> Need | None:
    nodes = nodes_for_reaction(part.reaction, target)
    return Need(tuple(nodes), _ports("reaction", part.reaction, part)) if nodes else None


def needs_text(name: str, spec: ScenarioSpec | None, target: Target = "socrates") -> str:
    """What the prompt tells the model this human's tree must contain."""
    if spec is None:
        return ""
    lines = []
    for enc, part in spec.parts_of(name):
        where = f"node {enc.node} ({enc.place})" if enc.node else f"a {enc.place}"
        trigger, reaction = trigger_need(part, target), reaction_need(part, target)
        what = _part_words(part)
        if trigger is None:
            need = f"use {reaction.describe()}" if reaction else "walk normally"
        else:
            need = (f"detect it with {trigger.describe()} and, gated by that condition, "
                    f"{'use ' + reaction.describe() if reaction else 'react'}")
        latch = " Once triggered the reaction lasts (latch)." if part.latch else ""
        lines.append(f"- Encounter {enc.id} at {where}: {what}. Your tree must {need}.{latch}")
    if not lines:
        return ""
    return "\n".join(["What the scenario's spec requires of this human's tree:", *lines, script_text(spec)])


def script_text(spec: ScenarioSpec) -> str:
    """The robot's script in words: when the robot speaks or waits (what a human's tree can react to)."""
    cues = []
    for cue in spec.script.cues:
        t = cue.trigger
        when = {"start": "at the start", "at_encounter": f"within {t.distance:g} m of encounter {t.encounter}",
                "blocked": f"when someone stands in its way within {t.distance:g} m",
                "human_within": f"when {t.human or 'anyone'} is within {t.distance:g} m",
                "human_farther": f"when {t.human or 'anyone'} is farther than {t.distance:g} m",
                "human_says": f"when {t.human or 'someone'} says {t.phrase}",
                "after": f"{t.seconds:g} s after the start"}[t.when]
        acts = []
        if cue.say:
            acts.append(f"says {cue.say} (held {cue.hold:g} s)")
        if cue.wait_until_clear:
            acts.append("waits until its way is clear")
        elif cue.wait:
            acts.append(f"waits {cue.wait:g} s")
        if cue.speed is not None:
            acts.append(f"goes on at {cue.speed:g} m/s")
        cues.append(f"{when} it {' and '.join(acts) or 'does nothing special'}")
    script = "; ".join(cues) if cues else "it says nothing and does not stop on purpose"
    return f"The robot drives at {spec.script.speed:g} m/s; {script}."


def _part_words(part: HumanPart) -> str:
    trig = part.trigger.replace("_", " ")
    if part.phrase:
        trig += f" {part.phrase}"
    if part.other and part.trigger == "human_says":
        trig = f"{part.other} says {part.phrase}"
    if part.distance:
        trig += f" (within {part.distance:g} m)"
    reaction = part.reaction.replace("_", " ") + (f" {part.says}" if part.says else "") + \
        (f" {part.other}" if part.reaction == "follow_human" and part.other else "")
    return f"when {trig} -> {reaction}" if part.trigger != "always" else reaction


# ---- reading a tree ---------------------------------------------------------------------------------
def _matches(node: Node, need: Need) -> bool:
    return node.name in need.nodes and all((value := node.value(k)) is not None and literal_text(value) == v
                                           for k, v in need.ports)


def _contains(node: Node, need: Need, *, inverted: bool) -> bool:
    """`node`'s subtree holds the condition, negated an odd number of times when `inverted`."""
    def visit(n: Node, flips: int) -> bool:
        if _matches(n, need):
            return (flips % 2 == 1) == inverted
        step = 1 if n.spec is not None and n.spec.rule == "invert" else 0
        return any(visit(c, flips + step) for c in n.children)
    return visit(node, 0)


def _gated(action: Node, path: tuple[Node, ...], need: Need) -> bool:
    """An earlier sibling of the action (or of an ancestor) lets it run only when the condition holds: the
    condition in a sequence-like control, or the negated condition in a fallback-like one."""
    for parent, child in zip(reversed(path), (action, *reversed(path[1:])), strict=True):
        flow = parent.spec.flow if parent.spec is not None else None
        earlier = parent.children[:next(k for k, c in enumerate(parent.children) if c is child)]
        if flow is not None and any(_contains(c, need, inverted=flow == "fallback") for c in earlier):
            return True
    return False


def tree_need_mistakes(xml: str, name: str, spec: ScenarioSpec | None, target: Target = "socrates") -> list[str]:
    """What the tree of `name` (one `bt check` accepts) lacks for its encounter parts, each mistake naming
    the nodes to add. The tree is read as it runs: SubTree calls expanded, ports typed, controls and
    decorators by their library semantics (flow, rule)."""
    if spec is None:
        return []
    try:
        nodes = list(load_instance(xml, f"behaviors/{name}.xml").root.walk_with_path())
    except ValidationFailed:  # bt check names the tree's problems; its needs are checked once it has none
        return []
    mistakes: list[str] = []
    for enc, part in spec.parts_of(name):
        mistakes += _part_mistakes(nodes, enc, part, target)
    return mistakes


def _part_mistakes(nodes: list[tuple[Node, tuple[Node, ...]]], enc: Encounter, part: HumanPart,
                   target: Target) -> list[str]:
    trigger, reaction = trigger_need(part, target), reaction_need(part, target)
    what = f"encounter {enc.id} ({_part_words(part)})"
    if reaction is None:
        return []
    actions = [(n, path) for n, path in nodes if _matches(n, reaction)]
    if not actions:
        return [f"{what}: the tree has no {reaction.describe()} to realize the reaction {part.reaction}"]
    if trigger is None:
        return []
    if not any(_matches(n, trigger) for n, _ in nodes):
        return [f"{what}: the tree never checks {trigger.describe()}, so the trigger {part.trigger} cannot fire"]
    if not any(_gated(a, path, trigger) for a, path in actions):
        return [f"{what}: {reaction.describe()} is not gated by {trigger.describe()}; put the condition before "
                f"the action in a Sequence (or inverted in an earlier branch of a Fallback)"]
    return []
