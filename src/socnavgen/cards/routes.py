"""Routes on the scene graph for the card generator: the robot's route through / into / out of a place
and each human's path from its role. All paths are walks along graph edges; nothing here looks at
pixels except through PlaceFinder (world positions, for straightness)."""

from __future__ import annotations

from dataclasses import dataclass, field

import networkx as nx

from socnavgen.bodies import PERSON_RADIUS, ROBOT_RADIUS
from socnavgen.cards.models import Card, HumanRole
from socnavgen.cards.trees import sight_distance, waiting_distance
from socnavgen.location.placement import Walker, start_problems
from socnavgen.location.places import Candidate, PlaceFinder

REACH = 3  # nodes on each side of the place the robot's route extends to (when the graph allows)


class DoesNotFit(Exception):
    """This card cannot be placed here; the message says why in plain words."""


@dataclass
class HumanRoute:
    role: HumanRole
    path: list[str]
    meets_at: str | None  # interaction point (a node on both paths), None for same-direction roles
    group_id: int = -1
    encounter: bool = True  # False: paced to meets_at with the others of its crowd, judged with the first one


@dataclass
class Placement:
    card: Card
    place: Candidate
    robot: list[str]
    humans: list[HumanRoute] = field(default_factory=list)


class RouteBuilder:
    def __init__(self, finder: PlaceFinder) -> None:
        self.f = finder
        self.g: nx.Graph = finder.graph

    # -- small walks ---------------------------------------------------------------------------
    def extend(self, start: str, prev: str, avoid: set[str], hops: int = REACH - 1) -> list[str]:
        """Walk outward from `start` (entered from `prev`), always taking the straightest way on."""
        out = [start]
        used = set(avoid) | {start, prev}
        while len(out) <= hops:
            here, before = out[-1], (out[-2] if len(out) > 1 else prev)
            options = [n for n in self.g.neighbors(here) if n not in used]
            if not options:
                break
            nxt = min(options, key=lambda n: (self.f.turn_deg(before, here, n), n))
            out.append(nxt)
            used.add(nxt)
        return out

    def straightest_pair(self, p: str, forced: str | None = None, exclude: set[str] | None = None) -> tuple[str, str]:
        nbrs = sorted(n for n in self.g.neighbors(p) if n not in (exclude or set()))
        pairs = [(a, b) for a in nbrs for b in nbrs if a != b and (forced is None or b == forced)]
        if not pairs:
            kind = self.f.type_of(p)
            raise DoesNotFit(f"{p} ({kind}) is a dead end, so no route passes through it")
        return min(pairs, key=lambda ab: (self.f.turn_deg(ab[0], p, ab[1]), ab))

    # -- the robot -----------------------------------------------------------------------------
    def robot_route(self, card: Card, place: Candidate) -> list[str]:
        p, other = place.node, place.other
        if card.route == "through":
            forced = other if card.place == "narrow_passage" else None
            a, b = self.straightest_pair(p, forced)
            side_a = self.extend(a, p, {p})
            side_b = self.extend(b, p, {p, *side_a})
            if forced is not None and len(side_b) < 2:
                raise DoesNotFit(f"the narrow passage {p}-{forced} ends in a dead end at {forced}")
            return side_a[::-1] + [p] + side_b
        if card.route in ("into", "out_of"):
            if other is None:
                raise DoesNotFit(f"{p} has nothing behind it to enter")
            way_in = min((n for n in self.g.neighbors(p) if n != other),
                         key=lambda n: (self.f.turn_deg(n, p, other), n), default=None)
            if way_in is None:
                raise DoesNotFit(f"{p} has no way in besides {other}")
            route = self.extend(way_in, p, {p, other})[::-1] + [p, other]
            return route if card.route == "into" else route[::-1]
        # ends_at / starts_at: come from (go to) the neighbour with the longest way out
        sides = [self.extend(n, p, {p}) for n in sorted(self.g.neighbors(p))]
        if not sides:
            raise DoesNotFit(f"node {p} has no edges")
        side = max(sides, key=len)
        if card.route == "ends_at":  # come up to P (people gather there) and stop next to it
            return min(sides, key=lambda sd: (self.f.distance(sd[0], p), -len(sd), sd[0]))[::-1]
        return [p] + side

    # -- the humans ----------------------------------------------------------------------------
    def near_nodes(self, p: str, avoid: set[str], hops: int = 2) -> list[str]:
        dist = nx.single_source_shortest_path_length(self.g, p, cutoff=hops)
        return sorted((n for n, d in dist.items() if d > 0 and n not in avoid), key=lambda n: (dist[n], n))

    def beyond(self, robot: list[str]) -> list[str]:
        """Nodes past the robot's goal (straightest first): where same-direction walkers go on to."""
        if len(robot) < 2:
            return []
        return sorted((n for n in self.g.neighbors(robot[-1]) if n not in robot),
                      key=lambda n: (self.f.turn_deg(robot[-2], robot[-1], n), n))

    def across(self, start: str, p: str, forbid_end: set[str]) -> list[str] | None:
        """start -> ... -> p -> on to the far side, as straight as the graph allows, ending on a node
        outside `forbid_end` (a person who stops on the robot's way ahead would block it for good)."""
        to_p = nx.shortest_path(self.g, start, p)
        if len(to_p) < 2:
            return None
        options = sorted((n for n in self.g.neighbors(p) if n not in to_p),
                         key=lambda n: (self.f.turn_deg(to_p[-2], p, n), n))
        for nxt in options:
            path = to_p + self.extend(nxt, p, set(to_p), hops=1)
            if path[-1] not in forbid_end:
                return path
        return None

    def humans(self, placement: Placement) -> list[HumanRoute]:
        card, robot = placement.card, placement.robot
        starts: set[str] = {robot[0]}
        placed: list[Walker] = []
        out: list[HumanRoute] = []
        group = 0
        for role in card.humans:
            gid = -1
            if role.group:
                group += 1
                gid = group
            paths = [(path, meets) for path, meets in self.role_paths(role, placement, starts)
                     if path[0] not in starts]
            need = role.min_count or role.count
            picked: list[tuple[list[str], str | None]] = []
            if role.group and paths:  # a group walks together: every member on the same path, side by side
                members = [Walker(f"member{k + 1}", paths[0][0], gid) for k in range(role.count)]
                if not start_problems(self.f.location, robot, placed + members):
                    picked = [paths[0]] * role.count
            for path, meets in paths:
                if path[0] not in {q[0] for q, _ in picked} and len(picked) < role.count \
                        and not start_problems(self.f.location, robot,
                                               [*placed, *(Walker("other", q, gid) for q, _ in picked),
                                                Walker("this", path, gid)]):
                    picked.append((path, meets))
            if len(picked) < need:
                raise DoesNotFit(self.shortfall(role, placement.place.node, len(picked), need))
            for k, (path, meets) in enumerate(picked):
                starts.add(path[0])
                placed.append(Walker(f"human{len(out) + 1}", path, gid))
                # in a stream or a crowd only the first person is held back to meet the robot at P;
                # the others pass when they pass (holding all of them would bunch them at P); a converging
                # crowd is meant to bunch around the robot at P, so every one of them is paced to it
                held = k == 0 or role.role == "converging"
                out.append(HumanRoute(role=role, path=path, meets_at=meets if held else None, group_id=gid,
                                      encounter=k == 0))
        return out

    def shortfall(self, role: HumanRole, p: str, got: int, need: int) -> str:
        what = {"crossing": f"a side branch at {p} that the robot's route does not use",
                "behind": "a node behind the robot's start", "beside": "a side node next to the robot's route",
                "ahead": "a route with a way on past the robot's goal for people walking ahead of it",
                "gathering": f"enough nodes around {p} for the group to come from (off the robot's route)",
                "circular": f"enough nodes around {p} to cross from", "through_place": f"enough nodes around {p}",
                "converging": f"enough nodes around {p}"}.get(role.role, "room for the humans")
        return f"needs {what} ({need} {role.role} human(s) starting clear of everybody else, found {got})"

    def role_paths(self, role: HumanRole, placement: Placement, starts: set[str]) -> list[tuple[list[str], str | None]]:
        """Candidate (path, interaction point) pairs for one role, best first."""
        robot, p = placement.robot, placement.place.node
        i = robot.index(p) if p in robot else len(robot) - 1
        ahead_of_robot = set(robot[1:])  # where a person must not end up standing (the robot still has to pass)
        kind = role.role
        if kind == "oncoming":  # starts past the robot's goal: standing on it would block the robot for good
            start = self.oncoming_start(placement, waiting_distance(role.tree))  # (none past a room's dead end)
            if not start and placement.card.place == "doorway":
                # through a door from a dead-end room the person waits for the robot on the robot's own goal
                return []
            return [([*start, *robot[::-1]], self.meeting_node(placement, i))]
        if kind == "standing":
            return [([p], p)]
        full = robot + self.beyond(robot)[:1]  # same-direction walkers go on past the robot's goal
        if kind in ("ahead", "behind", "beside") and full[-1] == robot[-1]:
            return []  # they would stop on the robot's goal and block it for good
        if kind == "ahead":
            return [(full[k:], None) for k in range(1, len(robot) - 1)]
        if kind == "behind":
            back = [n for n in sorted(self.g.neighbors(robot[0])) if n not in robot]
            return [([b, *full], None) for b in back]
        if kind == "beside":
            side = [n for n in sorted(self.g.neighbors(robot[1])) if n not in robot] if len(robot) > 2 else []
            return [([c, *full[1:]], None) for c in side]
        if kind == "crossing":
            used = {robot[j] for j in (i - 1, i + 1) if 0 <= j < len(robot)}
            branches = sorted(n for n in self.g.neighbors(p) if n not in used)
            if not branches:
                return []
            c = branches[0]
            feeder = self.extend(c, p, {p, *robot}, hops=REACH)
            exits = [n for n in branches[1:] if n not in feeder]
            # with no branch of their own past P they turn into the robot's way in, behind the robot; never as far
            # as where it starts (it may still be there: they would walk up to it and stand in its way)
            tail = self.extend(exits[0], p, {p, *feeder}, hops=1) if exits else robot[:i][::-1][:2]
            if not exits and tail[-1:] == robot[:1]:
                return []
            return [(feeder[k::-1] + [p] + tail, p) for k in range(len(feeder))]
        if kind == "gathering":  # nearest first, so the group forms quickly; no pausing for groups
            ring = sorted(self.near_nodes(p, set(robot)), key=lambda n: (self.f.distance(n, p), n))
            paths = [nx.shortest_path(self.g, s, p) for s in ring]
            return [(path, None) for path in paths if not set(path[:-1]) & set(robot)]
        # converging / through_place / circular: from nodes around P across P, never stopping ahead of the robot,
        # never starting on the robot's way to P (held there to meet at P, a person blocks the robot before P)
        ring = self.near_nodes(p, {robot[-1]})
        if kind == "circular":
            ring = [n for n in ring if n not in robot]
        before_p = set(robot[:i])
        off_route = [n for n in ring if n not in before_p]
        ring = off_route + [n for n in ring if n in before_p]
        # a crowd walking to where the robot starts traps it there; a few circling people do not
        forbid = ahead_of_robot | {robot[-1]} | (set() if kind == "circular" else {robot[0]})
        if kind == "converging":  # out of the robot's sight at t = 0, or they crowd it at its start, not at P
            sight = sight_distance(role.tree)
            ring = [n for n in ring if self.f.distance(n, robot[0]) > sight or not self.f.sees(n, robot[0])]
        paths = [self.across(s, p, forbid) for s in ring]
        return [(path, p) for path in paths if path is not None]

    def oncoming_start(self, placement: Placement, wait: float) -> list[str]:
        """The nodes past the robot's goal an oncoming person walks from (where they start first): the next one,
        or for a person who stands waiting for the robot, out along the straightest way until they start `wait` (how near the robot makes their tree stand and wait:
        trees.waiting_distance) and both bodies past the goal, where the graph goes that far (at a blind corner,
        not as far as a node the robot's way in sees: the corner must stay blind). A person who waits while the
        robot is within 2.5 m, starting 1.5 m from its goal (the next node on SocRATES's hospital graph), stood
        waiting there while the robot stood short of its goal at a polite gap from them, each waiting for the
        other: a placement that cannot start them that far does not fit."""
        robot = placement.robot
        first = self.beyond(robot)[:1]
        if not first or wait <= 0:  # a person who never stands waiting for it: the next node past its goal
            return first
        need = wait + PERSON_RADIUS + ROBOT_RADIUS
        way = self.extend(first[0], robot[-1], set(robot), hops=len(self.g))
        i = robot.index(placement.place.node) if placement.place.node in robot else len(robot) - 1
        out, far, here = [first[0]], self.f.distance(robot[-1], first[0]), first[0]
        for nxt in way[1:]:
            if far >= need or (placement.card.place == "blind_corner"
                               and any(self.f.sees(a, nxt) for a in robot[:i])):
                break
            out.append(nxt)
            far, here = far + self.f.distance(here, nxt), nxt
        if self.f.distance(robot[-1], out[-1]) < need:  # they would wait by its goal, it for them
            raise DoesNotFit(f"no node past the robot's goal {robot[-1]} is {need:.1f} m from it (where a person "
                             f"coming the other way waits for the robot and the robot reaches its goal)")
        return out[::-1]

    def meeting_node(self, placement: Placement, i: int) -> str:
        """Where an oncoming person meets the robot. Through a narrow passage only one fits at a time, so
        the person is held until the robot is through: the meeting node is the first node after it. At a
        doorway they meet AT the door: the person, paced to arrive with the robot, steps aside next to
        it (its tree) and the robot goes through first."""
        robot, card = placement.robot, placement.card
        past = {"narrow_passage": i + 2}.get(card.place)
        if past is not None and past < len(robot):
            return robot[past]
        return placement.place.node

    def place(self, card: Card, place: Candidate) -> Placement:
        robot = self.robot_route(card, place)
        if len(robot) < 2:
            raise DoesNotFit(f"no route of two or more nodes through {place.node}")
        if card.route == "through" and robot.index(place.node) in (0, len(robot) - 1):
            raise DoesNotFit(f"{place.node} is a dead end")
        roles = {h.role for h in card.humans}
        interior = card.route == "through"
        if "behind" in roles and not [n for n in self.g.neighbors(robot[0]) if n not in robot] \
                and interior and robot.index(place.node) > 1 and len(robot) > 3:
            robot = robot[1:]  # the first node becomes the start of the person behind
        if "oncoming" in roles and interior and not self.beyond(robot) and self.beyond(robot[::-1]):
            robot = robot[::-1]  # the far side is a dead end (a room): start there, so the person can come from past the goal
        if roles & {"ahead", "behind", "beside", "oncoming"} and not self.beyond(robot) \
                and interior and robot.index(place.node) < len(robot) - 2 and len(robot) > 3:
            robot = robot[:-1]  # the last node becomes where the walkers go on to
        if card.place == "blind_corner":
            robot = self.blind_route(robot, place.node)
        self.check_lead_in(card, robot, place.node)
        placement = Placement(card=card, place=place, robot=robot)
        placement.humans = self.humans(placement)
        return placement

    def check_lead_in(self, card: Card, robot: list[str], p: str) -> None:
        """People who come up to the robot once they see it must not see it before it is on its way: the
        robot's way to P is at least their sight (or P cannot see the start), or they crowd it at its start."""
        sight = max((sight_distance(r.tree) for r in card.humans if r.role == "converging"), default=0.0)
        if not sight or p not in robot or not self.f.sees(robot[0], p):
            return  # a wall hides the start from P: they cannot see the robot before it comes round
        k = robot.index(p)
        lead = sum(self.f.distance(a, b) for a, b in zip(robot[:k], robot[1:k + 1], strict=True))
        if lead < sight:
            raise DoesNotFit(f"the robot's way to {p} is {lead:.1f} m: people who come up to it within "
                             f"{sight:g} m would crowd it at its start")

    def blind_route(self, robot: list[str], p: str) -> list[str]:
        """A blind corner must be blind: the route's far end (where an oncoming person starts) is cut back
        until no node of the far leg is in sight of a node of the near leg (a route that wraps around a
        shelf would otherwise show the person across the room at t = 0)."""
        i = robot.index(p)
        near = robot[:i]
        def seen(route: list[str]) -> bool:
            return any(self.f.sees(a, b) for a in near for b in route[i + 1:] + self.beyond(route)[:1])

        while len(robot) > i + 2 and seen(robot):
            robot = robot[:-1]
        if seen(robot):
            raise DoesNotFit(f"{p} is not blind: the legs before and after it see each other")
        return robot
