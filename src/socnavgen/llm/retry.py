"""Retrying transient failures with exponential backoff and jitter under an overall deadline.

The backoff is a floor whatever Retry-After says; a longer Retry-After is honoured (with jitter)
while the deadline allows, otherwise the exchange ends at once with one message.

Backends raise `TransientError` for what may pass (timeouts, 429, 5xx, dropped connections) and
`LLMError` for what will not (bad key, unknown model, no server); only the former are retried.
"""

from __future__ import annotations

import logging
import random
import time
from collections.abc import Callable
from typing import TypeVar

from socnavgen.errors import LLMError
from socnavgen.llm.redact import redact

R = TypeVar("R")
log = logging.getLogger("socnavgen.llm")

BASE_DELAY = 0.5
MAX_DELAY = 30.0


class TransientError(Exception):
    """A failure worth retrying; `retry_after` is the server's requested wait in seconds, if any."""

    def __init__(self, message: str, retry_after: float | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.retry_after = retry_after


def backoff_delay(attempt: int, rng: Callable[[], float] = random.random) -> float:
    """Exponential backoff with jitter: half fixed, half random, capped."""
    ceiling = min(MAX_DELAY, BASE_DELAY * 2 ** (attempt - 1))
    return ceiling / 2 + rng() * ceiling / 2


def call_with_retries(attempt_fn: Callable[[float], R], *, describe: str, timeout: float, deadline: float,
                      sleep: Callable[[float], None] = time.sleep,
                      clock: Callable[[], float] = time.monotonic,
                      rng: Callable[[], float] = random.random) -> tuple[R, int]:
    """Call `attempt_fn(timeout_for_this_attempt)` until it succeeds; return (result, attempts).

    Raises LLMError naming `describe` when the deadline is used up or a fatal error occurs."""
    start = clock()
    attempt = 0
    while True:
        attempt += 1
        remaining = deadline - (clock() - start)
        try:
            return attempt_fn(max(0.05, min(timeout, remaining))), attempt
        except TransientError as exc:
            elapsed = clock() - start
            remaining = deadline - elapsed
            # our own backoff is a floor: a server saying `Retry-After: 0` during a 429 storm must not
            # get a request storm back; its longer waits are honoured, with jitter so clients spread out
            delay = backoff_delay(attempt, rng)
            if exc.retry_after is not None and exc.retry_after > delay:
                delay = exc.retry_after + rng() * min(1.0, 0.1 * exc.retry_after + 0.05)
            if delay >= remaining:
                asked = (f"; the server asked to wait {exc.retry_after:g}s"
                         if exc.retry_after is not None and exc.retry_after >= remaining else "")
                raise LLMError(redact(
                    f"{describe}: gave up after {attempt} attempt{'s' if attempt > 1 else ''} in {elapsed:.1f}s "
                    f"(deadline {deadline:g}s); last error: {exc.message}{asked}"),
                    hint="check that the server is healthy, then re-run (finished stages are kept)") from None
            log.warning("%s", redact(f"{describe}: {exc.message}; retrying in {delay:.1f}s (attempt {attempt + 1})"))
            sleep(delay)
