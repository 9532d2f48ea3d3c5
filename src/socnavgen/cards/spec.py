"""A placed card as a scenario spec (spec.json, run/spec.py): the robot's script (the card's
robot_gestures become cues), one encounter per human who meets the robot, grounded at its node, and
the acceptance criteria, including the card's DEFINING condition (the blind corner is blind, the group is
together, the robot's phrase precedes the reaction, the encounter is in the doorway)."""

from __future__ import annotations

from socnavgen.bt.library import ROBOT_GESTURES
from socnavgen.cards.routes import Placement
from socnavgen.location import Location
from socnavgen.location.inventory import BLIND_SIGHT_M
from socnavgen.run import PathPlan
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import (
    Criterion,
    CueTrigger,
    Encounter,
    HumanPart,
    RobotCue,
    RobotScript,
    ScenarioSpec,
)

# What each tree template of templates.yaml makes its human do, in the spec's words:
# template -> (trigger, reaction, robot phrase or human phrase (for `say`), trigger distance)
TEMPLATE_PARTS: dict[str, tuple[str, str, str | None, float | None]] = {
    "regular": ("always", "walk_past", None, None),
    "stop_and_look_when_close": ("robot_visible", "look", None, 2.5),
    "give_way_on_excuse_me": ("robot_says", "give_way", "EXCUSE ME", None),
    "stand_until_excuse_me": ("robot_says", "give_way", "EXCUSE ME", None),
    "dawdle_and_let_pass": ("robot_says", "give_way", "EXCUSE ME", None),
    "say_wait_and_walk": ("robot_near", "say", "WAIT", 3.0),
    "stop_and_say_proceed": ("robot_near", "say", "PROCEED", 2.0),
    "wait_while_robot_near": ("robot_near", "look", None, 2.5),
    "wait_aside_while_robot_near": ("robot_near", "give_way", None, 2.0),
    "wait_for_follower": ("robot_far", "stop", None, 4.0),
    "follow_robot": ("robot_visible", "follow", None, 6.0),
    "crowd_robot": ("robot_visible", "follow", None, 5.0),
}
# Templates whose reaction ends after this many seconds (an inverted TimeExpiredCondition): the part's `lasts`.
TEMPLATE_LASTS: dict[str, float] = {"crowd_robot": 15.0}
ROBOT_CRUISE = 0.6  # m/s
HUMAN_WALK = 1.2  # m/s: a person's effective walking speed (max 1.5 m/s, slowed by turns and others)
HIDDEN_UNTIL = BLIND_SIGHT_M  # m: at a blind corner robot and human see each other only once this close (centres)
GROUP_SPREAD = 2.5  # m: largest distance between two members of a group, the whole run
_WHEN = {"blocked": "blocked", "near_human": "human_within", "always": "start"}


def _cue(rule: RobotGestureRule, node_encounter: dict[str, str]) -> RobotCue | None:
    phrase = ROBOT_GESTURES.get(rule.gesture)
    if not rule.gesture or phrase is None:
        return None
    if rule.when == "at_node":
        enc = node_encounter.get(rule.node or "")
        if enc is None:
            return None
        trigger = CueTrigger(when="at_encounter", encounter=enc, distance=1.0)
    else:
        trigger = CueTrigger.model_validate({"when": _WHEN[rule.when], "distance": rule.distance})
    hold = 3600.0 if rule.when == "always" else rule.duration
    # the tables hold names as plain strings: the models check them against their literals
    return RobotCue.model_validate({"trigger": trigger, "say": phrase, "hold": min(hold, 600.0),
                                    "once": rule.when == "always"})


def _part(name: str, template: str) -> HumanPart:
    trigger, reaction, phrase, distance = TEMPLATE_PARTS.get(template, ("always", "walk_past", None, None))
    return HumanPart.model_validate({"human": name, "trigger": trigger, "reaction": reaction, "distance": distance,
                                     "phrase": phrase if trigger == "robot_says" else None,
                                     "says": phrase if reaction == "say" else None,
                                     "lasts": TEMPLATE_LASTS.get(template)})


def card_spec(placement: Placement, plan: PathPlan, location: Location) -> ScenarioSpec:
    """spec.json of a placed card (plan: the paths.json written for it)."""
    card = placement.card
    encounters: list[Encounter] = []
    criteria: list[Criterion] = []
    node_encounter: dict[str, str] = {}
    for h, route in zip(plan.humans, placement.humans, strict=True):
        if not h.interaction_point or not route.encounter:
            continue
        enc_id = f"e{len(encounters) + 1}"
        part = _part(h.name, route.role.tree)
        # a doorway encounter is IN the doorway (the door node, even if a person is paced to another node)
        node = placement.place.node if card.place == "doorway" and placement.place.node in plan.robot \
            else h.interaction_point
        node_type = str(location.graph.nodes[node].get("type", "") or "INTERACTION POINT")
        encounters.append(Encounter(id=enc_id, place=node_type, node=node,
                                    robot_does=card.expected_robot_behavior, humans=[part], within=1.0))
        node_encounter.setdefault(h.interaction_point, enc_id)
        if part.trigger == "robot_says" and part.phrase:
            criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="reacts_after_phrase", human=h.name,
                                      encounter=enc_id, phrase=part.phrase, reaction=part.reaction, seconds=10.0,
                                      text=f"{h.name} does {part.reaction} only after the robot says {part.phrase}"))
        if card.place == "blind_corner" and route.role.role == "oncoming":
            criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="hidden_until", human=h.name,
                                      encounter=enc_id, distance=HIDDEN_UNTIL,
                                      text=f"the corner hides {h.name} from the robot until they are "
                                           f"{HIDDEN_UNTIL:g} m apart"))
    groups: dict[int, list[str]] = {}
    for h in plan.humans:
        if h.group_id != -1:
            groups.setdefault(h.group_id, []).append(h.name)
    for gid, members in sorted(groups.items()):
        if len(members) > 1:
            criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="group_together", humans=members,
                                      distance=GROUP_SPREAD, text=f"group {gid} ({', '.join(members)}) stays together"))
    criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="robot_reaches_goal",
                              text=f"the robot reaches its goal {plan.robot[-1]}"))
    if plan.humans:
        criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="no_collision",
                                  text="the robot never touches a person"))
        criteria.append(Criterion(id=f"c{len(criteria) + 1}", kind="no_deadlock", seconds=10.0,
                                  text="the robot never stands 10 s behind someone in its way"))
    cues = [c for c in (_cue(rule, node_encounter) for rule in card.robot_gestures) if c is not None]
    late = max((_lateness(plan, h.name, h.interaction_point, location) for h in plan.humans
                if h.interaction_point), default=0.0)
    if late > 1.0:  # the person cannot be there in time: the robot starts later (pacing only slows people)
        cues.insert(0, RobotCue(trigger=CueTrigger(when="start"), wait=round(late, 1)))
    script = RobotScript(route=f"{card.task} ({' -> '.join(plan.robot)})", speed=0.6, cues=cues)
    return ScenarioSpec(script=script, encounters=encounters, criteria=criteria)


def _path_length(nodes: list[str], location: Location) -> float:
    pts = [complex(*location.node_world(n)) for n in nodes]
    return sum(abs(b - a) for a, b in zip(pts, pts[1:], strict=False))


def _lateness(plan: PathPlan, human: str, node: str, location: Location) -> float:
    """Seconds by which `human` would reach `node` after the robot, both going at their cruise speed."""
    path = next(h.path for h in plan.humans if h.name == human)
    if node not in path or node not in plan.robot:
        return 0.0
    human_time = _path_length(path[:path.index(node) + 1], location) / HUMAN_WALK
    robot_time = _path_length(plan.robot[:plan.robot.index(node) + 1], location) / ROBOT_CRUISE
    return max(0.0, human_time - robot_time)
