"""Building behavior trees for the simulator from BT.CPP v3/v4 XML: strict like BT.CPP (unknown nodes,
unknown or missing ports, bad literals, wrong child counts, undefined subtrees), listing every problem with
its line. Leaves are dispatched through the node library table; their behaviour comes from the
implementations passed in (socnavgen.sim.nodes.IMPLEMENTATIONS)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path, PurePosixPath
from typing import Any

from socnavgen.bt.library import LIBRARY, LIBRARY_TREE_XML
from socnavgen.bt.tree import BTDocument, BTElement, parse_bt
from socnavgen.errors import ValidationFailed
from socnavgen.safeio import contained_path, read_text_limited
from socnavgen.sim.bt_runtime import (
    CONVERTERS,
    EXPLICIT_TAGS,
    EXTRA_DECORATORS,
    FAILURE,
    MAX_SUBTREE_DEPTH,
    SUCCESS,
    ActionLeaf,
    BehaviorTree,
    Blackboard,
    ConditionLeaf,
    Fallback,
    ForceFailure,
    ForceSuccess,
    Inverter,
    KeepRunningUntilFailure,
    Node,
    ReactiveFallback,
    ReactiveSequence,
    Repeat,
    Sequence,
    SetBlackboard,
    _blackboard_key,
)


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
            return self._tree(tree_id, bb, depth + 1)  # a SubTree ticks as its root: no wrapper
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
        return self._tree(tree_id, child_bb, depth + 1)


def build_tree(source: str | BTDocument, sim: Any, owner: int, implementations: dict[str, Callable],
               node_index: dict[str, int], base_dir: Path | None = None, name: str = "<tree>") -> BehaviorTree:
    """Instantiate the main tree of `source` (XML text or parsed document) for agent `owner`."""
    doc = source if isinstance(source, BTDocument) else parse_bt(source, name)
    return _Builder(doc, sim, owner, implementations, node_index, base_dir).build()
