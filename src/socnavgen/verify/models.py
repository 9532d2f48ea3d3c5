"""What the verifier expects of a run and what it found, as plain data (verify.json)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from socnavgen.run.spec import Blame
from socnavgen.verify import thresholds as T

Verdict = tuple[Blame, str | None, str]  # a failure's blame, the human (for behaviors) and the reason

ExpectationKind = Literal["executes", "gives_way_while_passing"]
Source = Literal["spec", "implied", "paths", "tree", "card"]
Stage = Literal["paths", "behaviors"]


class VerifySettings(BaseModel):
    """Thresholds of the checks (metres, seconds). The same strict values hold with or without spec.json;
    a criterion's own `distance` / `seconds` and an encounter's `within` override them. The defaults live in
    verify/thresholds.py; the `verify` command reads its options' defaults and help from these fields."""

    model_config = ConfigDict(extra="forbid")
    distance: float = Field(default=T.MEET_DISTANCE, gt=0, le=50,
                            description="robot-human centre distance (m) that counts as meeting, unless a criterion "
                                        "gives its own")
    near: float = Field(default=T.NEAR_NODE, gt=0, le=50,
                        description="how close (m) to its encounter node a meeting must happen, for runs without "
                                    "spec.json (an encounter's `within` otherwise)")
    passing: float = Field(default=T.PASSING_DISTANCE, gt=0, le=50,
                           description="robot-human centre distance (m) within which a tree's GiveWaytoRobot counts "
                                       "as giving way while the robot passes")
    group_spread: float = Field(default=T.GROUP_SPREAD, gt=0, le=50,
                                description="largest distance (m) between group members, the whole run")
    goal_radius: float | None = Field(default=None, gt=0, le=50,
                                      description="robot goal radius (m) (default: the trace's, else "
                                                  f"{T.DEFAULT_GOAL_RADIUS:g} m)")
    deadlock_seconds: float = Field(default=T.DEADLOCK_SECONDS, gt=0, le=3600,
                                    description="longest (s) the robot may make no progress along its route with "
                                                "someone in its way")
    reaction_seconds: float = Field(default=T.REACTION_SECONDS, gt=0, le=3600,
                                    description="default time (s) a reaction has after its cause")
    collisions_fail: bool = Field(default=True, description=(
        "a robot-human contact (gap <= 0.05 m, sim/contact.py) fails verification; False reports it as a warning"))

    @classmethod
    def with_overrides(cls, base: VerifySettings | None = None, **overrides: float | bool | None) -> VerifySettings:
        """`base` (default settings when None) with some fields changed, validated. An unknown name is a
        TypeError (a misspelled threshold must not be silently ignored); a value out of range a ValueError
        naming the field; None leaves a field as it is."""
        unknown = sorted(set(overrides) - set(cls.model_fields))
        if unknown:
            raise TypeError(f"unknown verify threshold(s) {', '.join(map(repr, unknown))}; thresholds are "
                            f"{', '.join(cls.model_fields)}")
        data = (base or cls()).model_dump()
        data.update({k: v for k, v in overrides.items() if v is not None})
        try:
            return cls.model_validate(data)
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors())
            raise ValueError(f"invalid verify threshold: {problems}") from None


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
