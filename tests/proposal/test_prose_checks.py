"""The spec and the paths must say what the prose says (issue 25, proposal/prose_checks.py): a follower the text has
right behind someone, who goes first, where a person comes from. Each check refuses answers that say less than their
text and accepts the ones that say it."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import TypeVar

import pytest
from gen_helpers import paths_reply, scenario_reply, spec_for
from pydantic import BaseModel, ValidationError

from socnavgen.bodies import PERSONAL_SPACE
from socnavgen.llm.jsonrepair import extract_json
from socnavgen.location import load_location
from socnavgen.proposal.conversation import Upstream
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.place_checks import robot_wait_mistakes, stay_mistakes
from socnavgen.proposal.prose_checks import (
    close_follow_gap,
    close_follow_mistakes,
    named_nodes,
    order_mistakes,
    person_order_mistakes,
    way_in_mistakes,
)
from socnavgen.proposal.replies import PathsReply, ScenarioReply
from socnavgen.proposal.scenario import scenario_checker
from socnavgen.proposal.spec_checks import parse_spec
from socnavgen.proposal.stop_checks import stop_mistakes
from socnavgen.run.spec import ScenarioSpec
from socnavgen.safeio import load_yaml_file
from socnavgen.sim.people.leaves import follow_trail

_M = TypeVar("_M", bound=BaseModel)
FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "new_requests"
ROOT = Path(__file__).resolve().parents[2]


def _follow_spec(distance: float, text: str, kind: str = "follows_robot", speed: float = 0.5) -> ScenarioSpec:
    spec = spec_for(2)
    spec["script"].update(speed=speed, cues=[{"trigger": {"when": "start"}, "say": "FOLLOW ME"}])
    spec["encounters"][0]["humans"][0] = {"human": "human1", "trigger": "robot_says", "phrase": "FOLLOW ME",
                                          "reaction": "follow", "latch": True}
    if kind == "follows_human":
        spec["encounters"][0]["humans"][0].update(reaction="follow_human", other="human2")
    spec["people"] = {"human1": {"speed": 1.0}}
    spec["criteria"].append({"id": "c9", "kind": kind, "human": "human1", "encounter": "e1", "distance": distance,
                             "text": text})
    return ScenarioSpec.model_validate(spec)


# -- a follower right behind someone --------------------------------------------------------------------------------
def test_the_close_follow_gap_is_the_simulators_trail_plus_personal_space():
    assert close_follow_gap(0.5, 1.0) == pytest.approx(follow_trail(0.5, 1.0) + PERSONAL_SPACE)
    assert 2.5 < close_follow_gap(0.5, 1.0) < 3.0  # home_09's older child stood 3.25 m away: this catches him


@pytest.mark.parametrize("text", ["the older child follows the robot right behind it into the bedroom",
                                  "she walks close behind the robot", "he stays on its heels all the way"])
def test_a_follower_right_behind_the_robot_may_not_be_allowed_far_behind(text):
    mistakes = close_follow_mistakes(_follow_spec(4.5, text), {})
    assert len(mistakes) == 1 and "criterion c9 (follows_robot) lets human1 be up to 4.5 m" in mistakes[0]
    assert f"at most {int(close_follow_gap(0.5, 1.0) * 10) / 10:g} m" in mistakes[0]


def test_a_distance_the_text_states_holds_the_criterion_to_it():
    """'right behind it, about 2 m back' with 4.5 m allows more than the text says: still refused."""
    assert close_follow_mistakes(_follow_spec(4.5, "the child follows right behind it, about 2 m back"), {})


def test_the_words_may_be_in_the_persons_behavior():
    behaviors = {"human1": "When the robot says FOLLOW ME the child follows it for good, right behind it."}
    assert close_follow_mistakes(_follow_spec(4.5, "the child follows the robot"), behaviors)


@pytest.mark.parametrize("distance, text", [
    (2.5, "the older child follows the robot right behind it"),  # within the gap
    (4.5, "the visitor follows the robot to her room"),  # no words about closeness: the prompt's 4 m holds
    (4.5, "the worker walks in single file right behind the lead worker"),  # not about the robot (another mistake)
    (3.5, "Mia follows right behind it, about 1.5-3 m back"),  # the text says how far (round 14's home_09 player)
    (4.0, "she walks close behind the robot, within 4 m"),
])
def test_followers_whose_distance_says_what_the_text_says_are_accepted(distance, text):
    assert close_follow_mistakes(_follow_spec(distance, text), {}) == []


def test_a_person_following_right_behind_a_person_is_measured_against_that_persons_pace():
    spec = _follow_spec(4.5, "human1 walks right behind human2", kind="follows_human")
    mistakes = close_follow_mistakes(spec, {})
    assert len(mistakes) == 1 and "from human2" in mistakes[0]


# -- who goes first --------------------------------------------------------------------------------------------------
WALKS_ON_BEHIND = ("The second worker (Human 2) restocks at sh and walks west. As she passes ki the robot comes out "
                   "of the aisle; she stops, startled. The robot drives on west to up, and she then walks on behind it.")


def test_an_order_the_description_states_needs_a_criterion_that_can_see_it():
    mistakes = order_mistakes(WALKS_ON_BEHIND, {}, ScenarioSpec.model_validate(spec_for(2)))
    assert len(mistakes) == 1 and "between human2 and the robot ('behind it'" in mistakes[0]
    assert "(human2_to_node_N > 2.0) until (robot_to_node_N < 1.0)" in mistakes[0]


def test_an_order_in_a_persons_behavior_needs_it_too():
    behaviors = {"human1": "Steps out of the aisle and walks ahead of the robot to the door."}
    mistakes = order_mistakes("The robot patrols.", behaviors, ScenarioSpec.model_validate(spec_for(2)))
    assert len(mistakes) == 1 and "between human1 and the robot ('ahead of the robot'" in mistakes[0]


@pytest.mark.parametrize("criterion", [
    {"id": "c9", "kind": "stl", "formula": "(human2_to_node_07 > 2.0) until (robot_to_node_07 < 1.0)",
     "text": "the robot reaches 07 before the worker"},
    {"id": "c9", "kind": "gives_way", "human": "human2", "encounter": "e1", "text": "she lets the robot pass"},
])
def test_an_order_stated_by_a_criterion_is_accepted(criterion):
    spec = spec_for(2)
    spec["criteria"].append(criterion)
    assert order_mistakes(WALKS_ON_BEHIND, {}, ScenarioSpec.model_validate(spec)) == []


def test_an_order_whose_person_the_text_does_not_name_is_left_alone():
    text = "Both children walk right behind the robot the whole way."  # nobody named: no person to hold to it
    assert order_mistakes(text, {}, ScenarioSpec.model_validate(spec_for(2))) == []


# -- where a person comes from (stage 2) -----------------------------------------------------------------------------
def test_node_ids_named_by_a_text_skip_words_and_amounts():
    nodes = {"up", "ki", "12", "hd"}
    assert named_nodes("She walks up the aisle from ki, waits 12 s, then goes to hd and to 12.", nodes) == \
        ["ki", "hd", "12"]


FROM_07 = {"human1": "Worker 1 comes from the corner 07 round the blind corner 11 to ch.",
           "human2": "Worker 2 walks to the corner and stops when the robot blocks the way."}


def test_a_person_who_comes_in_another_way_than_the_text_says_is_refused_upstream(mini_location):
    location = load_location(mini_location)
    reply = paths_reply(trajectories={"robot": ["32", "ch", "11", "07"], "human1": ["d9", "ch", "11"],
                                      "human2": ["f7", "07", "11"]},
                        interaction_points={"human1": "11", "human2": "11"})
    mistakes = check_paths(PathsReply.model_validate(reply), location.graph, ["human1", "human2"],
                           ScenarioSpec.model_validate(spec_for(2)), location, FROM_07)
    found = [m for m in mistakes if "come to 11 (encounter e1) from 07" in m]
    assert len(found) == 1 and isinstance(found[0], Upstream) and found[0].key == "way_in:human1:11"
    assert "comes into 11 from ch (d9 ch 11)" in found[0] and "along 07 11" in found[0]
    assert "stage 1 is then asked" in found[0] and "where human1 comes from" in found[0].upstream


@pytest.mark.parametrize("path", [["07", "11", "ch"], ["f7", "07", "11"], ["11", "ch"]])
def test_a_person_who_comes_in_the_texts_way_or_starts_there_is_accepted(mini_location, path):
    graph = load_location(mini_location).graph
    paths = {"human1": path, "human2": ["f7", "07", "11"]}
    assert way_in_mistakes(graph, ScenarioSpec.model_validate(spec_for(2)), FROM_07, paths, {"e1": "11"}) == []


FROM_0E = {"human1": "Worker 1 comes from the corner 0e along the passageway through 32 and ch to the blind corner 11."}


@pytest.mark.parametrize(("path", "refused"), [(["ch", "11", "07"], True), (["32", "ch", "11"], False),
                                               (["0e", "32", "ch", "11"], False)])
def test_a_plan_that_starts_nearer_the_encounter_than_the_texts_origin_leaves_the_way_out(mini_location, path,
                                                                                          refused):
    """warehouse_12: the picker's text has her come up the aisle from yh; the final plan starts her at the aisle's
    far end xq, nearer to the encounter than to yh: she comes in along the text's way, but never walks it. A start
    nearer to the text's place than to the encounter (home_08's husband at vh, just out of the kitchen) is seen
    coming from it."""
    graph = load_location(mini_location).graph
    spec = ScenarioSpec.model_validate(spec_for(1))
    mistakes = way_in_mistakes(graph, spec, FROM_0E, {"human1": path}, {"e1": "11"})
    assert bool(mistakes) is refused
    if refused:
        assert "starts at ch, nearer to 11 than to 0e, leaving the way from 0e out" in mistakes[0]
        assert isinstance(mistakes[0], Upstream) and "along 0e 32 ch 11" in mistakes[0]


def test_a_text_that_names_no_origin_is_left_alone(mini_location):
    graph = load_location(mini_location).graph
    behaviors = {"human1": "Worker 1 walks round the blind corner 11 and on to 07."}  # 11 first: no origin named
    paths = {"human1": ["d9", "ch", "11", "07"], "human2": ["f7", "07", "11"]}
    assert way_in_mistakes(graph, ScenarioSpec.model_validate(spec_for(2)), behaviors, paths, {"e1": "11"}) == []


# -- in stage 1's own check, and on the recorded answers of the new-request suite ------------------------------------
def test_stage_one_refuses_a_spec_that_says_less_than_its_prose(mini_location):
    check = scenario_checker(load_location(mini_location))
    spec = _follow_spec(4.5, "human1 follows the robot right behind it").model_dump(mode="json", exclude_none=True)
    reply = scenario_reply(spec=spec, scenario_description=WALKS_ON_BEHIND)
    mistakes = check(ScenarioReply.model_validate(reply))
    assert any("lets human1 be up to 4.5 m" in m for m in mistakes)
    assert any("between human2 and the robot" in m for m in mistakes)
    fixed = copy.deepcopy(spec)
    fixed["criteria"][-1]["distance"] = 2.5
    fixed["criteria"].append({"id": "c10", "kind": "stl", "text": "the robot reaches 07 before human2",
                              "formula": "(human2_to_node_07 > 2.0) until (robot_to_node_07 < 1.0)"})
    mistakes = check(ScenarioReply.model_validate(scenario_reply(spec=fixed, scenario_description=WALKS_ON_BEHIND)))
    assert not [m for m in mistakes if "lets human1 be up to" in m or "who goes first" in m], mistakes


def _valid(model: type[_M], answer: str) -> _M | None:
    try:
        return model.model_validate(extract_json(answer))
    except (ValidationError, ValueError):
        return None


def _findings(path: Path) -> dict[str, list[str]]:
    """The prose checks' findings on every recorded answer of a fixture (paths answers with its last scenario)."""
    data = load_yaml_file(path)
    graph = load_location(ROOT / data["request"]["location"]).graph
    found: dict[str, list[str]] = {}
    scenarios = [_valid(ScenarioReply, a) for a in data["stages"]["scenario"]]
    for i, scenario in enumerate(scenarios):
        spec = parse_spec(scenario.spec)[0] if scenario is not None else None
        if scenario is None or spec is None:  # refused as it stands (its JSON or spec): no prose to check
            continue
        behaviors = scenario.human_behaviors
        found[f"scenario[{i}]"] = close_follow_mistakes(spec, behaviors) + \
            order_mistakes(scenario.scenario_description, behaviors, spec) + \
            person_order_mistakes(scenario.scenario_description, behaviors, spec) + \
            stop_mistakes(scenario.scenario_description, behaviors, spec) + \
            robot_wait_mistakes(scenario.scenario_description, scenario.expected_robot_behavior, behaviors, spec,
                                {str(n) for n in graph.nodes}) + \
            stay_mistakes(scenario.scenario_description, behaviors, spec)
        if i == len(scenarios) - 1:
            for j, paths in enumerate(_valid(PathsReply, a) for a in data["stages"]["paths"]):
                found[f"paths[{j}]"] = way_in_mistakes(graph, spec, behaviors, dict(paths.trajectories),
                                                       dict(paths.encounter_nodes)) if paths else []
    return {k: v for k, v in found.items() if v}


# Every recorded answer of the suite the prose checks refuse, and why that is right (rounds 16, 18 and 19 re-answered
# home_03, home_09, warehouse_10 and warehouse_12 live with these checks: the answers refused there are the model's
# before it fixed them).
REFUSED = {
    ("home_03_welcome_dinner_guests", "scenario[0]"): "human2 'behind Human 1' in the hallway with no criterion "
    "relating the two guests (the live model of round 18 then dropped the order: the rough says only 'single file')",
    ("home_09_telepresence_grandma_kids_follow", "scenario[0]"): "right behind the robot, allowed 4 m (the live model "
    "of round 19 then allowed at most 2.8 m)",
    ("warehouse_10_against_the_unloading_crew", "scenario[0]"): "right behind the crew, a follows_human allowing 4 m "
    "(the live model then allowed 3.1 m)",
    ("home_16_hide_and_seek_laundry", "paths[0]"): "the children come to 41 from vh in the text, their paths from "
    "iq out of the main bedroom (round 20's live model then moved them to the living room's east end, as stage 1 was "
    "asked)",
    # place_checks (session 12); warehouse_17, whose first answer of round 26 the robot-wait check refused (the live
    # model then dropped 'short of sw': the stop was meant at the group's edge; its round-34 answer kept that fix)
    # round 27-28's new requests: each first answer below was refused live and the model then fixed it
    ("home_19_toddlers_trail_milk_delivery", "scenario[0]"): "toddlers 'right behind the robot', a follows_robot "
    "allowing 4.5 m (the round-28 live model then allowed 3 m)",
    ("home_20_slippers_past_walker_practice", "scenario[0]"): "the robot waits ~1.6 m short of the hallway junction, "
    "its criterion keeps it back only 0.5 m (the round-27 live model then asked 0.6 m)",
    ("warehouse_17_first_aid_kit_to_staging", "scenario[0]"): "the robot 'stops just short of sw' with no criterion "
    "keeping it back from sw (the round-26 live model then reworded the stop as at the group's edge, which an stl "
    "on robot_to_node_vj states)",
    # round 29's new requests (the fifteenth session): refused live, then fixed by the model
    ("hospital_21_water_jugs_past_mopping_cleaner", "scenario[0]"): "the cleaner 'stays where she is' while she signals "
    "WAIT, no criterion sees her stay (the round-29 live model then bounded her moving while she says it; its player "
    "noted that the same sentence goes on to say when she moves)",
    ("home_22_folding_chair_past_arriving_friends", "scenario[1]"): "the robot waits 'short of' the doorway z2, no "
    "criterion keeps it back from z2 (the round-29 live model then added robot_to_node_z2)",
    # round 30's new requests (the sixteenth session): refused live, then fixed by the model
    ("hospital_24_follow_nurse_to_west_room", "scenario[1]"): "the patient lets the robot go by in her doorway, no "
    "criterion sees who goes first (the round-30 live model then added one)",
    ("hospital_24_follow_nurse_to_west_room", "scenario[3]"): "the patient 'stays put' in her doorway, no criterion "
    "sees her stay (the round-30 live model then bounded her moving)",
    ("hospital_24_follow_nurse_to_west_room", "paths[0]"): "the patient's text brings her to i1 from her doorway pf, "
    "her path from ck (the round-30 live model then changed it)",
    # round 34's re-answers (the seventeenth session's final code): refused live, then fixed by the model
    ("home_05_serving_drinks_at_party", "scenario[0]"): "the guests stay put until the robot says EXCUSE ME, no "
    "criterion sees them stay (the round-34 live model then added one)",
    # round 35's new requests (the eighteenth session): refused live, then fixed by the model
    ("warehouse_27_crates_with_follower_around_blind_corners", "scenario[0]"): "the worker steadying the crates walks "
    "'right behind' the robot with a follow distance beyond the trail (the live model then allowed 2.8 m; its player "
    "found the wording casual)",
    ("warehouse_28_labels_past_pallet_wrapping", "scenario[0]"): "the scanner worker 'stays where he is', no criterion "
    "sees him stay (the live model then bounded his moving)",
    ("home_30_phone_past_blanket_fort_builders", "paths[0]"): "the child's text has her come to vh from the robot's "
    "side (g9, i6, z2), her path comes in from 41 (the live model kept it twice and said why; stage 1 then re-wrote "
    "where she comes from)",
    ("home_30_phone_past_blanket_fort_builders", "paths[1]"): "the same plan kept, with its reason (round 37)",
}


def test_on_the_suites_recorded_answers_the_checks_refuse_only_what_the_text_does_not_say():
    """Exactly the answers above are refused, each an answer whose spec or plan says less than (or other than) its
    prose; every other recorded answer of the suite passes the checks."""
    refused = {(p.stem, k) for p in sorted(FIXTURES.glob("*.yaml")) for k in _findings(p)}
    assert refused == set(REFUSED)


def test_a_plan_that_cannot_bring_a_person_in_the_texts_way_sends_stage_1_to_change_the_text(tmp_path, mini_location):
    """hospital_11 on the mini map: the text has human1 come from d9 through ch, stage 2 brings her from 07 and says
    twice that it cannot do otherwise; stage 1 is asked where she comes from, its new text has her come from 07,
    and the same paths are then valid."""
    from gen_helpers import run_replay, tree_reply, write_script

    def scenario(behavior: str) -> dict:
        return scenario_reply(n=1, human_behaviors={"human1": behavior}, spec=spec_for(1))

    paths = paths_reply(trajectories={"robot": ["32", "ch", "11", "07"], "human1": ["07", "11", "ch"]},
                        interaction_points={"human1": "11"}, group_ids={"human1": -1})
    cannot = {**paths, "reasoning": "She cannot come from d9: the robot comes that way; she must come from 07."}
    script = write_script(tmp_path / "s.yaml", {
        "scenario": [scenario("Worker 1 comes from d9 through ch to the blind corner 11 and stops for the robot."),
                     scenario("Worker 1 comes from the corner 07 to the blind corner 11 and stops for the robot.")],
        "paths": [paths, cannot, paths], "behaviors": {"human1": [tree_reply()]}})
    run, llm = run_replay(script, mini_location, tmp_path / "run")
    assert [s for s, _, _ in llm.calls] == ["scenario", "paths", "paths", "scenario", "paths", "behaviors"]
    told = [m for s, _, m in llm.calls if s == "paths"][1][-1].content
    assert "come to 11 (encounter e1) from d9, ch, but human1's path comes into 11 from 07" in told
    to_stage1 = [m for s, _, m in llm.calls if s == "scenario"][1][-1].content
    assert "where human1 comes from" in to_stage1 and "she must come from 07" in to_stage1
    assert "07" in run.scenario.human_behaviors["human1"]


def test_the_order_example_warns_of_a_node_the_robot_passes_on_the_way_out():
    """warehouse_07's route sk up ... ki up: "(human2_to_node_up > 2.0) until (robot_to_node_up < 1.0)" holds at
    1.9 s, when the robot first passes up on its way out, so the example says which node N is."""
    mistakes = order_mistakes(WALKS_ON_BEHIND, {}, ScenarioSpec.model_validate(spec_for(2)))
    assert "reaches only once, after the encounter" in mistakes[0] and "round trip" in mistakes[0]


# -- a robot that waits until someone has passed (who goes first, said of the robot) --------------------------------
@pytest.mark.parametrize("text", [
    "The robot stops before the doorway and waits until the nurse (Human 2) has come through.",
    "At the junction the robot stays put until Human 2 has walked past, then drives on.",
    "The robot pulls over at the wide spot and lets Human 2 go first.",
])
def test_a_robot_that_waits_for_someone_to_pass_states_who_goes_first(text):
    mistakes = order_mistakes(text, {}, ScenarioSpec.model_validate(spec_for(2)))
    assert len(mistakes) == 1 and "between human2 and the robot" in mistakes[0], mistakes


@pytest.mark.parametrize("text", [
    "The robot waits until they have stepped aside.",  # a step aside, not an order: gives_way's business
    "The robot stops and waits until the nurse (Human 2) has finished her call.",
    "Human 2 stands at the counter and lets it go on.",
])
def test_other_waits_are_not_an_order_of_passing(text):
    assert order_mistakes(text, {}, ScenarioSpec.model_validate(spec_for(2))) == []


def test_behind_a_piece_of_furniture_is_no_order_between_people() -> None:
    """Round 35's hospital_28: "a nurse working at a computer behind the nurse station counter" was read as the nurse
    walking behind another person (the word nurse in 'the nurse station'); the phrase's head noun decides."""
    from socnavgen.proposal.prose_checks import _person

    assert _person("the nurse station", {}) == (False, None)
    assert _person("the lead worker", {}) == (True, None)
    assert _person("the nurse and", {}) == (True, None)
    assert _person("his sister", {}) == (True, None)
    assert _person("the robot", {}) == (False, None)
