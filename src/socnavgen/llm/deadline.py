"""Bounds on one HTTP exchange that the client library does not give: a deadline on the WHOLE reply
(httpx's read timeout restarts at every byte, so a server dripping one byte every few seconds never
trips it) and a size cap on the body (a runaway model must not fill memory and the run folder).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from typing import TypeVar

import httpx

from socnavgen.errors import LLMError
from socnavgen.llm.retry import TransientError

R = TypeVar("R")

MAX_REPLY_BYTES = 4 * 1024 * 1024  # one HTTP reply body; a stage answer is a few KB
GRACE_SECONDS = 1.0  # the watchdog fires this long after the attempt's own deadline


class ReplyTooLarge(Exception):
    """The reply body passed MAX_REPLY_BYTES; reading stopped there."""


class _BoundedStream(httpx.SyncByteStream):
    def __init__(self, inner: httpx.SyncByteStream, deadline_at: float, max_bytes: int) -> None:
        self.inner, self.deadline_at, self.max_bytes = inner, deadline_at, max_bytes

    def __iter__(self) -> Iterator[bytes]:
        total = 0
        for chunk in self.inner:
            total += len(chunk)
            if total > self.max_bytes:
                raise ReplyTooLarge(f"the reply is larger than {self.max_bytes} bytes")
            if time.monotonic() > self.deadline_at:
                raise httpx.ReadTimeout("the whole reply did not arrive in time")
            yield chunk

    def close(self) -> None:
        self.inner.close()


class BoundedTransport(httpx.BaseTransport):
    """httpx transport whose response bodies stop at a size cap and at the attempt's read timeout,
    counted from the start of the request rather than from the last byte."""

    def __init__(self, max_bytes: int | None = None, inner: httpx.BaseTransport | None = None) -> None:
        self.max_bytes = max_bytes
        self.inner = inner or httpx.HTTPTransport()

    def handle_request(self, request: httpx.Request) -> httpx.Response:
        timeout = (request.extensions.get("timeout") or {}).get("read")
        started = time.monotonic()
        response = self.inner.handle_request(request)
        deadline_at = started + float(timeout) if timeout else float("inf")
        limit = self.max_bytes if self.max_bytes is not None else MAX_REPLY_BYTES
        assert isinstance(response.stream, httpx.SyncByteStream)
        response.stream = _BoundedStream(response.stream, deadline_at, limit)
        return response

    def close(self) -> None:
        self.inner.close()


def run_with_deadline(fn: Callable[[], R], seconds: float) -> R:
    """Run `fn` in a worker thread and give up after `seconds` (+ grace) with a TransientError.

    Covers what the transport cannot: a server that drips its status line and headers. The
    abandoned worker is a daemon thread; its socket is closed by its own read timeout or at exit."""
    box: dict[str, object] = {}
    done = threading.Event()

    def work() -> None:
        try:
            box["value"] = fn()
        except BaseException as exc:  # handed to the caller's thread below
            box["error"] = exc
        finally:
            done.set()

    threading.Thread(target=work, name="llm-attempt", daemon=True).start()
    if not done.wait(seconds + GRACE_SECONDS):
        raise TransientError(f"no complete reply within {seconds:.1f}s (the server stalled or drips its reply)")
    if "error" in box:
        raise box["error"]  # type: ignore[misc]
    return box["value"]  # type: ignore[return-value]


def too_large(describe: str, limit: int) -> LLMError:
    return LLMError(f"{describe}: the reply is larger than {limit} bytes; reading stopped there",
                    hint="lower max_tokens or check the server (a stage answer is a few KB)")
