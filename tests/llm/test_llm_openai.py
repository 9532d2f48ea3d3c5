"""openai backend against a scripted OpenAI-compatible server on loopback (real HTTP, real SDK)."""

from __future__ import annotations

import base64
import json
import logging
import socket
import threading
import time
from pathlib import Path

import pytest
from pydantic import BaseModel

from socnavgen.errors import LLMError
from socnavgen.llm import ChatMessage, make_llm
from socnavgen.llm.transcript import read_transcript

GOOD = '{"scenario_description": "a robot meets a worker", "humans": 1}'


class Scenario(BaseModel):
    scenario_description: str
    humans: int


def ask(text: str = "Propose a scenario.") -> list[ChatMessage]:
    return [ChatMessage(role="system", content="You design robot tests."), ChatMessage(role="user", content=text)]


def make(fake, tmp_path: Path, **kw):
    kw.setdefault("cache_dir", tmp_path / "cache")
    kw.setdefault("transcript", tmp_path / "transcript.jsonl")
    kw.setdefault("timeout", 2.0)
    kw.setdefault("deadline", 5.0)
    return make_llm(f"openai:fake-model@{fake.url}", **kw)


def test_structured_reply_uses_json_schema_and_reports_usage(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.ok(GOOD, prompt_tokens=21, completion_tokens=9))
    llm = make(fake_openai, tmp_path)
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok and reply.value == Scenario(scenario_description="a robot meets a worker", humans=1)
    assert (reply.usage.prompt_tokens, reply.usage.completion_tokens, reply.usage.cached) == (21, 9, False)
    sent = fake_openai.requests[0]
    assert sent["path"] == "/v1/chat/completions"
    assert sent["json"]["response_format"]["type"] == "json_schema"
    assert sent["json"]["response_format"]["json_schema"]["schema"]["required"] == ["scenario_description", "humans"]
    assert sent["json"]["temperature"] == 0.0
    assert sent["headers"]["authorization"] == f"Bearer {secret_key}"
    entry = read_transcript(tmp_path / "transcript.jsonl")[0]
    assert entry["stage"] == "scenario" and entry["raw"] == GOOD and entry["value"]["humans"] == 1
    assert entry["prompt_tokens"] == 21 and entry["attempt"] == 1 and entry["cached"] is False
    assert llm.usage_by_stage()["scenario"]["prompt_tokens"] == 21


def test_429_with_retry_after_then_success(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.error(429, "slow down", headers={"retry-after": "0.4"}), fake_openai.ok(GOOD))
    llm = make(fake_openai, tmp_path)
    started = time.monotonic()
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok
    assert time.monotonic() - started >= 0.4  # the server's wait was honoured
    assert len(fake_openai.requests) == 2
    assert read_transcript(tmp_path / "transcript.jsonl")[0]["attempt"] == 2


def test_500s_until_the_deadline_end_in_one_clear_error(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.error(500, "upstream exploded") for _ in range(50)])
    llm = make(fake_openai, tmp_path, deadline=1.5)
    started = time.monotonic()
    with pytest.raises(LLMError) as info:
        llm.chat(ask(), Scenario, stage="scenario")
    elapsed = time.monotonic() - started
    text = str(info.value)
    assert "openai:fake-model at http://127.0.0.1" in text and "gave up" in text and "HTTP 500" in text
    assert 1 < len(fake_openai.requests) < 10  # retried with backoff, not hammered
    assert elapsed < 3.0
    entry = read_transcript(tmp_path / "transcript.jsonl")[0]
    assert entry["raw"] is None and "gave up" in entry["error"]


def test_garbage_reply_gives_an_error_and_the_requery_succeeds(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.ok("Sure! Here it is: {scenario_description: 'x', humans: }"), fake_openai.ok(GOOD))
    llm = make(fake_openai, tmp_path)
    history = ask()
    first = llm.chat(history, Scenario, stage="scenario")
    assert not first.ok and "JSON" in first.error
    history += [ChatMessage(role="assistant", content=first.raw), ChatMessage(role="user", content=first.error)]
    second = llm.chat(history, Scenario, stage="scenario")
    assert second.ok and second.value.humans == 1
    resent = fake_openai.requests[1]["json"]["messages"]
    assert [m["role"] for m in resent] == ["system", "user", "assistant", "user"]
    assert resent[2]["content"] == first.raw and resent[3]["content"] == first.error
    entries = read_transcript(tmp_path / "transcript.jsonl")
    assert entries[0]["error"] == first.error and entries[1]["error"] is None


def test_slow_reply_past_the_timeout_is_retried(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.Scripted(body={}, delay=1.5), fake_openai.ok(GOOD))
    llm = make(fake_openai, tmp_path, timeout=0.4, deadline=5.0)
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok and len(fake_openai.requests) == 2


def test_always_slow_server_ends_with_a_timeout_error(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.Scripted(body={}, delay=1.0) for _ in range(10)])
    llm = make(fake_openai, tmp_path, timeout=0.3, deadline=1.2)
    with pytest.raises(LLMError, match="timeout"):
        llm.chat(ask(), Scenario, stage="scenario")


def test_dropped_connection_is_retried(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.Scripted(drop=True), fake_openai.ok(GOOD))
    reply = make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert reply.ok and len(fake_openai.requests) == 2


def test_401_fails_at_once_naming_the_key(fake_openai, tmp_path, secret_key, caplog):
    caplog.set_level(logging.DEBUG)
    fake_openai.add(fake_openai.error(401, f"Incorrect API key provided: {secret_key}"), fake_openai.ok(GOOD))
    llm = make(fake_openai, tmp_path)
    started = time.monotonic()
    with pytest.raises(LLMError) as info:
        llm.chat(ask(), Scenario, stage="scenario")
    assert time.monotonic() - started < 1.0 and len(fake_openai.requests) == 1
    message = str(info.value)
    assert "401" in message and "OPENAI_API_KEY" in message and "openai:fake-model at http://127.0.0.1" in message
    assert secret_key not in message


def test_404_unknown_model_fails_at_once(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.error(404, "The model `fake-model` does not exist"))
    with pytest.raises(LLMError, match="model 'fake-model' not found"):
        make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert len(fake_openai.requests) == 1


def test_quota_exhausted_429_is_not_retried(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.error(429, "You exceeded your current quota", code="insufficient_quota"))
    with pytest.raises(LLMError, match="quota"):
        make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert len(fake_openai.requests) == 1


def test_unreachable_server_fails_at_once(tmp_path, secret_key):
    with socket.socket() as sock:  # a port nobody listens on
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    llm = make_llm(f"openai:m@http://127.0.0.1:{port}/v1", cache_dir=tmp_path, timeout=2, deadline=10)
    started = time.monotonic()
    with pytest.raises(LLMError, match="cannot connect") as info:
        llm.chat(ask(), Scenario, stage="scenario")
    assert time.monotonic() - started < 2.0
    assert f"127.0.0.1:{port}" in str(info.value)


def test_refused_json_schema_falls_back_to_json_object_then_prompt(fake_openai, tmp_path, secret_key):
    def refuse_structured(request: dict):
        if "response_format" in request:
            kind = request["response_format"]["type"]
            return fake_openai.error(400, f"response_format type '{kind}' is not supported")
        return fake_openai.ok("```json\n" + GOOD + "\n```")

    fake_openai.add(*[refuse_structured] * 4)
    llm = make(fake_openai, tmp_path)
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok
    kinds = [r["json"].get("response_format", {}).get("type") for r in fake_openai.requests]
    assert kinds == ["json_schema", "json_object", None]
    last_user = fake_openai.requests[-1]["json"]["messages"][-1]
    assert last_user["role"] == "user" and "JSON schema" in last_user["content"]
    assert "scenario_description" in last_user["content"]
    llm.chat(ask("another"), Scenario, stage="scenario")  # the working mode is remembered
    assert len(fake_openai.requests) == 4


def test_json_object_mode_carries_the_schema_in_the_prompt(fake_openai, tmp_path, secret_key):
    def only_json_object(request: dict):
        if request.get("response_format", {}).get("type") == "json_schema":
            return fake_openai.error(400, "Invalid parameter: 'response_format' of type 'json_schema'")
        return fake_openai.ok(GOOD)

    fake_openai.add(only_json_object, only_json_object)
    assert make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario").ok
    second = fake_openai.requests[1]["json"]
    assert second["response_format"] == {"type": "json_object"}
    assert "JSON" in second["messages"][-1]["content"]


def test_cache_hit_costs_no_tokens_and_no_request(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.ok(GOOD) for _ in range(4)])
    llm = make(fake_openai, tmp_path)
    first = llm.chat(ask(), Scenario, stage="scenario")
    again = make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")  # a new run, same cache
    assert len(fake_openai.requests) == 1
    assert again.value == first.value and again.usage.cached
    assert again.usage.prompt_tokens == 0 and again.usage.completion_tokens == 0
    assert read_transcript(tmp_path / "transcript.jsonl")[1]["cached"] is True
    make(fake_openai, tmp_path, use_cache=False).chat(ask(), Scenario, stage="scenario")
    assert len(fake_openai.requests) == 2  # --no-cache
    llm.chat(ask(), Scenario, stage="scenario", temperature=0.7)
    assert len(fake_openai.requests) == 3  # sampling is not cached
    llm.chat(ask("a different question"), Scenario, stage="scenario")
    assert len(fake_openai.requests) == 4


def test_api_key_never_reaches_transcript_cache_or_logs(fake_openai, tmp_path, secret_key, caplog):
    caplog.set_level(logging.DEBUG)
    fake_openai.add(fake_openai.error(500, f"internal error for key {secret_key}"),
                    fake_openai.ok(json.dumps({"scenario_description": f"echo {secret_key}", "humans": 2})),
                    fake_openai.error(401, f"Incorrect API key provided: {secret_key}"))
    llm = make(fake_openai, tmp_path)
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok and fake_openai.requests[0]["headers"]["authorization"].endswith(secret_key)
    with pytest.raises(LLMError) as info:
        llm.chat(ask("again"), Scenario, stage="scenario", temperature=0.5)
    assert secret_key not in str(info.value)
    transcript = (tmp_path / "transcript.jsonl").read_text()
    assert "scenario" in transcript and secret_key not in transcript
    cache_files = [p for p in (tmp_path / "cache").rglob("*") if p.is_file()]
    assert cache_files and all(secret_key not in p.read_text() for p in cache_files)
    assert caplog.text and "retrying" in caplog.text
    assert secret_key not in caplog.text and "SECRET" not in caplog.text


def test_images_are_sent_as_data_urls_and_logged_by_hash(fake_openai, tmp_path, secret_key):
    png = tmp_path / "scene_graph.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\nfake-image-bytes")
    fake_openai.add(fake_openai.ok(GOOD), fake_openai.ok(GOOD))
    messages = [ChatMessage(role="user", content="Look at the map.", images=[png])]
    make(fake_openai, tmp_path).chat(messages, Scenario, stage="scenario")
    content = fake_openai.requests[0]["json"]["messages"][0]["content"]
    assert content[0] == {"type": "text", "text": "Look at the map."}
    prefix, _, data = content[1]["image_url"]["url"].partition(",")
    assert prefix == "data:image/png;base64" and base64.b64decode(data) == png.read_bytes()
    entry = read_transcript(tmp_path / "transcript.jsonl")[0]
    assert entry["messages"][0]["images"][0]["file"] == "scene_graph.png"
    assert len(entry["messages"][0]["images"][0]["sha256"]) == 64
    assert "base64" not in (tmp_path / "transcript.jsonl").read_text()
    make(fake_openai, tmp_path, use_image=False, use_cache=False).chat(messages, Scenario, stage="scenario")
    assert fake_openai.requests[1]["json"]["messages"][0]["content"] == "Look at the map."


def test_server_refusing_images_gets_text_only(fake_openai, tmp_path, secret_key):
    png = tmp_path / "map.png"
    png.write_bytes(b"\x89PNG fake")

    def no_vision(request: dict):
        if isinstance(request["messages"][0]["content"], list):
            return fake_openai.error(400, "image input is not supported by this model")
        return fake_openai.ok(GOOD)

    fake_openai.add(no_vision, no_vision)
    reply = make(fake_openai, tmp_path).chat([ChatMessage(role="user", content="map", images=[png])], Scenario,
                                             stage="scenario")
    assert reply.ok and fake_openai.requests[1]["json"]["response_format"]["type"] == "json_schema"


def test_max_parallel_bounds_requests_in_flight(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.Scripted(body=fake_openai.ok(GOOD).body, delay=0.3) for _ in range(6)])
    llm = make(fake_openai, tmp_path, max_parallel=2, use_cache=False)
    replies = [None] * 6

    def work(i: int) -> None:
        replies[i] = llm.chat(ask(f"human {i}"), Scenario, stage="behaviors", key=f"human{i}")

    threads = [threading.Thread(target=work, args=(i,)) for i in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(r is not None and r.ok for r in replies)
    assert fake_openai.max_in_flight == 2
    keys = sorted(e["key"] for e in read_transcript(tmp_path / "transcript.jsonl"))
    assert keys == [f"human{i}" for i in range(6)]


def test_missing_key_for_openai_itself_is_a_clear_error(monkeypatch, tmp_path):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    with pytest.raises(LLMError, match="OPENAI_API_KEY is not set"):
        make_llm("openai:gpt-4o", cache_dir=tmp_path)


def test_local_server_needs_no_key(fake_openai, tmp_path, monkeypatch):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    fake_openai.add(fake_openai.ok(GOOD))
    assert make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario").ok
    assert fake_openai.requests[0]["headers"]["authorization"].startswith("Bearer ")


def test_malformed_http_bodies_are_retried(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.Scripted(body="garbage"), fake_openai.Scripted(body={"nope": 1}), fake_openai.ok(GOOD))
    reply = make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert reply.ok and len(fake_openai.requests) == 3


def test_unwritable_cache_does_not_cost_the_reply(fake_openai, tmp_path, secret_key, caplog):
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("a file where the cache folder should be")
    fake_openai.add(fake_openai.ok(GOOD))
    reply = make(fake_openai, tmp_path, cache_dir=blocker).chat(ask(), Scenario, stage="scenario")
    assert reply.ok and "cannot write the LLM cache" in caplog.text
