"""The typed tree (bt.model) written back as BT.CPP XML: the one writer of trees that socnavgen builds or
rewrites (the exporters' timing holds, phrase conditions and 2.x translations). `node()` builds a node of
the library table from typed port values; `document_xml()` writes a file in BTCPP_format 3 or 4.

Only what the parser reads is written: a node's registered name as its tag, its `name` label and its
written ports (typed values as BT.CPP reads them: `{key}` for entries, true/false for bools), SubTree calls
with the format's own remapping syntax (v3 `id='agentid'`, v4 `id='{agentid}'`)."""

from __future__ import annotations

from collections.abc import Iterable
from xml.sax.saxutils import quoteattr

from socnavgen.bt.library import LIBRARY
from socnavgen.bt.model import Document, Node, Ref, SubTreeCall, Value, literal_text

INDENT = "  "


def node(name: str, *children: Node, label: str | None = None, **ports: Value) -> Node:
    """A node of the library table (kind from its row) with typed port values; `{key}` texts become
    blackboard references. Raises KeyError for a name the table does not know (a socnavgen bug)."""
    spec = LIBRARY[name]
    typed = {k: Ref(v[1:-1]) if isinstance(v, str) and v.startswith("{") and v.endswith("}") and k != "output_key"
             else v for k, v in ports.items()}
    return Node(name, spec.kind, typed, tuple(children), label=label)


def subtree_call(tree: str, version: int, **remap: str) -> Node:
    """A SubTree call of `tree` remapping its keys to the caller's entries (key -> caller key)."""
    call = SubTreeCall(tree, {k: Ref(v) for k, v in remap.items()})
    attrs = {k: (f"{{{v}}}" if version == 4 else v) for k, v in remap.items()}
    return Node("SubTree", "subtree", {}, (), attrs=attrs, call=call)


def _attrs(n: Node, version: int) -> list[tuple[str, str]]:
    out: list[tuple[str, str]] = []
    if n.call is not None:
        out.append(("ID", n.call.tree))
        out += [(k, _remap_text(v, version)) for k, v in n.call.remap.items()]
        if n.call.shared:
            out.append(("__shared_blackboard", "true"))
        if n.call.autoremap:
            out.append(("_autoremap", "true"))
    if n.label is not None:
        out.insert(0, ("name", n.label))
    out += [(k, literal_text(v)) for k, v in n.ports.items()]
    return out


def _remap_text(value: Ref | str, version: int) -> str:
    if isinstance(value, Ref):
        return str(value) if version == 4 else value.key
    return value  # a v4 constant


def node_xml(n: Node, version: int = 3, level: int = 2) -> str:
    """One node and its children as indented XML."""
    pad = INDENT * level
    attrs = "".join(f" {k}={quoteattr(v)}" for k, v in _attrs(n, version))
    if not n.children:
        return f"{pad}<{n.name}{attrs}/>\n"
    inner = "".join(node_xml(c, version, level + 1) for c in n.children)
    return f"{pad}<{n.name}{attrs}>\n{inner}{pad}</{n.name}>\n"


def trees_xml(trees: Iterable[tuple[str, Node]], version: int) -> str:
    """`<BehaviorTree ID=...>` elements, one per (id, root)."""
    return "".join(f'{INDENT}<BehaviorTree ID={quoteattr(tid)}>\n{node_xml(root, version)}{INDENT}</BehaviorTree>\n'
                   for tid, root in trees)


def document_xml(doc: Document, *, version: int | None = None, roots: dict[str, Node] | None = None,
                 includes: Iterable[str] | None = None, head: str = "") -> str:
    """A whole tree file: the document's own trees (with `roots` replacing some of them, or adding new
    ones), its includes, `head` (e.g. a TreeNodesModel block) after them; `version` defaults to the
    document's. Trees without a root (a problem the parser reported) are left out."""
    version = version or doc.format_version
    trees = {tid: t.root for tid, t in doc.trees.items() if t.root is not None}
    trees.update(roots or {})
    fmt = ' BTCPP_format="4"' if version == 4 else ""
    main = f" main_tree_to_execute={quoteattr(doc.main_tree)}" if doc.main_tree else ""
    includes = doc.includes if includes is None else tuple(includes)
    ordered = sorted(trees.items(), key=lambda item: item[0] != doc.main_tree)  # the main tree first
    return (f"<root{main}{fmt}>\n" + "".join(f"{INDENT}<include path={quoteattr(p)}/>\n" for p in includes)
            + head + trees_xml(ordered, version) + "</root>\n")


__all__ = ["SubTreeCall", "document_xml", "node", "node_xml", "subtree_call", "trees_xml"]
