"""What every backend shares: cache, concurrency limit, retries, parsing, transcript, accounting.

A backend only implements `_complete(request, timeout) -> Completion` (one attempt, raising
`TransientError` or `LLMError`); `Backend.chat` does the rest, identically for all of them.
"""

from __future__ import annotations

import base64
import hashlib
import logging
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel

from socnavgen.errors import LLMError
from socnavgen.llm.base import ChatMessage, Reply, Usage
from socnavgen.llm.cache import ReplyCache, cache_key, default_cache_dir
from socnavgen.llm.redact import redact
from socnavgen.llm.retry import call_with_retries
from socnavgen.llm.structured import parse_reply, schema_text
from socnavgen.llm.transcript import Transcript, utc_now
from socnavgen.safeio import MAX_IMAGE_BYTES

T = TypeVar("T", bound=BaseModel)
log = logging.getLogger("socnavgen.llm")

DEFAULT_TEMPERATURE = 0.0  # reproducible runs by default; stages may ask for more variety


@dataclass(frozen=True)
class LLMOptions:
    transcript: Path | None = None
    cache_dir: Path | None = None
    use_cache: bool = True
    max_parallel: int = 4
    timeout: float = 120.0  # one HTTP attempt
    deadline: float = 600.0  # one exchange, retries included
    use_image: bool = True


@dataclass(frozen=True)
class ImageRef:
    name: str
    sha256: str
    data: bytes = field(repr=False)

    def data_url(self) -> str:
        return "data:image/png;base64," + base64.b64encode(self.data).decode("ascii")


@dataclass(frozen=True)
class Message:
    """A ChatMessage with its images loaded (or dropped when the backend does not take images)."""
    role: str
    content: str
    images: tuple[ImageRef, ...] = ()

    def record(self) -> dict[str, Any]:
        """The form stored in transcripts and cache keys: images by name and hash, never bytes."""
        entry: dict[str, Any] = {"role": self.role, "content": self.content}
        if self.images:
            entry["images"] = [{"file": img.name, "sha256": img.sha256} for img in self.images]
        return entry


@dataclass(frozen=True)
class Request:
    messages: tuple[Message, ...]
    schema: type[BaseModel]
    grammar: str | None
    temperature: float
    max_tokens: int | None
    stage: str = ""
    key: str | None = None


@dataclass
class Completion:
    text: str
    prompt_tokens: int = 0
    completion_tokens: int = 0
    model: str = ""
    extra: dict[str, Any] = field(default_factory=dict)  # backend details for the transcript


def load_image(path: Path) -> ImageRef:
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_IMAGE_BYTES:
            raise LLMError(f"image is {size} bytes, more than {MAX_IMAGE_BYTES}", file=path)
        data = path.read_bytes()
    except OSError as exc:
        raise LLMError(f"cannot read the image attached to the prompt ({exc.strerror})", file=path,
                       hint="check that the location folder has its scene_graph.png") from exc
    return ImageRef(name=path.name, sha256=hashlib.sha256(data).hexdigest(), data=data)


class Backend:
    """Base of every backend; thread-safe, so stages may call `chat` from a thread pool."""

    kind = "base"
    cacheable = True

    def __init__(self, spec: str, model: str, options: LLMOptions, *, supports_images: bool,
                 supports_grammar: bool) -> None:
        if options.max_parallel < 1:
            raise LLMError(f"max_parallel must be at least 1, got {options.max_parallel}")
        self.spec = spec
        self.model = model
        self.supports_images = supports_images and options.use_image
        self.supports_grammar = supports_grammar
        self.options = options
        self.transcript = Transcript(options.transcript)
        self.cache = ReplyCache(options.cache_dir or default_cache_dir()) if self.cacheable else None
        self._slots = threading.BoundedSemaphore(options.max_parallel)
        self._stats_lock = threading.Lock()
        self._stats: dict[str, dict[str, float]] = {}

    # -- to implement -----------------------------------------------------------------------------
    def _complete(self, request: Request, timeout: float) -> Completion:
        raise NotImplementedError

    def describe(self) -> str:
        """How error messages name this backend, e.g. 'openai:gpt-4o at https://api.openai.com/v1'."""
        return self.spec

    def cache_identity(self) -> dict[str, Any]:
        return {"backend": self.kind, "model": self.model}

    # -- the exchange -----------------------------------------------------------------------------
    def chat(self, messages: list[ChatMessage], schema: type[T], *, stage: str, key: str | None = None,
             grammar: str | None = None, temperature: float | None = None,
             max_tokens: int | None = None) -> Reply[T]:
        temperature = DEFAULT_TEMPERATURE if temperature is None else float(temperature)
        request = Request(messages=tuple(self._prepare(m) for m in messages), schema=schema,
                          grammar=grammar if self.supports_grammar else None,
                          temperature=temperature, max_tokens=max_tokens, stage=stage, key=key)
        entry: dict[str, Any] = {"timestamp": utc_now(), "stage": stage, "key": key, "backend": self.spec,
                                 "model": self.model, "schema": schema.__name__,
                                 "temperature": temperature, "max_tokens": max_tokens,
                                 "messages": [m.record() for m in request.messages]}
        started = time.monotonic()
        ckey = self._cache_key(request) if self._use_cache(temperature) else None
        hit = self.cache.get(ckey) if (ckey and self.cache) else None
        if hit is not None:
            completion = Completion(text=hit["raw"], model=hit.get("model") or self.model)
            attempts, cached = 0, True
        else:
            try:
                completion, attempts = call_with_retries(
                    lambda timeout: self._attempt(request, timeout), describe=self.describe(),
                    timeout=self.options.timeout, deadline=self.options.deadline)
            except LLMError as exc:
                entry.update(raw=None, value=None, error=redact(exc.render()), latency=time.monotonic() - started,
                             cached=False, fatal=True)
                self.transcript.append(entry)
                raise
            cached = False
            if ckey and self.cache:
                try:
                    self.cache.put(ckey, {"raw": completion.text, "model": completion.model or self.model,
                                          "prompt_tokens": completion.prompt_tokens,
                                          "completion_tokens": completion.completion_tokens,
                                          "created": utc_now()})
                except OSError as exc:  # a full or read-only cache must not cost the reply
                    log.warning("cannot write the LLM cache in %s (%s); continuing without it",
                                self.cache.root, exc.strerror or exc)
        seconds = time.monotonic() - started
        value, error = parse_reply(completion.text, schema)
        usage = Usage(prompt_tokens=0 if cached else completion.prompt_tokens,
                      completion_tokens=0 if cached else completion.completion_tokens,
                      seconds=seconds, cached=cached)
        entry.update(raw=completion.text, value=value.model_dump(mode="json") if value is not None else None,
                     error=error, prompt_tokens=usage.prompt_tokens, completion_tokens=usage.completion_tokens,
                     latency=round(seconds, 4), cached=cached, attempt=attempts,
                     served_by=completion.model or self.model, **completion.extra)
        self.transcript.append(entry)
        self._account(stage, usage)
        # pydantic specialises Reply for this schema at run time; mypy cannot subscript a class by a variable
        return Reply[schema](raw=completion.text, value=value, error=error, usage=usage,  # type: ignore[valid-type]
                             model=completion.model or self.model)

    def _attempt(self, request: Request, timeout: float) -> Completion:
        with self._slots:
            return self._complete(request, timeout)

    def _prepare(self, message: ChatMessage) -> Message:
        images = tuple(load_image(p) for p in message.images) if self.supports_images else ()
        return Message(role=message.role, content=message.content, images=images)

    def _use_cache(self, temperature: float) -> bool:
        return self.cacheable and self.options.use_cache and temperature == 0.0

    def _cache_key(self, request: Request) -> str:
        return cache_key({**self.cache_identity(),
                          "messages": [m.record() for m in request.messages],
                          "schema": schema_text(request.schema), "grammar": request.grammar,
                          "temperature": request.temperature, "max_tokens": request.max_tokens,
                          "images": self.supports_images})

    # -- accounting -------------------------------------------------------------------------------
    def _account(self, stage: str, usage: Usage) -> None:
        with self._stats_lock:
            totals = self._stats.setdefault(stage, {"calls": 0, "cached_calls": 0, "prompt_tokens": 0,
                                                    "completion_tokens": 0, "seconds": 0.0})
            totals["calls"] += 1
            totals["cached_calls"] += int(usage.cached)
            totals["prompt_tokens"] += usage.prompt_tokens
            totals["completion_tokens"] += usage.completion_tokens
            totals["seconds"] += usage.seconds

    def usage_by_stage(self) -> dict[str, dict[str, float]]:
        """Totals per stage (calls, cached_calls, prompt/completion tokens, seconds) for manifest.json."""
        with self._stats_lock:
            return {stage: dict(totals) for stage, totals in self._stats.items()}
