"""Small wording helpers shared by every report, so numbers read as a person writes them."""

from __future__ import annotations

from collections.abc import Iterable


def count(n: int, word: str, plural: str | None = None) -> str:
    """`1 step`, `2 steps` (no "1 steps")."""
    return f"{n} {word if n == 1 else (plural or word + 's')}"


def close_matches(word: str, options: Iterable[str], n: int = 1, cutoff: float = 0.6) -> list[str]:
    """The options that look like `word` (a typo's likely meaning), best first."""
    import difflib

    return difflib.get_close_matches(word, list(options), n=n, cutoff=cutoff)


def did_you_mean(word: str, options: Iterable[str], n: int = 1, cutoff: float = 0.6) -> str | None:
    """`did you mean locations?` for a typo of one of `options`, else None."""
    close = close_matches(word, options, n, cutoff)
    return f"did you mean {' or '.join(close)}?" if close else None


def printable(text: object) -> str:
    """Untrusted text (a model's reply, a user's file) safe to print on a terminal: control characters other
    than newline and tab (ESC of a terminal escape sequence, carriage return, bell, C1 codes) are shown as
    visible escapes (\\x1b) instead of being executed by the terminal."""
    import unicodedata

    return "".join(ch if ch in "\n\t" or unicodedata.category(ch) not in ("Cc", "Cf") else repr(ch)[1:-1]
                   for ch in str(text))
