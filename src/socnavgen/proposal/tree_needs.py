"""Stage 3 against the spec: a human's tree must contain what each of its encounter parts needs, the
conditions that DETECT the trigger gating the actions that REALIZE the reaction (bt.library's
TRIGGER_NODES / REACTION_NODES / PART_PORTS say which). E.g. trigger robot_says EXCUSE ME with reaction
give_way needs RobotSays(message=4) before GiveWaytoRobot in a Sequence (or, inverted, in an earlier
branch of a Fallback).

The rest of a part is checked the same way, each as a gate of the action:
- a negated trigger (run/spec.py NEGATED_TRIGGERS: robot_far) is its base trigger's condition inverted;
- the trigger time carries its `seconds` on TimeExpiredCondition;
- a reaction that `lasts` (wait_then_go too) is gated by an inverted TimeExpiredCondition of that many
  seconds (the action runs for the first `lasts` seconds);
- a latched part keeps its action for good: the action inside KeepRunningUntilFailure after its
  condition (facts.LATCH_NODE); latched with `lasts`, the timer gates the action INSIDE the latch (a timer
  before it is never ticked again once the latch runs). A robot phrase may also be latched by RobotSaid or by the tree's own
  memory (recorded trees hold "heard FOLLOW ME, or already left the room"): not checked;
- a `say` part that ends (it lasts, or holds while its trigger does) clears its phrase: the tree has a
  MakeGesture of message 0 (a gesture stays shown until another MakeGesture replaces it);
- a person whose `otherwise` is stand has a stop action that no trigger gates (what they do meanwhile);
- of two parts of one person, the later encounter's takes over: its branch comes first in the Fallback
  that chooses between them.
The prompt (`needs_text`) says the same in words.
"""

from __future__ import annotations

from collections.abc import Iterator
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
from socnavgen.proposal.facts import follower_turn_text
from socnavgen.proposal.target_facts import LATCH_NODE, detecting_nodes, latches_by_running, latching_node
from socnavgen.run.spec import NEGATED_TRIGGERS, Encounter, HumanPart, ScenarioSpec

TIMER = "TimeExpiredCondition"
GESTURE = "MakeGesture"
CLEAR_GESTURE = f"<{GESTURE} agent_id='{{id}}' message='0'/>"
Placed = tuple[Node, tuple[Node, ...]]  # a node and its ancestors from the top


def _code(table: dict[int, str], phrase: str | None) -> str | None:
    return next((str(k) for k, v in table.items() if v == phrase), None)


def _agent_id(name: str | None) -> str | None:
    return str(int(name[5:]) - 1) if name else None


@dataclass(frozen=True)
class Need:
    """Nodes (any of), the port values they must carry (`numbers`: numeric ports), and whether the tree
    must check the condition inverted (`negated`: the reaction runs while it FAILS)."""

    nodes: tuple[str, ...]
    ports: tuple[tuple[str, str], ...]
    negated: bool = False
    numbers: tuple[tuple[str, float], ...] = ()

    def describe(self) -> str:
        ports = ", ".join([f"{k}='{v}'" for k, v in self.ports] + [f"{k}='{v:g}'" for k, v in self.numbers])
        names = " or ".join(f"{n}({ports})" if ports else n for n in self.nodes)
        return f"an inverted {names}" if self.negated else names


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
    nodes, negated = detecting_nodes(part.trigger, target)
    if not nodes:
        return None
    numbers = (("seconds", part.seconds),) if part.trigger == "time" and part.seconds is not None else ()
    return Need(tuple(nodes), _ports("trigger", part.trigger, part), negated, numbers)


def reaction_need(part: HumanPart, target: Target = "socrates") -> Need | None:
    nodes = nodes_for_reaction(part.reaction, target)
    return Need(tuple(nodes), _ports("reaction", part.reaction, part)) if nodes else None


def lasting_need(part: HumanPart, target: Target = "socrates") -> Need | None:
    """The timer that ends a reaction after `lasts` seconds (None when it lasts while its trigger holds)."""
    seconds = part.lasting()
    if seconds is None or TIMER not in nodes_for_trigger("time", target):
        return None
    return Need((TIMER,), (), negated=True, numbers=(("seconds", seconds),))


def until_need(part: HumanPart, target: Target = "socrates") -> Need | None:
    """The remembered phrase that ends a reaction for good (`until`): the latching condition of robot_says,
    inverted (the action runs while the robot has not said it yet)."""
    node = latching_node("robot_says", target) if part.until else None
    code = _code(ROBOT_GESTURES, part.until)
    return Need((node,), (("message", code),), negated=True) if node and code is not None else None


def until_xml(part: HumanPart) -> str:
    return f"<Inverter><RobotSaid agent_id='{{id}}' message='{_code(ROBOT_GESTURES, part.until)}'/></Inverter>"


# ---- the prompt ------------------------------------------------------------------------------------
def needs_text(name: str, spec: ScenarioSpec | None, target: Target = "socrates") -> str:
    """What the prompt tells the model this human's tree must contain."""
    if spec is None:
        return ""
    parts = spec.parts_of(name)
    lines = []
    for enc, part in parts:
        where = f"node {enc.node} ({enc.place})" if enc.node else f"a {enc.place}"
        trigger, reaction = trigger_need(part, target), reaction_need(part, target)
        if trigger is None:
            need = f"use {reaction.describe()}" if reaction else "walk normally"
        else:
            need = (f"detect it with {trigger.describe()} and, gated by that condition, "
                    f"{'use ' + reaction.describe() if reaction else 'react'}")
        timer = lasting_need(part, target)
        if timer is not None and part.latch and _latch_by_node(part, target):
            need += (f"; once triggered it lasts {part.lasting():g} s whatever the trigger does (latch with lasts), "
                     f"then they walk on for good: "
                     f"{_timed_latch_words(part, spec.person(name).otherwise == 'stand')}")
        else:
            if timer is not None:
                need += (f"; it lasts {part.lasting():g} s: {_timer_xml(part)} before the action in its Sequence")
            if part.latch:
                need += "; once triggered it lasts for good (latch): " + _latch_words(part, target)
        if until_need(part, target) is not None:
            inside = f" INSIDE <{LATCH_NODE}>, right before the action (outside it is never checked again)" \
                if part.latch and _latch_by_node(part, target) else " before the action in its Sequence"
            need += (f"; it ends for good once the robot has said {part.until}: {until_xml(part)}{inside}, then "
                     f"they walk on")
        if _gesture_ends(part, target):
            need += (f"; MakeGesture keeps showing {part.says} until another MakeGesture, so when the reaction ends "
                     f"({'its ' + format(part.lasting(), 'g') + ' s are over' if part.lasting() else 'its trigger no longer holds'}) "
                     f"clear it: begin the branch that walks on with {CLEAR_GESTURE}")
        if part.trigger in NEGATED_TRIGGERS:  # a tree's condition is ticked from the first step
            need += (f"; {part.trigger.replace('_', ' ')} holds from t = 0 while the robot starts farther away, so "
                     f"this reaction runs from the start")
        lines.append(f"- Encounter {enc.id} (order {enc.order}) at {where}: {_part_words(part)}. Your tree must "
                     f"{need}.")
    if not lines:
        return ""
    if len(parts) > 1:
        lines.append(f"- {name} switches reactions: a later encounter's part takes over from an earlier one when its "
                     f"trigger holds, so check the later encounters' conditions first (their branches come first "
                     f"in the Fallback); when the later trigger stops holding the earlier branch runs again if its condition "
                     f"holds, unless the later part is latched. A latched part (<{LATCH_NODE}>) is not left while it runs: the Sequence and the "
                     f"Fallback above it resume at the RUNNING child without checking the branches before it again. So when "
                     f"an earlier encounter's part is latched, put the later encounter's branch INSIDE the latch: "
                     f"<{LATCH_NODE}><Fallback><Sequence>(later trigger)(later action)</Sequence>(earlier action)"
                     f"</Fallback></{LATCH_NODE}>.")
    lines += person_lines(name, spec)
    if any(part.reaction == "follow" for _, part in parts):
        lines.append(follower_turn_text())
    return "\n".join(["What the scenario's spec requires of this human's tree:", *lines, script_text(spec)])


def _gesture_ends(part: HumanPart, target: Target) -> bool:
    """A `say` part that ends (it lasts, or holds only while its trigger does) with a gesture that stays shown
    until another MakeGesture replaces it (bt.library: MakeGesture)."""
    ends = part.lasting() is not None or (part.trigger != "always" and not part.latch)
    return part.reaction == "say" and ends and GESTURE in nodes_for_reaction("say", target)


def _timer_xml(part: HumanPart) -> str:
    return f"<Inverter><{TIMER} seconds='{part.lasting():g}' ts='{{dt}}' only_once='true'/></Inverter>"


def _latch_by_node(part: HumanPart, target: Target) -> bool:
    """The latch of this part is LATCH_NODE (no condition of the trigger stays SUCCESS by itself)."""
    return latching_node(part.trigger, target) is None


def _timed_latch_words(part: HumanPart, stand: bool = False) -> str:
    """How to write a latched part that lasts; `stand`: the person's otherwise is stand, so walking on goes inside
    the latch too (the tree's last branch stands)."""
    if stand:
        return (f"inside <{LATCH_NODE}> right after the condition, a Fallback of the timed action and the walk: "
                f"<{LATCH_NODE}><Fallback><Sequence>{_timer_xml(part)}(the action)</Sequence>(the walking Sequence "
                f"with RegularNavTree)</Fallback></{LATCH_NODE}> (when the timer expires they walk on inside the "
                f"latch; the tree's last branch, standing, is only for before the trigger)")
    return (f"put a Sequence of the timer and the action inside <{LATCH_NODE}> right after the condition: "
            f"<{LATCH_NODE}><Sequence>{_timer_xml(part)}(the action)</Sequence></{LATCH_NODE}> (when the timer "
            f"expires the latch fails, and the expired timer keeps the reaction from starting again)")


def _latch_words(part: HumanPart, target: Target) -> str:
    said = latching_node(part.trigger, target)
    keep = f"put the action inside <{LATCH_NODE}> right after the condition in the Sequence"
    if said and latches_by_running(target):
        return f"gate it with {said} (SUCCESS for good once said), or {keep}"
    return f"gate it with {said}" if said else keep


def person_lines(name: str, spec: ScenarioSpec) -> list[str]:
    person = spec.person(name)
    lines = []
    if person.otherwise == "stand":
        lines.append(f"- While none of its triggers holds, {name} stands still (\"otherwise\": \"stand\"): the last "
                     f"branch of the tree is <MakeGesture agent_id='{{id}}' message='0'/> (or LookAtRobot), not "
                     f"walking.")
    if person.speed is not None:
        lines.append(f"- {name} walks at up to {person.speed:g} m/s (the simulator sets it; nothing to do in the "
                     f"tree).")
    return lines


def script_text(spec: ScenarioSpec) -> str:
    """The robot's script in words: when the robot speaks or waits (what a human's tree can react to)."""
    cues = []
    for cue in spec.script.cues:
        t = cue.trigger
        when = {"start": "at the start", "at_encounter": f"within {t.distance:g} m of encounter {t.encounter}",
                "at_node": f"within {t.distance:g} m of node {t.node} of its route",
                "blocked": f"when someone is in its way within {t.distance:g} m",
                "human_within": f"when {t.human or 'anyone'} is within {t.distance:g} m",
                "human_farther": f"when {t.human or 'anyone'} is farther than {t.distance:g} m",
                "human_says": f"when {t.human or 'someone'} says {t.phrase}",
                "after": f"{t.seconds:g} s after the start"}[t.when]
        acts = []
        if cue.say:
            acts.append(f"says {cue.say} (held {cue.hold:g} s)")
        if cue.wait and cue.wait_until_clear:
            acts.append(f"stands still {cue.wait:g} s and then until its way is clear")
        elif cue.wait_until_clear:
            acts.append("stands still until its way is clear")
        elif cue.wait and not cue.let_pass:
            acts.append(f"stands still {cue.wait:g} s")
        if cue.let_pass:
            acts.append(f"stands still beside {cue.let_pass}'s way (not in front of them) until {cue.let_pass} has gone by"
                        + (f" (at most {cue.wait:g} s)" if cue.wait else ""))
        if cue.speed is not None:
            acts.append(f"goes on at {cue.speed:g} m/s")
        again = "" if cue.once else " (each time it becomes true again)"
        cues.append(f"{when}{again} it {' and '.join(acts) or 'does nothing special'}")
    script = "; ".join(cues) if cues else "it says nothing and does not stop on purpose"
    return f"The robot drives at {spec.script.speed:g} m/s; {script}."


def _part_words(part: HumanPart) -> str:
    trig = part.trigger.replace("_", " ")
    if part.phrase:
        trig += f" {part.phrase}"
    if part.other and part.trigger == "human_says":
        trig = f"{part.other} says {part.phrase}"
    if part.distance:
        trig += f" ({'farther than' if part.trigger in NEGATED_TRIGGERS else 'within'} {part.distance:g} m)"
    if part.trigger == "time" and part.seconds is not None:
        trig = f"{part.seconds:g} s after the start"
    reaction = part.reaction.replace("_", " ") + (f" {part.says}" if part.says else "") + \
        (f" {part.other}" if part.reaction == "follow_human" and part.other else "")
    if part.lasting() is not None:
        reaction += f" for {part.lasting():g} s, then walk on"
    if part.until:
        reaction += f" until the robot has said {part.until}, then walk on"
    return f"when {trig} -> {reaction}" if part.trigger != "always" else reaction


# ---- reading a tree ---------------------------------------------------------------------------------
def _matches(node: Node, need: Need) -> bool:
    if node.name not in need.nodes:
        return False
    if not all((value := node.value(k)) is not None and literal_text(value) == v for k, v in need.ports):
        return False
    return all(isinstance(value := node.value(k), int | float) and abs(float(value) - v) < 1e-6
               for k, v in need.numbers)


def _contains(node: Node, need: Need, *, inverted: bool) -> bool:
    """`node`'s subtree holds the condition, negated an odd number of times when `inverted` (for a negated
    need: an even number)."""
    def visit(n: Node, flips: int) -> bool:
        if _matches(n, need):
            return (flips % 2 == 1) == (inverted != need.negated)
        step = 1 if n.spec is not None and n.spec.rule == "invert" else 0
        return any(visit(c, flips + step) for c in n.children)
    return visit(node, 0)


def _steps(action: Node, path: tuple[Node, ...]) -> Iterator[tuple[Node, Node]]:
    """(parent, the child on the way down to `action`), from the action up to the top."""
    return zip(reversed(path), (action, *reversed(path[1:])), strict=True)


def _index(parent: Node, child: Node) -> int:
    return next(k for k, c in enumerate(parent.children) if c is child)


def _gated(action: Node, path: tuple[Node, ...], need: Need) -> bool:
    """An earlier sibling of the action (or of an ancestor) lets it run only when the condition holds: the
    condition in a sequence-like control, or the negated condition in a fallback-like one."""
    for parent, child in _steps(action, path):
        flow = parent.spec.flow if parent.spec is not None else None
        earlier = parent.children[:_index(parent, child)]
        if flow is not None and any(_contains(c, need, inverted=flow == "fallback") for c in earlier):
            return True
    return False


def _latched(action: Node, path: tuple[Node, ...], trigger: Need) -> bool:
    """The action sits inside LATCH_NODE, below the Sequence step that checks the trigger."""
    for parent, child in _steps(action, path):
        if parent.name == LATCH_NODE:
            return True
        flow = parent.spec.flow if parent.spec is not None else None
        if flow is not None and any(_contains(c, trigger, inverted=flow == "fallback")
                                    for c in parent.children[:_index(parent, child)]):
            return False  # reached the gate without passing the latch
    return False


def _timed_inside_latch(action: Node, path: tuple[Node, ...], timer: Need) -> bool:
    """The timer gates the action below LATCH_NODE (the latch re-checks it on every tick, so it ends)."""
    timed = False
    for parent, child in _steps(action, path):
        if parent.name == LATCH_NODE:
            return timed
        flow = parent.spec.flow if parent.spec is not None else None
        if flow is not None and any(_contains(c, timer, inverted=flow == "fallback")
                                    for c in parent.children[:_index(parent, child)]):
            timed = True
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
    parts = spec.parts_of(name)
    mistakes: list[str] = []
    for enc, part in parts:
        mistakes += _part_mistakes(nodes, enc, part, target)
    if not mistakes:
        mistakes += _order_mistakes(nodes, parts, target) + _stand_mistakes(nodes, name, spec, target)
    return mistakes


def _part_mistakes(nodes: list[Placed], enc: Encounter, part: HumanPart, target: Target) -> list[str]:
    trigger, reaction = trigger_need(part, target), reaction_need(part, target)
    what = f"encounter {enc.id} ({_part_words(part)})"
    if reaction is None:
        return []
    actions = [(n, path) for n, path in nodes if _matches(n, reaction)]
    if not actions:
        return [f"{what}: the tree has no {reaction.describe()} to realize the reaction {part.reaction}"]
    if trigger is not None:
        if not any(_matches(n, trigger) for n, _ in nodes):
            return [f"{what}: the tree never checks {trigger.describe()}, so the trigger {part.trigger} cannot fire"]
        actions = [(a, path) for a, path in actions if _gated(a, path, trigger)]
        if not actions:
            return [f"{what}: {reaction.describe()} is not gated by {trigger.describe()}; put the condition before "
                    f"the action in a Sequence (or inverted in an earlier branch of a Fallback)"]
    timer, until = lasting_need(part, target), until_need(part, target)
    ends = []  # what ends the reaction: a gate before it, inside the latch if the reaction is latched
    if timer is not None:
        ends.append((timer, f"lasts {part.lasting():g} s", _timer_xml(part),
                     f"a timer outside the latch is never checked again once the latch runs: {_timed_latch_words(part)}"))
    if until is not None:
        ends.append((until, f"ends once the robot said {part.until}", until_xml(part),
                     f"a check outside the latch is never made again once the latch runs: put {until_xml(part)} "
                     f"INSIDE <{LATCH_NODE}>, right before the action"))
    for need, how, xml, inside in ends:
        if not any(_gated(a, path, need) for a, path in actions):
            return [f"{what}: the reaction {how}; put {xml} before {reaction.describe()} in its Sequence"]
        if part.latch and trigger is not None and _latch_by_node(part, target) \
                and not any(_timed_inside_latch(a, path, need) for a, path in actions):
            return [f"{what}: the reaction is latched and {how}; {inside}"]
    if _gesture_ends(part, target) and not any(n.name == GESTURE and (v := n.value("message")) is not None
                                               and literal_text(v) == "0"
                                               for n, _ in nodes):
        return [f"{what}: MakeGesture keeps showing {part.says} until another MakeGesture, and this reaction ends; "
                f"clear the phrase when it does: begin the branch that walks on with {CLEAR_GESTURE}"]
    if part.latch and trigger is not None and latching_node(part.trigger, target) is None \
            and not any(_latched(a, path, trigger) for a, path in actions):
        return [f"{what}: the reaction is latched (it lasts for good once triggered); {_latch_words(part, target)}"]
    return []


def _gated_actions(nodes: list[Placed], part: HumanPart, target: Target) -> list[Placed]:
    trigger, reaction = trigger_need(part, target), reaction_need(part, target)
    if trigger is None or reaction is None:
        return []
    return [(n, path) for n, path in nodes if _matches(n, reaction) and _gated(n, path, trigger)]


def _order_mistakes(nodes: list[Placed], parts: list[tuple[Encounter, HumanPart]], target: Target) -> list[str]:
    """Of two parts of one person, the later encounter's must take over when its trigger holds: where one
    Fallback chooses between their branches, the later one's comes first."""
    mistakes = []
    for (early_enc, early), (late_enc, late) in zip(parts, parts[1:], strict=False):
        if late_enc.order <= early_enc.order or set(nodes_for_reaction(early.reaction, target)) == \
                set(nodes_for_reaction(late.reaction, target)):
            continue
        firsts, seconds = _gated_actions(nodes, late, target), _gated_actions(nodes, early, target)
        late_trigger = trigger_need(late, target)
        if not firsts or not seconds or late_trigger is None:
            continue
        unless_late = Need(late_trigger.nodes, late_trigger.ports, not late_trigger.negated, late_trigger.numbers)
        if any(_gated(b, path, unless_late) for b, path in seconds):
            continue  # the earlier reaction runs only while the later trigger does not hold
        if not any(_comes_first(a, b) for a in firsts for b in seconds):
            mistakes.append(f"encounter {late_enc.id} comes after {early_enc.id}, so its reaction ({late.reaction}) "
                            f"must take over when its trigger holds: put its branch before the branch of "
                            f"{early_enc.id} ({early.reaction}) in the Fallback")
    return mistakes


def _comes_first(a: Placed, b: Placed) -> bool:
    """`a` is chosen before `b`: in the control node where their ways part, a's branch is earlier (or they
    part in a sequence, which does not choose between them)."""
    way_a, way_b = (*a[1], a[0]), (*b[1], b[0])
    k = 0
    while k < min(len(way_a), len(way_b)) and way_a[k] is way_b[k]:
        k += 1
    if k == 0 or k >= min(len(way_a), len(way_b)):
        return True
    parent = way_a[k - 1]
    if parent.spec is None or parent.spec.flow != "fallback":
        return True
    return _index(parent, way_a[k]) < _index(parent, way_b[k])


def _stand_mistakes(nodes: list[Placed], name: str, spec: ScenarioSpec, target: Target) -> list[str]:
    """A person who stands while no trigger holds has a stop action that no trigger of theirs gates."""
    if spec.person(name).otherwise != "stand":
        return []
    triggers = [need for _, part in spec.parts_of(name) if (need := trigger_need(part, target)) is not None]
    stops = set(nodes_for_reaction("stop", target))
    if any(n.name in stops and not any(_gated(n, path, t) for t in triggers) for n, path in nodes):
        return []
    return [f"{name} stands while none of its triggers holds (\"otherwise\": \"stand\"): end the tree's Fallback with "
            f"a branch that stands, <MakeGesture agent_id='{{id}}' message='0'/> (or LookAtRobot), not walking"]
