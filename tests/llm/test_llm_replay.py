"""replay:FILE scripts and recorded transcripts; spec parsing."""

from __future__ import annotations

import json
import threading
from concurrent.futures import ThreadPoolExecutor

import pytest
from pydantic import BaseModel

from socnavgen.errors import InputFileError, LLMError
from socnavgen.llm import ChatMessage, make_llm
from socnavgen.llm.factory import ACCEPTED_FORMS
from socnavgen.llm.transcript import read_transcript


class Scenario(BaseModel):
    scenario_description: str


class Tree(BaseModel):
    xml: str


SCRIPT = """
stages:
  scenario:
    - "not json at all"
    - '{"Scenario Description": "second try"}'
  behaviors:
    human1: ['{"xml": "<root h1a/>"}', '{"xml": "<root h1b/>"}']
    human2: ['{"xml": "<root h2/>"}']
  paths:
    - {scenario_description: written inline as YAML}
"""


def msgs(text: str) -> list[ChatMessage]:
    return [ChatMessage(role="user", content=text)]


@pytest.fixture
def script(tmp_path):
    path = tmp_path / "script.yaml"
    path.write_text(SCRIPT)
    return path


def test_list_stage_is_consumed_in_order_and_errors_are_replies(script, tmp_path):
    llm = make_llm(f"replay:{script}", transcript=tmp_path / "t.jsonl")
    first = llm.chat(msgs("propose"), Scenario, stage="scenario")
    assert not first.ok and "JSON" in first.error and first.raw == "not json at all"
    history = msgs("propose") + [ChatMessage(role="assistant", content=first.raw),
                                 ChatMessage(role="user", content=first.error)]
    second = llm.chat(history, Scenario, stage="scenario")
    assert second.ok and second.value.scenario_description == "second try"
    assert [(stage, key, len(m)) for stage, key, m in llm.calls] == [("scenario", None, 1), ("scenario", None, 3)]
    assert llm.calls[1][2][1].content == "not json at all"
    entries = read_transcript(tmp_path / "t.jsonl")
    assert [e["stage"] for e in entries] == ["scenario", "scenario"] and entries[1]["value"] == {
        "scenario_description": "second try"}
    inline = llm.chat(msgs("paths"), Scenario, stage="paths")
    assert inline.value.scenario_description == "written inline as YAML"


def test_mapping_stage_is_consumed_per_key(script):
    llm = make_llm(f"replay:{script}")
    assert llm.chat(msgs("h2"), Tree, stage="behaviors", key="human2").value.xml == "<root h2/>"
    assert llm.chat(msgs("h1"), Tree, stage="behaviors", key="human1").value.xml == "<root h1a/>"
    assert llm.chat(msgs("h1"), Tree, stage="behaviors", key="human1").value.xml == "<root h1b/>"


def test_exhausted_stage_names_stage_key_and_file(script):
    llm = make_llm(f"replay:{script}")
    llm.chat(msgs("h2"), Tree, stage="behaviors", key="human2")
    with pytest.raises(LLMError) as info:
        llm.chat(msgs("h2"), Tree, stage="behaviors", key="human2")
    text = str(info.value)
    assert "'behaviors'" in text and "'human2'" in text and str(script) in text
    with pytest.raises(LLMError, match="'human3'"):
        llm.chat(msgs("h3"), Tree, stage="behaviors", key="human3")
    with pytest.raises(LLMError, match="'verify'"):
        llm.chat(msgs("?"), Tree, stage="verify")


def test_threads_get_their_own_keys(tmp_path):
    path = tmp_path / "many.json"
    humans = {f"human{i}": [json.dumps({"xml": f"<h{i}/>"})] for i in range(8)}
    path.write_text(json.dumps({"stages": {"behaviors": humans}}))
    llm = make_llm(f"replay:{path}", max_parallel=3)
    with ThreadPoolExecutor(8) as pool:
        replies = list(pool.map(lambda i: llm.chat(msgs(str(i)), Tree, stage="behaviors", key=f"human{i}"), range(8)))
    assert [r.value.xml for r in replies] == [f"<h{i}/>" for i in range(8)]


def test_recorded_transcript_replays_exactly(script, tmp_path):
    record = tmp_path / "run" / "transcript.jsonl"
    llm = make_llm(f"replay:{script}", transcript=record)
    original = [llm.chat(msgs("a"), Scenario, stage="scenario"), llm.chat(msgs("b"), Scenario, stage="scenario"),
                llm.chat(msgs("c"), Tree, stage="behaviors", key="human1")]
    again = make_llm(f"replay:{record}")
    replayed = [again.chat(msgs("a"), Scenario, stage="scenario"), again.chat(msgs("b"), Scenario, stage="scenario"),
                again.chat(msgs("c"), Tree, stage="behaviors", key="human1")]
    assert [(r.raw, r.value, r.error) for r in replayed] == [(r.raw, r.value, r.error) for r in original]
    with pytest.raises(LLMError, match="no reply left"):
        again.chat(msgs("c"), Tree, stage="behaviors", key="human1")


def test_transcript_lines_stay_whole_under_concurrency(tmp_path):
    path = tmp_path / "s.json"
    big = "x" * 20000
    path.write_text(json.dumps({"stages": {"b": {f"h{i}": [json.dumps({"xml": big})] * 5 for i in range(6)}}}))
    llm = make_llm(f"replay:{path}", transcript=tmp_path / "t.jsonl", max_parallel=6)

    def work(i: int) -> None:
        for _ in range(5):
            assert llm.chat(msgs(big), Tree, stage="b", key=f"h{i}").ok

    threads = [threading.Thread(target=work, args=(i,)) for i in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    lines = (tmp_path / "t.jsonl").read_text().splitlines()
    assert len(lines) == 30 and all(json.loads(line)["value"]["xml"] == big for line in lines)


@pytest.mark.parametrize("content, words", [
    ("just: text", "stages"),
    ("stages: [1, 2]", "stages"),
    ("stages:\n  scenario: 3", "stages.scenario"),
    ("stages:\n  scenario: [3]", "must be a string"),
    ("stages: {scenario: [", "malformed YAML"),
])
def test_bad_scripts_are_input_errors(tmp_path, content, words):
    path = tmp_path / "bad.yaml"
    path.write_text(content)
    with pytest.raises(InputFileError) as info:
        make_llm(f"replay:{path}")
    assert words in str(info.value) and str(path) in str(info.value)


@pytest.mark.parametrize("spec", ["", "gpt-4o", "claude:opus", "openai:", "openai:m@ftp://x", "gguf:", "replay:"])
def test_bad_specs_list_the_accepted_forms(spec):
    with pytest.raises(LLMError) as info:
        make_llm(spec)
    assert all(form.split(" ")[0] in str(info.value) for form in ACCEPTED_FORMS)


def test_missing_gguf_file_is_a_clear_error(tmp_path):
    with pytest.raises(LLMError, match="model file not found"):
        make_llm(f"gguf:{tmp_path / 'nope.gguf'}")
