"""`openai:MODEL[@BASE_URL]` through the official SDK: OpenAI, Azure and every OpenAI-compatible
server (Ollama, vLLM, llama.cpp server, LM Studio, OpenRouter ...).

Structured output is asked for natively (`response_format` json_schema); servers that refuse it
get json_object mode, then a plain prompt instruction, and the mode that worked is remembered.
The SDK's own retries are off: `retry.call_with_retries` retries transient failures and every
fatal one becomes a single sentence naming the backend and what to check.
"""

from __future__ import annotations

import email.utils
import json
import logging
import os
import threading
import time
from typing import Any
from urllib.parse import urlparse

import httpx
import openai

from socnavgen.credentials import hide_url_credentials, register_secret, url_secrets
from socnavgen.errors import LLMError
from socnavgen.llm.deadline import (
    MAX_REPLY_BYTES,
    BoundedTransport,
    ReplyTooLarge,
    run_with_deadline,
    too_large,
)
from socnavgen.llm.engine import Backend, Completion, LLMOptions, Request
from socnavgen.llm.redact import install_log_redaction, redact
from socnavgen.llm.retry import TransientError
from socnavgen.llm.structured import json_instruction, json_schema

log = logging.getLogger("socnavgen.llm")
MODES = ("json_schema", "json_object", "prompt")  # most to least native structured output
LOCAL_HOSTS = {"localhost", "127.0.0.1", "::1", "0.0.0.0", "[::1]"}
NO_KEY_PLACEHOLDER = "no-key-needed"


def _error_text(exc: openai.APIStatusError) -> str:
    body = exc.body
    if isinstance(body, dict):
        inner = body.get("error", body)
        if isinstance(inner, dict) and inner.get("message"):
            return str(inner["message"])
        if isinstance(inner, str):
            return inner
    return str(getattr(exc, "message", "") or exc)


def _error_code(exc: openai.APIStatusError) -> str:
    body = exc.body
    if isinstance(body, dict):
        inner = body.get("error", body)
        if isinstance(inner, dict):
            return str(inner.get("code") or inner.get("type") or "")
    return ""


def retry_after_seconds(headers: Any) -> float | None:
    """Seconds the server asks us to wait: `retry-after-ms`, `retry-after` as seconds or HTTP date."""
    if headers is None:
        return None
    value = headers.get("retry-after-ms")
    if value:
        try:
            return max(0.0, float(value) / 1000.0)
        except ValueError:
            pass
    value = headers.get("retry-after")
    if not value:
        return None
    try:
        return max(0.0, float(value))
    except ValueError:
        pass
    try:
        when = email.utils.parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    return max(0.0, when.timestamp() - time.time())


def _root_cause(exc: BaseException) -> BaseException:
    seen = set()
    while (exc.__cause__ or exc.__context__) is not None and id(exc) not in seen:
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__  # type: ignore[assignment]
    return exc


def _is_unreachable(exc: BaseException) -> bool:
    """Connection refused / unknown host: nothing listens there, so retrying will not help."""
    current: BaseException | None = exc
    while current is not None:
        if isinstance(current, ConnectionRefusedError) or type(current).__name__ == "gaierror":
            return True
        if type(current).__name__ == "ConnectError":
            text = str(current).lower()
            if "refused" in text or "name or service not known" in text or "nodename" in text \
                    or "no address" in text or "unreachable" in text:
                return True
        current = current.__cause__ or current.__context__
    return False


class OpenAIBackend(Backend):
    kind = "openai"

    def __init__(self, spec: str, model: str, base_url: str | None, options: LLMOptions) -> None:
        super().__init__(spec, model, options, supports_images=True, supports_grammar=False)
        install_log_redaction()
        raw_key = os.environ.get("OPENAI_API_KEY", "")
        register_secret(raw_key)
        for secret in url_secrets(base_url or ""):
            register_secret(secret)
        key = raw_key.strip()  # a pasted key often ends in a space or CR; the header must not
        host = urlparse(base_url).hostname if base_url else None
        if not key:
            if base_url is None:
                raise LLMError(f"{spec}: OPENAI_API_KEY is not set",
                               hint="export OPENAI_API_KEY=... (or use openai:MODEL@http://localhost:PORT/v1 "
                                    "for a local server that needs no key)")
            key = NO_KEY_PLACEHOLDER  # local and self-hosted servers often need none; a 401 will say so
        self.base_url = base_url
        self.local_server = host in LOCAL_HOSTS if host else False
        self.max_reply_bytes = MAX_REPLY_BYTES
        self._transport = BoundedTransport()
        # openai 3.x annotates http_client as its httpx2.Client; an httpx.Client works the same at run time
        # (a request through this bounded transport was checked against a local server)
        self._client = openai.OpenAI(api_key=key, base_url=base_url, max_retries=0, timeout=options.timeout,
                                     http_client=httpx.Client(transport=self._transport,  # type: ignore[arg-type]
                                                              follow_redirects=True))
        self._mode_index = 0
        self._mode_lock = threading.Lock()

    def describe(self) -> str:
        return f"{self.spec.split('@', 1)[0]} at {hide_url_credentials(str(self._client.base_url).rstrip('/'))}"

    def cache_identity(self) -> dict[str, Any]:
        return {"backend": self.kind, "model": self.model, "base_url": str(self._client.base_url)}

    @property
    def mode(self) -> str:
        return MODES[self._mode_index]

    # -- one attempt ------------------------------------------------------------------------------
    def _complete(self, request: Request, timeout: float) -> Completion:
        """One attempt, bounded as a whole: the watchdog stops a reply that drips in forever."""
        self._transport.max_bytes = self.max_reply_bytes
        return run_with_deadline(lambda: self._complete_once(request, timeout), timeout)

    def _complete_once(self, request: Request, timeout: float) -> Completion:
        while True:
            mode, images = self.mode, self.supports_images
            try:
                return self._create(request, mode, images, timeout)
            except (openai.BadRequestError, openai.UnprocessableEntityError) as exc:
                if not self._downgrade(exc, mode, images, request):
                    raise self._fatal(f"the server refused the request ({exc.status_code}: {_error_text(exc)})",
                                      "check the model's context size and the request parameters") from None
            except openai.APIStatusError as exc:
                raise self._classify_status(exc) from None
            except openai.APITimeoutError:
                raise TransientError(f"no reply within {timeout:.1f}s (timeout)") from None
            except openai.APIConnectionError as exc:
                if isinstance(_root_cause(exc), ReplyTooLarge):
                    raise too_large(self.describe(), self.max_reply_bytes) from None
                if _is_unreachable(exc):
                    raise self._fatal(f"cannot connect ({_root_cause(exc)})",
                                      "is the server running, and is the URL right?") from None
                raise TransientError(f"connection failed ({_root_cause(exc)})") from None
            except openai.APIResponseValidationError as exc:
                raise TransientError(f"the server sent a malformed response ({exc})") from None
            except ReplyTooLarge:
                raise too_large(self.describe(), self.max_reply_bytes) from None
            except RecursionError:  # the HTTP body itself nested absurdly deep (the client's json.loads gave up)
                raise self._fatal("the server's reply is JSON nested too deeply to be an OpenAI-compatible answer",
                                  "check BASE_URL and the server") from None
            except (json.JSONDecodeError, UnicodeDecodeError):  # HTTP 200 from a proxy or captive portal
                raise self._fatal("the server answered with a body that is not JSON (a proxy, captive portal "
                                  "or a URL that is not an OpenAI-compatible API?)",
                                  "check BASE_URL (it usually ends with /v1) and any proxy settings") from None
            except openai.OpenAIError as exc:
                raise self._fatal(f"the OpenAI client failed ({type(exc).__name__}: {exc})",
                                  "check the spec and the server") from None

    def _create(self, request: Request, mode: str, images: bool, timeout: float) -> Completion:
        kwargs: dict[str, Any] = {"model": self.model, "messages": self._messages(request, mode, images),
                                  "temperature": request.temperature, "timeout": timeout}
        if request.max_tokens is not None:
            kwargs["max_tokens"] = request.max_tokens
        if mode == "json_schema":
            kwargs["response_format"] = {"type": "json_schema", "json_schema": {
                "name": request.schema.__name__[:64], "schema": json_schema(request.schema), "strict": False}}
        elif mode == "json_object":
            kwargs["response_format"] = {"type": "json_object"}
        response = self._client.chat.completions.create(**kwargs)
        if isinstance(response, str | bytes):  # the SDK hands back the text of a non-JSON content type
            text = response.decode(errors="replace") if isinstance(response, bytes) else response
            if text.lstrip().startswith("<"):  # an HTML page: a proxy or captive portal, not a flaky server
                raise json.JSONDecodeError("not JSON", text[:100], 0)
            raise TransientError("the server replied without any choices")
        if not getattr(response, "choices", None):
            raise TransientError("the server replied without any choices")
        message = response.choices[0].message
        text = message.content if message.content is not None else (getattr(message, "refusal", None) or "")
        usage = response.usage
        return Completion(text=text, model=response.model or self.model,
                          prompt_tokens=getattr(usage, "prompt_tokens", 0) or 0 if usage else 0,
                          completion_tokens=getattr(usage, "completion_tokens", 0) or 0 if usage else 0,
                          extra={"response_mode": mode, "finish_reason": response.choices[0].finish_reason})

    def _messages(self, request: Request, mode: str, images: bool) -> list[dict[str, Any]]:
        texts = [m.content for m in request.messages]
        if mode != "json_schema":  # the model must learn the format from the prompt itself; it goes in
            users = [i for i, m in enumerate(request.messages) if m.role == "user"]  # the last user turn,
            if users:  # since some chat templates refuse a system message after the first turn
                texts[users[-1]] += "\n\n" + json_instruction(request.schema)
        out: list[dict[str, Any]] = []
        for message, text in zip(request.messages, texts, strict=True):
            if images and message.images and message.role == "user":
                parts: list[dict[str, Any]] = [{"type": "text", "text": text}]
                parts += [{"type": "image_url", "image_url": {"url": img.data_url()}} for img in message.images]
                out.append({"role": message.role, "content": parts})
            else:
                out.append({"role": message.role, "content": text})
        if mode != "json_schema" and not any(m.role == "user" for m in request.messages):
            out.append({"role": "user", "content": json_instruction(request.schema)})
        return out

    def _downgrade(self, exc: openai.APIStatusError, mode: str, images: bool, request: Request) -> bool:
        """On a refused request, drop what the server may not support: images, then native structure."""
        text = _error_text(exc).lower()
        with self._mode_lock:
            if images and self.supports_images and any(m.images for m in request.messages) and \
                    any(word in text for word in ("image", "vision", "multimodal", "content type", "image_url")):
                self.supports_images = False
                log.warning("%s", redact(f"{self.describe()} refused images ({_error_text(exc)}); sending text only"))
                return True
            if self.mode != mode:  # another thread already downgraded
                return True
            if self._mode_index + 1 < len(MODES):
                self._mode_index += 1
                log.warning("%s", redact(f"{self.describe()} refused response mode '{mode}' ({exc.status_code}: "
                                         f"{_error_text(exc)}); using '{self.mode}' instead"))
                return True
        return False

    # -- errors -----------------------------------------------------------------------------------
    def _fatal(self, what: str, check: str) -> LLMError:
        return LLMError(redact(f"{self.describe()}: {what}; {check}"))

    def _classify_status(self, exc: openai.APIStatusError) -> Exception:
        status, text, code = exc.status_code, _error_text(exc), _error_code(exc)
        if status == 401:
            return self._fatal("the server rejected the API key (401)", "check OPENAI_API_KEY")
        if status == 403:
            return self._fatal(f"access denied (403: {text})",
                               f"check that the key in OPENAI_API_KEY may use model '{self.model}'")
        if status == 404:
            return self._fatal(f"model '{self.model}' not found (404: {text})",
                               "check the model name (and that BASE_URL ends with /v1)")
        if status == 429 and code == "insufficient_quota":
            return self._fatal("the account has no quota left (429 insufficient_quota)",
                               "check the account's plan and billing")
        if status in (408, 409, 425, 429) or status >= 500:
            return TransientError(f"HTTP {status}: {text}", retry_after_seconds(exc.response.headers))
        return self._fatal(f"the server refused the request ({status}: {text})", "check the request and the server")
