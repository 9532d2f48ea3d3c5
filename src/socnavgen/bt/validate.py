"""The behavior-tree validator: one function used by stage 3 (re-query on mistakes), by
`socnavgen bt check` (people editing trees by hand) and by the exporters (target support).

Every rule derives from the node library table (`socnavgen.bt.library`); every problem names the
exact mistake and its line, so a model or a person can fix it without guessing. Hostile input
never raises: it becomes a problem.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from socnavgen.bt.library import (
    LIBRARY,
    LIBRARY_TREE_XML,
    LIBRARY_TREES,
    NodeSpec,
    Port,
    PortType,
    hunav2_refusal,
)
from socnavgen.bt.library import TARGETS as LIBRARY_TARGETS
from socnavgen.bt.tree import MAX_XML_BYTES, BTDocument, BTElement, parse_bt
from socnavgen.errors import SocnavgenError
from socnavgen.text import close_matches

TARGETS = LIBRARY_TARGETS  # spelled once, in bt.library
MAX_PROBLEMS = 50  # more than this is noise for a model (and for a person)

ROOT_CHILDREN = ("BehaviorTree", "include", "TreeNodesModel")
ROOT_ATTRIBUTES = ("main_tree_to_execute", "BTCPP_format")
# BT.CPP's explicit form <Action ID="RegularNav" .../>: which library kinds each wrapper may name.
EXPLICIT_WRAPPERS = {"Action": {"action", "builtin"}, "Condition": {"condition"}, "Control": {"control"},
                     "Decorator": {"decorator"}}
BLACKBOARD_REF = re.compile(r"^\{([A-Za-z_][A-Za-z0-9_]*)\}$")
KEY_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
INT_LITERAL = re.compile(r"^[+-]?[0-9]+$")
DOUBLE_LITERAL = re.compile(r"^[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?$")
BOOL_LITERALS = {"true": True, "True": True, "TRUE": True, "1": True,
                 "false": False, "False": False, "FALSE": False, "0": False}
# Entries every agent's root blackboard holds (HuNavSim sets them before each tick).
ROOT_KEYS: dict[str, PortType] = {"id": PortType.INT, "dt": PortType.DOUBLE}
SHARED_BLACKBOARD = "__shared_blackboard"  # v3; v4 spells it _autoremap
AUTOREMAP = "_autoremap"


@dataclass(frozen=True)
class BTProblem:
    """One mistake in a tree: what is wrong, where (line), in which file or reply."""

    message: str
    line: int | None = None
    source: str = "<reply>"

    def __str__(self) -> str:
        where = f"{self.source}:{self.line}" if self.line else self.source
        return f"{where}: {self.message}"


def validate_bt_text(text: str, source: str = "<reply>", *, target: str = "socrates",
                     human_ids: set[int] | None = None, agent_id: int | None = None) -> list[BTProblem]:
    """Every problem of a BT XML text (empty list = valid). Never raises on bad input.

    `target` reports nodes the export target cannot run; `human_ids` (the ids of the scenario's
    humans) bounds HumanSays/FollowHuman `target_id`; `agent_id` (the tree's own human) forbids
    targeting oneself.
    """
    try:
        return _Checker(source, target, human_ids, agent_id).run(text)
    except RecursionError:
        return [BTProblem("tree is nested too deeply to check", None, source)]
    except Exception as exc:  # noqa: BLE001 - the contract: hostile input is a problem, not a crash
        return [BTProblem(f"could not check the tree ({type(exc).__name__}: {exc})", None, source)]


def validate_bt_file(path: Path | str, *, target: str = "socrates", human_ids: set[int] | None = None,
                     agent_id: int | None = None) -> list[BTProblem]:
    """Validate a tree file. Includes are resolved against the library's own trees, never the disk."""
    from socnavgen.safeio import read_text_limited

    source = str(path)
    try:
        text = read_text_limited(Path(path), limit=MAX_XML_BYTES)
    except SocnavgenError as exc:
        return [BTProblem(exc.message + (f" ({exc.hint})" if exc.hint else ""), exc.line, source)]
    except OSError as exc:
        return [BTProblem(f"cannot read the file: {exc.strerror or exc}", None, source)]
    return validate_bt_text(text, source, target=target, human_ids=human_ids, agent_id=agent_id)


def format_problems(problems: Iterable[BTProblem]) -> str:
    """Problems one per line, as appended to a re-query and printed by `bt check`."""
    return "\n".join(str(p) for p in problems)


# ------------------------------------------------------------------------------------------------
@dataclass
class _TreeInfo:
    """What a BehaviorTree reads from and writes to its blackboard (for SubTree remapping checks)."""

    element: BTElement
    reads: set[str] = field(default_factory=set)
    writes: set[str] = field(default_factory=set)
    subtrees: list[BTElement] = field(default_factory=list)


def _display(kind: str) -> str:
    return {"action": "an action", "condition": "a condition", "control": "a control node",
            "decorator": "a decorator", "builtin": "a built-in node"}[kind]


def _suggest(word: str, options: Iterable[str]) -> str:
    close = close_matches(word, options)
    return f" (did you mean '{close[0]}'?)" if close else ""


@cache
def _library_tree_infos() -> dict[str, _TreeInfo]:
    """BehaviorTrees of the library's includable files, by ID (parsed once)."""
    infos: dict[str, _TreeInfo] = {}
    for file_name, xml in LIBRARY_TREE_XML.items():
        doc = parse_bt(xml, file_name)
        for tree_id, elem in doc.trees.items():
            infos[tree_id] = _scan_tree(elem)
    return infos


def _bare_key(value: str) -> str:
    ref = BLACKBOARD_REF.match(value)
    return ref.group(1) if ref else value


def _node_name(elem: BTElement) -> str:
    if elem.tag in EXPLICIT_WRAPPERS and "ID" in elem.attrs:
        return elem.attrs["ID"]
    return elem.tag


def _scan_tree(tree: BTElement) -> _TreeInfo:
    info = _TreeInfo(tree)
    for elem in tree.walk():
        if elem is tree:
            continue
        name = _node_name(elem)
        if name == "SubTree":
            info.subtrees.append(elem)
            for key, value in elem.attrs.items():
                if key not in ("ID", "name", SHARED_BLACKBOARD, AUTOREMAP):
                    ref = BLACKBOARD_REF.match(value)
                    info.reads.add(ref.group(1) if ref else value)
            continue
        if name == "SetBlackboard" and "output_key" in elem.attrs:
            info.writes.add(_bare_key(elem.attrs["output_key"]))
        for key, value in elem.attrs.items():
            ref = BLACKBOARD_REF.match(value)
            if ref and key not in ("name", "output_key"):
                info.reads.add(ref.group(1))
    return info


class _Checker:
    def __init__(self, source: str, target: str, human_ids: set[int] | None, agent_id: int | None) -> None:
        self.source = source
        self.target = target
        self.human_ids = set(human_ids) if human_ids is not None else None
        self.agent_id = agent_id
        self.problems: list[BTProblem] = []
        self.included_trees: dict[str, _TreeInfo] = {}
        self.local_trees: dict[str, _TreeInfo] = {}
        self.version = 3

    def add(self, message: str, line: int | None) -> None:
        self.problems.append(BTProblem(message, line, self.source))

    # -- top level -------------------------------------------------------------------------------
    def run(self, text: object) -> list[BTProblem]:
        if not isinstance(text, str):
            self.add(f"expected XML text, got {type(text).__name__}", None)
            return self.problems
        if len(text) > MAX_XML_BYTES:  # cheap pre-check: characters <= bytes
            self.add(f"XML is larger than {MAX_XML_BYTES} bytes; a behavior tree is a few kilobytes", None)
            return self.problems
        if not text.strip():
            self.add("the tree is empty; expected <root main_tree_to_execute='...'> with a <BehaviorTree>", None)
            return self.problems
        try:
            text.encode("utf-8")
        except UnicodeEncodeError as exc:
            line = text.count("\n", 0, exc.start) + 1
            self.add(f"XML does not parse: invalid character (lone surrogate) at offset {exc.start}", line)
            return self.problems
        try:
            doc = parse_bt(text, self.source)
        except SocnavgenError as exc:
            self.add(exc.message, exc.line)
            return self.problems
        self.version = doc.format_version
        if self.target not in TARGETS:
            self.add(f"unknown target '{self.target}'; targets: {', '.join(TARGETS)}", None)
        self.check_root(doc)
        for tree_id, info in self.local_trees.items():
            self.check_tree(tree_id, info, is_main=(tree_id == doc.main_tree))
        self.check_subtree_cycles()
        if len(self.problems) > MAX_PROBLEMS:
            extra = len(self.problems) - MAX_PROBLEMS
            self.problems = self.problems[:MAX_PROBLEMS]
            self.add(f"... and {extra} more problems (fix the ones above first)", None)
        return self.problems

    def check_root(self, doc: BTDocument) -> None:
        root = doc.root
        for key in root.attrs:
            if key not in ROOT_ATTRIBUTES:
                self.add(f"unknown attribute '{key}' on <root>; allowed: {', '.join(ROOT_ATTRIBUTES)}", root.line)
        fmt = root.attrs.get("BTCPP_format")
        if fmt is not None and fmt not in ("3", "4"):
            self.add(f"BTCPP_format='{fmt}' is not supported; use 3 (or omit it) or 4", root.line)
        for child in root.children:
            if child.tag == "BehaviorTree":
                self.collect_tree(child)
            elif child.tag == "include":
                self.check_include(child)
            elif child.tag == "TreeNodesModel":
                continue  # Groot documentation; BT.CPP ignores it at run time
            else:
                self.add(f"unexpected <{child.tag}> directly under <root>{_suggest(child.tag, ROOT_CHILDREN)}; "
                         f"<root> holds only <BehaviorTree>, <include> and <TreeNodesModel>; nodes go inside a "
                         f"<BehaviorTree ID='...'>", child.line)
        for tree_id in self.local_trees.keys() & self.included_trees.keys():
            self.add(f"BehaviorTree ID '{tree_id}' is also defined by an included library tree; choose another ID",
                     self.local_trees[tree_id].element.line)
        if not self.local_trees:
            self.add("no <BehaviorTree ID='...'> in the file", root.line)
            return
        main = doc.main_tree
        if main is None:
            self.add("<root> has no main_tree_to_execute attribute; write "
                     f"<root main_tree_to_execute='{next(iter(self.local_trees))}'>", root.line)
        elif main not in self.local_trees:
            known = ", ".join(f"'{t}'" for t in self.local_trees)
            self.add(f"main_tree_to_execute='{main}' names no <BehaviorTree> in this file"
                     f"{_suggest(main, self.local_trees)}; defined: {known}", root.line)

    def collect_tree(self, elem: BTElement) -> None:
        tree_id = elem.attrs.get("ID")
        if not tree_id:
            self.add("<BehaviorTree> without an ID attribute", elem.line)
            return
        for key in elem.attrs:
            if key not in ("ID", "name"):
                self.add(f"unknown attribute '{key}' on <BehaviorTree ID='{tree_id}'>", elem.line)
        if tree_id in self.local_trees:
            self.add(f"BehaviorTree ID '{tree_id}' is defined twice", elem.line)
            return
        self.local_trees[tree_id] = _scan_tree(elem)

    def check_include(self, elem: BTElement) -> None:
        path = elem.attrs.get("path")
        for key in elem.attrs:
            if key != "path":
                self.add(f"unknown attribute '{key}' on <include>; write <include path='BTRegularNav.xml'/>",
                         elem.line)
        allowed = ", ".join(LIBRARY_TREES)
        if not path:
            self.add(f"<include> without a path; the library provides: {allowed}", elem.line)
            return
        if path.startswith(("/", "\\")) or ".." in path or "/" in path or "\\" in path or ":" in path:
            self.add(f"include path '{path}' leaves the behavior-tree library; only the library's own trees "
                     f"can be included: {allowed}", elem.line)
            return
        if path not in LIBRARY_TREES:
            self.add(f"include of '{path}' is not a library tree{_suggest(path, LIBRARY_TREES)}; only the "
                     f"library's own trees can be included: {allowed}", elem.line)
            return
        if elem.children:
            self.add("<include> takes no children", elem.line)
        tree_id = LIBRARY_TREES[path]
        self.included_trees[tree_id] = _library_tree_infos()[tree_id]

    # -- one BehaviorTree ------------------------------------------------------------------------
    def check_tree(self, tree_id: str, info: _TreeInfo, *, is_main: bool) -> None:
        elem = info.element
        if len(elem.children) != 1:
            self.add(f"<BehaviorTree ID='{tree_id}'> must have exactly one child node, it has "
                     f"{len(elem.children)}; wrap several nodes in a <Sequence> or <Fallback>", elem.line)
        # Keys set so far (in document order) in this tree's blackboard: SubTree remaps must refer to them.
        self.known_keys: dict[str, PortType | None] = dict(ROOT_KEYS) if is_main else {}
        self.is_main = is_main
        self.tree_info = info
        for child in elem.children:
            self.check_node(child)

    def check_node(self, elem: BTElement) -> None:
        name = _node_name(elem)
        if elem.tag in EXPLICIT_WRAPPERS and "ID" not in elem.attrs:
            self.add(f"<{elem.tag}> needs an ID attribute naming a library node", elem.line)
            return
        spec = LIBRARY.get(name)
        if spec is not None and spec.targets == {"hunav2"} and self.target != "hunav2":
            spec = None  # a HuNavSim 2.x node (hunav2 exports only): unknown to the v3 node libraries
        if spec is None:
            self.add(self.unknown_node_message(name), elem.line)
            for child in elem.children:  # still report mistakes below it
                self.check_node(child)
            return
        if elem.tag in EXPLICIT_WRAPPERS and spec.kind not in EXPLICIT_WRAPPERS[elem.tag]:
            self.add(f"'{name}' is {_display(spec.kind)}, not a <{elem.tag}>", elem.line)
        if self.target in TARGETS and self.target not in spec.targets:
            self.add(self.target_message(spec), elem.line)
        self.check_children(spec, elem)
        if name == "SubTree":
            self.check_subtree(elem)
        else:
            self.check_ports(spec, elem)
        if name == "SetBlackboard":
            key = _bare_key(elem.attrs.get("output_key", ""))
            value = elem.attrs.get("value", "")
            ref = BLACKBOARD_REF.match(value)
            self.known_keys[key] = self.known_keys.get(ref.group(1)) if ref else None
        for child in elem.children:
            self.check_node(child)

    def unknown_node_message(self, name: str) -> str:
        if name in ("BehaviorTree", "root", "include", "TreeNodesModel"):
            return f"<{name}> cannot appear inside a tree; it belongs directly under <root>"
        # Suggest from every node; list the ones the model is taught (plus the SubTree idiom's built-ins).
        usable = [n.name for n in LIBRARY.values() if (n.in_prompt or n.kind == "builtin")
                  and (self.target not in TARGETS or self.target in n.targets)]
        known = {k: v for k, v in LIBRARY.items() if self.target == "hunav2" or v.targets != {"hunav2"}}
        return f"unknown node '{name}'{_suggest(name, known)}; available: {', '.join(usable)}"

    def target_message(self, spec: NodeSpec) -> str:
        if self.target == "hunav2" and hunav2_refusal(spec.name):
            return f"node '{spec.name}' is not supported by target hunav2: {hunav2_refusal(spec.name)}"
        equivalent = getattr(spec, self.target, None) if self.target != "socrates" else None
        hint = f" (its {self.target} counterpart is '{equivalent}')" if equivalent else ""
        return f"node '{spec.name}' is not supported by target {self.target}{hint}"

    def check_children(self, spec: NodeSpec, elem: BTElement) -> None:
        n = len(elem.children)
        if spec.kind == "decorator" and n != 1:
            self.add(f"{spec.name} must have exactly one child, it has {n}", elem.line)
        elif spec.kind == "control" and n < spec.min_children:
            self.add(f"{spec.name} must have at least {spec.min_children} child"
                     f"{'ren' if spec.min_children != 1 else ''}, it has none", elem.line)
        elif spec.kind in ("action", "condition", "builtin") and n:
            self.add(f"{spec.name} is {_display(spec.kind)} and cannot have child nodes (it has {n}); "
                     f"write it as <{spec.name} .../>", elem.line)
        elif spec.max_children is not None and spec.kind == "control" and n > spec.max_children:
            self.add(f"{spec.name} takes at most {spec.max_children} children, it has {n}", elem.line)

    # -- ports -----------------------------------------------------------------------------------
    def check_ports(self, spec: NodeSpec, elem: BTElement) -> None:
        port_names = [p.name for p in spec.ports]
        for key, value in elem.attrs.items():
            if key == "name" or (key == "ID" and elem.tag in EXPLICIT_WRAPPERS):
                continue
            port = spec.port(key)
            if port is None:
                ports = ", ".join(port_names) if port_names else "none besides name"
                self.add(f"unknown port '{key}' on {spec.name}{_suggest(key, port_names)}; its ports: {ports}",
                         elem.line)
                continue
            self.check_value(spec, port, value, elem)
        for port in spec.ports:
            if port.required and port.name not in elem.attrs and port.name != "name":
                self.add(f"{spec.name} is missing required port '{port.name}' ({port.type}: {port.description})",
                         elem.line)

    def check_value(self, spec: NodeSpec, port: Port, value: str, elem: BTElement) -> None:
        where = f"{spec.name} {port.name}='{value}'"
        ref = BLACKBOARD_REF.match(value.strip())
        if port.name == "agent_id" and value != "{id}":
            self.add(f"{where}: agent_id must be {{id}} (the human's own id from the blackboard)", elem.line)
            return
        if port.name == "time_step" and value != "{dt}":
            self.add(f"{where}: time_step must be {{dt}} (the simulation step from the blackboard)", elem.line)
            return
        if spec.name == "SetBlackboard":
            if port.name == "output_key" and not KEY_NAME.match(value) and not (self.version >= 4 and ref):
                self.add(f"{where}: output_key is a blackboard key name without braces, e.g. "
                         f"output_key='agentid'", elem.line)
            elif port.name == "value" and ref and ref.group(1) not in self.known_keys and self.is_main:
                self.add(f"{where}: blackboard key '{ref.group(1)}' is never set; known keys: "
                         f"{', '.join(sorted(self.known_keys))}", elem.line)
            return
        if ref:
            self.check_ref(where, port, ref.group(1), elem)
            return
        if "{" in value or "}" in value:
            self.add(f"{where}: malformed blackboard reference; write {{key}} (e.g. {{id}}, {{dt}})", elem.line)
            return
        literal = value.strip()
        if port.type is PortType.INT:
            if not INT_LITERAL.match(literal):
                self.add(f"{where}: {port.name} must be an integer", elem.line)
                return
            number = int(literal)
            if port.allowed is not None and number not in port.allowed:
                table = ", ".join(f"{k} {v}" for k, v in port.allowed.items())
                self.add(f"{where}: code {number} is not allowed; codes: {table}", elem.line)
            elif port.name == "target_id":
                self.check_target_id(where, number, elem)
        elif port.type is PortType.DOUBLE:
            if not DOUBLE_LITERAL.match(literal) or not math.isfinite(float(literal)):
                self.add(f"{where}: {port.name} must be a number like 2.0", elem.line)
            elif float(literal) < 0:
                self.add(f"{where}: {port.name} cannot be negative", elem.line)
        elif port.type is PortType.BOOL and literal not in BOOL_LITERALS:
            self.add(f"{where}: {port.name} must be true or false", elem.line)

    def check_ref(self, where: str, port: Port, key: str, elem: BTElement) -> None:
        if not self.is_main:
            return  # a subtree's keys come from its caller's remapping (checked at the SubTree)
        if key not in self.known_keys:
            self.add(f"{where}: blackboard key '{key}' is never set{_suggest(key, self.known_keys)}; known keys: "
                     f"{', '.join(sorted(self.known_keys))}", elem.line)
            return
        held = self.known_keys[key]
        if held is not None and held is not port.type and port.type is not PortType.STRING:
            self.add(f"{where}: {port.name} is {port.type} but {{{key}}} holds a {held}", elem.line)
        elif port.name == "target_id" and key == "id":
            self.add(f"{where}: target_id {{id}} is the human itself; write the other human's id", elem.line)

    def check_target_id(self, where: str, number: int, elem: BTElement) -> None:
        if self.agent_id is not None and number == self.agent_id:
            self.add(f"{where}: target_id {number} is this human itself; name another human", elem.line)
        elif self.human_ids is not None and number not in self.human_ids:
            ids = ", ".join(str(i) for i in sorted(self.human_ids)) or "none"
            self.add(f"{where}: there is no human with id {number}; human ids: {ids}", elem.line)

    # -- SubTree ---------------------------------------------------------------------------------
    def check_subtree(self, elem: BTElement) -> None:
        tree_id = elem.attrs.get("ID")
        if not tree_id:
            self.add("SubTree is missing required port 'ID' (the BehaviorTree to run)", elem.line)
            return
        info = self.local_trees.get(tree_id) or self.included_trees.get(tree_id)
        if info is None:
            for file_name, library_id in LIBRARY_TREES.items():
                if library_id == tree_id:
                    self.add(f"SubTree '{tree_id}' needs <include path='{file_name}'/> directly under <root>",
                             elem.line)
                    return
            known = list(self.local_trees) + list(self.included_trees)
            self.add(f"SubTree ID '{tree_id}' names no BehaviorTree{_suggest(tree_id, known)}; defined or "
                     f"included: {', '.join(known) or 'none'}", elem.line)
            return
        flag = AUTOREMAP if self.version >= 4 else SHARED_BLACKBOARD
        shared = elem.attrs.get(flag)
        if shared is not None and shared not in BOOL_LITERALS:
            self.add(f"SubTree {flag}='{shared}' must be true or false", elem.line)
        remaps = {k: v for k, v in elem.attrs.items() if k not in ("ID", "name", flag)}
        if shared is not None and BOOL_LITERALS.get(shared):
            return
        needed = info.reads - info.writes
        for key, value in remaps.items():
            if key not in needed:
                self.add(f"SubTree '{tree_id}' remaps '{key}', which that tree never reads; it reads: "
                         f"{', '.join(sorted(needed)) or 'nothing'}", elem.line)
                continue
            parent_key = self.remap_parent_key(tree_id, key, value, elem)
            if parent_key is None or not self.is_main:
                continue
            if parent_key not in self.known_keys:
                self.add(f"SubTree '{tree_id}' {key}='{value}': blackboard key '{parent_key}' is not set before "
                         f"this SubTree; add <SetBlackboard output_key='{parent_key}' value='{{{key}}}'/> before it",
                         elem.line)
        for key in sorted(needed - set(remaps)):
            self.add(f"SubTree '{tree_id}' does not pass blackboard key '{key}'; copy it first with "
                     f"<SetBlackboard output_key='...' value='{{{key}}}'/> and remap it, e.g. "
                     f"<SubTree ID='RegularNavTree' id='agentid' dt='timestep'/>", elem.line)

    def remap_parent_key(self, tree_id: str, key: str, value: str, elem: BTElement) -> str | None:
        ref = BLACKBOARD_REF.match(value)
        if self.version >= 4:
            if ref:
                return ref.group(1)
            self.add(f"SubTree '{tree_id}' {key}='{value}': in BTCPP_format 4 a remapping is written "
                     f"{key}='{{key}}'", elem.line)
            return None
        if ref or not KEY_NAME.match(value):
            self.add(f"SubTree '{tree_id}' {key}='{value}': a remapping names a parent blackboard key without "
                     f"braces, e.g. {key}='{'agentid' if key == 'id' else 'timestep'}'", elem.line)
            return None
        return value

    def check_subtree_cycles(self) -> None:
        graph = {tid: [s.attrs.get("ID", "") for s in info.subtrees] for tid, info in self.local_trees.items()}
        state: dict[str, int] = {}

        def visit(node: str, trail: list[str]) -> None:
            state[node] = 1
            for nxt in graph.get(node, []):
                if state.get(nxt) == 1:
                    cycle = " -> ".join([*trail[trail.index(nxt):], nxt]) if nxt in trail else nxt
                    self.add(f"SubTrees call each other in a loop: {cycle}", self.local_trees[node].element.line)
                elif nxt in graph and nxt not in state:
                    visit(nxt, [*trail, nxt])
            state[node] = 2

        for tid in graph:
            if tid not in state:
                visit(tid, [tid])
