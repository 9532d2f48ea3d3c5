"""The `--review` hook: after each stage a person accepts the result, asks for a fresh try, or types
an edit request that goes back to the model as a user message (as in SocRATES)."""

from __future__ import annotations

from typing import Literal, Protocol

from pydantic import BaseModel


class ReviewDecision(BaseModel):
    action: Literal["accept", "retry", "edit"] = "accept"
    request: str = ""  # the edit request, for action == "edit"


class ReviewHook(Protocol):
    def __call__(self, stage: str, key: str | None, result: str) -> ReviewDecision:
        """Show `result` (the stage's answer as JSON or XML) and return the person's decision."""
        ...
