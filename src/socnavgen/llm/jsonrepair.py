"""Find and repair the JSON inside a model's free-text reply.

Servers that ignore structured-output requests (and small local models) wrap JSON in prose or code
fences, use Python literals, single quotes, trailing commas or unquoted keys. Strict `json.loads`
is tried first; only when it fails does the lenient parser below run. A reply that still cannot be
read raises `JSONRepairError` whose message tells the model what to fix.
"""

from __future__ import annotations

import re
from typing import Any, Literal

from socnavgen.safeio import MAX_INT_DIGITS, parse_json_text

MAX_REPLY_CHARS = 1_000_000  # a reply larger than this is not a stage answer
MAX_DEPTH = 200
MAX_START_TRIES = 40  # how many '{' / '[' positions to try in prose before giving up

_FENCE = re.compile(r"```[ \t]*([A-Za-z0-9_+-]*)[ \t]*\n?(.*?)(?:```|\Z)", re.DOTALL)
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_BARE_KEY = re.compile(r"[A-Za-z_$][\w$\-. ]*?(?=\s*:)")
_WORD = re.compile(r"[A-Za-z_]+")
_LITERALS = {"true": True, "false": False, "null": None, "True": True, "False": False, "None": None}
_SIMPLE_ESCAPES = {'"': '"', "'": "'", "\\": "\\", "/": "/", "b": "\b", "f": "\f", "n": "\n", "r": "\r",
                   "t": "\t", "0": "\0"}

Expect = Literal["object", "array", "any"]


class JSONRepairError(ValueError):
    """The reply holds no readable JSON value; the message is written for the model to act on."""


class _SyntaxProblem(Exception):
    def __init__(self, message: str, pos: int) -> None:
        super().__init__(message)
        self.message = message
        self.pos = pos


def extract_json(text: str, expect: Expect = "object") -> Any:
    """Return the JSON value in `text` (an object by default), repairing common slips."""
    if not isinstance(text, str):
        raise JSONRepairError("the reply is not text")
    if len(text) > MAX_REPLY_CHARS:
        raise JSONRepairError(f"the reply is {len(text)} characters long; reply with one JSON value only")
    text = text.lstrip("\ufeff")
    if not text.strip():
        raise JSONRepairError("the reply is empty; reply with one JSON object")
    first_problem: tuple[str, str, int] | None = None
    for candidate in _candidates(text):
        try:
            value = parse_json_text(candidate, max_depth=MAX_DEPTH)
        except (ValueError, RecursionError):  # syntax, depth or integer-size limits: the scanner explains
            pass
        else:
            if _fits(value, expect):
                return value
        value, problem = _scan(candidate, expect)
        if problem is None:
            return value
        if first_problem is None and problem[0] != "none":
            first_problem = (candidate, problem[1], problem[2])
    if first_problem is None:
        what = {"object": "JSON object ({...})", "array": "JSON array ([...])", "any": "JSON value"}[expect]
        raise JSONRepairError(f"the reply contains no {what}; reply with the JSON only, no prose")
    candidate, message, pos = first_problem
    raise JSONRepairError(f"invalid JSON: {message} ({_where(candidate, pos)})")


def _candidates(text: str) -> list[str]:
    """Code-fenced blocks first (a model that fences usually fences the answer), then the whole text."""
    fenced = [m.group(2).strip() for m in _FENCE.finditer(text)]
    fenced.sort(key=lambda block: 0 if block[:1] in "{[" else 1)
    return [*[f for f in fenced if f], text.strip()]


def _fits(value: Any, expect: Expect) -> bool:
    if expect == "object":
        return isinstance(value, dict)
    if expect == "array":
        return isinstance(value, list)
    return True


def _scan(text: str, expect: Expect) -> tuple[Any, tuple[str, str, int] | None]:
    """Try the lenient parser at each opening bracket; return the first value that fits."""
    openers = {"object": "{", "array": "[", "any": "{["}[expect]
    starts = [i for i, ch in enumerate(text) if ch in openers][:MAX_START_TRIES]
    if expect == "any" and not starts:
        starts = [len(text) - len(text.lstrip())]
    first: tuple[str, str, int] | None = None
    for start in starts:
        parser = _Lenient(text, start)
        try:
            value = parser.parse_value(0)
        except _SyntaxProblem as exc:
            if first is None:
                first = ("syntax", exc.message, exc.pos)
            continue
        except RecursionError:
            if first is None:
                first = ("syntax", "nesting is too deep", start)
            continue
        if _fits(value, expect):
            return value, None
    return None, first or ("none", "", 0)


def _where(text: str, pos: int) -> str:
    line = text.count("\n", 0, pos) + 1
    column = pos - (text.rfind("\n", 0, pos) + 1) + 1
    snippet = text[max(0, pos - 20):pos + 20].replace("\n", " ")
    return f"line {line}, column {column}, near {snippet!r}"


class _Lenient:
    """Recursive-descent parser for JSON plus the slips language models make."""

    def __init__(self, text: str, pos: int) -> None:
        self.text = text
        self.pos = pos

    def fail(self, message: str) -> _SyntaxProblem:
        return _SyntaxProblem(message, self.pos)

    def skip(self) -> None:
        text, n = self.text, len(self.text)
        while self.pos < n:
            ch = text[self.pos]
            if ch in " \t\r\n\u00a0":
                self.pos += 1
            elif text.startswith("//", self.pos):
                end = text.find("\n", self.pos)
                self.pos = n if end < 0 else end + 1
            elif text.startswith("/*", self.pos):
                end = text.find("*/", self.pos + 2)
                self.pos = n if end < 0 else end + 2
            else:
                return

    def peek(self) -> str:
        self.skip()
        return self.text[self.pos] if self.pos < len(self.text) else ""

    def parse_value(self, depth: int) -> Any:
        if depth > MAX_DEPTH:
            raise self.fail("nesting is too deep")
        ch = self.peek()
        if ch == "{":
            return self.parse_object(depth + 1)
        if ch == "[":
            return self.parse_array(depth + 1)
        if ch in "\"'":
            return self.parse_string()
        if ch and (ch.isdigit() or ch in "+-."):
            return self.parse_number()
        if ch == "":
            raise self.fail("the reply ends where a value was expected (was it cut off?)")
        word = _WORD.match(self.text, self.pos)
        if word and word.group(0) in _LITERALS:
            self.pos = word.end()
            return _LITERALS[word.group(0)]
        shown = word.group(0) if word else ch
        raise self.fail(f"unexpected {shown!r} where a value was expected (strings need double quotes)")

    def parse_object(self, depth: int) -> dict[str, Any]:
        self.pos += 1  # '{'
        result: dict[str, Any] = {}
        while True:
            ch = self.peek()
            if ch == "}":
                self.pos += 1
                return result
            if ch == "":
                raise self.fail("the JSON object is not closed with '}' (was the reply cut off?)")
            if ch == ",":  # stray or trailing comma
                self.pos += 1
                continue
            key = self.parse_key()
            if self.peek() not in (":", "="):
                raise self.fail(f"expected ':' after the key {key!r}")
            self.pos += 1
            result[key] = self.parse_value(depth)
            after = self.peek()
            if after == ",":
                self.pos += 1
            elif after == "}" or after in "\"'":  # missing comma before the next key is tolerated
                continue
            elif after == "":
                raise self.fail("the JSON object is not closed with '}' (was the reply cut off?)")
            else:
                raise self.fail(f"expected ',' or '}}' after the value of {key!r}")

    def parse_key(self) -> str:
        ch = self.peek()
        if ch in "\"'":
            return self.parse_string()
        bare = _BARE_KEY.match(self.text, self.pos)
        if bare and bare.group(0).strip():
            self.pos = bare.end()
            return bare.group(0).strip()
        if ch.isdigit() or ch == "-":  # numeric keys, e.g. {1: "a"}
            number = _NUMBER.match(self.text, self.pos)
            if number:
                self.pos = number.end()
                return number.group(0)
        raise self.fail("expected a quoted key")

    def parse_array(self, depth: int) -> list[Any]:
        self.pos += 1  # '['
        result: list[Any] = []
        while True:
            ch = self.peek()
            if ch == "]":
                self.pos += 1
                return result
            if ch == "":
                raise self.fail("the JSON array is not closed with ']' (was the reply cut off?)")
            if ch == ",":
                self.pos += 1
                continue
            result.append(self.parse_value(depth))
            after = self.peek()
            if after == ",":
                self.pos += 1
            elif after == "]":
                continue
            elif after == "":
                raise self.fail("the JSON array is not closed with ']' (was the reply cut off?)")
            elif after in "\"'{[":  # missing comma between items
                continue
            else:
                raise self.fail("expected ',' or ']' between array items")

    def parse_number(self) -> int | float:
        match = _NUMBER.match(self.text, self.pos)
        if not match:
            raise self.fail("malformed number")
        self.pos = match.end()
        literal = match.group(0).lstrip("+")
        if re.fullmatch(r"-?\d+", literal):
            if len(literal.lstrip("-")) > MAX_INT_DIGITS:
                raise self.fail(f"an integer of {len(literal.lstrip('-'))} digits is not a sensible value")
            return int(literal)
        return float(literal)

    def parse_string(self) -> str:
        text, n = self.text, len(self.text)
        quote = text[self.pos]
        start = self.pos
        self.pos += 1
        out: list[str] = []
        while True:
            if self.pos >= n:
                self.pos = start
                raise self.fail("a string is not closed (missing quote)")
            ch = text[self.pos]
            if ch == "\\":
                out.append(self.parse_escape())
                continue
            if ch == quote:
                if self._closes(self.pos + 1):
                    self.pos += 1
                    return "".join(out)
                out.append(ch)  # an unescaped quote inside the text, e.g. "he said "stop" twice"
                self.pos += 1
                continue
            out.append(ch)
            self.pos += 1

    def _closes(self, pos: int) -> bool:
        """A quote ends its string only if what follows can follow a string."""
        text, n = self.text, len(self.text)
        begin = pos
        while pos < n and text[pos] in " \t\r\n":
            pos += 1
        if pos >= n or text[pos] in ",:}]=" or text.startswith("//", pos) or text.startswith("/*", pos):
            return True
        return "\n" in text[begin:pos] and text[pos] in "\"'"  # next key on the next line, comma missing

    def parse_escape(self) -> str:
        text = self.text
        code = text[self.pos + 1:self.pos + 2]
        if code in _SIMPLE_ESCAPES:
            self.pos += 2
            return _SIMPLE_ESCAPES[code]
        width = {"u": 4, "x": 2, "U": 8}.get(code)
        if width:
            digits = text[self.pos + 2:self.pos + 2 + width]
            if len(digits) == width and all(c in "0123456789abcdefABCDEF" for c in digits):
                self.pos += 2 + width
                value = int(digits, 16)
                if code == "u" and 0xD800 <= value < 0xDC00 and text.startswith("\\u", self.pos):
                    low = text[self.pos + 2:self.pos + 6]
                    if len(low) == 4 and all(c in "0123456789abcdefABCDEF" for c in low) \
                            and 0xDC00 <= int(low, 16) < 0xE000:
                        self.pos += 6
                        value = 0x10000 + ((value - 0xD800) << 10) + (int(low, 16) - 0xDC00)
                if value > 0x10FFFF:
                    raise self.fail("invalid unicode escape")
                return chr(value)
        if code == "":
            raise self.fail("a string ends with a lone backslash")
        self.pos += 2  # unknown escape such as \q: keep the character
        return code
