"""Behavior trees lowered for the simulator: every person's tree (BT.CPP v3/v4 XML) becomes rows of one
flat program that people.vm ticks. Lowering is strict like BT.CPP and lists every problem with its line:
unknown nodes, unknown or missing ports, bad literals, wrong child counts, undefined subtrees. Blackboard
keys are resolved once, through SubTree remapping, to numbered slots; what a slot may hold is a number
(int, double, bool) or a text (a SetBlackboard literal, kept as BT.CPP keeps strings and converted by the
port that reads it). The node table (file, line, element) names the place of an error at run time.

`lower_document` is the one place that reads the parsed XML (bt.tree.BTDocument)."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from enum import IntEnum
from pathlib import Path, PurePosixPath
from typing import Any, NamedTuple

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, LIBRARY, LIBRARY_TREE_XML, PortType, leaf_nodes
from socnavgen.bt.tree import BTDocument, BTElement, parse_bt
from socnavgen.bt.validate import BOOL_LITERALS
from socnavgen.errors import ValidationFailed
from socnavgen.safeio import contained_path, read_text_limited
from socnavgen.sim.records import layout, table

LEAF_NAMES = [n.name for n in leaf_nodes()]  # a leaf's code = its row in the library (the trace's node_names)
PORT_NAMES = sorted({p.name for n in leaf_nodes() for p in n.ports if p.name != "name"})
# a leaf reads its ports by name from its arguments: args[Port.distance] (columns of every leaf's ports)
Port = IntEnum("Port", {name: k for k, name in enumerate(PORT_NAMES)})
NOT_MOVING = {"MakeGesture", "UpdateGoal", "SaySomething", "AlwaysSuccess"}  # the trace prefers a moving action
MAX_SUBTREE_DEPTH = 16
# nodes outside the library table that BT.CPP provides: decorator -> its count attribute
EXTRA_DECORATORS = {"Repeat": "num_cycles", "RetryUntilSuccessful": "num_attempts", "KeepRunningUntilFailure": None}
EXPLICIT_TAGS = {"Action", "Condition", "Control", "Decorator"}  # v3 <Action ID="X"/> form
GESTURE_OF_WORD = {word: code for code, word in HUMAN_GESTURES.items()}  # SaySomething's message

# node kinds
SEQUENCE, FALLBACK, REACTIVE_SEQUENCE, REACTIVE_FALLBACK = 0, 1, 2, 3
INVERTER, FORCE_SUCCESS, FORCE_FAILURE, REPEAT, KEEP_RUNNING = 4, 5, 6, 7, 8
SET_BLACKBOARD, CONDITION, ACTION = 9, 10, 11
CONTROLS = {"Sequence": SEQUENCE, "Fallback": FALLBACK, "ReactiveSequence": REACTIVE_SEQUENCE,
            "ReactiveFallback": REACTIVE_FALLBACK}
DECORATORS = {"Inverter": INVERTER, "ForceSuccess": FORCE_SUCCESS, "ForceFailure": FORCE_FAILURE}
# statuses; an error is reported through the clock record (engine.state) and the node table
FAILURE, SUCCESS, RUNNING = 0, 1, 2
# what a blackboard slot holds
UNSET, INT, DOUBLE, BOOL, TEXT = 0, 1, 2, 3, 4
PORT_TYPES = {PortType.INT: INT, PortType.DOUBLE: DOUBLE, PortType.BOOL: BOOL, PortType.STRING: TEXT}
LITERAL = -1  # a port's slot when it holds a literal

NODE = layout([("kind", "i8"), ("first", "i8"), ("count", "i8"), ("end", "i8"), ("leaf", "i8"), ("owner", "i8"),
               ("moves", "?"), ("cycles", "i8"), ("until", "i8"), ("out_slot", "i8"), ("source_slot", "i8"),
               ("first_port", "i8"), ("port_count", "i8"), ("current", "i8"), ("memory", "f8")])
PORT = layout([("column", "i8"), ("slot", "i8"), ("literal", "f8"), ("type", "i8")])
SLOT = layout([("value", "f8"), ("type", "i8")])
TEXT_VALUE = layout([("as_int", "f8"), ("int_ok", "?"), ("as_double", "f8"), ("double_ok", "?"),
                     ("as_bool", "f8"), ("bool_ok", "?"), ("gesture", "f8")])


class Trees(NamedTuple):
    """Every person's tree as one program (pre-order rows: a node's subtree is rows [k, end))."""

    nodes: np.recarray  # NODE per node
    ports: np.recarray  # PORT per port of a leaf (a leaf's are rows first_port .. + port_count)
    slots: np.recarray  # SLOT per blackboard entry
    texts: np.recarray  # TEXT_VALUE per text a slot may hold
    kids: np.ndarray  # int: children of node k are kids[first:first + count]
    stack: np.ndarray  # (depth, 3) int: the interpreter's frames
    args: np.ndarray  # (ports,) float: the ports of the leaf being ticked, by column


@dataclass
class NodeInfo:
    """Where a node comes from (its error messages say so)."""

    tag: str
    source: str
    line: int | None
    keys: dict[int, str] = field(default_factory=dict)  # port column -> blackboard key it reads


@dataclass
class Program:
    """Lowered trees, the table of their nodes, and per person: root node and the slot of its `dt`."""

    trees: Trees
    info: list[NodeInfo]
    roots: list[int]
    dt_slots: list[int]
    texts: dict[str, int] = field(default_factory=dict)  # text -> its row in trees.texts

    def fresh(self) -> Trees:
        """A copy an episode may change (the read-only parts are shared)."""
        t = self.trees
        return Trees(t.nodes.copy(), t.ports, t.slots.copy(), t.texts, t.kids, t.stack.copy(), t.args.copy())


def blackboard_key(value: str) -> str | None:
    """`{key}` -> key; anything else -> None (a literal)."""
    if len(value) >= 2 and value[0] == "{" and value[-1] == "}":
        return value[1:-1].strip()
    return None


def parse_literal(text: str, kind: int) -> float:
    """A port literal as the port's type reads it (ValueError if it does not)."""
    text = text.strip()
    if kind == INT:
        return float(int(float(text)) if "." in text else int(text))
    if kind == DOUBLE:
        return float(text)
    if kind == BOOL:
        if text not in BOOL_LITERALS:
            raise ValueError(text)
        return float(BOOL_LITERALS[text])
    return float(GESTURE_OF_WORD.get(text, 0))  # the one string port a leaf reads: SaySomething's word


class _Blackboard:
    """A blackboard while lowering: its own keys' slots, remapped keys, and where unknown keys go."""

    def __init__(self, lowering: _Lowering, parent: _Blackboard | None = None, autoremap: bool = False) -> None:
        self.lowering, self.parent, self.autoremap = lowering, parent, autoremap
        self.slots: dict[str, int] = {}
        self.remap: dict[str, str] = {}

    def slot(self, key: str) -> int:
        """The slot that `key` reads and writes here (created unset in the blackboard that owns it)."""
        bb = self
        while True:
            if key in bb.remap:
                key, bb = bb.remap[key], bb.parent
            elif key in bb.slots:
                return bb.slots[key]
            elif bb.autoremap and bb.parent is not None:
                bb = bb.parent
            else:
                bb.slots[key] = self.lowering.new_slot(UNSET, 0.0)
                return bb.slots[key]


class _Lowering:
    def __init__(self, base_dir: Path | None) -> None:
        self.base_dir = base_dir
        self.errors: list[str] = []
        self.nodes: list[dict[str, Any]] = []
        self.info: list[NodeInfo] = []
        self.ports: list[tuple[int, int, float, int]] = []
        self.slot_rows: list[tuple[float, int]] = []
        self.texts: dict[str, int] = {}
        self.kids: list[int] = []
        self.depth = 1

    # -- slots and texts ---------------------------------------------------------------------------
    def new_slot(self, kind: int, value: float) -> int:
        self.slot_rows.append((value, kind))
        return len(self.slot_rows) - 1

    def text(self, value: str) -> int:
        return self.texts.setdefault(value, len(self.texts))

    def text_table(self) -> np.recarray:
        out = table(TEXT_VALUE, max(len(self.texts), 1))
        for value, k in self.texts.items():
            row = out[k]
            for name, kind in (("as_int", INT), ("as_double", DOUBLE), ("as_bool", BOOL)):
                with contextlib.suppress(ValueError):
                    row[name], row[name.replace("as_", "") + "_ok"] = parse_literal(value, kind), True
            row.gesture = parse_literal(value, TEXT)
        return out

    # -- documents ---------------------------------------------------------------------------------
    def error(self, doc: BTDocument, line: int | None, message: str) -> None:
        self.errors.append(f"{doc.source}:{line or '?'}: {message}")

    def collect(self, doc: BTDocument, trees: dict[str, tuple[BTElement, BTDocument]], depth: int = 0) -> None:
        for tree_id, elem in doc.trees.items():
            trees.setdefault(tree_id, (elem, doc))
        if depth > 4:
            return
        for inc in doc.includes:
            name = PurePosixPath(inc.replace("\\", "/")).name
            if name in LIBRARY_TREE_XML:
                self.collect(parse_bt(LIBRARY_TREE_XML[name], name), trees, depth + 1)
            elif self.base_dir is not None:
                try:
                    path = contained_path(self.base_dir, inc)
                    self.collect(parse_bt(read_text_limited(path), str(path)), trees, depth + 1)
                except Exception as exc:  # noqa: BLE001 - reported with the others
                    self.error(doc, doc.root.line, f"cannot include {inc!r}: {exc}")
            else:
                self.error(doc, doc.root.line, f"cannot include {inc!r}: only library trees "
                                               f"({', '.join(LIBRARY_TREE_XML)}) are available")

    def person(self, doc: BTDocument, owner: int) -> tuple[int, int]:
        """Lower one person's tree: (root node, slot of its `dt`)."""
        trees: dict[str, tuple[BTElement, BTDocument]] = {}
        self.collect(doc, trees)
        bb = _Blackboard(self)
        bb.slots["id"] = self.new_slot(INT, float(owner))
        bb.slots["dt"] = self.new_slot(DOUBLE, 0.0)
        main = doc.main_tree if doc.main_tree is not None or len(doc.trees) != 1 else next(iter(doc.trees))
        if main not in trees:
            self.error(doc, doc.root.line, f"main tree {main!r} is not defined")
            return self.placeholder(doc, owner), bb.slots["dt"]
        return self.tree(main, trees, bb, owner, 0), bb.slots["dt"]

    def tree(self, tree_id: str, trees: dict, bb: _Blackboard, owner: int, depth: int) -> int:
        elem, doc = trees[tree_id]
        if len(elem.children) != 1:
            self.error(doc, elem.line, f"BehaviorTree {tree_id!r} must have exactly one child, has "
                                       f"{len(elem.children)}")
            return self.placeholder(doc, owner)
        return self.node(elem.children[0], doc, trees, bb, owner, depth, 1)

    def placeholder(self, doc: BTDocument, owner: int) -> int:
        return self.add(SEQUENCE, owner, NodeInfo("Sequence", doc.source, None), [])

    def add(self, kind: int, owner: int, info: NodeInfo, children: list, **fields: Any) -> int:
        """A node row and (in pre-order, right after it) its children's; children are thunks that lower
        themselves when called."""
        k = len(self.nodes)
        row = {"kind": kind, "owner": owner, "until": SUCCESS, "cycles": 1, **fields}
        self.nodes.append(row)
        self.info.append(info)
        first = len(self.kids)
        self.kids.extend([0] * len(children))
        for j, child in enumerate(children):
            self.kids[first + j] = child()
        row.update(first=first, count=len(children), end=len(self.nodes))
        return k

    def node(self, e: BTElement, doc: BTDocument, trees: dict, bb: _Blackboard, owner: int, depth: int,
             level: int) -> int:
        tag, attrs = e.tag, dict(e.attrs)
        if tag in EXPLICIT_TAGS:
            tag = attrs.pop("ID", tag)
        self.depth = max(self.depth, level + 1)
        info = NodeInfo(tag, doc.source, e.line)
        spec = LIBRARY.get(tag)

        def children(lo: int, hi: int | None) -> list:
            if len(e.children) < lo or (hi is not None and len(e.children) > hi):
                want = f"exactly {lo}" if lo == hi else f"at least {lo}"
                self.error(doc, e.line, f"<{e.tag}> needs {want} child node(s), has {len(e.children)}")
            return [lambda c=c: self.node(c, doc, trees, bb, owner, depth, level + 1) for c in e.children]

        if tag in ("SubTree", "SubTreePlus"):
            return self.subtree(tag, attrs, e, doc, trees, bb, owner, depth, level)
        if tag in EXTRA_DECORATORS:
            kids = children(1, 1)
            if tag == "KeepRunningUntilFailure":
                return self.add(KEEP_RUNNING, owner, info, kids[:1])
            raw = attrs.get(EXTRA_DECORATORS[tag], "1")
            try:
                cycles = int(raw)
            except ValueError:
                self.error(doc, e.line, f"{tag}: {EXTRA_DECORATORS[tag]} must be an integer literal, got {raw!r}")
                cycles = 1
            return self.add(REPEAT, owner, info, kids[:1], cycles=cycles,
                            until=SUCCESS if tag == "Repeat" else FAILURE)
        if spec is None:
            self.error(doc, e.line, f"unknown node <{tag}> (not in the node library)")
            return self.placeholder(doc, owner)
        self.check_attrs(spec, attrs, e, doc)
        if spec.kind == "control":
            return self.add(CONTROLS[tag], owner, info, children(spec.min_children, spec.max_children) or [])
        if spec.kind == "decorator":
            return self.add(DECORATORS[tag], owner, info, children(1, 1)[:1])
        if tag == "SetBlackboard":
            if "output_key" not in attrs or "value" not in attrs:
                return self.placeholder(doc, owner)
            key = blackboard_key(attrs["value"])
            source = bb.slot(key) if key is not None else self.new_slot(TEXT, float(self.text(attrs["value"])))
            info.keys[-1] = key or ""
            return self.add(SET_BLACKBOARD, owner, info, [], out_slot=bb.slot(attrs["output_key"]),
                            source_slot=source)
        if e.children:
            self.error(doc, e.line, f"<{tag}> is a leaf and cannot have children")
        return self.leaf(spec, attrs, e, doc, bb, owner, info)

    def leaf(self, spec: Any, attrs: dict[str, str], e: BTElement, doc: BTDocument, bb: _Blackboard, owner: int,
             info: NodeInfo) -> int:
        first = len(self.ports)
        for port in spec.ports:
            raw = attrs.get(port.name, port.default)
            if port.name == "name" or raw is None:
                continue
            column, kind = PORT_NAMES.index(port.name), PORT_TYPES[port.type]
            key = blackboard_key(raw)
            if key is not None:
                self.ports.append((column, bb.slot(key), 0.0, kind))
                info.keys[column] = key
                continue
            try:
                self.ports.append((column, LITERAL, parse_literal(raw, kind), kind))
            except ValueError:
                self.error(doc, e.line, f"{spec.name}: port `{port.name}` = {raw!r} is not a {port.type.value}")
        return self.add(CONDITION if spec.kind == "condition" else ACTION, owner, info, [],
                        leaf=LEAF_NAMES.index(spec.name), moves=spec.name not in NOT_MOVING, first_port=first,
                        port_count=len(self.ports) - first)

    def check_attrs(self, spec: Any, attrs: dict[str, str], e: BTElement, doc: BTDocument) -> None:
        known = {p.name for p in spec.ports} | {"name"}
        for a in attrs:
            if a not in known and not a.startswith("_"):
                self.error(doc, e.line, f"<{spec.name}> has no port `{a}` (ports: {', '.join(sorted(known))})")
        for p in spec.ports:
            if p.required and p.name not in attrs and p.name != "name":
                self.error(doc, e.line, f"<{spec.name}> is missing the required port `{p.name}`")

    def subtree(self, tag: str, attrs: dict[str, str], e: BTElement, doc: BTDocument, trees: dict,
                bb: _Blackboard, owner: int, depth: int, level: int) -> int:
        tree_id = attrs.pop("ID", None)
        if tree_id is None or tree_id not in trees:
            self.error(doc, e.line, f"SubTree ID {tree_id!r} is not defined (include the file that defines it)")
            return self.placeholder(doc, owner)
        if depth >= MAX_SUBTREE_DEPTH:
            self.error(doc, e.line, f"SubTree {tree_id!r} nests more than {MAX_SUBTREE_DEPTH} levels (recursion?)")
            return self.placeholder(doc, owner)
        attrs.pop("name", None)
        shared = attrs.pop("__shared_blackboard", "false").lower() == "true"
        auto = (attrs.pop("_autoremap", "false").lower() == "true"
                or attrs.pop("__autoremap", "false").lower() == "true")
        if shared:
            return self.tree(tree_id, trees, bb, owner, depth + 1)  # a SubTree ticks as its root: no wrapper
        child = _Blackboard(self, parent=bb, autoremap=auto)
        for key, value in attrs.items():
            if key.startswith("_"):
                continue
            ref = blackboard_key(value)
            if ref is not None:
                child.remap[key] = key if ref == "=" else ref
            elif doc.format_version == 3 and tag == "SubTree":
                child.remap[key] = value  # v3: a plain name is the parent's key
            else:  # v4 / SubTreePlus: a plain value is a literal
                child.slots[key] = self.new_slot(TEXT, float(self.text(value)))
        self.depth = max(self.depth, level + 1)
        return self.tree(tree_id, trees, child, owner, depth + 1)

    def program(self, roots: list[int], dt_slots: list[int]) -> Program:
        nodes = table(NODE, len(self.nodes))
        for k, row in enumerate(self.nodes):
            for name, value in row.items():
                nodes[k][name] = value
        ports = table(PORT, max(len(self.ports), 1))
        for k, (column, slot, literal, kind) in enumerate(self.ports):
            ports[k].column, ports[k].slot, ports[k].literal, ports[k].type = column, slot, literal, kind
        slots = table(SLOT, max(len(self.slot_rows), 1))
        for k, (value, kind) in enumerate(self.slot_rows):
            slots[k].value, slots[k].type = value, kind
        trees = Trees(nodes, ports, slots, self.text_table(), np.array(self.kids + [0], dtype=np.int64),
                      np.zeros((self.depth + 1, 3), dtype=np.int64), np.zeros(len(PORT_NAMES)))
        return Program(trees, self.info, roots, dt_slots, dict(self.texts))


def lower_document(lowering: _Lowering, source: str | BTDocument, owner: int, name: str) -> tuple[int, int]:
    """One person's tree (XML text or an already parsed document) into the program."""
    doc = source if isinstance(source, BTDocument) else parse_bt(source, name)
    return lowering.person(doc, owner)


def lower_trees(sources: list[str | BTDocument], names: list[str] | None = None,
                base_dir: Path | None = None) -> Program:
    """The program of every person's tree (person i's is sources[i]); raises ValidationFailed listing every
    problem of every tree."""
    lowering = _Lowering(base_dir)
    roots, dt_slots = [], []
    for i, source in enumerate(sources):
        name = names[i] if names else f"tree of agent {i}"
        root, dt_slot = lower_document(lowering, source, i, name)
        if lowering.errors:
            raise ValidationFailed("behavior tree cannot be simulated:\n  " + "\n  ".join(lowering.errors),
                                   file=source.source if isinstance(source, BTDocument) else name)
        roots.append(root)
        dt_slots.append(dt_slot)
    return lowering.program(roots, dt_slots)
