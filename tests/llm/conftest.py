"""A scripted OpenAI-compatible HTTP server on 127.0.0.1, so tests exercise real HTTP through the real
`openai` SDK: each request pops the next scripted response (status, headers, delay, dropped
connection, or a function of the request)."""

from __future__ import annotations

import json
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

import pytest

SECRET = "sk-test-SECRET-0123456789abcdefXYZ"


def completion_body(content: str, model: str = "fake-model", prompt_tokens: int = 11,
                    completion_tokens: int = 7) -> dict[str, Any]:
    return {"id": "chatcmpl-1", "object": "chat.completion", "created": 1, "model": model,
            "choices": [{"index": 0, "finish_reason": "stop",
                         "message": {"role": "assistant", "content": content}}],
            "usage": {"prompt_tokens": prompt_tokens, "completion_tokens": completion_tokens,
                      "total_tokens": prompt_tokens + completion_tokens}}


@dataclass
class Scripted:
    status: int = 200
    body: Any = None
    headers: dict[str, str] = field(default_factory=dict)
    delay: float = 0.0
    drop: bool = False  # close the connection without answering
    raw: bytes | None = None  # body sent as-is (text/html), e.g. what a captive portal answers
    content_type: str | None = None  # default: text/html for `raw`, application/json otherwise
    drip: float = 0.0  # send the whole response (status line included) one byte every `drip` seconds
    drip_body_only: bool = False  # with `drip`: status line and headers at once, only the body dripped


def ok(content: str, **kw: Any) -> Scripted:
    return Scripted(body=completion_body(content, **kw))


def error(status: int, message: str, *, code: str | None = None, headers: dict[str, str] | None = None) -> Scripted:
    return Scripted(status=status, headers=headers or {},
                    body={"error": {"message": message, "type": "error", "code": code}})


class FakeOpenAI:
    def __init__(self) -> None:
        self.script: deque[Scripted | Callable[[dict], Scripted]] = deque()
        self.requests: list[dict[str, Any]] = []
        self.in_flight = 0
        self.max_in_flight = 0
        self.stopped = threading.Event()
        self._lock = threading.Lock()
        fake = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"

            def log_message(self, *args: Any) -> None:
                pass

            def do_POST(self) -> None:  # noqa: N802 (http.server naming)
                length = int(self.headers.get("content-length") or 0)
                payload = json.loads(self.rfile.read(length) or b"{}")
                with fake._lock:
                    fake.requests.append({"path": self.path, "headers": {k.lower(): v for k, v in self.headers.items()}, "json": payload})
                    item = fake.script.popleft() if fake.script else error(500, "script exhausted")
                    fake.in_flight += 1
                    fake.max_in_flight = max(fake.max_in_flight, fake.in_flight)
                try:
                    if callable(item):
                        item = item(payload)
                    if item.delay:
                        time.sleep(item.delay)
                    if item.drop:
                        self.close_connection = True
                        self.connection.shutdown(2)
                        return
                    data = item.raw if item.raw is not None else json.dumps(item.body).encode()
                    kind = item.content_type or ("text/html" if item.raw is not None else "application/json")
                    if item.drip:
                        head = (f"HTTP/1.1 {item.status} OK\r\ncontent-type: {kind}\r\n"
                                f"content-length: {len(data)}\r\n\r\n").encode()
                        if item.drip_body_only:
                            self.wfile.write(head)
                            self.wfile.flush()
                            head = b""
                        for i, byte in enumerate(head + data):
                            if fake.stopped.is_set() or i > 200:
                                break
                            self.wfile.write(bytes([byte]))
                            self.wfile.flush()
                            fake.stopped.wait(item.drip)
                        self.close_connection = True
                        return
                    self.send_response(item.status)
                    self.send_header("content-type", kind)
                    self.send_header("content-length", str(len(data)))
                    for name, value in item.headers.items():
                        self.send_header(name, value)
                    self.end_headers()
                    self.wfile.write(data)
                except (BrokenPipeError, ConnectionResetError, OSError):
                    pass
                finally:
                    with fake._lock:
                        fake.in_flight -= 1

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.server.daemon_threads = True
        self.thread = threading.Thread(target=self.server.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
        self.thread.start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server.server_address[1]}/v1"

    ok = staticmethod(ok)
    error = staticmethod(error)
    Scripted = Scripted

    def add(self, *items: Scripted | Callable[[dict], Scripted]) -> None:
        self.script.extend(items)

    def close(self) -> None:
        self.stopped.set()
        self.server.shutdown()
        self.server.server_close()


@pytest.fixture
def fake_openai():
    server = FakeOpenAI()
    yield server
    server.close()


@pytest.fixture
def secret_key(monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setenv("OPENAI_API_KEY", SECRET)
    return SECRET


@pytest.fixture
def cache_dir(tmp_path):
    return tmp_path / "cache"
