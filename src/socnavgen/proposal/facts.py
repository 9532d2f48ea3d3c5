"""The facts every prompt tells the model, generated from where each fact lives (the bodies, the
simulator's pacing and group constants, the spec's models and defaults, the node library, the
verifier's signals, the location's map), so the numbers the model reads are the numbers the
simulator and the verifier use. Nothing here is typed twice: a fact that changes at its source
changes in the prompts."""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from typing import get_args

from socnavgen.bt.library import (
    HUMAN_GESTURES,
    LIBRARY,
    ROBOT_GESTURES,
    Target,
    nodes_for_trigger,
    prompt_nodes,
)
from socnavgen.location.inventory import BLOCKING_WIDTH
from socnavgen.run.spec import CueTrigger, Encounter, HumanTrigger, Reaction, RobotCue, RobotScript

# Conditions of the library whose SUCCESS stays once reached (bt/library.py's "latching conditions"), by the
# trigger they latch. A spec part with latch: true needs one of them.
LATCHING_CONDITIONS: dict[str, str] = {"robot_says": "RobotSaid"}
STL_EXAMPLE = "eventually[0:60] (robot_says_excuse_me > 0.5 and dist_human1 <= 2.0)"


@dataclass(frozen=True)
class Body:
    human_radius: float
    human_max_vel: float
    robot_radius: float
    robot_speed: float

    @property
    def blocking_width(self) -> float:
        """A passage narrower than this is closed to the robot by one person standing in its middle."""
        return BLOCKING_WIDTH


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


def pacing_text() -> str:
    """How the simulator holds a person back so that the encounter happens at its node (sim/interaction.py)."""
    from socnavgen.sim.interaction import ThrottleConfig

    pace = ThrottleConfig()
    return (f"- Pacing: a person who is alone (group id -1) and has an interaction point on the robot's path "
            f"(after the robot's start) is paced to arrive there together with the robot: while the robot is "
            f"still far, they walk slower, or stand at their start (or at the node) when they would walk slower "
            f"than {pace.min_pace:g} m/s. Only walking normally (RegularNav) is paced; nobody is held within "
            f"{pace.release_distance:g} m of the robot, and once the robot is {pace.robot_near:g} m from the node "
            f"they walk at full speed. So put the interaction point where the encounter should happen: the person "
            f"waits for the robot there. Members of a group and people without an interaction point are never "
            f"paced: they walk from the start.")


def groups_text() -> str:
    """How groups are simulated (sim/scenario.py spawns them, sim/sfm.py holds them together)."""
    from socnavgen.bodies import GROUP_SPAWN_RADIUS

    return (f"- Groups: humans who share a group id (at least two) start evenly on a circle of "
            f"{GROUP_SPAWN_RADIUS:g} m around their first node and are pulled toward each other while they walk "
            f"(group forces of the social force model): give every member the same path and the same reaction. "
            f"People who must act differently (one gives way, another follows the robot) are better separate "
            f"humans with group id -1, or the group force holds them back.")


def encounter_within_text() -> str:
    field = Encounter.model_fields["within"]
    most = next((m.le for m in field.metadata if getattr(m, "le", None) is not None), None)
    return (f"- An encounter's \"within\" ({field.default:g} m unless set, at most {most:g} m) is how close to the "
            f"encounter's node the meeting must happen (the point halfway between the robot and the person). "
            f"Set it yourself when the place is wide or people meet spread out: a group in a lobby, a meeting "
            f"just before a doorway.")


def cue_once_text() -> str:
    once = RobotCue.model_fields["once"].default
    return (f"- A cue fires {'once, the first time its trigger holds' if once else 'each time its trigger holds'}, "
            f"unless it says \"once\": {str(not once).lower()} (then it fires again each time its trigger becomes "
            f"true, e.g. wait every time the follower falls behind).")


def latch_text() -> str:
    latching = ", ".join(f"{trigger} ({node})" for trigger, node in LATCHING_CONDITIONS.items())
    return (f"- \"latch\": true keeps a reaction going once its trigger fired. A tree can latch only these triggers: "
            f"{latching}. To latch a reaction on anything else (the robot came near, a person fell behind), give "
            f"the robot a cue that SAYS a phrase on that event (e.g. trigger human_within human1 2 m, say FOLLOW "
            f"ME) and make the person's trigger robot_says that phrase, with latch: true. Without a latch a "
            f"reaction lasts only while its trigger holds.")


def stl_text() -> str:
    """How to write a `stl` criterion: the syntax and the signals (verify/stl.py, verify/signals.py)."""
    from socnavgen.verify.signals import SIGNAL_KINDS
    from socnavgen.verify.stl import MAX_FORMULA_CHARS, MAX_NESTING

    signals = "; ".join(f"{k.shown} ({k.unit}): {k.meaning}" for k in SIGNAL_KINDS)
    return (f"- A criterion of kind stl holds a signal temporal logic \"formula\": one expression of at most "
            f"{MAX_FORMULA_CHARS} characters and {MAX_NESTING} nested levels, with the operators always, "
            f"eventually, historically, once, until, since (bounds in seconds, e.g. eventually[0:5]), and, or, "
            f"not, implies, and comparisons (<, <=, >, >=); 0/1 signals are compared with 0.5. Example: "
            f"\"{STL_EXAMPLE}\" (within the first 60 s the robot says EXCUSE ME while human1 is within 2 m). "
            f"Signals: {signals}. Use the other kinds when one fits: they are checked with care for cause and "
            f"effect.")


def cue_triggers_text() -> str:
    """Each cue trigger with its meaning, read from CueTrigger's docstring (the one place that explains them)."""
    meanings = dict(re.findall(r"^\s+([a-z_]+)\s+(\S.*)$", CueTrigger.__doc__ or "", re.MULTILINE))
    return ", ".join(f"{when} ({meanings.get(when, '').strip()})"
                     for when in get_args(CueTrigger.model_fields["when"].annotation))


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


def scenario_rules_text() -> str:
    """What stage 1 must know about how its spec plays out (pacing, within, cues, groups, latch, stl)."""
    return "\n".join(["HOW THE SPEC PLAYS OUT:", pacing_text(), encounter_within_text(), cue_once_text(),
                      groups_text(), latch_text(), stl_text()])


def target_nodes(target: Target) -> list[str]:
    return [name for name, spec in LIBRARY.items() if target in spec.targets]


def missing_nodes(target: Target) -> list[str]:
    """Nodes the prompts offer for the simulator that `target` cannot run."""
    return [n.name for n in prompt_nodes() if target not in n.targets]


def latching_node(trigger: str, target: Target = "socrates") -> str | None:
    node = LATCHING_CONDITIONS.get(trigger)
    return node if node is not None and node in nodes_for_trigger(trigger, target) else None
