"""Keep secrets out of everything we write: transcripts, cache files, logs and error messages.

Every text the LLM layer persists or shows passes through `redact`, which removes the values of the
key variables in the environment and anything shaped like a key or an auth header.
"""

from __future__ import annotations

import logging
import os
import re
from typing import Any

SECRET_ENV_VARS = ("OPENAI_API_KEY", "AZURE_OPENAI_API_KEY", "OPENROUTER_API_KEY", "OPENAI_ADMIN_KEY",
                   "ANTHROPIC_API_KEY", "GROQ_API_KEY", "TOGETHER_API_KEY", "MISTRAL_API_KEY")
_PATTERNS = [
    (re.compile(r"(?i)\b(bearer)\s+[A-Za-z0-9._~+/=-]{6,}"), r"\1 ***"),
    (re.compile(r"(?i)((?:api[-_]?key|authorization|x-api-key)[\"']?\s*[:=]\s*[\"']?)[^\s\"',}]{6,}"), r"\1***"),
    (re.compile(r"\bsk-[A-Za-z0-9_\-*]{6,}"), "sk-***"),
]
MASK = "***"


def _env_secrets() -> list[str]:
    values = [os.environ.get(name, "") for name in SECRET_ENV_VARS]
    return sorted({v for v in values if len(v) >= 8}, key=len, reverse=True)


def redact(text: str) -> str:
    if not text:
        return text
    for secret in _env_secrets():
        text = text.replace(secret, MASK)
    for pattern, replacement in _PATTERNS:
        text = pattern.sub(replacement, text)
    return text


def redact_data(value: Any) -> Any:
    """Redact every string inside a JSON-like structure."""
    if isinstance(value, str):
        return redact(value)
    if isinstance(value, dict):
        return {redact(str(k)): redact_data(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [redact_data(v) for v in value]
    return value


class RedactingFilter(logging.Filter):
    """Attached to the handlers of the loggers the SDK and HTTP stack use, so debug logging stays clean."""

    def filter(self, record: logging.LogRecord) -> bool:
        try:
            message = record.getMessage()
        except Exception:  # a broken log call is not ours to fix
            return True
        cleaned = redact(message)
        if cleaned != message:
            record.msg, record.args = cleaned, None
        return True


_INSTALLED = False


def install_log_redaction() -> None:
    """Redact records of the HTTP-facing loggers (they may print request options at DEBUG level)."""
    global _INSTALLED
    if _INSTALLED:
        return
    _INSTALLED = True
    for name in ("openai", "openai._base_client", "httpx", "httpx2", "httpcore", "httpcore2", "socnavgen.llm"):
        logging.getLogger(name).addFilter(RedactingFilter())
