"""Scenario cards: the 25 canonical scenarios of Francis et al. as data (cards.yaml), and a
deterministic generator that places a card on any location's scene graph (no LLM)."""

from socnavgen.cards.library import all_cards, card_criteria, get_card
from socnavgen.cards.models import Card, Criterion, HumanRole

__all__ = ["Card", "Criterion", "HumanRole", "all_cards", "card_criteria", "get_card"]
