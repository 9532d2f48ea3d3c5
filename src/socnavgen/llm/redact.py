"""Keep secrets out of everything we write: transcripts, cache files, logs and error messages.

Every text the LLM layer persists or shows passes through `redact`, which removes the values of the
key variables in the environment (raw and stripped), keys registered at run time, credentials in
URLs, and anything shaped like a key or an auth header. Keys shorter than 8 characters are hidden
where they stand as a whole token (hiding every substring of a 3-letter key would garble the text).
"""

from __future__ import annotations

import logging
import re
from typing import Any

from socnavgen.credentials import MASK, hide_url_credentials, known_secrets

SHORT_SECRET = 8  # below this length a key is only hidden as a whole token
_PATTERNS = [
    (re.compile(r"(?i)\b(bearer)\s+[A-Za-z0-9._~+/=-]{6,}"), r"\1 ***"),
    (re.compile(r"(?i)((?:api[-_]?key|authorization|x-api-key)[\"']?\s*[:=]\s*[\"']?)[^\s\"',}]{6,}"), r"\1***"),
    (re.compile(r"\bsk-[A-Za-z0-9_\-*]{6,}"), "sk-***"),
]


def redact(text: str) -> str:
    if not text:
        return text
    for secret in known_secrets():
        if len(secret.strip()) >= SHORT_SECRET:
            text = text.replace(secret, MASK)
        else:
            text = re.sub(r"(?<![A-Za-z0-9_\-])" + re.escape(secret) + r"(?![A-Za-z0-9_\-])", MASK, text)
    text = hide_url_credentials(text)
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
