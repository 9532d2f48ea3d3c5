"""The room cards (entering-room, exiting-room) fit extracted graphs: rooms get ROOM nodes behind
DOORWAY nodes, which is what the cards look for. Before room segmentation they never fitted."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.cards.generate import place_card
from socnavgen.cards.library import get_card
from socnavgen.location.extract import ExtractOptions, extract_location
from tests.extract.person_graphs import person_map


@pytest.mark.parametrize("name", ["home", "office"])
def test_room_cards_fit_an_extracted_graph(name: str, tmp_path: Path) -> None:
    pm = person_map(name, tmp_path)
    location, _ = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=2))
    types = {n.id: n.type for n in location.scene_graph.nodes}
    for card in ("entering-room", "exiting-room"):
        fit = place_card(get_card(card), location)
        assert fit.fits, fit.reason
        place = fit.placement.place
        assert {types[place.node], types.get(place.other)} >= {"DOORWAY", "ROOM"}, (card, place)


def test_room_cards_do_not_fit_the_bare_skeleton(tmp_path: Path) -> None:
    pm = person_map("office", tmp_path)
    location, _ = extract_location(pm.map_yaml, tmp_path / "out", ExtractOptions(seed=2, rooms=False))
    assert not place_card(get_card("entering-room"), location).fits
