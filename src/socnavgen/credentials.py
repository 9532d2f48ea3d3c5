"""What counts as a secret: API key variables in the environment, keys registered at run time, and
the credentials a base URL may carry (`user:password@host`, `?api-key=...`).

The redaction of texts and logs (llm/redact.py) and the models that store a `--llm` spec
(run/models.py) both ask this module, so a new kind of secret is taught in one place.
"""

from __future__ import annotations

import os
import re
import threading

SECRET_ENV_VARS = ("OPENAI_API_KEY", "AZURE_OPENAI_API_KEY", "OPENROUTER_API_KEY", "OPENAI_ADMIN_KEY",
                   "ANTHROPIC_API_KEY", "GROQ_API_KEY", "TOGETHER_API_KEY", "MISTRAL_API_KEY")
MASK = "***"
# query parameters whose values are credentials (Azure api-key, signed URLs, OAuth tokens ...)
SECRET_QUERY_NAMES = ("api-key", "api_key", "apikey", "key", "token", "access_token", "auth", "code", "sig",
                      "signature", "password", "secret", "client_secret", "x-api-key")

_USERINFO = re.compile(r"(?i)\b([a-z][a-z0-9+.-]*://)[^/\s@?#]+@")
_QUERY_SECRET = re.compile(r"(?i)([?&;](?:" + "|".join(re.escape(n) for n in SECRET_QUERY_NAMES)
                           + r")=)[^&\s\"'#]+")
_registered: set[str] = set()
_lock = threading.Lock()


def register_secret(value: str | None) -> None:
    """Remember a secret seen at run time (a key from a URL, say) so every later text hides it."""
    for form in _forms(value or ""):
        with _lock:
            _registered.add(form)


def _forms(value: str) -> set[str]:
    """The raw value and its stripped form: a key pasted with a trailing space or CR is both."""
    return {v for v in (value, value.strip()) if v.strip()}


def known_secrets() -> list[str]:
    """Every secret value to hide, longest first (so a key is hidden before any part of it)."""
    values: set[str] = set()
    for name in SECRET_ENV_VARS:
        values |= _forms(os.environ.get(name, ""))
    with _lock:
        values |= _registered
    return sorted(values, key=len, reverse=True)


def hide_url_credentials(text: str) -> str:
    """`https://user:pw@host/v1?api-key=K` -> `https://***@host/v1?api-key=***` (anywhere in `text`)."""
    if not text or "://" not in text and "=" not in text:
        return text
    text = _USERINFO.sub(lambda m: m.group(1) + MASK + "@", text)
    return _QUERY_SECRET.sub(lambda m: m.group(1) + MASK, text)


def url_secrets(url: str) -> list[str]:
    """The credential values a URL carries (userinfo and secret query parameters), for `register_secret`."""
    from urllib.parse import parse_qsl, unquote, urlsplit

    found: list[str] = []
    try:
        parts = urlsplit(url)
    except ValueError:
        return found
    if parts.password:  # user:password@ -> the password; token@ -> the token
        found.append(unquote(parts.password))
    elif parts.username:
        found.append(unquote(parts.username))
    for name, value in parse_qsl(parts.query, keep_blank_values=False):
        if name.lower() in SECRET_QUERY_NAMES and value:
            found.append(value)
    return found
