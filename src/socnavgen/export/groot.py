"""Groot2 `TreeNodesModel` generated from the node library, so exported trees open in Groot2 with
every leaf's ports named, typed and explained (BT.CPP ignores the model at run time)."""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from socnavgen.bt.library import HUNAV2_REGISTERED, NodeSpec, Port, PortType, leaf_nodes
from socnavgen.export.models import ExportFormat

GROOT_TYPES = {PortType.INT: "int", PortType.DOUBLE: "double", PortType.BOOL: "bool",
               PortType.STRING: "std::string"}
GROOT_KIND = {"action": "Action", "condition": "Condition"}


def _port_line(name: str, type_: str, description: str, default: str | None) -> str:
    default_attr = f" default={quoteattr(default)}" if default is not None else ""
    return (f'      <input_port name={quoteattr(name)} type={quoteattr(type_)}{default_attr}>'
            f"{escape(description)}</input_port>\n")


def _our_ports(spec: NodeSpec) -> list[tuple[str, str, str, str | None]]:
    def describe(p: Port) -> str:
        if p.allowed:
            return p.description + ": " + ", ".join(f"{k}={v}" for k, v in p.allowed.items())
        return p.description
    return [(p.name, GROOT_TYPES[p.type], describe(p), p.default) for p in spec.ports]


def _registered_block(names: set[str] | None) -> list[str]:
    """2.x nodes exactly as HuNavSim 2.x registers them (ids, port names, types, code defaults)."""
    lines: list[str] = []
    for node in HUNAV2_REGISTERED.values():
        if names is not None and node.id not in names:
            continue
        lines.append(f"    <{node.kind} ID={quoteattr(node.id)}>\n")
        for p in node.ports:
            default = f" default={quoteattr(p.default)}" if p.default is not None else ""
            tag = f"{p.direction}_port"
            lines.append(f"      <{tag} name={quoteattr(p.name)} type={quoteattr(p.type)}{default}/>\n")
        lines.append(f"    </{node.kind}>\n")
    return lines


def model_block(target: ExportFormat, names: set[str] | None = None) -> str:
    """The `<TreeNodesModel>` element (indented for a child of <root>) for `target`'s leaf names.

    socrates: our (fork) names; hunav2: the nodes HuNavSim 2.x registers, with their registered ports
    (hunav1 runs built-in trees only, so it needs no model). `names` limits it to nodes actually used
    (names in the TARGET's vocabulary)."""
    lines = ["  <TreeNodesModel>\n"]
    if target == "hunav2":
        lines += _registered_block(names)
    else:
        for spec in leaf_nodes():
            if "socrates" not in spec.targets or (names is not None and spec.name not in names):
                continue
            lines.append(f"    <{GROOT_KIND[spec.kind]} ID={quoteattr(spec.name)}>\n")
            lines += [_port_line(*p) for p in _our_ports(spec)]
            lines.append(f"    </{GROOT_KIND[spec.kind]}>\n")
    lines.append("  </TreeNodesModel>\n")
    return "".join(lines)


def tree_nodes_model_xml(target: ExportFormat) -> str:
    """A stand-alone TreeNodesModel.xml (Groot2: "Import models from file")."""
    return f'<?xml version="1.0" encoding="UTF-8"?>\n<root BTCPP_format="4">\n{model_block(target)}</root>\n'
