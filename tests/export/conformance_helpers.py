"""Shared by the HuNavSim conformance tests: every card placed on every bundled location (built once
per session), the trees of the replay fixtures, and a real BehaviorTree.CPP 4 (behaviortreepy) with
dummy nodes registered under exactly the ids HuNavSim 2.x registers."""

from __future__ import annotations

import itertools
import json
from functools import cache
from pathlib import Path

import yaml

from socnavgen.bt.library import HUNAV2_REGISTERED
from socnavgen.bt.tree import BTElement, read_xml
from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.export.models import ExportScene, HumanExport, WorldPoint
from socnavgen.export.scene import build_scene
from socnavgen.export.writer import element_xml
from socnavgen.location import load_location

ROOT = Path(__file__).resolve().parents[2]
LOCATIONS = sorted(p for p in (ROOT / "examples" / "locations").iterdir() if (p / "location.yaml").is_file())
REPLAY = sorted((ROOT / "tests" / "fixtures" / "replay").glob("*.yaml"))


@cache
def card_scenes(workdir: str) -> tuple[tuple[str, ExportScene], ...]:
    """(label, scene) of every card that fits every bundled location, written under workdir."""
    out = []
    for location_dir in LOCATIONS:
        for fit in fit_all(load_location(location_dir)):
            if fit.placement is None:
                continue
            label = f"{location_dir.name}/{fit.card.name}"
            run = write_card_run(fit.card.name, location_dir, Path(workdir) / label.replace("/", "__"))
            out.append((label, build_scene(run.root, location_dir)[0]))
    return tuple(out)


def replay_trees() -> list[tuple[str, str]]:
    """(label, xml) of every behavior tree in the scripted LLM replies."""
    found: list[tuple[str, str]] = []

    def walk(node: object, where: str) -> None:
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, f"{where}/{k}")
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, f"{where}[{i}]")
        elif isinstance(node, str) and node.lstrip().startswith("{") and "<root" in node:
            try:  # a recorded reply: the JSON object the model answered ({"reasoning": ..., "tree": "<root ...>"})
                walk(json.loads(node), where)
            except json.JSONDecodeError:
                return
        elif isinstance(node, str) and node.lstrip().startswith("<root") and "<BehaviorTree" in node:
            found.append((where, node))

    for path in REPLAY:
        walk(yaml.safe_load(path.read_text()), path.name)
    return found


def human_for(xml: str, label: str) -> HumanExport:
    point = WorldPoint(node="n", x=0.0, y=0.0)
    return HumanExport(name="human1", agent_id=0, skin=0, start=point, goals=[point], path=["n"], tree_xml=xml,
                       tree_file=label)


def without_leaf_ports(text: str) -> str:
    """The same tree with the ports of 2.x leaves removed (their `name` kept): behaviortreepy cannot declare
    ports, so BT.CPP would reject every one; the ports themselves are checked by bt.loader_rules against the table."""
    root = read_xml(text, "tree")

    def strip(elem: BTElement) -> BTElement:
        attrs = {k: v for k, v in elem.attrs.items() if k == "name" or elem.tag not in HUNAV2_REGISTERED}
        return BTElement(elem.tag, attrs, [strip(c) for c in elem.children])

    trees = "".join(element_xml(strip(t)) for t in root.children if t.tag == "BehaviorTree")
    main = root.attrs["main_tree_to_execute"]
    return f'<root BTCPP_format="4" main_tree_to_execute="{main}">\n{trees}</root>\n'


def btcpp_factory(ticks: list[str]):  # noqa: ANN201 - behaviortreepy factory
    """A real BT.CPP 4 factory with every 2.x leaf id registered: conditions alternate SUCCESS/FAILURE
    in a fixed irregular pattern (so every branch gets ticked), simple actions succeed, stateful ones
    stay RUNNING for a few ticks (as 2.x's do)."""
    import behaviortreepy as bt

    pattern = itertools.cycle([True, True, False, True, False, False, True])
    factory = bt.BehaviorTreeFactory()

    def condition(node):  # noqa: ANN001, ANN202
        ticks.append(node.name())
        return bt.NodeStatus.SUCCESS if next(pattern) else bt.NodeStatus.FAILURE

    def action(node):  # noqa: ANN001, ANN202
        ticks.append(node.name())
        return bt.NodeStatus.SUCCESS

    def running(node):  # noqa: ANN001, ANN202
        ticks.append(node.name())
        return bt.NodeStatus.RUNNING if next(pattern) else bt.NodeStatus.SUCCESS

    for node in HUNAV2_REGISTERED.values():
        if node.kind == "Condition":
            factory.register_simple_condition(node.id, condition)
        elif node.kind == "Action" and node.stateful:
            factory.register_simple_stateful_action(node.id, running, running)
        elif node.kind == "Action":
            factory.register_simple_action(node.id, action)
    return factory, bt
