"""What the verifier expects of a run and what it found, as plain data (verify.json)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from socnavgen.run.spec import Blame

ExpectationKind = Literal["executes", "gives_way_while_passing"]
Source = Literal["spec", "implied", "paths", "tree", "card"]
Stage = Literal["paths", "behaviors"]


class VerifySettings(BaseModel):
    """Thresholds of the checks (metres, seconds). The same strict values hold with or without spec.json;
    a criterion's own `distance` / `seconds` and an encounter's `within` override them."""

    distance: float = Field(default=2.0, description="robot-human centre distance that counts as meeting")
    near: float = Field(default=1.0, description="how close to its encounter node a meeting must happen")
    passing: float = Field(default=2.5, description="robot-human centre distance at which a tree's "
                                                    "GiveWaytoRobot counts as 'while the robot passes'")
    group_spread: float = Field(default=2.5, description="largest distance between group members, the whole run")
    goal_radius: float | None = Field(default=None, description="robot goal radius (default: the trace's, "
                                                                "else 0.5 m)")
    deadlock_seconds: float = Field(default=10.0, description="longest the robot may stand still with someone "
                                                              "in its way")
    reaction_seconds: float = Field(default=5.0, description="default time a reaction has after its cause")
    collisions_fail: bool = Field(default=True, description=(
        "a robot-human overlap (sim/contact.py) fails verification; False reports it as a warning"))


class Expectation(BaseModel):
    """One tree-level claim (a key node of a human's tree must really run), from the trees or a card."""

    kind: ExpectationKind
    name: str  # short title shown in the table
    source: Source
    detail: str = ""  # why it is expected, e.g. "RobotSays(message=4) gates GiveWaytoRobot"
    human: str | None = None  # None = any human (card criteria without a named human)
    node: str | None = None  # BT node name
    message: int | None = None  # MakeGesture code that must be shown
    within: float | None = None  # distance threshold override
    caused_by: list[tuple[str, int | None]] = Field(default_factory=list)  # gating conditions (node, message)


class Finding(BaseModel):
    """The verdict on one criterion or expectation, with the evidence (when, how far, who), the STL
    robustness when it was monitored, and what can fix it when it failed."""

    name: str
    kind: str
    passed: bool
    evidence: str
    time: float | None = None
    distance: float | None = None
    human: str | None = None
    node: str | None = None
    source: Source = "spec"
    criterion: str | None = None  # spec criterion id
    formula: str | None = None  # the STL formula monitored
    robustness: float | None = None  # > 0 passed, < 0 failed, in the unit of the deciding signal
    blame: Blame | None = None  # what can fix a failure (docs/verify.md, blame rules)
    blame_human: str | None = None  # the human whose tree to fix, for blame == behaviors
    blame_reason: str = ""
    stage: Stage | None = None  # blame, when it is a generation stage the --verify loop can re-ask
    required: bool = True  # False: a failure is a warning and does not fail the report


class VerifyReport(BaseModel):
    """verify.json: overall verdict and one finding per criterion / expectation."""

    run: str
    passed: bool
    findings: list[Finding]
    settings: VerifySettings = Field(default_factory=VerifySettings)
    spec: bool = False  # True: criteria came from spec.json (else derived from paths, trees and card)
    trace_steps: int = 0
    trace_seconds: float = 0.0
    end_reason: str = ""

    @property
    def failures(self) -> list[Finding]:
        return [f for f in self.findings if not f.passed and f.required]

    @property
    def warnings(self) -> list[Finding]:
        return [f for f in self.findings if not f.passed and not f.required]

    def blamed_on(self, blame: Blame, human: str | None = None) -> list[Finding]:
        """Failing findings that `blame` (robot_script | paths | behaviors | spec) can fix; for behaviors,
        optionally only those of one human's tree."""
        return [f for f in self.failures if f.blame == blame and (human is None or f.blame_human == human)]

    def blamed(self) -> dict[str, list[Finding]]:
        """Failing findings grouped by what can fix them (only non-empty groups)."""
        out: dict[str, list[Finding]] = {}
        for f in self.failures:
            if f.blame is not None:
                out.setdefault(f.blame, []).append(f)
        return out

    def humans_to_fix(self) -> list[str]:
        """Humans whose trees are blamed, in order."""
        return sorted({f.blame_human for f in self.blamed_on("behaviors") if f.blame_human},
                      key=lambda n: int(n[5:]) if n[5:].isdigit() else 0)

    def feedback(self, blame: Blame | None = None, human: str | None = None) -> str:
        """The failing findings as text for a re-query prompt (generate --verify), optionally only those
        blamed on one stage (and human)."""
        chosen = self.failures if blame is None else self.blamed_on(blame, human)
        return "\n".join(f"- {f.name}: {f.evidence}"
                         + (f" (robustness {f.robustness:+.2f})" if f.robustness is not None else "")
                         + (f" (fix: {f.blame_reason})" if f.blame_reason else "") for f in chosen)
