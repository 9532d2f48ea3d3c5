"""Small wording helpers shared by every report, so numbers read as a person writes them."""

from __future__ import annotations


def count(n: int, word: str, plural: str | None = None) -> str:
    """`1 step`, `2 steps` (no "1 steps")."""
    return f"{n} {word if n == 1 else (plural or word + 's')}"
