"""Checks of the scenario spec (spec.json) and of stage 1's prose: each mistake is named in words
that tell the model (or the user who edited spec.json) what to fix.

Prose: placeholders (`<...>`), echoes of the answer template and empty behaviors are rejected.
Spec: validated by the models of run/spec.py, then for consistency with the scenario (its humans),
the location (node types), the robot script (a phrase a human waits for must be said by the robot)
and the export target (a trigger or reaction needs a node the target can run)."""

from __future__ import annotations

import math
import re
from typing import get_args

from pydantic import BaseModel, ValidationError

from socnavgen.bt.library import Target, nodes_for_reaction
from socnavgen.location import Location
from socnavgen.location.inventory import BLIND_MARGIN
from socnavgen.proposal.facts import STATED_BY
from socnavgen.proposal.replies import human_name
from socnavgen.proposal.target_facts import can_latch, detecting_nodes, latching_node
from socnavgen.run.spec import Criterion, Encounter, HumanPart, ScenarioSpec
from socnavgen.verify.blame import contradictions, spec_problem
from socnavgen.verify.stl import formula_problems
from socnavgen.verify.thresholds import KIND_DISTANCE as CRITERION_DEFAULTS

# Criterion kinds that are about one human and therefore need `human`.
_PER_HUMAN = {"meets", "stops_near_robot", "reacts_after_phrase", "gives_way", "follows_robot", "follows_human",
              "hidden_until", "says", "keeps_away", "blocks_robot"}
_GLOBAL = {"robot_reaches_goal", "no_collision", "people_apart", "no_deadlock", "stl", "robot_stops"}
MIN_BEHAVIOR_WORDS = 4
HIDDEN_UNTIL_DEFAULT = CRITERION_DEFAULTS["hidden_until"]
_PLACEHOLDER = re.compile(r"<[^<>]{0,80}>|^\s*\.\.\.\s*$|\[[A-Z _]{3,40}\]|(?i:\b(?:placeholder|todo|tbd|lorem ipsum)\b)")
# Phrases of the answer template (scenario_user.md); a reply that contains one copied the template.
TEMPLATE_ECHOES = ("task and behavior towards the robot", "detailed description", "what the robot should do",
                   "number of humans", "short reasoning", "node id")


def prose_mistakes(field: str, text: str, *, min_words: int = 1) -> list[str]:
    """Empty text, a placeholder, a template echo, stray JSON punctuation: each a named mistake."""
    stripped = str(text).strip()
    if not stripped:
        return [f"{field} is empty; write it out"]
    mistakes: list[str] = []
    lowered = stripped.lower()
    echo = next((e for e in TEMPLATE_ECHOES if e in lowered), None)
    if echo:
        mistakes.append(f"{field} copies the answer template ('{echo}'); write the real content instead")
    elif _PLACEHOLDER.search(stripped):
        found = _PLACEHOLDER.search(stripped).group(0)  # type: ignore[union-attr]
        mistakes.append(f"{field} contains the placeholder '{found}'; replace it with the real content")
    if re.search(r"[{}]\s*,?\s*$", stripped) or stripped.startswith(("{", "}")):
        mistakes.append(f"{field} ends or starts with JSON punctuation ({stripped[-3:]!r}); it must be plain text")
    if not mistakes and len(re.findall(r"[A-Za-z]{2,}", stripped)) < min_words:
        mistakes.append(f"{field} is too short to be a behavior ('{stripped}'); say what the person does and "
                        f"how they react to the robot")
    return mistakes


def _words(text: str) -> list[str]:
    return re.findall(r"[a-z]+", text.lower())


def prose_spec_mistakes(behaviors: dict[str, str], spec: ScenarioSpec) -> list[str]:
    """Where the spec has a person do what their own behavior text never says: a phrase they say (in a part,
    or asked by a `says` criterion). What the spec contradicts in itself is the verifier's rule S1
    (verify/blame.py contradictions), which spec_mistakes applies."""
    texts = {human_name(k) or k: _words(str(v)) for k, v in behaviors.items()}

    def unsaid(human: str | None, phrase: str | None) -> bool:  # a phrase their behavior text never has
        words, said = texts.get(human or ""), _words(phrase or "")
        return words is not None and bool(said) and \
            not any(words[i:i + len(said)] == said for i in range(len(words)))

    mistakes = [f"criterion {c.id} asks {c.human} to say {c.phrase}, but the behavior of {c.human} never mentions "
                f"it; say in human_behaviors when and why {c.human} says {c.phrase} (and give them the reaction "
                f"say), or drop the criterion" for c in spec.criteria if c.kind == "says" and unsaid(c.human, c.phrase)]
    mistakes += [f"encounter {enc.id}: {part.human} says {part.says} in the spec, but the behavior of {part.human} "
                 f"never mentions it; say in human_behaviors when and why {part.human} says {part.says}, or change "
                 f"the reaction" for enc in spec.encounters for part in enc.humans
                 if part.reaction == "say" and unsaid(part.human, part.says)]
    return mistakes


def parse_spec(data: object) -> tuple[ScenarioSpec | None, list[str]]:
    """Validate `data` with the spec models; mistakes name the field path."""
    if data is None:
        return None, ["spec is missing; add the \"spec\" object (robot script, encounters, criteria)"]
    try:
        return ScenarioSpec.model_validate(data), []
    except ValidationError as exc:
        out = []
        for err in exc.errors()[:12]:
            where = ".".join(str(p) for p in err["loc"])
            home = _belongs(err["loc"]) if err["type"] == "extra_forbidden" else ""
            out.append(f"spec.{where}: {err['msg']}{home}" if where else f"spec: {err['msg']}")
        return None, out


def _model_at(loc: tuple) -> type[BaseModel] | None:
    """The spec model at a validation error's location (list indices and dict keys skipped)."""
    model: type[BaseModel] | None = ScenarioSpec
    for step in loc:
        if model is None:
            return None
        if isinstance(step, str) and step in model.model_fields:
            inner = [a for a in _flat(model.model_fields[step].annotation) if isinstance(a, type)
                     and issubclass(a, BaseModel)]
            model = inner[0] if inner else None
    return model


def _flat(annotation: object) -> list[object]:
    args = get_args(annotation)
    return [a for arg in args for a in _flat(arg)] if args else [annotation]


def _belongs(loc: tuple) -> str:
    """Where a field given at the wrong level belongs: one level up (a cue's "once" put in its trigger) or
    one level down (a trigger's "distance" put beside it), so the mistake says where to move it."""
    name, parent = loc[-1], tuple(loc[:-1])
    ups = [parent[:k] for k in range(len(parent) - 1, -1, -1)]
    for up in ups:
        model = _model_at(up)
        if model is not None and name in model.model_fields:
            return f" here: \"{name}\" belongs to {'spec.' + '.'.join(map(str, up)) if up else 'spec'}, not inside " \
                   f"\"{parent[-1]}\""
    model = _model_at(parent)
    for field in (list(model.model_fields) if model is not None else []):
        inner = _model_at((*parent, field))
        if inner is not None and inner is not model and name in inner.model_fields:
            return f" here: \"{name}\" belongs inside \"{field}\" (spec.{'.'.join(map(str, (*parent, field)))})"
    return ""


def _human_refs(criterion: Criterion) -> list[str]:
    return [h for h in [criterion.human, *criterion.humans] if h]


def _robot_says(spec: ScenarioSpec) -> set[str]:
    return {c.say for c in spec.script.cues if c.say}


def _human_says(spec: ScenarioSpec) -> dict[str, set[str]]:
    said: dict[str, set[str]] = {}
    for enc in spec.encounters:
        for part in enc.humans:
            if part.reaction == "say" and part.says:
                said.setdefault(part.human, set()).add(part.says)
    return said


def _checks_encounter(criterion: Criterion, encounter: Encounter) -> bool:
    if criterion.encounter == encounter.id:
        return True
    if criterion.kind in _GLOBAL:
        return False
    members = {p.human for p in encounter.humans}
    return bool(set(_human_refs(criterion)) & members)


def spec_mistakes(spec: ScenarioSpec, humans: list[str], node_types: list[str] | None = None,
                  target: Target | None = None, location: Location | None = None) -> list[str]:
    """Consistency of a validated spec with the scenario's humans, the location (its node types and, when
    given, what its map allows: location/inventory.py) and the target."""
    mistakes: list[str] = []
    ids = [e.id for e in spec.encounters]
    if not spec.encounters:
        mistakes.append("spec.encounters is empty; describe at least one encounter (who meets the robot, where)")
    for dup in sorted({i for i in ids if ids.count(i) > 1}):
        mistakes.append(f"spec.encounters: the id {dup} is used twice; number the encounters e1, e2, ...")
    in_encounters = {p.human for e in spec.encounters for p in e.humans}
    for name in humans:
        if name not in in_encounters:
            mistakes.append(f"spec.encounters: {name} of human_behaviors takes part in no encounter; add {name} "
                            f"to the encounter it is in")
    for name in sorted(in_encounters - set(humans), key=lambda n: int(n[5:])):
        mistakes.append(f"spec.encounters: {name} is not one of the humans of human_behaviors "
                        f"({', '.join(humans)})")
    types = {t.upper(): t for t in (node_types or [])}
    robot_phrases, human_phrases = _robot_says(spec), _human_says(spec)
    for enc in spec.encounters:
        if types and enc.place.strip().upper() not in types:
            mistakes.append(f"encounter {enc.id}: place '{enc.place}' is not a node type of the location; use one "
                            f"of {', '.join(types.values())}")
        seen: set[str] = set()
        for part in enc.humans:
            who = f"encounter {enc.id}, {part.human}"
            if part.human in seen:
                mistakes.append(f"{who}: listed twice in the same encounter")
            seen.add(part.human)
            if part.trigger == "robot_says" and part.phrase and part.phrase not in robot_phrases:
                mistakes.append(f"{who}: reacts when the robot says {part.phrase}, but no cue of spec.script.cues "
                                f"says {part.phrase}; add a cue that says it (or change the trigger)")
            if part.trigger == "human_says" and part.other:
                if part.other not in humans:
                    mistakes.append(f"{who}: waits for {part.other}, who is not a human of the scenario")
                elif part.phrase not in human_phrases.get(part.other, set()):
                    mistakes.append(f"{who}: waits for {part.other} to say {part.phrase}, but {part.other} never "
                                    f"has the reaction say {part.phrase}")
            if part.reaction == "follow_human" and not part.other:
                mistakes.append(f"{who}: reaction follow_human names the human to follow in `other`")
            if part.other == part.human:
                mistakes.append(f"{who}: `other` is {part.human} itself; name another human")
            if part.latch and part.trigger != "always" and not can_latch(part.trigger, target or "socrates"):
                mistakes.append(f"{who}: latch is true, but a {target} tree cannot remember the trigger "
                                f"{part.trigger} (it re-checks every condition at each tick); set latch false "
                                f"(the reaction then lasts while its trigger holds, or `lasts` seconds)")
            if part.until and part.until not in robot_phrases:
                mistakes.append(f"{who}: the reaction ends when the robot says {part.until} (`until`), but no cue of "
                                f"spec.script.cues says {part.until}; add a cue that says it")
            if part.until and latching_node("robot_says", target or "socrates") is None:
                mistakes.append(f"{who}: `until` needs a tree that remembers what the robot said, which {target} "
                                f"cannot; end the reaction with `lasts` instead")
            if target is not None:
                if part.trigger != "always" and not detecting_nodes(part.trigger, target)[0]:
                    mistakes.append(f"{who}: trigger {part.trigger} cannot be detected by any node {target} runs; "
                                    f"choose another trigger")
                if not nodes_for_reaction(part.reaction, target):
                    mistakes.append(f"{who}: reaction {part.reaction} has no node {target} runs; choose another "
                                    f"reaction")
        if not any(_checks_encounter(c, enc) for c in spec.criteria):
            mistakes.append(f"encounter {enc.id} has no acceptance criterion that checks it; add one (e.g. kind "
                            f"meets for {enc.humans[0].human} with encounter {enc.id})")
    for cue in spec.script.cues:  # (a cue naming an encounter or human absent from the spec fails validation)
        if cue.trigger.human and cue.trigger.human not in humans:
            mistakes.append(f"spec.script.cues: the cue names {cue.trigger.human}, who is not a human of the scenario")
    mistakes += _criteria_mistakes(spec, humans, ids, robot_phrases)
    mistakes += unstated_reactions(spec)
    mistakes += [m for c in spec.criteria for m in contradictions(c, spec)]  # the verifier's rule S1
    if location is not None:
        mistakes += place_mistakes(spec, location)
        mistakes += _formula_mistakes(spec, humans, location)
    if not mistakes:  # the rest of the verifier's rule S1 (a criterion that says only "placeholder", ...)
        mistakes += [problem for c in spec.criteria if (problem := spec_problem(c, spec))]
    return mistakes


def _criteria_mistakes(spec: ScenarioSpec, humans: list[str], ids: list[str], robot_phrases: set[str]) -> list[str]:
    mistakes: list[str] = []
    cids = [c.id for c in spec.criteria]
    for dup in sorted({i for i in cids if cids.count(i) > 1}):
        mistakes.append(f"spec.criteria: the id {dup} is used twice; number the criteria c1, c2, ...")
    for c in spec.criteria:
        for name in _human_refs(c):
            if name not in humans:
                mistakes.append(f"criterion {c.id}: {name} is not a human of the scenario ({', '.join(humans)})")
        if c.encounter and c.encounter not in ids:
            mistakes.append(f"criterion {c.id}: encounter {c.encounter} is not in spec.encounters ({', '.join(ids)})")
        if c.kind in _PER_HUMAN and not c.human and not (c.kind == "meets" and len(c.humans) >= 2):
            mistakes.append(f"criterion {c.id}: kind {c.kind} names the `human` it is about"
                            + (" (or the `humans` of a group)" if c.kind == "meets" else ""))
        if c.kind in ("group_together", "stop_together") and len(c.humans) < 2:
            mistakes.append(f"criterion {c.id}: {c.kind} lists at least two `humans`")
        if c.kind == "robot_stops" and not c.encounter:
            mistakes.append(f"criterion {c.id}: robot_stops names the `encounter` at whose place the robot stands")
        if c.kind == "reacts_after_phrase":
            if not c.phrase:
                mistakes.append(f"criterion {c.id}: reacts_after_phrase names the robot's `phrase`")
            elif c.phrase not in robot_phrases:
                mistakes.append(f"criterion {c.id}: waits for the robot to say {c.phrase}, but no cue of "
                                f"spec.script.cues says it")
        if c.kind == "says" and c.human in humans and not any(p.reaction == "say" for _, p in spec.parts_of(c.human)):
            mistakes.append(f"criterion {c.id} asks {c.human} to say {c.phrase or 'something'}, but no encounter has "
                            f"{c.human} speak (a `says` criterion needs a part of {c.human} with the reaction say); "
                            f"give {c.human} that part, or drop the criterion")
        if c.kind == "stl" and not (c.formula or "").strip():
            mistakes.append(f"criterion {c.id}: kind stl needs its `formula`")
        if c.text.strip():
            mistakes += prose_mistakes(f"criterion {c.id}: text", c.text)
    return mistakes


def _about(c: Criterion, human: str) -> bool:
    """The criterion is about `human`: names it, or (stl) uses one of its signals."""
    if c.kind == "stl":
        return re.search(rf"\w_{human}\b|\b{human}_\w", c.formula or "") is not None
    return human in _human_refs(c)


def _stating_kinds(part: HumanPart) -> tuple[str, ...]:
    """The criterion kinds that state one part's reaction (facts.STATED_BY; after a robot phrase also
    reacts_after_phrase)."""
    return STATED_BY[part.reaction] + (("reacts_after_phrase",) if part.trigger == "robot_says" else ())


def unstated_reactions(spec: ScenarioSpec) -> list[str]:
    """Every person the text gives a reaction to the robot (a part on a robot_* trigger whose reaction a criterion
    kind states: facts.STATED_BY) has a criterion that states it; `meets` only says they came near, so an event of
    the text would go unchecked and no verifier could see it missing. An stl naming the person states it too, and
    a group member is stated by group_together with a member whose reaction is stated."""
    reacting: dict[str, list[tuple[Encounter, HumanPart]]] = {}
    stated: dict[str, bool] = {}
    for human in spec.humans():
        parts = [(e, p) for e, p in spec.parts_of(human) if p.reaction in STATED_BY and p.trigger.startswith("robot_")]
        if parts:
            kinds = {"stl", *(k for _, p in parts for k in _stating_kinds(p))}
            reacting[human] = parts
            stated[human] = any(c.kind in kinds and _about(c, human) for c in spec.criteria)
    mistakes = []
    for human, parts in reacting.items():
        if stated[human] or any(c.kind == "group_together" and human in c.humans and
                                any(stated.get(g) for g in c.humans if g != human) for c in spec.criteria):
            continue
        enc, part = parts[0]
        mistakes.append(f"encounter {enc.id}: {human} reacts to the robot ({part.reaction} on {part.trigger}), but no "
                        f"criterion states it (meets only says they came near, so the verifier could not see it "
                        f"missing); add a criterion of kind {' or '.join(_stating_kinds(part))} for {human} with "
                        f"encounter {enc.id}, its text saying what {human} does")
    return mistakes


def place_mistakes(spec: ScenarioSpec, location: Location) -> list[str]:
    """Encounters at places that cannot work on THIS map (location/inventory.py measures it)."""
    inventory = location.inventory
    mistakes: list[str] = []
    for enc in spec.encounters:
        reason = inventory.unworkable_reason(enc.place)
        if reason:
            mistakes.append(f"encounter {enc.id} happens at a {enc.place}, but {reason}; choose a place where the "
                            f"robot can meet and pass a person (see the PLACE INVENTORY)")
            continue
        cramped = inventory.no_room_to_step_aside(enc.place)
        for part in enc.humans if cramped else []:
            if part.reaction == "give_way":
                mistakes.append(f"encounter {enc.id}: {part.human} gives way at a {enc.place}, but {cramped}; let "
                                f"them give way at a place with room before it, or walk out ahead of the robot "
                                f"(walk_past), or wait (stop) before the narrow part")
    for human in spec.humans():  # TWO_ENCOUNTERS (facts.py): one person's encounters need a node each
        parts = spec.parts_of(human)
        for place in sorted({e.place.strip().upper() for e, _ in parts}):
            ids = [e.id for e, _ in parts if e.place.strip().upper() == place]
            nodes = [n.id for n in inventory.of_type(place)]
            if 1 <= len(nodes) < len(ids):
                mistakes.append(f"encounters {', '.join(ids)} of {human} are all at a {place}, but this map has only "
                                f"{len(nodes)} {place} node(s) ({', '.join(nodes)}): one person's encounters happen at "
                                f"different nodes; put one at another place, or make them one encounter")
    for c in spec.criteria:
        if c.kind != "hidden_until" or not c.human:
            continue
        found = spec.encounter(c.encounter) if c.encounter else next((e for e, _ in spec.parts_of(c.human)), None)
        if found is None:
            continue
        enc = found
        turns = inventory.blind_nodes(enc.place)
        if not turns:
            blind = sorted({f"{inventory.nodes[t.node].type} {t.node}" for t in inventory.blind_turns})
            where = f"blind turns of this map: {', '.join(blind[:8])}" if blind else "this map has no blind turn"
            mistakes.append(f"criterion {c.id} (hidden_until) needs a blind turn, but no {enc.place} node of this map "
                            f"hides one way from the other ({where}); move encounter {enc.id} or drop the criterion")
            continue
        distance = c.distance or HIDDEN_UNTIL_DEFAULT
        closest = turns[0].sight_m
        if distance < closest:  # refused only below the worst approach measured; the advice adds the margin
            mistakes.append(f"criterion {c.id} (hidden_until) asks that they see each other only within {distance:g} "
                            f"m, but at the {enc.place} nodes of this map they first see each other {closest:.1f} m "
                            f"apart or more; set its distance to at least {math.ceil(2 * (closest + BLIND_MARGIN)) / 2:g} "
                            f"(+{BLIND_MARGIN:g} m margin)")
    return mistakes


def _formula_mistakes(spec: ScenarioSpec, humans: list[str], location: Location) -> list[str]:
    """`stl` formulas that cannot be monitored on this run (the verifier's own check)."""
    places = [e.id for e in spec.encounters] + [f"node_{n}" for n in location.graph.nodes]
    return [f"criterion {c.id}: {problem}" for c in spec.criteria if c.kind == "stl" and (c.formula or "").strip()
            for problem in formula_problems(c.formula or "", humans, places)]
