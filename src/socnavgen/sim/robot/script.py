"""The robot's script: the cues of spec.json (say, wait, wait until clear, change speed) and the older
gesture rules of paths.json (say EXCUSE ME while someone blocks the way...), played every step before the
robot's policy acts. What they ask now is `Cues` (obs.cues): every policy sees it.

A cue fires on the step its trigger becomes true (`once`: only the first time). Firing: `say` shows the
phrase for `hold` s, `wait` stands still for `wait` s, `wait_until_clear` then stands until nobody is inside
the corridor the robot's body sweeps ahead (people who stepped aside do not hold it; people walking into it
do); still blocked after CLEAR_PATIENCE s it says the cue's phrase again (a silent cue waits on as long),
CLEAR_REPEATS times, then stops waiting (the robot then goes around where there is room: a scripted wait never becomes a deadlock); `let_pass` stands until that
person has gone by (gone_by: came near, out of its way, moving off; or at the end of their walk), at most `wait` s (LET_PASS_PATIENCE without
one): "the robot lets her go first" (having walked by, they may stop out of its way: gone by too); `speed` sets
the cruise speed.
A gesture rule holds its gesture while its condition held within its last `duration` seconds; the first
rule that holds wins. The robot shows a cue's phrase, else the first rule's gesture (scripted_gesture).

Outside a simulation (the export's ROS node, which hears poses on topics), `poses(n)` is the part of the
state the script reads and `play_gesture` plays one step of it: the same code, on those poses.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import ROBOT_SOCIAL_GAP
from socnavgen.bt.library import HUMAN_GESTURES, ROBOT_GESTURES
from socnavgen.run.models import RobotGestureRule
from socnavgen.run.spec import RobotCue, RobotScript
from socnavgen.sim.jit import jit
from socnavgen.sim.people.routing import project
from socnavgen.sim.records import layout, table
from socnavgen.sim.robot.polite import stands_clear
from socnavgen.sim.world.grid import empty_room

ROBOT_PHRASE_CODE = {name: code for code, name in ROBOT_GESTURES.items() if code}
HUMAN_PHRASE_CODE = {name: code for code, name in HUMAN_GESTURES.items() if code}
CLEAR_PATIENCE = 8.0  # s: still blocked after this long, the robot asks again (its cue's phrase; silent: waits on) ...
CLEAR_REPEATS = 2  # ... this many times, then stops waiting and drives around like an operator would
LET_PASS_PATIENCE = 20.0  # s: a `let_pass` cue without a `wait` stands at most this long for its person
LET_PASS_AWAY = 0.5  # m: the person let pass has gone by once this much farther from the robot than its closest
LET_PASS_WALKED = 1.0  # m: ... or, having walked this far since the cue fired, once they stand (within LET_PASS_STILL_REACH)
LET_PASS_STILL = 2.0  # s out of its way: they stopped there (a child at her hiding place 2.7 m off): not coming
LET_PASS_STILL_REACH = 0.3  # m: moving less than this is standing (people jitter in place)
AT_NODE = 1.0  # m: a gesture rule `at_node` holds within this distance of its node
SQUEEZE = ROBOT_SOCIAL_GAP + 0.15  # m: someone beside the route whom the robot passes by edging at most this far
# aside (keeping ROBOT_SOCIAL_GAP, where walls and other people leave it room) does not hold it "until clear". Named
# from the gap: the people it passes so are those up to SQUEEZE - ROBOT_SOCIAL_GAP + proxemics.WAY_MARGIN_SCRIPT
# (0.25 m) inside the corridor its body sweeps, whatever the gap (a SQUEEZE below gap - margin passes nobody)
INTO_WAY = proxemics.STANDING_SPEED  # m/s toward the robot's route: someone walking into its way (not one who
# stepped aside) is not squeezed past: they will stand in it (a worker coming to block it, someone crossing) ...
INTO_WAY_LOOK = 1.0  # s: ... and is in its way already where they will be this soon

START, AFTER, AT_ENCOUNTER, BLOCKED, HUMAN_WITHIN, HUMAN_SAYS, HUMAN_FARTHER = range(7)
TRIGGERS = {"start": START, "after": AFTER, "at_encounter": AT_ENCOUNTER, "at_node": AT_ENCOUNTER,  # both: near a point
            "blocked": BLOCKED, "human_within": HUMAN_WITHIN, "human_farther": HUMAN_FARTHER, "human_says": HUMAN_SAYS}
ALWAYS, NEAR_HUMAN = 7, 8  # gesture rules' own conditions (`blocked` and `at_node` are shared)
RULE_WHEN = {"always": ALWAYS, "at_node": AT_ENCOUNTER, "near_human": NEAR_HUMAN, "blocked": BLOCKED}
FIRED, ASKED_AGAIN, GAVE_UP, WENT_BY = 0, 1, 2, 3  # events of the cue log

NOW = layout([("say", "i8"), ("wait", "?"), ("timed", "?"),  # timed: a cue's `wait` s hold it (not until clear)
              ("letting", "i8"),  # the person a `let_pass` cue stands the robot for (-1: none)
              ("speed", "f8"), ("misbehave", "?"), ("logged", "i8")])
CUE = layout([("when", "i8"), ("who", "i8"), ("phrase", "i8"), ("say", "i8"), ("once", "?"), ("until_clear", "?"),
              ("has_point", "?"), ("point", "c16"), ("seconds", "f8"), ("distance", "f8"), ("hold", "f8"),
              ("pause", "f8"), ("speed", "f8"),  # speed NaN: no change
              ("fired", "i8"), ("was_true", "?"), ("waiting_until_clear", "?"), ("repeats", "i8"),
              ("say_until", "f8"), ("wait_until", "f8"), ("clear_since", "f8"),
              # let_pass: the person (-1: none), waiting for them, they came near, their closest, the limit
              ("lets_pass", "i8"), ("letting_pass", "?"), ("pass_near", "?"), ("pass_closest", "f8"),
              ("pass_until", "f8"),
              # where they were when it fired, where they last stood still since when (gone_by: stopped off its way)
              ("pass_from", "c16"), ("pass_still_at", "c16"), ("pass_still_since", "f8")])
RULE = layout([("when", "i8"), ("gesture", "i8"), ("has_point", "?"), ("point", "c16"), ("distance", "f8"),
               ("duration", "f8"), ("last_true", "f8")])


POSE = layout([("t", "f8"), ("pos", "c16"), ("vel", "c16"), ("heading", "c16"), ("radius", "f8"), ("gesture", "i8")])
# (vel: 0 where only poses are heard - the export's ROS node - as if everyone stood)
# where a policy drives (none: the robot's heading) and the waypoint it heads for (its route: Poses.waypoints)
STEERING = layout([("heading", "c16"), ("has_heading", "?"), ("waypoint", "i8")])


class Poses(NamedTuple):
    """What the script reads of the state (s.clock[0].t, s.robot[0].pos/heading/radius, s.policy[0].heading/waypoint,
    s.people[i].pos/radius/gesture, s.waypoints), as one-row tables and a table per person: fill it and
    play_gesture. A replayed robot has no policy steering and (without waypoints) no route: its way is its heading."""

    clock: np.recarray
    robot: np.recarray
    people: np.recarray
    policy: np.recarray
    waypoints: np.ndarray  # (W,) complex: the robot's route (empty: unknown, its way is straight ahead)
    world: object  # the map's walls (World.map; a replay without a route never looks at it)


def poses(people: int) -> Poses:
    """Empty poses of the robot and `people` people."""
    return Poses(table(POSE, 1), table(POSE, 1, heading=1 + 0j), table(POSE, people), table(STEERING, 1),
                 np.zeros(0, complex), empty_room(1.0, 1.0).map)


class Script(NamedTuple):
    now: np.recarray  # NOW (one row): what the script asks this step
    cues: np.recarray  # CUE per cue of spec.json's script
    rules: np.recarray  # RULE per gesture rule of paths.json
    log_t: np.ndarray  # (E,) time of each logged event
    log_cue: np.ndarray  # (E,) cue of each logged event
    log_event: np.ndarray  # (E,) FIRED, ASKED_AGAIN or GAVE_UP
    finished: np.ndarray  # (N,) bool: person N has finished its walk (the simulator says; the ROS node: never)


def human_index(name: str | None, n: int) -> int:
    """humanK -> agent id K-1 (-1: any person, or a name beyond the crowd)."""
    if not name:
        return -1
    k = int(name[5:]) - 1
    return k if 0 <= k < n else -1


def lower_script(script: RobotScript | None, encounter_points: dict[str, complex], rules: list[RobotGestureRule],
                 node_points: dict[str, complex], people: int, steps: int) -> Script:
    """The script's cues and the gesture rules as tables; room in the log for `steps` steps."""
    cues = list(script.cues) if script is not None else []
    table_ = table(CUE, len(cues))
    for k, cue in enumerate(cues):
        trig, row = cue.trigger, table_[k]
        point = node_points.get(trig.node or "") if trig.when == "at_node" else encounter_points.get(trig.encounter or "")
        row.when, row.who = TRIGGERS[trig.when], human_index(trig.human, people)
        row.phrase = HUMAN_PHRASE_CODE.get(trig.phrase or "", -1)
        row.say = ROBOT_PHRASE_CODE[cue.say] if cue.say else 0
        row.once, row.until_clear, row.has_point = cue.once, cue.wait_until_clear, point is not None
        row.point = point if point is not None else 0j
        row.seconds, row.distance, row.hold, row.pause = trig.seconds, trig.distance, cue.hold, cue.wait
        row.speed = math.nan if cue.speed is None else cue.speed
        row.say_until = row.wait_until = -math.inf
        row.lets_pass = human_index(cue.let_pass, people) if cue.let_pass else -1
        row.clear_since = math.inf
    rows = table(RULE, len(rules), last_true=-math.inf)
    for k, rule in enumerate(rules):
        point = node_points.get(rule.node or "")
        rows[k].when, rows[k].gesture = RULE_WHEN[rule.when], rule.gesture
        rows[k].has_point, rows[k].point = point is not None, point if point is not None else 0j
        rows[k].distance, rows[k].duration = rule.distance, rule.duration
    size = max(len(cues), 1) * 2 * (steps + 2)
    now = table(NOW, 1, letting=-1, speed=script.speed if script is not None else 0.6,
                 misbehave=script.misbehave if script is not None else False)
    return Script(now, table_, rows, np.zeros(size), np.zeros(size, dtype=np.int64), np.zeros(size, dtype=np.int64),
                  np.zeros(people, dtype=np.bool_))


def describe(cue: RobotCue) -> str:
    trig = cue.trigger
    what = [f"say {cue.say}" if cue.say else "", f"wait {cue.wait:g} s" if cue.wait else "",
            "wait until clear" if cue.wait_until_clear else "", f"let {cue.let_pass} pass" if cue.let_pass else "",
            f"speed {cue.speed:g}" if cue.speed is not None else ""]
    return f"{trig.when}: " + ", ".join(w for w in what if w)


def fired(script: Script, cues: list[RobotCue]) -> list[tuple[float, str]]:
    """(t, what) of every logged cue event, as the trace's meta lists them."""
    out = []
    for m in range(min(int(script.now[0].logged), script.log_t.shape[0])):
        cue, event = cues[int(script.log_cue[m])], int(script.log_event[m])
        text = (describe(cue) if event == FIRED else f"still blocked: say {cue.say} again" if event == ASKED_AGAIN
                else f"{cue.let_pass} has gone by: drive on" if event == WENT_BY
                else f"{cue.let_pass} did not go by: drive on" if cue.let_pass and not cue.wait_until_clear
                else "still blocked: stop waiting, go around")
        out.append((round(float(script.log_t[m]), 3), text))
    return out


blocking = jit(proxemics.blocking)  # the one "in the robot's way" (socnavgen.proxemics), compiled


@jit(inline=True)
def still_waits(script, t):  # noqa: ANN001, ANN201
    """Seconds from `t` the robot will still stand for its cues' timed waits (`wait`; 0: none now). A wait
    until clear has no known end and is not counted (pacing: the robot's ETA)."""
    left = 0.0
    for c in range(script.cues.shape[0]):
        left = max(left, script.cues[c].wait_until - t)
    return left


@jit
def start_waits(script, t):  # noqa: ANN001, ANN201
    """Seconds from `t` the robot will still stand for its start cues' timed waits (a late start: pacing counts it
    even where the robot starts near a person's node - it has not come there to meet them)."""
    left = 0.0
    for c in range(script.cues.shape[0]):
        if script.cues[c].when == START:
            left = max(left, script.cues[c].wait_until - t)
    return left


@jit(inline=True)
def waiting_for(script):  # noqa: ANN001, ANN201
    """The person a `let_pass` cue stands the robot for now (-1: none): pacing lets them go first."""
    for c in range(script.cues.shape[0]):
        if script.cues[c].letting_pass:
            return script.cues[c].lets_pass
    return -1


@jit
def route_segment(s):  # noqa: ANN001, ANN201
    """The segment of the robot's route it is on: the nearest to it from the one before the waypoint it heads
    for (the first as near as the nearest); -1 without a route."""
    wps, r = s.waypoints, s.robot[0].pos
    first = max(s.policy[0].waypoint - 1, 0)
    if wps.shape[0] - first < 2:
        return -1
    best, seg = math.inf, first
    for j in range(first, wps.shape[0] - 1):
        d = project(r, wps[j], wps[j + 1])[1]
        if d < best - 1e-9:
            best, seg = d, j
    return seg


@jit(inline=True)
def into_route(q, foot, d):  # noqa: ANN001, ANN201
    """m/s at which person q walks toward `foot`, their nearest route point d m away (0 on the route)."""
    return (q.vel * ((foot - q.pos) / d).conjugate()).real if d > 1e-6 else 0.0


@jit
def squeezes_past(s, i, foot, d):  # noqa: ANN001, ANN201
    """The robot passes person i (d from its route, `foot` the nearest route point) on the far side keeping
    ROBOT_SOCIAL_GAP (the gap its moves keep), by edging at most SQUEEZE aside, with room from walls and everyone
    else there; not while they walk into its way (INTO_WAY)."""
    robot, q = s.robot[0], s.people[i]
    clear = robot.radius + q.radius + ROBOT_SOCIAL_GAP
    if d < 1e-6 or clear - d > SQUEEZE or into_route(q, foot, d) > INTO_WAY:
        return False
    return stands_clear(s, i, q.pos - (q.pos - foot) / d * clear)  # the robot's centre passing them


@jit
def on_route_ahead(s, seg, i, reach, distance):  # noqa: ANN001, ANN201
    """Person i stands within `reach` of the robot's route ahead of it (from the robot along the remaining
    waypoints of segment `seg` on, the first `distance` metres of it), or walks into that within INTO_WAY_LOOK s,
    ahead of the robot, and the robot cannot squeeze past them (squeezes_past)."""
    wps, a, q = s.waypoints, s.robot[0].pos, s.people[i].pos
    left = distance
    for j in range(seg + 1, wps.shape[0]):
        b = wps[j]
        length = abs(b - a)
        if length > 1e-9:
            along, d = project(q, a, b)
            foot = a + (b - a) / length * along
            into = into_route(s.people[i], foot, d)
            near = d < reach or (into > INTO_WAY and d - into * INTO_WAY_LOOK < reach)
            if along <= left and near and (along > 0.0 or j > seg + 1):
                # beside the leg, or off its end by a turn (stepped into the corner: it rounds the turn on the far
                past = j < wps.shape[0] - 1 or along < length - 1e-6  # side), not past its goal (it stops there)
                if not (past and squeezes_past(s, i, foot, d)):
                    return True
            left -= length
            if left <= 0.0:
                return False
        a = b
    return False


@jit
def in_way(s, i, distance, seg, cone):  # noqa: ANN001, ANN201
    """Person i in the robot's way within `distance` (person_in_way's rule for one person; seg: the route
    segment, -1 for the cone ahead)."""
    robot, policy, p = s.robot[0], s.policy[0], s.people[i]
    r = robot.pos
    if seg >= 0:
        return abs(p.pos - r) <= distance and on_route_ahead(s, seg, i, robot.radius + p.radius
                                                             + proxemics.WAY_MARGIN_SCRIPT, distance)
    # the way it is going: a built-in robot's direction of travel (a differential drive may face elsewhere
    # while it turns or edges aside), else where it last moved
    h = policy.heading if policy.has_heading and abs(policy.heading) > 0 else robot.heading
    return blocking(r.real, r.imag, h.real, h.imag, p.pos.real, p.pos.imag, robot.radius, p.radius, distance,
                    proxemics.WAY_MARGIN_SCRIPT, cone)


@jit
def person_in_way(s, distance, swept_only):  # noqa: ANN001, ANN201
    """Someone within `distance` (centres) ahead of the robot's direction of travel, in its way: in a cone
    ahead (to notice people coming), or (`swept_only`) only inside the corridor its body sweeps along its
    route's next `distance` metres (round its turns: someone beside the route past a corner is not in its way;
    nor is someone it passes by edging a little aside; straight ahead without a route), so that people who
    stepped aside do not keep a robot waiting "until clear"."""
    cone = -1.0 if swept_only else proxemics.FRONT_CONE_SCRIPT
    seg = route_segment(s) if swept_only else -1
    for i in range(s.people.shape[0]):  # noqa: SIM110 - numba compiles no generator
        if in_way(s, i, distance, seg, cone):
            return True
    return False


@jit
def gone_by(s, cue, finished):  # noqa: ANN001, ANN201
    """Whether the person a `let_pass` cue waits for has gone by: they came within HELD_UP_DISTANCE of the robot
    (or were in its way), are out of its way now (the corridor its body sweeps ahead, as wait_until_clear) and
    LET_PASS_AWAY farther from it than the closest they came: past it, across its way, or on ahead of it; or they
    stand at the end of their walk (`finished`): no longer coming, the robot would wait for them for ever (home_14
    of the new-request suite: she stopped at the front door 1.7 m from it and the run ended with the robot still
    waiting); or, having walked LET_PASS_WALKED since the cue fired, they have stood LET_PASS_STILL s (moving less
    than LET_PASS_STILL_REACH): they stopped there, off its way (home_16: the seeker stopped by the hider 2.7 m from
    it, never LET_PASS_AWAY farther than her closest, and the robot stood its whole 15 s with its way clear).
    From poses alone (the export's ROS node has no velocities, nor knows where anyone's walk ends: `finished` is
    False there)."""
    i = cue.lets_pass
    if i < 0 or i >= s.people.shape[0]:
        return True
    pos, t = s.people[i].pos, s.clock[0].t
    d = abs(pos - s.robot[0].pos)
    way = in_way(s, i, proxemics.HELD_UP_DISTANCE, route_segment(s), -1.0)
    if d <= proxemics.HELD_UP_DISTANCE or way:
        cue.pass_near = True
    cue.pass_closest = min(cue.pass_closest, d)
    if abs(pos - cue.pass_still_at) > LET_PASS_STILL_REACH:
        cue.pass_still_at, cue.pass_still_since = pos, t
    stopped = abs(pos - cue.pass_from) >= LET_PASS_WALKED and t - cue.pass_still_since >= LET_PASS_STILL
    return cue.pass_near and not way and (d >= cue.pass_closest + LET_PASS_AWAY or finished or stopped)


@jit
def holds(s, when, who, phrase, point, has_point, seconds, distance):  # noqa: ANN001, ANN201
    """Whether a trigger (or a gesture rule's condition) holds now."""
    if when in (START, ALWAYS):
        return True
    if when == AFTER:
        return s.clock[0].t >= seconds
    if when == AT_ENCOUNTER:
        return has_point and abs(point - s.robot[0].pos) <= distance
    if when == BLOCKED:
        return person_in_way(s, distance, False)
    for i in range(s.people.shape[0]):
        if who >= 0 and i != who:
            continue
        if when == HUMAN_SAYS:
            if s.people[i].gesture == phrase:
                return True
        elif when == HUMAN_FARTHER:
            if abs(s.people[i].pos - s.robot[0].pos) > distance:
                return True
        elif abs(s.people[i].pos - s.robot[0].pos) <= distance:  # HUMAN_WITHIN, NEAR_HUMAN
            return True
    return False


@jit
def log(script, t, c, event):  # noqa: ANN001, ANN201
    m = script.now[0].logged
    if m < script.log_t.shape[0]:
        script.log_t[m], script.log_cue[m], script.log_event[m] = t, c, event
    script.now[0].logged = m + 1


@jit
def play(s, script):  # noqa: ANN001, ANN201
    """Fire the cues whose trigger became true; then what the robot says now, whether it waits, its cruise
    speed."""
    t = s.clock[0].t
    now = script.now[0]
    for c in range(script.cues.shape[0]):
        cue = script.cues[c]
        true = holds(s, cue.when, cue.who, cue.phrase, cue.point, cue.has_point, cue.seconds, cue.distance)
        rising = true and not cue.was_true
        cue.was_true = true
        if not rising or (cue.once and cue.fired > 0):
            continue
        cue.fired += 1
        if cue.say != 0:
            cue.say_until = t + cue.hold
        if cue.pause != 0 and cue.lets_pass < 0:  # with let_pass, `wait` is the most it stands for them
            cue.wait_until = t + cue.pause
        cue.waiting_until_clear = cue.until_clear
        cue.letting_pass, cue.pass_near, cue.pass_closest = cue.lets_pass >= 0, False, math.inf
        if 0 <= cue.lets_pass < s.people.shape[0]:
            cue.pass_from, cue.pass_still_at = s.people[cue.lets_pass].pos, s.people[cue.lets_pass].pos
            cue.pass_still_since = t
        cue.pass_until = t + (cue.pause if cue.pause > 0 else LET_PASS_PATIENCE)
        cue.clear_since, cue.repeats = t, 0
        if not math.isnan(cue.speed):
            now.speed = cue.speed
        log(script, t, c, FIRED)
    say, wait, timed, letting = 0, False, False, -1
    for c in range(script.cues.shape[0]):
        cue = script.cues[c]
        if cue.say != 0 and t < cue.say_until:
            say = cue.say  # the latest cue in script order wins
        if t < cue.wait_until:
            wait = timed = True
        elif cue.waiting_until_clear:
            blocked = person_in_way(s, max(cue.distance, proxemics.HELD_UP_DISTANCE), True)
            cue.waiting_until_clear = blocked
            if blocked and t - cue.clear_since >= CLEAR_PATIENCE:
                if cue.repeats < CLEAR_REPEATS:  # ask again: a person who reacts only while the robot
                    cue.repeats += 1  # speaks gets another chance (a silent cue waits on as long)
                    cue.clear_since = t
                    if cue.say != 0:
                        cue.say_until = t + cue.hold
                        log(script, t, c, ASKED_AGAIN)
                else:
                    cue.waiting_until_clear = False
                    log(script, t, c, GAVE_UP)
            wait = wait or cue.waiting_until_clear
        if cue.letting_pass:  # stands (for no known time: pacing lets the person come) until they went by
            i = cue.lets_pass
            went = gone_by(s, cue, script.finished[i] if 0 <= i < script.finished.shape[0] else False)
            if went or t >= cue.pass_until:
                cue.letting_pass = False
                log(script, t, c, WENT_BY if went else GAVE_UP)
            wait = wait or cue.letting_pass
            if cue.letting_pass and letting < 0:
                letting = cue.lets_pass
    now.say, now.wait, now.timed, now.letting = say, wait, timed, letting


@jit
def rules_gesture(s, rules):  # noqa: ANN001, ANN201
    """The gesture of the first rule whose condition held within its last `duration` seconds (0: none)."""
    t = s.clock[0].t
    for r in range(rules.shape[0]):
        rule = rules[r]
        if holds(s, rule.when, -1, -1, rule.point, rule.has_point, 0.0, AT_NODE if rule.when == AT_ENCOUNTER
                 else rule.distance):
            rule.last_true = t
        if t - rule.last_true <= rule.duration:
            return rule.gesture
    return 0


@jit(inline=True)
def scripted_gesture(s, script):  # noqa: ANN001, ANN201
    """What the script shows now: the phrase of a cue (script.now, set by play), else the first gesture rule's."""
    say = script.now[0].say
    return say if say != 0 else rules_gesture(s, script.rules)


@jit
def play_gesture(s, script):  # noqa: ANN001, ANN201
    """One step of the script on a snapshot (a State, or Poses): the cues fire, and the gesture it shows."""
    play(s, script)
    return scripted_gesture(s, script)
