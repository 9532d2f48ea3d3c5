"""Where bodies may START on a map: the one rule the scenario cards and stage 2's checks share.

Every person starts at the first node of their path (a group's members on a circle of GROUP_SPAWN_RADIUS
around it), the robot at the first node of its route. Nobody starts on or against another body: the
gap (surface to surface) between two starting bodies is at least START_GAP, so nobody is inside
another's intimate space at t = 0. Nobody starts on the robot's goal unless they walk away from it
(someone leaving the room the robot is about to enter): a person standing on the goal, or walking to
it, keeps the robot from ever arriving. A robot route that ends where it starts goes somewhere only
when it passes another node on the way (a round trip, "to X and back").

Distances are measured between node positions as the prompts show them (`shown_position`: metres,
rounded to 0.1 m), and compared exactly as the rule says ("at least 1.2 m": 1.2 m passes), so the
rule a model reads and the check it meets are the same comparison. The rounding moves a body by at
most 0.05 m per axis: the gap stays well clear of contact (bodies.CONTACT_MARGIN)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from socnavgen.bodies import GROUP_SPAWN_RADIUS, INTIMATE_SPACE, PERSON_RADIUS, ROBOT_RADIUS, group_ring
from socnavgen.location.location import Location

START_GAP = INTIMATE_SPACE  # m: smallest gap between two bodies where they start
POSITION_DECIMALS = 1  # node positions in metres are shown (and measured) to 0.1 m
_EPS = 1e-9  # float noise of a subtraction: 8.0 - 6.8 is 1.2 here


@dataclass(frozen=True)
class Walker:
    """A person as placement sees them: name, path of node ids, group id (-1 alone)."""

    name: str
    path: list[str]
    group: int = -1


def _centre_distance_needed(a_ring: float, b_ring: float, a_radius: float, b_radius: float) -> float:
    """Node-to-node distance that keeps START_GAP between two bodies, each anywhere on its ring."""
    return round(a_ring + b_ring + a_radius + b_radius + START_GAP, 2)


def shown_position(location: Location, node: str) -> tuple[float, float]:
    """A node's position in metres (x east, y north) as every prompt shows it."""
    x, y = location.node_world(node)
    return round(x, POSITION_DECIMALS), round(y, POSITION_DECIMALS)


def node_distance(location: Location, a: str, b: str) -> float:
    """Distance between two nodes' shown positions: what a model computes from the prompt."""
    (ax, ay), (bx, by) = shown_position(location, a), shown_position(location, b)
    return math.hypot(bx - ax, by - ay)


def too_close(distance: float, need: float) -> bool:
    """The start rule's one comparison: closer than `need` ("at least need" passes at need)."""
    return distance < need - _EPS


def start_rule_text() -> str:
    """The rule in words, for the prompts (numbers from the bodies)."""
    alone = _centre_distance_needed(0.0, 0.0, PERSON_RADIUS, ROBOT_RADIUS)
    people = _centre_distance_needed(0.0, 0.0, PERSON_RADIUS, PERSON_RADIUS)
    return (f"Where everybody starts: the robot's route ends at another node than its start, or comes back to its "
            f"start only after passing other nodes (a round trip: [A, B, C, B, A]); a person starts at least {alone:.1f} m "
            f"from the robot's start ({alone + GROUP_SPAWN_RADIUS:.1f} m for a group, whose members stand on a "
            f"{GROUP_SPAWN_RADIUS:g} m circle around their shared first node, {group_ring(4):g} m for four) and at least {people:.2f} m from "
            f"any other person who is not in their group, so two people not in one group never start at one node "
            f"(measured between the xy_m of the two start nodes, as shown; \"at least\" includes the number itself: "
            f"a person exactly {alone:.1f} m from the robot's start passes); nobody starts on the robot's goal unless their path walks "
            f"away from it and ends elsewhere.")


def route_problems(robot: list[str]) -> list[str]:
    """A robot route that goes nowhere: its goal is its start and it passes no other node on the way (a
    round trip that passes other nodes is a route)."""
    if len(robot) >= 2 and robot[0] == robot[-1] and set(robot) == {robot[0]}:
        return [f"the robot's goal is its start ({robot[0]}) and it goes nowhere in between: end the robot's path "
                f"at another node, or come back only after passing other nodes (a round trip)"]
    return []


def clear_starts(location: Location) -> dict[str, frozenset[str]]:
    """For each node the robot may start at, the nodes a person (or a group member, on its ring) may start at
    under the start rule: what stage 2's grammar admits, so that an in-process model cannot sample a start the
    check refuses."""
    need = _centre_distance_needed(GROUP_SPAWN_RADIUS, 0.0, PERSON_RADIUS, ROBOT_RADIUS)
    nodes = list(location.graph.nodes)
    return {s: frozenset(u for u in nodes if not too_close(node_distance(location, u, s), need)) for s in nodes}


def start_problems(location: Location, robot: list[str], walkers: list[Walker]) -> list[str]:
    """Every way these starts break the rule (route_problems included), in words that say what to change."""
    problems = route_problems(robot)
    known = set(location.graph.nodes)
    if not robot or any(n not in known for n in [robot[0], robot[-1]]):
        return problems
    members: dict[int, int] = {}
    for w in walkers:
        if w.group >= 0:
            members[w.group] = members.get(w.group, 0) + 1

    def ring(w: Walker) -> float:
        return group_ring(members[w.group]) if w.group >= 0 and members[w.group] > 1 else 0.0

    def dist(a: str, b: str) -> float:
        return node_distance(location, a, b)

    starts = [w for w in walkers if w.path and set(w.path) <= known]  # unknown nodes are reported elsewhere
    goal = robot[-1]
    for w in starts:
        start = w.path[0]
        need = _centre_distance_needed(ring(w), 0.0, PERSON_RADIUS, ROBOT_RADIUS)
        d = dist(start, robot[0])
        if too_close(d, need):
            where = "where the robot starts" if start == robot[0] else f"{d:.2f} m from where the robot starts ({robot[0]})"
            problems.append(f"{w.name} starts at {start}, {where}: they would start touching or too close; start "
                            f"{w.name} at a node at least {need:g} m from {robot[0]}")
        if len(robot) >= 2 and goal != robot[0] and too_close(dist(start, goal), need) \
                and _stays(w.path, goal, dist, need):
            where = "on the robot's goal" if start == goal else f"{dist(start, goal):.2f} m from the robot's goal"
            problems.append(f"{w.name} starts at {start}, {where} {goal}, and does not walk away from it for good (their "
                            f"path stays near it or ends there): the robot could never arrive; start {w.name} "
                            f"elsewhere, or let them walk away and end elsewhere")
    for i, a in enumerate(starts):
        for b in starts[i + 1:]:
            if a.group >= 0 and a.group == b.group:
                continue  # a group shares its node: its members stand on their circle
            need = _centre_distance_needed(ring(a), ring(b), PERSON_RADIUS, PERSON_RADIUS)
            d = dist(a.path[0], b.path[0])
            if too_close(d, need):
                problems.append(f"{a.name} and {b.name} start {d:.2f} m apart ({a.path[0]}, {b.path[0]}): they would "
                                f"start on each other; start them at nodes at least {need:g} m apart, or make them "
                                f"one group (same group id)")
    return problems


def _stays(path: list[str], goal: str, dist, need: float) -> bool:  # noqa: ANN001 - the distance function above
    """Whether a person who starts at the goal stays there: their path never leaves the goal's
    neighbourhood, or comes back to end on it."""
    return all(too_close(dist(n, goal), need) for n in path) or too_close(dist(path[-1], goal), need)
