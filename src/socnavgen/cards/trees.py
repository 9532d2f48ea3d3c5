"""Card tree templates (templates.yaml) -> BT.CPP v3 XML from library nodes, validated like any tree."""

from __future__ import annotations

from functools import cache
from importlib import resources
from xml.sax.saxutils import quoteattr

import yaml

from socnavgen.bt.expand import load_instance
from socnavgen.bt.library import LIBRARY, regular_nav_sequence
from socnavgen.bt.validate import format_problems, validate_bt_text
from socnavgen.errors import ValidationFailed

REGULAR = "REGULAR"


@cache
def templates() -> dict[str, object]:
    text = resources.files("socnavgen.cards").joinpath("templates.yaml").read_text(encoding="utf-8")
    return dict(yaml.safe_load(text)["templates"])


@cache
def sight_distance(template: str) -> float:
    """The farthest a template's conditions look for the robot (m): a person placed closer than this to
    the robot's start reacts at t = 0, before any encounter can be paced."""
    instance = load_instance(render_template(template, "CardTree"), f"template {template}")
    return max((float(d) for n in instance.root.walk()
                if n.kind == "condition" and isinstance(d := n.value("distance"), float)), default=0.0)


NEAR_CONDITIONS = ("IsRobotNearby", "IsRobotVisible")  # conditions that hold while the robot is within a distance
STANDING_LEAVES = ("LookAtRobot",)  # leaves that keep a person standing where they are


@cache
def waiting_distance(template: str) -> float:
    """How near the robot makes a template's person stand and wait for as long as it stays that near (m; 0: none):
    a Sequence whose children are only a robot-near condition and standing leaves (a timer or an inverted
    condition bounds the wait). A robot whose goal lies this close to where such a person waits never gets them
    to walk on (cards.routes.oncoming_start)."""
    found = 0.0

    def visit(node: object) -> None:
        nonlocal found
        if not isinstance(node, dict):
            return
        for name, body in node.items():
            if name == "Sequence" and isinstance(body, list):
                near = [next(iter(c.values())) for c in body if isinstance(c, dict) and next(iter(c)) in NEAR_CONDITIONS]
                rest = [c for c in body if not (isinstance(c, dict) and next(iter(c)) in NEAR_CONDITIONS)]
                if len(near) == 1 and rest and all(c in STANDING_LEAVES for c in rest):
                    found = max(found, float(near[0].get("distance", 0.0)))
            for child in body if isinstance(body, list) else []:
                visit(child)

    visit(templates()[template])
    return found


def _regular(pad: str) -> str:
    return regular_nav_sequence(pad)


def _leaf(name: str, ports: dict, pad: str) -> str:
    spec = LIBRARY.get(name)
    if spec is None or spec.kind not in ("action", "condition"):
        raise ValidationFailed(f"card template uses {name!r}, which is not a leaf of the node library")
    attrs = {p.name: "{" + p.reads_root + "}" for p in spec.ports if p.reads_root is not None}
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
    if name in LIBRARY and LIBRARY[name].kind in ("control", "decorator"):
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
