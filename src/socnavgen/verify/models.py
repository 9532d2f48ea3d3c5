"""What the verifier expects of a run and what it found, as plain data (verify.json)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

ExpectationKind = Literal["meets_human", "executes", "gives_way_while_passing", "group_together",
                          "robot_reaches_goal", "no_collision"]
Source = Literal["paths", "tree", "card"]
Stage = Literal["paths", "behaviors"]


class VerifySettings(BaseModel):
    """Thresholds of the checks (all in metres / seconds / fractions)."""

    distance: float = Field(default=2.5, description="robot-human centre distance that counts as meeting")
    near: float = Field(default=3.0, description="how close to the interaction point the meeting must happen")
    passing: float = Field(default=3.0, description="robot-human distance at which giving way counts as "
                                                    "'while the robot passes'")
    group_spread: float = Field(default=3.0, description="largest pairwise distance inside a group that still "
                                                         "counts as together")
    group_fraction: float = Field(default=0.8, description="share of the run a group must stay together")
    goal_radius: float | None = Field(default=None, description="robot goal radius (default: the trace's, "
                                                                "else 0.5 m)")
    overlap: float = Field(default=0.05, description="robot-human disc overlap (m) that counts as a collision")
    collisions_fail: bool = Field(default=False, description=(
        "a collision fails verification (default: reported as a warning, because it judges the robot "
        "under test, not whether the scenario happened)"))


class Expectation(BaseModel):
    """One checkable claim derived from the paths, the trees or the scenario card."""

    kind: ExpectationKind
    name: str  # short title shown in the table
    source: Source
    detail: str = ""  # why it is expected, e.g. "RobotSays(message=4) gates GiveWaytoRobot"
    human: str | None = None  # None = any human (card criteria without a named human)
    node: str | None = None  # BT node name (executes / gives_way_while_passing)
    message: int | None = None  # MakeGesture code that must be shown
    point: tuple[float, float] | None = None  # interaction point, world
    point_id: str | None = None
    within: float | None = None  # distance threshold override

    @property
    def stage(self) -> Stage | None:
        """The generation stage to re-query when this expectation fails."""
        if self.kind in ("executes", "gives_way_while_passing"):
            return "behaviors"
        if self.kind in ("meets_human", "group_together", "robot_reaches_goal"):
            return "paths"
        return None


class Finding(BaseModel):
    """The verdict on one expectation, with the evidence (when, how far, who)."""

    name: str
    kind: ExpectationKind
    passed: bool
    evidence: str
    time: float | None = None
    distance: float | None = None
    human: str | None = None
    node: str | None = None
    source: Source = "paths"
    stage: Stage | None = None
    required: bool = True  # False: a failure is a warning and does not fail the report


class VerifyReport(BaseModel):
    """verify.json: overall verdict and one finding per expectation."""

    run: str
    passed: bool
    findings: list[Finding]
    settings: VerifySettings = Field(default_factory=VerifySettings)
    trace_steps: int = 0
    trace_seconds: float = 0.0
    end_reason: str = ""

    @property
    def failures(self) -> list[Finding]:
        return [f for f in self.findings if not f.passed and f.required]

    @property
    def warnings(self) -> list[Finding]:
        return [f for f in self.findings if not f.passed and not f.required]

    def feedback(self) -> str:
        """The failing findings as text for a re-query prompt (generate --verify)."""
        return "\n".join(f"- {f.name}: {f.evidence}" for f in self.failures)
