"""THE parser of the tree language: XML text -> typed `Document` (bt.model) and every problem with its
file and line. What it accepts is what `bt check` accepts and what the simulator runs (docs/behavior-trees.md
describes the language): library nodes by name or in the explicit <Action ID='X'/> form, each with its
ports typed by the table, controls and decorators with their arity, SubTree calls with the format's own
remapping syntax, includes of the library's own trees only (nothing is read from disk)."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache

from socnavgen.bt.library import LIBRARY, LIBRARY_TREE_XML, LIBRARY_TREES, NodeSpec, Port
from socnavgen.bt.model import (
    BLACKBOARD_REF,
    KEY_NAME,
    ROOT_MEANING,
    BTProblem,
    Document,
    LiteralError,
    Node,
    Ref,
    SubTreeCall,
    Tree,
    Value,
    display_kind,
    parse_bool,
    parse_literal,
    range_problem,
    suggest,
)
from socnavgen.bt.tree import MAX_XML_BYTES, BTElement, read_xml
from socnavgen.errors import SocnavgenError

ROOT_CHILDREN = ("BehaviorTree", "include", "TreeNodesModel")
ROOT_ATTRIBUTES = ("main_tree_to_execute", "BTCPP_format")
# BT.CPP's explicit form <Action ID="RegularNav" .../>: which library kinds each wrapper may name.
EXPLICIT_WRAPPERS: dict[str, set[str]] = {"Action": {"action", "builtin"}, "Condition": {"condition"},
                                          "Control": {"control"}, "Decorator": {"decorator"}}
SHARED_BLACKBOARD = "__shared_blackboard"  # v3: the called tree uses the caller's blackboard
AUTOREMAP = "_autoremap"  # v4: keys not remapped are the caller's keys of the same name

@cache
def library_tree(tree_id: str) -> Tree:
    """A BehaviorTree of the library's includable files (parsed once; they have no problems)."""
    file_name = next(f for f, t in LIBRARY_TREES.items() if t == tree_id)
    doc, problems = parse_document(LIBRARY_TREE_XML[file_name], file_name)
    assert doc is not None and not problems, problems
    return doc.trees[tree_id]


def parse_document(text: object, source: str = "<reply>",
                   nodes: Mapping[str, NodeSpec] | None = None) -> tuple[Document | None, list[BTProblem]]:
    """THE parser: XML text -> (Document, every problem). Never raises on bad input. The Document is None
    when the text is no tree file at all; with problems it is a best effort (unknown nodes kept with kind
    "unknown", bad ports left out) that must not be run. `nodes` is the vocabulary (default: the library,
    what the simulator runs; `bt.library.known_nodes(target)` for a target's loader)."""
    parser = _Parser(source, LIBRARY if nodes is None else nodes)
    doc = parser.run(text)
    return doc, parser.problems


class _Parser:
    def __init__(self, source: str, nodes: Mapping[str, NodeSpec]) -> None:
        self.source, self.nodes = source, nodes
        self.problems: list[BTProblem] = []
        self.version = 3
        self.known_trees: set[str] = set()

    def add(self, message: str, line: int | None) -> None:
        self.problems.append(BTProblem(message, line, self.source))

    def run(self, text: object) -> Document | None:
        if not isinstance(text, str):
            self.add(f"expected XML text, got {type(text).__name__}", None)
            return None
        if len(text) > MAX_XML_BYTES:  # cheap pre-check: characters <= bytes
            self.add(f"XML is larger than {MAX_XML_BYTES} bytes; a behavior tree is a few kilobytes", None)
            return None
        if not text.strip():
            self.add("the tree is empty; expected <root main_tree_to_execute='...'> with a <BehaviorTree>",
                     None)
            return None
        try:
            text.encode("utf-8")
        except UnicodeEncodeError as exc:
            line = text.count("\n", 0, exc.start) + 1
            self.add(f"XML does not parse: invalid character (lone surrogate) at offset {exc.start}", line)
            return None
        try:
            root = read_xml(text, self.source)
        except SocnavgenError as exc:
            self.add(exc.message, exc.line)
            return None
        return self.document(root)

    # -- the file ------------------------------------------------------------------------------------
    def document(self, root: BTElement) -> Document:
        for key in root.attrs:
            if key not in ROOT_ATTRIBUTES:
                self.add(f"unknown attribute '{key}' on <root>; allowed: {', '.join(ROOT_ATTRIBUTES)}", root.line)
        fmt = root.attrs.get("BTCPP_format")
        if fmt is not None and fmt not in ("3", "4"):
            self.add(f"BTCPP_format='{fmt}' is not supported; use 3 (or omit it) or 4", root.line)
        self.version = 4 if fmt == "4" else 3
        elements: dict[str, BTElement] = {}
        includes: list[str] = []
        for child in root.children:
            if child.tag == "BehaviorTree":
                self.collect(child, elements)
            elif child.tag == "include":
                includes += self.include(child)
            elif child.tag != "TreeNodesModel":  # Groot documentation; BT.CPP ignores it at run time
                self.add(f"unexpected <{child.tag}> directly under <root>{suggest(child.tag, ROOT_CHILDREN)}; "
                         f"<root> holds only <BehaviorTree>, <include> and <TreeNodesModel>; nodes go inside a "
                         f"<BehaviorTree ID='...'>", child.line)
        included = {LIBRARY_TREES[f] for f in includes}
        for tree_id in elements.keys() & included:
            self.add(f"BehaviorTree ID '{tree_id}' is also defined by an included library tree; choose another ID",
                     elements[tree_id].line)
        trees = {tree_id: self.tree(tree_id, elem, included | elements.keys()) for tree_id, elem in elements.items()}
        main = root.attrs.get("main_tree_to_execute")
        if main is None and len(trees) == 1 and not includes:  # BT.CPP 3.8 and 4: the only tree it knows
            main = next(iter(trees))
        if not trees:
            self.add("no <BehaviorTree ID='...'> in the file", root.line)
        elif main is None:
            self.add("<root> has no main_tree_to_execute attribute; write "
                     f"<root main_tree_to_execute='{next(iter(trees))}'>", root.line)
        elif main not in trees:
            known = ", ".join(f"'{t}'" for t in trees)
            self.add(f"main_tree_to_execute='{main}' names no <BehaviorTree> in this file"
                     f"{suggest(main, trees)}; defined: {known}", root.line)
        self.cycles(trees)
        return Document(self.source, self.version, main, trees, tuple(includes), root.line,
                        {LIBRARY_TREES[f]: library_tree(LIBRARY_TREES[f]) for f in includes})

    def collect(self, elem: BTElement, elements: dict[str, BTElement]) -> None:
        tree_id = elem.attrs.get("ID")
        if not tree_id:
            self.add("<BehaviorTree> without an ID attribute", elem.line)
            return None
        for key in elem.attrs:
            if key not in ("ID", "name"):
                self.add(f"unknown attribute '{key}' on <BehaviorTree ID='{tree_id}'>", elem.line)
        if tree_id in elements:
            self.add(f"BehaviorTree ID '{tree_id}' is defined twice", elem.line)
            return None
        elements[tree_id] = elem

    def include(self, elem: BTElement) -> list[str]:
        path = elem.attrs.get("path")
        for key in elem.attrs:
            if key != "path":
                self.add(f"unknown attribute '{key}' on <include>; write <include path='BTRegularNav.xml'/>",
                         elem.line)
        allowed = ", ".join(LIBRARY_TREES)
        if not path:
            self.add(f"<include> without a path; the library provides: {allowed}", elem.line)
        elif path.startswith(("/", "\\")) or ".." in path or "/" in path or "\\" in path or ":" in path:
            self.add(f"include path '{path}' leaves the behavior-tree library; only the library's own trees "
                     f"can be included: {allowed}", elem.line)
        elif path not in LIBRARY_TREES:
            self.add(f"include of '{path}' is not a library tree{suggest(path, LIBRARY_TREES)}; only the "
                     f"library's own trees can be included: {allowed}", elem.line)
        else:
            if elem.children:
                self.add("<include> takes no children", elem.line)
            return [path]
        return []

    def tree(self, tree_id: str, elem: BTElement, known_trees: set[str]) -> Tree:
        self.known_trees = known_trees
        if len(elem.children) != 1:
            self.add(f"<BehaviorTree ID='{tree_id}'> must have exactly one child node, it has "
                     f"{len(elem.children)}; wrap several nodes in a <Sequence> or <Fallback>", elem.line)
        roots = [self.node(child) for child in elem.children]
        return Tree(tree_id, roots[0] if len(roots) == 1 else None, elem.line, self.source)

    def cycles(self, trees: dict[str, Tree]) -> None:
        graph = {tid: [n.call.tree for n in t.root.walk() if n.call is not None] if t.root else []
                 for tid, t in trees.items()}
        state: dict[str, int] = {}

        def visit(tid: str, trail: list[str]) -> None:
            state[tid] = 1
            for nxt in graph.get(tid, []):
                if state.get(nxt) == 1:
                    cycle = " -> ".join([*trail[trail.index(nxt):], nxt]) if nxt in trail else nxt
                    self.add(f"SubTrees call each other in a loop: {cycle}", trees[tid].line)
                elif nxt in graph and nxt not in state:
                    visit(nxt, [*trail, nxt])
            state[tid] = 2

        for tid in graph:
            if tid not in state:
                visit(tid, [tid])

    # -- one node ------------------------------------------------------------------------------------
    def node(self, elem: BTElement) -> Node:
        explicit = elem.tag in EXPLICIT_WRAPPERS
        name = elem.attrs.get("ID", elem.tag) if explicit else elem.tag
        children = tuple(self.node(child) for child in elem.children)
        attrs = {k: v for k, v in elem.attrs.items() if not (explicit and k == "ID")}
        label = attrs.pop("name", None)
        spec = self.nodes.get(name)
        if explicit and "ID" not in elem.attrs:
            self.add(f"<{elem.tag}> needs an ID attribute naming a library node", elem.line)
        elif spec is None:
            self.add(self.unknown(name), elem.line)
        elif explicit and spec.kind not in EXPLICIT_WRAPPERS[elem.tag]:
            self.add(f"'{name}' is {display_kind(spec.kind)}, not a <{elem.tag}>", elem.line)
        if spec is None or (explicit and "ID" not in elem.attrs):
            return Node(name, "unknown", {}, children, elem.line, self.source, label, attrs)
        self.arity(spec, len(children), elem.line)
        if spec.kind == "subtree":
            call = self.call(dict(attrs), elem.line)
            return Node(name, spec.kind, {}, children, elem.line, self.source, label, attrs, call)
        ports = self.ports(spec, attrs, elem.line)
        return Node(name, spec.kind, ports, children, elem.line, self.source, label, attrs)

    def unknown(self, name: str) -> str:
        if name in ("BehaviorTree", "root", "include", "TreeNodesModel"):
            return f"<{name}> cannot appear inside a tree; it belongs directly under <root>"
        usable = [n.name for n in self.nodes.values() if n.in_prompt or n.kind in ("builtin", "subtree")]
        return f"unknown node '{name}'{suggest(name, self.nodes)}; available: {', '.join(usable)}"

    def arity(self, spec: NodeSpec, n: int, line: int | None) -> None:
        low, high = spec.min_children, spec.max_children
        if high == 0 and n:
            self.add(f"{spec.name} is {display_kind(spec.kind)} and cannot have child nodes (it has {n}); "
                     f"write it as <{spec.name} .../>", line)
        elif low == high and n != low:
            self.add(f"{spec.name} must have exactly {'one' if low == 1 else low} child, it has {n}", line)
        elif n < low:
            self.add(f"{spec.name} must have at least {low} child{'ren' if low != 1 else ''}, it has none", line)
        elif high is not None and n > high:
            self.add(f"{spec.name} takes at most {high} children, it has {n}", line)

    def ports(self, spec: NodeSpec, attrs: dict[str, str], line: int | None) -> dict[str, Value]:
        names = [p.name for p in spec.ports]
        ports: dict[str, Value] = {}
        for key, text in attrs.items():
            port = spec.port(key)
            if port is None:
                listed = ", ".join(names) if names else "none besides name"
                self.add(f"unknown port '{key}' on {spec.name}{suggest(key, names)}; its ports: {listed}", line)
                continue
            value = self.port_value(spec, port, text, line)
            if value is not None:
                ports[key] = value
        for port in spec.ports:
            if port.required and port.name not in attrs:
                self.add(f"{spec.name} is missing required port '{port.name}' ({port.type}: {port.description})",
                         line)
        return ports

    def port_value(self, spec: NodeSpec, port: Port, text: str, line: int | None) -> Value | None:
        where = f"{spec.name} {port.name}='{text}'"
        ref = BLACKBOARD_REF.match(text.strip())
        if spec.name == "SetBlackboard" and port.name == "output_key":
            if KEY_NAME.match(text):
                return text
            self.add(f"{where}: output_key is a blackboard key name without braces, e.g. "
                     f"output_key='agentid'", line)
            return None
        if ref:
            return Ref(ref.group(1))
        if "{" in text or "}" in text:
            self.add(f"{where}: malformed blackboard reference; write {{key}} (e.g. {{id}}, {{dt}})", line)
            return None
        if port.reads_root is not None:
            self.add(f"{where}: {port.name} must be {{{port.reads_root}}} "
                     f"({ROOT_MEANING[port.reads_root]} from the blackboard)", line)
            return None
        try:
            value = parse_literal(text, port.type)
        except LiteralError as exc:
            self.add(f"{where}: {port.name} {exc}", line)
            return None
        return value if self.in_range(where, port, value, line) else None

    def in_range(self, where: str, port: Port, value: object, line: int | None) -> bool:
        problem = range_problem(port, value)
        if problem is not None:
            self.add(f"{where}: {problem}", line)
        return problem is None

    def call(self, attrs: dict[str, str], line: int | None) -> SubTreeCall | None:
        tree_id = attrs.pop("ID", None)
        if not tree_id:
            self.add("SubTree is missing required port 'ID' (the BehaviorTree to run)", line)
            return None
        if tree_id not in self.known_trees:
            for file_name, library_id in LIBRARY_TREES.items():
                if library_id == tree_id:
                    self.add(f"SubTree '{tree_id}' needs <include path='{file_name}'/> directly under <root>", line)
                    break
            else:
                known = sorted(self.known_trees)
                self.add(f"SubTree ID '{tree_id}' names no BehaviorTree{suggest(tree_id, known)}; defined or "
                         f"included: {', '.join(known) or 'none'}", line)
        flag, other = (AUTOREMAP, SHARED_BLACKBOARD) if self.version == 4 else (SHARED_BLACKBOARD, AUTOREMAP)
        flags = {flag: False}
        remap: dict[str, Ref | str] = {}
        for key, text in attrs.items():
            if key in (flag, other, "__autoremap"):
                if key != flag:
                    self.add(f"SubTree {key}='{text}' is not BTCPP_format {self.version} syntax; write "
                             f"{flag}='true' in this format", line)
                    continue
                try:
                    flags[flag] = parse_bool(text)
                except LiteralError:
                    self.add(f"SubTree {flag}='{text}' must be true or false", line)
                continue
            remap[key] = self.remap(tree_id, key, text, line)
        return SubTreeCall(tree_id, remap, shared=flags.get(SHARED_BLACKBOARD, False),
                           autoremap=flags.get(AUTOREMAP, False))

    def remap(self, tree_id: str, key: str, text: str, line: int | None) -> Ref | str:
        ref = BLACKBOARD_REF.match(text)
        if self.version == 4:  # {key} remaps, {=} is the same name, anything else is a constant
            return Ref(key) if text == "{=}" else Ref(ref.group(1)) if ref else text
        if ref or not KEY_NAME.match(text):
            self.add(f"SubTree '{tree_id}' {key}='{text}': a remapping names a parent blackboard key without "
                     f"braces, e.g. {key}='{'agentid' if key == 'id' else 'timestep'}'", line)
        return Ref(ref.group(1) if ref else text)

