"""The scenario spec (spec.json): the executable, checkable part of a scenario, beside its prose.

Stage 1 (or a scenario card) writes it; stage 2 grounds each encounter on a scene-graph node; stage 3
is checked against what each encounter needs; the simulator's default robot executes the script; the
verifier monitors the acceptance criteria on the trace (signal temporal logic, with robustness).

Vocabulary, units and conventions (the prompts teach the same words):
- distances are metres between CENTRES unless a field says `gap` (surface to surface);
- a human is `human1`..`humanN`; an encounter is `e1`, `e2`, ...; a criterion `c1`, `c2`, ...;
- phrases are the gesture words of the node library (bt.library.ROBOT_GESTURES / HUMAN_GESTURES).
"""

from __future__ import annotations

import re
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from socnavgen.bodies import PERSON_TOP_SPEED

RobotPhrase = Literal["WAIT", "PROCEED", "ACKNOWLEDGED", "EXCUSE ME", "FOLLOW ME"]
HumanPhrase = Literal["WAIT", "PROCEED", "EXCUSE ME"]

_HUMAN = re.compile(r"^human[1-9][0-9]{0,2}$")
_ID = re.compile(r"^[a-z][a-z0-9_]{0,31}$")


def _check_human(name: str | None) -> str | None:
    if name is not None and not _HUMAN.match(name):
        raise ValueError(f"{name!r} is not a human name (human1, human2, ...)")
    return name


# ---- the robot's script -------------------------------------------------------------------------
class CueTrigger(BaseModel):
    """When a cue of the robot's script fires.

    start         at t = 0
    at_encounter  the robot is within `distance` of encounter `encounter`'s node
    at_node       the robot is within `distance` of `node` (a node of its route)
    blocked       someone is within `distance` ahead of the robot, in its way (standing or walking)
    human_within  `human` (anyone if not given) is within `distance` of the robot
    human_farther `human` (anyone if not given) is farther than `distance` from it (a guide waits for a slow follower)
    human_says    `human` (anyone if not given) makes the phrase `phrase`
    after         `seconds` after the start
    """

    model_config = ConfigDict(extra="forbid")
    when: Literal["start", "at_encounter", "at_node", "blocked", "human_within", "human_farther", "human_says",
                  "after"]
    encounter: str | None = None
    node: str | None = Field(default=None, pattern=r"^[A-Za-z0-9_]{1,32}$")  # for at_node: a node of the robot's route
    human: str | None = None
    phrase: HumanPhrase | None = None
    distance: float = Field(default=1.5, gt=0, le=50)
    seconds: float = Field(default=0.0, ge=0, le=3600)

    @field_validator("human")
    @classmethod
    def _human(cls, v: str | None) -> str | None:
        return _check_human(v)

    @model_validator(mode="after")
    def _needs(self) -> CueTrigger:
        if self.when == "at_encounter" and not self.encounter:
            raise ValueError("a cue `at_encounter` names its `encounter` (e1, e2, ...)")
        if self.when == "at_node" and not self.node:
            raise ValueError("a cue `at_node` names the `node` of the robot's route it is at")
        if self.when == "human_says" and not self.phrase:
            raise ValueError("a cue `human_says` names the `phrase` it waits for")
        return self


class RobotCue(BaseModel):
    """One line of the robot's script: on `trigger`, say `say` (held `hold` s), and/or stand still for
    `wait` s (`wait_until_clear`: until nobody is in its way any more; `let_pass`: until that person has gone
    by), then go on at `speed` if given."""

    model_config = ConfigDict(extra="forbid")
    trigger: CueTrigger
    say: RobotPhrase | None = None
    hold: float = Field(default=3.0, ge=0, le=600)
    wait: float = Field(default=0.0, ge=0, le=600)
    wait_until_clear: bool = False
    speed: float | None = Field(default=None, ge=0, le=2.0)
    once: bool = True  # fire at most once (False: every time the trigger becomes true)
    # humanN: after firing, stand until that person has gone by (across its way, past it, or on ahead of it), at
    # most `wait` s (20 without): "the robot lets her go first" (sim/robot/script.py gone_by)
    let_pass: str | None = Field(default=None, pattern=r"^human[1-9][0-9]?$")


class RobotScript(BaseModel):
    """What the robot does: its route is the robot path of paths.json (stage 2); `route` here is the
    prose intent of stage 1 ("from the loading dock through the blind corner to the shelves")."""

    model_config = ConfigDict(extra="forbid")
    route: str = ""
    speed: float = Field(default=0.6, gt=0, le=2.0)  # m/s cruise speed
    cues: list[RobotCue] = Field(default_factory=list, max_length=32)
    misbehave: bool = False  # True: the scenario WANTS the robot to be rude (no stopping for people)


# ---- encounters --------------------------------------------------------------------------------
HumanTrigger = Literal["always", "robot_visible", "robot_near", "robot_far", "robot_blocking", "robot_says",
                       "robot_moving", "human_says", "time"]
Reaction = Literal["walk_past", "stop", "look", "give_way", "follow", "block", "avoid", "say", "follow_human",
                   "wait_then_go", "join"]
# A trigger that holds exactly when another does not: a tree detects it with that trigger's condition inverted.
NEGATED_TRIGGERS: dict[str, str] = {"robot_far": "robot_near"}
WAIT_THEN_GO_SECONDS = 3.0  # s a wait_then_go stands when its part does not say `lasts`


class HumanPart(BaseModel):
    """What one human does in an encounter: `reaction` on `trigger`.

    trigger: always | robot_visible (in line of sight within `distance`) | robot_near (within `distance`,
    walls or not) | robot_far (farther than `distance`: not robot_near) | robot_blocking (in its way within
    `distance`) | robot_says `phrase` | robot_moving | human_says (`other` says `phrase`) | time (`seconds`
    after the run starts, whatever happened before).
    reaction: walk_past | stop | look | give_way | follow (the robot) | block | avoid | say `says` |
    follow_human (`other`) | wait_then_go (stands `lasts` s, WAIT_THEN_GO_SECONDS unless set, then walks
    on) | join (a group).
    `lasts`: the reaction stops after this many seconds (then the person walks on); unset, it lasts while
    the trigger holds. `latch`: once triggered, keep reacting for good (the trigger is not checked again).
    Both: once triggered, the reaction runs its `lasts` seconds whatever the trigger does meanwhile, then
    the person walks on for good (wait_then_go latched: stands `lasts` s, then walks on and never waits
    again). `until`: a robot phrase that ends the reaction for good once the robot has said it (then the
    person walks on): a child blocks the robot from first sight until it says EXCUSE ME."""

    model_config = ConfigDict(extra="forbid")
    human: str
    trigger: HumanTrigger = "always"
    reaction: Reaction = "walk_past"
    phrase: RobotPhrase | None = None  # the robot's phrase for trigger robot_says (or the other human's)
    says: HumanPhrase | None = None  # for reaction say
    other: str | None = None  # for human_says / follow_human
    distance: float | None = Field(default=None, gt=0, le=50)
    seconds: float | None = Field(default=None, ge=0, le=3600)  # of the trigger time
    lasts: float | None = Field(default=None, gt=0, le=600)
    latch: bool = False
    until: RobotPhrase | None = None  # the robot's phrase that ends the reaction for good

    @field_validator("human", "other")
    @classmethod
    def _names(cls, v: str | None) -> str | None:
        return _check_human(v)

    @model_validator(mode="after")
    def _needs(self) -> HumanPart:
        if self.trigger == "robot_says" and not self.phrase:
            raise ValueError(f"{self.human}: trigger robot_says names the robot's `phrase`")
        if self.reaction == "say" and not self.says:
            raise ValueError(f"{self.human}: reaction say names the phrase in `says`")
        if self.trigger == "human_says" and not (self.other and self.phrase):
            raise ValueError(f"{self.human}: trigger human_says names the `other` human and the `phrase`")
        if self.until is not None and self.trigger == "robot_says" and self.until == self.phrase:
            raise ValueError(f"{self.human}: the reaction starts and ends when the robot says {self.until}; end it "
                             f"with `lasts`, or `until` another phrase")
        if self.seconds is not None and self.trigger != "time":
            raise ValueError(f"{self.human}: `seconds` belongs to the trigger time (after how many seconds); how "
                             f"long a reaction lasts is `lasts`")
        return self

    def lasting(self) -> float | None:
        """Seconds the reaction lasts once triggered (None: while the trigger holds, or for good if latched;
        latched with `lasts`: these seconds once triggered, the trigger not checked again)."""
        return self.lasts if self.lasts is not None else WAIT_THEN_GO_SECONDS if self.reaction == "wait_then_go" \
            else None


class Encounter(BaseModel):
    """Who meets the robot, where (a place of the location; `node` once stage 2 grounds it), in what
    order, and what each side does.

    `order`: the encounters happen in this order (1 first). A person in several encounters switches
    reactions: the part of a later encounter takes over from an earlier one as soon as its trigger holds
    (its tree checks the later trigger first), e.g. e1 give way at the door, e2 follow it from the lobby once
    it says FOLLOW ME; one person's encounters happen at different nodes (proposal/facts.TWO_ENCOUNTERS).
    The person's interaction point (where pacing brings them to meet the robot) is the node of their first
    encounter."""

    model_config = ConfigDict(extra="forbid")
    id: str
    place: str = Field(description="kind of place, a node type of the location (e.g. BLIND CORNER)")
    node: str | None = Field(default=None, description="scene-graph node it happens at (set by stage 2)")
    order: int = Field(default=1, ge=1, le=32)
    robot_does: str = ""
    humans: list[HumanPart] = Field(min_length=1, max_length=16)
    within: float = Field(default=1.0, gt=0, le=5, description="how close to the node it must happen (m)")

    @field_validator("id")
    @classmethod
    def _id(cls, v: str) -> str:
        if not _ID.match(v):
            raise ValueError(f"encounter id {v!r}: use e1, e2, ...")
        return v


class Person(BaseModel):
    """What a person is like, whatever the encounter: how fast they walk (HuNavSim's max_vel; the default is
    bodies.PERSON_MAX_SPEED) and what they do while none of their triggers holds: walk their path, or stand
    at their start (then their triggers set them going)."""

    model_config = ConfigDict(extra="forbid")
    speed: float | None = Field(default=None, gt=0, le=PERSON_TOP_SPEED)
    otherwise: Literal["walk", "stand"] = "walk"


# ---- acceptance criteria -----------------------------------------------------------------------
CriterionKind = Literal[
    "meets",  # robot and `human` come within `distance` (centre) of each other, within the encounter's `within` of its node
    "stops_near_robot",  # `human` slower than 0.1 m/s within `distance` in front of the robot: facing it or in its way
    "reacts_after_phrase",  # after the robot says `phrase`, `human` does `reaction` within `seconds`, and not before
    "gives_way",  # `human` leaves the robot's corridor within `seconds` of the robot coming within `distance`
    "follows_robot",  # after the trigger, `human` stays within `distance` of the robot for the rest of the run
    "follows_human",  # after the trigger, `human` stays within `distance` of whom it follows (follow_human `other`)
    "hidden_until",  # no line of sight between robot and `human` until they are closer than `distance`
    "group_together",  # every pair of `humans` within `distance` of each other the whole run
    "says",  # `human` makes the phrase `phrase` (when the robot is within `distance`, if given)
    "keeps_away",  # `human` keeps at least `distance` from the robot after first noticing it
    "blocks_robot",  # `human` stands in front of the robot within `distance` while the robot stands still
    "robot_stops",  # the robot stands still `seconds` within `distance` (else its within) of the `encounter`'s node
    "stop_together",  # the `humans`, having walked, stand still at once within `distance` of each other (a greeting)
    "robot_reaches_goal",  # the robot reaches its last waypoint
    "no_collision",  # robot and humans never touch (sim.contact defines contact)
    "people_apart",  # no two humans touch each other (the same contact; `human`: that one with anybody)
    "no_deadlock",  # the robot never stands still longer than `seconds` with someone in its way
    "stl",  # `formula`: a raw STL formula over the named signals (docs/verify.md lists them)
]

Blame = Literal["robot_script", "paths", "behaviors", "spec", "scenario", "policy", "simulator"]  # policy: a campaign's robot;
# simulator: the simulated robot failed on its own (no stage can fix it)


class Criterion(BaseModel):
    """One acceptance criterion, a temporal assertion monitored on the simulated trace."""

    model_config = ConfigDict(extra="forbid")
    id: str
    kind: CriterionKind
    human: str | None = None
    humans: list[str] = Field(default_factory=list)
    encounter: str | None = None
    phrase: RobotPhrase | HumanPhrase | None = None
    reaction: Reaction | None = None
    distance: float | None = Field(default=None, gt=0, le=50)
    seconds: float | None = Field(default=None, gt=0, le=3600)
    formula: str | None = Field(default=None, max_length=2000)
    text: str = ""  # the criterion in words, shown in reports

    @field_validator("human")
    @classmethod
    def _names(cls, v: str | None) -> str | None:
        return _check_human(v)


class ScenarioSpec(BaseModel):
    """spec.json."""

    model_config = ConfigDict(extra="forbid")
    version: Literal[1] = 1
    script: RobotScript = Field(default_factory=RobotScript)
    encounters: list[Encounter] = Field(default_factory=list, max_length=16)
    criteria: list[Criterion] = Field(default_factory=list, max_length=64)
    people: dict[str, Person] = Field(default_factory=dict, max_length=16)  # per human; unlisted: the defaults

    @model_validator(mode="after")
    def _cues_name_what_exists(self) -> ScenarioSpec:
        """A cue waiting for an encounter or a human the spec does not have would never fire: refused."""
        ids, humans = [e.id for e in self.encounters], self.humans()
        for k, cue in enumerate(self.script.cues):
            when = f"script.cues.{k} ({cue.trigger.when})"
            if cue.trigger.encounter and cue.trigger.encounter not in ids:
                raise ValueError(f"{when} names encounter {cue.trigger.encounter}, which is not in encounters "
                                 f"({', '.join(ids) or 'none'}): it would never fire")
            if cue.trigger.human and cue.trigger.human not in humans:
                raise ValueError(f"{when} names {cue.trigger.human}, who takes part in no encounter "
                                 f"({', '.join(humans) or 'none'}): it would never fire")
            if cue.let_pass and cue.let_pass not in humans:
                raise ValueError(f"{when} lets {cue.let_pass} pass, who takes part in no encounter "
                                 f"({', '.join(humans) or 'none'}): it would wait for nobody")
        for name in self.people:
            _check_human(name)
            if name not in humans:
                raise ValueError(f"people names {name}, who takes part in no encounter ({', '.join(humans) or 'none'})")
        return self

    def person(self, human: str) -> Person:
        return self.people.get(human) or Person()

    def encounter(self, encounter_id: str) -> Encounter | None:
        return next((e for e in self.encounters if e.id == encounter_id), None)

    def parts_of(self, human: str) -> list[tuple[Encounter, HumanPart]]:
        """Every (encounter, part) that involves `human`, in the encounters' order (the first is where they
        meet the robot first; a later part takes over from an earlier one when its trigger holds)."""
        parts = [(e, p) for e in self.encounters for p in e.humans if p.human == human]
        return sorted(parts, key=lambda ep: ep[0].order)

    def humans(self) -> list[str]:
        names = {p.human for e in self.encounters for p in e.humans}
        return sorted(names, key=lambda n: int(n[5:]))
