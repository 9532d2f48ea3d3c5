"""The real in-process `local` model (SmolLM2-135M GGUF) end to end with grammar-constrained decoding.

Selected with `-m local_model`. It FAILS (never skips) when llama-cpp-python is missing: the Makefile
installs the `local` extra, so a missing module is a broken install."""

from __future__ import annotations

import importlib.util

import pytest

from socnavgen.llm import ChatMessage, make_llm
from socnavgen.llm.transcript import read_transcript
from socnavgen.run.models import ScenarioProposal

pytestmark = pytest.mark.local_model

PROMPT = ("Context: a delivery robot in a small warehouse; employees walk around.\n"
          "Task: transport a box from one point to another.\n"
          "Propose a social navigation test scenario with two humans. Give the scenario description, the "
          "number of humans, what each human (human1, human2) does, and the expected robot behavior.")


def test_local_model_reply_validates_against_a_stage_schema(tmp_path):
    if importlib.util.find_spec("llama_cpp") is None:
        pytest.fail("llama_cpp is not importable: install the local extra (pip install -e '.[local]'); "
                    "the `local` backend cannot run without it")
    llm = make_llm("local", transcript=tmp_path / "transcript.jsonl", cache_dir=tmp_path / "cache")
    assert llm.supports_grammar and not llm.supports_images
    messages = [ChatMessage(role="system", content="You design test scenarios for social robot navigation."),
                ChatMessage(role="user", content=PROMPT)]
    reply = llm.chat(messages, ScenarioProposal, stage="scenario", max_tokens=400)
    assert reply.error is None, reply.raw
    assert isinstance(reply.value, ScenarioProposal)
    assert reply.usage.prompt_tokens > 50 and reply.usage.completion_tokens > 5
    entry = read_transcript(tmp_path / "transcript.jsonl")[0]
    assert entry["model"] == "SmolLM2-135M-Instruct" and entry["grammar"] == "schema"
    again = llm.chat(messages, ScenarioProposal, stage="scenario", max_tokens=400)
    assert again.usage.cached and again.value == reply.value  # temperature 0: served from the cache


def test_local_model_follows_a_caller_grammar(tmp_path):
    from pydantic import BaseModel

    class Choice(BaseModel):
        action: str

    grammar = 'root ::= "{\\"action\\": \\"" ("stop" | "wait" | "go") "\\"}"'
    llm = make_llm("local", use_cache=False)
    reply = llm.chat([ChatMessage(role="user", content="The robot meets a human at a door. What should it do?")],
                     Choice, stage="decide", grammar=grammar, max_tokens=20)
    assert reply.ok and reply.value.action in {"stop", "wait", "go"}
