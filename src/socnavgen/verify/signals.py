"""The named per-step signals of a simulation trace that acceptance criteria (STL formulas) talk about.

One registry of signal kinds (a name pattern, its unit, what it means, how to compute it); signals are
computed on demand and cached, so a formula pays only for what it names. Booleans are 0/1 signals,
tested in formulas as `x > 0.5` (their robustness is then +-0.5). Every distance is in metres, centre
to centre unless the name says `gap` (sim/contact.py is the one definition of gap and collision).
docs/verify.md lists the same table.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, TypeVar

import numpy as np

from socnavgen import proxemics
from socnavgen.bodies import PERSON_GOAL_RADIUS
from socnavgen.bt.library import HUMAN_GESTURES, LIBRARY, REACTION_NODES, ROBOT_GESTURES
from socnavgen.sim import contact
from socnavgen.sim.arrival import short_of_goal_steps
from socnavgen.sim.social_metrics import arrival_row
from socnavgen.sim.trace import VX, VY, YAW, Trace
from socnavgen.verify.held_up import holding_up
from socnavgen.verify.idle import idle_seconds
from socnavgen.verify.passing import (  # aside: re-exported (its home is verify/passing.py)
    aside,
    kept_aside,
    parted_for_robot,
)
from socnavgen.verify.perceived import perceived, seen_hold
from socnavgen.verify.route import lag_along, progress_events, route_progress
from socnavgen.verify.runs import lasting, latched, runlength
from socnavgen.verify.thresholds import (
    AHEAD_HALF_ANGLE,
    ASIDE_DISTANCE,
    FAR,
    MOVED_DISTANCE,
    PROGRESS_STEP,
    STILL_SPEED,
    STOP_HOLD,
    STOP_SPEED,
    WALK_SPEED,
)
from socnavgen.verify.ways import start_apart, walkable

# Reactions judged by what the human physically does rather than by the nodes that implement them
# (bt.library.REACTION_NODES is the one home of those): stopping is standing still STOP_HOLD s after having walked
# (seen standing that long less the window speeds are seen over: verify/perceived.py; a slow step is no stop),
# saying is showing a gesture, giving way is being out of the robot's way having moved off its route (`aside`: a
# GiveWaytoRobot node that ran while the body stayed in the way is no giving way). Every other reaction counts
# on the steps one of its nodes executes.
PHYSICAL_REACTIONS = ("stop", "wait_then_go", "say", "give_way")
WALKING_REACTIONS = ("walk_past", "follow", "follow_human", "join", "avoid")  # their node counts while the body walks


def phrase_id(phrase: str) -> str:
    """'EXCUSE ME' -> 'excuse_me' (the form phrases take in signal names)."""
    return phrase.strip().lower().replace(" ", "_")


ROBOT_PHRASES = {phrase_id(w): code for code, w in ROBOT_GESTURES.items() if code}
HUMAN_PHRASES = {phrase_id(w): code for code, w in HUMAN_GESTURES.items() if code}


class UnknownSignal(ValueError):
    """A formula names a signal that does not exist for this run."""

_T = TypeVar("_T")


@dataclass(frozen=True)
class SignalKind:
    pattern: str  # regular expression over the whole name, groups passed to `build`
    shown: str  # the pattern as documented, e.g. dist_<human>
    unit: str
    meaning: str
    build: Callable[[Signals, re.Match], np.ndarray]
    listed: bool = True  # in the prompts' list of signals (False: the verifier's own, no_deadlock's `idle`)


class Signals:
    """The signals of one trace. `places`: named world points (encounter ids, `goal`, `node_<id>`)."""

    def __init__(self, trace: Trace, *, world=None, places: dict[str, tuple[float, float]] | None = None,  # noqa: ANN001
                 node_points: dict[str, tuple[float, float]] | None = None, goal_radius: float = 0.5,
                 world_factory: Callable[[], object] | None = None,
                 windows: Callable[[Signals, str, str], np.ndarray] | None = None) -> None:
        self.trace = trace
        self._windows = windows  # verify/windows.encounter_window with the run's spec: during_<human>_<encounter>
        self.world = world
        self._world_factory = world_factory  # builds the World only if a formula needs line of sight
        self.places = dict(places or {})
        if trace.robot_goal is not None and "goal" not in self.places:
            self.places["goal"] = (trace.robot_goal[0], trace.robot_goal[1])
        for node, point in (node_points or {}).items():
            self.places.setdefault(f"node_{node}", point)
        self.goal_radius = goal_radius
        self._cache: dict[str, np.ndarray] = {}
        self._los: np.ndarray | None = None
        self._kept: dict[object, Any] = {}  # geometry several signals, evidence and blame share

    def keep(self, key: object, build: Callable[[], _T]) -> _T:
        if key not in self._kept:
            self._kept[key] = build()
        return self._kept[key]

    @property
    def t(self) -> np.ndarray:
        return np.asarray(self.trace.t, dtype=float)

    # -- lookup --------------------------------------------------------------------------------
    def get(self, name: str) -> np.ndarray:
        """The (T,) float signal `name`; UnknownSignal with what exists when there is no such signal."""
        if name not in self._cache:
            found = _kind_of(name)
            if found is None:
                raise UnknownSignal(f"unknown signal {name!r}; signals are: "
                                    + ", ".join(k.shown for k in SIGNAL_KINDS) + " (docs/verify.md)")
            kind, match = found
            self._cache[name] = np.asarray(kind.build(self, match), dtype=float)
        return self._cache[name]

    def human(self, name: str) -> int:
        if name not in self.trace.human_names:
            raise UnknownSignal(f"{name} is not in this run (humans: {', '.join(self.trace.human_names) or 'none'})")
        return self.trace.human_names.index(name)

    def place(self, name: str) -> np.ndarray:
        if name not in self.places:
            raise UnknownSignal(f"unknown place {name!r} (places: {', '.join(sorted(self.places)) or 'none'}; "
                                "encounter ids, goal, node_<scene-graph id>)")
        return np.asarray(self.places[name], dtype=float)

    # -- geometry helpers ------------------------------------------------------------------------
    def pos(self, who: str) -> np.ndarray:
        if who == "robot":
            return self.trace.robot[:, :2]
        if who.startswith("mid_"):
            return 0.5 * (self.trace.robot[:, :2] + self.pos(who[4:]))
        return self.trace.humans[:, self.human(who), :2]

    def speed(self, who: str) -> np.ndarray:
        """(T,) speed as a person watching sees it (verify/perceived.py): every moving / stopping judgement reads it."""
        def build() -> np.ndarray:
            state = self.trace.robot if who == "robot" else self.trace.humans[:, self.human(who)]
            vx, vy = state[:, VX], state[:, VY]
            return perceived(np.sqrt(vx * vx + vy * vy), self.trace.dt)  # np.linalg.norm(state[:, VX:VY + 1], axis=1)

        return self.keep(("speed", who), build)

    def distances(self) -> np.ndarray:
        """(T, H) robot-human centre distances (contact.trace_distances), computed once."""
        return self.keep("distances", lambda: contact.trace_distances(self.trace))

    def gaps(self) -> np.ndarray:
        """(T, H) robot-human surface gaps (contact.trace_gaps: the centre distances minus both radii)."""
        radii = float(self.trace.robot_radius) + np.asarray(self.trace.human_radii, dtype=float).reshape(1, -1)
        return self.keep("gaps", lambda: self.distances() - radii)

    def people_gaps(self) -> tuple[np.ndarray, list[tuple[int, int]]]:
        """contact.people_gaps of the trace ((T, P) person-person gaps and their pairs), computed once."""
        return self.keep("people_gaps", lambda: contact.people_gaps(self.trace))

    def contacts(self) -> contact.ContactSummary:
        """contact.summarize of the trace, computed once."""
        return self.keep("contacts", lambda: contact.summarize(self.trace, gaps=self.gaps()
                                                                if self.trace.humans.ndim == 3 else None))

    def line_of_sight(self) -> np.ndarray:
        """(T, H) 1 where the robot and each human see each other (walls of the occupancy map)."""
        if self._los is None:
            self.need_world("line of sight")
            robot = self.trace.robot[:, 0] + 1j * self.trace.robot[:, 1]
            humans = self.trace.humans[:, :, 0] + 1j * self.trace.humans[:, :, 1]
            self._los = self.world.segments_clear(robot[:, None], humans) \
                if humans.shape[1] else np.zeros((self.trace.steps, 0), dtype=bool)
        return self._los

    def _ways(self, along: str) -> np.ndarray:
        """(T, H) 1 where each human is in the robot's way (proxemics.in_way, WAY_MARGIN_VERIFY) along its heading
        (`along` = "heading") or along its route's direction ("route"; 0 where the robot has no route)."""
        def build() -> np.ndarray:
            robot, humans = self.trace.robot, self.trace.humans
            if along == "heading":
                hx, hy = np.cos(robot[:, YAW]), np.sin(robot[:, YAW])
            else:
                hx, hy = self.route()[1].T
            way = proxemics.in_way(robot[:, 0:1], robot[:, 1:2], hx[:, None], hy[:, None], humans[:, :, 0],
                                   humans[:, :, 1], float(self.trace.robot_radius),
                                   np.asarray(self.trace.human_radii, dtype=float).reshape(1, -1),
                                   proxemics.WAY_MARGIN_VERIFY)
            return way if along == "heading" else way & ((hx != 0) | (hy != 0))[:, None]

        return self.keep(("ways", along), build)

    def in_way(self, i: int) -> np.ndarray:
        """1 where human i is ahead of the robot (along its heading) inside its swept corridor."""
        return self._ways("heading")[:, i]

    def route(self) -> tuple[np.ndarray, np.ndarray]:
        """(progress (T,) m, tangent (T, 2)) of the robot along its waypoints (verify/route.py), computed once."""
        def build() -> tuple[np.ndarray, np.ndarray]:
            points = list(self.trace.robot_waypoints) or (
                [tuple(self.trace.robot[0, :2]), self.places["goal"]] if "goal" in self.places and
                self.trace.steps else [])
            return route_progress(self.trace.robot[:, :2], points)

        return self.keep("route", build)

    def holding_up(self) -> np.ndarray:
        """(T, H) 1 where a human holds the robot up: in its way (heading, route leg, route ahead round a bend, or
        its planned way round walls) within proxemics.HELD_UP_DISTANCE (verify/held_up.py), computed once."""
        return self.keep("holding_up", lambda: holding_up(self))

    def blocked(self) -> np.ndarray:
        """1 where some human holds the robot up (holding_up)."""
        return self.keep("blocked", lambda: contact.row_any(self.holding_up()))

    def need_world(self, what: str) -> object:
        if self.world is None and self._world_factory is not None:
            self.world = self._world_factory()
        if self.world is None:
            raise UnknownSignal(f"{what} needs the run's location (map)")
        return self.world


# ---- builders ------------------------------------------------------------------------------------
def _dist(s: Signals, m: re.Match) -> np.ndarray:
    return s.distances()[:, s.human(m[1])]


def _gap(s: Signals, m: re.Match) -> np.ndarray:
    return s.gaps()[:, s.human(m[1])]


def _gap_min(s: Signals, m: re.Match) -> np.ndarray:
    if not s.trace.human_names:
        return np.full(s.trace.steps, FAR)
    return contact.row_min(s.gaps())


def _pgap(s: Signals, m: re.Match) -> np.ndarray:
    gaps, pairs = s.people_gaps()
    cols = [c for c, pair in enumerate(pairs) if m[1] is None or s.human(m[1]) in pair]
    return contact.row_min(gaps[:, cols]) if cols else np.full(s.trace.steps, FAR)


def _speed(s: Signals, m: re.Match) -> np.ndarray:
    who = m[1]
    if who != "robot":
        s.human(who)
    return s.speed(who)


def _robot_still(s: Signals, m: re.Match) -> np.ndarray:
    return s.speed("robot") < STILL_SPEED


def robot_holds(s: Signals) -> np.ndarray:
    """(T,) bool: the robot does not advance along its route, as seen (its progress along it grows slower than
    STILL_SPEED): standing, or stepping aside or back for someone during a wait (sim.robot.wait_spot: a plain wait
    steps aside for someone coming past; round 29's warehouse_21 and warehouse_17: stops broken by that step)."""
    progress = s.route()[0]
    rate = np.gradient(progress, s.t) if len(progress) > 1 else np.zeros(len(progress))
    return (s.get("robot_still") > 0.5) | (perceived(rate, s.trace.dt) < STILL_SPEED)  # still, or not advancing


def _stalled(s: Signals, m: re.Match) -> np.ndarray:
    return runlength(s.speed("robot") < STILL_SPEED, s.trace.dt)


def _deadlock(s: Signals, m: re.Match) -> np.ndarray:
    blocked = s.blocked()
    if not blocked.any():  # nobody ever holds the robot up: no need to follow its route
        return np.zeros(s.trace.steps)
    at_goal = np.zeros(s.trace.steps, dtype=bool)
    if "goal" in s.places:
        at_goal = contact.lengths(s.pos("robot") - s.place("goal")) <= s.goal_radius
    at_goal[arrival_row(s.trace):] = True  # arrived: it stands while its followers come in (sim.people.grace)
    stuck = ~progress_events(s.route()[0], PROGRESS_STEP)
    return runlength(stuck & blocked & ~at_goal, s.trace.dt)


def _short_of_goal(s: Signals, m: re.Match) -> np.ndarray:
    """1 where the robot stands short of its goal at a social distance from someone standing there
    (proxemics.short_of_goal, the simulator's rule: sim.arrival)."""
    if "goal" not in s.places:
        return np.zeros(s.trace.steps)
    world = s.world if s.world is not None or s._world_factory is None else s.need_world("line of sight")
    return short_of_goal_steps(s.trace, s.places["goal"], world).astype(float)


def _route_done(s: Signals, m: re.Match) -> np.ndarray:
    """1 from the step the robot has come within proxemics.OCCUPIED_REACH of each intermediate waypoint in turn
    (the robots skip an occupied one that close); routes without one: always 1. Sequential, so a round trip
    [A, B, A] is done only on the way back, whatever the route's legs overlap."""
    points = np.asarray(list(s.trace.robot_waypoints), dtype=float).reshape(-1, 2)
    done = np.zeros(s.trace.steps)
    at = 0
    robot = s.pos("robot")
    for point in points[1:-1]:
        near = np.flatnonzero(contact.lengths(robot[at:] - point) <= proxemics.OCCUPIED_REACH)
        if not len(near):
            return done
        at += int(near[0])
    done[at:] = 1.0
    return done


def _progress(s: Signals, m: re.Match) -> np.ndarray:
    return np.maximum.accumulate(s.route()[0]) if s.trace.steps else np.zeros(0)


def _phrase(table: dict[str, int], word: str, who: str) -> int:
    if word not in table:
        raise UnknownSignal(f"{who} has no phrase {word!r} (phrases: {', '.join(sorted(table))})")
    return table[word]


def _robot_says(s: Signals, m: re.Match) -> np.ndarray:
    says = np.asarray(s.trace.robot_gesture) == _phrase(ROBOT_PHRASES, m[2], "the robot")
    return latched(says) if m[1] == "said" else says


def _human_says(s: Signals, m: re.Match) -> np.ndarray:
    says = np.asarray(s.trace.human_gesture[:, s.human(m[1])]) == _phrase(HUMAN_PHRASES, m[3], m[1])
    return latched(says) if m[2] == "said" else says


def _los(s: Signals, m: re.Match) -> np.ndarray:
    return s.line_of_sight()[:, s.human(m[1])]


def _ahead(s: Signals, m: re.Match) -> np.ndarray:
    i = s.human(m[1])
    rel = s.trace.robot[:, :2] - s.trace.humans[:, i, :2]
    bearing = np.arctan2(rel[:, 1], rel[:, 0]) - s.trace.humans[:, i, YAW]
    off = np.abs((bearing + math.pi) % (2 * math.pi) - math.pi)
    return off <= math.radians(AHEAD_HALF_ANGLE)


def _inway(s: Signals, m: re.Match) -> np.ndarray:
    return s.in_way(s.human(m[1]))


def _library_node(name: str, kind: str) -> str:
    found = next((n for n, spec in LIBRARY.items() if n.lower() == name and spec.kind == kind), None)
    if found is None:
        names = sorted(n.lower() for n, spec in LIBRARY.items() if spec.kind == kind)
        raise UnknownSignal(f"no library {kind} {name!r} ({', '.join(names)})")
    return found


def _exec(s: Signals, m: re.Match) -> np.ndarray:
    return s.trace.executed(s.human(m[1]), _library_node(m[2], "action"))


def _holds(s: Signals, m: re.Match) -> np.ndarray:
    return s.trace.fired(s.human(m[1]), _library_node(m[2], "condition"))


def _to_place(s: Signals, m: re.Match) -> np.ndarray:
    return contact.lengths(s.pos(m[1]) - s.place(m[2]))


def _spread(s: Signals, m: re.Match) -> np.ndarray:
    names = m[1].split("_")
    idx = [s.human(n) for n in names]
    pos = s.trace.humans[:, :, :2]
    pairs = [np.where(parted_for_robot(s, a, b), 0.0, contact.lengths(pos[:, a] - pos[:, b]))
             for a, b in itertools.combinations(idx, 2)]  # not while they part to let the robot through
    return np.max(np.stack(pairs, axis=1), axis=1)


def _closer(s: Signals, m: re.Match) -> np.ndarray:
    """How much closer than at the start: robot-human distance (from how far apart they start along the way one
    would walk to the other: verify/ways.start_apart), or the robot's / a human's distance to a place."""
    values = s.get(f"dist_{m[1]}" if m[1] else f"{m[2]}_to_{m[3]}")
    if not len(values):
        return values
    return (start_apart(s, m[1]) if m[1] else values[0]) - values


def _aside(s: Signals, m: re.Match) -> np.ndarray:  # kept out of the way until the robot got past (verify/passing.py)
    return kept_aside(s, m[1], aside(s, m[1]))


def _way(s: Signals, m: re.Match) -> np.ndarray:
    return walkable(s, m[2] or "robot", m[1])


def moved(s: Signals, human: str) -> np.ndarray:
    """1 from the first step the human is MOVED_DISTANCE from where it started."""
    p = s.pos(human)
    return latched(contact.lengths(p - p[:1]) >= MOVED_DISTANCE)


def reaction_evidence(s: Signals, human: str, reaction: str, says: str | None = None) -> np.ndarray:
    """(T,) bool: steps showing `human` performing the spec reaction: physical for PHYSICAL_REACTIONS,
    else executing one of its bt.library.REACTION_NODES actions."""
    i = s.human(human)
    if reaction in ("stop", "wait_then_go"):
        hold = seen_hold(STOP_HOLD, s.trace.dt)
        return lasting((s.speed(human) < STOP_SPEED) & (moved(s, human) > 0.5), hold, s.trace.dt)
    if reaction == "give_way":
        return s.get(f"aside_{human}") > 0.5
    if reaction == "say":
        gest = np.asarray(s.trace.human_gesture[:, i])
        return gest == HUMAN_PHRASES[phrase_id(says)] if says else gest != 0
    nodes = REACTION_NODES.get(reaction)
    if nodes is None:
        raise UnknownSignal(f"unknown reaction {reaction!r} ({', '.join(REACTION_NODES)})")
    out = np.zeros(s.trace.steps, dtype=bool)
    for node in nodes:
        out |= s.trace.executed(i, node)
    if reaction in WALKING_REACTIONS:  # the node runs and the body walks (a RegularNav that stands is no walking)
        out &= s.speed(human) > WALK_SPEED
    return out


def _react(s: Signals, m: re.Match) -> np.ndarray:
    return reaction_evidence(s, m[1], m[2])


def _during(s: Signals, m: re.Match) -> np.ndarray:
    if s._windows is None:
        raise UnknownSignal(f"{m[0]}: encounter windows need the run's spec")
    return s._windows(s, m[1], m[2])


_H = r"(human[1-9][0-9]{0,2})"
SIGNAL_KINDS: tuple[SignalKind, ...] = (
    SignalKind(rf"dist_{_H}", "dist_<human>", "m", "robot-human centre distance", _dist),
    SignalKind(rf"gap_{_H}", "gap_<human>", "m", "robot-human surface gap (negative: overlap)", _gap),
    SignalKind(r"gap_min", "gap_min", "m", "smallest robot-human gap over all humans", _gap_min),
    SignalKind(rf"pgap_(?:min|{_H})", "pgap_min, pgap_<human>", "m", "smallest person-person gap (of that human)", _pgap),
    SignalKind(rf"speed_(robot|{_H[1:-1]})", "speed_robot, speed_<human>", "m/s", "speed", _speed),
    SignalKind(r"robot_still", "robot_still", "0/1", f"robot speed below {STILL_SPEED} m/s", _robot_still),
    SignalKind(r"robot_holds", "robot_holds", "0/1", "the robot does not advance along its route (standing, or "
               "stepping aside for someone during a wait)", lambda s, m: robot_holds(s), listed=False),
    SignalKind(r"stalled", "stalled", "s", "how long the robot has been standing still, continuously", _stalled),
    SignalKind(r"progress", "progress", "m", "how far along its route the robot has come (best so far)", _progress),
    SignalKind(r"route_done", "route_done", "0/1", "the robot has come near every waypoint of its route but the last, "
               "in turn: a round trip's goal counts only on the way back", _route_done),
    SignalKind(r"short_of_goal", "short_of_goal", "0/1", "the robot stands within "
               f"{proxemics.GOAL_STOP_GAP + proxemics.GOAL_STOP_SLACK:g} m (gap) of someone standing on or next to its "
               "goal (a robot at the goal would be in their personal space), near the goal: it has arrived",
               _short_of_goal),
    SignalKind(r"deadlock", "deadlock", "s", f"how long the robot has made no progress along its route (less than "
               f"{PROGRESS_STEP:g} m) with someone in its way within {proxemics.HELD_UP_DISTANCE:g} m (not at its "
               f"goal), continuously: standing still or jittering in place", _deadlock),
    SignalKind(r"idle", "idle", "s", "how long the robot has got nowhere along its route, its way clear, no cue asking it to "
               "wait, short of its goal (verify/idle.py)", lambda s, m: idle_seconds(s), listed=False),
    SignalKind(r"robot_(says|said)_([a-z_]+)", "robot_says_<phrase>, robot_said_<phrase>", "0/1",
               "the robot makes the phrase now / has made it at some time so far (excuse_me, follow_me, wait, "
               "proceed, acknowledged)", _robot_says),
    SignalKind(rf"{_H}_(says|said)_([a-z_]+)", "<human>_says_<phrase>, <human>_said_<phrase>", "0/1",
               "the human makes the phrase now / has made it so far (wait, proceed, excuse_me)", _human_says),
    SignalKind(rf"los_{_H}", "los_<human>", "0/1", "line of sight between robot and human (map walls)", _los),
    SignalKind(rf"ahead_{_H}", "ahead_<human>", "0/1", f"the robot is ahead of the human, within "
               f"{AHEAD_HALF_ANGLE:g} degrees of its heading", _ahead),
    SignalKind(rf"inway_{_H}", "inway_<human>", "0/1", "the human is ahead of the robot, in its swept corridor",
               _inway),
    SignalKind(rf"exec_{_H}_([a-z]+)", "exec_<human>_<action>", "0/1",
               "the human's tree executes this library action (lower case, e.g. exec_human1_givewaytorobot)", _exec),
    SignalKind(rf"holds_{_H}_([a-z]+)", "holds_<human>_<condition>", "0/1",
               "this library condition returned SUCCESS for the human (e.g. holds_human1_robotsays)", _holds),
    SignalKind(rf"(robot|{_H[1:-1]}|mid_{_H[1:-1]})_to_([a-z][a-z0-9_]*)",
               "robot_to_<place>, <human>_to_<place>, mid_<human>_to_<place>", "m",
               "distance of the robot / the human / the robot-human midpoint to a place: an encounter id (its "
               f"node), goal, or node_<scene-graph id> (a person walking to a node stops up to {PERSON_GOAL_RADIUS:g} m "
               "short of it)", _to_place),
    SignalKind(rf"spread_({_H[1:-1]}(?:_{_H[1:-1]})+)", "spread_<human>_<human>[_...]", "m",
               "largest distance between any two of these humans (group spread), "
               "not counting two who part to let the robot through (it is between them, or one gives way)", _spread),
    SignalKind(rf"moved_{_H}", "moved_<human>", "0/1", f"the human has walked {MOVED_DISTANCE} m from its start",
               lambda s, m: moved(s, m[1])),
    SignalKind(rf"closer_(?:{_H}|(robot|{_H[1:-1]})_to_([a-z][a-z0-9_]*))",
               "closer_<human>, closer_robot_to_<place>, closer_<human>_to_<place>", "m",
               "how much closer than at the start: robot and human (apart at the start along the walkable way), or "
               "the robot / the human and a place", _closer),
    SignalKind(rf"aside_{_H}", "aside_<human>", "0/1", f"the human is out of the robot's way, having moved "
               f"{ASIDE_DISTANCE:g} m from where it last stood in it, and stays out until the robot got past", _aside),
    SignalKind(rf"way_{_H}(?:_{_H})?", "way_<human>, way_<human>_<human>", "m", "walkable robot-human (or "
               "human-human) distance along the map's free space, never through a wall (straight in sight)", _way),
    SignalKind(rf"lag_{_H}", "lag_<human>", "m", "how far the human is behind the robot along the way it drives "
               "(its route's direction there; negative: ahead of it)", lambda s, m: lag_along(s.pos("robot"), s.pos(m[1]), s.route()[1]),
               listed=False),
    SignalKind(rf"react_{_H}_([a-z_]+)", "react_<human>_<reaction>", "0/1",
               "evidence of a spec reaction: its library actions executing (bt.library.REACTION_NODES); stop, "
               f"wait_then_go: slower than 0.1 m/s for {STOP_HOLD:g} s after having walked; say: showing a gesture; give_way: aside_<human>; "
               f"walk_past, follow, follow_human, join, avoid: their nodes while faster than {WALK_SPEED:g} m/s",
               _react),
    SignalKind(rf"during_{_H}_([a-z][a-z0-9_]*)", "during_<human>_<encounter>", "0/1", "inside the window of the "
               "human's encounter (verify/windows.py: from when the two are together at its place, after the one "
               "before it ended, until the next one opens)", _during),
)


@lru_cache(maxsize=4096)
def _kind_of(name: str) -> tuple[SignalKind, re.Match] | None:
    """The kind a signal name belongs to, with its match (names repeat on every trace of a campaign)."""
    for kind in SIGNAL_KINDS:
        match = re.fullmatch(kind.pattern, name)
        if match:
            return kind, match
    return None
