"""What the model must ANSWER at each stage (the stored models are in socnavgen.run). The LLM layer
lower-cases keys and turns spaces into underscores before validating, so "Scenario Description"
arrives as scenario_description; the aliases accept the spellings models commonly use."""

from __future__ import annotations

import re

from pydantic import AliasChoices, BaseModel, ConfigDict, Field, field_validator

_HUMAN_KEY = re.compile(r"^\s*human[\s_-]*(\d+)\s*$", re.IGNORECASE)


def human_name(key: str) -> str | None:
    """'Human 1' / 'HUMAN_1' / 'human1' -> 'human1'; anything else -> None."""
    match = _HUMAN_KEY.match(str(key))
    return f"human{int(match.group(1))}" if match else None


def _node_id(value: object) -> object:
    """Models sometimes write node ids as numbers (7 for "07" is ambiguous, so only str() is applied)."""
    return str(value) if isinstance(value, int | float) and not isinstance(value, bool) else value


class ScenarioReply(BaseModel):
    model_config = ConfigDict(extra="ignore")

    scenario_description: str
    number_of_humans: int
    human_behaviors: dict[str, str] = Field(
        validation_alias=AliasChoices("human_behaviors", "human_behavior", "human_behaviour", "human_behaviours"))
    expected_robot_behavior: str = Field(
        validation_alias=AliasChoices("expected_robot_behavior", "expected_robot_behaviour"))
    # The scenario spec (run/spec.py), checked by proposal.spec_checks so each mistake is named.
    spec: dict | None = Field(default=None, validation_alias=AliasChoices("spec", "scenario_spec"))


class PathsReply(BaseModel):
    model_config = ConfigDict(extra="ignore")

    reasoning: str = ""
    trajectories: dict[str, list[str]] = Field(validation_alias=AliasChoices("trajectories", "paths"))
    group_ids: dict[str, int] = Field(default_factory=dict,
                                      validation_alias=AliasChoices("group_ids", "group_id", "groups"))
    interaction_points: dict[str, str | None] = Field(
        default_factory=dict, validation_alias=AliasChoices("interaction_points", "interaction_point"))
    # Stage 2 grounds each encounter of the spec on a node: {"e1": "f7"}.
    encounter_nodes: dict[str, str] = Field(
        default_factory=dict, validation_alias=AliasChoices("encounter_nodes", "encounters"))

    @field_validator("trajectories", mode="before")
    @classmethod
    def _ids_as_text(cls, value: object) -> object:
        if isinstance(value, dict):
            return {k: [_node_id(n) for n in v] if isinstance(v, list) else v for k, v in value.items()}
        return value

    @field_validator("interaction_points", "encounter_nodes", mode="before")
    @classmethod
    def _point_as_text(cls, value: object) -> object:
        if isinstance(value, dict):
            return {k: _node_id(v) for k, v in value.items()}
        return value


class BehaviorReply(BaseModel):
    model_config = ConfigDict(extra="ignore")

    reasoning: str = ""
    tree: str = Field(validation_alias=AliasChoices("tree", "answer", "xml"))


class NaiveReply(ScenarioReply, PathsReply):
    """The naive baseline asks for everything in one answer."""

    trees: dict[str, str]
