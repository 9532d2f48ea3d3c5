"""Hostile servers and replies (issue 17): each case must end in one clear LLMError within its limits,
or be survived; no key in any form may reach the transcript, the cache or an error message."""

from __future__ import annotations

import json
import time

import pytest

from socnavgen.credentials import hide_url_credentials
from socnavgen.errors import LLMError
from socnavgen.llm import make_llm
from socnavgen.llm.redact import redact
from socnavgen.llm.retry import TransientError, call_with_retries
from socnavgen.llm.transcript import Transcript, read_transcript

from .test_llm_openai import GOOD, Scenario, ask, make


def test_a_server_dripping_one_byte_at_a_time_ends_within_the_deadline(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.Scripted(body={}, drip=0.25) for _ in range(10)])
    llm = make(fake_openai, tmp_path, timeout=0.6, deadline=1.5)
    started = time.monotonic()
    with pytest.raises(LLMError, match="no complete reply within"):
        llm.chat(ask(), Scenario, stage="scenario")
    assert time.monotonic() - started < 1.5 + 0.6 + 1.0 + 3.0  # deadline + one attempt + grace + slack (loaded CI)
    assert read_transcript(tmp_path / "transcript.jsonl")[0]["fatal"] is True


def test_a_body_dripping_after_quick_headers_is_cut_by_the_transport(fake_openai, tmp_path, secret_key, caplog):
    # the body arrives one byte every 0.1 s: httpx's per-read timeout (0.5 s) never fires on its own
    fake_openai.add(fake_openai.Scripted(raw=b"x" * 1000, drip=0.1, drip_body_only=True), fake_openai.ok(GOOD))
    llm = make(fake_openai, tmp_path, timeout=0.5, deadline=5.0)
    started = time.monotonic()
    assert llm.chat(ask(), Scenario, stage="scenario").ok
    assert "(timeout)" in caplog.text and "no complete reply" not in caplog.text  # the transport, not the watchdog
    assert time.monotonic() - started < 6.0 and len(fake_openai.requests) == 2  # 1000 bytes would take 100 s


def test_retry_after_zero_storm_is_paced_by_our_own_backoff(fake_openai, tmp_path, secret_key):
    fake_openai.add(*[fake_openai.error(429, "busy", headers={"retry-after": "0"}) for _ in range(100)])
    llm = make(fake_openai, tmp_path, deadline=3.0)
    with pytest.raises(LLMError, match="gave up"):
        llm.chat(ask(), Scenario, stage="scenario")
    assert len(fake_openai.requests) <= 5  # 0.5 + 1 + 2 s of floor: never a storm


def test_backoff_floor_holds_whatever_retry_after_says():
    waits: list[float] = []
    calls = iter([TransientError("429", retry_after=0.0)] * 3)

    def attempt(_timeout: float) -> str:
        exc = next(calls, None)
        if exc is not None:
            raise exc
        return "ok"

    clock = [0.0]
    result, attempts = call_with_retries(attempt, describe="x", timeout=1, deadline=100,
                                         sleep=lambda s: (waits.append(s), clock.__setitem__(0, clock[0] + s)),
                                         clock=lambda: clock[0], rng=lambda: 0.5)
    assert (result, attempts) == ("ok", 4)
    assert waits[0] >= 0.375 and waits[1] >= 0.75 and waits[2] >= 1.5  # exponential floor, jitter included


@pytest.mark.parametrize("content_type", ["text/html", "application/json"])
def test_http_200_with_an_html_body_is_one_clear_error(fake_openai, tmp_path, secret_key, content_type):
    fake_openai.add(fake_openai.Scripted(raw=b"<html><body>Log in to the hotel wifi</body></html>",
                                         content_type=content_type))
    with pytest.raises(LLMError, match="not JSON"):
        make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert len(fake_openai.requests) == 1


def test_a_huge_reply_is_refused_and_nothing_big_is_stored(fake_openai, tmp_path, secret_key):
    fake_openai.add(fake_openai.ok("x" * 300_000))
    llm = make(fake_openai, tmp_path)
    llm.max_reply_bytes = 100_000
    with pytest.raises(LLMError, match="larger than 100000 bytes"):
        llm.chat(ask(), Scenario, stage="scenario")
    assert (tmp_path / "transcript.jsonl").stat().st_size < 20_000
    assert not any(p.is_file() for p in (tmp_path / "cache").rglob("*"))


def test_long_replies_are_stored_clipped_and_not_cached(fake_openai, tmp_path, secret_key, monkeypatch):
    import socnavgen.llm.cache as cache_module

    monkeypatch.setattr(cache_module, "MAX_STORED_CHARS", 1000)
    long_reply = json.dumps({"scenario_description": "y" * 5000, "humans": 1})
    fake_openai.add(fake_openai.ok(long_reply))
    llm = make(fake_openai, tmp_path)
    llm.transcript.max_chars = 1000
    reply = llm.chat(ask(), Scenario, stage="scenario")
    assert reply.ok and len(reply.value.scenario_description) == 5000  # the answer itself is whole
    entry = read_transcript(tmp_path / "transcript.jsonl")[0]
    assert len(entry["raw"]) < 1100 and "more characters not stored" in entry["raw"]
    assert not any(p.is_file() for p in (tmp_path / "cache").rglob("*"))


def test_the_transcript_stops_storing_replies_past_its_run_cap(tmp_path):
    transcript = Transcript(tmp_path / "t.jsonl", max_bytes=5000, max_chars=1000)
    for i in range(30):
        transcript.append({"stage": "scenario", "raw": "z" * 900, "messages": [], "attempt": i})
    entries = read_transcript(tmp_path / "t.jsonl")
    assert len(entries) == 30 and (tmp_path / "t.jsonl").stat().st_size < 5000 + 30 * 200
    assert "omitted" in entries[-1] and "raw" not in entries[-1] and entries[-1]["attempt"] == 29


def test_a_failed_transcript_write_leaves_no_torn_line(tmp_path, monkeypatch):
    import os as os_module

    path = tmp_path / "t.jsonl"
    transcript = Transcript(path)
    transcript.append({"stage": "a"})
    real_write = os_module.write

    def full_disk(fd: int, data: bytes) -> int:
        real_write(fd, data[: len(data) // 2])
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("socnavgen.llm.transcript.os.write", full_disk)
    with pytest.raises(OSError):
        transcript.append({"stage": "b", "raw": "half of me would be torn"})
    monkeypatch.setattr("socnavgen.llm.transcript.os.write", real_write)
    transcript.append({"stage": "c"})
    lines = path.read_text().splitlines()
    assert [json.loads(line)["stage"] for line in lines] == ["a", "c"]  # every line readable


@pytest.mark.parametrize("reply", [
    '{"scenario_description": "x", "humans": ' + "9" * 5000 + "}",
    '{"scenario_description": ' + "[" * 100_000 + "]" * 100_000 + ', "humans": 1}',
    "[" * 100_000,
    '{"a": ' + '{"b": ' * 100_000 + "1" + "}" * 100_001,
])
def test_hostile_reply_bodies_become_a_correction_not_a_crash(fake_openai, tmp_path, secret_key, reply):
    fake_openai.add(fake_openai.ok(reply))
    result = make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
    assert not result.ok and "JSON" in result.error


@pytest.mark.parametrize("raw_key", ["sk-live-KEY-with-space-0123 ", "sk-live-KEY-with-cr-0123\r", "k3y-Ab"])
def test_keys_with_trailing_whitespace_or_short_keys_never_reach_files(fake_openai, tmp_path, monkeypatch,
                                                                       raw_key):
    monkeypatch.setenv("OPENAI_API_KEY", raw_key)
    key = raw_key.strip()
    fake_openai.add(fake_openai.ok(json.dumps({"scenario_description": f"echo {key} and {raw_key}", "humans": 1})),
                    fake_openai.error(401, f"Incorrect API key provided: {key}."))
    llm = make(fake_openai, tmp_path)
    assert llm.chat(ask(), Scenario, stage="scenario").ok
    assert fake_openai.requests[0]["headers"]["authorization"] == f"Bearer {key}"  # sent stripped
    with pytest.raises(LLMError) as info:
        llm.chat(ask("again"), Scenario, stage="scenario", temperature=0.3)
    assert key not in str(info.value)
    stored = (tmp_path / "transcript.jsonl").read_text()
    stored += "".join(p.read_text() for p in (tmp_path / "cache").rglob("*.json"))
    assert "echo ***" in stored and key not in stored


def test_credentials_in_the_base_url_never_reach_files_or_messages(fake_openai, tmp_path, monkeypatch):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    host = fake_openai.url.removeprefix("http://")
    url = f"http://alice:pw-Hunter2@{host}?api-key=AZ-secret-77"
    fake_openai.add(fake_openai.ok(GOOD), fake_openai.error(404, "no model"))
    llm = make_llm(f"openai:fake-model@{url}", transcript=tmp_path / "t.jsonl", cache_dir=tmp_path / "cache",
                   timeout=2, deadline=4)
    assert llm.chat(ask(), Scenario, stage="scenario").ok
    with pytest.raises(LLMError) as info:
        llm.chat(ask("b"), Scenario, stage="scenario")
    text = str(info.value) + (tmp_path / "t.jsonl").read_text()
    assert "pw-Hunter2" not in text and "AZ-secret-77" not in text and "***" in text


@pytest.mark.parametrize("text, hidden", [
    ("openai:gpt@https://user:pa55@example.org/v1", "pa55"),
    ("https://example.org/v1?api-key=abcdef&x=1", "abcdef"),
    ("see https://tok-en@proxy.local/v1", "tok-en"),
])
def test_url_credentials_are_hidden_anywhere_in_text(text, hidden):
    assert hidden not in hide_url_credentials(text) and hidden not in redact(text)
    assert "example.org" in redact(text) or "proxy.local" in redact(text)
