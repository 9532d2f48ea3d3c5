"""Where the robot waits and who stays put (issue 25: specs that say less than their prose). Two runs of the session-11
suite passed the verifier where a person looking at the GIF saw their text not happen, each because no criterion held
the spec to a place the text names:

- warehouse_04's robot was to stop "about 3 m before the mouth of the middle aisle"; its criteria measured the
  robot from the worker only, and it drove up to the aisle mouth; hospital_04's robot was to wait "about 4 m short of
  i1" until the team had gone in; it drove on at once and pulled up 0.5 m behind the last of them;
- home_10's friends were to "stay where they are" while the robot skirts their circle; one walked 1.2 m off into a
  doorway, the robot drove through the broken circle, and no criterion said who stays put.

Like prose_checks and stop_checks, general checks of the words against the criteria, never keyed to a scenario:

- `robot_wait_mistakes` (stage 1): the robot waits / stops / holds N m short of (before, back from, away from) a
  PLACE (not a person: "3 m behind the nurse" is about her) needs an stl criterion that keeps the robot at least
  N - WAIT_SLACK from that place (`robot_to_node_X >= v`; a place the text names by node id is measured from that
  node or an encounter at it, a place in words from any place); "short of PLACE" without a distance needs any such
  lower bound;
- `stay_mistakes` (stage 1): a person the text has stay where they are / stay put / not move (not "until" something:
  that is a wait; nor "if" / "otherwise": a stay on a condition) needs a criterion that fails when they walk off: an stl on `moved_<human>` or an upper bound on
  their distance to a place (`<human>_to_node_X < r`);
- `back_mistakes` (stage 1): a person who comes to the robot (follow, block) and whom the text has go back (walk / go
  / head back to a place, return to it) needs a criterion that sees where they end up: an stl on `moved_<human>` or an upper bound on their distance to a place.
  home_18 (round 22): the physiotherapist was to take the towel "then walk back to the resident on the mat"; he stood
  on the robot's goal to the end and the run verified (no criterion said where he goes after the handover).
"""

from __future__ import annotations

import re

from socnavgen.proposal.prose_checks import (
    PEOPLE_WORDS,
    named_nodes,
    owned_sentences,
    people_names,
    quoted,
    sentences,
)
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.thresholds import MOVED_DISTANCE

WAIT_SLACK = 1.0  # m: "about N m short of the door" still reads true of a robot that holds a metre nearer
_AMOUNT = r"(?:about |some |roughly |around |approximately |at least |~ ?)?(?P<n>\d+(?:\.\d+)?)(?:\s*-\s*\d+(?:\.\d+)?)?" \
          r"\s*(?:m|metres|meters)"
# "N m short of PLACE" / "short of PLACE" (no amount): the place ends at a clause's end or a conjunction.
_SHORT = re.compile(rf"(?:\b{_AMOUNT} (?:short of|before|back from|away from|in front of)|\bshort of) "
                    r"(?P<place>(?:(?!(?:and|while|until|when|as|so|then|but|where|which|who|because)\b)[^,.;:()])+)",
                    re.IGNORECASE)
_WAIT = re.compile(r"\b(?:stops?|stopping|waits?|waiting|holds?|holding|halts?|pauses?|pausing|stands?|standing|"
                   r"parks?|comes? to a (?:halt|stop)|keeps?|keeping|hangs? back|stays?|staying|remains?|"
                   r"(?:pulls?|draws?) up|idles?)\b", re.IGNORECASE)
_ROBOT = re.compile(r"\b(?:the robot|it)\b", re.IGNORECASE)
_GROUP_WORDS = {"group", "team", "cluster", "circle", "pair", "family", "crowd", "couple", "queue", "them", "him", "her",
                "everyone", "others", "robot", "it", "crew", "children", "kids", "people", "friends", "guests",
                "visitors", "workers"}
_SUBJECTS = PEOPLE_WORDS | {"he", "she", "they"}  # a person who may be the one that stops
_WAIT_REACH = 80  # characters: a wait verb this near the amount (same clause) is the robot's wait there
# Staying put: not for good when "until" follows in the clause (a wait), nor of the robot.
_WHERE = r"(?:right )?where (?:he|she|they) (?:is|are|stands?|stood)"
STAY = re.compile(rf"\b(?:stay(?:s|ing)? (?:{_WHERE}|put|in (?:his|her|their) place|in place)|"
                  rf"remain(?:s|ing)? (?:{_WHERE}|in place|in (?:his|her|their) place|put)|"
                  r"(?:holds?|holding|stands?|standing) (?:his|her|their) ground|"
                  r"keeps? (?:his|her|their) (?:place|spot|position)|"
                  r"(?:do|does|did) not (?:move|step away|walk away|move away)|doesn'?t move|don'?t move|"
                  r"never moves?)\b", re.IGNORECASE)
_CLAUSE_END = re.compile(r"[,;:]|\b(?:but|then|while|until|and then|after|before)\b", re.IGNORECASE)
_IF = re.compile(r"\b(?:if|unless|otherwise)\b", re.IGNORECASE)  # a stay on a condition is no stay for good
_UNTIL = re.compile(r"^[^,.;:]*?\b(?:until|till|unless)\b", re.IGNORECASE)
_PERSON = re.compile(r"\b[Hh]uman ?(\d+)\b")


def place_events_text(detail: bool = True) -> str:
    """Stage 1's rule for what these checks (and prose_checks.file_place_mistakes) ask, told with the stl help (after
    facts.events_text; `detail` False: fit.py's signals cut drops it, the checks still name what is missing)."""
    if not detail:
        return ""
    return ("\n- STATE WHERE THE ROBOT WAITS AND WHO STAYS PUT: a robot your text has wait N m short of (before) a place "
            "is held there by an stl \"(robot_to_node_X >= M) until (what ends its wait)\" (X: that place, M at "
            f"least N - {WAIT_SLACK:g}; a distance from a person, or robot_to_node_X < d, lets it drive right up to "
            "X); a person your text has stay where they are (stay put, not move away) by \"always (moved_human1 < "
            "0.5)\"; a person your text puts second, third or last in a file of people by an stl relating them to the "
            "one before, measured at a node inside where they go (\"(human3_to_node_R > 1.0) until (human2_to_node_R "
            "< 0.5)\"), not at a doorway both crowd round; a person your text has come to the robot (follow, block) "
            "and then go back to node N by \"eventually (dist_human1 < 2.0 and human1_to_node_N > 1.0 and eventually "
            "(human1_to_node_N < 0.8))\" (away from N by the robot, then back: an upper bound alone holds at the "
            "start).")


def _a_person(place: str, names: dict[str, str]) -> bool:
    """The words after "short of" name a person or a group of them (or the robot), not a place."""
    words = {w.lower() for w in re.findall(r"[A-Za-z]+", place)}
    return bool(_PERSON.search(place) or words & (PEOPLE_WORDS | _GROUP_WORDS | set(names)))


def _robot_waits(sentence: str, names: dict[str, str], about_robot: bool) -> list[tuple[float | None, str]]:
    """(amount or None, place words) of each place the sentence has the robot wait short of: a wait verb near the
    amount, and the robot the subject (`about_robot`: every sentence of the robot's behavior is; else the robot or
    "it" named after the last person before the verb)."""
    found = []
    for m in _SHORT.finditer(sentence):
        place = m.group("place").strip()
        verb = next((v for v in _WAIT.finditer(sentence) if abs(v.start() - m.start()) <= _WAIT_REACH), None)
        if verb is None or _a_person(place, names):
            continue
        if not about_robot:
            before = sentence[:min(verb.start(), m.start())]
            robot = [r.start() for r in _ROBOT.finditer(before)]
            people = [p.start() for p in _PERSON.finditer(before)] + \
                [w.start() for w in re.finditer(r"\b\w+\b", before)
                 if w.group(0).lower() in names or w.group(0).lower() in _SUBJECTS]
            if not robot or (people and max(people) > max(robot)):
                continue
        found.append((float(m.group("n")) if m.group("n") else None, place))
    return found


_LOWER = re.compile(r"\brobot_to_(?P<a>\w+)\s*>=?\s*(?P<v>\d+(?:\.\d+)?)|(?P<w>\d+(?:\.\d+)?)\s*<=?\s*robot_to_(?P<b>\w+)")


def _bounds(c: Criterion) -> list[tuple[str, float]]:
    """(place, metres) of each lower bound an stl criterion puts on the robot's distance to a place."""
    if c.kind != "stl":
        return []
    return [(m.group("a") or m.group("b"), float(m.group("v") or m.group("w"))) for m in _LOWER.finditer(c.formula or "")]


def _place_nodes(place: str, sentence: str, nodes: set[str]) -> list[str]:
    """The node the place words name ("short of i1", "before INTERSECTION sh", "before up": a lone id is an id even
    where it is also a word), else the nodes the sentence names ("approaching the intersection sh, it stops 2.5 m
    before the intersection")."""
    words = place.split()
    if words and words[-1] in nodes and (len(words) == 1 or words[-2].isupper()):
        return [words[-1]]
    return named_nodes(place, nodes) or named_nodes(sentence, nodes)


def _keeps_back(spec: ScenarioSpec, near: list[str], need: float | None) -> bool:
    """Some criterion keeps the robot back from a node the text names there (or an encounter at it), by any amount,
    or from any place by at least `need` (the text's amount less WAIT_SLACK: "3 m before the junction" held as "at
    least 2 m from the node just past it"; None: the text says no amount, so only its own place tells)."""
    at_node = {f"node_{n}" for n in near} | {e.id for e in spec.encounters if e.node in near}
    return any(v > 0 and (place in at_node or (need is not None and v >= need - 1e-9) or not (near or need))
               for c in spec.criteria for place, v in _bounds(c))


def robot_wait_mistakes(description: str, expected: str, behaviors: dict[str, str], spec: ScenarioSpec,
                        nodes: set[str] | None = None) -> list[str]:
    """Each place the text has the robot wait N m short of without a criterion that keeps it that far back."""
    names = people_names(description, behaviors)
    said = [(n, place, s) for text, mine in ((description, False), (expected, True)) for s in sentences(text)
            for n, place in _robot_waits(s, names, mine)]
    mistakes, told = [], set()
    for amount, place, sentence in said:
        near = _place_nodes(place, sentence, nodes or set())
        node = near[0] if near else None
        need = max(amount - WAIT_SLACK, 0.0) if amount is not None else None
        if (node or place) in told or _keeps_back(spec, near, need):
            continue
        told.add(node or place)
        quote = quoted(sentence)
        signal = f"robot_to_node_{node}" if node else "robot_to_node_N"
        bound = f"{need:g}" if need else "D"
        mistakes.append(
            f"the text has the robot wait {'about ' + format(amount, 'g') + ' m ' if amount else ''}short of "
            f"{place} (\"{quote}\"), but no criterion keeps the robot back from {node or 'that place'} (a distance "
            f"from a person, or only an upper bound such as robot_to_... < d, passes a robot that drives right up to "
            f"it); add an stl criterion such as \"({signal} >= {bound}) until (humanK_to_node_M < 1.0)\" (humanK at node "
            f"M: what ends the wait in your text, e.g. the last of them at a node past the robot or inside where they go"
            f"{'; N: the node of ' + place if not node else ''}{'' if need else '; D: how far back it waits, in metres'}"
            f"), or drop the place from the text")
    return mistakes


def _stayers(description: str, behaviors: dict[str, str], words: re.Pattern[str] = STAY,
             until: bool = True) -> list[tuple[str, str, str]]:
    """(humanN, words, sentence) of each person the text has stay put for good (or do what `words` say; `until`:
    not "until" something after them): in a behavior its person (unless the clause names the robot or another
    person first), in the description the people the clause names before it."""
    names = people_names(description, behaviors)
    found = []
    for owner, sentence in owned_sentences(description, behaviors):
        for m in words.finditer(sentence):
            if (until and _UNTIL.match(sentence[m.end():])) or _IF.search(sentence):
                continue
            head = sentence[:m.start()]
            ends = [e.end() for e in _CLAUSE_END.finditer(head)]
            clause = head[max(ends) if ends else 0:]
            named = [f"human{n}" for n in _PERSON.findall(clause)]
            named += [names[w.lower()] for w in re.findall(r"\b[A-Z][a-z]+\b", clause) if w.lower() in names]
            if named:
                found += [(h, m.group(0), sentence) for h in dict.fromkeys(named)]
            elif owner and not _ROBOT.search(clause):
                found.append((owner, m.group(0), sentence))
    return found


def _sees_stay(c: Criterion, human: str) -> bool:
    """An stl that fails when `human` walks off: on moved_<human>, or an upper bound on their distance to a place."""
    formula = (c.formula or "") if c.kind == "stl" else ""
    return re.search(rf"\bmoved_{human}\b|\b{human}_to_\w+\s*<|>=?\s*{human}_to_\w+", formula) is not None


def _sees_back(c: Criterion, human: str) -> bool:
    """An stl that bounds `human`'s distance to one place from above AND from below: they were away from it (came
    to the robot) and then back. An upper bound alone holds at the start for someone who starts there and meets
    the robot nearby ("eventually (dist_h < 2.0 and eventually (h_to_node_N < 1.0))" held as round 27's driver set
    off; home_18's resident was 'back on her mat' before she left it). Not moved_<human>: it latches once they
    have walked, so "moved_h < 1.0" after the walk up never holds again (round 25)."""
    formula = (c.formula or "") if c.kind == "stl" else ""
    below = set(re.findall(rf"\b{human}_to_(\w+)\s*<", formula)) | \
        set(re.findall(rf">=?\s*{human}_to_(\w+)", formula))
    above = set(re.findall(rf"\b{human}_to_(\w+)\s*>", formula)) | \
        set(re.findall(rf"<=?\s*{human}_to_(\w+)", formula))
    return bool(below & above)


def stay_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """Each person the text has stay put without a criterion that sees them stay."""
    mistakes, told = [], set()
    humans = set(spec.humans())
    for human, words, sentence in _stayers(description, behaviors):
        if human in told or human not in humans or any(_sees_stay(c, human) for c in spec.criteria):
            continue
        told.add(human)
        quote = quoted(sentence)
        mistakes.append(
            f"the text has {human} stay where they are ('{words}': \"{quote}\"), but no criterion sees {human} stay "
            f"(meets, look, stops_near_robot and group_together all pass a person who walks off); add an stl "
            f"criterion such as \"always (moved_{human} < 0.5)\" ({human} never gets {MOVED_DISTANCE:g} m from where "
            f"they started) or \"always ({human}_to_node_N < 1.0)\" (N: the node they stand at), or say in the text "
            f"when they move")
    return mistakes


# Going back to a place: "walks back to the mat", "heads back toward her desk", "returns to the group".
BACK = re.compile(r"\b(?:(?:walks?|walking|goes|going|go|heads?|heading|comes?|coming|wanders?|wandering|strolls?|"
                  r"hurries|hurrying|moves?|moving) back (?:to|toward|towards|into|onto)|"
                  r"returns? to|returning to)\b", re.IGNORECASE)


COMING = ("follow", "block")  # reactions that take a person to the robot (sim/robot/lead.goes_with_robot)


def back_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """Each person whom a reaction takes to the robot (COMING: a handover) and the text has go back to a place,
    without a criterion that sees where they end up (_sees_stay's signals: meets, blocks_robot, stops_near_robot
    and the like pass a person who never goes back). Someone who steps aside and goes back is not asked: giving
    way walks them back (people.give_way), and a give-way is judged by its own criteria."""
    mistakes, told = [], set()
    humans = {h for h in spec.humans() if any(p.reaction in COMING for _, p in spec.parts_of(h))}
    for human, words, sentence in _stayers(description, behaviors, BACK, until=False):
        if human in told or human not in humans or any(_sees_back(c, human) for c in spec.criteria):
            continue
        told.add(human)
        mistakes.append(
            f"the text has {human} go back ('{words}': \"{quoted(sentence)}\"), but no criterion sees where {human} "
            f"ends up (meets, blocks_robot, stops_near_robot and follows_robot all pass a person who stays by the "
            f"robot); add an stl criterion such as \"eventually (dist_{human} < 2.0 and {human}_to_node_N > 1.0 and "
            f"eventually ({human}_to_node_N < 0.8))\" (at the robot, over 1 m from node N, the node they go back to, "
            f"then back within 0.8 m of it; an upper bound alone holds at the start for someone who starts at N), or "
            f"drop it from the text")
    return mistakes
