"""The only way the pipeline talks to models: `make_llm(spec)` returns an `LLM`."""

from socnavgen.llm.base import LLM, ChatMessage, Reply, Usage
from socnavgen.llm.factory import make_llm

__all__ = ["LLM", "ChatMessage", "Reply", "Usage", "make_llm"]
