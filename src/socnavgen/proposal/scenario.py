"""Stage 1: a textual scenario from the metadata (SocRATES Sec. III-B).

`--proposals N` asks N SEPARATE questions, each told the scenarios proposed so far and asked to
differ. Separate questions keep one reply format (and one grammar) for every backend, let each
proposal be checked and re-queried on its own, and a bad proposal never spoils the others, which a
single "list of N" reply would.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import get_args

from socnavgen.bt.describe import capabilities_text
from socnavgen.bt.library import Target, nodes_for_reaction
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.location import Location
from socnavgen.location.inventory import inventory_text
from socnavgen.location.location import SCENE_GRAPH_IMAGE
from socnavgen.proposal.conversation import Outcome, Policy, Recorder, converse
from socnavgen.proposal.facts import (
    STATED_BY,
    cue_triggers_text,
    follows_distance_text,
    follows_human_text,
    physical_facts_text,
    robot_vocabulary_text,
    scenario_rules_text,
)
from socnavgen.proposal.fit import NOTHING, Cut, Note, examples_kept, fit_prompt
from socnavgen.proposal.gbnf import Grammar, Lit, Ref, Symbol, text_rules
from socnavgen.proposal.place_checks import (
    back_mistakes,
    place_events_text,
    robot_wait_mistakes,
    stay_mistakes,
)
from socnavgen.proposal.prose_checks import close_follow_mistakes, order_mistakes, person_order_mistakes
from socnavgen.proposal.replies import ScenarioReply, human_name
from socnavgen.proposal.spec_checks import (
    MIN_BEHAVIOR_WORDS,
    parse_spec,
    prose_mistakes,
    prose_spec_mistakes,
    spec_mistakes,
)
from socnavgen.proposal.stop_checks import stop_mistakes
from socnavgen.proposal.target_facts import detecting_nodes, missing_nodes
from socnavgen.proposal.templates import render, template_data
from socnavgen.run import ScenarioProposal, ScenarioRequest
from socnavgen.run.spec import CriterionKind, HumanTrigger, Reaction, ScenarioSpec
from socnavgen.verify.derive import SHOWS_ENCOUNTER

STAGE = "scenario"
MAX_HUMANS = 8
MAX_TOKENS = 2048
# Triggers / reactions a grammar-bound model may pick: those that need no further field.
_PLAIN_TRIGGERS = ("always", "robot_visible", "robot_near", "robot_blocking", "robot_moving")
_PLAIN_REACTIONS = ("walk_past", "stop", "look", "give_way", "follow", "block", "avoid", "wait_then_go")


INVENTORY_TRUST = ("The description above is the location author's words; where its widths differ from this inventory, "
                   "the inventory (measured) is right.")


def location_text(location: Location, inventory: bool = True, *, detail: bool = True) -> str:
    """The user's description of the location, its schema, and (unless `inventory` is False: the naive
    baseline) the place inventory measured on its map, with node positions (`detail` False: without the
    positions and the inventory's detail lists, fit.py)."""
    schema = location.schema
    return render("scenario_location.md", description=location.config.description.strip(),
                  node_types=", ".join(schema.node_types), edge_types=", ".join(schema.edge_types),
                  inventory=inventory_text(location, positions=detail, detail=detail) if inventory else "",
                  trust=f"\n{INVENTORY_TRUST}" if inventory and detail else "")


def spec_help_text(target: Target | None = None, *, signals: bool = True, robot: bool = True) -> str:
    """How to write the spec: its vocabulary (from run/spec.py and the library), how it plays out in the
    simulator, and the physical facts (`signals` False: the STL signals by name only; `robot` False: not what
    the robot does by itself; fit.py)."""
    return render("scenario_spec.md", vocabulary=robot_vocabulary_text(), facts=physical_facts_text(),
                  kinds=", ".join(k for k in get_args(CriterionKind) if robot or k not in STOP_KINDS),
                  stop_kinds=STOP_KINDS_TEXT if robot else "", target=target_text(target),
                  rules=scenario_rules_text(target, signals, robot) + place_events_text(signals),
                  cue_triggers=cue_triggers_text(robot),
                  follow_distance=follows_distance_text(), follows_human=follows_human_text(robot))


# Kinds told behind fit.py's robot cut (the small model's stage-1 prompt is full); the stop check of stop_checks.py
# names them in its finding when a text states such a stop.
STOP_KINDS = ("robot_stops", "stop_together")
STOP_KINDS_TEXT = ("; robot_stops: the robot stands `seconds` within `distance` (else the encounter's `within`) of the "
                   "`encounter`'s node (slowing down is no stop: size `within` for where its cue stops it); "
                   "stop_together: the `humans`, having walked, stand still at once within `distance` of each other "
                   "(people who stop to greet each other)")


def target_text(target: Target | None) -> str:
    if target is None:
        return ""
    triggers = [t for t in get_args(HumanTrigger) if t == "always" or detecting_nodes(t, target)[0]]
    reactions = [r for r in get_args(Reaction) if nodes_for_reaction(r, target)]
    lacks = missing_nodes(target)
    lacking = f" {target} lacks the nodes {', '.join(lacks)}." if lacks else ""
    return (f"The scenario will be exported to {target}: use only the triggers {', '.join(triggers)} and the "
            f"reactions {', '.join(reactions)} (the others cannot run there).{lacking}")


def scenario_messages(request: ScenarioRequest, location: Location,
                      previous: list[ScenarioProposal] | None = None, *, left_out: Cut = NOTHING,
                      images: bool = False) -> list[ChatMessage]:
    """System (definition, capabilities, rules), the hand-written examples as earlier turns, the request
    (with the annotated map image when `images`). `left_out`: parts fit.py leaves out for a small context."""
    target = request.target
    messages = [ChatMessage(role="system", content=render(
        "scenario_system.md", capabilities=capabilities_text(target or "socrates"),
        spec_help=spec_help_text(target, signals="signals" not in left_out, robot="robot" not in left_out)))]
    examples = examples_kept(left_out, template_data("scenario_examples.json"))
    for example in examples:
        messages.append(ChatMessage(role="user", content=render(
            "scenario_user.md", context=example["context"], task=example["task"], location=example["location"],
            rough=example["rough"], differ="")))
        messages.append(ChatMessage(role="assistant", content=json.dumps(example["reply"], ensure_ascii=False)))
    differ = ""
    if previous:
        listing = "\n".join(f"{i}. {p.scenario_description}" for i, p in enumerate(previous, 1))
        differ = render("scenario_differ.md", previous=listing) + "\n"
    image = location.root / SCENE_GRAPH_IMAGE
    picture = [image] if images and image.is_file() else []
    place = location_text(location, detail="inventory" not in left_out)
    if picture:
        place += ("\nThe attached image is the map with the scene graph drawn on it (nodes labelled with their ids): "
                  "use it to tell which place the request means (north is up).")
    messages.append(ChatMessage(role="user", content=render(
        "scenario_user.md", context=request.context, task=request.task, location=place,
        rough=request.rough or "None", differ=differ), images=picture))
    return messages


def fitted_scenario_messages(request: ScenarioRequest, location: Location, llm: LLM,
                             previous: list[ScenarioProposal] | None = None, tail: list[ChatMessage] | None = None,
                             note: Note | None = None) -> list[ChatMessage]:
    """The stage-1 prompt (then `tail`, e.g. the earlier answer and a re-ask), shortened to fit the model's
    context (fit.py); the map image goes to models that take images unless the request says --no-image."""
    images = request.use_image and bool(getattr(llm, "supports_images", False))
    return fit_prompt(llm, lambda cut: [*scenario_messages(request, location, previous, left_out=cut, images=images),
                                        *(tail or [])], reply_tokens=MAX_TOKENS, stage=STAGE, note=note)


def scenario_checker(location: Location | None, target: Target | None = None,
                     require_spec: bool = True) -> Callable[[ScenarioReply], list[str]]:
    """The stage-1 check: the prose (no placeholders, echoes, empty behaviors) and the spec."""
    node_types = list(location.schema.node_types) if location is not None else None
    nodes = {str(n) for n in location.graph.nodes} if location is not None else set()

    def check(reply: ScenarioReply) -> list[str]:
        mistakes = check_scenario(reply)
        if reply.spec is None and not require_spec:
            return mistakes
        spec, invalid = parse_spec(reply.spec)
        mistakes += invalid
        if spec is not None:
            humans = [n for k in reply.human_behaviors if (n := human_name(k))]
            mistakes += spec_mistakes(spec, humans, node_types, target, location)
            mistakes += prose_spec_mistakes(reply.human_behaviors, spec)
            mistakes += close_follow_mistakes(spec, reply.human_behaviors)
            mistakes += order_mistakes(reply.scenario_description, reply.human_behaviors, spec)
            mistakes += person_order_mistakes(reply.scenario_description, reply.human_behaviors, spec)
            mistakes += stop_mistakes(reply.scenario_description, reply.human_behaviors, spec)
            mistakes += robot_wait_mistakes(reply.scenario_description, reply.expected_robot_behavior,
                                            reply.human_behaviors, spec, nodes)
            mistakes += stay_mistakes(reply.scenario_description, reply.human_behaviors, spec)
            mistakes += back_mistakes(reply.scenario_description, reply.human_behaviors, spec)
        return mistakes
    return check


def to_spec(reply: ScenarioReply) -> ScenarioSpec | None:
    """The spec of a CHECKED reply (None when the reply had none: the naive baseline)."""
    return parse_spec(reply.spec)[0] if reply.spec is not None else None


def check_scenario(reply: ScenarioReply) -> list[str]:
    """The prose part of a stage-1 reply."""
    mistakes: list[str] = []
    mistakes += prose_mistakes("scenario_description", reply.scenario_description, min_words=MIN_BEHAVIOR_WORDS)
    mistakes += prose_mistakes("expected_robot_behavior", reply.expected_robot_behavior, min_words=MIN_BEHAVIOR_WORDS)
    names = []
    for key, text in reply.human_behaviors.items():
        name = human_name(key)
        if name is None:
            mistakes.append(f"human_behaviors: '{key}' is not a human name; name the humans human1, human2, ...")
            continue
        names.append(name)
        mistakes += prose_mistakes(f"human_behaviors: the behavior of {name}", str(text), min_words=MIN_BEHAVIOR_WORDS)
    n = reply.number_of_humans
    if not 1 <= n <= MAX_HUMANS:
        mistakes.append(f"number_of_humans is {n}; a scenario has 1 to {MAX_HUMANS} humans")
    if n != len(reply.human_behaviors):
        mistakes.append(f"number_of_humans is {n} but human_behaviors describes {len(reply.human_behaviors)} "
                        f"human(s); give exactly one behavior per human")
    expected = [f"human{i}" for i in range(1, len(names) + 1)]
    if names and sorted(names, key=lambda s: int(s[5:])) != expected:
        mistakes.append(f"human_behaviors: name the humans {', '.join(expected)} (got {', '.join(names)})")
    return mistakes


def to_proposal(reply: ScenarioReply) -> ScenarioProposal:
    behaviors = {human_name(k) or k: v.strip() for k, v in reply.human_behaviors.items()}
    ordered = dict(sorted(behaviors.items(), key=lambda kv: int(kv[0][5:])))
    return ScenarioProposal(scenario_description=reply.scenario_description.strip(),
                            number_of_humans=reply.number_of_humans, human_behaviors=ordered,
                            expected_robot_behavior=reply.expected_robot_behavior.strip())


def scenario_grammar(node_types: list[str] | None = None, target: Target | None = None,
                     tight: set[str] | None = None) -> str:
    """The GBNF text passed as `grammar=` for stage 1."""
    return build_scenario_grammar(node_types=node_types, target=target, tight=tight).to_gbnf()


def build_scenario_grammar(max_humans: int = MAX_HUMANS, description_chars: int = 400,
                           behavior_chars: int = 240, node_types: list[str] | None = None,
                           target: Target | None = None, tight: set[str] | None = None) -> Grammar:
    """Replies of 1..max_humans humans whose count, names and behaviors agree, all texts non-empty and
    bounded (a small model otherwise rambles until the token limit cuts the JSON), with a small spec:
    one encounter at a node type of the location, each human with a trigger and a reaction that need no
    further field (and that `target` can run; no give_way at the `tight` places, where nobody can step
    aside), all humans with one reaction, and per human a `meets` criterion and one of the kind that states
    the reaction (facts.STATED_BY: stage 1's check asks it; a kind that shows the encounter replaces meets)."""
    g = Grammar()
    places = node_types or ["PLACE"]
    reactions = [r for r in _PLAIN_REACTIONS if nodes_for_reaction(r, target or "socrates")]
    per_human: list[list[Symbol]] = []
    for n in range(1, max_humans + 1):
        body: list[Symbol] = [Lit(f'{n}, "human_behaviors": {{')]
        for i in range(1, n + 1):
            body += [Lit(("" if i == 1 else ", ") + f'"human{i}": "'), Ref("short"), Lit('"')]
        body += [Lit('}, "expected_robot_behavior": "'), Ref("short"),
                 Lit('", "spec": {"script": {"route": "'), Ref("route"),
                 Lit('", "cues": []}, "encounters": [{"id": "e1", "place": "'), Ref(f"encounter{n}")]
        per_human.append(body)
        alternatives = []
        for place in places:
            for reaction in reactions:
                if reaction == "give_way" and place in (tight or set()):
                    continue
                alt: list[Symbol] = [Lit(place), Lit('", "humans": [')]
                for i in range(1, n + 1):
                    alt += [Lit(("" if i == 1 else ", ") + f'{{"human": "human{i}", "trigger": "'), Ref("trigger"),
                            Lit(f'", "reaction": "{reaction}"}}')]
                alternatives.append([*alt, Lit(f']}}], "criteria": [{_grammar_criteria(n, reaction)}]}}}}')])
        g.add(f"encounter{n}", *alternatives)
    g.add("root", [Lit('{"scenario_description": "'), Ref("long"), Lit('", "number_of_humans": '), Ref("humans")])
    g.add("humans", *per_human)
    text_rules(g, "long", description_chars, non_empty=True, prose=True)
    text_rules(g, "short", behavior_chars, non_empty=True, prose=True)
    text_rules(g, "route", 120, non_empty=True, prose=True)
    triggers = [t for t in _PLAIN_TRIGGERS if t == "always" or detecting_nodes(t, target or "socrates")[0]]
    g.add("trigger", *[[Lit(t)] for t in triggers])
    return g


def _grammar_criteria(n: int, reaction: str) -> str:
    """The grammar's criteria for n humans with one reaction: meets, and the kind that states the reaction."""
    stating = STATED_BY.get(reaction, ("",))[0]
    kinds = [stating] if stating in SHOWS_ENCOUNTER else ["meets", *([stating] if stating else [])]
    rows = [(k, i) for k in kinds for i in range(1, n + 1)]
    return ", ".join(f'{{"id": "c{j}", "kind": "{k}", "human": "human{i}", "encounter": "e1"}}'
                     for j, (k, i) in enumerate(rows, start=1))


def propose_scenarios(request: ScenarioRequest, location: Location, llm: LLM, recorder: Recorder,
                      policy: Policy) -> list[Outcome[ScenarioReply]]:
    """`request.proposals` checked proposals, each asked to differ from the ones before."""
    grammar = stage_grammar(llm, location, request.target)
    check = scenario_checker(location, request.target)
    outcomes: list[Outcome[ScenarioReply]] = []
    count = max(1, request.proposals)
    for k in range(count):
        previous = [to_proposal(o.value) for o in outcomes]
        key = None if count == 1 else f"proposal{k + 1}"
        messages = fitted_scenario_messages(request, location, llm, previous, note=recorder.note)
        outcomes.append(converse(llm, messages, ScenarioReply, check,
                                 stage=STAGE, key=key, recorder=recorder, policy=policy, grammar=grammar,
                                 max_tokens=MAX_TOKENS))
    return outcomes


def stage_grammar(llm: LLM, location: Location, target: Target | None) -> str | None:
    if not getattr(llm, "supports_grammar", False):
        return None
    places = workable_places(location)
    tight = {p for p in places if location.inventory.no_room_to_step_aside(p)}
    return scenario_grammar(places, target, tight)


def workable_places(location: Location) -> list[str]:
    """The node types where an encounter can work on this map (the place inventory), in schema order."""
    return [t for t in location.schema.node_types if location.inventory.unworkable_reason(t) is None]
