"""Reading replies into stage models: loose key matching, unwrapping, and errors the model can act on."""

from __future__ import annotations

from typing import Literal

from pydantic import AliasChoices, BaseModel, ConfigDict, Field

from socnavgen.llm.structured import json_instruction, key_forms, normalise_keys, parse_reply


class HumanPlan(BaseModel):
    name: str
    path: list[str]
    group_id: int | None = None


class ScenarioReply(BaseModel):
    scenario_description: str
    humans: list[HumanPlan]
    robot_path: list[str] = Field(alias="Robot Path")
    extras: dict[str, HumanPlan] = {}


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")
    mode: Literal["stop", "go"]
    count: int


def test_key_forms():
    assert key_forms("Scenario Description") == ("scenario_description", "scenariodescription")
    assert key_forms(" HUMAN-1 ") == ("human_1", "human1")


def test_socrates_style_keys_fill_snake_case_fields():
    raw = """```json
    {"Scenario Description": "A worker crosses at the corner",
     "HUMANS": [{"Name": "HUMAN 1", "PATH": ["ab", "cd"], "Group-ID": 2}],
     "robot path": ["ab", "ef"],
     "extras": {"HUMAN 2": {"NAME": "human2", "Path": []}}}
    ```"""
    value, error = parse_reply(raw, ScenarioReply)
    assert error is None
    assert value.scenario_description == "A worker crosses at the corner"
    assert value.humans == [HumanPlan(name="HUMAN 1", path=["ab", "cd"], group_id=2)]
    assert value.robot_path == ["ab", "ef"]
    assert value.extras == {"HUMAN 2": HumanPlan(name="human2", path=[])}  # data keys are left alone


def test_a_single_wrapper_key_is_unwrapped():
    value, error = parse_reply('{"scenario": {"mode": "go", "count": 3}}', Strict)
    assert error is None and value == Strict(mode="go", count=3)


def test_exact_key_wins_over_a_loose_duplicate():
    assert normalise_keys({"COUNT": 1, "count": 2, "mode": "go"}, Strict) == {"count": 2, "mode": "go"}


def test_validation_errors_name_fields_in_plain_words():
    value, error = parse_reply('{"mode": "fly", "colour": "red"}', Strict)
    assert value is None
    assert "- mode:" in error and "'stop' or 'go'" in error
    assert "- count: this field is required but missing" in error
    assert "- colour: this field is not allowed" in error
    assert error.rstrip().endswith("Reply again with the whole corrected JSON object.")


def test_unparsable_reply_error_asks_for_json():
    value, error = parse_reply("I think the robot should stop.", Strict)
    assert value is None and "could not be read as JSON" in error and "no JSON object" in error


def test_json_instruction_carries_the_schema():
    text = json_instruction(ScenarioReply)
    assert "JSON" in text and '"scenario_description"' in text and '"Robot Path"' in text


class WithChoices(BaseModel):
    human_behaviors: dict[str, str] = Field(validation_alias=AliasChoices("human_behaviors", "human_behaviour"))
    tree: str = Field(validation_alias=AliasChoices("tree", "xml"))


def test_validation_alias_choices_and_unknown_keys_are_snake_cased():
    value, error = parse_reply('{"Human Behaviour": {"HUMAN 1": "walks"}, "XML": "<root/>"}', WithChoices)
    assert error is None
    assert value.human_behaviors == {"HUMAN 1": "walks"} and value.tree == "<root/>"
    assert normalise_keys({"Some Other-Key": 1}, Strict) == {"some_other_key": 1}
