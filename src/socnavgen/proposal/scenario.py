"""Stage 1: a textual scenario from the metadata (SocRATES Sec. III-B).

`--proposals N` asks N SEPARATE questions, each told the scenarios proposed so far and asked to
differ. Separate questions keep one reply format (and one grammar) for every backend, let each
proposal be checked and re-queried on its own, and a bad proposal never spoils the others, which a
single "list of N" reply would.
"""

from __future__ import annotations

import json

from socnavgen.bt.describe import capabilities_text
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.location import Location
from socnavgen.proposal.conversation import Outcome, Policy, Recorder, converse
from socnavgen.proposal.gbnf import Grammar, Lit, Ref, Symbol, text_rules
from socnavgen.proposal.replies import ScenarioReply, human_name
from socnavgen.proposal.templates import render, template_data
from socnavgen.run import ScenarioProposal, ScenarioRequest

STAGE = "scenario"
MAX_HUMANS = 8
MAX_TOKENS = 1024


def location_text(location: Location) -> str:
    schema = location.schema
    return render("scenario_location.md", description=location.config.description.strip(),
                  node_types=", ".join(schema.node_types), edge_types=", ".join(schema.edge_types))


def scenario_messages(request: ScenarioRequest, location: Location,
                      previous: list[ScenarioProposal] | None = None) -> list[ChatMessage]:
    """System (definition, capabilities, rules), the hand-written examples as earlier turns, the request."""
    messages = [ChatMessage(role="system", content=render("scenario_system.md", capabilities=capabilities_text()))]
    for example in template_data("scenario_examples.json"):
        messages.append(ChatMessage(role="user", content=render(
            "scenario_user.md", context=example["context"], task=example["task"], location=example["location"],
            rough=example["rough"], differ="")))
        messages.append(ChatMessage(role="assistant", content=json.dumps(example["reply"], ensure_ascii=False)))
    differ = ""
    if previous:
        listing = "\n".join(f"{i}. {p.scenario_description}" for i, p in enumerate(previous, 1))
        differ = render("scenario_differ.md", previous=listing) + "\n"
    messages.append(ChatMessage(role="user", content=render(
        "scenario_user.md", context=request.context, task=request.task, location=location_text(location),
        rough=request.rough or "None", differ=differ)))
    return messages


def check_scenario(reply: ScenarioReply) -> list[str]:
    mistakes: list[str] = []
    if not reply.scenario_description.strip():
        mistakes.append("scenario_description is empty")
    if not reply.expected_robot_behavior.strip():
        mistakes.append("expected_robot_behavior is empty")
    names = []
    for key, text in reply.human_behaviors.items():
        name = human_name(key)
        if name is None:
            mistakes.append(f"human_behaviors: '{key}' is not a human name; name the humans human1, human2, ...")
            continue
        names.append(name)
        if not str(text).strip():
            mistakes.append(f"human_behaviors: the behavior of {name} is empty")
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


def scenario_grammar() -> str:
    """The GBNF text passed as `grammar=` for stage 1."""
    return build_scenario_grammar().to_gbnf()


def build_scenario_grammar(max_humans: int = MAX_HUMANS, description_chars: int = 400,
                           behavior_chars: int = 240) -> Grammar:
    """Replies of 1..max_humans humans whose count, names and behaviors agree, all texts non-empty and
    bounded (a small model otherwise rambles until the token limit cuts the JSON)."""
    g = Grammar()
    per_human: list[list[Symbol]] = []
    for n in range(1, max_humans + 1):
        body: list[Symbol] = [Lit(f'{n}, "human_behaviors": {{')]
        for i in range(1, n + 1):
            body += [Lit(("" if i == 1 else ", ") + f'"human{i}": "'), Ref("short"), Lit('"')]
        per_human.append([*body, Lit("}")])
    g.add("root", [Lit('{"scenario_description": "'), Ref("long"), Lit('", "number_of_humans": '), Ref("humans"),
                   Lit(', "expected_robot_behavior": "'), Ref("short"), Lit('"}')])
    g.add("humans", *per_human)
    text_rules(g, "long", description_chars, non_empty=True)
    text_rules(g, "short", behavior_chars, non_empty=True)
    return g


def propose_scenarios(request: ScenarioRequest, location: Location, llm: LLM, recorder: Recorder,
                      policy: Policy) -> list[Outcome[ScenarioReply]]:
    """`request.proposals` checked proposals, each asked to differ from the ones before."""
    grammar = scenario_grammar() if getattr(llm, "supports_grammar", False) else None
    outcomes: list[Outcome[ScenarioReply]] = []
    count = max(1, request.proposals)
    for k in range(count):
        previous = [to_proposal(o.value) for o in outcomes]
        key = None if count == 1 else f"proposal{k + 1}"
        outcomes.append(converse(llm, scenario_messages(request, location, previous), ScenarioReply, check_scenario,
                                 stage=STAGE, key=key, recorder=recorder, policy=policy, grammar=grammar,
                                 max_tokens=MAX_TOKENS))
    return outcomes
