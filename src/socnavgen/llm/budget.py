"""How many tokens a conversation takes, and how many a backend's context holds.

A backend that knows its context size (gguf: the context it was loaded with, at most the model's
training context) says so in `context_tokens`, and counts a conversation with its own tokenizer and
chat template in `count_tokens`. Backends that do not know (a remote server) have `context_tokens`
None: nothing is shortened for them. The stages ask `prompt_room` before they send a prompt and
shorten it in their documented order (proposal/fit.py) when it would not fit.
"""

from __future__ import annotations

from collections.abc import Sequence

from socnavgen.llm.base import LLM, ChatMessage

CHARS_PER_TOKEN = 3.0  # English prose with JSON and ids: 3.3-4 characters a token; 3 errs on the safe side
TOKENS_PER_MESSAGE = 6  # role markers of a chat template
SAFETY_TOKENS = 32  # a counted prompt may differ by a few tokens from what the server builds


def estimate_tokens(messages: Sequence[ChatMessage]) -> int:
    """A cautious count without a tokenizer (overestimates rather than under)."""
    return sum(int(len(m.content) / CHARS_PER_TOKEN) + TOKENS_PER_MESSAGE for m in messages)


def context_tokens(llm: LLM) -> int | None:
    """The backend's context size in tokens, None when it does not know it."""
    value = getattr(llm, "context_tokens", None)
    return int(value) if isinstance(value, int) and value > 0 else None


def count_tokens(llm: LLM, messages: Sequence[ChatMessage]) -> int:
    counter = getattr(llm, "count_tokens", None)
    return int(counter(list(messages))) if callable(counter) else estimate_tokens(messages)


def prompt_room(llm: LLM, reply_tokens: int) -> int | None:
    """Tokens a prompt may take so that `reply_tokens` of answer still fit; None = no limit known."""
    context = context_tokens(llm)
    if context is None:
        return None
    return context - reply_tokens - SAFETY_TOKENS


def fits(llm: LLM, messages: Sequence[ChatMessage], reply_tokens: int) -> bool:
    room = prompt_room(llm, reply_tokens)
    return room is None or count_tokens(llm, messages) <= room
