"""The facts every prompt tells the model, generated from where each fact lives (the bodies, the
simulator's pacing and group constants, the spec's models and defaults, the node library, the
verifier's signals, the location's map), so the numbers the model reads are the numbers the
simulator and the verifier use. Nothing here is typed twice: a fact that changes at its source
changes in the prompts."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from functools import cache
from typing import get_args

from socnavgen.bodies import GROUP_SPAWN_RADIUS, group_ring
from socnavgen.bt.library import (
    BLOCKING_DEGREES,
    HUMAN_GESTURES,
    ROBOT_GESTURES,
    Target,
)
from socnavgen.location.inventory import BLOCKING_WIDTH, PASS_WIDTH
from socnavgen.proposal.target_facts import detected, export_text, latch_text
from socnavgen.run.spec import (
    NEGATED_TRIGGERS,
    WAIT_THEN_GO_SECONDS,
    CueTrigger,
    Encounter,
    Person,
    RobotCue,
    RobotScript,
    ScenarioSpec,
)

# The rule for one person in several encounters, stated in stage 1 and stage 2 and checked by stage 2 (path_checks):
# the verifier tells two meetings of one person apart by where they happen and the parting between them.
TWO_ENCOUNTERS = ("One person in two encounters meets the robot twice, at two DIFFERENT nodes, and the two move apart "
                  "(farther than the meeting distance) in between")
# `until` (run/spec.py HumanPart), stated once for stage 1's rules and its field list
UNTIL_FACT = ("\"until\" (a robot phrase) ends it for good once the robot has said it, then they walk on: a child "
              "blocks the robot from first sight, stepping into its way, \"until\": \"EXCUSE ME\"")
STL_EXAMPLE = "eventually[0:60] (robot_says_excuse_me > 0.5 and dist_human1 <= 2.0)"
# The criterion kinds that state a person's reaction to the robot (stage 1 asks one for every person the text gives
# one, spec_checks.unstated_reactions): `meets` only says they came near. A reaction to a robot phrase is also stated
# by reacts_after_phrase; a group member's by group_together with a member whose reaction is stated; any by stl.
STATED_BY: dict[str, tuple[str, ...]] = {
    "follow": ("follows_robot", "stops_near_robot"), "follow_human": ("follows_human", "follows_robot"), "join": ("follows_robot", "group_together"),
    "give_way": ("gives_way", "keeps_away"), "avoid": ("keeps_away", "gives_way"), "block": ("blocks_robot",),
    "say": ("says",), "stop": ("stops_near_robot",), "wait_then_go": ("stops_near_robot",)}


def group_end_reach(members: int) -> float:
    """m: how far from a group's last node its farthest member ends (the first stands ~0.6 m from it, the others round
    them: measured 2.1 / 2.4 / 2.7 / 3.3 m for 2-5 members on the bundled home, 1.0-2.2 m on the 24 runs of rounds
    30-31; a player's "member_to_node < 1.0" failed at 1.13 m). tests/sim/test_group_in_file.py holds it to this."""
    return round(1.4 + 0.4 * members, 1)


# Stage 1's worked example of "who goes first" (an order of places), told with the stl help (fit.py's signals cut)
ORDER_EXAMPLE = "(robot_to_node_B > 0.5) until (human1_to_node_A < 1.0)"


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


def physical_facts_text(scene_graph: bool = False) -> str:
    """The bodies, speeds and distances every stage plans with; `scene_graph`: how to read node positions
    (stage 2, whose prompt has the scene graph's `pos` and `xy_m`)."""
    from socnavgen.verify.models import VerifySettings  # the verifier's own thresholds
    from socnavgen.verify.thresholds import APPROACH

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
        f"there must step aside (give_way), or wait before the passage; where {PASS_WIDTH:g}-{b.blocking_width:g} m "
        f"is free they pass only if the person keeps to one side.",
        f"- How an encounter is checked: the robot and the human 'meet' when their centres are within "
        f"{meet.distance:g} m (or the criterion's `distance`) while the point halfway between them is within "
        f"the encounter's `within` ({meet.near:g} m by default) of the encounter's node, and only after an "
        f"approach: both came {APPROACH:g} m closer to each other and to the node than at the start (a robot "
        f"standing at its start meets nobody; a person waiting at the node: at least {approach_room():g} m from the robot's start, more with a larger meets `distance`: that "
        f"+ {APPROACH:g} m). A group (humans listed "
        "together in a group_together criterion) is met where the robot meets any member: members stepping "
        "aside is their reaction; a `meets` criterion may name the group's `humans`.",
        _follow_fact(b.robot_speed),
        time_limit_text(b.robot_speed),
        *(["- Positions: `pos` is the pixel position of a node in the map image; `xy_m` is the same point in "
           "metres in the world frame (x east, y north), so distances between nodes can be computed from it."]
          if scene_graph else []),
    ])


def time_limit_text(robot_speed: float) -> str:
    """When a run ends (sim/engine/budget.py: the one home of the rule) and what must fit in it."""
    from socnavgen.sim.engine.budget import RULE_TEXT

    return (f"- A run ends when the robot reaches its goal, or at its time limit: {RULE_TEXT}. A route that the "
            f"robot drives at {robot_speed:g} m/s fits; long waits for people and slow followers beyond that do not.")


def follow_trail(robot_speed: float) -> float:
    """How far (m) a follower at a person's usual top speed trails a robot driving at `robot_speed`
    (sim/people/leaves.follow_trail: their own pace, slowing near whom they follow)."""
    from socnavgen.bodies import PERSON_MAX_SPEED
    from socnavgen.sim.people.leaves import follow_trail as trail

    return trail(robot_speed, PERSON_MAX_SPEED)


def follows_distance_text() -> str:
    """The follows_robot `distance` a follower behind the default robot keeps (stage 1's criteria), and the most one
    the text has right behind it may be allowed (prose_checks holds stage 1 to it: one fact, said where it is used)."""
    from socnavgen.bodies import PERSON_MAX_SPEED
    from socnavgen.proposal.prose_checks import close_follow_gap  # the ceiling for "right behind"

    speed = body().robot_speed
    return (f"a follower trails {follow_trail(speed):.1f} m behind the robot at {speed:g} m/s: use a `distance` of "
            f"{follow_trail(speed) + 2:.0f} m ({close_follow_gap(speed, PERSON_MAX_SPEED):.1f} right behind)")


def follows_human_text(detail: bool = True) -> str:
    """What follows_human measures (verify/criteria.leader_of: from whom the person follows, never from the
    robot; a round-13 player was told to state follow_human with follows_robot, which then measured the robot)."""
    from socnavgen.bodies import PERSON_MAX_SPEED

    if not detail:  # stage 1's `robot` cut (fit.py)
        return "like follows_robot, measured from whom `human` follows (`other`)"
    trail = follow_trail(PERSON_MAX_SPEED)
    return (f"like follows_robot, measured from whom `human`'s follow_human reaction follows (the encounter part's "
            f"`other`; the criterion itself has no `other`), not the robot (they trail ~{trail:.1f} m: `distance` at "
            f"least {trail + 2:.0f} m; a follower of someone who stands or barely moves stands too, and no follow is "
            f"seen: whom they follow must walk on)")


def _follow_fact(robot_speed: float) -> str:
    """How far a follower trails (kept short: a player's reader cut this line when it was long)."""
    from socnavgen.sim.people.leaves import FOLLOW_STOP

    return (f"- A follower (FollowRobot, FollowHuman) walks at their own speed to catch up (around walls) and stands "
            f"within {FOLLOW_STOP:g} m of whom they follow: about {follow_trail(robot_speed):.1f} m behind the robot "
            f"at {robot_speed:g} m/s, more after doors, corners and other followers.")


def approach_room(spec: ScenarioSpec | None = None, enc: Encounter | None = None, human: str | None = None) -> float:
    """How far (m, straight) an encounter's node must be from the robot's start for a person waiting there to be
    met after an approach: the meeting distance (its `meets` criterion's, else the verifier's default) plus the
    verifier's APPROACH (a meeting counts only once the two came that much closer: verify/criteria.py; proposal/path_checks checks it in stage 2)."""
    from socnavgen.verify.derive import meeting_distance
    from socnavgen.verify.models import VerifySettings
    from socnavgen.verify.thresholds import APPROACH

    settings = VerifySettings()
    distance = meeting_distance(spec, enc, human, settings) if spec and enc and human else settings.distance
    return distance + APPROACH


def pacing_text(detail: bool = True) -> str:
    """How the simulator holds a person back so that the encounter happens at its node (sim/people/pacing.py's
    `eta` rule, what it does today: the robot's nominal ETA, no holding near a robot or while it stands; its
    lower_pacing aims at the FIRST pass of a route that passes the node twice). `detail` False (stage 1's `robot`
    cut, fit.py) leaves out the round trip."""
    from socnavgen.sim import ThrottleConfig
    from socnavgen.sim.people.state import QUEUE_REACH

    pace = ThrottleConfig()
    return ("- Pacing: a person who is alone (group id -1) and has an interaction point on the robot's path "
            "(after the robot's start) is paced to arrive there together with the robot"
            + (", wherever they start (the robot's goal too)," if detail else "")
            + " by the robot's ETA re-estimated as it goes (its route left at its speed, plus "
            + ("what is left of the `wait` of cues that fired: not a cue yet to fire, a let_pass, a wait_until_clear,"
               f" nor a wait it stands on its way within {pace.release_distance:g} m of the node along its route: they come during that wait)"
               if detail else "the time it still stands for its cues' waits)")
            + f": a person standing stays where they are (at their start, out of sight if that is hidden) until "
            f"walking to the node at their own speed gets them there with the robot, then walks there; a person "
            f"walking slows down, and stands when they would walk slower than {pace.min_pace:g} m/s. Only walking "
            f"normally (RegularNav) is paced; nobody is held in the robot's way within {pace.release_distance:g} m of it"
            + (", nor ahead on its way while it stands for no known time (let_pass, wait_until_clear)" if detail else "")
            + f": they walk on to the node. Once the robot is {pace.robot_near:g} m from the node they walk "
            f"at full speed. So put the interaction point where the encounter should happen and the person's start "
            f"where they wait (unseen, if they should appear suddenly): they come out as the robot arrives. {_narrow_pacing()} "
            f"Members of a group and people without an interaction point are never paced: they walk from the start."
            + (" Whom a let_pass cue stands for comes at their own speed. Someone who starts ON their interaction point "
               "stands there until the robot is about to arrive (a second or two before), then walks on along their path. "
               f"Someone starting within {QUEUE_REACH:.1f} m of their interaction point while another person stands on it is paced there "
               f"beside them (reached once they walk). On a route that passes the interaction point twice (a round trip [A, B, C, B, A]) pacing aims at "
               "the robot's FIRST pass; once it has passed they walk at their own speed: to meet on the way back, start them "
               "where walking at their own speed brings them there then, or meet at a node passed once." if detail else ""))


def _narrow_pacing() -> str:
    """What arriving together means at a passage one person closes (a player's doorway standoff, round 6)."""
    return (f"Arriving together at a passage narrower than {BLOCKING_WIDTH:g} m (a doorway) puts the two face to "
            f"face in it: for the person to come through first while the robot waits before it, put the encounter "
            f"(their interaction point) at the wider place on the robot's side where it waits, not at the passage.")


def groups_text(detail: bool = True) -> str:
    """How groups are simulated (sim.spawn_points spawns them, sim/people/physics.group_forces holds together the
    members walking the group's walk; a member whose tree does something else leaves the group meanwhile);
    `detail` False (stage 1's `robot` cut) leaves out where on the circle each member stands."""
    return (f"- Groups: humans who share a group id (at least two) start evenly on a circle of "
            f"{GROUP_SPAWN_RADIUS:g} m around their first node and are pulled toward each other while they walk "
            f"their path (group forces of the social force model): give every member the same path. A member "
            f"whose tree makes them do something else (give way, follow the robot, run away, stand) leaves the "
            f"group's pull while doing it, so a group whose members react differently splits up and the others "
            f"walk on; once that member walks their path again the pull holds them together again."
            + (" Following (follow, follow_human) leaves the pull too: a file of one walker and members each following "
               "the one ahead is no group for the pull; make its first walker the member on the side they walk toward."
               + _group_places() if detail else ""))


def _group_places() -> str:
    """Where each member of a group starts (sim/engine/scenario.spawn_points, its one home)."""
    return (f" The circle is {group_ring(4):g} m for four, {group_ring(5):g} m for five, so that neighbours do not "
            "touch. On it, member k of n (counted from 0 in the order of their names) starts k x 360/n degrees "
            "counter-clockwise from east of the node (two: east and west of it; three: east, north-west, "
            "south-west; nearer the node where a wall is there), so which member stands in the robot's way depends "
            "on the side it comes from: from the east, the first named; from the west, for two, the second. Nobody "
            f"of a group stands ON its nodes: they start {GROUP_SPAWN_RADIUS:g} m from the first, and at the last one "
            f"member stands about {GROUP_SPAWN_RADIUS:g} m from it and the others round them, up to "
            f"{group_end_reach(2):g} m away for two, {group_end_reach(3):g} for three, {group_end_reach(4):g} for "
            "four: bound a member's distance to a group's node by that, not by a lone walker's 0.5-1.0 m.")


def encounter_within_text() -> str:
    field = Encounter.model_fields["within"]
    most = next((m.le for m in field.metadata if getattr(m, "le", None) is not None), None)
    return (f"- An encounter's \"within\" ({field.default:g} m unless set, at most {most:g} m) is how close to the "
            f"encounter's node the meeting must happen (the point halfway between the robot and the person). "
            f"Set it yourself when the place is wide or people meet spread out: a group in a lobby, a meeting "
            f"just before a doorway.")


def implied_meets_text() -> str:
    """The meeting every encounter part is checked on unless the spec shows it itself (verify/derive.with_implied,
    its one home: a round-10 player's stop at 4 m failed an unwritten 2 m meeting)."""
    from socnavgen.verify.derive import NOT_MET, SHOWS_ENCOUNTER
    from socnavgen.verify.models import VerifySettings

    kinds = ", ".join(sorted(SHOWS_ENCOUNTER))
    return (f"- Every person of an encounter is also checked as meeting the robot there: unless a criterion of "
            f"theirs is of kind {kinds} (or their reaction is {', '.join(NOT_MET)}), the verifier adds a meets "
            f"criterion with the default {VerifySettings().distance:g} m, even when the reaction fires farther off. "
            f"For someone who reacts at a distance (stops as soon as they see the robot 4 m away), write that meets "
            f"criterion yourself with the `distance` they react at (4.5) and give the encounter a `within` of half "
            f"of it or more (the point halfway between them lies that far from the node).")


def cue_once_text(detail: bool = True) -> str:
    """When a cue fires (sim/robot/script.play: on the step its trigger becomes true, `was_true` starting False);
    `detail` False (stage 1's `robot` cut) leaves out the rising edge and t = 0."""
    once = RobotCue.model_fields["once"].default
    example = {"trigger": {"when": "human_farther", "human": "human1", "distance": 5}, "wait": 3, "once": not once}
    edge = (" A cue fires on the step its trigger becomes true (at t = 0 when it holds from the start); with "
            "\"once\": false again each time it becomes true again after it stopped holding, never twice while it "
            "keeps holding (the example drives on after its 3 s, whether the follower caught up or not). A follower "
            "hovering about its distance (it waits, they close in, it drives on, they drop back) re-fires it every few s: "
            "where they cannot close in (a doorway, a small room at its goal) it holds the robot to the run's end.")
    return (f"- A cue fires {'once, the first time its trigger holds' if once else 'each time its trigger holds'}, "
            f"unless it says \"once\": {str(not once).lower()}, a field of the cue beside \"trigger\" (not inside "
            f"it): {json.dumps(example)} waits 3 s each time the follower falls 5 m behind.{edge if detail else ''}")


def people_text(detail: bool = True) -> str:
    """Per-person facts of the spec (run/spec.py Person) and how one person's several parts combine; `detail` False
    (fit.py's `robot` cut) leaves out why a block can end at once (block_until_text)."""
    from socnavgen.bodies import PERSON_MAX_SPEED

    most = next((m.le for m in Person.model_fields["speed"].metadata if getattr(m, "le", None) is not None), None)
    return (f"- \"people\": per human, \"speed\" (m/s, at most {most:g}; default up to {PERSON_MAX_SPEED:g}; 0.5-0.8 "
            f"for someone slow, with a cane) and \"otherwise\": \"walk\" (default: walk their path while no trigger "
            f"holds) or \"stand\" (stand at their start until a trigger sets them going).\n"
            f"- {TWO_ENCOUNTERS} (e1 give way at the door, e2 follow it from the lobby once it says FOLLOW ME). "
            f"The later encounter's part (higher order) takes over while its trigger holds (latch it, or the earlier "
            f"part comes back once, e.g., the phrase is over). Pacing brings them to their FIRST encounter's node. "
            f"One meeting is one encounter, one reaction per person (\"lasts\" ends it after so many seconds, "
            f"{UNTIL_FACT}; {block_until_text() + '; ' if detail else ''}to stand still in the robot's way until it says EXCUSE ME, then step aside: "
            f"\"otherwise\": \"stand\" and give_way on robot_says).\n"
            f"- \"lasts\" (s) ends a reaction (then they walk on), e.g. say WAIT for at most 5 s; wait_then_go "
            f"stands {WAIT_THEN_GO_SECONDS:g} s unless set. \"seconds\" is only the time trigger's. "
            f"{_negations(detail)}\n"
            f"- {stop_evidence_text()}"
            + ("\n- Only people who meet the robot are simulated: someone the story needs who never comes onto the "
               "robot's path is only mentioned in the description, not a human of human_behaviors." if detail else ""))


def block_until_text() -> str:
    """Why a block can end the moment it begins (sim/people/leaves.BLOCK_AHEAD: where BlockRobot stands; a round-7
    player's child stepped in front, the robot's blocked cue said EXCUSE ME at once and the block was over)."""
    from socnavgen.sim.people.leaves import BLOCK_AHEAD

    return (f"a person who blocks (block) stands {BLOCK_AHEAD:g} m (centres) ahead of the robot, so a robot cue "
            f"\"blocked\" with a `distance` of {BLOCK_AHEAD:g} m or more fires as soon as the block stands in front of it: if "
            f"that cue says the block's \"until\" phrase, the block is over the moment it holds the robot. To hold the robot a while, give the block "
            f"\"lasts\" seconds, or have the phrase said by a cue that fires later (\"after\" a time when the "
            f"block is under way)")


def stop_evidence_text() -> str:
    """How the verifier sees a stop (verify/signals.reaction_evidence: a change, after having walked)."""
    from socnavgen.verify.thresholds import MOVED_DISTANCE, STOP_HOLD, STOP_SPEED

    return (f"As a reaction (reacts_after_phrase), a stop or wait_then_go is a person slower than {STOP_SPEED:g} "
            f"m/s for {STOP_HOLD:g} s AFTER having walked {MOVED_DISTANCE:g} m from their start: someone standing "
            f"from the start (\"otherwise\": \"stand\", or held by pacing) shows none until they have walked.")


def _negations(detail: bool = True) -> str:
    """The negated triggers (run/spec.py); `detail`: that they hold from t = 0 (a tree's condition is ticked from
    the first step: a round-10 player's guide stood at her start while the robot was far away)."""
    start = (", from t = 0 when the robot starts farther away: a guide whose stop is on it stands at their start "
             "until the robot comes within `distance`") if detail else ""
    near = (" Alike, robot_near and robot_visible hold from t = 0 for someone who starts within their `distance` "
            "of the robot's start: the reaction begins at once, before anyone moved (start them farther, or gate it "
            "on something that happens later)." if detail else "")
    return " ".join(f"{neg} holds exactly when {base} does not (a guide waits while the robot is farther than "
                    f"`distance`{start})." for neg, base in NEGATED_TRIGGERS.items()) + near


def robot_limits_text(detail: bool = True, target: Target = "socrates") -> str:
    """What the robot's script can and cannot do, and (`detail`) what the default robot does by itself
    (sim/robot/polite.py, its make_way after `patience` s face to face) and where it stops, so that the model
    plans around it (fit.py leaves the detail out for a small context: the "robot" cut)."""
    from socnavgen.bodies import TOUCH_DISTANCE
    from socnavgen.sim.robot.api import ScriptedPolicy
    from socnavgen.sim.robot.polite import FACE_GAP
    from socnavgen.sim.robot.script import LET_PASS_PATIENCE
    from socnavgen.sim.robot.wait_spot import ASIDE, SPOT_REACH
    from socnavgen.verify.blame_cue import NEAR_MISS

    limits = ("- The script drives the robot's route (node to node), stands it still (wait, wait_until_clear, "
              "let_pass) and speaks; no cue makes it back off, pull over or follow someone. A route may come back to "
              "its start after passing other nodes.")
    let_pass = (" \"It lets her go first\" is a cue with \"let_pass\": \"humanN\": the robot stands where the cue "
                f"fires (stepping up to {SPOT_REACH:g} m aside off her way where there is room) until that person has "
                f"gone by (across its way, past it, or on ahead of it), at most `wait` s ({LET_PASS_PATIENCE:g} "
                "without); fire it before the place they cross and before any narrow edge she needs (at_encounter "
                "with a distance, or human_within). It may stand only a moment (she is already on ahead): a stop the "
                f"story needs as such is a cue's plain `wait` (in which it steps up to {ASIDE:g} m to its right for "
                "someone coming past).")
    if not detail:
        return limits
    seen = [t for t in ("robot_near", "robot_visible", "robot_blocking") if detected(t, target)]  # target offers
    return (limits + let_pass + " By itself the robot passes people on one "
            "side where there is room, slows near them, and makes way for someone who must get past it (after "
            f"{ScriptedPolicy.patience:g} s face to face, a gap of {FACE_GAP:g} m or less, it backs off the way it "
            "came and steps aside where there is room). So \"it pulls over\": a person meets it face to face in a "
            "passage, or a wait_until_clear cue at a wider node; \"it follows someone\": they lead along its route "
            "(robot_far to wait).\n"
            f"- It stops about {round(ScriptedPolicy.stop_gap + TOUCH_DISTANCE, 2):g} m (centres) from a person in "
            f"its way; {wait_until_clear_text()}, so a cue needing it closer to them never fires meanwhile.\n"
            f"- A person's {' / '.join(seen)} must hold where the robot really comes: one its cue "
            f"stands stays where the cue fired, so give the trigger the distance between them then plus {NEAR_MISS:g} m "
            "(a distance reached only by a hair fails on any change of its approach)" + (
                f"; robot_blocking needs the robot in sight within {BLOCKING_DEGREES} degrees of the way they face, "
                "never so while it stands aside to let them pass: to stop as it waits there, use robot_visible or "
                "robot_near." if "robot_blocking" in seen else "."))


def follower_turn_text() -> str:
    """A follower in the robot's way (sim/people/give_way.lets_robot_by), so how to bring something to someone."""
    from socnavgen.sim.people.leaves import FOLLOW_STOP
    from socnavgen.sim.people.side_step import FOLLOW_WAY_AHEAD

    return (f"- A follower (follow, FollowRobot) on the robot's way ahead of it, within {FOLLOW_WAY_AHEAD:g} m (it turns "
            f"round at a dead end or on a round trip), steps aside like give_way as it drives (not while a cue holds it) and "
            f"follows again once it has passed; with no room beside it (under {PASS_WIDTH:g} m free) they first walk "
            f"ahead of it to the nearest place wide enough. While a cue holds it they come up and stand {FOLLOW_STOP:g} m "
            f"in front of it, facing it. BRING X TO SOMEONE: their node is not the robot's goal (the run ends there): "
            f"a `wait` cue stops it a few metres before them, they `follow` (\"lasts\", then they walk back), stated by "
            f"stops_near_robot. So start a follower behind or beside the robot's start, not on its route ahead; "
            f"someone who falls in as it sets off may meet it at its start node (stated by follows_robot, with no "
            f"meets, they need no approach). Following does not walk their own path: when it ends they walk on to "
            f"the node they were walking to when it began (back the way they came).")


def wait_until_clear_text() -> str:
    """What a wait_until_clear cue waits for (sim/robot/script.py: the larger of HELD_UP_DISTANCE and the cue's
    trigger distance, whatever the trigger; CLEAR_PATIENCE, CLEAR_REPEATS)."""
    from socnavgen import proxemics
    from socnavgen.sim.robot.script import CLEAR_PATIENCE, CLEAR_REPEATS

    return (f"a wait_until_clear cue (after the cue's `wait`, if it has one) holds it where the cue fired while anyone is in its way (ahead of it, on its "
            f"route) within {proxemics.HELD_UP_DISTANCE:g} m, or within the cue trigger's `distance` when that is "
            f"larger, whatever the trigger is (at_encounter, human_within, blocked alike; nobody ahead: it goes on "
            f"at once); still held after {CLEAR_PATIENCE:g} s it says its phrase again, {CLEAR_REPEATS} times "
            f"{CLEAR_PATIENCE:g} s apart (a cue without a phrase waits as long, silently), then drives around them; "
            f"with nobody in its way it ends at once, so a stop the story needs for N s is a `wait` of N s")


def stl_text(signals: bool = True) -> str:
    """How to write a `stl` criterion: the syntax and the signals (verify/stl.py, verify/signals.py); `signals`
    False (fit.py's `signals` cut, a small context) only says to use the other kinds."""
    from socnavgen.verify.signals import SIGNAL_KINDS
    from socnavgen.verify.stl import MAX_FORMULA_CHARS, MAX_NESTING

    if not signals:
        return "- A criterion of kind stl holds a raw signal temporal logic formula: use the other kinds."
    listed = "; ".join(f"{k.shown} ({k.unit}): {k.meaning}" for k in SIGNAL_KINDS if k.listed)
    return (f"- A criterion of kind stl holds a signal temporal logic \"formula\": one expression of at most "
            f"{MAX_FORMULA_CHARS} characters and {MAX_NESTING} nested levels, with the operators always, "
            f"eventually, historically, once, until, since (bounds in seconds, e.g. eventually[0:5]; an operator "
            f"without bounds, e.g. \"eventually (dist_human1 < 2.0)\", is allowed and spans the whole run), and, or, "
            f"not, implies, and comparisons (<, <=, >, >=); 0/1 signals are compared with 0.5. Example: "
            f"\"{STL_EXAMPLE}\" (within the first 60 s the robot says EXCUSE ME while human1 is within 2 m). "
            f"Signals: {listed}. Use the other kinds when one fits: they are checked with care for cause and "
            f"effect.")


def cue_triggers_text(detail: bool = True) -> str:
    """Each cue trigger with its meaning, read from CueTrigger's docstring (the one place that explains them);
    `detail` False (stage 1's `robot` cut, fit.py): without how its distance is measured."""
    meanings = dict(re.findall(r"^\s+([a-z_]+)\s+(\S.*)$", CueTrigger.__doc__ or "", re.MULTILINE))
    if not detail:  # without the asides in parentheses (the small model's context, fit.py)
        meanings = {when: re.sub(r"\s*\([^()]*\)", "", text) for when, text in meanings.items()}
    return ", ".join(f"{when} ({meanings.get(when, '').strip()})"
                     for when in get_args(CueTrigger.model_fields["when"].annotation)) + \
        (" (a cue trigger's `distance` is straight, walls or not)" if detail else "")


def robot_vocabulary_text() -> str:
    """The phrases of the robot and of the humans (the words the spec's validator accepts; the triggers and
    reactions are listed with their meanings by scenario_spec.md, tested to name every one of run/spec.py)."""
    robot_words = ", ".join(v for k, v in ROBOT_GESTURES.items() if k)
    human_words = ", ".join(v for k, v in HUMAN_GESTURES.items() if k)
    return f"The robot can say: {robot_words}. A human can say: {human_words}."


def scenario_rules_text(target: Target | None = None, signals: bool = True, robot: bool = True) -> str:
    """What stage 1 must know about how its spec plays out (pacing, within, cues, groups, people, latch, what
    the robot cannot do, export, stl); `signals` False names the STL signals without their meanings."""
    lines = ["HOW THE SPEC PLAYS OUT:", starts_text() if robot else "", pacing_text(robot), encounter_within_text(),
             implied_meets_text() if robot else "", cue_once_text(robot), groups_text(robot), people_text(detail=robot),
             latch_text(target or "socrates"), robot_limits_text(robot, target or "socrates"), follower_turn_text() if robot else "",
             export_text(target, spec_words=True), stl_text(signals), events_text(signals)]
    return "\n".join(line for line in lines if line)


def events_text(detail: bool = True) -> str:
    """Stage 1's rule that its criteria state the events its own text names (no verifier sees an unstated event
    missing), with a worked example; told with the stl help (`detail` False: fit.py's signals cut drops it, the
    check spec_checks.unstated_reactions still names what is missing)."""
    if not detail:
        return ""
    kinds = "; ".join(f"{r}: {' or '.join(k)}" for r, k in STATED_BY.items())
    return ("- STATE THE EVENTS OF YOUR TEXT: an event no criterion states can fail unseen. Every person who reacts "
            f"to the robot gets a criterion of the reaction's kind ({kinds}; after a robot phrase also "
            "reacts_after_phrase): meets only says they came near. Who goes first is an event too: \"the robot "
            "stands aside while the visitor passes\" is {\"kind\": \"stl\", \"formula\": "
            f"\"{ORDER_EXAMPLE}\"}}, with A a node she reaches once past the robot and B the node the robot "
            "drives on to: the robot reaching B itself, not where it waits (it stands where its cue fires, often "
            "1-2 m short of B, wherever she is then). Unbounded always / until are judged from t = 0, everyone at "
            "their start: a distance kept once something began is \"always ((once X) implies Y)\". \"always (X "
            "implies Y)\" also holds when X never happens: when X is an event of your text (the worker stands in "
            "the robot's way), state X itself too (eventually X).")


def starts_text() -> str:
    """Stage 2's start rule (location/placement.py, the one home of its numbers and its check), told at stage 1 too:
    the prose decides who waits where, and a scene it cannot place is refused only at stage 2 (round-7 players)."""
    from socnavgen.location.placement import start_rule_text

    return (f"- {start_rule_text()} The paths stage refuses other starts, so write the scene with them: people "
            "waiting together at one place are a group (or wait at different nodes), and whoever waits for the "
            f"robot at an encounter's node stands at least {approach_room():g} m (straight) from where it starts "
            f"(a meeting counts only after an approach; more with a larger meets `distance`): \"right in front "
            f"of\" the robot's start means a node that far away, or the robot starts a node farther back.")
