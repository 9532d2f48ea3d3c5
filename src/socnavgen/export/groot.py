"""Groot2 `TreeNodesModel` generated from the node library, so exported trees open in Groot2 with
every leaf's ports named, typed and explained (BT.CPP ignores the model at run time)."""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from socnavgen.bt.library import HUNAV2_PORTS, NodeSpec, Port, PortType, leaf_nodes
from socnavgen.export.models import ExportFormat

GROOT_TYPES = {PortType.INT: "int", PortType.DOUBLE: "double", PortType.BOOL: "bool",
               PortType.STRING: "std::string"}
GROOT_KIND = {"action": "Action", "condition": "Condition"}


def _port_line(name: str, type_: str, description: str, default: str | None) -> str:
    default_attr = f" default={quoteattr(default)}" if default is not None else ""
    return (f'      <input_port name={quoteattr(name)} type={quoteattr(type_)}{default_attr}>'
            f"{escape(description)}</input_port>\n")


def _hunav2_ports(spec: NodeSpec) -> list[tuple[str, str, str, str | None]]:
    """Ports of the 2.x counterpart as our translation writes them (see bt.library.HUNAV2_PORTS)."""
    tr = HUNAV2_PORTS.get(spec.name)
    out: list[tuple[str, str, str, str | None]] = []
    for port in spec.ports:
        name = tr.rename.get(port.name, port.name) if tr else port.name
        if tr and port.name in tr.values:  # codes become words: what the human says
            described = ", ".join(f"{k}={v}" for k, v in tr.values[port.name].items())
            out.append((name, "std::string", f"text said (socnavgen writes the gesture word: {described})",
                        port.default))
        else:
            out.append((name, GROOT_TYPES[port.type], port.description, port.default))
    for name, value in (tr.fixed.items() if tr else []):
        out.append((name, "double", f"set by socnavgen export to match {spec.name}", value))
    return out


def _our_ports(spec: NodeSpec) -> list[tuple[str, str, str, str | None]]:
    def describe(p: Port) -> str:
        if p.allowed:
            return p.description + ": " + ", ".join(f"{k}={v}" for k, v in p.allowed.items())
        return p.description
    return [(p.name, GROOT_TYPES[p.type], describe(p), p.default) for p in spec.ports]


def model_block(target: ExportFormat, names: set[str] | None = None) -> str:
    """The `<TreeNodesModel>` element (indented for a child of <root>) for `target`'s leaf names.

    socrates: our (fork) names; hunav2: the 2.x names and ports our translation emits. (hunav1
    runs built-in trees only, so it needs no model.)
    `names` limits it to nodes actually used (names in the TARGET's vocabulary)."""
    lines = ["  <TreeNodesModel>\n"]
    seen: set[str] = set()
    for spec in leaf_nodes():
        if target == "hunav2":
            if spec.hunav2 is None:
                continue
            node_id, ports = spec.hunav2, _hunav2_ports(spec)
        else:
            if "socrates" not in spec.targets:
                continue
            node_id, ports = spec.name, _our_ports(spec)
        if node_id in seen or (names is not None and node_id not in names):
            continue
        seen.add(node_id)
        lines.append(f"    <{GROOT_KIND[spec.kind]} ID={quoteattr(node_id)}>\n")
        lines += [_port_line(*p) for p in ports]
        lines.append(f"    </{GROOT_KIND[spec.kind]}>\n")
    if target == "hunav2":  # the exporter queues goals with 2.x's SetGoal (see export.hunav2)
        lines += ['    <Action ID="SetGoal">\n',
                  _port_line("agent_id", "int", "the agent's own id; always {id}", None),
                  _port_line("goal_id", "int", "id of a global goal of the scenario yaml", None),
                  "    </Action>\n"]
    lines.append("  </TreeNodesModel>\n")
    return "".join(lines)


def tree_nodes_model_xml(target: ExportFormat) -> str:
    """A stand-alone TreeNodesModel.xml (Groot2: "Import models from file")."""
    return f'<?xml version="1.0" encoding="UTF-8"?>\n<root BTCPP_format="4">\n{model_block(target)}</root>\n'
