"""Prompts fit the model's context (proposal/fit.py): a backend that knows its context gets prompts that
leave out, in the documented order, what a small model needs least, and never the request, the rules or
the answer format; a prompt that cannot fit is one clear error. Fake small contexts, no model."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from gen_helpers import request_for, run_replay

from socnavgen.errors import LLMError
from socnavgen.llm.base import ChatMessage
from socnavgen.llm.budget import SAFETY_TOKENS, estimate_tokens
from socnavgen.location import load_location
from socnavgen.proposal import behaviors, paths, scenario
from socnavgen.proposal.behaviors import examples_text
from socnavgen.proposal.facts import ORDER_EXAMPLE
from socnavgen.proposal.fit import CUTS, fit_history
from socnavgen.run import HumanPlan, PathPlan, ScenarioProposal
from socnavgen.run.spec import ScenarioSpec
from socnavgen.verify.signals import SIGNAL_KINDS

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "examples" / "locations" / "warehouse"
REPLAY = ROOT / "tests" / "fixtures" / "replay" / "warehouse_blind_corner.yaml"


class SmallModel:
    """Just enough of an LLM for fitting: a context size and a token count (the cautious estimate)."""

    supports_images = False
    supports_grammar = False

    def __init__(self, context: int) -> None:
        self.context_tokens = context

    def count_tokens(self, messages: list[ChatMessage]) -> int:
        return estimate_tokens(messages)


@pytest.fixture(scope="module")
def warehouse():
    return load_location(WAREHOUSE)


REQUEST = request_for(WAREHOUSE, context="Delivery robot in a small warehouse; CONTEXT-MARK",
                      task="Carry a box; TASK-MARK", rough="The robot meets a worker; ROUGH-MARK")
EXAMPLE_CONTEXT = "care home for elderly residents"  # the first hand-written example's context
SECOND_EXAMPLE = "guides visitors in a busy hospital"  # the second one's


def _full(warehouse) -> int:  # noqa: ANN001
    return estimate_tokens(scenario.scenario_messages(REQUEST, warehouse))


def _stage1(warehouse, context: int) -> str:  # noqa: ANN001
    messages = scenario.fitted_scenario_messages(REQUEST, warehouse, SmallModel(context))
    assert estimate_tokens(messages) <= context - scenario.MAX_TOKENS - SAFETY_TOKENS
    return "\n".join(m.content for m in messages)


def _kept(text: str) -> None:
    """What is never left out: the request, the rules, the facts and the answer format."""
    for mark in ("CONTEXT-MARK", "TASK-MARK", "ROUGH-MARK", "Rules:", "PHYSICAL FACTS", "HOW THE SPEC PLAYS OUT",
                 "Answer with exactly this JSON object", "PLACE INVENTORY", "- BLIND CORNER: 54 (",
                 "A criterion of kind stl"):
        assert mark in text, mark


def test_a_model_without_a_known_context_gets_the_whole_prompt(warehouse):
    class Server:  # a remote backend: no context_tokens
        supports_images = False

    whole = scenario.fitted_scenario_messages(REQUEST, warehouse, Server())
    assert [m.content for m in whole] == [m.content for m in scenario.scenario_messages(REQUEST, warehouse)]


def test_stage1_leaves_out_what_a_small_model_needs_least_in_the_documented_order(warehouse):
    """Each context one token too small for the prompt at the previous level gets the next level: more
    examples, then the signal meanings, then the inventory detail, then what the robot does by itself, then the
    last example."""
    def size(k: int) -> int:
        return estimate_tokens(scenario.scenario_messages(REQUEST, warehouse, left_out=frozenset(CUTS[:k])))

    whole = _stage1(warehouse, size(0) + scenario.MAX_TOKENS + SAFETY_TOKENS)
    assert EXAMPLE_CONTEXT in whole and SECOND_EXAMPLE in whole
    assert SIGNAL_KINDS[0].meaning in whole and "Narrow passages" in whole
    levels = [_stage1(warehouse, size(k) + scenario.MAX_TOKENS + SAFETY_TOKENS - 1) for k in range(5)]
    for text in levels:
        _kept(text)
        assert SECOND_EXAMPLE not in text
        assert "no cue makes it back off, pull over or follow someone" in text  # what the script cannot do stays
    one_example, no_signals, no_detail, no_robot, no_example = levels
    robot_detail = "makes way for someone who must get past it"
    assert robot_detail in no_detail and EXAMPLE_CONTEXT in no_robot and robot_detail not in no_robot
    assert EXAMPLE_CONTEXT in one_example and SIGNAL_KINDS[0].meaning in one_example  # the first example stays
    # the signals cut leaves out the whole stl help (its syntax, example and signals); the kind stays named
    assert "eventually[0:60]" in one_example and "eventually[0:60]" not in no_signals
    assert SIGNAL_KINDS[0].meaning not in no_signals and SIGNAL_KINDS[0].shown not in no_signals
    # with it the rule that the criteria state the text's events and its worked example (the check stays)
    assert "STATE THE EVENTS OF YOUR TEXT" in one_example and ORDER_EXAMPLE in one_example
    assert "STATE THE EVENTS OF YOUR TEXT" not in no_signals and ORDER_EXAMPLE not in no_signals
    assert "Narrow passages" in no_signals and EXAMPLE_CONTEXT in no_signals
    assert "54 (at " in no_signals and "seen within" in no_signals and scenario.INVENTORY_TRUST in no_signals
    assert "Narrow passages" not in no_detail and "Blind turns (" not in no_detail and EXAMPLE_CONTEXT in no_detail
    # the inventory cut also leaves out stage 1's node positions, how near each blind turn is seen and the note
    # that the inventory beats the description; each node with its ways and free width stays
    assert "54 (at " not in no_detail and "seen within" not in no_detail and "54 (2 ways, 1.4 m free, blind turn)" \
        in no_detail and scenario.INVENTORY_TRUST not in no_detail
    assert "No room to step aside (give_way) at:" in no_detail  # where nobody can give way stays
    assert EXAMPLE_CONTEXT not in no_example


def test_a_prompt_that_cannot_fit_is_one_clear_error(warehouse):
    with pytest.raises(LLMError) as caught:
        scenario.fitted_scenario_messages(REQUEST, warehouse, SmallModel(scenario.MAX_TOKENS + 500))
    message = caught.value.render()
    assert "stage scenario: the prompt takes" in message and "even without more_examples, signals, inventory, " \
        "robot, examples, tutorials" in message
    assert "SOCNAVGEN_GGUF_N_CTX" in message


PROPOSAL = ScenarioProposal(scenario_description="The robot meets a worker at a blind corner.", number_of_humans=1,
                            human_behaviors={"human1": "Walks to the entrance and stops when the robot is close."},
                            expected_robot_behavior="Slow down at the corner.")
SPEC = ScenarioSpec.model_validate({
    "encounters": [{"id": "e1", "place": "BLIND CORNER", "node": "f7", "humans": [
        {"human": "human1", "trigger": "robot_blocking", "reaction": "stop", "distance": 1.5}]}],
    "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"}]})
PLAN = PathPlan(robot=["up", "co", "54", "f7", "6r"], humans=[HumanPlan(name="human1", path=["6r", "f7", "54"],
                                                                         interaction_point="f7")])


def test_stage2_and_stage3_shorten_in_the_same_order(warehouse):
    full = estimate_tokens(paths.paths_messages(warehouse, PROPOSAL, spec=SPEC, images=False))
    model = SmallModel(full + paths.MAX_TOKENS + SAFETY_TOKENS - 1)
    text = "\n".join(m.content for m in paths.fitted_paths_messages(warehouse, PROPOSAL, model, REQUEST, SPEC))
    assert text.count('"reasoning": "') == 1 + 1 and "SCENE GRAPH TUTORIAL" in text  # 1 example + the format
    assert "Rules:" in text and "encounter_nodes" in text and PROPOSAL.scenario_description in text

    full = estimate_tokens(behaviors.behavior_messages("human1", PROPOSAL, PLAN, SPEC))
    model = SmallModel(full + behaviors.MAX_TOKENS + SAFETY_TOKENS - 1)
    text = "\n".join(m.content for m in behaviors.fitted_behavior_messages("human1", PROPOSAL, PLAN, model, SPEC))
    assert "EXAMPLES" in text and "Q: How does a human" in text  # the first example stays, and the tutorial
    assert len(text.split("EXAMPLES")[1].split("Behavior:")) < len(examples_text().split("Behavior:"))
    assert "NODE LIBRARY" in text and "Your tree must" in text and "Answer with exactly this JSON object" in text
    bare = "\n".join(m.content for m in behaviors.behavior_messages("human1", PROPOSAL, PLAN, SPEC,
                                                                    left_out=frozenset(CUTS)))
    assert "Q: How does a human" not in bare and "Syntax rules:" in bare


def test_a_growing_conversation_is_trimmed_to_the_first_prompt_and_the_last_correction():
    first = [ChatMessage(role="system", content="s" * 300), ChatMessage(role="user", content="u" * 300)]
    exchange = [ChatMessage(role="assistant", content="a" * 600), ChatMessage(role="user", content="fix A")]
    latest = [ChatMessage(role="assistant", content="b" * 600), ChatMessage(role="user", content="fix B")]
    history = [*first, *exchange, *latest]
    assert fit_history(SmallModel(10_000), history, 2, 100) == history
    room = estimate_tokens([*first, *latest]) + 100 + SAFETY_TOKENS
    assert fit_history(SmallModel(room), history, 2, 100) == [*first, *latest]
    room = estimate_tokens([*first, latest[1]]) + 100 + SAFETY_TOKENS
    assert fit_history(SmallModel(room), history, 2, 100) == [*first, latest[1]]  # the mistakes stay
    assert fit_history(SmallModel(estimate_tokens(first) + 100 + SAFETY_TOKENS), history, 2, 100) == first


def test_a_run_on_a_small_context_sends_fitted_prompts_and_says_so(tmp_path, monkeypatch):
    """The whole pipeline (replay answers) on a backend that says its context is small."""
    from socnavgen.llm.backends.replay_backend import ReplayBackend

    small = _full(load_location(WAREHOUSE)) + scenario.MAX_TOKENS + SAFETY_TOKENS - 1
    monkeypatch.setattr(ReplayBackend, "context_tokens", small, raising=False)
    monkeypatch.setattr(ReplayBackend, "count_tokens", lambda self, messages: estimate_tokens(messages),
                        raising=False)
    out = tmp_path / "run"
    run, _ = run_replay(REPLAY, WAREHOUSE, out, request=REQUEST)
    assert not isinstance(run, Exception), run
    entries = [json.loads(line) for line in (out / "transcript.jsonl").read_text().splitlines()]
    fits = [e for e in entries if e.get("kind") == "fit"]
    assert fits and fits[0]["stage"] == "scenario" and fits[0]["left_out"] == ["more_examples"]
    asked = next(e for e in entries if e.get("stage") == "scenario" and "messages" in e)
    sent = "\n".join(m["content"] for m in asked["messages"])
    assert SECOND_EXAMPLE not in sent and EXAMPLE_CONTEXT in sent and "TASK-MARK" in sent
