"""The HTTP body of an OpenAI-compatible reply is untrusted like the text in it (issue 30)."""

from __future__ import annotations

import pytest

from socnavgen.errors import LLMError

from .test_llm_openai import Scenario, ask, make


@pytest.mark.parametrize("body", [
    b"[" * 100_000 + b"]" * 100_000,
    b'{"id": "x", "choices": ' + b"[" * 100_000 + b"]" * 100_000 + b"}",
])
def test_an_http_body_nested_100000_deep_is_one_clear_error(fake_openai, tmp_path, secret_key, body) -> None:  # noqa: ANN001
    """A 200 reply nested 100,000 deep raised RecursionError inside the OpenAI client."""
    fake_openai.add(fake_openai.Scripted(raw=body, content_type="application/json"))
    with pytest.raises(LLMError, match="nested"):
        make(fake_openai, tmp_path).chat(ask(), Scenario, stage="scenario")
