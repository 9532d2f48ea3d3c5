"""Stage 2: robot and human paths on the scene graph (SocRATES Sec. III-C).

The prompt holds the scene graph JSON, the annotated map image (for models that take images), the
tutorial generated for this map, example scenarios whose paths are computed on this map (so the
examples are valid here, not on some other building), and the scenario. Every answer is checked by
path_checks; in-process models also get a grammar that only admits valid answers.
"""

from __future__ import annotations

import json
import random
import re
from pathlib import Path

import networkx as nx

from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.location import Location
from socnavgen.location.inventory import inventory_text
from socnavgen.location.location import SCENE_GRAPH_IMAGE
from socnavgen.location.placement import (
    Walker,
    clear_starts,
    node_distance,
    shown_position,
    start_problems,
    start_rule_text,
)
from socnavgen.proposal.conversation import Outcome, Policy, Recorder, converse
from socnavgen.proposal.facts import (
    TWO_ENCOUNTERS,
    approach_room,
    follower_turn_text,
    groups_text,
    pacing_text,
    physical_facts_text,
    stop_evidence_text,
)
from socnavgen.proposal.fit import NOTHING, Cut, Note, examples_kept, fit_prompt
from socnavgen.proposal.path_checks import check_paths, doorway_goal
from socnavgen.proposal.path_grammar import paths_grammar
from socnavgen.proposal.replies import PathsReply
from socnavgen.proposal.templates import render
from socnavgen.proposal.tutorial import generate_tutorial, tutorial_text
from socnavgen.run import PathPlan, ScenarioProposal, ScenarioRequest
from socnavgen.run.spec import ScenarioSpec
from socnavgen.verify.thresholds import APPROACH

STAGE = "paths"
MAX_TOKENS = 1536
POINT_RULE = ("6. The interaction point of a human is the node where pacing brings that human together with the "
              "robot: it must be on that human's path AND on the robot's path.")
POINT_RULE_ENCOUNTERS = ("6. The interaction point of a human is the node of that human's FIRST encounter (lowest "
                         "order; its node in encounter_nodes; a null is read as that node): pacing brings the human there together with the robot. "
                         "It must be on that human's path AND on the robot's path. " + TWO_ENCOUNTERS + ": each later "
                         "encounter of a human on a node of its own.")


def encounter_rule() -> str:
    """Rule 8 of a scenario with encounters (the approach distance from path_checks, the one check of it)."""
    return ("8. encounter_nodes: for each encounter of the scenario, the node where it happens. It must be of the "
            "encounter's kind of place (node type), on the robot's path and on the path of every human of that "
            "encounter (rule 6 says which one is a human's interaction point). Where someone gives way, the node "
            "needs room to step aside (the inventory lists where there is none). A person waiting at an encounter's "
            f"node must be at least {approach_room():g} m (between xy_m) from the robot's start: a meeting counts "
            f"only after the robot and the person came {APPROACH:g} m closer to each other (more when a meets "
            "criterion's distance is larger: that distance + "
            f"{APPROACH:g} m). {stop_evidence_text()} So a person whose stop is checked starts at a node before "
            "the encounter's node and walks in.")


def scene_graph_text(location: Location) -> str:
    """The node-link JSON, one node or edge per line: complete, but a fraction of the indented size.
    Each node has its position in metres beside its pixel `pos`; each edge its free width and whether
    one standing person closes it to the robot."""
    sg = location.scene_graph

    def node(n) -> str:  # noqa: ANN001 - a scene-graph node
        return json.dumps({"id": n.id, "type": n.type, "pos": [round(n.pos[0]), round(n.pos[1])],
                           "xy_m": list(shown_position(location, n.id))})

    def link(e) -> str:  # noqa: ANN001 - a scene-graph edge
        passage = location.inventory.passage(e.source, e.target)
        item = {"source": e.source, "target": e.target, "type": e.type}
        if passage is not None:
            item["width_m"] = passage.width_m
            item["narrow"] = passage.narrow
        return json.dumps(item)

    nodes = ",\n".join("  " + node(n) for n in sg.nodes)
    links = ",\n".join("  " + link(e) for e in sg.links)
    return '{"directed": false, "nodes": [\n' + nodes + '\n], "links": [\n' + links + "\n]}"


def encounters_text(spec: ScenarioSpec | None) -> str:
    """The spec's encounters as stage 2 must ground them."""
    if spec is None or not spec.encounters:
        return "The scenario names no encounters."
    lines = ["Encounters of the scenario (ground each on ONE node in encounter_nodes):"]
    for enc in sorted(spec.encounters, key=lambda e: e.order):
        parts = "; ".join(f"{p.human}: {p.reaction} on {p.trigger}" for p in enc.humans)
        lines.append(f"- {enc.id} (order {enc.order}) at a {enc.place} node, with {parts}. Robot: {enc.robot_does}")
    return "\n".join(lines)


def reply_json(plan_or_reply: dict) -> str:
    return json.dumps(plan_or_reply, ensure_ascii=False)


def answer_dict(reasoning: str, robot: list[str], humans: dict[str, tuple[list[str], int, str | None]],
                encounter_nodes: dict[str, str] | None = None) -> dict:
    """A stage-2 answer in the order the grammar uses: reasoning, interaction points, trajectories, groups
    (then the encounters' nodes when the scenario has a spec)."""
    answer = {"reasoning": reasoning,
              "interaction_points": {h: v[2] for h, v in humans.items()},
              "trajectories": {"robot": robot, **{h: v[0] for h, v in humans.items()}},
              "group_ids": {h: v[1] for h, v in humans.items()}}
    if encounter_nodes:
        answer["encounter_nodes"] = dict(encounter_nodes)
    return answer


def plan_to_answer(plan: PathPlan, spec: ScenarioSpec | None = None) -> dict:
    nodes = {e.id: e.node for e in spec.encounters if e.node} if spec is not None else None
    return answer_dict(plan.reasoning, plan.robot,
                       {h.name: (h.path, h.group_id, h.interaction_point) for h in plan.humans}, nodes)


def format_line(humans: list[str], spec: ScenarioSpec | None = None) -> str:
    answer = {"reasoning": "<short reasoning>",
              "interaction_points": {h: "<node id>" for h in humans},
              "trajectories": {"robot": ["<node id>", "..."], **{h: ["<node id>", "..."] for h in humans}},
              "group_ids": {h: -1 for h in humans}}  # an integer: -1 alone, or the group's id
    if spec is not None and spec.encounters:
        answer["encounter_nodes"] = {e.id: "<node id>" for e in spec.encounters}
    return reply_json(answer)


def map_examples(graph: nx.Graph, seed: int = 0, location: Location | None = None) -> list[tuple[str, list[str], dict]]:
    """Two example scenarios with paths computed on THIS graph: a head-on encounter in a passage and a
    group of two standing on the robot's way. Returns (scenario text, humans, answer). With the location,
    only placements where everybody starts clear of everybody else (location/placement.py)."""
    rng = random.Random(seed + 1)
    examples: list[tuple[str, list[str], dict]] = []

    def clear(robot: list[str], walkers: list[Walker]) -> bool:  # the examples keep stage 2's own rules
        return not doorway_goal(graph, robot) and (location is None or not start_problems(location, robot, walkers))

    routes = [p for a, targets in sorted(nx.all_pairs_shortest_path(graph)) for b, p in sorted(targets.items())
              if a < b and len(p) >= 3]
    if not routes:
        return examples
    longest = max(len(p) for p in routes)
    long_routes = [p for p in routes if len(p) >= min(longest, 4)]
    route = rng.choice([p for p in long_routes if clear(p, [Walker("human1", p[::-1])])] or long_routes)
    mid = route[len(route) // 2]
    kind = graph.nodes[mid].get("type", "node")
    examples.append((
        f"The robot carries a box from {route[0]} to {route[-1]}. A worker walks the same way in the opposite "
        f"direction, from {route[-1]} to {route[0]}, and they meet at {mid} ({kind}). human1: the worker, walks "
        f"normally and steps aside for the robot.",
        ["human1"],
        answer_dict(f"The shortest route {', '.join(route)} joins the two ends; the worker walks it backwards, "
                    f"so both pass {mid}, where they meet. One human, no group: -1.",
                    route, {"human1": (list(reversed(route)), -1, mid)})))
    shorts = [p for p in routes if len(p) == 3] or routes
    short = rng.choice([p for p in shorts if clear(p, [Walker("human1", [p[1]], 1), Walker("human2", [p[1]], 1)])]
                       or shorts)
    spot = short[1]
    kind = graph.nodes[spot].get("type", "node")
    examples.append((
        f"The robot goes from {short[0]} to {short[-1]}. Two workers stand talking together at {spot} ({kind}), "
        f"in the robot's way, and let it pass only when it says EXCUSE ME. human1 and human2: the two workers.",
        ["human1", "human2"],
        answer_dict(f"The route {', '.join(short)} passes {spot}; the two workers stand there (a path of one "
                    f"node) as one group, so they share group id 1, and meet the robot at {spot}.",
                    list(short), {"human1": ([spot], 1, spot), "human2": ([spot], 1, spot)})))
    return examples


def scenario_text(scenario: ScenarioProposal) -> str:
    lines = [f"Scenario: {scenario.scenario_description}"]
    lines += [f"{name}: {text}" for name, text in scenario.human_behaviors.items()]
    lines.append(f"Expected robot behavior: {scenario.expected_robot_behavior}")
    return "\n".join(lines)


def paths_messages(location: Location, scenario: ScenarioProposal, *, seed: int = 0,
                   images: bool = True, spec: ScenarioSpec | None = None, left_out: Cut = NOTHING) -> list[ChatMessage]:
    """The stage-2 prompt; `left_out`: parts fit.py leaves out for a small context (examples, inventory
    detail, the tutorial)."""
    graph = location.graph
    humans = list(scenario.human_behaviors)
    shown = examples_kept(left_out, map_examples(graph, seed, location))
    examples = "EXAMPLES (scenarios on this map, with correct answers):\n" + "\n\n".join(
        render("paths_example.md", scenario=text, humans=", ".join(names), answer=reply_json(ans))
        for text, names, ans in shown) if shown else ""
    tutorial = "" if "tutorials" in left_out else "SCENE GRAPH TUTORIAL (questions about this map, with their " \
        "correct answers):\n" + tutorial_text(generate_tutorial(graph, seed))
    user = render("paths_user.md", scene_graph=scene_graph_text(location),
                  node_types=", ".join(location.schema.node_types), edge_types=", ".join(location.schema.edge_types),
                  tutorial=tutorial, examples=examples,
                  scenario=scenario_text(scenario), humans=", ".join(humans), format=format_line(humans, spec),
                  facts="\n".join([physical_facts_text(scene_graph=True), pacing_text(), groups_text(),
                                   follower_turn_text()]),
                  encounters=encounters_text(spec),
                  inventory=inventory_text(location, positions=False, detail="inventory" not in left_out),
                  start_rule=start_rule_text(),
                  point_rule=POINT_RULE_ENCOUNTERS if spec is not None and spec.encounters else POINT_RULE,
                  encounter_rule=encounter_rule() if spec is not None and spec.encounters else "")
    picture: list[Path] = []
    image = location.root / SCENE_GRAPH_IMAGE
    if images and image.is_file():
        picture.append(image)
    return [ChatMessage(role="system", content=render("paths_system.md")),
            ChatMessage(role="user", content=re.sub(r"\n{3,}", "\n\n", user), images=picture)]


def fitted_paths_messages(location: Location, scenario: ScenarioProposal, llm: LLM, request: ScenarioRequest,
                          spec: ScenarioSpec | None = None, tail: list[ChatMessage] | None = None,
                          note: Note | None = None) -> list[ChatMessage]:
    """The stage-2 prompt (then `tail`) shortened to fit the model's context (fit.py)."""
    images = request.use_image and bool(getattr(llm, "supports_images", False))
    return fit_prompt(llm, lambda cut: [*paths_messages(location, scenario, seed=request.seed, images=images, spec=spec,
                                                        left_out=cut), *(tail or [])],
                      reply_tokens=MAX_TOKENS, stage=STAGE, note=note)


def too_near(location: Location, spec: ScenarioSpec | None) -> frozenset[tuple[str, str]]:
    """(robot start, node) pairs nearer than approach_room(): a person waiting at such a node is met without an
    approach (path_checks refuses it; the grammar of in-process models leaves it out)."""
    if spec is None or not spec.encounters:
        return frozenset()
    room, nodes = approach_room(), list(location.inventory.nodes)
    return frozenset((a, b) for a in nodes for b in nodes if node_distance(location, a, b) < room)


def plan_paths(messages: list[ChatMessage], location: Location, scenario: ScenarioProposal, llm: LLM,
               recorder: Recorder, policy: Policy, spec: ScenarioSpec | None = None) -> Outcome[PathsReply]:
    humans = list(scenario.human_behaviors)
    graph = location.graph
    cramped = {n for n, facts in location.inventory.nodes.items() if not facts.turnable}
    grammar = paths_grammar(graph, humans, spec, cramped, clear_starts(location), too_near(location, spec)) \
        if getattr(llm, "supports_grammar", False) else None
    return converse(llm, messages, PathsReply, lambda reply: check_paths(reply, graph, humans, spec, location,
                                                                              scenario.human_behaviors),
                    stage=STAGE, key=None, recorder=recorder, policy=policy, grammar=grammar, max_tokens=MAX_TOKENS)
