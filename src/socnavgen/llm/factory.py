"""`make_llm(spec)`: turn an `--llm` spec into a backend.

Accepted forms: openai:MODEL, openai:MODEL@BASE_URL, gguf:PATH, local, replay:FILE.
"""

from __future__ import annotations

from pathlib import Path

from socnavgen.errors import LLMError
from socnavgen.llm.base import LLM
from socnavgen.llm.engine import LLMOptions

ACCEPTED_FORMS = ("openai:MODEL (e.g. openai:gpt-4o)",
                  "openai:MODEL@BASE_URL (e.g. openai:llama3.1@http://localhost:11434/v1)",
                  "gguf:PATH (a .gguf file run in-process)",
                  "local (the bundled SmolLM2-135M smoke-test model)",
                  "replay:FILE (scripted replies or a recorded transcript.jsonl)")


def _bad_spec(spec: str, why: str) -> LLMError:
    return LLMError(f"bad --llm spec {spec!r}: {why}", hint="use one of: " + "; ".join(ACCEPTED_FORMS))


def make_llm(spec: str, *, transcript: Path | None = None, cache_dir: Path | None = None,
             use_cache: bool = True, max_parallel: int = 4, timeout: float = 120.0, deadline: float = 600.0,
             use_image: bool = True) -> LLM:
    """Build the backend `spec` names. Options: `transcript` (the run's transcript.jsonl), `cache_dir`
    (default $SOCNAVGEN_CACHE_DIR or ~/.cache/socnavgen/llm), `use_cache` (False = --no-cache),
    `max_parallel` (requests in flight), `timeout` (one attempt, s), `deadline` (one exchange with its
    retries, s), `use_image` (False = --no-image)."""
    spec = (spec or "").strip()
    options = LLMOptions(transcript=Path(transcript) if transcript else None,
                         cache_dir=Path(cache_dir) if cache_dir else None, use_cache=use_cache,
                         max_parallel=max_parallel, timeout=timeout, deadline=deadline, use_image=use_image)
    kind, sep, rest = spec.partition(":")
    if spec == "local":
        from socnavgen.llm.backends.gguf_backend import (
            LOCAL_MAX_STRING,
            LOCAL_SAMPLING,
            LOCAL_THREADS,
            GGUFBackend,
            smollm2_path,
        )
        return GGUFBackend("local", smollm2_path(), options, model_name="SmolLM2-135M-Instruct",
                           max_string=LOCAL_MAX_STRING, sampling=LOCAL_SAMPLING, threads=LOCAL_THREADS)
    if not sep:
        raise _bad_spec(spec, "unknown form")
    rest = rest.strip()
    if kind == "openai":
        model, at, base_url = rest.partition("@")
        model, base_url = model.strip(), base_url.strip()
        if not model:
            raise _bad_spec(spec, "the model name is missing")
        if at and not base_url.startswith(("http://", "https://")):
            raise _bad_spec(spec, "BASE_URL must start with http:// or https://")
        from socnavgen.llm.backends.openai_backend import OpenAIBackend
        return OpenAIBackend(spec, model, base_url or None, options)
    if kind == "gguf":
        if not rest:
            raise _bad_spec(spec, "the .gguf path is missing")
        from socnavgen.llm.backends.gguf_backend import GGUFBackend
        return GGUFBackend(spec, Path(rest), options)
    if kind == "replay":
        if not rest:
            raise _bad_spec(spec, "the replay file is missing")
        from socnavgen.llm.backends.replay_backend import ReplayBackend
        return ReplayBackend(spec, Path(rest).expanduser(), options)
    raise _bad_spec(spec, f"unknown backend {kind!r}")
