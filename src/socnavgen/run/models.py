"""Data that flows between stages, defined once. Humans are named human1..humanN; human i (1-based
name) has agent id i-1, as in SocRATES."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


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

    @property
    def agent_id(self) -> int:
        return int(self.name.removeprefix("human")) - 1


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
    humans: list[HumanPlan]
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
    status: Literal["running", "done", "failed"] = "running"
    stages: dict[str, StageRecord] = Field(default_factory=dict)
    message: str | None = None
