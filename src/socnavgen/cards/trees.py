"""Card tree templates (templates.yaml) -> BT.CPP v3 XML from library nodes, validated like any tree."""

from __future__ import annotations

from functools import cache
from importlib import resources
from xml.sax.saxutils import quoteattr

import yaml

from socnavgen.bt.library import LIBRARY, regular_nav_sequence
from socnavgen.bt.validate import format_problems, validate_bt_text
from socnavgen.errors import ValidationFailed

REGULAR = "REGULAR"
OWN_PORTS = {"agent_id": "{id}", "time_step": "{dt}"}
CONTROLS = ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "Inverter", "ForceSuccess",
            "ForceFailure")


@cache
def templates() -> dict[str, object]:
    text = resources.files("socnavgen.cards").joinpath("templates.yaml").read_text(encoding="utf-8")
    return dict(yaml.safe_load(text)["templates"])


def sight_distance(template: str) -> float:
    """The farthest a template's conditions look for the robot (m): a person placed closer than this to
    the robot's start reacts at t = 0, before any encounter can be paced."""
    def walk(node: object) -> float:
        if isinstance(node, list):
            return max((walk(n) for n in node), default=0.0)
        if isinstance(node, dict):
            found = [float(v) for k, v in node.items() if k == "distance" and isinstance(v, int | float)]
            return max([*found, *(walk(v) for v in node.values())], default=0.0)
        return 0.0
    return walk(templates().get(template))


def _regular(pad: str) -> str:
    return regular_nav_sequence(pad)


def _leaf(name: str, ports: dict, pad: str) -> str:
    spec = LIBRARY.get(name)
    if spec is None or spec.kind not in ("action", "condition"):
        raise ValidationFailed(f"card template uses {name!r}, which is not a leaf of the node library")
    attrs = {p.name: OWN_PORTS[p.name] for p in spec.ports if p.name in OWN_PORTS}
    attrs.update({k: str(v) for k, v in ports.items()})
    text = "".join(f" {k}={quoteattr(v)}" for k, v in attrs.items())
    return f"{pad}<{name}{text}/>\n"


def _node(node: object, level: int) -> str:
    pad = "    " * level
    if node == REGULAR:
        return _regular(pad)
    if isinstance(node, str):
        return _leaf(node, {}, pad)
    if not isinstance(node, dict) or len(node) != 1:
        raise ValidationFailed(f"card template node must be a name or a one-key mapping, got {node!r}")
    (name, body), = node.items()
    if name in CONTROLS:
        children = "".join(_node(c, level + 1) for c in (body or []))
        return f"{pad}<{name}>\n{children}{pad}</{name}>\n"
    return _leaf(name, body or {}, pad)


def render_template(template: str, tree_id: str) -> str:
    """The template as a complete v3 file with the RegularNavTree include, validated on the library."""
    spec = templates().get(template)
    if spec is None:
        raise ValidationFailed(f"unknown card tree template {template!r}", hint="see cards/templates.yaml")
    xml = (f'<root main_tree_to_execute="{tree_id}">\n'
           '    <include path="BTRegularNav.xml"/>\n'
           f'    <BehaviorTree ID="{tree_id}">\n'
           + _node(spec, 2)
           + "    </BehaviorTree>\n</root>\n")
    problems = validate_bt_text(xml, f"template {template}")
    if problems:
        raise ValidationFailed(f"card template {template!r} is not a valid tree:\n" + format_problems(problems))
    return xml
