"""A small, independent GBNF interpreter for tests: parses the grammar TEXT (the subset llama.cpp
syntax our grammars use), matches strings against it, and samples random strings from it.
It does not share code with socnavgen.bt.grammar, so it checks what the text really says."""

from __future__ import annotations

import random
import re
from dataclasses import dataclass

Node = tuple  # ("lit", str) | ("cls", negated, [(lo, hi)]) | ("ref", name) | ("seq", [..]) | ("alt", [..]) | ("rep", node, lo, hi)

_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "\\": "\\", '"': '"', "[": "[", "]": "]", "-": "-", "^": "^", "/": "/"}


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text
        self.i = 0

    def ws(self) -> None:
        while self.i < len(self.text) and self.text[self.i] in " \t":
            self.i += 1

    def char(self) -> str:
        c = self.text[self.i]
        if c != "\\":
            self.i += 1
            return c
        e = self.text[self.i + 1]
        if e == "x":
            value = chr(int(self.text[self.i + 2:self.i + 4], 16))
            self.i += 4
            return value
        self.i += 2
        return _ESCAPES[e]

    def alt(self) -> Node:
        options = [self.seq()]
        while self.i < len(self.text) and self.text[self.i] == "|":
            self.i += 1
            options.append(self.seq())
        return options[0] if len(options) == 1 else ("alt", options)

    def seq(self) -> Node:
        items = []
        while True:
            self.ws()
            if self.i >= len(self.text) or self.text[self.i] in "|)":
                break
            items.append(self.postfix())
        return items[0] if len(items) == 1 else ("seq", items)

    def postfix(self) -> Node:
        node = self.atom()
        while self.i < len(self.text):
            c = self.text[self.i]
            if c == "?":
                node, self.i = ("rep", node, 0, 1), self.i + 1
            elif c == "*":
                node, self.i = ("rep", node, 0, None), self.i + 1
            elif c == "+":
                node, self.i = ("rep", node, 1, None), self.i + 1
            elif c == "{":
                m = re.compile(r"\{(\d+)(,(\d*))?\}").match(self.text, self.i)
                assert m, self.text[self.i:]
                lo = int(m.group(1))
                hi = lo if m.group(2) is None else (int(m.group(3)) if m.group(3) else None)
                node, self.i = ("rep", node, lo, hi), m.end()
            else:
                break
        return node

    def atom(self) -> Node:
        c = self.text[self.i]
        if c == '"':
            self.i += 1
            out = []
            while self.text[self.i] != '"':
                out.append(self.char())
            self.i += 1
            return ("lit", "".join(out))
        if c == "[":
            self.i += 1
            negated = self.text[self.i] == "^"
            if negated:
                self.i += 1
            ranges = []
            while self.text[self.i] != "]":
                lo = self.char()
                hi = lo
                if self.text[self.i] == "-" and self.text[self.i + 1] != "]":
                    self.i += 1
                    hi = self.char()
                ranges.append((lo, hi))
            self.i += 1
            return ("cls", negated, ranges)
        if c == "(":
            self.i += 1
            node = self.alt()
            self.ws()
            assert self.text[self.i] == ")", self.text[self.i:]
            self.i += 1
            return node
        m = re.compile(r"[a-zA-Z0-9-]+").match(self.text, self.i)
        assert m, f"bad grammar at {self.text[self.i:self.i + 30]!r}"
        self.i = m.end()
        return ("ref", m.group(0))


@dataclass
class Grammar:
    rules: dict[str, Node]

    @classmethod
    def parse(cls, text: str) -> Grammar:
        rules = {}
        for line in text.splitlines():
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            name, body = line.split("::=", 1)
            parser = _Parser(body.strip())
            rules[name.strip()] = parser.alt()
            assert parser.i == len(parser.text), f"rule {name}: trailing {parser.text[parser.i:]!r}"
        for node in rules.values():
            _check_refs(node, rules)
        return cls(rules)

    # -- matching: the set of end positions reachable from `pos` -------------------------------
    def matches(self, text: str, start: str = "root") -> bool:
        memo: dict[tuple[int, int], frozenset[int]] = {}
        return len(text) in self._ends(self.rules[start], text, 0, memo)

    def _ends(self, node: Node, text: str, pos: int, memo: dict) -> frozenset[int]:
        key = (id(node), pos)
        if key in memo:
            return memo[key]
        kind = node[0]
        if kind == "lit":
            result = frozenset([pos + len(node[1])]) if text.startswith(node[1], pos) else frozenset()
        elif kind == "cls":
            result = frozenset([pos + 1]) if pos < len(text) and _in_class(node, text[pos]) else frozenset()
        elif kind == "ref":
            result = self._ends(self.rules[node[1]], text, pos, memo)
        elif kind == "seq":
            current = {pos}
            for item in node[1]:
                current = {e for p in current for e in self._ends(item, text, p, memo)}
                if not current:
                    break
            result = frozenset(current)
        elif kind == "alt":
            result = frozenset(e for option in node[1] for e in self._ends(option, text, pos, memo))
        else:  # rep
            _, item, lo, hi = node
            current, seen, out, count = {pos}, set(), set(), 0
            while current:
                if count >= lo:
                    out |= current
                if hi is not None and count == hi:
                    break
                seen |= current
                current = {e for p in current for e in self._ends(item, text, p, memo)}
                if count >= lo:
                    current -= seen
                count += 1
            result = frozenset(out)
        memo[key] = result
        return result

    # -- sampling --------------------------------------------------------------------------------
    def sample(self, rng: random.Random, start: str = "root", max_extra: int = 3) -> str:
        out: list[str] = []
        self._sample(self.rules[start], rng, out, max_extra)
        return "".join(out)

    def _sample(self, node: Node, rng: random.Random, out: list[str], max_extra: int) -> None:
        kind = node[0]
        if kind == "lit":
            out.append(node[1])
        elif kind == "cls":
            candidates = [chr(c) for c in range(32, 127) if _in_class(node, chr(c))]
            out.append(rng.choice(candidates))
        elif kind == "ref":
            self._sample(self.rules[node[1]], rng, out, max_extra)
        elif kind == "seq":
            for item in node[1]:
                self._sample(item, rng, out, max_extra)
        elif kind == "alt":
            self._sample(rng.choice(node[1]), rng, out, max_extra)
        else:
            _, item, lo, hi = node
            top = lo + max_extra if hi is None else min(hi, lo + max_extra)
            for _ in range(rng.randint(lo, top)):
                self._sample(item, rng, out, max_extra)


def _in_class(node: Node, ch: str) -> bool:
    inside = any(lo <= ch <= hi for lo, hi in node[2])
    return inside != node[1]


def _check_refs(node: Node, rules: dict) -> None:
    kind = node[0]
    if kind == "ref":
        assert node[1] in rules, f"undefined rule {node[1]}"
    elif kind in ("seq", "alt"):
        for item in node[1]:
            _check_refs(item, rules)
    elif kind == "rep":
        _check_refs(node[1], rules)
