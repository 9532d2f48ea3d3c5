"""Checks that the criteria and the paths say what the prose says (issue 25). Three round-13 runs passed the verifier
where a person looking at the GIF saw their text not happen, each because nothing held the spec or the plan to the
description: a child "right behind" the robot allowed 4.5 m (he stood 12 s by the table), a correction that started
a patient in a side room while her text still has her come from the corridor's end, and a worker the text has "walk
on behind" the robot with no criterion about who goes first. Each check is general (words and node ids of the text
against the numbers, criteria and paths), never keyed to a scenario:

- `close_follow_mistakes` (stage 1): a follower the text has right / close behind someone may be no farther from
  them than a follower keeps (sim.people.leaves.follow_trail) plus Hall's personal space (bodies.PERSONAL_SPACE);
- `order_mistakes` (stage 1): a person the description puts behind or ahead of the robot (who goes first) has a
  criterion that can see an order (an stl naming them, follows_*, gives_way, blocks_robot);
- `person_order_mistakes` (stage 1): a person the text puts behind or ahead of another PERSON has a criterion that
  relates the two (follows_human, or an stl naming both): follows_robot measures each follower from the robot only,
  so round 14's home_09 passed with the two children in the reverse of the text's order;
- `way_in_mistakes` (stage 2): a person whose text names where they come from into their first encounter's node
  comes into it that way (an Upstream mistake: when the plan cannot, stage 1 changes the text).
"""

from __future__ import annotations

import math
import re

import networkx as nx

from socnavgen.bodies import PERSON_MAX_SPEED, PERSON_RADIUS, PERSONAL_SPACE
from socnavgen.proposal.conversation import Upstream
from socnavgen.proposal.replies import human_name
from socnavgen.run.spec import Criterion, ScenarioSpec


def owned_sentences(description: str, behaviors: dict[str, str],
                    more: list[tuple[str | None, str]] | None = None) -> list[tuple[str | None, str]]:
    """(owner, sentence) of every sentence the checks read: each behavior's (its person), any `more` texts (with
    their owner), then the description's (owner None)."""
    texts: list[tuple[str | None, str]] = [(human_name(k) or k, str(v)) for k, v in behaviors.items()]
    texts += more or []
    texts.append((None, description))
    return [(owner, sentence) for owner, text in texts for sentence in sentences(text)]


def sentences(text: str) -> list[str]:
    """The sentences of a text, stripped (the one split every prose check reads)."""
    return [s.strip() for s in re.split(r"(?<=[.;!?])\s+", text) if s.strip()]


def quoted(sentence: str, limit: int = 160) -> str:
    """A sentence short enough to quote back to the model."""
    return sentence if len(sentence) <= limit else sentence[:limit - 3] + "..."


# Words that put a follower right at someone's back (criterion text or the person's behavior text).
# `whom`: what follows "behind" ("it", "the robot", "the lead worker"; none at the end of a clause).
CLOSE_BEHIND = re.compile(r"\b(?:right|close|closely|just|directly|immediately) behind\b(?: (?P<whom>the robot|it\b|"
                          r"(?:the|a|an|his|her|its|their|human) ?\w+))?|\bon (?:its|his|her|their) heels\b|"
                          r"\bfollows? (?:it |them |him |her |the robot )?closely\b", re.IGNORECASE)
# Words that say who goes first between a person and the robot.
_PASSER = r"(?!(?:the robot|it)\b)(?:he|she|they|him|her|them|the \w+|human ?\d+|(?-i:[A-Z]\w+))(?: \([^)]*\))?"  # who passes the
# robot (a person: "lets the robot pass" is a person giving way, the order the robot-first words above already say)
ORDER_WORDS = re.compile(r"\b(?:behind (?:it|the robot)|ahead of (?:it|the robot)|go(?:es)? (?:on )?first|"
                         r"(?:after|once|until) (?:it|the robot) (?:has )?(?:passed|gone by|gone past)|"
                         # the robot waits for someone to pass (a ROBOT WAIT: they go first)
                         rf"(?:waits?|stays?|stands?|stops?)\b[^.;]{{0,50}}?\buntil {_PASSER} (?:has|have) (?:passed|"
                         r"gone by|gone past|walked (?:past|by)|come (?:through|out|past)|run past|rushed past|crossed)|"
                         rf"lets {_PASSER} (?:pass|go first|go by|go past|come through|come out|cross))\b",
                         re.IGNORECASE)
ORDER_KINDS = ("follows_robot", "follows_human", "gives_way", "blocks_robot")  # (and an stl naming the person)
# Words that put a person behind or ahead of someone; `whom` is a person (person_whom) or a place ("the counter").
PERSON_ORDER = re.compile(r"\b(?P<how>behind|ahead of) (?P<whom>[Hh]uman ?\d+|(?:his|her|their|the|a) (?:\w+ )?\w+|"
                          r"[A-Z][a-z]+)\b")
# Nouns that name a person (after his / her / their / the): "behind his sister", "behind the lead worker".
PEOPLE_WORDS = {"sister", "brother", "sibling", "mother", "father", "mum", "mom", "dad", "parent", "son", "daughter",
                "child", "kid", "grandchild", "grandmother", "grandfather", "grandma", "grandpa", "friend", "colleague",
                "partner", "husband", "wife", "companion", "leader", "guide", "supervisor", "boss", "nurse", "doctor",
                "patient", "visitor", "guest", "host", "worker", "picker", "porter", "resident", "teenager", "man",
                "woman", "boy", "girl", "person", "auditor", "technician", "driver", "cleaner", "manager", "relative"}
METRES = re.compile(r"(\d+(?:\.\d+)?)\s*(?:m|metres|meters)\b")  # a distance the text states
_NAMED = re.compile(r"\b[Hh]uman ?(\d+)\b")
# Tokens that are words or amounts before they are node ids ("walks up the aisle", "waits 12 s").
_NOT_NODES = {"up", "in", "on", "at", "to", "go", "do", "be", "it", "is", "as", "by", "of", "or", "an", "no", "so"}


def close_follow_gap(leader_speed: float, own_speed: float) -> float:
    """The farthest (m, along the walkable way) a follower right behind someone is: the trail a follower keeps behind
    a leader at `leader_speed` (the simulator's own) and, beyond it, Hall's personal space."""
    from socnavgen.sim.people.leaves import follow_trail

    return follow_trail(leader_speed, own_speed) + PERSONAL_SPACE


def _person_speed(spec: ScenarioSpec, human: str | None) -> float:
    person = spec.people.get(human or "")
    return person.speed if person is not None and person.speed else PERSON_MAX_SPEED


def _leader(spec: ScenarioSpec, c: Criterion) -> tuple[str, float]:
    """Whom `c` measures its follower against, and that one's speed."""
    if c.kind == "follows_human":
        other = next((p.other for _, p in spec.parts_of(c.human or "") if p.reaction == "follow_human" and p.other),
                     None)
        return (other or "whom they follow"), _person_speed(spec, other)
    return "the robot", spec.script.speed


def _behind_leader(kind: str, whom: str | None) -> bool:
    """Whether "right behind <whom>" is about whom the criterion measures: the robot (it, the robot, nobody named) for
    follows_robot, anyone but the robot for follows_human (a follows_robot whose text has them right behind a person
    measures the wrong leader, which is another mistake)."""
    robot = whom is None or whom.lower() in ("it", "the robot")
    return robot if kind == "follows_robot" else whom is None or whom.lower() != "the robot"


STATED_SLACK = 0.5  # m: a criterion may allow this much beyond the farthest distance its text states


def _says_how_far(text: str, distance: float) -> bool:
    """The text that has them close behind also says how far, in metres, and the criterion allows no more than the
    farthest it states (+ STATED_SLACK): "right behind it, about 1.5-3 m back" with 3.5 m says what it checks."""
    stated = [float(v) for v in METRES.findall(text)]
    return bool(stated) and distance <= max(stated) + STATED_SLACK + 1e-9


def close_follow_mistakes(spec: ScenarioSpec, behaviors: dict[str, str]) -> list[str]:
    """A follows_* criterion whose text (or its person's behavior) has them right / close behind, but whose distance
    lets them stand far behind: the verifier would pass a follower who stood still while the leader went on."""
    texts = {human_name(k) or k: str(v) for k, v in behaviors.items()}
    mistakes = []
    for c in spec.criteria:
        if c.kind not in ("follows_robot", "follows_human") or not c.human or c.distance is None:
            continue
        found = next(((m, text) for text in (c.text, texts.get(c.human, "")) for m in CLOSE_BEHIND.finditer(text)
                      if _behind_leader(c.kind, m.group("whom"))), None)
        if found is None or _says_how_far(found[1], c.distance):
            continue
        said = found[0]
        leader, speed = _leader(spec, c)
        ceiling = close_follow_gap(speed, _person_speed(spec, c.human))
        if c.distance > ceiling + 1e-9:
            trail = ceiling - PERSONAL_SPACE
            mistakes.append(
                f"criterion {c.id} ({c.kind}) lets {c.human} be up to {c.distance:g} m from {leader}, but the text has "
                f"{c.human} '{said.group(0)}': a follower keeps about {trail:.1f} m behind a leader at {speed:g} "
                f"m/s, and right behind is within Hall's personal space ({PERSONAL_SPACE:g} m) beyond that, so with "
                f"{c.distance:g} m someone standing still while {leader} goes on would pass; set its distance to at "
                f"most {math.floor(ceiling * 10) / 10:g} m (a robot that must not lose them waits with a human_farther "
                f"cue at that distance), or say in the text how far behind {c.human} walks")
    return mistakes


def _about(c: Criterion, human: str) -> bool:
    if c.kind == "stl":
        return re.search(rf"\w_{human}\b|\b{human}_\w", c.formula or "") is not None
    return human in [c.human, *c.humans]


def _ordered_sentences(description: str, behaviors: dict[str, str]) -> list[tuple[str, str, str]]:
    """(person, words, sentence) for each sentence that says who goes first between a person and the robot: in a
    person's behavior, or in the description, where the person is the one human the sentence (or the last sentence
    naming one human, 'Human 2' or 'human2') names."""
    found = []
    for key, text in behaviors.items():
        name = human_name(key) or key
        found += [(name, m.group(0), str(text)) for m in ORDER_WORDS.finditer(str(text))][:1]
    subject: str | None = None
    for sentence in sentences(description):
        named = set(_NAMED.findall(sentence)) | set(re.findall(r"\bhuman(\d+)\b", sentence))
        if named:
            subject = f"human{named.pop()}" if len(named) == 1 else None
        said = ORDER_WORDS.search(sentence)
        if said is not None and subject is not None:
            found.append((subject, said.group(0), sentence.strip()))
    return found


def order_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """A person the text puts behind or ahead of the robot needs a criterion that can see the order: meets,
    stops_near_robot or says pass whoever goes first."""
    mistakes, told = [], set()
    humans = set(spec.humans())
    for human, words, sentence in _ordered_sentences(description, behaviors):
        if human in told or human not in humans:
            continue
        if any(_about(c, human) and (c.kind == "stl" or c.kind in ORDER_KINDS) for c in spec.criteria):
            continue
        told.add(human)
        quote = quoted(sentence)
        mistakes.append(
            f"the text says who goes first between {human} and the robot ('{words}': \"{quote}\"), but no criterion "
            f"about {human} can see that order (meets, stops_near_robot and says pass whoever goes first); add one "
            f"that states it, e.g. an stl criterion such as \"({human}_to_node_N > 2.0) until (robot_to_node_N < "
            f"1.0)\" (the robot reaches node N before {human} comes near it; swap the two for {human} first; N: a "
            f"node id of the robot's route that it reaches only once, after the encounter: never its start, nor a node "
            f"a round trip passes on the way out, where it would hold at once), or follows_robot / gives_way where "
            f"that is what {human} does; or drop the order from the text if it does not matter")
    return mistakes


def people_names(description: str, behaviors: dict[str, str]) -> dict[str, str]:
    """{word: humanN} for the names and roles the text gives its people: "Mia (Human 1)", "the nurse (human2)", and a
    behavior that opens with a name ("Mia, the older grandchild, ...")."""
    names = {m.group(1).lower(): f"human{m.group(2)}"
             for m in re.finditer(r"\b(\w+) \((?:[Hh]uman ?)(\d+)\b", description)}
    for key, text in behaviors.items():
        opening = re.match(r"\s*([A-Z][a-z]+),", str(text))
        if opening and (name := human_name(key)):
            names.setdefault(opening.group(1).lower(), name)
    return names


_FUNCTION_WORDS = {"and", "or", "with", "to", "in", "at", "on", "as", "while", "who", "when", "then", "into", "from"}


def _person(words: str, names: dict[str, str]) -> tuple[bool, str | None]:
    """(is a person, which human when the text says) for the words after "behind" / "ahead of": the head noun of the
    phrase decides, its last word before a function word ("the lead worker" and "the nurse and ..." are people; "the
    nurse station" behind which someone works is furniture - round 35's hospital_28 was told to order a nurse
    'behind the nurse station counter' after another person)."""
    named = human_name(words)
    if named:
        return True, named
    tokens = words.split()
    body = tokens[1:] if len(tokens) > 1 else tokens
    while len(body) > 1 and body[-1].lower() in _FUNCTION_WORDS:
        body = body[:-1]
    for token in body:
        low = token.lower()
        if low in ("robot", "it"):
            return False, None
        if low in names:
            return True, names[low]
    head = body[-1].lower() if body else ""
    return head in PEOPLE_WORDS, None


def _mentions(text: str, names: dict[str, str]) -> list[tuple[int, str]]:
    """(position, humanN) of every person the text names: humanN, Human N, or a name of `names`."""
    found = [(m.start(), f"human{m.group(1)}") for m in re.finditer(r"\b[Hh]uman ?(\d+)\b", text)]
    found += [(m.start(), names[m.group(0).lower()]) for m in re.finditer(r"\b\w+\b", text)
              if m.group(0)[0].isupper() and m.group(0).lower() in names]
    return sorted(found)


def _person_orders(description: str, behaviors: dict[str, str], spec: ScenarioSpec
                   ) -> list[tuple[str, str, str | None, str, str]]:
    """(person, how, whom as humanN or None, words, sentence) for each sentence that puts a person behind or ahead
    of another person: in a behavior (its person, unless the sentence names another before the words), a
    criterion's text (its human) or the description (the person the sentence names last before the words)."""
    names = people_names(description, behaviors)
    found = []
    for owner, sentence in owned_sentences(description, behaviors,
                                           [(c.human, c.text) for c in spec.criteria if c.human and c.text]):
        for m in PERSON_ORDER.finditer(sentence):
            person, whom = _person(m.group("whom"), names)
            before = [h for at, h in _mentions(sentence, names) if at < m.start() and h != whom]
            who = before[-1] if before else owner
            if person and who and who != whom:
                found.append((who, m.group("how"), whom, m.group(0), sentence.strip()))
    return found


# Signals of an stl that tell who is ahead: a distance from the robot (dist_, way_), to a place (_to_) or between
# two people along the way (way_h_o); spread_ and pgap_ are the same whichever of the two goes first.
_PLACED = re.compile(r"\b(?:(?:dist|way)_(human\d+)(?:_(human\d+))?|(human\d+)_to_\w+)")


def _relates(c: Criterion, human: str) -> bool:
    """`c` can see where `human` walks relative to another person: follows_human, or an stl placing both."""
    if c.kind == "follows_human":
        return c.human == human
    named = {h for m in _PLACED.finditer(c.formula or "") for h in m.groups() if h} if c.kind == "stl" else set()
    return human in named and len(named) >= 2


# Words that give a person a place in a file of people ("walks third through the doorway", "as the fourth and last
# of the team", "after both of them"); "first" is left to ORDER_WORDS (who goes first is most often said of the robot).
# An ordinal after a determiner names a thing, not a place in the file ("comes out of the second bedroom").
FILE_PLACE = re.compile(r"\b(?:(?:go(?:es)?|walks?|steps?|comes?|pass(?:es)?|enters?|files?|gets?|moves?)(?: \w+){0,4}? "
                        r"(?<!\bthe )(?<!\ba )(?<!\bhis )(?<!\bher )(?<!\bits )(?<!\btheir )(?<!\bthis )"
                        r"(?:second|third|fourth|fifth|last)|as the (?:second|third|fourth|fifth|last)|"
                        r"(?:the )?last of (?:them|the \w+|all)|after (?:all|both)(?: of)? (?:them|the \w+)|"
                        r"after the others|after everyone(?: else)?)\b", re.IGNORECASE)
_ROBOT_SAID = re.compile(r"\b(?:the robot|it)\b", re.IGNORECASE)


def _file_places(description: str, behaviors: dict[str, str]) -> list[tuple[str, str, str]]:
    """(person, words, sentence) for each sentence that gives a person a place in a file of people: a behavior's
    person, or in the description the person named last before the words (none where the robot is named after them:
    "the robot goes in last")."""
    names = people_names(description, behaviors)
    found = []
    for owner, sentence in owned_sentences(description, behaviors):
        for m in FILE_PLACE.finditer(sentence):
            before = sentence[:m.start()]
            people = [(at, h) for at, h in _mentions(before, names)]
            robot = [r.start() for r in _ROBOT_SAID.finditer(before)]
            last_person = people[-1][0] if people else -1
            if robot and max(robot) > last_person and (owner is None or re.search(
                    r"\b(?:the robot|it) (?:\w+ ){0,3}$", before[max(robot):] + " ")):
                continue  # the robot is the one the words are about
            who = people[-1][1] if people and owner is None else owner
            if who:
                found.append((who, m.group(0), sentence.strip()))
    return found


def file_place_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec,
                        told: set[str] | None = None) -> list[str]:
    """A person the text gives a place in a file of people (second, last, after all of them) needs a criterion that
    relates them to another person of the file: follows_robot or meets measure each from the robot only (`told`:
    people already told of an order)."""
    mistakes: list[str] = []
    told = set() if told is None else told
    humans = set(spec.humans())
    if len(humans) < 2:
        return []
    for human, words, sentence in _file_places(description, behaviors):
        if human in told or human not in humans or any(_relates(c, human) or (
                c.kind == "follows_human" and _leader(spec, c)[0] == human) for c in spec.criteria):
            continue
        told.add(human)
        quote = quoted(sentence)
        mistakes.append(
            f"the text gives {human} a place in a file of people ('{words}': \"{quote}\"), but no criterion relates "
            f"{human} to the others (each measured from the robot or a place alone passes them in any order); add an "
            f"stl criterion over {human} and the one before them, such as \"(({human}_to_node_N > 1.0) until "
            f"(humanX_to_node_N < 0.5))\" (humanX at node N, a node inside where they go, before {human} comes "
            f"near it), or drop the order from the text if it does not matter")
    return mistakes


def person_order_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """A person the text puts behind or ahead of another person needs a criterion that relates the two."""
    mistakes, told = [], set()
    humans = set(spec.humans())
    for human, how, whom, words, sentence in _person_orders(description, behaviors, spec):
        if human in told or human not in humans or any(_relates(c, human) for c in spec.criteria):
            continue
        told.add(human)
        other = whom if whom in humans else "humanX"
        back, front = (human, other) if how == "behind" else (other, human)
        quote = quoted(sentence)
        mistakes.append(
            f"the text puts {human} {how} another person ('{words}': \"{quote}\"), but no criterion relates "
            f"{human} to that person (follows_robot measures each follower from the robot only, so the reverse order "
            f"passes); let {back} follow {front} (reaction follow_human with `other`, criterion follows_human), or add "
            f"an stl criterion such as \"eventually (always (way_{back} >= way_{front} + {PERSON_RADIUS:g}))\" "
            f"(two followers of the robot: {back} the farther from it along the way, from some moment to the end"
            f"{'; humanX: the person ' + human + ' walks ' + how if other == 'humanX' else ''})")
    return mistakes + file_place_mistakes(description, behaviors, spec, told)


def named_nodes(text: str, nodes: set[str]) -> list[str]:
    """The node ids a text names, in the order it first names them (words and amounts that happen to be ids left
    out)."""
    found = []
    for match in re.finditer(r"[0-9A-Za-z_]+", text):
        token = match.group(0)
        amount = token.isdigit() and re.match(r"\s*(?:m\b|s\b|%|m/s|seconds?|metres?|meters?)", text[match.end():])
        if token in nodes and token.lower() not in _NOT_NODES and not amount and token not in found:
            found.append(token)
    return found


def _starts_past_halfway(graph: nx.Graph, start: str, origin: str, node: str) -> bool:
    """The path starts nearer (along the graph) to the encounter's node than to the place the text has the person come
    from: they are seen coming from near the encounter, and the way from the text's place is left out (warehouse_12's
    final plan started the picker at the aisle's north end xq, 2.4 m from the encounter and 7.2 m from yh, where her
    text has her come up the aisle from; home_08's husband, "leaving the kitchen 3y", starting at vh 2.75 m out of it
    and 3.3 m from the encounter, is seen leaving it)."""
    if start == origin or not (nx.has_path(graph, start, node) and nx.has_path(graph, start, origin)):
        return False
    return bool(nx.shortest_path_length(graph, start, node, weight="length")
                < nx.shortest_path_length(graph, start, origin, weight="length"))


def way_in_mistakes(graph: nx.Graph, spec: ScenarioSpec, behaviors: dict[str, str], paths: dict[str, list[str]],
                    encounter_nodes: dict[str, str]) -> list[str]:
    """A person whose behavior names where they come from into their first encounter's node (the nodes it names
    before that node) comes into that node along that way (the node their path enters it from is on a shortest way
    from a named one), from a start nearer to the place the text has them come from (the first node it names) than to
    the encounter (_starts_past_halfway): hospital_11's correction started a patient in a side room while her text has
    her walk in from the corridor's end."""
    mistakes: list[str] = []
    nodes = {str(n) for n in graph.nodes}
    for key, text in behaviors.items():
        human = human_name(key) or key
        parts = sorted(spec.parts_of(human), key=lambda ep: ep[0].order)
        path = paths.get(human) or []
        node = encounter_nodes.get(parts[0][0].id) if parts else None
        named = named_nodes(str(text), nodes)
        if node is None or node not in named or node not in path or path.index(node) == 0:
            continue
        before = named[:named.index(node)]
        way: set[str] = set()
        for origin in before:
            if nx.has_path(graph, origin, node):
                way |= set(nx.shortest_path(graph, origin, node, weight="length"))
        came = path[path.index(node) - 1]
        if not before or (came in way and not _starts_past_halfway(graph, path[0], before[0], node)):
            continue
        enc = parts[0][0]
        text_way = " ".join(nx.shortest_path(graph, before[0], node, weight="length")) \
            if nx.has_path(graph, before[0], node) else f"{before[0]} ... {node}"
        walked = " ".join(path[:path.index(node) + 1])
        how = f"comes into {node} from {came}" if came not in way else \
            f"starts at {path[0]}, nearer to {node} than to {before[0]}, leaving the way from {before[0]} out"
        mistakes.append(Upstream(
            f"{human}'s behavior has {human} come to {node} (encounter {enc.id}) from {', '.join(before)}, but "
            f"{human}'s path {how} ({walked}): the encounter would not happen the way the text says; let {human}'s path come in along {text_way}; if that cannot work on this plan (the text's "
            f"place is the robot's start or goal, or its pacing cannot hold {human} there), keep your answer and say "
            f"why: stage 1 is then asked to change where {human} comes from",
            key=f"way_in:{human}:{node}", upstream=(
                f"{human}'s behavior has {human} come to encounter {enc.id} ({enc.place} {node}) from "
                f"{', '.join(before)}, and stage 2 could not plan that way (it brought {human} in from {came}: "
                f"{walked}); say in human_behaviors and the description where {human} comes from as stage 2 can plan "
                f"it (a place off the robot's start and goal), or put {enc.id} elsewhere")))
    return mistakes
