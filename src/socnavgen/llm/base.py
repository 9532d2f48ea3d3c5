"""Interface every backend implements (openai, gguf/local, replay).

A stage calls `llm.chat(messages, schema=Model, stage="paths", key="human1")` and gets a `Reply`:
either `value` (a validated instance of the stage's pydantic model) or `error` (why the reply could
not be parsed: the caller re-queries with that text). Transport failures that retrying cannot fix
raise `socnavgen.errors.LLMError`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Generic, Literal, Protocol, TypeVar

from pydantic import BaseModel, Field

T = TypeVar("T", bound=BaseModel)


class ChatMessage(BaseModel):
    role: Literal["system", "user", "assistant"]
    content: str
    images: list[Path] = Field(default_factory=list)  # PNGs sent when the model takes images


class Usage(BaseModel):
    prompt_tokens: int = 0
    completion_tokens: int = 0
    seconds: float = 0.0
    cached: bool = False


class Reply(BaseModel, Generic[T]):
    raw: str
    value: T | None = None
    error: str | None = None  # parse/validation error of the reply, in words the model can act on
    usage: Usage = Field(default_factory=Usage)
    model: str = ""

    @property
    def ok(self) -> bool:
        return self.value is not None


class LLM(Protocol):
    spec: str  # e.g. "openai:gpt-4o", "local", "replay:file.json"
    model: str
    supports_images: bool
    supports_grammar: bool  # in-process models can constrain decoding

    def chat(self, messages: list[ChatMessage], schema: type[T], *, stage: str, key: str | None = None,
             grammar: str | None = None, temperature: float | None = None,
             max_tokens: int | None = None) -> Reply[T]:
        """One exchange. `grammar` (GBNF) is used by backends that support it, ignored by others.
        `key` names the item within a stage (e.g. the human) for replay scripts and transcripts."""
        ...
