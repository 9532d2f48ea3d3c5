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
