"""Prompt texts are derived from the library table: every node, port and code table appears, and
every example they show passes the validator."""

from __future__ import annotations

import re

import pytest

from socnavgen.bt.describe import (
    capabilities_text,
    gesture_tables,
    library_text,
    node_example,
    regular_nav_text,
)
from socnavgen.bt.library import DISTANCE_WORDS, LIBRARY, LIBRARY_TREES, NODES, prompt_nodes
from socnavgen.bt.validate import validate_bt_text


def test_library_text_lists_every_prompt_node_with_its_ports() -> None:
    text = library_text()
    for spec in prompt_nodes():
        if spec.kind in ("builtin", "subtree"):
            continue
        assert f"- {spec.name}: {spec.description}" in text
        for port in spec.ports:
            if port.name != "name":
                assert f"port {port.name} ({port.type}" in text
    hidden = [n.name for n in NODES if not n.in_prompt]
    assert hidden and all(f"- {name}:" not in text for name in hidden)


def test_library_text_has_every_gesture_table_and_distance_word() -> None:
    text = library_text()
    tables = gesture_tables()
    users = {u for names, _ in tables for u in names}
    expected_users = {f"{n.name}.{p.name}" for n in NODES for p in n.ports if p.allowed}
    assert users == expected_users
    for names, table in tables:
        line = next(x for x in text.splitlines() if x.startswith(f"Gesture codes for {', '.join(names)}:"))
        for code, meaning in table.items():
            assert f"{code} = {meaning}" in line
    for distance, word in DISTANCE_WORDS.items():
        assert f"{word} = {distance:g} m" in text


def test_library_text_for_a_target_lists_only_its_nodes() -> None:
    text = library_text("hunav1")
    assert "- RobotSays:" not in text and "- TimeExpiredCondition:" in text
    assert "Gesture codes" not in text  # no hunav1 node takes a gesture code


@pytest.mark.parametrize("name", [n.name for n in NODES if n.kind in ("action", "condition")
                                  and "socrates" in n.targets])
def test_every_node_example_validates(name: str) -> None:
    example = node_example(LIBRARY[name])
    xml = f"<root main_tree_to_execute='T'><BehaviorTree ID='T'>{example}</BehaviorTree></root>"
    assert validate_bt_text(xml) == []
    assert '"' not in example  # single quotes: the XML travels inside a JSON string


def test_examples_in_the_prompt_text_are_the_derived_ones() -> None:
    text = library_text()
    shown = re.findall(r"example: (<\w+[^>]*/>)", text)
    assert len(shown) == len([n for n in prompt_nodes() if n.kind in ("action", "condition")])
    for example in shown:
        xml = f"<root main_tree_to_execute='T'><BehaviorTree ID='T'>{example}</BehaviorTree></root>"
        assert validate_bt_text(xml) == [], example


def test_capabilities_text_has_every_capability() -> None:
    text = capabilities_text()
    caps = [n.capability for n in prompt_nodes() if n.capability]
    assert caps
    assert text.splitlines()[1:] == [f"- {c}" for c in caps]


def test_regular_nav_text_shows_a_valid_include_and_idiom() -> None:
    text = regular_nav_text()
    (file_name, tree_id), = LIBRARY_TREES.items()
    assert f"<include path='{file_name}'/>" in text
    idiom = re.search(r"(<Sequence name='RegNav'>.*?</Sequence>)", text, re.S).group(1)
    assert f"<SubTree ID='{tree_id}' id='agentid' dt='timestep'/>" in idiom
    xml = (f"<root main_tree_to_execute='T'><include path='{file_name}'/>"
           f"<BehaviorTree ID='T'>{idiom}</BehaviorTree></root>")
    assert validate_bt_text(xml) == []
    # The library tree itself is shown, with single quotes.
    assert f"<BehaviorTree ID='{tree_id}'>" in text
