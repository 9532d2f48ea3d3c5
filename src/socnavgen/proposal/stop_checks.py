"""A stop the text states for a greeting needs a criterion that sees it (issue 25). home_03's text has the robot stand
still a few seconds in the living room so that the guests, who stop too, can greet the host; its criteria had the
host meet the robot and stop near it (measured from the robot only) and the guests follow it, so a run in which the
robot only slowed to 0.25 m/s and the host turned back before the first guest came out of the hallway passed. Like
prose_checks.person_order_mistakes, a general check of the words against the criteria, never keyed to a scenario:

- a sentence with a stop (stops, stands still, pauses, halts) and a greeting (greet, welcome, say hello, shake
  hands, introduce; not of the robot itself);
- the robot's stop ("the robot stands still", "while it pauses") needs `robot_stops` (or an stl on robot_still /
  stalled / speed_robot);
- a person's stop (a behavior's person; in the description, the person it names last before the verb) needs
  `stop_together` with that person among its humans (or an stl placing them and another person while still).
"""

from __future__ import annotations

import re

from socnavgen.proposal.prose_checks import owned_sentences, people_names, quoted
from socnavgen.run.spec import Criterion, ScenarioSpec

STOP_WORDS = re.compile(r"\b(?:stops?|stopping|stands? still|pauses?|halts?)\b", re.IGNORECASE)
GREETING = re.compile(r"\b(?:greet\w*|welcom\w*|say(?:s|ing)? hello|shak\w* hands|introduc\w*)\b"
                      r"(?! (?:to )?(?:the robot|it)\b)", re.IGNORECASE)
_ROBOT_SUBJECT = re.compile(r"\b(?:the robot|it)(?: \w+){0,3}? ?$", re.IGNORECASE)  # "the robot then" + verb
_PERSON = re.compile(r"\b[Hh]uman ?(\d+)\b")
_ROBOT_STILL = re.compile(r"\b(?:robot_still|stalled|speed_robot)\b")
_STILL_PERSON = re.compile(r"\bspeed_(human\d+)\b")
_TOGETHER = re.compile(r"\b(?:way|spread|pgap)_((?:human\d+_?)+)")


def _stops(description: str, behaviors: dict[str, str]) -> list[tuple[str, str, str]]:
    """(who: 'robot' or humanN, words, sentence) of every stop for a greeting the text states."""
    names = people_names(description, behaviors)
    found = []
    for owner, sentence in owned_sentences(description, behaviors):
        if not GREETING.search(sentence):
            continue
        for m in STOP_WORDS.finditer(sentence):
            before = sentence[:m.start()]
            if _ROBOT_SUBJECT.search(before.rstrip(" ")):  # "the robot (then) stops", not "follows the robot, stops"
                found.append(("robot", m.group(0), sentence.strip()))
                continue
            named = [f"human{n}" for n in _PERSON.findall(before)]
            named += [names[w.lower()] for w in re.findall(r"\b[A-Z][a-z]+\b", before) if w.lower() in names]
            who = owner or (named[-1] if named else None)  # a behavior's sentences are about its person
            if who:
                found.append((who, m.group(0), sentence.strip()))
    return found


def _sees_robot_stop(c: Criterion) -> bool:
    return c.kind == "robot_stops" or (c.kind == "stl" and _ROBOT_STILL.search(c.formula or "") is not None)


def _sees_person_stop(c: Criterion, human: str) -> bool:
    """`c` sees `human` stand still beside someone: stop_together naming them, or an stl with their speed and a
    distance between them and another person."""
    if c.kind == "stop_together":
        return human in c.humans
    if c.kind != "stl":
        return False
    formula = c.formula or ""
    together = {h for m in _TOGETHER.finditer(formula) for h in re.findall(r"human\d+", m.group(1))}
    return human in _STILL_PERSON.findall(formula) and human in together and len(together) >= 2


def stop_mistakes(description: str, behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """Each stop for a greeting the text states (the robot's, a person's) without a criterion that sees it."""
    mistakes, told = [], set()
    humans = set(spec.humans())
    for who, words, sentence in _stops(description, behaviors):
        if who in told or (who != "robot" and who not in humans):
            continue
        quote = quoted(sentence)
        if who == "robot" and not any(_sees_robot_stop(c) for c in spec.criteria):
            mistakes.append(
                f"the text has the robot stop for a greeting ('{words}': \"{quote}\"), but no criterion sees the robot "
                "stand still (a robot that only slows down there passes the others); add {\"kind\": \"robot_stops\", "
                "\"encounter\": \"eN\", \"seconds\": S} for the encounter where it stops (S: how long, 2 s unless "
                "given), with a cue there that stops it, or drop the stop from the text")
        elif who != "robot" and not any(_sees_person_stop(c, who) for c in spec.criteria):
            mistakes.append(
                f"the text has {who} stop to greet someone ('{words}': \"{quote}\"), but no criterion sees {who} stand "
                f"still beside them (meets and stops_near_robot measure from the robot only); add {{\"kind\": "
                f"\"stop_together\", \"humans\": [\"{who}\", ...everyone who stops with them], \"encounter\": \"eN\"}} "
                f"(all stand still at once within `distance`, default 3 m, of each other), or drop the stop from "
                f"the text")
        else:
            continue
        told.add(who)
    return mistakes
