"""A tree file as it runs: the main tree with its SubTree calls expanded and every blackboard reference
resolved to the entry it names (`Instance`), and the blackboard's data flow checked. SubTree semantics
are decided here, once (BT.CPP v3.8 / v4):

- v3 `<SubTree ID='T' k='parent_key'/>`: T gets its own blackboard; its key `k` IS the caller's entry
  `parent_key` (reads and writes go through); other keys are T's own. `__shared_blackboard='true'`: T uses
  the caller's blackboard itself.
- v4 `<SubTree ID='T' k='{parent_key}'/>` remaps the same way (`k='{=}'` = the same name), and a plain
  value `k='2.5'` is a constant T's entry `k` holds from the start; `_autoremap='true'`: keys not
  remapped name the caller's entries of the same name (except keys starting with `_`).

The data flow is checked in document order (what a tick does when every Sequence runs through): an entry
is read only after something set it; `agent_id` reads the agent's own `{id}` and `time_step` the step
`{dt}` (through any remaps and SetBlackboard copies); a literal text held in an entry converts to the type
of every port reading it; an `other_human` port never reads the agent's own id.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Literal

from socnavgen.bt.library import ROOT_KEYS, NodeSpec, Port, PortType
from socnavgen.bt.model import (
    ROOT_MEANING,
    BTProblem,
    Document,
    Entry,
    LiteralError,
    Node,
    Ref,
    Value,
    parse_literal,
    range_problem,
    suggest,
)
from socnavgen.bt.parse import parse_document
from socnavgen.bt.tree import MAX_ELEMENTS
from socnavgen.errors import ValidationFailed

MAX_SUBTREE_DEPTH = 16
ROOT_ID, ROOT_DT = Entry(0, "id"), Entry(0, "dt")


@dataclass(frozen=True)
class Instance:
    """The main tree of a valid document, ready to lower (see bt.model's docstring)."""

    document: Document
    root: Node  # SubTree calls replaced by the called trees' roots; references are `Entry`s
    constants: dict[Entry, str] = field(default_factory=dict)  # set by v4 SubTree calls before their tree runs

    @property
    def source(self) -> str:
        return self.document.source


class TreeProblems(ValidationFailed):
    """A tree that cannot run; `problems` lists every reason with its file and line."""

    def __init__(self, source: str, problems: list[BTProblem]) -> None:
        self.problems = problems
        super().__init__("behavior tree has problems:\n  " + "\n  ".join(str(p) for p in problems), file=source,
                         hint="socnavgen bt check FILE lists them; docs/behavior-trees.md describes the language")


def check_text(text: object, source: str = "<reply>", nodes: dict[str, NodeSpec] | None = None
               ) -> tuple[Document | None, Instance | None, list[BTProblem]]:
    """Parse and expand: (document, instance, every problem). The instance is None unless there is none."""
    doc, problems = parse_document(text, source, nodes)
    if doc is None or doc.main is None or doc.main.root is None:
        return doc, None, problems
    instance, flow = expand(doc)
    problems += flow
    return doc, instance if not problems else None, problems


@lru_cache(maxsize=512)
def load_instance(text: str, source: str = "<tree>") -> Instance:
    """The runnable instance of a tree file (any library node), or TreeProblems naming every problem."""
    _, instance, problems = check_text(text, source)
    if instance is None:
        raise TreeProblems(source, problems)
    return instance


def expand(doc: Document) -> tuple[Instance | None, list[BTProblem]]:
    """The main tree expanded, and the problems of its SubTree calls and blackboard data flow."""
    main = doc.main
    if main is None or main.root is None:
        return None, [BTProblem(f"main tree {doc.main_tree!r} is not defined", doc.line, doc.source)]
    expander = _Expander(doc)
    root = expander.node(main.root, expander.root_scope, 0)
    problems = list(dict.fromkeys(expander.problems))  # a key read by several nodes is named once
    if root is None:
        return None, problems
    return Instance(doc, root, expander.constants), problems


# ---- expansion ---------------------------------------------------------------------------------------
Hop = tuple[Node, str, str]  # the SubTree call, the called tree's key, the value written for it


@dataclass
class _Scope:
    id: int
    parent: _Scope | None = None
    call: Node | None = None  # the SubTree call that made this blackboard
    autoremap: bool = False
    remap: dict[str, tuple[Entry, Hop | None]] = field(default_factory=dict)
    used: set[str] = field(default_factory=set)  # keys looked up here


@dataclass(frozen=True)
class _Held:
    """What an entry holds at a point of the document: the root's id or dt, or a literal text."""

    kind: Literal["id", "dt", "text"]
    text: str = ""
    constant: tuple[Node, str] | None = None  # the v4 SubTree call and key that set it (for the hint)

    def describe(self) -> str:
        return f"'{self.text}'" if self.kind == "text" else f"{{{self.kind}}}"


class _Expander:
    def __init__(self, doc: Document) -> None:
        self.doc = doc
        self.problems: list[BTProblem] = []
        self.root_scope = _Scope(0)
        self.scopes = [self.root_scope]
        self.held: dict[Entry, _Held] = {ROOT_ID: _Held("id"), ROOT_DT: _Held("dt")}
        self.constants: dict[Entry, str] = {}
        self.count = 0
        self.stack: list[str] = []
        self.anchor: Node | None = None  # the call into a library tree (its problems are reported there)

    def add(self, message: str, node: Node) -> None:
        if node.source != self.doc.source and self.anchor is not None:
            message += f" (in {node.source}:{node.line})"
            node = self.anchor
        self.problems.append(BTProblem(message, node.line, self.doc.source))

    def resolve(self, scope: _Scope, key: str) -> tuple[Entry, Hop | None]:
        hop: Hop | None = None
        while True:
            scope.used.add(key)
            if key in scope.remap:
                entry, inner = scope.remap[key]
                return entry, inner or hop
            if scope.autoremap and scope.parent is not None and not key.startswith("_") and scope.call is not None:
                hop, scope = (scope.call, key, "_autoremap"), scope.parent
                continue
            return Entry(scope.id, key), hop

    # -- nodes ---------------------------------------------------------------------------------------
    def node(self, node: Node, scope: _Scope, depth: int) -> Node | None:
        self.count += 1
        if self.count == MAX_ELEMENTS + 1:
            self.add(f"the tree has more than {MAX_ELEMENTS} nodes once its SubTrees are expanded", node)
        if self.count > MAX_ELEMENTS:
            return None
        if node.call is not None:
            return self.call(node, scope, depth)
        ports: dict[str, Value] = {}
        copied: _Held | None = None
        for name, value in node.ports.items():
            if isinstance(value, Ref):
                entry, hop = self.resolve(scope, value.key)
                ports[name] = entry
                copied = self.read(node, name, entry, hop)
            else:
                ports[name] = value
        if node.name == "SetBlackboard" and "output_key" in node.ports:
            out = ports["output_key"] = self.resolve(scope, str(node.ports["output_key"]))[0]
            given = node.ports.get("value")
            held = copied if isinstance(given, Ref) else _Held("text", given) if isinstance(given, str) else None
            if held is not None:
                self.held[out] = held
        kids = [self.node(child, scope, depth) for child in node.children]
        return replace(node, ports=ports, children=tuple(k for k in kids if k is not None))

    def call(self, node: Node, scope: _Scope, depth: int) -> Node | None:
        call = node.call
        assert call is not None
        tree = self.doc.tree(call.tree)
        if tree is None or tree.root is None:
            return None  # reported by the parser
        if call.tree in self.stack or depth >= MAX_SUBTREE_DEPTH:
            self.add(f"SubTree '{call.tree}' calls itself or nests more than {MAX_SUBTREE_DEPTH} levels", node)
            return None
        inner = scope
        if not call.shared:
            inner = _Scope(len(self.scopes), scope, node, call.autoremap)
            self.scopes.append(inner)
            for key, target in call.remap.items():
                if isinstance(target, Ref):
                    entry, hop = self.resolve(scope, target.key)
                    inner.remap[key] = (entry, hop or (node, key, node.attrs.get(key, str(target))))
                else:
                    entry = Entry(inner.id, key)
                    inner.remap[key] = (entry, None)
                    self.constants[entry] = target
                    self.held[entry] = _Held("text", target, constant=(node, key))
        anchor = self.anchor
        if anchor is None and tree.source != self.doc.source:
            self.anchor = node
        self.stack.append(call.tree)
        root = self.node(tree.root, inner, depth + 1)
        self.stack.pop()
        self.anchor = anchor
        if not call.shared:
            for key in call.remap:
                if key not in inner.used:
                    reads = ", ".join(sorted(inner.used)) or "nothing"
                    self.add(f"SubTree '{call.tree}' remaps '{key}', which that tree never reads; it reads: {reads}",
                             node)
        return root

    # -- data flow -----------------------------------------------------------------------------------
    def read(self, node: Node, name: str, entry: Entry, hop: Hop | None) -> _Held | None:
        spec = node.spec
        port = spec.port(name) if spec is not None else None
        where = f"{node.name} {name}='{node.attrs.get(name, '')}'"
        held = self.held.get(entry)
        if held is None:
            self.unset(node, where, entry, hop)
            return None
        if port is None or node.name == "SetBlackboard":
            return held
        problem = self.mismatch(port, entry, held)
        if problem is not None and held.constant is not None:
            call, key = held.constant
            assert call.call is not None
            text = call.attrs.get(key, "")
            self.add(f"SubTree '{call.call.tree}' {key}='{text}': in BTCPP_format 4 a plain value is a constant, "
                     f"not the caller's entry ({problem}); write {key}='{{{text}}}' to pass the entry '{text}'", call)
        elif problem is not None:
            self.add(f"{where}: {problem}", node)
        return held

    def mismatch(self, port: Port, entry: Entry, held: _Held) -> str | None:
        if port.reads_root is not None:
            if held.kind != port.reads_root:
                return (f"{port.name} must be {{{port.reads_root}}} ({ROOT_MEANING[port.reads_root]} from the "
                        f"blackboard); {entry} holds {held.describe()}")
            return None
        if port.other_human and held.kind == "id":
            return f"{port.name} {{id}} is the human itself; write the other human's id"
        if port.type is PortType.STRING:
            return None
        if held.kind != "text":
            have = ROOT_KEYS[held.kind]
            return f"{port.name} is {port.type} but {entry} holds a {have}" if have is not port.type else None
        try:
            return range_problem(port, parse_literal(held.text, port.type))
        except LiteralError as exc:
            return f"{entry} holds '{held.text}', and {port.name} {exc}"

    def unset(self, node: Node, where: str, entry: Entry, hop: Hop | None) -> None:
        if hop is not None:
            call, key, text = hop
            assert call.call is not None
            self.add(f"SubTree '{call.call.tree}' {key}='{text}': blackboard key '{entry.key}' is not set before "
                     f"this SubTree; add <SetBlackboard output_key='{entry.key}' value='{{{key}}}'/> before it",
                     call)
        elif entry.scope != 0 and (outer := self.scopes[entry.scope].call) is not None:
            call = outer
            assert call.call is not None
            self.add(f"SubTree '{call.call.tree}' does not pass blackboard key '{entry.key}'; copy it first with "
                     f"<SetBlackboard output_key='...' value='{{{entry.key}}}'/> and remap it, e.g. "
                     f"<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>", call)
        else:
            known = [e.key for e in self.held if e.scope == entry.scope]
            self.add(f"{where}: blackboard key '{entry.key}' is never set{suggest(entry.key, known)}; known keys: "
                     f"{', '.join(sorted(known))}", node)
