"""One home per fact, as round-7 players read them: stage 1's narrow-passage list is the scene graph's narrow
edges (home i6-z2 1.2 m was narrow at stage 2 and missing at stage 1), the location prose states no door width
the inventory contradicts, and stage 1 states the start rule, what a wait_until_clear cue waits for and why a
block can end at once, each with the numbers of where it is implemented."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.location.inventory import inventory_text
from socnavgen.location.placement import start_rule_text
from socnavgen.proposal.paths import scene_graph_text
from socnavgen.proposal.scenario import scenario_messages
from socnavgen.proposal.templates import template_data
from socnavgen.run import ScenarioRequest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
BUNDLED = ("home", "hospital", "warehouse")


@pytest.fixture(scope="module", params=BUNDLED)
def location(request):  # noqa: ANN001, ANN201
    return load_location(EXAMPLES / request.param)


def _listed_narrow(text: str) -> set[frozenset[str]]:
    line = next(line for line in text.splitlines() if line.startswith("Narrow passages"))
    return {frozenset((a, b)) for a, b in re.findall(r"(\w+)-(\w+) \d+\.\d m", line.split("):", 1)[1])}


def test_stage_1_lists_every_edge_the_scene_graph_marks_narrow(location):
    graph = json.loads(scene_graph_text(location))
    marked = {frozenset((e["source"], e["target"])) for e in graph["links"] if e.get("narrow")}
    assert marked and _listed_narrow(inventory_text(location)) == marked


def test_the_homes_hallway_door_edge_is_narrow_at_both_stages():
    home = load_location(EXAMPLES / "home")
    assert frozenset(("i6", "z2")) in _listed_narrow(inventory_text(home))
    assert re.search(r"i6-z2 1\.2 m", _stage1(home))


DOOR_WIDTH = re.compile(r"doorways? (?:are|is|about) (?:about )?(\d+(?:\.\d+)?) m wide", re.IGNORECASE)


def _door_claims(description: str, widths: list[float]) -> list[str]:
    """The door widths a description states that the inventory's doorways do not have (within 0.15 m of the
    median doorway)."""
    median = sorted(widths)[len(widths) // 2]
    return [w for w in DOOR_WIDTH.findall(description) if abs(float(w) - median) > 0.15]


def test_no_location_prose_states_a_door_width_its_inventory_contradicts(location):
    widths = [d.width_m for d in location.inventory.doorways]
    assert widths and _door_claims(location.config.description, widths) == []


def test_the_door_width_check_finds_the_old_home_sentence():
    home = load_location(EXAMPLES / "home")
    widths = [d.width_m for d in home.inventory.doorways]
    assert _door_claims("Doorways are 1.5 m wide, so only one person passes at a time", widths) == ["1.5"]


def _stage1(location) -> str:  # noqa: ANN001
    request = ScenarioRequest(location=str(location.root), context="Assistant robot", task="Bring tea",
                              llm="replay")
    return "\n".join(m.content for m in scenario_messages(request, location))


def test_stage_1_states_the_start_rule_and_the_waits_with_their_sources_numbers():
    from socnavgen import proxemics
    from socnavgen.sim.people.leaves import BLOCK_AHEAD
    from socnavgen.sim.robot.script import CLEAR_PATIENCE

    text = _stage1(load_location(EXAMPLES / "home"))
    assert start_rule_text() in text
    assert f"in its way (ahead of it, on its route) within {proxemics.HELD_UP_DISTANCE:g} m" in text
    assert "whatever the trigger is (at_encounter, human_within, blocked" in text
    assert f"still held after {CLEAR_PATIENCE:g} s" in text
    assert f"stands {BLOCK_AHEAD:g} m (centres) ahead of the robot" in text
    assert "where its widths differ from this inventory, the inventory (measured) is right" in text


def test_no_example_robot_says_proceed_while_it_holds():
    """PROCEED tells the other to go: a robot that waits while it says it reads as a contradiction."""
    for example in template_data("scenario_examples.json"):
        spec = example["reply"].get("spec") or {}
        for cue in (spec.get("script") or {}).get("cues", []):
            assert not (cue.get("say") == "PROCEED" and (cue.get("wait") or cue.get("wait_until_clear"))), cue


def test_the_stl_text_says_bounds_are_optional_and_an_unbounded_formula_parses():
    from socnavgen.proposal.facts import stl_text
    from socnavgen.verify.stl import formula_bounds

    assert "an operator without bounds" in stl_text() and "is allowed and spans the whole run" in stl_text()
    assert formula_bounds("eventually (dist_human1 <= 2.0)", 0.1) == []
