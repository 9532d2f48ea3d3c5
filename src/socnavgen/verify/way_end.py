"""Where a follower ends (issue 25): a person who follows the robot for good (a latched follow, or one a follows_*
criterion judges to the end; following someone who follows the robot counts the same) ends where the robot ends.
When the robot's goal is inside a room (the part of the scene graph its doorways close off), the follower must end
in that room or in one of its doorways: the run goes on after the robot arrives while its followers come in to a spot
round its goal (sim.people.grace), but in a small room the spots in sight of the goal may lie through the doorway, so
a follower in the doorway counts as come in, and one still out in the hallway does not (home_09: the robot reached the
bedroom with one child in its doorway and the other still at the hallway's far end, and "both follow it into the
bedroom" passed). A goal in a space no doorway closes off (a warehouse floor) leaves nothing to judge.

Where a person is: at the scene-graph node nearest them (the graph's nodes stand for the places of the map)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import networkx as nx
import numpy as np

from socnavgen.run.models import PathPlan
from socnavgen.run.spec import ScenarioSpec
from socnavgen.sim.trace import Trace
from socnavgen.verify.models import Finding, Source

KIND = "ends_with_leader"
FOLLOWS = ("follows_robot", "follows_human")


@dataclass(frozen=True)
class RoomEnd:
    """A follower of the robot whose goal is inside a room."""

    human: str
    goal: str  # the robot's goal node
    room: frozenset[str]  # the room's nodes (doorways excluded)
    doors: frozenset[str]  # its doorways
    source: Source


def room_of(graph: nx.Graph, node: str, is_door: Any) -> tuple[frozenset[str], frozenset[str]] | None:
    """(the nodes of the room `node` is in, its doorways): `node`'s part of the graph with the doorways taken out;
    None when that part is everything but the doorways (no doorway closes it off) or `node` is a doorway."""
    if node not in graph or is_door(node):
        return None
    inside = graph.subgraph([n for n in graph if not is_door(n)])
    room = frozenset(nx.node_connected_component(inside, node))
    if len(room) == inside.number_of_nodes():
        return None
    return room, frozenset(d for n in room for d in graph.neighbors(n) if is_door(d))


def _leaders(spec: ScenarioSpec) -> dict[str, str]:
    """Whom each person follows for good: 'robot' or another person (a latched follow / follow_human, or one a
    follows_* criterion judges to the end); a follow that `lasts` a while ends, and the person goes on elsewhere."""
    judged = {c.human for c in spec.criteria if c.kind in FOLLOWS and c.human}
    out: dict[str, str] = {}
    for enc in spec.encounters:
        for p in enc.humans:
            if p.reaction not in ("follow", "follow_human") or not (p.latch or p.human in judged) or p.lasts is not None:
                continue
            leader = "robot" if p.reaction == "follow" else p.other
            if leader:
                out[p.human] = leader
    return out


def follows_robot_to_the_end(spec: ScenarioSpec, human: str) -> bool:
    """Whether `human` follows the robot for good, directly or behind others who do (a line behind the robot)."""
    leaders, seen, who = _leaders(spec), set(), human
    while who in leaders and who not in seen:
        seen.add(who)
        who = leaders[who]
        if who == "robot":
            return True
    return False


def room_ends(plan: PathPlan, spec: ScenarioSpec, graph: nx.Graph, node_type: Any,
              source: Source = "spec") -> list[RoomEnd]:
    """Every follower of the robot to the end, when the robot's goal is inside a room. `node_type(n)`: a node's type
    (location.places.type_matches with the family 'doorway' tells its doorways)."""
    from socnavgen.location.places import type_matches

    if not plan.robot:
        return []
    found = room_of(graph, plan.robot[-1], lambda n: type_matches(node_type(n), "doorway"))
    if found is None:
        return []
    room, doors = found
    return [RoomEnd(human=h.name, goal=plan.robot[-1], room=room, doors=doors, source=source)
            for h in plan.humans if follows_robot_to_the_end(spec, h.name)]


def judge_room_end(end: RoomEnd, trace: Trace, node_points: dict[str, tuple[float, float]],
                   goal_reached: bool) -> Finding:
    """The verdict on one follower's end place: in the robot's goal room or one of its doorways."""
    doors = "/".join(sorted(end.doors))
    base = Finding(name=f"{end.human} ends with the robot in the room of {end.goal} (or a doorway of it: {doors})", kind=KIND,
                   passed=True, evidence="", human=end.human, node=end.goal, source=end.source)
    if end.human not in trace.human_names or not trace.steps:
        return base.model_copy(update={"passed": False, "evidence": f"{end.human} is not in the trace",
                                       "blame": "paths", "stage": "paths", "blame_reason": "no such person"})
    if not goal_reached:
        return base.model_copy(update={"evidence": "the robot did not reach its goal: nothing to judge here"})
    p = trace.humans[-1, trace.human_names.index(end.human), :2]
    names = list(node_points)
    dist = np.hypot(*(np.asarray([node_points[n] for n in names]) - p).T)
    at = names[int(np.argmin(dist))]
    t = float(trace.t[-1])
    gap = float(np.hypot(*(trace.robot[-1, :2] - p)))
    if at in end.room or at in end.doors:
        return base.model_copy(update={"evidence": f"{end.human} ended at {at} when the run ended ({t:.1f} s), "
                                                   f"{gap:.1f} m from the robot", "time": round(t, 3)})
    return base.model_copy(update={
        "passed": False, "time": round(t, 3), "distance": round(gap, 2),
        "evidence": f"when the run ended ({t:.1f} s, the robot at its goal {end.goal}) {end.human}, who follows it, "
                    f"was at {at} ({gap:.1f} m from the robot), outside the room of {end.goal} and its doorways "
                    f"({', '.join(sorted(end.room | end.doors))})",
        "blame": "robot_script", "stage": None,
        "blame_reason": f"the robot drove into the room of {end.goal} leaving {end.human} behind outside: let it wait "
                        f"for its followers before the room's doorway (a human_farther cue for {end.human}), so "
                        f"they come in with it"})


def room_end_findings(ends: list[RoomEnd], trace: Trace, node_points: dict[str, tuple[float, float]],
                      goal_reached: bool) -> list[Finding]:
    """One finding per follower whose leader's goal is inside a room."""
    return [judge_room_end(e, trace, node_points, goal_reached) for e in ends]
