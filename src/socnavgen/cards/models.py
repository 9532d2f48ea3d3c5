"""Scenario cards (Francis et al., "Principles and Guidelines for Evaluating Social Robot Navigation
Algorithms") as data: what a card needs from a location, what the robot and the humans do, and the
success criteria the verifier checks. The cards themselves live in cards.yaml."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from socnavgen.run.models import RobotGestureRule
from socnavgen.sim.behaviour_checks import ExpectedCheck

# Places a card can need on the scene graph (found by type keywords and by geometry, see location/places.py).
Feature = Literal["any", "corridor", "open_area", "intersection", "blind_corner", "narrow_passage", "doorway",
                  "room_entry", "elevator_entry"]

# How the robot's route uses the place P:
#   through   ... a, P, b ...            (meets humans at P)
#   into      ... a, P, T                (T = the room / elevator behind P; ends inside)
#   out_of    T, P, b ...                (starts inside T, leaves through P)
#   ends_at   ... a                      (comes up to P, next to it: joins a group there)
#   starts_at P, b ...                   (leaves P: leaves a group there)
RobotRoute = Literal["through", "into", "out_of", "ends_at", "starts_at"]

# How a human's path is built from the robot's route and P (see generate.py):
HumanRoleKind = Literal[
    "oncoming",  # the robot's route reversed, from one node past the robot's goal; meets it at P
    "crossing",  # through P along branches the robot does not use; count > 1 = a stream along that branch
    "standing",  # stays at P (a one-node path)
    "ahead",  # starts on the robot's route ahead of it and walks the same way to its end
    "behind",  # starts behind the robot's start and walks the robot's route
    "beside",  # starts next to the robot's second node and walks the route with it
    "gathering",  # walks from a neighbour of P to P (a group forms at P)
    "through_place",  # from a node near P, across P, to a node on the far side (crowds)
    "converging",  # from a node near P to P (crowding the robot)
    "circular",  # from a neighbour of P across P to the opposite neighbour
]

CriterionKind = Literal["meets_human", "executes", "gives_way_while_passing", "group_together", "robot_reaches_goal"]


class Criterion(BaseModel):
    """A success criterion the verifier reads (socnavgen.verify.expectations.card_expectations)."""

    model_config = ConfigDict(extra="forbid")
    kind: CriterionKind
    human: str | None = None  # human1.. ; None = any / every human concerned
    node: str | None = None  # BT node that must be executed
    within: float | None = None  # metres


class HumanRole(BaseModel):
    model_config = ConfigDict(extra="forbid")
    role: HumanRoleKind
    count: int = Field(default=1, ge=1, le=6)
    min_count: int | None = Field(default=None, description="fewest humans acceptable when the graph is small")
    tree: str = Field(description="template name in templates.yaml")
    behavior: str = Field(description="what this human does, in words (scenario.json)")
    group: bool = False


class Card(BaseModel):
    """One canonical scenario."""

    model_config = ConfigDict(extra="forbid")
    name: str  # slug used on the command line
    title: str
    category: str
    picture: str = Field(description="one-line text sketch: R = robot, H = human, arrows = directions")
    summary: str
    place: Feature
    route: RobotRoute = "through"
    requires: list[Feature] = Field(default_factory=list, description="features needed besides the place")
    context: str
    task: str
    human_behavior: str
    rough: str = Field(description="rough scenario, usable as `generate --rough`")
    expected_robot_behavior: str
    expected_checks: list[ExpectedCheck] = Field(default_factory=list, description="its checkable parts, measured")
    humans: list[HumanRole]
    robot_gestures: list[RobotGestureRule] = Field(default_factory=list)
    criteria: list[Criterion]

    @property
    def needs(self) -> list[Feature]:
        return [self.place, *[f for f in self.requires if f != self.place]]
