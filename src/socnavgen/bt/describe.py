"""Prompt text derived from the node library table, so what the model is told and what the
validator and simulator accept can never drift apart (nothing here is typed twice)."""

from __future__ import annotations

from socnavgen.bt.library import (
    DISTANCE_WORDS,
    LIBRARY,
    LIBRARY_TREE_XML,
    LIBRARY_TREES,
    ROOT_KEYS,
    NodeSpec,
    Port,
    PortType,
    Target,
    prompt_nodes,
)
from socnavgen.bt.model import ROOT_MEANING

_KIND_TITLES = (("condition", "Conditions (return SUCCESS or FAILURE, never move the human)"),
                ("action", "Actions (do something this tick, return SUCCESS)"),
                ("control", "Control nodes (hold one or more children)"),
                ("decorator", "Decorators (hold exactly one child)"))


def example_value(port: Port) -> str:
    """A value that is valid for the port, shown in the prompt's examples (and used by the grammar tests)."""
    if port.reads_root is not None:
        return "{" + port.reads_root + "}"
    if port.example is not None:
        return port.example
    if port.allowed:
        return str(next((k for k in port.allowed if k != 0), 0))
    if port.default is not None:
        return port.default
    return {PortType.INT: "1", PortType.DOUBLE: "2.0", PortType.BOOL: "true", PortType.STRING: "text"}[port.type]


def node_example(spec: NodeSpec) -> str:
    """The node as XML with single-quoted attributes (the reply puts XML inside a JSON string)."""
    attrs = "".join(f" {p.name}='{example_value(p)}'" for p in spec.ports)
    if spec.kind in ("control", "decorator"):
        return f"<{spec.name} name='...'{attrs}> child{'ren' if spec.kind == 'control' else ''} </{spec.name}>"
    return f"<{spec.name}{attrs}/>"


def _port_text(port: Port) -> str:
    extra = "" if port.required else f", optional, default {port.default}" if port.default else ", optional"
    return f"{port.name} ({port.type}{extra}): {port.description}"


def gesture_tables(target: Target = "socrates") -> list[tuple[list[str], dict[int, str]]]:
    """Distinct code tables of message ports, each with the nodes that use it (in library order)."""
    tables: list[tuple[list[str], dict[int, str]]] = []
    for spec in LIBRARY.values():
        if target not in spec.targets:
            continue
        for port in spec.ports:
            if not port.allowed:
                continue
            for users, table in tables:
                if table == port.allowed:
                    users.append(f"{spec.name}.{port.name}")
                    break
            else:
                tables.append(([f"{spec.name}.{port.name}"], port.allowed))
    return tables


def library_text(target: Target = "socrates") -> str:
    """The node-library section of the stage-3 prompt."""
    nodes = [n for n in prompt_nodes() if target in n.targets]  # built-ins: the tutorial and regular_nav_text
    lines = ["NODE LIBRARY. Use only these nodes, with exactly these ports (the optional `name` attribute "
             "is free text allowed on every node). Write every attribute in single quotes.", ""]
    for kind, title in _KIND_TITLES:
        group = [n for n in nodes if n.kind == kind]
        if not group:
            continue
        lines.append(f"{title}:")
        for spec in group:
            lines.append(f"- {spec.name}: {spec.description}")
            for port in spec.ports:
                lines.append(f"    port {_port_text(port)}")
            lines.append(f"    example: {node_example(spec)}")
        lines.append("")
    for users, table in gesture_tables(target):
        codes = ", ".join(f"{code} = {meaning}" for code, meaning in table.items())
        lines.append(f"Gesture codes for {', '.join(users)}: {codes}.")
    words = ", ".join(f"{word} = {dist:g} m" for dist, word in DISTANCE_WORDS.items())
    lines.append(f"Distances: {words}.")
    lines.append(f"Blackboard: {blackboard_text()}")
    return "\n".join(lines) + "\n"


def blackboard_text() -> str:
    """The root blackboard entries and the ports that must read them, from the table."""
    entries = ", ".join(f"{{{key}}} is {ROOT_MEANING[key]} ({type_})" for key, type_ in ROOT_KEYS.items())
    readers = {p.name: p.reads_root for n in LIBRARY.values() for p in n.ports if p.reads_root is not None}
    always = ", ".join(f"{name} is always {{{key}}}" for name, key in readers.items())
    return f"{entries}; {always}."


def capabilities_text(target: Target = "socrates") -> str:
    """What simulated humans can do (stage-1 prompt), one line per library capability."""
    caps = [n.capability for n in prompt_nodes() if n.capability and target in n.targets]
    return "Simulated humans can:\n" + "\n".join(f"- {c}" for c in caps) + "\n"


def regular_nav_text() -> str:
    """The includable regular-navigation tree and the idiom that calls it from a generated tree."""
    parts = []
    for file_name, tree_id in LIBRARY_TREES.items():
        xml = LIBRARY_TREE_XML[file_name].replace('"', "'").strip()
        parts.append(
            f"The library tree file {file_name} defines the BehaviorTree '{tree_id}': the human walks "
            f"normally to its goals and moves on to the next goal when one is reached:\n{xml}\n\n"
            f"To use it, put <include path='{file_name}'/> directly under <root>, then call it with a "
            f"SubTree. A SubTree has its own blackboard, so first copy the id and the time step into "
            f"named entries and remap them, always inside one Sequence:\n"
            f"<Sequence name='RegNav'>\n"
            f"    <SetBlackboard output_key='agentid' value='{{id}}'/>\n"
            f"    <SetBlackboard output_key='timestep' value='{{dt}}'/>\n"
            f"    <SubTree ID='{tree_id}' id='agentid' dt='timestep'/>\n"
            f"</Sequence>\n"
            f"A SubTree '{tree_id}' without the include is an error."
        )
    return "\n\n".join(parts) + "\n"
