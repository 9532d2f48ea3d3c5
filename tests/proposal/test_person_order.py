"""Who walks behind whom among people (issue 25, proposal/prose_checks.person_order_mistakes): home_09 of round 14
passed with both children following in the REVERSE of the text's order ("Leo behind his sister"), because each had
a follows_robot criterion, which measures every follower from the robot only, and the order check took follows_robot
for a criterion that sees the order. A text that puts a person behind (or ahead of) another person needs a
criterion that relates the two; places ("behind the counter") are no people."""

from __future__ import annotations

import pytest
from gen_helpers import spec_for

from socnavgen.proposal.prose_checks import person_order_mistakes
from socnavgen.run.spec import ScenarioSpec

KIDS = ("Her two grandchildren are playing: Mia (Human 1) at the table, Leo (Human 2) by the sofa. The robot says "
        "FOLLOW ME, and both children fall in behind it in single file: Mia right behind the robot, Leo behind his "
        "sister. They follow it into the bedroom.")


def _followers(*extra: dict, leo: dict | None = None) -> ScenarioSpec:
    spec = spec_for(2)
    spec["script"]["cues"] = [{"trigger": {"when": "start"}, "say": "FOLLOW ME"}]
    spec["encounters"][0]["humans"] = [
        {"human": "human1", "trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow", "latch": True},
        leo or {"human": "human2", "trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow",
                "latch": True}]
    spec["criteria"] = [{"id": "c1", "kind": "follows_robot", "human": "human1", "encounter": "e1", "distance": 3.5,
                         "text": "Mia follows right behind the robot"},
                        {"id": "c2", "kind": "follows_robot", "human": "human2", "encounter": "e1", "distance": 5.0,
                         "text": "Leo follows the robot"}, *extra]
    return ScenarioSpec.model_validate(spec)


def test_followers_of_the_robot_in_a_stated_order_need_a_criterion_that_relates_them():
    mistakes = person_order_mistakes(KIDS, {}, _followers())
    assert len(mistakes) == 1, mistakes
    said = mistakes[0]
    assert "human2" in said and "'behind his sister'" in said
    assert "follows_robot measures each follower from the robot only" in said
    assert "follow_human" in said and "follows_human" in said
    assert "eventually (always (way_human2 >= way_humanX + 0.4))" in said  # his sister is not resolved to a name


def test_the_order_may_be_in_a_behavior_or_a_criterion_text():
    behaviors = {"human2": "Leo runs over and walks behind it, behind his sister, up the hallway."}
    assert person_order_mistakes("The robot leads the children.", behaviors, _followers())
    spec = _followers()
    spec.criteria[1].text = "Leo follows the robot behind his sister"
    assert person_order_mistakes("The robot leads the children.", {}, spec)


def test_a_person_named_in_the_text_is_put_in_the_example():
    text = "Mia (Human 1) and Leo (Human 2) follow the robot. Leo walks behind Mia all the way."
    mistakes = person_order_mistakes(text, {}, _followers())
    assert len(mistakes) == 1 and "eventually (always (way_human2 >= way_human1 + 0.4))" in mistakes[0]


@pytest.mark.parametrize("criterion", [
    {"id": "c9", "kind": "stl", "formula": "eventually (always (way_human2 >= way_human1 + 0.4))",
     "text": "Leo walks behind his sister"},
    {"id": "c9", "kind": "stl", "formula": "(human2_to_node_i6 > 1.0) until (human1_to_node_i6 < 1.0)",
     "text": "Mia reaches the hallway before Leo"},
    {"id": "c9", "kind": "follows_human", "human": "human2", "encounter": "e1", "distance": 2.5,
     "text": "Leo walks right behind his sister"},
])
def test_a_criterion_that_relates_the_two_is_accepted(criterion):
    leo = {"human": "human2", "trigger": "robot_says", "phrase": "FOLLOW ME", "reaction": "follow_human",
           "other": "human1", "latch": True}
    assert person_order_mistakes(KIDS, {}, _followers(criterion, leo=leo)) == []


def test_a_distance_between_the_two_that_is_the_same_either_way_round_does_not_state_the_order():
    spread = {"id": "c9", "kind": "stl", "formula": "always (spread_human1_human2 < 3.5)", "text": "in single file"}
    assert person_order_mistakes(KIDS, {}, _followers(spread))


@pytest.mark.parametrize("text", [
    "The picker (Human 2) waits behind the rack until the robot has passed.",
    "The nurse (Human 2) stands behind the counter at the nurse station.",
    "The worker (Human 2) walks behind the robot to the door.",  # the robot: the order check's business
    "The two friends (Human 1 and Human 2) walk behind it side by side.",
])
def test_places_and_the_robot_are_no_people(text):
    assert person_order_mistakes(text, {}, _followers()) == []


def test_the_word_that_names_the_person_may_not_be_the_last():
    text = "The porter (Human 2) pushes the bed. The patient (Human 1) walks behind the porter and the bed."
    mistakes = person_order_mistakes(text, {}, _followers())
    assert len(mistakes) == 1 and "human1" in mistakes[0] and "way_human1 >= way_human2 + 0.4" in mistakes[0]
