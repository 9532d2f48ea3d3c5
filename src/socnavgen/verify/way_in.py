"""Where a person walks into their first encounter (issue 25): the plan (paths.json) gives each person a way to
their encounter's node, path[0] ... node, and the simulated run must show them coming in that way. Criteria judge
what happens at the encounter (a meeting, a follow, a give-way), never how the person got there, so a worker who
left his aisle the other way and walked 15 m round to the back of the line "followed" (warehouse_03), and a patient
whose plan has her walk across the lobby towards the elevators, who stood at the bench until the robot called
her, was "intercepted" (hospital_06). Judged on every run with a plan, two facts per person whose path comes to
their encounter's node from somewhere else:

- `passes`: before they reach the encounter (within its `within` of the node), they pass each node of the way
  between, in order (within `way_reach`: the node's free disc, at least WAY_REACH);
- `walks`: a person the spec has walk (`otherwise: walk`) has walked (MOVED_DISTANCE from the start) before their
  tree turns to the robot (the trace's behavior state leaves "regular"), unless it turns at once (within STOP_HOLD
  of the start: called at the start, the reaction itself brings them in). A follower, a give-way or a blocker
  whose reaction takes them in from the start is that exception; a person standing (`otherwise: stand`) has no
  walk of their own before the reaction. Required where the spec states the walk (the person listed in
  `people`, `otherwise: walk`, as stage 1 writes it from the text: hospital_06's patient "gets up and heads across the lobby");
  a warning where the walk is only the default (the cards' specs state no people: their crowding and following
  people are walkers by the tree contract, every card template ending in REGULAR, held at their start by pacing
  until the robot comes into sight, and their card's text has them walk up to the robot only then).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass

import numpy as np

from socnavgen.bodies import PERSON_RADIUS, group_ring
from socnavgen.run.models import PathPlan
from socnavgen.run.spec import ScenarioSpec
from socnavgen.sim.trace import REGULAR_BEHAVIOR, Trace
from socnavgen.verify.models import Finding, Source, VerifySettings
from socnavgen.verify.thresholds import MOVED_DISTANCE, STOP_HOLD, WAY_REACH
from socnavgen.verify.windows import encounters_of

KIND = "way_in"


@dataclass(frozen=True)
class WayIn:
    """One person's planned way into their first encounter."""

    human: str
    encounter: str  # id
    node: str
    within: float  # m: at the encounter this close to its node
    nodes: tuple[str, ...]  # path[0] ... node
    points: tuple[tuple[float, float], ...]
    reach: tuple[float, ...]  # m: each node is passed this close (way_reach)
    walker: bool  # the spec has them walk when not reacting
    source: Source
    stated: bool = False  # the spec states that walk (they are listed in its `people`): `walks` is then required


def way_reach(clearance: float, members: int = 1) -> float:
    """How close a person passes a node of their way: anywhere in its free disc (its clearance, the free radius
    round it: across an aisle, over an open area) with a body at its edge, and at least WAY_REACH; a member of a
    group of `members` walks beside the others, up to the group's circle (bodies.group_ring) farther off (round 30:
    a pair turning a corner cut it 1.6 m from the node, 0.2 m beyond a lone walker's reach, "another way")."""
    return max(WAY_REACH, clearance + PERSON_RADIUS) + (group_ring(members) if members > 1 else 0.0)


def ways_in(plan: PathPlan, spec: ScenarioSpec, node_points: dict[str, tuple[float, float]],
            clearance: dict[str, float], *, authored: bool = True, source: Source = "paths") -> list[WayIn]:
    """Every person whose path comes to their first encounter's node (`spec`: spec.json's, or the one derived from
    the paths) from another node (a person who starts at it has no way in to judge). `clearance`: each node's free
    radius (m); `authored`: the spec is spec.json, whose `people` say who walks (a derived one says nothing)."""
    out: list[WayIn] = []
    groups = Counter(h.group_id for h in plan.humans if h.group_id >= 0)
    for h in plan.humans:
        found = encounters_of(spec, h.name)
        enc = found[0] if found else None
        node = enc.node if enc is not None else None
        if enc is None or node is None or node not in h.path or h.path.index(node) == 0:
            continue
        nodes = tuple(h.path[: h.path.index(node) + 1])
        if any(n not in node_points for n in nodes):
            continue
        walker = authored and spec.person(h.name).otherwise == "walk"
        stated = walker and h.name in spec.people  # spec.json writes every listed person's `otherwise` out
        out.append(WayIn(human=h.name, encounter=enc.id, node=node, within=enc.within, nodes=nodes,
                         points=tuple(node_points[n] for n in nodes),
                         reach=tuple(way_reach(clearance.get(n, 0.0), groups.get(h.group_id, 1)) for n in nodes), walker=walker, source=source,
                         stated=stated))
    return out


def _arrival(way: WayIn, trace: Trace, i: int) -> int:
    """The step the person reaches their encounter (within its `within` of the node); the last step when never."""
    pos = trace.humans[:, i, :2]
    hit = np.flatnonzero(np.hypot(*(pos - np.asarray(way.points[-1])).T) <= way.within)
    return int(hit[0]) if len(hit) else trace.steps - 1


def _missed(way: WayIn, trace: Trace, i: int, arrival: int) -> tuple[str, float, float] | None:
    """The first node between start and encounter not passed (within its reach, in order) by `arrival`: (node,
    closest distance before arrival, when), or None."""
    pos = trace.humans[: arrival + 1, i, :2]
    start = 0
    for node, point, reach in zip(way.nodes[1:-1], way.points[1:-1], way.reach[1:-1], strict=True):
        if math.dist(point, way.points[-1]) < way.within:  # inside the encounter's place: reached with it, or after
            continue
        d = np.hypot(*(pos[start:] - np.asarray(point)).T)
        hit = np.flatnonzero(d <= reach)
        if not len(hit):
            k = int(np.argmin(d)) if len(d) else 0
            return node, float(d[k]) if len(d) else float("inf"), float(trace.t[min(start + k, trace.steps - 1)])
        start += int(hit[0])
    return None


def _title(way: WayIn) -> str:
    return f"{way.human} comes to {way.node} ({way.encounter}) along their way {' -> '.join(way.nodes)}"


def judge_way_in(way: WayIn, trace: Trace, settings: VerifySettings) -> Finding:
    """The verdict on one person's way in, with what happened and who can fix it."""
    base = Finding(name=_title(way), kind=KIND, passed=True, evidence="", human=way.human, node=way.node,
                   source=way.source)
    if way.human not in trace.human_names or not trace.steps:
        return base.model_copy(update={"passed": False, "evidence": f"{way.human} is not in the trace",
                                       "blame": "paths", "stage": "paths",
                                       "blame_reason": "the trace has no such person"})
    i = trace.human_names.index(way.human)
    t = trace.t
    arrival = _arrival(way, trace, i)
    came = f"reached {way.encounter} at {t[arrival]:.1f} s" if arrival < trace.steps - 1 else \
        f"never reached {way.encounter}"
    turned = np.flatnonzero(trace.behavior_state[:, i] != REGULAR_BEHAVIOR)
    react = int(turned[0]) if len(turned) else None
    missed = _missed(way, trace, i, arrival)
    if missed is not None:
        node, closest, when = missed
        reach = way.reach[way.nodes.index(node)]
        early = react is not None and react < arrival and t[react] - t[0] > STOP_HOLD
        why = (f"{way.human} never came within {reach:.1f} m of {node} (closest {closest:.1f} m, at {when:.1f} s) "
               f"on the way {' -> '.join(way.nodes)} before the encounter ({came}): they came another way")
        if early:
            why += f"; their tree turned to the robot at {t[react]:.1f} s, before they had walked it"
            return base.model_copy(update={
                "passed": False, "evidence": why, "time": round(when, 3), "distance": round(closest, 2),
                "blame": "behaviors", "blame_human": way.human, "stage": "behaviors",
                "blame_reason": f"{way.human}'s reaction starts before {way.human} has walked {' -> '.join(way.nodes)} "
                                f"and takes them to {way.node} another way: let {way.human} walk the path to "
                                f"{way.node} first (the reaction gated on being there, or a trigger that holds only "
                                f"near it)"})
        return base.model_copy(update={
            "passed": False, "evidence": why, "time": round(when, 3), "distance": round(closest, 2),
            "blame": "paths", "stage": "paths",
            "blame_reason": f"plan {way.human}'s way to {way.node} along which they really walk (a way the "
                            f"simulated person takes: the shortest walkable one between its nodes)"})
    if way.walker and react is not None and t[react] - t[0] > STOP_HOLD:
        pos = trace.humans[: react + 1, i, :2]
        walked = float(np.hypot(*(pos - pos[0]).T).max())
        if walked < MOVED_DISTANCE:
            why = (f"{way.human} stood at their start {way.nodes[0]} (walked {walked:.2f} m) until their tree turned to "
                   f"the robot at {t[react]:.1f} s: the plan has them walk {' -> '.join(way.nodes)} into "
                   f"{way.encounter}, and they had not walked it when it began")
            return base.model_copy(update={
                "passed": False, "evidence": why, "time": round(float(t[react]), 3), "distance": round(walked, 2),
                "blame": "paths", "stage": "paths", "required": way.stated,
                "blame_reason": f"{way.human} was held at the start (paced to reach {way.node} with the robot) until "
                                f"the robot was already there: start {way.human} farther back along the way, so that "
                                f"they are walking it when the robot comes"})
    ok = f"{way.human} came along {' -> '.join(way.nodes)} and {came}"
    return base.model_copy(update={"evidence": ok, "time": round(float(t[arrival]), 3)})


def way_in_findings(ways: list[WayIn], trace: Trace, settings: VerifySettings) -> list[Finding]:
    """One finding per planned way in (a `walks` failure only warns where the spec does not state the walk)."""
    return [judge_way_in(way, trace, settings) for way in ways]
