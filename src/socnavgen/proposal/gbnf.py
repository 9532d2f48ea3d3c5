"""A tiny grammar model for GBNF (llama.cpp's grammar format): rules are built as Python data,
rendered to GBNF for the in-process model, and matched in Python so tests can check that the
grammar admits exactly the replies we mean (without loading a model)."""

from __future__ import annotations

import re
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache


@dataclass(frozen=True)
class Lit:
    text: str


@dataclass(frozen=True)
class Ref:
    name: str


@dataclass(frozen=True)
class Chars:
    """A character class repeated min..max times, e.g. Chars('^"\\\\\\n', 0, 200)."""

    cls: str  # GBNF class body (between the brackets)
    min: int = 1
    max: int = 1

    @property
    def regex(self) -> re.Pattern[str]:
        return re.compile(f"[{self.cls}]")


Symbol = Lit | Ref | Chars


@dataclass
class Grammar:
    rules: dict[str, list[list[Symbol]]] = field(default_factory=dict)
    root: str = "root"

    def add(self, name: str, *alternatives: Sequence[Symbol]) -> str:
        if name in self.rules:
            raise ValueError(f"rule {name} defined twice")
        self.rules[name] = [list(a) for a in alternatives]
        return name

    # -- rendering -------------------------------------------------------------------------------
    def to_gbnf(self) -> str:
        lines = []
        for name, alts in self.rules.items():
            body = " | ".join(" ".join(_render(s) for s in alt) if alt else '""' for alt in alts)
            lines.append(f"{name} ::= {body}")
        return "\n".join(lines) + "\n"

    # -- matching ----------------------------------------------------------------------------------
    def matches(self, text: str) -> bool:
        """True when `text` is exactly a sentence of the grammar."""
        limit = sys.getrecursionlimit()
        sys.setrecursionlimit(max(limit, 20_000))
        try:
            return len(text) in self._ends(text)(self.root, 0)
        finally:
            sys.setrecursionlimit(limit)

    def _ends(self, text: str):  # noqa: ANN202 - returns a memoised closure
        rules = self.rules

        @cache
        def rule_ends(name: str, pos: int) -> frozenset[int]:
            out: set[int] = set()
            for alt in rules[name]:
                out |= seq_ends(alt, 0, pos)
            return frozenset(out)

        def seq_ends(alt: list[Symbol], i: int, pos: int) -> set[int]:
            if i == len(alt):
                return {pos}
            out: set[int] = set()
            for nxt in sym_ends(alt[i], pos):
                out |= seq_ends(alt, i + 1, nxt)
            return out

        def sym_ends(sym: Symbol, pos: int) -> set[int]:
            if isinstance(sym, Lit):
                return {pos + len(sym.text)} if text.startswith(sym.text, pos) else set()
            if isinstance(sym, Ref):
                return set(rule_ends(sym.name, pos))
            pattern, out, count, p = sym.regex, set(), 0, pos
            if sym.min == 0:
                out.add(pos)
            while count < sym.max and p < len(text) and pattern.fullmatch(text[p]):
                p += 1
                count += 1
                if count >= sym.min:
                    out.add(p)
            return out

        return rule_ends


def literal(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _render(sym: Symbol) -> str:
    if isinstance(sym, Lit):
        return literal(sym.text)
    if isinstance(sym, Ref):
        return sym.name
    rep = "" if (sym.min, sym.max) == (1, 1) else f"{{{sym.min},{sym.max}}}"
    return f"[{sym.cls}]{rep}"


# JSON string content without quotes, backslashes or control characters: what a model may write
# inside a free-text field. The first character of a non-empty text is not a space.
TEXT_CHAR = '^"\\\\\\x00-\\x1f'
TEXT_START = '^"\\\\\\x00-\\x20'


# Prose (scenario texts): no angle brackets or braces either, so a small model cannot copy the answer
# template's `<...>` placeholders or spill JSON punctuation into a behavior.
PROSE_CHAR = '^"\\\\<>{}\\x00-\\x1f'
PROSE_START = '^"\\\\<>{}\\x00-\\x20'


def text_rules(grammar: Grammar, name: str, max_chars: int, *, non_empty: bool, prose: bool = False) -> str:
    char, start = (PROSE_CHAR, PROSE_START) if prose else (TEXT_CHAR, TEXT_START)
    if non_empty:
        grammar.add(name, [Chars(start, 1, 1), Chars(char, 0, max_chars - 1)])
    else:
        grammar.add(name, [Chars(char, 0, max_chars)])
    return name
