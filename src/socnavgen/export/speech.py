"""What the robot says, for a target that cannot hear it (HuNavSim 2.x has no input for the robot's speech):
each phrase condition of a tree becomes the geometric condition under which the robot's script says that
phrase, as seen from the person - an approximation, listed per node in the export's README and at
`generate --target hunav2`. A refusal remains only where no such condition exists.

    RobotSays(m)   -> the condition of every cue (spec.json) and gesture rule (paths.json) that says m, OR-ed:
                        blocked / rule blocked     the robot within the cue's distance, in view (IsRobotVisible)
                        at_encounter / at_node     the same, for a person whose path goes through the
                                                   encounter's node or that node (else not heard: said elsewhere)
                        human_within (this person, anyone, or the person's group) / rule near_human
                                                   the robot within the distance (IsRobotNearby); said to
                                                   another person: not heard
                        human_farther (the same people)   the robot farther than the distance
                                                   (Inverter(IsRobotNearby)); said to another: not heard
                        rule at_node               the robot within 1 m, in view, for a person passing the node
                        start / after / always     the same time window (TimeExpiredCondition)
                      (each distance condition counts only once it has held HEARD_AFTER s: see there)
                        human_says                 refused: 2.x cannot tell which phrase another person says
                      no cue says m: never (Inverter(AlwaysSuccess))
    RobotSaid(m)   -> the same condition, latched at the root: once it held, the tree runs with RobotSaid
                      true for good (timing.latch)

The phrase is held `hold` seconds after its trigger in the script; the condition holds only while its
geometry does (the difference is the approximation)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.bt.model import Document, Node
from socnavgen.bt.write import node
from socnavgen.export.models import ExportScene, HumanExport
from socnavgen.export.timing import latch
from socnavgen.run.spec import RobotCue

PHRASE_NODES = ("RobotSays", "RobotSaid")
REFUSED = "refused: "  # marks a cue no condition can express (vs one this person does not hear)
AT_NODE_DISTANCE = 1.0  # m: a paths.json `at_node` rule holds with the robot this close to the node
HEARD_AFTER = 0.5  # s: a geometric phrase condition must first have held this long (a person takes a moment to
# hear the robot; the script's own trigger - someone AHEAD within the distance - is stricter than "near, in
# view", so without it a person at a corner would react before the robot speaks)


@dataclass(frozen=True)
class Spoken:
    """A phrase condition rewritten: where, what it became (or why it could not be)."""

    line: int | None
    node: str
    text: str  # the approximation, or the reason of a refusal
    refused: bool = False


def _never() -> Node:
    return node("Inverter", node("AlwaysSuccess"))


def _key(n: Node) -> tuple:
    return (n.name, tuple(sorted((k, str(v)) for k, v in n.ports.items())), tuple(_key(c) for c in n.children))


def _any(conditions: list[Node]) -> Node:
    """The conditions OR-ed (the same condition once)."""
    unique = list({_key(c): c for c in conditions}.values())
    if not unique:
        return _never()
    return unique[0] if len(unique) == 1 else node("Fallback", *unique)


def _heard(condition: Node) -> Node:
    """`condition`, once it has held HEARD_AFTER seconds (counted while it holds; from then on at once)."""
    return node("Sequence", condition, node("TimeExpiredCondition", seconds=HEARD_AFTER, ts="{dt}", only_once=True))


def _visible(distance: float) -> Node:
    return _heard(node("IsRobotVisible", agent_id="{id}", distance=distance))


def _near(distance: float) -> Node:
    return _heard(node("IsRobotNearby", agent_id="{id}", distance=distance))


def _far(distance: float) -> Node:
    return _heard(node("Inverter", node("IsRobotNearby", agent_id="{id}", distance=distance)))


def _window(start: float, hold: float, latched: bool) -> Node:
    """True from `start` s for `hold` s (latched: from `start` on) - time the node is ticked."""
    begun = node("TimeExpiredCondition", seconds=start, ts="{dt}", only_once=True) if start > 0 else None
    if latched:
        return begun or node("AlwaysSuccess")
    over = node("Inverter", node("TimeExpiredCondition", seconds=hold, ts="{dt}", only_once=True))
    return node("Sequence", begun, over) if begun is not None else over


class _Speech:
    """The script's conditions for one person."""

    def __init__(self, human: HumanExport, scene: ExportScene) -> None:
        self.human, self.scene = human, scene
        self.group = {h.name for h in scene.humans if h.group_id != -1 and h.group_id == human.group_id}

    def cue(self, cue: RobotCue, latched: bool) -> tuple[Node | None, str]:
        """(condition, what it approximates); (None, why) for a phrase this person does not hear (said to
        someone else, elsewhere); REFUSED in `why` when no condition can say when it is said."""
        trig = cue.trigger
        if trig.when in ("start", "after"):
            start = trig.seconds if trig.when == "after" else 0.0
            return _window(start, cue.hold, latched), f"{trig.when} {start:g} s, held {cue.hold:g} s: the same time window"
        if trig.when == "blocked":
            return _visible(trig.distance), f"blocked within {trig.distance:g} m: the robot within {trig.distance:g} m, in view"
        if trig.when in ("at_encounter", "at_node"):
            enc = self.scene.spec.encounter(trig.encounter or "") if self.scene.spec else None
            node = trig.node if trig.when == "at_node" else enc.node if enc is not None else None
            where = f"node {node}" if trig.when == "at_node" else f"encounter {trig.encounter} ({node or '?'})"
            if node is None or node not in self.human.path:
                return None, f"not heard when said at {where}, which {self.human.name}'s path does not pass"
            return _visible(trig.distance), (f"at {where} within {trig.distance:g} m: the robot within "
                                             f"{trig.distance:g} m of {self.human.name}, in view")
        if trig.when == "human_within":
            if trig.human in (None, self.human.name) or trig.human in self.group:
                who = "anyone" if trig.human is None else trig.human
                return _near(trig.distance), f"{who} within {trig.distance:g} m: the robot within {trig.distance:g} m"
            return None, f"not heard when said to {trig.human} (not {self.human.name} or its group)"
        if trig.when == "human_farther":
            if trig.human in (None, self.human.name) or trig.human in self.group:
                who = "anyone" if trig.human is None else trig.human
                return _far(trig.distance), (f"{who} farther than {trig.distance:g} m: the robot farther than "
                                             f"{trig.distance:g} m from {self.human.name}")
            return None, f"not heard when said to {trig.human} (not {self.human.name} or its group)"
        return None, f"{REFUSED}it is said when {trig.human or 'someone'} says {trig.phrase}: HuNavSim 2.x cannot " \
                     "tell which phrase a person says"

    def rule(self, rule, latched: bool) -> tuple[Node | None, str]:  # noqa: ANN001 - run.models.RobotGestureRule
        if rule.when == "always":
            return node("AlwaysSuccess"), "always"
        if rule.when == "blocked":
            return _visible(rule.distance), f"rule blocked within {rule.distance:g} m: the robot within " \
                                            f"{rule.distance:g} m, in view"
        if rule.when == "near_human":
            return _near(rule.distance), f"rule near_human {rule.distance:g} m: the robot within {rule.distance:g} m"
        if rule.node in self.human.path:
            return _visible(AT_NODE_DISTANCE), f"rule at_node {rule.node}: the robot within {AT_NODE_DISTANCE:g} m, in view"
        return None, f"not heard when said at node {rule.node}, which {self.human.name}'s path does not pass"

    def condition(self, message: int, latched: bool) -> tuple[Node | None, str]:
        """The condition under which this person hears the robot say `message`, or (None, why none can say it).
        A phrase said to someone else or at a place the person does not pass is not heard (the robot speaks
        to those near it); only a phrase said when a person speaks cannot be told at all."""
        phrase = ROBOT_GESTURES.get(message, str(message))
        found: list[tuple[Node | None, str]] = []
        if self.scene.spec is not None:
            found += [self.cue(c, latched) for c in self.scene.spec.script.cues if c.say == phrase]
        found += [self.rule(r, latched) for r in self.scene.plan.robot_gestures if r.gesture == message]
        refused = [why.removeprefix(REFUSED) for cond, why in found if cond is None and why.startswith(REFUSED)]
        if refused:
            return None, f"the robot says {phrase} ({message}) but " + "; ".join(refused)
        heard = [(c, why) for c, why in found if c is not None]
        what = "; ".join(why for _, why in found)
        if not heard:
            return _never(), f"{phrase} ({message}): never" + (f" ({what})" if what else ": the script never says it")
        return _any([c for c, _ in heard]), f"{phrase} ({message}) is heard on {what}"


def _message(n: Node) -> int:
    """The literal gesture code of a RobotSays/RobotSaid node (a checked tree holds a number there)."""
    value = n.ports.get("message", 0)
    if not isinstance(value, int | float | str):
        raise TypeError(f"{n.name} at line {n.line}: message is not a literal")
    return int(value)


def rebuild(root: Node, swap: Callable[[Node], Node | None], keep: set[Node]) -> Node:
    """`root` with every node `swap` replaces (it returns None to keep one), rebuilt bottom-up; a rebuilt
    control that was in `keep` stays in it."""
    new = swap(root)
    if new is not None:
        return new
    if not root.children:
        return root
    out = replace(root, children=tuple(rebuild(c, swap, keep) for c in root.children))
    if root in keep:
        keep.add(out)
    return out


def rewrite_phrases(doc: Document, human: HumanExport, scene: ExportScene,
                    keep: set[Node]) -> tuple[dict[str, Node], list[Spoken]]:
    """The document's trees with every phrase condition made geometric (RobotSaid latched at the main tree's
    root), and what each became (refused ones marked)."""
    speech = _Speech(human, scene)
    notes: list[Spoken] = []
    roots = {tid: t.root for tid, t in doc.trees.items() if t.root is not None}

    def says(n: Node) -> Node | None:
        if n.name != "RobotSays":
            return None
        cond, why = speech.condition(_message(n), latched=False)
        notes.append(Spoken(n.line, n.name, why, refused=cond is None))
        return cond

    roots = {tid: rebuild(r, says, keep) for tid, r in roots.items()}
    for tid, root in roots.items():
        for n in root.walk():
            if n.name == "RobotSaid" and tid != doc.main_tree:
                notes.append(Spoken(n.line, n.name, "RobotSaid inside a SubTree cannot be latched", refused=True))
    main = roots.get(doc.main_tree or "")
    said = sorted({_message(n) for n in main.walk() if n.name == "RobotSaid"}) if main else []
    for message in said:
        assert main is not None  # said is empty without a main tree
        cond, why = speech.condition(message, latched=True)
        lines = [n.line for n in main.walk() if n.name == "RobotSaid" and n.ports.get("message") == message]
        notes.append(Spoken(lines[0], "RobotSaid", why + " (latched)", refused=cond is None))
        if cond is None:
            continue

        def heard(n: Node, m: int = message, value: bool = True) -> Node | None:
            if n.name == "RobotSaid" and n.ports.get("message") == m:
                return node("AlwaysSuccess") if value else _never()
            return None

        after = rebuild(main, heard, keep)
        def unheard(n: Node, m: int = message) -> Node | None:
            return heard(n, m, False)

        before = rebuild(main, unheard, keep)
        main = latch(cond, after, before, keep, f"socnavgen_said_{message}")
    if main is not None:
        roots[doc.main_tree or ""] = main
    return roots, notes


__all__ = ["PHRASE_NODES", "Spoken", "rebuild", "rewrite_phrases"]
