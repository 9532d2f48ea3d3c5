"""The card library as data: complete, valid, and readable by the verifier."""

from __future__ import annotations

import json
from pathlib import Path
from typing import get_args

import pytest

from socnavgen.bt.validate import validate_bt_text
from socnavgen.cards.library import all_cards, card_criteria, get_card
from socnavgen.cards.models import CriterionKind
from socnavgen.cards.trees import render_template, templates
from socnavgen.errors import SocnavgenError

FRANCIS = ["frontal approach", "pedestrian obstruction", "pedestrian overtaking", "robot overtaking", "down path",
           "intersection no gesture", "intersection wait", "intersection proceed", "blind corner",
           "narrow hallway", "narrow doorway", "entering room", "exiting room", "entering elevator",
           "exiting elevator", "join group", "leave group", "following human", "leading human",
           "accompanying peer", "crowd navigation", "parallel traffic", "perpendicular traffic",
           "circular crossing", "robot crowding"]


def test_the_25_canonical_scenarios_are_all_there() -> None:
    names = [c.name for c in all_cards()]
    assert len(names) == 25 == len(set(names))
    assert names == [n.replace(" ", "-") for n in FRANCIS]


def test_every_card_is_complete() -> None:
    for card in all_cards():
        assert card.rough and card.context and card.task and card.expected_robot_behavior, card.name
        assert card.picture and "\n" not in card.picture, card.name
        assert card.criteria and card.humans, card.name
        assert all(h.tree in templates() for h in card.humans), card.name


def test_criteria_kinds_are_known() -> None:
    known = set(get_args(CriterionKind))
    for card in all_cards():
        for c in card.criteria:
            assert c.kind in known, (card.name, c.kind)
            if c.kind in ("executes", "gives_way_while_passing"):
                assert c.node, card.name


def test_every_template_renders_a_valid_tree() -> None:
    for name in templates():
        xml = render_template(name, "CardTree")
        assert validate_bt_text(xml, name) == []
        assert 'main_tree_to_execute="CardTree"' in xml


def test_get_card_is_forgiving_and_suggests() -> None:
    card = get_card("Blind_Corner")
    assert card.name == "blind-corner" and "blind corner" in card.rough
    with pytest.raises(SocnavgenError, match="blind-corner"):
        get_card("blind-corne")


def test_card_criteria_reads_the_run_request(tmp_path: Path) -> None:
    (tmp_path / "request.json").write_text(json.dumps({"location": "x", "context": "c", "task": "t",
                                                       "card": "narrow-hallway"}))
    crit = card_criteria(tmp_path)
    assert {"kind": "gives_way_while_passing", "human": "human1", "node": "GiveWaytoRobot"} in crit
    assert all(isinstance(c, dict) and "kind" in c for c in crit)
    (tmp_path / "request.json").write_text(json.dumps({"location": "x", "context": "c", "task": "t"}))
    assert card_criteria(tmp_path) == []
