"""Who can fix a failing finding: the robot's script, the paths, one human's behavior tree, or the spec.

The rule table (first matching rule wins; docs/verify.md shows the same):

  S1  the criterion contradicts its own spec (unknown encounter or human, a meeting closer than the two
      radii, a phrase other than the one its encounter waits for, a stop asked of a walk_past, a
      reaction its encounter does not give the human (follows_robot / follows_human / blocks_robot / gives_way /
      keeps_away / reacts_after_phrase), keeps_away farther than a meeting it also asks for, a
      placeholder for its text, a formula that cannot be monitored; stage 1 applies the same
      `contradictions`)                                                                         -> spec
  S2  the criterion's place cannot work on this map (location/inventory.py: no node of that type, every one
      unreachable or a dead end too tight to pass a person), or it asks for a hidden approach where no
      node of that type is a blind turn                                                       -> spec
  C1  collision, with a robot that is not meant to misbehave                                   -> robot_script
  C2  collision demanded away by a spec whose robot misbehaves on purpose                      -> spec
  C3  (checked before C1) a human walked into the robot while it stood still                  -> behaviors(h)
  A1  two people touch (people_apart) from the start, or both walking into one place at once  -> paths
  A2  two people touch, one walking into the other standing                                   -> behaviors(walker)
  D1  deadlock / goal not reached behind a human whose reaction waits for a robot phrase the
      robot never said                                                                        -> robot_script
  D5  (checked first) deadlock / goal not reached behind a human standing round its own goal, its tree only
      walking it there, that goal at or next to the robot's goal (verify/blame_end.py)          -> paths
  D3  (checked before D1) deadlock behind a human standing at its own goal off the robot's route
      (the robot could pass: the paths put that goal beside the route)                         -> paths
  D4  (checked before D2) a standoff the spec sets up, h having no part that makes way (give_way, avoid): the
      robot's wait_until_clear cue fired as the wait began
      (its phrase said up to 3 s before) with h in its way, or h's encounter has it stop / look while the robot is there with no `lasts` (each waits for the
      other), with who, where, gap and how long                                                 -> spec
  D2  deadlock / goal not reached behind a human (the human's tree keeps it in the way)        -> behaviors(h)
  P1  the criterion (or, for meets / stops / gives_way / says / blocks, its encounter) waits for
      a robot phrase the robot never said                                                       -> robot_script
  P2  the reaction happened before its cause (the tree is not gated on the phrase)             -> behaviors(h)
  N1  the robot, or the human, never came within `within` of the encounter node                -> paths
  N2  both reached the node but never within the distance at the same time (timing, place)    -> paths
  N3  the robot never came near the human, or the human was never in its way (a reaction's cause
      never held: also its encounter's robot_visible / robot_near / robot_blocking cue, e.g. a wall
      between them), or a meeting had no approach / shares the earlier encounter's meeting       -> paths
      except (verify/blame_cue.py): that cue missed by a hair (its distance by 1 m or less, or
      robot_blocking's cone with the robot in sight within its distance)                       -> spec
  V1  hidden_until failed: the two saw each other early (the place is not blind)               -> paths
  G1  a group apart whose members walk different paths                                          -> paths
  G2  a group apart on one path                                                                -> behaviors(farthest)
  F1  follows_human: whom h follows never walked -> behaviors(them); else (verify/blame_follow.py) -> behaviors(h)
  R1  the trigger held (the robot near / said the phrase) but the reaction never ran           -> behaviors(h)
      except: a hold (blocks_robot, stops_near_robot) whose reaction ran its whole `lasts` and was over
      before the robot was held there (the tree must keep the spec's `lasts`)                  -> spec
      except: a block whose `until` phrase a `blocked` cue says where the blocker stands, or
      (checked first) the robot within reach only after the encounter's window closed         -> spec
  R8  (after R1's exceptions) a stop lasting while the robot is near: h stood, then walked off with it still near
      (verify/stay.py): making room for the robot waiting in front of them -> spec; else       -> behaviors(h)
  R3  robot_reaches_goal failed, the robot ending still with nobody in its way, a cue of its script holding
      it then (the trace's cue log; without one: the script has cues that can make it stand)  -> robot_script
  R5  ... and the cue log shows no cue holding it: the robot's own navigation (blame_end.py)  -> simulator
  R6  no_deadlock failed on `idle` (no deadlock): no progress with its way clear, no cue (idle.py) -> simulator
  R4  (checked before R2) robot_reaches_goal failed with someone holding the robot up at the end of the run (a
      wait shorter than the deadlock limit): rule D4's standoff                                 -> spec
      else                                                                                      -> behaviors(h)
  R2  robot_reaches_goal failed without a deadlock (otherwise), saying whether the robot was still on its
      way when the run ended (the route takes longer than the run) or stood short of its goal   -> paths
  T1  tree checks (no spec.json): a RobotSays gate whose gesture the robot never made           -> robot_script
  T2  tree checks: IsRobotVisible / IsRobotNearby never succeeded                               -> paths
  T3  tree checks: any other node never ran, or ran before its cause, or (GiveWaytoRobot) ran without the
      body getting out of the robot's way                                                       -> behaviors(h)
  R7  (before R1 and T3) GiveWaytoRobot ran its reaction seconds at once with the robot near and the body never
      got out of the robot's way: the place leaves no room (blame_tree.gave_way_in_vain)         -> spec
  U1  a user `stl` formula: robot phrases it names never said -> robot_script; it names a human's
      actions, phrases or reactions -> behaviors(h); otherwise                                 -> paths
      (proposal/verify_loop.py: the spec's own formula failing again after the paths changed -> spec)
  W1  the implied walks_on (derive.walks_on): a stop lasting while the robot is near still held for the run's last
      HELD_ON s, the person's path going on: the stop's distance reaches where the robot ends   -> paths
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from socnavgen.bodies import (
    PERSON_GOAL_RADIUS,
    PERSON_GOAL_SLACK,
    PERSON_RADIUS,
    ROBOT_RADIUS,
    TOUCH_DISTANCE,
)
from socnavgen.run.models import PathPlan
from socnavgen.run.spec import Criterion, ScenarioSpec
from socnavgen.verify.blame_cue import cue_never_held, stop_not_held
from socnavgen.verify.blame_end import (
    SIMULATOR_NOTE,
    goal_taken,
    never_released,
    short_of_goal,
    standing_at_end,
)
from socnavgen.verify.blame_follow import ahead_of_robot, blame_follower, never_near_start
from socnavgen.verify.blame_timing import ended_at_once, stood_before_approach, window_closed_early
from socnavgen.verify.blame_tree import FACTS_CLOSE, FACTS_OPEN, gave_way_in_vain, tree_activity
from socnavgen.verify.criteria import Compiled
from socnavgen.verify.derive import WALKS_ON
from socnavgen.verify.evidence import deadlock_culprit, in_window, met_mask, stayed_off_place, way_cause
from socnavgen.verify.idle import idle_fact
from socnavgen.verify.models import Verdict
from socnavgen.verify.people import blame_people
from socnavgen.verify.runs import lasting
from socnavgen.verify.signals import ROBOT_PHRASES, Signals, phrase_id, reaction_evidence
from socnavgen.verify.stay import stay_broken
from socnavgen.verify.stl import formula_signals
from socnavgen.verify.thresholds import (
    APPROACH,
    KIND_DISTANCE,
    MEET_DISTANCE,
    PASSING_DISTANCE,
    REACTION_SECONDS,
    STILL_SPEED,
    STOP_HOLD,
)


def spec_problem(c: Criterion, spec: ScenarioSpec, roster: set[str] | None = None) -> str | None:
    """Rule S1: why a criterion contradicts its own spec, or None. `roster`: the run's humans (default: those
    of the spec's encounters)."""
    if c.text and _PLACEHOLDER_TEXT.fullmatch(c.text):
        return f"criterion {c.id} says only {c.text.strip()!r}: write what it checks, consistent with the scenario"
    if c.encounter and spec.encounter(c.encounter) is None:
        return f"criterion {c.id} names encounter {c.encounter!r}, which the spec does not have"
    humans = set(spec.humans()) if roster is None else roster
    for name in [c.human, *c.humans]:
        if name and humans and name not in humans:
            return f"criterion {c.id} is about {name}, who takes part in no encounter"
    found = contradictions(c, spec)
    return found[0] if found else None


def contradictions(c: Criterion, spec: ScenarioSpec) -> list[str]:
    """Every way a criterion asks what its own spec says does not happen (the heart of rule S1; stage 1 refuses
    the same before anything is simulated: proposal/spec_checks.py)."""
    out = []
    if c.kind == "meets" and c.distance is not None and c.distance < TOUCH_DISTANCE:
        out.append(f"criterion {c.id} asks for a meeting closer than {TOUCH_DISTANCE:g} m centre to centre: "
                   f"that is a collision ({ROBOT_RADIUS:g} m robot + {PERSON_RADIUS:g} m human radius)")
    parts = spec.parts_of(c.human) if c.human else []
    if c.encounter:
        parts = [(e, p) for e, p in parts if e.id == c.encounter]
    if c.kind in ("reacts_after_phrase", "follows_robot", "follows_human") and c.phrase:
        waits = {p.phrase for _, p in parts if p.trigger == "robot_says" and p.phrase}
        if waits and c.phrase not in waits:
            out.append(f"criterion {c.id} waits for the robot saying {c.phrase}, but its encounter reacts to "
                       f"{', '.join(sorted(waits))}")
    if c.kind in ("stops_near_robot", "blocks_robot") and parts and all(p.reaction == "walk_past" for _, p in parts):
        out.append(f"criterion {c.id} asks {c.human} to stop, but its encounter has it walk past")
    reactions = {p.reaction for _, p in parts}
    allowed = REACTIONS_OF.get(c.kind)
    if allowed is not None and parts and not reactions & allowed:
        out.append(f"criterion {c.id} ({c.kind}) asks {c.human} for what its encounter does not have it do (its "
                   f"reaction: {', '.join(sorted(reactions))}; {c.kind} needs {' or '.join(sorted(allowed))})")
    if c.kind == "reacts_after_phrase" and c.reaction and parts and c.reaction not in reactions:
        out.append(f"criterion {c.id} expects the reaction {c.reaction} of {c.human}, but its encounter has "
                   f"{', '.join(sorted(reactions))}")
    if c.kind == "says" and c.phrase and parts:
        said = {p.says for _, p in parts if p.reaction == "say" and p.says}
        if said and c.phrase not in said:
            out.append(f"criterion {c.id} asks {c.human} to say {c.phrase}, but its encounter has it say "
                       f"{', '.join(sorted(said))}")
    if c.kind == "keeps_away" and c.human:
        meet = next((m for m in spec.criteria if m.kind == "meets" and m.human == c.human), None)
        if meet is not None and (meet.distance or MEET_DISTANCE) < (c.distance or KIND_DISTANCE["keeps_away"]):
            out.append(f"criterion {c.id} keeps {c.human} {c.distance or KIND_DISTANCE['keeps_away']:g} m away, "
                       f"but criterion {meet.id} asks them to meet within {meet.distance or MEET_DISTANCE:g} m")
    return out


# the encounter reactions (run.spec.Reaction) a criterion kind can be about: any other contradicts the spec (S1)
REACTIONS_OF = {"follows_robot": {"follow", "follow_human", "join"}, "follows_human": {"follow_human"},
                "blocks_robot": {"block"}, "gives_way": {"give_way", "avoid"},
                "keeps_away": {"avoid", "walk_past", "give_way", "stop", "look", "wait_then_go", "say"}}
_PLACEHOLDER_TEXT = re.compile(r"\s*(placeholder|todo|tbd|xxx|\.\.\.|<[^<>]*>|criterion|text)\s*[.!]?\s*", re.I)


def place_problem(cc: Compiled, location: Any) -> str | None:
    """Rule S2: why the criterion's place cannot work on this map (location/inventory.py, the measure stage 1's
    checks use too), or None."""
    enc = cc.encounter
    inventory = getattr(location, "inventory", None) if enc is not None else None
    if enc is None or inventory is None:
        return None
    reason = inventory.unworkable_reason(enc.place)
    if reason:
        return f"encounter {enc.id} happens at a {enc.place}, but {reason}: choose a place of this map that can work"
    if cc.criterion.kind == "hidden_until" and not inventory.blind_nodes(enc.place):
        return (f"no {enc.place} node of this map hides one way from the other: nothing can stay hidden there; "
                "choose a blind turn of the map or drop the criterion")
    return None



def _walked_into_robot(s: Signals) -> str | None:
    """The human who walked into the robot while it stood still (rule C3), at the first collision."""
    summary = s.contacts()
    if not summary.collided or summary.first_collision_time is None:
        return None
    k = int(np.searchsorted(s.t, summary.first_collision_time))
    who = summary.first_collision_human
    if s.speed("robot")[k] < STILL_SPEED and who and s.speed(who)[k] >= STILL_SPEED:
        return who
    return None


def _never_said(s: Signals, phrase: str | None) -> bool:
    return bool(phrase) and not (s.get(f"robot_says_{phrase}") > 0.5).any()


def _waited_phrase(spec: ScenarioSpec, human: str | None, ending: bool = False) -> str | None:
    """The robot phrase `human` waits for to react (trigger robot_says); `ending`: or to end a reaction (`until`:
    a person blocking until a phrase the robot never says holds it up for good)."""
    for _, p in spec.parts_of(human) if human else []:
        if p.trigger == "robot_says" and p.phrase:
            return phrase_id(p.phrase)
        if ending and p.until:
            return phrase_id(p.until)
    return None


def _off_route_at_goal(s: Signals, plan: PathPlan | None, who: str, k: int) -> str | None:
    """Rule D3: `who` stands at its own last node at step k, and off the robot's route (the robot's body could
    pass beside it): the node it waits at, else None."""
    goal_node = next((h.path[-1] for h in (plan.humans if plan is not None else []) if h.name == who and h.path), None)
    goal = s.places.get(f"node_{goal_node}") if goal_node else None
    waypoints = np.asarray(s.trace.robot_waypoints, dtype=float).reshape(-1, 2)
    if goal is None or len(waypoints) < 2:
        return None
    p = s.pos(who)[k]
    if float(np.hypot(*(p - np.asarray(goal)))) > PERSON_GOAL_RADIUS + PERSON_GOAL_SLACK:
        return None
    a, d = waypoints[:-1], np.diff(waypoints, axis=0)
    u = np.clip(((p - a) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-12), 0.0, 1.0)
    off = float(np.min(np.hypot(*(a + u[:, None] * d - p).T)))
    radius = float(np.asarray(s.trace.human_radii)[s.human(who)])
    return goal_node if off >= float(s.trace.robot_radius) + radius else None


def _not_the_tree(s: Signals, spec: ScenarioSpec, who: str, k: int) -> Verdict | None:
    """Someone holds the robot up at step k for a reason their tree cannot fix (D1, D4, R4): they wait for a phrase
    the script never says, or the spec sets up the standoff."""
    phrase = _waited_phrase(spec, who, ending=True)
    if phrase and _never_said(s, phrase):
        return ("robot_script", None, f"{who} waits for the robot to say {phrase.replace('_', ' ').upper()}, "
                                      "which the script never says: add a cue (e.g. when blocked)")
    standoff = _standoff(s, spec, who, k)
    return ("spec", None, standoff) if standoff else None


def _stuck(cc: Compiled, s: Signals, spec: ScenarioSpec, settings_deadlock: float,
           plan: PathPlan | None = None) -> Verdict | None:
    """Rules D3, D1, D2."""
    dead = s.get("deadlock")
    if dead.max() < settings_deadlock:
        return None
    k, who = deadlock_culprit(s)
    if who is None:
        return None
    taken = goal_taken(s, plan, who, k)
    if taken:
        return taken
    at_goal = _off_route_at_goal(s, plan, who, k)
    if at_goal:
        return ("paths", None, f"{who} stood at its own goal ({at_goal}) beside the robot's route and the robot would "
                               "not pass: put that goal off the robot's way, or route the robot elsewhere")
    elsewhere = _not_the_tree(s, spec, who, k)
    if elsewhere:
        return elsewhere
    return ("behaviors", who, f"{who} stood in the robot's way ({_held_up_fact(s, who, k)}): its tree must let "
                              "the robot through, by giving way where there is room to step aside, or by walking on toward "
                              "its goal past the robot (the robot makes way for someone who needs to get past it), "
                              "not by standing in front of it")


STANDOFF_LEAD = 3.0  # s: a wait_until_clear cue whose phrase was said this long before a deadlock began started it
YIELDING = ("give_way", "avoid")  # a person with one of these parts is meant to make way for the robot
HOLDING_REACTIONS = ("stop", "look")  # a person with one of these stands while its trigger holds (no `lasts`)
PRESENCE_TRIGGERS = ("robot_blocking", "robot_near", "robot_visible")  # triggers the robot standing there keeps true


def _where(s: Signals, who: str, k: int) -> str:
    """'at node iq (0.4 m)': the scene-graph node nearest `who` at step k, '' when the run has none."""
    nodes = [(float(np.hypot(*(s.pos(who)[k] - np.asarray(p)))), n[5:]) for n, p in s.places.items()
             if n.startswith("node_")]
    return f" at node {min(nodes)[1]} ({min(nodes)[0]:.1f} m)" if nodes else ""


def _held_up_fact(s: Signals, who: str, k: int) -> str:
    """'at node iq (0.4 m), 0.55 m gap, 103 s from t=17.5 s': where, how close and how long `who` held the robot up
    in the deadlock ending at step k."""
    dead = float(s.get("deadlock")[k])
    gap = float(s.gaps()[k, s.human(who)])
    return f"{_where(s, who, k).strip() or 'here'}, {gap:.2f} m gap, {dead:.0f} s from t={s.t[k] - dead + s.trace.dt:.1f} s"


def _standoff(s: Signals, spec: ScenarioSpec, who: str, k: int) -> str | None:
    """Rule D4: the deadlock is a standoff the spec itself sets up (`who` has no part that makes way for the robot),
    with who, where, gap and how long: the robot's
    script waits until nobody is in its way (wait_until_clear, its cue's phrase said as the wait began, or during
    it) while `who` is in it, or
    `who`'s encounter has it stand (stop / look, no `lasts`) for as long as the robot is there: each waits for
    the other, which no path or tree can undo."""
    if any(part.reaction in YIELDING for _, part in spec.parts_of(who)):
        return None  # the spec has them make way: staying in it is their tree's doing (D2)
    fact = f"{who} in the robot's way ({_held_up_fact(s, who, k)})"
    start = max(0, k - int(round(float(s.get("deadlock")[k]) / s.trace.dt)) - int(round(STANDOFF_LEAD / s.trace.dt)))
    for n, cue in enumerate(spec.script.cues, 1):  # its phrase said as this wait began (a cue without one: unknown)
        said = cue.say is not None and (np.asarray(s.trace.robot_gesture[start:k + 1]) == ROBOT_PHRASES.get(
            phrase_id(cue.say), -1)).any()
        if cue.wait_until_clear and said:
            return (f"a standoff set by the spec: cue {n} of the robot's script waits until nobody is in its way "
                    f"(wait_until_clear) with {fact}, where the two cannot pass each other: say who yields (drop "
                    f"wait_until_clear, or have {who} give way or walk past, or meet at a wider place)")
    for enc, part in spec.parts_of(who):
        if part.reaction in HOLDING_REACTIONS and part.trigger in PRESENCE_TRIGGERS and part.lasting() is None:
            return (f"a standoff set by the spec: {enc.id} has {who} {part.reaction} while the robot is there "
                    f"({part.trigger}, no `lasts`) and the robot waits for {who}: {fact}; say who yields (give the "
                    f"{part.reaction} `lasts` seconds, or let {who} come through first, or meet at a wider place)")
    return None


def _held_at_end(s: Signals, spec: ScenarioSpec, plan: PathPlan | None) -> Verdict | None:
    """Rule R4: the run ended with someone holding the robot up short of its goal (a wait shorter than the deadlock
    limit): a standoff the spec sets up (rule D4), else that person's tree."""
    k = s.trace.steps - 1
    holding = s.holding_up()[k]
    if k < 0 or not holding.any():
        return None
    gaps = np.where(holding, s.gaps()[k], np.inf)
    who = s.trace.human_names[int(np.argmin(gaps))]
    elsewhere = goal_taken(s, plan, who, k) or _not_the_tree(s, spec, who, k)
    if elsewhere:
        return elsewhere
    return ("behaviors", who, f"the run ended with {who} in the robot's way short of its goal "
                              f"({_held_up_fact(s, who, k)}): its tree must let the robot through")


def blame_criterion(cc: Compiled, s: Signals, spec: ScenarioSpec, plan: PathPlan | None,
                    settings_deadlock: float, location: Any = None, authored: bool = True) -> Verdict:
    """Apply the rule table to one failing, monitored criterion that does not contradict its spec (rule S1 is
    the judge's: such a criterion fails without a robustness). `authored`: the spec is spec.json, not one
    derived from the paths, so rule S2 applies."""
    h, kind = cc.human, cc.criterion.kind
    problem = place_problem(cc, location) if authored else None
    if problem:
        return "spec", None, problem
    if kind == "no_collision":
        if spec.script.misbehave:
            return "spec", None, "the script wants a misbehaving robot but a criterion forbids collisions"
        walker = _walked_into_robot(s)
        if walker:
            return "behaviors", walker, f"{walker} walked into the standing robot: its tree must stop or go around"
        return "robot_script", None, "the robot ran into a person: its script must stop or wait (wait_until_clear)"
    if kind == "people_apart":
        return blame_people(h, s)
    if kind in ("no_deadlock", "robot_reaches_goal"):
        stuck = _stuck(cc, s, spec, settings_deadlock, plan)
        if stuck:
            return stuck
        if kind == "no_deadlock":
            idle = idle_fact(s)  # its way clear, no cue asking it to stand: the robot's own navigation (R6)
            if idle:
                return "simulator", None, f"{idle}: {SIMULATOR_NOTE}"
            return "robot_script", None, "the robot stood still too long: its script's waits are too long"
        waiting = standing_at_end(s, spec, settings_deadlock)
        if waiting:
            return waiting
        held = _held_at_end(s, spec, plan)
        return held or ("paths", None, short_of_goal(s))
    if kind == "stl" and cc.criterion.id.startswith(WALKS_ON) and cc.part is not None:
        return never_released(cc, s)
    if kind == "stl":
        return _blame_formula(cc, s)
    if kind == "robot_stops":
        return stop_not_held(cc, s)
    if kind == "stop_together":
        who = (cc.criterion.humans or [h or ""])[0] or None
        return "behaviors", who, "they did not stand still together: stop each one beside the others"
    robot_phrase = cc.phrase if kind in ("reacts_after_phrase", "follows_robot", "follows_human") else \
        _waited_phrase(spec, h) if kind in ("meets", "says", "stops_near_robot", "gives_way", "blocks_robot") else None
    if robot_phrase and _never_said(s, robot_phrase):
        return ("robot_script", None,
                f"the robot never said {robot_phrase.replace('_', ' ').upper()}: add a cue that says it")
    if kind == "reacts_after_phrase" and h and cc.reaction:
        says, react = s.get(f"robot_says_{cc.phrase}") > 0.5, s.get(f"react_{h}_{cc.reaction}") > 0.5
        first = int(np.argmax(says))
        if react.any() and says.any() and react[first]:  # already reacting when it first spoke
            if cc.reaction == "walk_past":  # the person's ordinary walking
                return "behaviors", h, (f"{h} was already walking when the robot spoke: make it stand (its earlier "
                                        f"part) until the phrase, and walk on gated by RobotSays")
            return "behaviors", h, f"{h} reacted before the robot spoke: gate the reaction on RobotSays"
    if kind == "hidden_until":
        return "paths", None, "robot and human see each other before they meet: choose a blind place"
    if kind == "group_together":
        return _blame_group(cc, s, plan)
    if h and kind == "meets":
        return _blame_meeting(cc, s, h)
    if h:
        reach = max(cc.distance or MEET_DISTANCE, MEET_DISTANCE)
        if kind != "follows_human" and s.get(f"dist_{h}").min() > reach:  # a follower of a person: rule F1
            return "paths", None, f"the robot never came within {reach:g} m of {h}"
        cause = (window_closed_early(cc, s, h, reach) or _missing_cause(cc, s, h, spec) or _spent(cc, s, spec, h)
                 or stay_broken(cc, s) or ended_at_once(cc, s, spec, h) or stood_before_approach(cc, s, h))
        if cause:
            return cause
        if kind == "follows_human":
            return blame_follower(cc, s, h)
        if kind == "follows_robot" and (ahead := ahead_of_robot(cc, s, h)):
            return ahead
        dist = s.get(f"dist_{h}")
        reaction = "give_way" if kind == "gives_way" else cc.reaction
        vain = gave_way_in_vain(s, h, dist <= max(reach, PASSING_DISTANCE), cc.seconds or REACTION_SECONDS) \
            if reaction == "give_way" else None
        if vain:
            return vain
        facts = tree_activity(s, h, dist <= reach, reach, reaction)
        return "behaviors", h, f"the robot came near {h} but {h} did not react as asked ({kind})" + \
            (f"{FACTS_OPEN}{facts}{FACTS_CLOSE}" if facts else "")
    return "paths", None, "the scenario did not unfold as asked"


def _blame_meeting(cc: Compiled, s: Signals, h: str) -> Verdict:
    """Rules N1, N2 and N3 for a meeting."""
    d = cc.distance or MEET_DISTANCE
    if cc.encounter is None:
        if (s.get(f"dist_{h}") <= d).any():
            return "paths", None, f"the robot and {h} start within {d:g} m: start them apart so that they approach"
        return "paths", None, f"the robot never came within {d:g} m of {h}"
    e, within, node = cc.encounter.id, cc.encounter.within, cc.encounter.node or cc.encounter.id
    near = (s.get(f"dist_{h}") <= d) & (s.get(f"mid_{h}_to_{e}") <= within)
    if near.any() and not met_mask(s, h, cc.encounter, d).any():
        return "paths", None, stayed_off_place(cc, s, h, near) or (
            f"the robot and {h} were together at {node} only without approaching each other (from where they "
            "started): start them farther apart, or from other nodes")
    if s.get(f"robot_to_{e}").min() > within:
        return "paths", None, f"the robot never came within {within:g} m of {node}"
    if s.get(f"{h}_to_{e}").min() > within:
        return "paths", None, f"{h} never came within {within:g} m of {node}"
    if near.any() and cc.previous is not None:
        return "paths", None, (f"{h} meets the robot only once, at {cc.previous.node or cc.previous.id}: this "
                               f"encounter needs its own meeting at {node}")
    return "paths", None, f"the robot and {h} were not at {node} at the same time"


def _missing_cause(cc: Compiled, s: Signals, h: str, spec: ScenarioSpec) -> Verdict | None:
    """Rule N3 for reactions: the cause never held (h never in the robot's way, never walking near it)."""
    kind, d = cc.criterion.kind, cc.distance or KIND_DISTANCE.get(cc.criterion.kind, MEET_DISTANCE)
    if cc.window and not in_window(cc, s).any():
        node = cc.encounter.node or cc.encounter.id if cc.encounter is not None else "its place"
        return "paths", None, (f"the robot and {h} were never together at {node} after their encounter before it "
                               "ended: make their paths meet there again")
    if kind == "gives_way" and not way_cause(cc, s, asked=False).any():
        who = " or ".join((h, *cc.together))
        return "paths", None, (f"{who} was never in the robot's way within {d:g} m" + (" in this encounter"
                               if cc.window else "") + ": nothing to give way to; make their paths meet head-on")
    if kind in ("follows_robot", "follows_human") and (never := never_near_start(cc, s, h)):
        return never
    if kind == "stops_near_robot" and not (s.get(f"closer_{h}") >= APPROACH).any():
        return "paths", None, f"the robot never came closer to {h} than where they started"
    return cue_never_held(cc, s, h, spec)


HOLDS = ("blocks_robot", "stops_near_robot")  # criteria that need the person to hold still while the robot is there


def _spent(cc: Compiled, s: Signals, spec: ScenarioSpec, h: str) -> Verdict | None:
    """Rule R1's exception: h did its reaction for the whole `lasts` its spec gives it (the tree must keep the spec's
    `lasts`: proposal/tree_needs.py), and it was over before the criterion saw it hold: the spec's timing (its
    `lasts` or trigger), not the tree."""
    if cc.criterion.kind not in HOLDS:
        return None
    for enc, part in spec.parts_of(h):
        if part.lasts is None or (cc.encounter is not None and enc.id != cc.encounter.id):
            continue
        ran = lasting(reaction_evidence(s, h, part.reaction, part.says), max(part.lasts - STOP_HOLD, 0.0), s.trace.dt)
        if ran.any():
            start = float(s.t[int(np.argmax(ran))])
            return ("spec", None, f"{h} did {part.reaction} for its whole `lasts` ({part.lasts:g} s, from t={start:.1f} "
                                  f"s, {part.trigger}) and it was over before the robot was held there ({cc.criterion.kind}"
                                  f"): its tree must keep the spec's `lasts`, so the spec must time it (a longer "
                                  f"`lasts`, or a later trigger)")
    return None


def _blame_group(cc: Compiled, s: Signals, plan: PathPlan | None) -> Verdict:
    """Rules G1, G2 (a group parting for the robot is not apart: verify/passing.parted_for_robot)."""
    names = re.findall(r"human\d+", cc.formula)
    if plan is not None:
        paths = {tuple(h.path) for h in plan.humans if h.name in names}
        if len(paths) > 1:
            return "paths", None, f"the group members {', '.join(names)} walk different paths"
    spread = s.get("spread_" + "_".join(names))
    k = int(np.argmax(spread))
    goal = None
    if plan is not None:
        last = next((h.path[-1] for h in plan.humans if h.name in names and h.path), None)
        goal = s.places.get(f"node_{last}") if last else None
    if goal is not None:  # the member farthest from the group's destination lags behind
        far = [float(np.linalg.norm(s.pos(n)[k] - np.asarray(goal))) for n in names]
    else:  # the member farthest from the others
        pos = np.stack([s.pos(n)[k] for n in names])
        far = list(np.linalg.norm(pos - pos.mean(axis=0), axis=1))
    who = names[int(np.argmax(far))]
    when = f"{float(spread[k]):.2f} m apart at t={float(s.t[k]):.1f} s"
    where = "lags behind the others" if goal is not None else "is farthest from the others"
    return "behaviors", who, f"{who} {where} ({when}): its tree must keep it with the others"


def _blame_formula(cc: Compiled, s: Signals) -> Verdict:
    """Rule U1: the robot's phrases, a human's doings, else the geometry: the paths (where and when people meet;
    the --verify loop sends the spec's own formula to stage 1 when it still fails after the paths changed)."""
    names = formula_signals(cc.formula)
    for name in names:
        m = re.fullmatch(r"robot_(?:says|said)_([a-z_]+)", name)
        if m and m[1] in ROBOT_PHRASES and _never_said(s, m[1]):
            return "robot_script", None, f"the formula needs the robot to say {m[1].replace('_', ' ').upper()}, which it never did"
    for name in names:
        m = re.match(r"(?:exec|holds|react)_(human\d+)_|(human\d+)_(?:says|said)_", name)
        if m:
            who = m[1] or m[2]
            return "behaviors", who, f"the formula asks something of {who}'s behavior"
    what = cc.criterion.text or "the formula's geometry"
    return "paths", None, f"{what}: not so in the simulation; check where and when the paths meet"

