"""Stage rules the model players met, each stated the way it is checked: where giving way is possible,
which node is a person's interaction point when they have several encounters, round trips, and what
stage 1 is shown to name places ("the north elevator"): node positions and the annotated map."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from socnavgen.location import load_location
from socnavgen.proposal.facts import STATED_BY
from socnavgen.proposal.path_checks import check_paths, to_path_plan
from socnavgen.proposal.replies import PathsReply, ScenarioReply
from socnavgen.proposal.scenario import fitted_scenario_messages, scenario_checker, to_spec
from socnavgen.run import ScenarioRequest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"


@pytest.fixture(scope="module")
def warehouse():
    return load_location(EXAMPLES / "warehouse")


def _reply(*encounters: dict) -> ScenarioReply:
    humans = sorted({p["human"] for e in encounters for p in e["humans"]})
    return ScenarioReply.model_validate({
        "scenario_description": "The robot carries a box past workers in the warehouse aisles and corners.",
        "number_of_humans": len(humans),
        "human_behaviors": {h: "A worker walks to the racks and lets the robot pass." for h in humans},
        "expected_robot_behavior": "Slow down near the workers and pass at a polite distance.",
        "spec": {"script": {"route": "from the entrance to the racks"}, "encounters": list(encounters),
                 "criteria": [{"id": f"c{k + 1}", "kind": kind, "human": e["humans"][0]["human"], "encounter": e["id"]}
                              for k, (kind, e) in enumerate((kind, e) for e in encounters for kind in
                                                            ("meets", *STATED_BY.get(e["humans"][0]["reaction"], ())[:1]))]}})


def _encounter(eid: str, place: str, reaction: str = "give_way", order: int = 1, human: str = "human1") -> dict:
    return {"id": eid, "place": place, "order": order,
            "humans": [{"human": human, "trigger": "robot_near", "reaction": reaction, "distance": 2.0}]}


def _answer(robot: list[str], human: list[str], point: str, nodes: dict[str, str]) -> PathsReply:
    return PathsReply.model_validate({"trajectories": {"robot": robot, "human1": human}, "group_ids": {"human1": -1},
                                      "interaction_points": {"human1": point}, "encounter_nodes": nodes})


# ---- giving way needs room -------------------------------------------------------------------------
def test_giving_way_where_nobody_can_step_aside_is_refused(warehouse):
    check = scenario_checker(warehouse)
    aisle = check(_reply(_encounter("e1", "AISLE END")))  # every aisle end is 1.0 m wide
    assert any("human1 gives way at a AISLE END, but no AISLE END node has room to step aside (1.6 m free" in m
               for m in aisle), aisle
    assert check(_reply(_encounter("e1", "AISLE END", reaction="walk_past"))) == []  # walking out ahead works
    corner = _reply(_encounter("e1", "BLIND CORNER"))
    assert check(corner) == []  # f7 and 6r have room
    spec = to_spec(corner)
    robot, human = ["up", "co", "54", "f7", "6r"], ["6r", "f7", "54"]
    at_54 = check_paths(_answer(robot, human, "54", {"e1": "54"}), warehouse.graph, ["human1"], spec, warehouse)
    assert any("human1 gives way in encounter e1 at node 54, which has only 1.4 m free" in m and "6r, f7" in m
               for m in at_54), at_54
    assert check_paths(_answer(robot, human, "f7", {"e1": "f7"}), warehouse.graph, ["human1"], spec, warehouse) == []


def test_the_inventory_says_where_nobody_can_step_aside(warehouse):
    from socnavgen.location.inventory import inventory_text

    text = inventory_text(warehouse)
    assert "whether both move or one of them stands" in text  # a waiting robot leaves no more room
    line = next(t for t in text.splitlines() if t.startswith("No room to step aside (give_way) at:"))
    assert "12" in line and "54" in line and "f7" not in line


# ---- a person in several encounters ------------------------------------------------------------------
def test_the_interaction_point_of_a_person_in_several_encounters_is_their_first_encounters_node(warehouse):
    spec = to_spec(_reply(_encounter("e2", "INTERSECTION", reaction="look", order=2),
                          _encounter("e1", "BLIND CORNER", reaction="stop", order=1)))
    robot, human = ["up", "co", "54", "f7", "6r", "hd"], ["hd", "6r", "f7"]
    nodes = {"e1": "f7", "e2": "hd"}
    assert check_paths(_answer(robot, human, "f7", nodes), warehouse.graph, ["human1"], spec, warehouse) == []
    wrong = check_paths(_answer(robot, human, "hd", nodes), warehouse.graph, ["human1"], spec, warehouse)
    assert any("the interaction point hd of human1 differs from the node f7 of its first encounter e1" in m
               for m in wrong), wrong
    missing = PathsReply.model_validate({"trajectories": {"robot": robot, "human1": human},
                                         "group_ids": {"human1": -1}, "encounter_nodes": nodes})
    assert to_path_plan(missing, ["human1"], spec).humans[0].interaction_point == "f7"


def test_one_persons_two_encounters_need_two_nodes(warehouse):
    """Two meetings of one person at one node cannot be told apart (the verifier orders encounters by where they
    happen): stage 2 refuses the same node, stage 1 more encounters at a kind of place than the map has nodes of."""
    from socnavgen.proposal.facts import TWO_ENCOUNTERS
    from socnavgen.proposal.paths import POINT_RULE_ENCOUNTERS, encounter_rule

    spec = to_spec(_reply(_encounter("e1", "INTERSECTION", reaction="stop"),
                          _encounter("e2", "INTERSECTION", reaction="look", order=2)))
    robot, human = ["up", "ki", "sh", "ki", "hd"], ["sw", "sh", "ki", "hd"]
    same = check_paths(_answer(robot, human, "ki", {"e1": "ki", "e2": "ki"}), warehouse.graph, ["human1"], spec,
                       warehouse)
    assert any("encounters e1 and e2 of human1 are both at node ki" in m for m in same), same
    assert check_paths(_answer(robot, human, "sh", {"e1": "sh", "e2": "ki"}), warehouse.graph, ["human1"], spec,
                       warehouse) == []
    check = scenario_checker(warehouse)
    corner = {n for n, d in warehouse.graph.nodes(data=True) if d.get("type") == "CORNER"}
    assert len(corner) == 1  # the warehouse has one CORNER node
    twice = check(_reply(_encounter("e1", "CORNER", reaction="stop"), _encounter("e2", "CORNER", "look", 2)))
    assert any("encounters e1, e2 of human1 are all at a CORNER, but this map has only 1 CORNER node" in m
               for m in twice), twice
    assert not any("are all at a" in m for m in check(_reply(_encounter("e1", "INTERSECTION", reaction="stop"),
                                                                _encounter("e2", "INTERSECTION", "look", 2))))
    request = ScenarioRequest(location=str(warehouse.root), context="c", task="carry a box", llm="replay")
    system = fitted_scenario_messages(request, warehouse, object())[0].content  # type: ignore[arg-type]
    assert TWO_ENCOUNTERS in system and TWO_ENCOUNTERS in POINT_RULE_ENCOUNTERS and "e2 give way" not in system
    assert encounter_rule()  # stage 2 states it with rule 6


def test_a_field_at_the_wrong_level_says_where_it_belongs():
    """A player put a cue's "once" inside its trigger: the mistake names where it goes (and the prompt shows it)."""
    from socnavgen.proposal.facts import cue_once_text
    from socnavgen.proposal.spec_checks import parse_spec
    from socnavgen.run.spec import RobotCue

    _, inside = parse_spec({"script": {"cues": [{"trigger": {"when": "start", "once": False}, "say": "EXCUSE ME"}]}})
    assert inside == ['spec.script.cues.0.trigger.once: Extra inputs are not permitted here: "once" belongs to '
                      'spec.script.cues.0, not inside "trigger"'], inside
    _, beside = parse_spec({"script": {"cues": [{"trigger": {"when": "human_within"}, "distance": 2.0}]}})
    assert 'spec.script.cues.0.distance: Extra inputs are not permitted here: "distance" belongs inside "trigger" ' \
           '(spec.script.cues.0.trigger)' in beside, beside
    _, unknown = parse_spec({"people": {"human1": {"fast": True}}})
    assert unknown == ["spec.people.human1.fast: Extra inputs are not permitted"]
    assert '"wait": 3, "once": false}' in cue_once_text() and 'beside "trigger" (not inside it)' in cue_once_text()
    cue = json.loads(cue_once_text().split("it): ")[1].split(" waits")[0])
    assert RobotCue.model_validate(cue).once is False


# ---- round trips --------------------------------------------------------------------------------------
def test_a_round_trip_is_a_route(warehouse):
    spec = to_spec(_reply(_encounter("e1", "INTERSECTION", reaction="look")))
    there_and_back = _answer(["up", "ki", "sh", "ki", "up"], ["sw", "sh"], "sh", {"e1": "sh"})
    assert check_paths(there_and_back, warehouse.graph, ["human1"], spec, warehouse) == []
    nowhere = _answer(["up", "up"], ["sw", "sh"], "sh", {"e1": "sh"})
    assert any("goes nowhere in between" in m for m in
               check_paths(nowhere, warehouse.graph, ["human1"], spec, warehouse))


# ---- a meeting needs an approach -----------------------------------------------------------------------
def test_an_encounter_where_a_person_waits_too_near_the_robots_start_is_refused(warehouse):
    """A person waiting at an encounter's node 1.9 m from the robot's start is met before anyone moved (the
    verifier's meets needs the two to come APPROACH closer): refused with the minimum, which the prompt states."""
    from socnavgen.proposal.facts import approach_room
    from socnavgen.proposal.paths import encounter_rule
    from socnavgen.verify.thresholds import APPROACH, MEET_DISTANCE

    assert approach_room() == MEET_DISTANCE + APPROACH
    assert f"at least {MEET_DISTANCE + APPROACH:g} m (between xy_m) from the robot's start" in encounter_rule()
    from socnavgen.proposal.facts import physical_facts_text
    for stage2 in (True, False):  # stage 1 places its encounters with it too (a round-6 player missed it there)
        assert f"both came {APPROACH:g} m closer to each other and to the node than at the start (a robot standing " \
               f"at its start meets nobody; a person waiting at the node: at least {MEET_DISTANCE + APPROACH:g} m " \
               "from the robot's start" in physical_facts_text(scene_graph=stage2)
    spec = to_spec(_reply(_encounter("e1", "INTERSECTION", reaction="look")))
    waits_near = _answer(["qs", "sh", "ki", "up"], ["sh"], "sh", {"e1": "sh"})  # qs-sh: 1.9 m
    refused = check_paths(waits_near, warehouse.graph, ["human1"], spec, warehouse)
    assert any("encounter e1: human1 waits at node sh, only 1.90 m from the robot's start qs" in m and
               f"at least {MEET_DISTANCE + APPROACH:g} m" in m for m in refused), refused
    waits_far = _answer(["up", "ki", "sh", "qs"], ["sh"], "sh", {"e1": "sh"})
    assert check_paths(waits_far, warehouse.graph, ["human1"], spec, warehouse) == []
    walks_in = _answer(["qs", "sh", "ki", "up"], ["sw", "sh"], "sh", {"e1": "sh"})  # the person approaches
    assert not any("waits at node" in m for m in check_paths(walks_in, warehouse.graph, ["human1"], spec, warehouse))
    wider = to_spec(_reply(_encounter("e1", "INTERSECTION", reaction="look")))
    wider.criteria[0].distance = 3.0  # its own meets distance: that + APPROACH
    assert approach_room(wider, wider.encounters[0], "human1") == 3.0 + APPROACH


def test_the_paths_prompt_defines_the_interaction_point_once(warehouse):
    from socnavgen.proposal.paths import encounter_rule, paths_messages
    from socnavgen.run import ScenarioProposal

    spec = to_spec(_reply(_encounter("e1", "INTERSECTION", reaction="look")))
    proposal = ScenarioProposal(scenario_description="A worker waits at an intersection.", number_of_humans=1,
                                human_behaviors={"human1": "A worker waits and looks at the robot."},
                                expected_robot_behavior="Pass politely.")
    user = paths_messages(warehouse, proposal, spec=spec, images=False)[-1].content
    assert "6. The interaction point of a human is the node of that human's FIRST encounter" in user
    assert "meets it first" not in user and "where it meets the robot first" not in user
    assert "interaction point is the node of its FIRST encounter" not in encounter_rule()  # rule 8 refers to 6
    plain = paths_messages(warehouse, proposal, images=False)[-1].content
    assert "6. The interaction point of a human is the node where pacing brings" in plain and "8. " not in plain


# ---- what stage 1 sees to name places -----------------------------------------------------------------
def test_stage1_shows_positions_and_to_vision_models_the_annotated_map(warehouse):
    class Vision:
        supports_images = True

    class Text:
        supports_images = False

    request = ScenarioRequest(location=str(warehouse.root), context="c", task="the north aisle", llm="replay")
    seen = fitted_scenario_messages(request, warehouse, Vision())[-1]
    assert [p.name for p in seen.images] == ["scene_graph.png"] and "north is up" in seen.content
    assert "at = position x,y in metres (x east, y north)" in seen.content and "- ENTRANCE: sk (at " in seen.content
    assert fitted_scenario_messages(request, warehouse, Text())[-1].images == []
    no_image = request.model_copy(update={"use_image": False})
    assert fitted_scenario_messages(no_image, warehouse, Vision())[-1].images == []


# ---- in-process models: the grammars keep give_way where there is room ------------------------------
def test_the_grammars_of_small_models_offer_give_way_only_where_there_is_room(warehouse):
    import json

    from socnavgen.proposal.path_grammar import build_paths_grammar
    from socnavgen.proposal.scenario import build_scenario_grammar, stage_grammar

    class Small:
        supports_grammar = True

    rule = next(line for line in stage_grammar(Small(), warehouse, None).splitlines()  # AISLE END is tight here
                if line.startswith("encounter1 ::="))
    offered = [(alt.split('"')[1], "give_way" in alt) for alt in rule.split("::=")[1].split(" | ")]
    assert ("AISLE END", False) in offered and ("AISLE END", True) not in offered and ("BLIND CORNER", True) in offered
    grammar = build_scenario_grammar(node_types=["AISLE END", "BLIND CORNER"], tight={"AISLE END"})
    reply = _reply(_encounter("e1", "AISLE END")).model_dump(exclude={"spec"})
    spec = {"script": {"route": "from the entrance to the racks", "cues": []},
            "encounters": [{"id": "e1", "place": "AISLE END", "humans": [
                {"human": "human1", "trigger": "robot_near", "reaction": "give_way"}]}],
            "criteria": [{"id": "c1", "kind": "meets", "human": "human1", "encounter": "e1"}]}
    assert not grammar.matches(json.dumps({**reply, "spec": spec}))
    spec["encounters"][0]["humans"][0]["reaction"] = "walk_past"
    assert grammar.matches(json.dumps({**reply, "spec": spec}))
    spec["encounters"][0].update(place="BLIND CORNER", humans=[{"human": "human1", "trigger": "robot_near",
                                                                 "reaction": "give_way"}])
    assert not grammar.matches(json.dumps({**reply, "spec": spec}))  # its giving way is stated, too
    spec["criteria"].append({"id": "c2", "kind": "gives_way", "human": "human1", "encounter": "e1"})
    assert grammar.matches(json.dumps({**reply, "spec": spec}))

    corner = to_spec(_reply(_encounter("e1", "BLIND CORNER")))
    cramped = {n for n, facts in warehouse.inventory.nodes.items() if not facts.turnable}
    paths = build_paths_grammar(warehouse.graph, ["human1"], corner, cramped)
    meeting = {r for r in paths.rules if r.startswith("robot")}
    index = {n: i for i, n in enumerate(sorted(warehouse.graph.nodes))}
    assert f"robot{index['f7']}" in meeting and f"robot{index['54']}" not in meeting  # 54: 1.4 m free


# ---- a checked stop needs a walk before it ---------------------------------------------------------------
def test_a_checked_stop_of_a_person_who_starts_at_its_node_is_refused(warehouse):
    """reacts_after_phrase sees a stop only after the person walked MOVED_DISTANCE from their start (verify/signals
    reaction_evidence): a person who starts at the node where they stop can never pass it. Stage 2 refuses that
    path, and rule 8 says so (a round-6 player learnt it only from the verifier)."""
    from socnavgen.proposal.facts import stop_evidence_text
    from socnavgen.proposal.paths import encounter_rule
    from socnavgen.verify.thresholds import MOVED_DISTANCE

    assert stop_evidence_text() in encounter_rule() and f"AFTER having walked {MOVED_DISTANCE:g} m" in encounter_rule()
    encounter = {"id": "e1", "place": "INTERSECTION", "order": 1,
                 "humans": [{"human": "human1", "trigger": "robot_says", "phrase": "EXCUSE ME",
                             "reaction": "wait_then_go"}]}
    reply = _reply(encounter)
    reply.spec["criteria"].append({"id": "c2", "kind": "reacts_after_phrase", "human": "human1", "encounter": "e1",
                                   "phrase": "EXCUSE ME", "reaction": "wait_then_go", "seconds": 5})
    spec = to_spec(reply)
    starts_there = _answer(["up", "ki", "sh", "qs"], ["sh", "sw"], "sh", {"e1": "sh"})
    refused = check_paths(starts_there, warehouse.graph, ["human1"], spec, warehouse)
    assert any(f"criterion c2 sees human1's wait_then_go at node sh only after they walked {MOVED_DISTANCE:g} m"
               in m and "starts at sh" in m for m in refused), refused
    walks_in = _answer(["up", "ki", "sh", "qs"], ["sw", "sh"], "sh", {"e1": "sh"})
    assert not any("only after they walked" in m for m in
                   check_paths(walks_in, warehouse.graph, ["human1"], spec, warehouse))
    spec.criteria.pop()  # without the criterion nothing checks the stop: the start is free
    assert not any("only after they walked" in m for m in
                   check_paths(starts_there, warehouse.graph, ["human1"], spec, warehouse))


def test_both_stages_say_that_pacing_meets_face_to_face_in_a_narrow_passage(warehouse):
    """Pacing brings the person to the node WITH the robot: in a passage one person closes that is a standoff, so
    the prompts say where to put the encounter when the robot should wait before it (a round-6 player's doorway)."""
    from socnavgen.location.inventory import BLOCKING_WIDTH
    from socnavgen.proposal.facts import pacing_text, scenario_rules_text
    from socnavgen.proposal.paths import paths_messages
    from socnavgen.run import ScenarioProposal

    fact = f"Arriving together at a passage narrower than {BLOCKING_WIDTH:g} m (a doorway) puts the two face to face"
    assert fact in pacing_text() and fact in scenario_rules_text()
    proposal = ScenarioProposal(scenario_description="A worker comes out of an aisle.", number_of_humans=1,
                                human_behaviors={"human1": "A worker walks out of the aisle past the robot."},
                                expected_robot_behavior="Wait before the aisle.")
    assert fact in paths_messages(warehouse, proposal, images=False)[-1].content
