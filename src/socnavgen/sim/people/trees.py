"""Behavior trees lowered for the simulator: every person's tree becomes rows of one flat program that
people.vm ticks. The tree language is bt's: `bt.expand.load_instance` parses and checks a file exactly as
`socnavgen bt check` does (every problem with its line) and expands its SubTree calls, each blackboard
reference resolved to the entry it names; this module numbers the nodes in pre-order and the entries as
slots. A slot holds a number (int, double, bool) or a text (a SetBlackboard literal, or a BTCPP_format 4
SubTree constant), which the port reading it converts to its type. The node table (file, line, node) names
the place of an error at run time.

`lower_instance` is the one place that reads the typed tree (bt.model)."""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, NamedTuple

import numpy as np

from socnavgen.bt.expand import Instance, load_instance
from socnavgen.bt.library import HUMAN_GESTURES, PortType, leaf_nodes
from socnavgen.bt.model import Entry, LiteralError, Node, parse_literal
from socnavgen.sim.records import layout, table

LEAF_NAMES = [n.name for n in leaf_nodes()]  # a leaf's code = its row in the library (the trace's node_names)
PORT_NAMES = sorted({p.name for n in leaf_nodes() for p in n.ports if p.name != "name"})
# a leaf reads its ports by name from its arguments: args[Port.distance] (columns of every leaf's ports)
# (members made from the library at import: mypy cannot list them)
Port = IntEnum("Port", {name: k for k, name in enumerate(PORT_NAMES)})  # type: ignore[misc]
GESTURE_OF_WORD = {word: code for code, word in HUMAN_GESTURES.items()}  # SaySomething's message

# node kinds
SEQUENCE, FALLBACK, REACTIVE_SEQUENCE, REACTIVE_FALLBACK = 0, 1, 2, 3
INVERTER, FORCE_SUCCESS, FORCE_FAILURE, REPEAT, KEEP_RUNNING = 4, 5, 6, 7, 8
SET_BLACKBOARD, CONDITION, ACTION = 9, 10, 11
CONTROLS = {("sequence", False): SEQUENCE, ("fallback", False): FALLBACK, ("sequence", True): REACTIVE_SEQUENCE,
            ("fallback", True): REACTIVE_FALLBACK}
DECORATORS = {"invert": INVERTER, "force_success": FORCE_SUCCESS, "force_failure": FORCE_FAILURE, "repeat": REPEAT,
              "retry": REPEAT, "keep_running": KEEP_RUNNING}
# statuses; an error is reported through the clock record (engine.state) and the node table
FAILURE, SUCCESS, RUNNING = 0, 1, 2
# what a blackboard slot holds
UNSET, INT, DOUBLE, BOOL, TEXT = 0, 1, 2, 3, 4
PORT_TYPES = {PortType.INT: INT, PortType.DOUBLE: DOUBLE, PortType.BOOL: BOOL, PortType.STRING: TEXT}
LITERAL = -1  # a port's slot when it holds a literal

NODE = layout([("kind", "i8"), ("first", "i8"), ("count", "i8"), ("end", "i8"), ("leaf", "i8"), ("owner", "i8"),
               ("moves", "?"), ("cycles", "i8"), ("cycles_slot", "i8"), ("until", "i8"), ("out_slot", "i8"),
               ("source_slot", "i8"),
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


def text_value(text: str) -> dict[str, Any]:
    """A text as each port type reads it (bt.model.parse_literal), and as SaySomething's gesture word."""
    row: dict[str, Any] = {"gesture": float(GESTURE_OF_WORD.get(text.strip(), 0))}
    for name, kind in (("int", PortType.INT), ("double", PortType.DOUBLE), ("bool", PortType.BOOL)):
        with contextlib.suppress(LiteralError):
            row[f"as_{name}"], row[f"{name}_ok"] = float(parse_literal(text, kind)), True
    return row


class _Lowering:
    """Numbers the nodes of every person's instance in pre-order, and their entries as slots."""

    def __init__(self) -> None:
        self.nodes: list[dict[str, Any]] = []
        self.info: list[NodeInfo] = []
        self.ports: list[tuple[int, int, float, int]] = []
        self.slot_rows: list[tuple[float, int]] = []
        self.slot_of: dict[tuple[int, Entry], int] = {}
        self.texts: dict[str, int] = {}
        self.kids: list[int] = []
        self.depth = 1

    def slot(self, owner: int, entry: Entry, kind: int = UNSET, value: float = 0.0) -> int:
        """The slot of a person's blackboard entry (created as given the first time)."""
        key = (owner, entry)
        if key not in self.slot_of:
            self.slot_of[key] = len(self.slot_rows)
            self.slot_rows.append((value, kind))
        return self.slot_of[key]

    def text(self, value: str) -> int:
        return self.texts.setdefault(value, len(self.texts))

    def person(self, instance: Instance, owner: int) -> tuple[int, int]:
        """Lower one person's instance: (root node, slot of its `dt`)."""
        self.slot(owner, Entry(0, "id"), INT, float(owner))
        dt_slot = self.slot(owner, Entry(0, "dt"), DOUBLE)
        for entry, text in instance.constants.items():
            self.slot(owner, entry, TEXT, float(self.text(text)))
        return self.node(instance.root, owner, 1), dt_slot

    def node(self, node: Node, owner: int, level: int) -> int:
        self.depth = max(self.depth, level + 1)
        spec = node.spec
        assert spec is not None  # an Instance has passed every check
        k = len(self.nodes)
        row: dict[str, Any] = {"owner": owner, "until": SUCCESS, "cycles": 1, "cycles_slot": LITERAL}
        info = NodeInfo(node.name, node.source, node.line)
        self.nodes.append(row)
        self.info.append(info)
        if spec.kind == "control":
            assert spec.flow is not None  # every control has one (bt.library)
            row["kind"] = CONTROLS[(spec.flow, spec.reactive)]
        elif spec.kind == "decorator":
            assert spec.rule is not None  # every decorator has one (bt.library)
            row["kind"] = DECORATORS[spec.rule]
            if spec.rule in ("repeat", "retry"):
                assert spec.count_port is not None  # repeat and retry name their count port
                row["until"] = SUCCESS if spec.rule == "repeat" else FAILURE
                count = node.value(spec.count_port)
                if isinstance(count, Entry):
                    row["cycles_slot"] = self.slot(owner, count)
                else:
                    row["cycles"] = int(count) if isinstance(count, int | float | str) else 1
        elif node.name == "SetBlackboard":
            value, out = node.ports["value"], node.ports["output_key"]
            assert isinstance(out, Entry)  # an Instance's keys are resolved entries
            row["kind"], row["out_slot"] = SET_BLACKBOARD, self.slot(owner, out)
            if isinstance(value, Entry):
                row["source_slot"], info.keys[-1] = self.slot(owner, value), value.key
            else:  # a literal is a text, as BT.CPP keeps it; the port reading it converts it
                row["source_slot"] = len(self.slot_rows)
                self.slot_rows.append((float(self.text(str(value))), TEXT))
        else:
            self.leaf(node, spec, row, info, owner)
        first = len(self.kids)
        self.kids.extend([0] * len(node.children))
        for j, child in enumerate(node.children):
            self.kids[first + j] = self.node(child, owner, level + 1)
        row.update(first=first, count=len(node.children), end=len(self.nodes))
        return k

    def leaf(self, node: Node, spec: Any, row: dict[str, Any], info: NodeInfo, owner: int) -> None:
        first = len(self.ports)
        for port in spec.ports:
            value = node.value(port.name)
            if port.name == "name" or value is None:
                continue
            column, kind = PORT_NAMES.index(port.name), PORT_TYPES[port.type]
            if isinstance(value, Entry):
                self.ports.append((column, self.slot(owner, value), 0.0, kind))
                info.keys[column] = value.key
            elif isinstance(value, str):  # the one text port a leaf reads: SaySomething's gesture word
                self.ports.append((column, LITERAL, float(GESTURE_OF_WORD.get(value.strip(), 0)), kind))
            else:
                assert isinstance(value, int | float)  # an Instance holds entries, not references
                self.ports.append((column, LITERAL, float(value), kind))
        row.update(kind=CONDITION if spec.kind == "condition" else ACTION, leaf=LEAF_NAMES.index(spec.name),
                   moves=spec.moves, first_port=first, port_count=len(self.ports) - first)

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
        texts = table(TEXT_VALUE, max(len(self.texts), 1))
        for text, k in self.texts.items():
            for name, value in text_value(text).items():
                texts[k][name] = value
        trees = Trees(nodes, ports, slots, texts, np.array(self.kids + [0], dtype=np.int64),
                      np.zeros((self.depth + 1, 3), dtype=np.int64), np.zeros(len(PORT_NAMES)))
        return Program(trees, self.info, roots, dt_slots, dict(self.texts))


def lower_instance(lowering: _Lowering, source: str | Instance, owner: int, name: str) -> tuple[int, int]:
    """One person's tree (XML text, checked and expanded here, or an Instance) into the program."""
    instance = source if isinstance(source, Instance) else load_instance(source, name)
    return lowering.person(instance, owner)


def lower_trees(sources: Sequence[str | Instance], names: list[str] | None = None) -> Program:
    """The program of every person's tree (person i's is sources[i]); a tree with problems raises
    bt.expand.TreeProblems (a ValidationFailed naming its file and every problem with its line)."""
    lowering = _Lowering()
    roots, dt_slots = [], []
    for i, source in enumerate(sources):
        root, dt_slot = lower_instance(lowering, source, i, names[i] if names else f"tree of agent {i}")
        roots.append(root)
        dt_slots.append(dt_slot)
    return lowering.program(roots, dt_slots)
