"""Routes on the scene graph for the card generator: the robot's route through / into / out of a place
and each human's path from its role. All paths are walks along graph edges; nothing here looks at
pixels except through PlaceFinder (world positions, for straightness)."""

from __future__ import annotations

from dataclasses import dataclass, field

import networkx as nx

from socnavgen.cards.models import Card, HumanRole
from socnavgen.cards.places import Candidate, PlaceFinder

REACH = 3  # nodes on each side of the place the robot's route extends to (when the graph allows)


class DoesNotFit(Exception):
    """This card cannot be placed here; the message says why in plain words."""


@dataclass
class HumanRoute:
    role: HumanRole
    path: list[str]
    meets_at: str | None  # interaction point (a node on both paths), None for same-direction roles
    group_id: int = -1


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
            return side_a[::-1] + [p] + side_b
        if card.route in ("into", "out_of"):
            if other is None:
                raise DoesNotFit(f"{p} has nothing behind it to enter")
            a = min((n for n in self.g.neighbors(p) if n != other),
                    key=lambda n: (self.f.turn_deg(n, p, other), n), default=None)
            if a is None:
                raise DoesNotFit(f"{p} has no way in besides {other}")
            route = self.extend(a, p, {p, other})[::-1] + [p, other]
            return route if card.route == "into" else route[::-1]
        # ends_at / starts_at: come from (go to) the neighbour with the longest way out
        sides = [self.extend(n, p, {p}) for n in sorted(self.g.neighbors(p))]
        if not sides:
            raise DoesNotFit(f"node {p} has no edges")
        side = max(sides, key=len)
        return side[::-1] + [p] if card.route == "ends_at" else [p] + side

    # -- the humans ----------------------------------------------------------------------------
    def near_nodes(self, p: str, avoid: set[str], hops: int = 2) -> list[str]:
        dist = nx.single_source_shortest_path_length(self.g, p, cutoff=hops)
        return sorted((n for n, d in dist.items() if d > 0 and n not in avoid), key=lambda n: (dist[n], n))

    def across(self, start: str, p: str) -> list[str] | None:
        """start -> ... -> p -> onward on the far side, as straight as the graph allows."""
        to_p = nx.shortest_path(self.g, start, p)
        before = to_p[-2] if len(to_p) > 1 else None
        options = [n for n in self.g.neighbors(p) if n not in to_p]
        if before is None or not options:
            return None
        nxt = min(options, key=lambda n: (self.f.turn_deg(before, p, n), n))
        return to_p + self.extend(nxt, p, set(to_p), hops=1)

    def humans(self, card: Card, place: Candidate, robot: list[str]) -> list[HumanRoute]:
        p = place.node
        starts: set[str] = {robot[0]}
        out: list[HumanRoute] = []
        group = 0
        for role in card.humans:
            gid = -1
            if role.group:
                group += 1
                gid = group
            paths = self.role_paths(role, p, robot, starts)
            need = role.min_count or role.count
            if len(paths) < need:
                raise DoesNotFit(self.shortfall(role, p, len(paths), need))
            for path, meets in paths[:role.count]:
                starts.add(path[0])
                out.append(HumanRoute(role=role, path=path, meets_at=meets, group_id=gid))
        return out

    def shortfall(self, role: HumanRole, p: str, got: int, need: int) -> str:
        what = {"crossing": f"a side branch at {p} that the robot's route does not use",
                "behind": "a node behind the robot's start", "beside": "a side node next to the robot's route",
                "ahead": "a route long enough for people ahead of the robot",
                "gathering": f"enough nodes around {p} for the group to come from",
                "circular": f"enough nodes around {p} to cross from", "through_place": f"enough nodes around {p}",
                "converging": f"enough nodes around {p}"}.get(role.role, "room for the humans")
        return f"needs {what} ({need} {role.role} human(s), found {got})"

    def role_paths(self, role: HumanRole, p: str, robot: list[str], starts: set[str]) -> list[tuple[list[str], str | None]]:
        """Candidate (path, interaction point) pairs for one role, best first, starts not yet taken."""
        i = robot.index(p)
        kind = role.role
        if kind == "oncoming":
            path = robot[::-1]
            return [] if path[0] in starts else [(path, p)]
        if kind == "standing":
            return [] if p in starts else [([p], p)]
        if kind == "ahead":
            return [(robot[k:], None) for k in range(1, len(robot) - 1) if robot[k] not in starts]
        if kind == "behind":
            back = [n for n in sorted(self.g.neighbors(robot[0])) if n not in robot and n not in starts]
            return [([b, *robot], None) for b in back]
        if kind == "beside":
            side = [n for n in sorted(self.g.neighbors(robot[1])) if n not in robot and n not in starts] \
                if len(robot) > 2 else []
            return [([c, *robot[1:]], None) for c in side]
        if kind == "crossing":
            used = {robot[j] for j in (i - 1, i + 1) if 0 <= j < len(robot)}
            branches = sorted(n for n in self.g.neighbors(p) if n not in used)
            if not branches:
                return []
            c = branches[0]
            feeder = self.extend(c, p, {p, *robot}, hops=REACH)
            exits = [n for n in branches[1:] if n not in feeder]
            tail = self.extend(exits[0], p, {p, *feeder}, hops=1) if exits else robot[:i][::-1][:2]
            return [(feeder[k::-1] + [p] + tail, p) for k in range(len(feeder)) if feeder[k] not in starts]
        if kind == "gathering":
            meets = p if robot[-1] == p else None
            ring = self.near_nodes(p, set(robot) | starts)
            return [(nx.shortest_path(self.g, s, p), meets) for s in ring]
        if kind == "converging":
            ring = self.near_nodes(p, starts | {robot[-1]})
            return [(nx.shortest_path(self.g, s, p), p) for s in ring]
        if kind in ("through_place", "circular"):
            ring = self.near_nodes(p, starts | {robot[-1]})
            if kind == "circular":
                ring = [n for n in ring if n not in robot]
            paths = [(self.across(s, p), p) for s in ring]
            return [(path, m) for path, m in paths if path is not None]
        raise DoesNotFit(f"unknown role {kind}")

    def place(self, card: Card, place: Candidate) -> Placement:
        robot = self.robot_route(card, place)
        if len(robot) < 2:
            raise DoesNotFit(f"no route of two or more nodes through {place.node}")
        if card.route == "through" and robot.index(place.node) in (0, len(robot) - 1):
            raise DoesNotFit(f"{place.node} is a dead end")
        if any(h.role == "behind" for h in card.humans):
            back = [n for n in self.g.neighbors(robot[0]) if n not in robot]
            if not back and robot.index(place.node) > 1 and len(robot) > 3:
                robot = robot[1:]  # the first node becomes the start of the person behind
        return Placement(card=card, place=place, robot=robot, humans=self.humans(card, place, robot))
