"""Errors a user can act on: they carry the file, the line and what to do, and the CLI prints them
without a traceback."""

from __future__ import annotations

from pathlib import Path


class SocnavgenError(Exception):
    """Base class of errors shown to the user as one clear message (no traceback)."""

    def __init__(self, message: str, *, file: Path | str | None = None, line: int | None = None,
                 hint: str | None = None) -> None:
        self.message = message
        self.file = str(file) if file is not None else None
        self.line = line
        self.hint = hint
        super().__init__(self.render())

    def render(self) -> str:
        where = ""
        if self.file:
            where = self.file + (f":{self.line}" if self.line else "") + ": "
        text = where + self.message
        if self.hint:
            text += f"\n  -> {self.hint}"
        return text


class InputFileError(SocnavgenError):
    """A user file is missing, too large, or malformed."""


class ValidationFailed(SocnavgenError):
    """Content parsed but breaks a rule (schema, graph, library)."""


class LLMError(SocnavgenError):
    """A model backend failed in a way retrying will not fix (bad key, unknown model, no server)."""


class StageFailed(SocnavgenError):
    """A pipeline stage used up its attempts; the run folder keeps everything."""
