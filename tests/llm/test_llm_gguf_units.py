"""gguf backend pieces that need no model run: grammar bounds and clear errors when parts are missing."""

from __future__ import annotations

import sys

import pytest
from pydantic import BaseModel

from socnavgen.errors import LLMError
from socnavgen.llm import make_llm
from socnavgen.llm.backends.gguf_backend import cap_string_lengths, require_llama_cpp


class Inner(BaseModel):
    label: str
    kind: str = "x"


class Outer(BaseModel):
    title: str
    mode: str = "a"
    items: list[Inner]
    note: str | None = None


def test_free_strings_get_a_length_bound_and_constraints_are_kept():
    schema = Outer.model_json_schema()
    schema["properties"]["mode"] = {"type": "string", "enum": ["a", "b"]}
    capped = cap_string_lengths(schema, 50)
    assert capped["properties"]["title"]["maxLength"] == 50
    assert capped["$defs"]["Inner"]["properties"]["label"]["maxLength"] == 50
    assert capped["properties"]["note"]["anyOf"][0]["maxLength"] == 50
    assert "maxLength" not in capped["properties"]["mode"]  # an enum is already bounded
    assert "maxLength" not in schema["properties"]["title"]  # the original is not modified
    assert cap_string_lengths(schema, 0) is schema


def test_missing_llama_cpp_is_a_clear_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "llama_cpp", None)
    with pytest.raises(LLMError, match="llama-cpp-python") as info:
        require_llama_cpp()
    assert "socnavgen[local]" in str(info.value)


def test_a_file_that_is_not_gguf_fails_to_load_clearly(tmp_path):
    import llama_cpp  # noqa: F401  (the [local] extra, installed by `make test`)
    fake = tmp_path / "model.gguf"
    fake.write_bytes(b"not a model")
    llm = make_llm(f"gguf:{fake}")
    with pytest.raises(LLMError, match="cannot load the model"):
        llm._load()


def test_the_local_model_knows_its_context_and_counts_prompts_as_llama_cpp_builds_them(monkeypatch):
    """No weights loaded: the tokenizer alone (a vocabulary-only load) counts, and the GGUF metadata says
    the context the model was trained for, which caps SOCNAVGEN_GGUF_N_CTX."""
    from socnavgen.llm import ChatMessage
    from socnavgen.llm.budget import estimate_tokens

    monkeypatch.setenv("SOCNAVGEN_GGUF_N_CTX", "4096")
    llm = make_llm("local", use_cache=False)
    assert llm.context_tokens == 4096
    monkeypatch.setenv("SOCNAVGEN_GGUF_N_CTX", "100000")
    assert make_llm("local", use_cache=False).context_tokens == 8192  # SmolLM2-135M was trained for 8192
    messages = [ChatMessage(role="system", content="You plan paths."),
                ChatMessage(role="user", content="Plan a path from up to f7 through co and 54. " * 20)]
    counted = llm.count_tokens(messages)
    one = llm.count_tokens(messages[:1])
    assert 0 < one < counted and abs(counted - estimate_tokens(messages)) < counted / 2  # the estimate is close
    assert llm._llm is None  # counting never loaded the weights


def test_the_local_model_decodes_on_one_thread_and_the_environment_overrides(monkeypatch):
    monkeypatch.delenv("SOCNAVGEN_GGUF_THREADS", raising=False)
    assert make_llm("local").threads == 1  # two threads stalled for minutes when another process held a core
    monkeypatch.setenv("SOCNAVGEN_GGUF_THREADS", "3")
    assert make_llm("local").threads == 3
    monkeypatch.setenv("SOCNAVGEN_GGUF_THREADS", "two")
    with pytest.raises(LLMError, match="SOCNAVGEN_GGUF_THREADS='two' is not a whole number"):
        make_llm("local")
