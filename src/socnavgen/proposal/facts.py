"""The physical facts every prompt tells the model, generated from where each fact lives (the
simulator's agent constants, the spec's defaults, the node library, the location's map), so the
numbers the model reads are the numbers the simulator uses.

Also the narrow places of a map: an edge whose free width is below a person's diameter plus the
robot's (plus a hand's breadth) is blocked by one standing person."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import get_args

import numpy as np

from socnavgen.bt.library import HUMAN_GESTURES, LIBRARY, ROBOT_GESTURES, Target
from socnavgen.location import Location
from socnavgen.run.spec import CueTrigger, HumanTrigger, Reaction, RobotScript

PASS_MARGIN = 0.1  # m of slack a robot needs beside a standing person


@dataclass(frozen=True)
class Body:
    human_radius: float
    human_max_vel: float
    robot_radius: float
    robot_speed: float

    @property
    def blocking_width(self) -> float:
        """A passage narrower than this is closed to the robot by one person standing in its middle: the
        robot's body must fit beside the person's on one side (a person at the wall leaves more)."""
        return round(2 * self.human_radius + 2 * (2 * self.robot_radius) + PASS_MARGIN, 2)


@cache
def body() -> Body:
    from socnavgen.bodies import PERSON_MAX_SPEED, PERSON_RADIUS, ROBOT_RADIUS

    return Body(PERSON_RADIUS, PERSON_MAX_SPEED, ROBOT_RADIUS, RobotScript().speed)


def physical_facts_text() -> str:
    from socnavgen.verify.models import VerifySettings  # the verifier's own thresholds

    b, meet = body(), VerifySettings()
    touch = b.human_radius + b.robot_radius
    return "\n".join([
        "PHYSICAL FACTS of the simulator (plan with these numbers):",
        f"- People walk at up to {b.human_max_vel:g} m/s (about 1 m/s when relaxed); the robot drives at "
        f"{b.robot_speed:g} m/s unless its script says otherwise.",
        f"- A person is a disc of radius {b.human_radius:g} m, the robot a disc of radius {b.robot_radius:g} m.",
        f"- Every distance (conditions of the trees, the spec's `distance`) is measured between CENTRES: at "
        f"{touch:g} m a person and the robot touch, so 'very close' is about 1.0 m and 'close' about 1.5-2 m.",
        f"- A passage narrower than {b.blocking_width:g} m is blocked for the robot by one person standing in "
        f"its middle (the scene graph marks such edges \"narrow\": true); a person who waits for the robot "
        f"there must step aside (give_way), or wait before the passage.",
        f"- How an encounter is checked: the robot and the human 'meet' when their centres are within "
        f"{meet.distance:g} m (or the criterion's `distance`) while the point halfway between them is within "
        f"the encounter's `within` ({meet.near:g} m by default) of the encounter's node. A group (humans listed "
        f"together in a group_together criterion) is met where the robot meets any member: members stepping "
        f"aside is their reaction; a `meets` criterion may name the group's `humans`.",
        "- Positions: `pos` is the pixel position of a node in the map image; `xy_m` is the same point in "
        "metres in the world frame (x east, y north), so distances between nodes can be computed from it.",
    ])


def robot_vocabulary_text() -> str:
    """The robot's script vocabulary, from the spec models (the words the validator accepts)."""
    robot_words = ", ".join(v for k, v in ROBOT_GESTURES.items() if k)
    human_words = ", ".join(v for k, v in HUMAN_GESTURES.items() if k)
    triggers = ", ".join(get_args(CueTrigger.model_fields["when"].annotation))
    return "\n".join([
        f"The robot can say: {robot_words}. A human can say: {human_words}.",
        f"A robot cue fires on: {triggers}.",
        f"A human's trigger is one of: {', '.join(get_args(HumanTrigger))}.",
        f"A human's reaction is one of: {', '.join(get_args(Reaction))}.",
    ])


def target_nodes(target: Target) -> list[str]:
    return [name for name, spec in LIBRARY.items() if target in spec.targets]


# ---- the map's narrow places -----------------------------------------------------------------------
_WIDTHS: dict[str, dict[tuple[str, str], float]] = {}


def _edge_widths(location: Location) -> dict[tuple[str, str], float]:
    key = str(location.root.resolve())
    if key not in _WIDTHS:
        _WIDTHS[key] = _measure_edges(location)
    return _WIDTHS[key]


def _measure_edges(location: Location) -> dict[tuple[str, str], float]:
    occ = location.occupancy
    clearance = occ.clearance_px
    mpp = location.transform.meters_per_pixel
    widths: dict[tuple[str, str], float] = {}
    sg = location.scene_graph
    for edge in sg.links:
        a, b = np.array(sg.node(edge.source).pos, float), np.array(sg.node(edge.target).pos, float)
        steps = max(2, int(np.linalg.norm(b - a)))
        ts = np.linspace(0.15, 0.85, steps)  # the ends sit in rooms or at junctions; the neck is between
        pts = a[None, :] + ts[:, None] * (b - a)[None, :]
        cols = np.clip(np.round(pts[:, 0]).astype(int), 0, occ.width - 1)
        rows = np.clip(np.round(pts[:, 1]).astype(int), 0, occ.height - 1)
        widths[(edge.source, edge.target)] = round(float(2 * clearance[rows, cols].min() * mpp), 2)
    return widths


def edge_width(location: Location, a: str, b: str) -> float:
    """Free width (m) of the passage between nodes a and b: twice the smallest wall clearance along it."""
    widths = _edge_widths(location)
    return widths.get((a, b), widths.get((b, a), float("inf")))


def is_narrow(location: Location, a: str, b: str) -> bool:
    return edge_width(location, a, b) < body().blocking_width
