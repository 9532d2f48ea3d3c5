"""Interpreter of BehaviorTree.CPP v3 and v4 XML for the simulator.

Each agent's tree is built once (strictly, like BT.CPP: unknown nodes or ports are errors, all of them
listed) and ticked once per step. Leaves are dispatched through the node library table
(`socnavgen.bt.library`): its kind and ports drive construction, `socnavgen.sim.nodes.IMPLEMENTATIONS`
supplies the behaviour. While ticking, leaves record into the simulation which action ran and which
leaves returned SUCCESS (for the trace).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path, PurePosixPath
from typing import Any

from socnavgen.bt.library import LIBRARY, LIBRARY_TREE_XML, PortType
from socnavgen.bt.tree import BTDocument, BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.safeio import contained_path, read_text_limited

FAILURE, SUCCESS, RUNNING = 0, 1, 2
MAX_SUBTREE_DEPTH = 16

# Nodes outside the library table that BT.CPP provides and cost nothing to support.
EXTRA_DECORATORS = {"Repeat": "num_cycles", "RetryUntilSuccessful": "num_attempts", "KeepRunningUntilFailure": None}
EXPLICIT_TAGS = {"Action", "Condition", "Control", "Decorator"}  # v3 <Action ID="X"/> form


class BTRuntimeError(ValidationFailed):
    """A tree failed while running (e.g. a port reads a blackboard key nobody wrote)."""


def _to_bool(text: str) -> bool:
    if text in ("true", "True", "TRUE", "1"):
        return True
    if text in ("false", "False", "FALSE", "0"):
        return False
    raise ValueError(f"not a bool: {text!r}")


CONVERTERS: dict[PortType, Callable[[str], Any]] = {
    PortType.INT: lambda s: int(float(s)) if "." in s else int(s),
    PortType.DOUBLE: float,
    PortType.BOOL: _to_bool,
    PortType.STRING: str,
}


class Blackboard:
    """Key-value store of one tree or subtree; remapped keys read and write the parent's entry live."""

    __slots__ = ("data", "parent", "remap", "autoremap")

    def __init__(self, parent: Blackboard | None = None, remap: dict[str, str] | None = None,
                 autoremap: bool = False) -> None:
        self.data: dict[str, Any] = {}
        self.parent = parent
        self.remap = remap or {}
        self.autoremap = autoremap

    def get(self, key: str) -> Any:
        if key in self.remap:
            return self.parent.get(self.remap[key])
        if key in self.data:
            return self.data[key]
        if self.autoremap and self.parent is not None:
            return self.parent.get(key)
        raise KeyError(key)

    def resolve(self, key: str) -> tuple[dict, str] | None:
        """(dict, key) holding `key` after following remaps; None when autoremap makes it dynamic."""
        bb = self
        while key in bb.remap:
            key = bb.remap[key]
            bb = bb.parent
        return None if bb.autoremap else (bb.data, key)

    def set(self, key: str, value: Any) -> None:
        if key in self.remap:
            self.parent.set(self.remap[key], value)
        elif self.autoremap and self.parent is not None and key not in self.data:
            self.parent.set(key, value)
        else:
            self.data[key] = value


def _blackboard_key(value: str) -> str | None:
    """`{key}` -> key; anything else -> None (a literal)."""
    if len(value) >= 2 and value[0] == "{" and value[-1] == "}":
        return value[1:-1].strip()
    return None


# ---- nodes -----------------------------------------------------------------------------------
class Node:
    __slots__ = ("line",)

    def tick(self) -> int:  # pragma: no cover - abstract
        raise NotImplementedError

    def reset(self) -> None:
        """Halt: forget a RUNNING child (called when a reactive parent interrupts this branch)."""


class Sequence(Node):
    __slots__ = ("children", "current")

    def __init__(self, children: list[Node]) -> None:
        self.children, self.current = children, 0

    def tick(self) -> int:
        children = self.children
        i = self.current
        n = len(children)
        while i < n:
            st = children[i].tick()
            if st == SUCCESS:
                i += 1
                continue
            if st == RUNNING:
                self.current = i
                return RUNNING
            self.current = 0  # nothing below is running any more: the running child just finished
            return FAILURE
        self.current = 0
        return SUCCESS

    def reset(self) -> None:
        self.current = 0
        for c in self.children:
            c.reset()


class Fallback(Sequence):
    __slots__ = ()

    def tick(self) -> int:
        children = self.children
        i = self.current
        n = len(children)
        while i < n:
            st = children[i].tick()
            if st == FAILURE:
                i += 1
                continue
            if st == RUNNING:
                self.current = i
                return RUNNING
            self.current = 0
            return SUCCESS
        self.current = 0
        return FAILURE


class ReactiveSequence(Sequence):
    """Re-evaluates from the first child every tick; a RUNNING child halts the ones after it."""

    __slots__ = ()

    def tick(self) -> int:
        for k, child in enumerate(self.children):
            st = child.tick()
            if st == SUCCESS:
                continue
            for later in self.children[k + 1:]:
                later.reset()
            return st
        return SUCCESS


class ReactiveFallback(Sequence):
    __slots__ = ()

    def tick(self) -> int:
        for k, child in enumerate(self.children):
            st = child.tick()
            if st == FAILURE:
                continue
            for later in self.children[k + 1:]:
                later.reset()
            return st
        return FAILURE


class Decorator(Node):
    __slots__ = ("child",)

    def __init__(self, child: Node) -> None:
        self.child = child

    def reset(self) -> None:
        self.child.reset()


class Inverter(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        st = self.child.tick()
        return st if st == RUNNING else SUCCESS - st


class ForceSuccess(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return RUNNING if self.child.tick() == RUNNING else SUCCESS


class ForceFailure(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return RUNNING if self.child.tick() == RUNNING else FAILURE


class Repeat(Decorator):
    """Ticks the child up to `count` times within one tick while it succeeds (synchronous leaves)."""

    __slots__ = ("count", "until")

    def __init__(self, child: Node, count: int, until: int) -> None:
        super().__init__(child)
        self.count, self.until = count, until

    def tick(self) -> int:
        stop = FAILURE if self.until == SUCCESS else SUCCESS
        for _ in range(max(self.count, 1) if self.count >= 0 else 1_000):
            st = self.child.tick()
            if st == RUNNING:
                return RUNNING
            if st == stop:
                return stop
        return self.until


class KeepRunningUntilFailure(Decorator):
    __slots__ = ()

    def tick(self) -> int:
        return FAILURE if self.child.tick() == FAILURE else RUNNING


class SetBlackboard(Node):
    __slots__ = ("bb", "key", "source", "literal", "out", "src")

    def __init__(self, bb: Blackboard, key: str, value: str) -> None:
        self.bb, self.key = bb, key
        self.source = _blackboard_key(value)
        self.literal = value
        # remaps are static: resolve both ends once (None = dynamic through autoremap)
        self.out = bb.resolve(key)
        self.src = bb.resolve(self.source) if self.source is not None else None

    def tick(self) -> int:
        out, src = self.out, self.src
        if src is not None:
            try:
                value = src[0][src[1]]
            except KeyError:
                value = self.bb.get(self.source)  # raises the KeyError the builder reports
        elif self.source is not None:
            value = self.bb.get(self.source)
        else:
            value = self.literal
        if out is not None:
            out[0][out[1]] = value
        else:
            self.bb.set(self.key, value)
        return SUCCESS


class SubTree(Node):
    __slots__ = ("root",)

    def __init__(self, root: Node) -> None:
        self.root = root

    def tick(self) -> int:
        return self.root.tick()

    def reset(self) -> None:
        self.root.reset()


class Leaf(Node):
    """A library leaf bound to one agent's tree. The node function gets (sim, leaf, agent index) and reads
    other ports through `leaf.get`. Port keys are resolved through SubTree remapping once, at build time
    (remaps are static; only values change), so a read is one dict lookup."""

    __slots__ = ("name", "fn", "sim", "owner", "bb", "ports", "bit", "index", "motion", "state", "source",
                 "agent_port", "last_agent")

    def __init__(self, name: str, fn: Callable, sim: Any, owner: int, bb: Blackboard,
                 ports: dict[str, tuple[str | None, Any, Callable]], index: int, line: int | None,
                 source: str) -> None:
        self.name, self.fn, self.sim, self.owner, self.bb = name, fn, sim, owner, bb
        self.ports = {k: (bb.resolve(key) if key is not None else None, key, value, conv)
                      for k, (key, value, conv) in ports.items()}
        self.agent_port = self.ports.get("agent_id")
        self.last_agent = None
        self.index, self.bit = index, 1 << index
        self.motion = name not in ("MakeGesture", "UpdateGoal")
        self.state: dict[str, Any] = {}
        self.line, self.source = line, source

    def get(self, name: str) -> Any:
        resolved, key, value, conv = self.ports[name]
        if key is None:
            return value
        try:
            value = resolved[0][resolved[1]] if resolved is not None else self.bb.get(key)
        except KeyError as exc:
            raise BTRuntimeError(f"{self.name}: port `{name}` reads blackboard key `{key}` that is not set",
                                 file=self.source, line=self.line,
                                 hint="write it with SetBlackboard or remap it in the SubTree") from exc
        if type(value) is str:
            try:
                return conv(value)
            except ValueError as exc:
                raise BTRuntimeError(f"{self.name}: port `{name}` got {value!r}", file=self.source,
                                     line=self.line) from exc
        return value

    def agent(self) -> int:
        """The `agent_id` port, checked to name an agent (checked again only when it changes)."""
        port = self.agent_port
        if port is None:
            return self.owner
        resolved = port[0]
        if resolved is not None:
            try:
                i = resolved[0][resolved[1]]
            except KeyError:
                i = self.get("agent_id")
        else:
            i = self.get("agent_id")
        if i is not self.last_agent:
            if type(i) is str:
                i = self.get("agent_id")
            if type(i) is not int or not 0 <= i < self.sim.crowd.n:
                raise BTRuntimeError(f"{self.name}: agent_id {i!r} is not an agent (0..{self.sim.crowd.n - 1})",
                                     file=self.source, line=self.line, hint="write agent_id=\"{id}\"")
            self.last_agent = i
        return i


class ConditionLeaf(Leaf):
    __slots__ = ()

    def tick(self) -> int:
        st = self.fn(self.sim, self, self.agent())
        if st:
            self.sim.tick_success[self.owner] |= self.bit
        return st


class ActionLeaf(Leaf):
    __slots__ = ()

    def tick(self) -> int:
        sim, owner = self.sim, self.owner
        st = self.fn(sim, self, self.agent())
        if st == SUCCESS:
            sim.tick_success[owner] |= self.bit
        if self.motion or not sim.tick_action_motion[owner]:
            sim.tick_action[owner] = self.index
            sim.tick_action_motion[owner] = self.motion
        return st


# ---- building --------------------------------------------------------------------------------
class BehaviorTree:
    """One agent's instantiated tree: tick() evaluates it once from the root."""

    def __init__(self, root: Node, blackboard: Blackboard) -> None:
        self.root = root
        self.blackboard = blackboard

    def tick(self, dt: float) -> int:
        self.blackboard.data["dt"] = dt
        return self.root.tick()


class _Builder:
    def __init__(self, doc: BTDocument, sim: Any, owner: int, implementations: dict[str, Callable],
                 node_index: dict[str, int], base_dir: Path | None) -> None:
        self.doc, self.sim, self.owner = doc, sim, owner
        self.impl, self.node_index, self.base_dir = implementations, node_index, base_dir
        self.errors: list[str] = []
        self.trees: dict[str, tuple[BTElement, BTDocument]] = {}
        self._collect(doc, depth=0)

    def _err(self, doc: BTDocument, line: int | None, message: str) -> None:
        self.errors.append(f"{doc.source}:{line or '?'}: {message}")

    def _collect(self, doc: BTDocument, depth: int) -> None:
        for tree_id, elem in doc.trees.items():
            self.trees.setdefault(tree_id, (elem, doc))
        if depth > 4:
            return
        for inc in doc.includes:
            name = PurePosixPath(inc.replace("\\", "/")).name
            if name in LIBRARY_TREE_XML:
                self._collect(parse_bt(LIBRARY_TREE_XML[name], name), depth + 1)
            elif self.base_dir is not None:
                try:
                    path = contained_path(self.base_dir, inc)
                    self._collect(parse_bt(read_text_limited(path), str(path)), depth + 1)
                except Exception as exc:  # noqa: BLE001 - reported with the others
                    self._err(doc, doc.root.line, f"cannot include {inc!r}: {exc}")
            else:
                self._err(doc, doc.root.line, f"cannot include {inc!r}: only library trees "
                                              f"({', '.join(LIBRARY_TREE_XML)}) are available")

    def build(self) -> BehaviorTree:
        bb = Blackboard()
        bb.data.update(id=self.owner, dt=0.0)
        main = self.doc.main_tree
        if main is None and len(self.doc.trees) == 1:
            main = next(iter(self.doc.trees))
        root: Node | None = None
        if main not in self.trees:
            self._err(self.doc, self.doc.root.line, f"main tree {main!r} is not defined")
        else:
            root = self._tree(main, bb, depth=0)
        if self.errors or root is None:
            raise ValidationFailed("behavior tree cannot be simulated:\n  " + "\n  ".join(self.errors),
                                   file=self.doc.source)
        return BehaviorTree(root, bb)

    def _tree(self, tree_id: str, bb: Blackboard, depth: int) -> Node:
        elem, doc = self.trees[tree_id]
        kids = [c for c in elem.children]
        if len(kids) != 1:
            self._err(doc, elem.line, f"BehaviorTree {tree_id!r} must have exactly one child, has {len(kids)}")
            return Sequence([])
        return self._node(kids[0], doc, bb, depth)

    def _node(self, e: BTElement, doc: BTDocument, bb: Blackboard, depth: int) -> Node:
        tag, attrs = e.tag, dict(e.attrs)
        if tag in EXPLICIT_TAGS:
            tag = attrs.pop("ID", tag)
        node = self._make(tag, attrs, e, doc, bb, depth)
        node.line = e.line
        return node

    def _children(self, e: BTElement, doc: BTDocument, bb: Blackboard, depth: int, lo: int,
                  hi: int | None) -> list[Node]:
        kids = [self._node(c, doc, bb, depth) for c in e.children]
        if len(kids) < lo or (hi is not None and len(kids) > hi):
            want = f"exactly {lo}" if lo == hi else f"at least {lo}"
            self._err(doc, e.line, f"<{e.tag}> needs {want} child node(s), has {len(kids)}")
        return kids or [Sequence([])]

    def _make(self, tag: str, attrs: dict[str, str], e: BTElement, doc: BTDocument, bb: Blackboard,
              depth: int) -> Node:
        spec = LIBRARY.get(tag)
        if tag == "SubTree" or tag == "SubTreePlus":
            return self._subtree(tag, attrs, e, doc, bb, depth)
        if tag in EXTRA_DECORATORS:
            kids = self._children(e, doc, bb, depth, 1, 1)
            if tag == "KeepRunningUntilFailure":
                return KeepRunningUntilFailure(kids[0])
            raw = attrs.get(EXTRA_DECORATORS[tag], "1")
            try:
                count = int(raw)
            except ValueError:
                self._err(doc, e.line, f"{tag}: {EXTRA_DECORATORS[tag]} must be an integer literal, got {raw!r}")
                count = 1
            return Repeat(kids[0], count, SUCCESS if tag == "Repeat" else FAILURE)
        if spec is None:
            self._err(doc, e.line, f"unknown node <{tag}> (not in the node library)")
            return Sequence([])
        self._check_attrs(spec, attrs, e, doc)
        if spec.kind == "control":
            kids = self._children(e, doc, bb, depth, spec.min_children, spec.max_children)
            return {"Sequence": Sequence, "Fallback": Fallback, "ReactiveSequence": ReactiveSequence,
                    "ReactiveFallback": ReactiveFallback}[tag](kids)
        if spec.kind == "decorator":
            kids = self._children(e, doc, bb, depth, 1, 1)
            return {"Inverter": Inverter, "ForceSuccess": ForceSuccess, "ForceFailure": ForceFailure}[tag](kids[0])
        if tag == "SetBlackboard":
            if "output_key" not in attrs or "value" not in attrs:
                return Sequence([])
            return SetBlackboard(bb, attrs["output_key"], attrs["value"])
        if e.children:
            self._err(doc, e.line, f"<{tag}> is a leaf and cannot have children")
        fn = self.impl.get(tag)
        if fn is None:
            self._err(doc, e.line, f"<{tag}> has no simulator implementation")
            return Sequence([])
        ports: dict[str, tuple[str | None, Any, Callable]] = {}
        for port in spec.ports:
            if port.name == "name":
                continue
            raw = attrs.get(port.name, port.default)
            if raw is None:
                continue
            conv = CONVERTERS[port.type]
            key = _blackboard_key(raw)
            value: Any = None
            if key is None:
                try:
                    value = conv(raw.strip())
                except ValueError:
                    self._err(doc, e.line, f"{tag}: port `{port.name}` = {raw!r} is not a {port.type.value}")
            ports[port.name] = (key, value, conv)
        cls = ActionLeaf if spec.kind == "action" else ConditionLeaf
        return cls(tag, fn, self.sim, self.owner, bb, ports, self.node_index[tag], e.line, doc.source)

    def _check_attrs(self, spec, attrs: dict[str, str], e: BTElement, doc: BTDocument) -> None:  # noqa: ANN001
        known = {p.name for p in spec.ports} | {"name"}
        for a in attrs:
            if a not in known and not a.startswith("_"):
                self._err(doc, e.line, f"<{spec.name}> has no port `{a}` (ports: {', '.join(sorted(known))})")
        for p in spec.ports:
            if p.required and p.name not in attrs and p.name != "name":
                self._err(doc, e.line, f"<{spec.name}> is missing the required port `{p.name}`")

    def _subtree(self, tag: str, attrs: dict[str, str], e: BTElement, doc: BTDocument, bb: Blackboard,
                 depth: int) -> Node:
        tree_id = attrs.pop("ID", None)
        if tree_id is None or tree_id not in self.trees:
            self._err(doc, e.line, f"SubTree ID {tree_id!r} is not defined (include the file that defines it)")
            return Sequence([])
        if depth >= MAX_SUBTREE_DEPTH:
            self._err(doc, e.line, f"SubTree {tree_id!r} nests more than {MAX_SUBTREE_DEPTH} levels (recursion?)")
            return Sequence([])
        attrs.pop("name", None)
        shared = attrs.pop("__shared_blackboard", "false").lower() == "true"
        auto = (attrs.pop("_autoremap", "false").lower() == "true"
                or attrs.pop("__autoremap", "false").lower() == "true")
        if shared:
            return SubTree(self._tree(tree_id, bb, depth + 1))
        child_bb = Blackboard(parent=bb, autoremap=auto)
        for key, value in attrs.items():
            if key.startswith("_"):
                continue
            ref = _blackboard_key(value)
            if ref == "=":
                child_bb.remap[key] = key
            elif ref is not None:
                child_bb.remap[key] = ref
            elif doc.format_version == 3 and tag == "SubTree":
                child_bb.remap[key] = value  # v3: a plain name is the parent's key
            else:
                child_bb.data[key] = value  # v4 / SubTreePlus: a plain value is a literal
        return SubTree(self._tree(tree_id, child_bb, depth + 1))


def build_tree(source: str | BTDocument, sim: Any, owner: int, implementations: dict[str, Callable],
               node_index: dict[str, int], base_dir: Path | None = None, name: str = "<tree>") -> BehaviorTree:
    """Instantiate the main tree of `source` (XML text or parsed document) for agent `owner`."""
    doc = source if isinstance(source, BTDocument) else parse_bt(source, name)
    return _Builder(doc, sim, owner, implementations, node_index, base_dir).build()
