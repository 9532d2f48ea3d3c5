"""The tree language, typed: the `Document` that ONE parser (bt.parse.parse_document) makes of BT.CPP v3/v4
XML, used by `bt check`, the simulator, the exporters, stage 3's tree needs and the verifier's expectations.

    bt.tree      XML read defensively (defusedxml; size, depth and element limits) -> elements with lines
    bt.parse     elements -> `Document` (the types of this module): every node resolved against the library
                 table, every port value parsed ONCE by the port's declared type (`parse_literal`), every
                 problem with file and line
    bt.expand    `Document` -> `Instance`: the main tree with its SubTree calls expanded and every blackboard
                 reference resolved to the entry it names; the blackboard's data flow checked
    bt.validate  `bt check`: the same problems, plus what an export target and a scenario add

What a lowering (the simulator's) reads, from `bt.expand.load_instance(text, source)`:
- `Instance.root`, a `Node`: `name` (registered name), `kind` (the library's: action, condition, control,
  decorator, builtin) and `spec` (its `NodeSpec` row: `flow`/`reactive` of controls, `rule`/`count_port` of
  decorators, `moves`/`gate`/`interaction` of leaves), `children`, `line` and `source` (the file the node
  is written in: the tree's own, or a library file such as BTRegularNav.xml) for error messages.
- `Node.ports`: each written port as a typed value: an int, float, bool or str literal (already converted
  by `parse_literal` with the port's type), or an `Entry` (a blackboard entry: `scope` 0 is the agent's
  root blackboard holding `id` (int) and `dt` (double), each isolated SubTree call has its own scope).
  `Node.value(port)` adds the table's default of a port left out. SubTree calls are gone from an
  Instance: a call is replaced by the called tree's root (BT.CPP's SubTree node only passes its child's
  status through); `__shared_blackboard` / `_autoremap` / remapping only decide which entry a key names.
- SetBlackboard: `ports["output_key"]` is the `Entry` written, `ports["value"]` an `Entry` (copied) or
  a literal text (str); a text held in an entry is converted by the port that reads it, with
  `parse_literal`, and `bt check` has checked that every such read converts.
- `Instance.constants`: entries a BTCPP_format 4 SubTree call sets to a literal text before its tree runs.
Every Instance has passed every check: no unknown node, port, literal, arity or unset entry remains.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Literal

from socnavgen.bt.library import LIBRARY, NodeKind, NodeSpec, Port, PortType

KEY_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
BLACKBOARD_REF = re.compile(r"^\{([A-Za-z_][A-Za-z0-9_]*)\}$")
INT_LITERAL = re.compile(r"^[+-]?[0-9]+$")
DOUBLE_LITERAL = re.compile(r"^[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?$")
# exactly BT.CPP's convertFromString<bool> (v3.8 and v4)
BOOL_LITERALS = {"true": True, "True": True, "TRUE": True, "1": True,
                 "false": False, "False": False, "FALSE": False, "0": False}
INT_RANGE = 2 ** 31  # BT.CPP reads int ports as a C++ int
ROOT_MEANING = {"id": "the human's own id", "dt": "the simulation step"}


# ---- values -------------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Ref:
    """`{key}` as written: a reference to an entry of the blackboard of the tree it is written in."""

    key: str

    def __str__(self) -> str:
        return "{" + self.key + "}"


@dataclass(frozen=True, slots=True)
class Entry:
    """A blackboard entry once SubTree remapping is resolved (bt.expand): `scope` 0 is the agent's root
    blackboard, each isolated SubTree call adds a scope; `key` is the entry's name in its scope."""

    scope: int
    key: str

    def __str__(self) -> str:
        return "{" + self.key + "}"


Value = int | float | bool | str | Ref | Entry


class LiteralError(ValueError):
    """A literal that is not of its port's type; the message says what it must be."""


def parse_bool(text: str) -> bool:
    """A bool literal exactly as BT.CPP converts it (true/True/TRUE/1, false/False/FALSE/0)."""
    if text not in BOOL_LITERALS:
        raise LiteralError("must be true or false")
    return BOOL_LITERALS[text]


def parse_literal(text: str, type_: PortType) -> int | float | bool | str:
    """THE conversion of a literal port text to the port's type (spaces around a number are ignored)."""
    if type_ is PortType.STRING:
        return text
    if type_ is PortType.BOOL:
        return parse_bool(text)
    number = text.strip()
    if type_ is PortType.INT:
        if not INT_LITERAL.match(number):
            raise LiteralError("must be an integer")
        if abs(int(number)) >= INT_RANGE:
            raise LiteralError("is out of range for an int")
        return int(number)
    if not DOUBLE_LITERAL.match(number) or not math.isfinite(float(number)):
        raise LiteralError("must be a number like 2.0")
    return float(number)


def range_problem(port: Port, value: object) -> str | None:
    """What is wrong with a literal of the right type for this port (a code outside its table, a number
    outside its bounds), or None."""
    if port.allowed is not None and value not in port.allowed:
        table = ", ".join(f"{k} {v}" for k, v in port.allowed.items())
        return f"code {value} is not allowed; codes: {table}"
    low, high = port.bounds()
    if isinstance(value, int | float) and not isinstance(value, bool):
        if low is not None and value < low:
            return f"{port.name} cannot be negative" if low == 0 else f"{port.name} must be at least {low:g}"
        if high is not None and value > high:
            return f"{port.name} must be at most {high:g}"
    return None


def literal_text(value: Value) -> str:
    """A value written back as XML attribute text ({key} for references, true/false for bools)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


# ---- the typed tree -----------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class SubTreeCall:
    """A SubTree call: which tree, and how the called tree's keys name the caller's entries."""

    tree: str
    remap: Mapping[str, Ref | str]  # called tree's key -> the caller's entry, or a constant text (v4)
    shared: bool = False  # v3 __shared_blackboard: the called tree uses the caller's blackboard itself
    autoremap: bool = False  # v4 _autoremap: keys not remapped name the caller's entries of the same name


@dataclass(frozen=True, eq=False, slots=True)
class Node:
    """One node of a tree (identity equality: two equal-looking nodes at different places differ)."""

    name: str  # the registered name (the explicit form <Action ID='X'/> gives X)
    kind: NodeKind | Literal["unknown"]  # from the library table; "unknown" only in a Document with problems
    ports: Mapping[str, Value] = field(default_factory=dict)  # written ports, typed (see value())
    children: tuple[Node, ...] = ()
    line: int | None = None
    source: str = "<tree>"
    label: str | None = None  # the free-text `name` attribute
    attrs: Mapping[str, str] = field(default_factory=dict)  # the attributes as written (exporters copy them)
    call: SubTreeCall | None = None  # SubTree nodes of a Document (an Instance has none)

    @property
    def spec(self) -> NodeSpec | None:
        return LIBRARY.get(self.name)

    def value(self, port: str) -> Value | None:
        """The port's value: as written, else the table's default (parsed), else None."""
        if port in self.ports:
            return self.ports[port]
        spec = self.spec
        declared = spec.port(port) if spec is not None else None
        if declared is None or declared.default is None:
            return None
        return parse_literal(declared.default, declared.type)

    def walk(self) -> Iterator[Node]:
        """This node and every node below it, in document order (pre-order)."""
        yield self
        for child in self.children:
            yield from child.walk()

    def walk_with_path(self, path: tuple[Node, ...] = ()) -> Iterator[tuple[Node, tuple[Node, ...]]]:
        """(node, its ancestors from the top) for this node and every node below it, in document order."""
        yield self, path
        for child in self.children:
            yield from child.walk_with_path((*path, self))


@dataclass(frozen=True, slots=True)
class Tree:
    """A `<BehaviorTree ID=...>`; `root` is None when it does not hold exactly one node (a problem)."""

    id: str
    root: Node | None
    line: int | None
    source: str


@dataclass(frozen=True, slots=True)
class Document:
    """A tree file: its own BehaviorTrees, the library files it includes, the tree to run."""

    source: str
    format_version: int  # 3, or 4 with BTCPP_format="4"
    main_tree: str | None
    trees: Mapping[str, Tree]  # this file's own BehaviorTrees, by ID
    includes: tuple[str, ...] = ()  # library tree files included (bt.library.LIBRARY_TREES)
    line: int | None = None  # of <root>
    included: Mapping[str, Tree] = field(default_factory=dict)  # the included files' trees, by ID

    def tree(self, tree_id: str) -> Tree | None:
        """A tree of this file, or of a library file it includes."""
        return self.trees.get(tree_id) or self.included.get(tree_id)

    @property
    def main(self) -> Tree | None:
        return self.trees.get(self.main_tree) if self.main_tree is not None else None


@dataclass(frozen=True)
class BTProblem:
    """One mistake in a tree: what is wrong, where (line), in which file or reply."""

    message: str
    line: int | None = None
    source: str = "<reply>"

    def __str__(self) -> str:
        where = f"{self.source}:{self.line}" if self.line else self.source
        return f"{where}: {self.message}"


def suggest(word: str, options: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def display_kind(kind: str) -> str:
    return {"action": "an action", "condition": "a condition", "control": "a control node",
            "decorator": "a decorator", "builtin": "a built-in node", "subtree": "a subtree call"}.get(kind, kind)


