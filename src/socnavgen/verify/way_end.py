"""Where a person ends who goes into a room (issue 25): a person whose way ends in a room or an elevator car - a place
behind a door - ends inside it, on its floor behind the door.

Two kinds of people go in: a follower of the robot to the end (a latched follow, or one a follows_* criterion judges
to the end; following someone who follows the robot counts the same) when the robot's goal is in a room: the run goes
on after the robot arrives while its followers come in to a spot round its goal (sim.people.grace); and a walker whose
path ends in a room and whose spec leaves them walking it to the end (no part that holds them for good, not standing
by plan: walks_to_the_end) into a room with one door. Judged at the end of the run; a person in the doorway or out in the hallway is not inside
(home_09: the robot reached the bedroom with both children on the hallway side of its doorway, and "both follow it
into the bedroom" passed; hospital_01 and hospital_27: the visitors and porters sent into the elevator car, one ended
in its door, another outside in the lobby, and nothing judged it).

A room: a node's part of the scene graph with the doorways taken out - doorway nodes and door edges (type words of
the doorway family, location.places) - when that is not the whole graph (a goal in a space no doorway closes off,
a warehouse floor, leaves nothing to judge). Inside: on the map, the centre in sight of a node of the room with no
doorway between them (sim.people.spots.through_door: the one test of "behind a doorway", the one that keeps the
simulated people's spots in the room; the centre past the door's narrowest point); without a map, at a node of the
room (the nearest one). A follower at the door (nearest a node of the room or of its doorways) ends with the robot
only when the room is full - no spot left in it for them, the others and the robot standing where they are
(sim.people.spots.room_left, the spots the simulated people take): a guide leading a patient to an elevator fills
the car and she stands at its door (hospital_09); home_09's children at the door of a roomy bedroom fail. (A body
whose centre is in but part of it still in a car's door passes: hospital_01's second visitor; the simulator's
walkers into an empty car stop as far in - hospital_22 - and a stricter test waits for them to go wholly in.)"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import networkx as nx
import numpy as np

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.run.models import PathPlan
from socnavgen.run.spec import HumanPart, ScenarioSpec
from socnavgen.sim.trace import Trace
from socnavgen.verify.models import Finding, Source
from socnavgen.verify.thresholds import MOVED_DISTANCE

KIND = "ends_with_leader"
FOLLOWS = ("follows_robot", "follows_human")
ENDING = ("walk_past", "join", "wait_then_go")  # reactions that end by themselves (then the person walks on)
COMING_SECONDS = 3.0  # s: a person who came MOVED_DISTANCE nearer the room's node in the run's last seconds was
# still walking in when it ended


@dataclass(frozen=True)
class RoomEnd:
    """A person whose way ends in a room: a follower of the robot whose goal is there, or a walker whose path is."""

    human: str
    goal: str  # the node the way ends at: the robot's goal (a follower), the person's path's last node (a walker)
    room: frozenset[str]  # the room's nodes (doorways excluded)
    doors: frozenset[str]  # its doorways (the doorway nodes, or the nodes across its door edges)
    source: Source
    follows: bool = True  # follows the robot in (else walks in on their own path)


def room_of(graph: nx.Graph, node: str, is_door: Any,
            is_door_edge: Callable[[str, str], bool] | None = None) -> tuple[frozenset[str], frozenset[str]] | None:
    """(the nodes of the room `node` is in, its doorways): `node`'s part of the graph with the doorway nodes and the
    door edges taken out; None when that part is everything but the doorways (no doorway closes it off) or `node` is
    a doorway. The doorways of a door edge are the nodes across it (an elevator car's lobby node)."""
    if node not in graph or is_door(node):
        return None
    kept = [n for n in graph if not is_door(n)]
    inside = nx.Graph(graph.subgraph(kept))
    if is_door_edge is not None:
        inside.remove_edges_from([(u, v) for u, v in list(inside.edges) if is_door_edge(u, v)])
    room = frozenset(nx.node_connected_component(inside, node))
    if len(room) == len(kept):
        return None
    doors = frozenset(d for n in room for d in graph.neighbors(n)
                      if d not in room and (is_door(d) or (is_door_edge is not None and is_door_edge(n, d))))
    return room, doors


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


def _ends(part: HumanPart) -> bool:
    """The reaction ends and the person walks on: it `lasts` a while, ends on a phrase (`until`), ends by itself
    (ENDING), or gives way while the robot is in the way (not latched: stepping aside for good)."""
    return part.lasts is not None or part.until is not None or part.reaction in ENDING or \
        (part.reaction == "give_way" and not part.latch)


def walks_to_the_end(spec: ScenarioSpec, human: str) -> bool:
    """Whether the spec leaves `human` walking their path to its end: every reaction of theirs ends (a stop, a block,
    a follow for good ... may hold them anywhere: their criteria judge where), and they walk it - by default, or,
    standing by plan (`otherwise: stand`), once a latched walk sets them going for good (hospital_27's porters, held
    at the bed until the robot says PROCEED)."""
    parts = [p for e in spec.encounters for p in e.humans if p.human == human]
    if not all(_ends(p) for p in parts):
        return False
    person = spec.people.get(human)
    if person is None or person.otherwise != "stand":
        return True
    return any(p.reaction in ("walk_past", "join") and p.latch and p.lasts is None and p.until is None for p in parts)


def room_ends(plan: PathPlan, spec: ScenarioSpec, graph: nx.Graph, node_type: Any, source: Source = "spec",
              edge_type: Callable[[str, str], str] | None = None) -> list[RoomEnd]:
    """Every person whose way ends in a room: the robot's followers to the end when its goal is in one, and the
    walkers to the end of a path that goes into one behind one door (a car, a bedroom, a patient's room: not a corridor
    with doors all along it, which a path crosses rather than ends in). `node_type(n)` / `edge_type(u, v)`: the types
    (location.places.type_matches with the family 'doorway' tells the doorways and door edges)."""
    from socnavgen.location.places import type_matches

    def is_door(n: str) -> bool:
        return type_matches(node_type(n), "doorway")

    door_edge = (lambda u, v: type_matches(edge_type(u, v), "doorway")) if edge_type is not None else None
    out: list[RoomEnd] = []
    goal_room = room_of(graph, plan.robot[-1], is_door, door_edge) if plan.robot else None
    for h in plan.humans:
        if goal_room is not None and follows_robot_to_the_end(spec, h.name):
            out.append(RoomEnd(h.name, plan.robot[-1], *goal_room, source=source))
            continue
        if len(h.path) < 2 or not walks_to_the_end(spec, h.name):
            continue
        found = room_of(graph, h.path[-1], is_door, door_edge)
        if found is not None and len(found[1]) == 1 and any(n not in found[0] for n in h.path):  # their path goes in
            out.append(RoomEnd(h.name, h.path[-1], *found, source=source, follows=False))
    return out


def inside(end: RoomEnd, p: np.ndarray, node_points: dict[str, tuple[float, float]], world: Any = None) -> bool:
    """Whether the centre `p` is in the room: on the map, in sight of a node of the room with no doorway between them
    (sim.people.spots.through_door, asked of a body a radius nearer the node, whose far side is the centre: the centre
    is past the door's narrowest point); without one, at a node of the room (the nearest one)."""
    if world is not None:
        from socnavgen.sim.people.spots import through_door

        here = complex(p[0], p[1])
        for n in sorted(end.room):
            if n not in node_points:
                continue
            node = complex(*node_points[n])
            away = abs(node - here)
            body = here + (node - here) / away * PERSON_RADIUS / 2 if away > PERSON_RADIUS else node
            if bool(world.line_of_sight(node, here)[0]) and not through_door(world.map, body, node):
                return True
        return False
    return _nearest(p, node_points) in end.room


def full(end: RoomEnd, trace: Trace, i: int, node_points: dict[str, tuple[float, float]], world: Any) -> bool:
    """No spot is left for person i in the room round its goal at the end of the run, the others and the robot
    standing where they are (sim.people.spots.room_left: the spots the simulated people take): a guide filling an
    elevator car, the patient at its door (hospital_09). Without a map nothing says it is full."""
    if world is None or end.goal not in node_points:
        return False
    from socnavgen.sim.people.spots import room_left

    others = np.arange(len(trace.human_names)) != i
    ends = trace.humans[-1, others, :2]
    bodies = np.ascontiguousarray(ends[:, 0] + 1j * ends[:, 1], dtype=np.complex128)
    radii = np.ascontiguousarray(np.asarray(trace.human_radii, dtype=np.float64)[others])
    robot = complex(*trace.robot[-1, :2])
    return not bool(room_left(world.map, complex(*node_points[end.goal]), bodies, radii, robot,
                              float(trace.robot_radius), float(trace.human_radii[i])))


def _nearest(p: np.ndarray, node_points: dict[str, tuple[float, float]]) -> str:
    names = list(node_points)
    if not names:
        return "?"
    return names[int(np.argmin(np.hypot(*(np.asarray([node_points[n] for n in names]) - p).T)))]


def judge_room_end(end: RoomEnd, trace: Trace, node_points: dict[str, tuple[float, float]],
                   goal_reached: bool, world: Any = None) -> Finding:
    """The verdict on one person's end place: inside the room their way ends in."""
    whose = f"with the robot in the room of {end.goal}" if end.follows else f"inside the room of {end.goal}, " \
                                                                            f"where their path ends"
    base = Finding(name=f"{end.human} ends {whose} (behind {'/'.join(sorted(end.doors))})", kind=KIND,
                   passed=True, evidence="", human=end.human, node=end.goal, source=end.source)
    if end.human not in trace.human_names or not trace.steps:
        return base.model_copy(update={"passed": False, "evidence": f"{end.human} is not in the trace",
                                       "blame": "paths", "stage": "paths", "blame_reason": "no such person"})
    if end.follows and not goal_reached:
        return base.model_copy(update={"evidence": "the robot did not reach its goal: nothing to judge here"})
    i = trace.human_names.index(end.human)
    p = trace.humans[-1, i, :2]
    at = _nearest(p, node_points)
    t = float(trace.t[-1])
    gap = float(np.hypot(*(trace.robot[-1, :2] - p)))
    where = f"({p[0]:.2f}, {p[1]:.2f}), nearest node {at}, {gap:.1f} m from the robot"
    if inside(end, p, node_points, world):
        return base.model_copy(update={"evidence": f"{end.human} was inside when the run ended ({t:.1f} s) at "
                                                   f"{where}", "time": round(t, 3)})
    if not end.follows and at not in end.room:  # a walker the run ended before they came to the room (a card's run
        # ends as the robot arrives; cards' crowds stand in front of the cars): nothing to see; one nearest the room's
        # node must be inside, not in its door
        return base.model_copy(update={"evidence": f"{end.human} never came to the room's door ({where}, "
                                                   f"{t:.1f} s): nothing to judge", "time": round(t, 3)})
    if end.follows and at in end.room | end.doors and full(end, trace, i, node_points, world):  # a follower at the
        # door of a room with no spot left for them (a guide's patient at the car's door, the robot filling the car)
        return base.model_copy(update={"evidence": f"{end.human} was at the doorway of the full room (no spot left "
                                                   f"in it) when the run ended ({t:.1f} s) at {where}",
                                       "time": round(t, 3)})
    failed = base.model_copy(update={
        "passed": False, "time": round(t, 3), "distance": round(gap, 2),
        "evidence": f"when the run ended ({t:.1f} s) {end.human} was at {where}: not inside the room of {end.goal} "
                    f"({', '.join(sorted(end.room))}) but in its doorway or outside it"})
    if end.follows:
        return failed.model_copy(update={
            "blame": "robot_script", "stage": None,
            "blame_reason": f"the robot drove into the room of {end.goal} leaving {end.human} behind outside: let it "
                            f"wait for its followers before the room's doorway (a human_farther cue for "
                            f"{end.human}), so they come in with it"})
    goal = np.asarray(node_points.get(end.goal, p), dtype=float)
    back = int(np.searchsorted(trace.t, t - COMING_SECONDS))
    came = float(np.hypot(*(trace.humans[back, i, :2] - goal)) - np.hypot(*(p - goal)))
    if came >= MOVED_DISTANCE:  # still on their way in when the run ended
        return failed.model_copy(update={
            "blame": "paths", "stage": "paths",
            "blame_reason": f"the run ended (the robot at its goal) while {end.human} was still walking in to "
                            f"{end.goal}: give the robot a longer way, or {end.human} a shorter one, so they are in "
                            f"before it arrives"})
    return failed.model_copy(update={
        "blame": "behaviors", "blame_human": end.human, "stage": "behaviors",
        "blame_reason": f"{end.human} stood outside the room of {end.goal} at the end although their path ends in "
                        f"it: their tree must let them walk on to the end of their path once their reactions are "
                        f"over"})


def room_end_findings(ends: list[RoomEnd], trace: Trace, node_points: dict[str, tuple[float, float]],
                      goal_reached: bool, world: Any = None) -> list[Finding]:
    """One finding per person whose way ends in a room."""
    return [judge_room_end(e, trace, node_points, goal_reached, world) for e in ends]
