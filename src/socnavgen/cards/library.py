"""The card library: cards.yaml loaded once into `Card` models, looked up by name.

`card_criteria(run_dir)` is the verifier's entry point: the success criteria of the card named in
the run's request.json, as plain dicts."""

from __future__ import annotations

from functools import cache
from importlib import resources
from pathlib import Path

import yaml
from pydantic import ValidationError

from socnavgen.cards.models import Card
from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.run import RunFolder
from socnavgen.text import did_you_mean

CARDS_FILE = "cards.yaml"


@cache
def all_cards() -> tuple[Card, ...]:
    """Every card, in the order of cards.yaml (Francis et al.'s order)."""
    text = resources.files("socnavgen.cards").joinpath(CARDS_FILE).read_text(encoding="utf-8")
    data = yaml.safe_load(text)
    try:
        cards = tuple(Card.model_validate(c) for c in data["cards"])
    except ValidationError as exc:  # a packaging bug, not a user error, but say where
        raise ValidationFailed(f"cards.yaml is invalid: {exc}", file=CARDS_FILE) from exc
    names = [c.name for c in cards]
    if len(set(names)) != len(names):
        raise ValidationFailed("cards.yaml has duplicate card names", file=CARDS_FILE)
    return cards


def card_names() -> list[str]:
    return [c.name for c in all_cards()]


def get_card(name: str) -> Card:
    """The card called `name` (case and -/_/space insensitive); a clear error with suggestions otherwise."""
    key = name.strip().lower().replace("_", "-").replace(" ", "-")
    for card in all_cards():
        if card.name == key:
            return card
    hint = did_you_mean(key, card_names(), n=3, cutoff=0.5) or "socnavgen cards list shows every card"
    raise ValidationFailed(f"no scenario card named {name!r}", hint=hint)


def card_criteria(run_dir: Path | str) -> list[dict]:
    """Success criteria of the run's card (request.json `card`), as dicts the verifier reads; [] if none."""
    run = RunFolder(Path(run_dir))
    if not run.request_path.is_file():
        raise InputFileError("the run has no request.json", file=run.root)
    name = run.read_request().card
    if not name:
        return []
    return [c.model_dump(exclude_none=True) for c in get_card(name).criteria]
