"""Data that flows between stages, defined once. Humans are named human1..humanN; human i (1-based
name) has agent id i-1, as in SocRATES."""

from __future__ import annotations

import re
from typing import Literal

from pydantic import BaseModel, Field, field_validator

from socnavgen.credentials import hide_url_credentials
from socnavgen.limits import MAX_HUMANS

HUMAN_NAME = re.compile(r"human([1-9][0-9]{0,3})")


def check_human_name(name: str) -> str:
    """human1..humanMAX_HUMANS and nothing else: the name becomes a file name and an agent id."""
    match = HUMAN_NAME.fullmatch(name) if isinstance(name, str) else None
    if match is None or int(match.group(1)) > MAX_HUMANS:
        raise ValueError(f"human name {str(name)[:40]!r} is not human1..human{MAX_HUMANS}")
    return name


def _public_spec(value: str) -> str:
    """A --llm spec as stored in request.json and manifest.json: URL credentials hidden."""
    return hide_url_credentials(value)


class ScenarioRequest(BaseModel):
    """What the user asked for (request.json)."""

    location: str = Field(description="path of the location folder")
    context: str = Field(description="social context")
    task: str = Field(description="robot task")
    rough: str | None = Field(default=None, description="optional rough scenario")
    card: str | None = Field(default=None, description="scenario card the rough scenario came from")
    llm: str = "local"
    proposals: int = 1
    pick: int = 0
    max_requeries: int = 3
    max_restarts: int = 2
    naive: bool = False
    seed: int = 0
    temperature: float = 0.0
    use_image: bool = True
    target: Literal["socrates", "hunav2", "hunav1"] | None = Field(
        default=None, description="export target: only nodes it can run are offered and accepted")

    @field_validator("llm")
    @classmethod
    def _public_llm(cls, value: str) -> str:
        return _public_spec(value)


class ScenarioProposal(BaseModel):
    """Stage 1 result (scenario.json)."""

    scenario_description: str
    number_of_humans: int
    human_behaviors: dict[str, str] = Field(description="human1..humanN -> behavior text")
    expected_robot_behavior: str


class HumanPlan(BaseModel):
    name: str  # human1, human2, ...
    path: list[str]  # scene-graph node ids
    group_id: int = -1
    interaction_point: str | None = None  # node id on both this path and the robot's

    @field_validator("name")
    @classmethod
    def _valid_name(cls, value: str) -> str:
        return check_human_name(value)

    @property
    def agent_id(self) -> int:
        return int(self.name.removeprefix("human")) - 1

    @property
    def goals(self) -> list[str]:
        """The goal list the simulator walks (as HuNavSim's agents: the start is no goal), or the start alone
        for a path of one node. The stage-3 prompt names these (proposal.behaviors.path_line)."""
        return self.path[1:] if len(self.path) > 1 else self.path[:1]


class RobotGestureRule(BaseModel):
    """Scripted robot speech for the simulator, e.g. say EXCUSE ME (4) when blocked."""

    gesture: int = Field(description="robot gesture code (see bt.library.ROBOT_GESTURES)")
    when: Literal["blocked", "near_human", "at_node", "always"] = "blocked"
    node: str | None = None  # for when == "at_node"
    distance: float = 1.5  # for blocked / near_human
    duration: float = 3.0  # seconds the gesture is held


class PathPlan(BaseModel):
    """Stage 2 result (paths.json)."""

    reasoning: str = ""
    robot: list[str]
    humans: list[HumanPlan] = Field(max_length=MAX_HUMANS)
    robot_gestures: list[RobotGestureRule] = Field(default_factory=list)

    def human(self, name: str) -> HumanPlan:
        return next(h for h in self.humans if h.name == name)


class StageRecord(BaseModel):
    status: Literal["pending", "running", "done", "failed"] = "pending"
    attempts: int = 0
    restarts: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    seconds: float = 0.0
    errors: list[str] = Field(default_factory=list)


class Manifest(BaseModel):
    """manifest.json: versions, model, timings, attempts per stage, token totals, status."""

    socnavgen_version: str
    created: str
    llm: str
    model: str | None = None

    @field_validator("llm")
    @classmethod
    def _public_llm(cls, value: str) -> str:
        return _public_spec(value)
    status: Literal["running", "done", "failed"] = "running"
    stages: dict[str, StageRecord] = Field(default_factory=dict)
    message: str | None = None
