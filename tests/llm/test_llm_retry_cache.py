"""Retry policy (with a fake clock), Retry-After parsing, cache and redaction units."""

from __future__ import annotations

import email.utils
import time

import pytest

from socnavgen.errors import LLMError
from socnavgen.llm.backends.openai_backend import retry_after_seconds
from socnavgen.llm.cache import ReplyCache, cache_key, default_cache_dir
from socnavgen.llm.redact import redact
from socnavgen.llm.retry import TransientError, backoff_delay, call_with_retries


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0
        self.sleeps: list[float] = []

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


def failing(times: int, retry_after: float | None = None, cost: float = 0.0, clock: FakeClock | None = None):
    calls = {"n": 0, "timeouts": []}

    def attempt(timeout: float) -> str:
        calls["n"] += 1
        calls["timeouts"].append(timeout)
        if clock is not None:
            clock.now += min(cost, timeout)
        if calls["n"] <= times:
            raise TransientError("HTTP 503: busy", retry_after)
        return "done"

    return attempt, calls


def test_backoff_grows_exponentially_with_bounded_jitter():
    for attempt in range(1, 8):
        low, high = backoff_delay(attempt, rng=lambda: 0.0), backoff_delay(attempt, rng=lambda: 0.999999)
        ceiling = min(30.0, 0.5 * 2 ** (attempt - 1))
        assert low == pytest.approx(ceiling / 2) and high == pytest.approx(ceiling, rel=1e-5)


def test_retries_until_success_and_counts_attempts():
    clock = FakeClock()
    attempt, calls = failing(3)
    result, attempts = call_with_retries(attempt, describe="x", timeout=10, deadline=100, sleep=clock.sleep,
                                         clock=clock, rng=lambda: 0.5)
    assert (result, attempts, calls["n"]) == ("done", 4, 4)
    assert clock.sleeps == pytest.approx([0.375, 0.75, 1.5])


def test_retry_after_is_honoured():
    clock = FakeClock()
    attempt, _ = failing(1, retry_after=7.0)
    call_with_retries(attempt, describe="x", timeout=10, deadline=100, sleep=clock.sleep, clock=clock,
                      rng=lambda: 0.0)
    assert clock.sleeps == [7.0]


def test_retry_after_beyond_the_deadline_gives_up_at_once():
    clock = FakeClock()
    attempt, calls = failing(5, retry_after=120.0)
    with pytest.raises(LLMError, match="asked to wait 120s"):
        call_with_retries(attempt, describe="openai:m", timeout=10, deadline=60, sleep=clock.sleep, clock=clock)
    assert calls["n"] == 1 and clock.sleeps == []


def test_deadline_bounds_total_time_and_each_attempt_timeout():
    clock = FakeClock()
    attempt, calls = failing(1000, cost=3.0, clock=clock)
    with pytest.raises(LLMError) as info:
        call_with_retries(attempt, describe="openai:m at http://h", timeout=5, deadline=20, sleep=clock.sleep,
                          clock=clock, rng=lambda: 0.5)
    assert clock.now <= 20.1 and "openai:m at http://h: gave up after" in str(info.value)
    assert "HTTP 503: busy" in str(info.value)
    assert calls["timeouts"][0] == 5 and all(t <= 5 for t in calls["timeouts"])
    assert calls["timeouts"][-1] < 5  # the last attempt only gets what is left of the deadline


def test_fatal_errors_are_not_retried():
    calls = {"n": 0}

    def attempt(timeout: float) -> str:
        calls["n"] += 1
        raise LLMError("bad key")

    with pytest.raises(LLMError, match="bad key"):
        call_with_retries(attempt, describe="x", timeout=1, deadline=10, sleep=lambda s: None)
    assert calls["n"] == 1


def test_retry_after_header_forms():
    assert retry_after_seconds({"retry-after": "2.5"}) == 2.5
    assert retry_after_seconds({"retry-after-ms": "1500"}) == 1.5
    future = email.utils.formatdate(time.time() + 30, usegmt=True)
    assert 25 < retry_after_seconds({"retry-after": future}) <= 31
    assert retry_after_seconds({"retry-after": "soon"}) is None
    assert retry_after_seconds({}) is None


def test_cache_round_trip_and_corruption(tmp_path):
    cache = ReplyCache(tmp_path)
    key = cache_key({"backend": "openai", "model": "m", "messages": [{"role": "user", "content": "hi"}]})
    assert key != cache_key({"backend": "openai", "model": "m2", "messages": [{"role": "user", "content": "hi"}]})
    assert cache.get(key) is None
    cache.put(key, {"raw": "{}", "model": "m"})
    assert cache.get(key)["raw"] == "{}"
    path = tmp_path / key[:2] / f"{key}.json"
    path.write_text("{torn")
    assert cache.get(key) is None  # a damaged entry is a miss, not a crash
    assert not [p for p in tmp_path.rglob("*.tmp")]


def test_default_cache_dir_honours_env(monkeypatch, tmp_path):
    monkeypatch.setenv("SOCNAVGEN_CACHE_DIR", str(tmp_path / "c"))
    assert default_cache_dir() == tmp_path / "c"
    monkeypatch.delenv("SOCNAVGEN_CACHE_DIR")
    assert default_cache_dir().parts[-3:] == (".cache", "socnavgen", "llm")


def test_redact_masks_env_keys_and_key_shapes(monkeypatch):
    monkeypatch.setenv("OPENAI_API_KEY", "custom-key-without-prefix-123")
    text = redact("key custom-key-without-prefix-123, header Authorization: Bearer abcdef123456, sk-proj-abcdef123")
    assert "custom-key-without-prefix-123" not in text and "abcdef123456" not in text and "sk-proj-abc" not in text
