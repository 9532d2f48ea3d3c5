"""Where on a location's scene graph a kind of place is (scenario cards place themselves with it; the
place inventory of the prompts describes the map with it). Schemas name node types differently per
location ("BLIND CORNER", "Corner", "DOOR", "ENTRANCE/EXIT"...), so places are found by KEYWORDS in
the type names and, where the words are missing, by GEOMETRY: node degree, free space around a
node (occupancy clearance) and whether two nodes can see each other."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from socnavgen.location import Location

# Word families (whole words of a type name, lower case).
KEYWORDS: dict[str, tuple[str, ...]] = {
    "blind_corner": ("blind",),
    "corner": ("corner", "turn", "bend"),
    "intersection": ("intersection", "junction", "crossing", "crossroad", "crossroads", "fork"),
    "open_area": ("open", "area", "hall", "lobby", "atrium", "plaza", "lounge", "foyer", "reception", "square"),
    "doorway": ("door", "doorway", "entrance", "exit", "entry", "gate", "threshold"),
    "room": ("room", "office", "ward", "kitchen", "bedroom", "bathroom", "toilet", "restroom", "lab",
             "laboratory", "classroom", "suite"),
    "elevator": ("elevator", "elevators", "lift", "lifts"),
    "narrow_edge": ("narrow", "aisle", "tight", "doorway", "door"),
}
# Words that make a type NOT of the family even when a keyword matches ("ELEVATOR LOBBY" is a hall).
EXCLUDE: dict[str, tuple[str, ...]] = {"elevator": ("lobby", "hall", "area", "waiting", "corridor")}
OPEN_CLEARANCE_M = 1.5  # free radius around a node that makes it an open area
NARROW_CLEARANCE_M = 0.75  # free half-width below which a passage is narrow (< 1.5 m wide)
DOOR_CLEARANCE_M = 0.6  # a pinch this tight at a degree-2 node looks like a doorway
CORNER_TURN_DEG = 45.0  # a turn sharper than this (deviation from straight) makes a corner


def words(type_name: str) -> set[str]:
    return {w for w in re.split(r"[^a-z]+", type_name.lower()) if w}


def type_matches(type_name: str, family: str) -> bool:
    found = words(type_name)
    return bool(found & set(KEYWORDS[family])) and not found & set(EXCLUDE.get(family, ()))


@dataclass(frozen=True)
class Candidate:
    """A place: the meeting node, an optional second node (room/elevator behind it, or the far end of
    a narrow edge), and how it was recognised (shown to the user)."""

    node: str
    other: str | None = None
    evidence: str = ""


class PlaceFinder:
    """All candidates of every feature on one location, best first."""

    def __init__(self, location: Location) -> None:
        self.location = location
        self.graph = location.graph
        self.mpp = location.transform.meters_per_pixel

    @cached_property
    def world(self) -> dict[str, tuple[float, float]]:
        return {n: self.location.node_world(n) for n in self.graph.nodes}

    def type_of(self, node: str) -> str:
        return str(self.graph.nodes[node].get("type", ""))

    def typed(self, family: str) -> list[str]:
        return sorted(n for n in self.graph.nodes if type_matches(self.type_of(n), family))

    def clearance_m(self, node: str) -> float:
        px, py = self.location.scene_graph.node(node).pos
        occ = self.location.occupancy
        if not occ.inside(px, py):
            return 0.0
        return float(occ.clearance_px[int(py), int(px)]) * self.mpp

    def turn_deg(self, a: str, p: str, b: str) -> float:
        """How far the walk a -> p -> b deviates from straight (0 = straight on, 180 = U-turn)."""
        (ax, ay), (px, py), (bx, by) = self.world[a], self.world[p], self.world[b]
        h1, h2 = math.atan2(py - ay, px - ax), math.atan2(by - py, bx - px)
        return abs(math.degrees((h2 - h1 + math.pi) % (2 * math.pi) - math.pi))

    def distance(self, a: str, b: str) -> float:
        (ax, ay), (bx, by) = self.world[a], self.world[b]
        return math.hypot(bx - ax, by - ay)

    def sees(self, a: str, b: str) -> bool:
        sa = self.location.scene_graph.node(a).pos
        sb = self.location.scene_graph.node(b).pos
        return self.location.occupancy.segment_clear(sa, sb)

    def edge_clearance_m(self, u: str, v: str) -> float:
        """Smallest free half-width along the straight edge, away from its end nodes."""
        a = np.asarray(self.location.scene_graph.node(u).pos, dtype=float)
        b = np.asarray(self.location.scene_graph.node(v).pos, dtype=float)
        occ = self.location.occupancy
        values = []
        for t in np.linspace(0.2, 0.8, 13):
            x, y = a + t * (b - a)
            if occ.inside(x, y):
                values.append(float(occ.clearance_px[int(y), int(x)]))
        return min(values) * self.mpp if values else 0.0

    # -- features ----------------------------------------------------------------------------
    def candidates(self, feature: str) -> list[Candidate]:
        finder = getattr(self, f"_{feature}")
        seen: set[tuple[str, str | None]] = set()
        out = []
        for c in finder():
            if (c.node, c.other) not in seen:
                seen.add((c.node, c.other))
                out.append(c)
        return out

    def _any(self) -> list[Candidate]:
        nodes = sorted(self.graph.nodes, key=lambda n: (-min(self.graph.degree[n], 3), n))
        return [Candidate(n, evidence=f"node {n} ({self.type_of(n)})") for n in nodes if self.graph.degree[n] >= 2]

    def _corridor(self) -> list[Candidate]:
        """Nodes a route passes through, widest first (room to pass, overtake or step aside)."""
        nodes = sorted((n for n in self.graph.nodes if self.graph.degree[n] >= 2),
                       key=lambda n: (-round(self.clearance_m(n), 1), self.graph.degree[n] != 2, n))
        return [Candidate(n, evidence=f"node {n} ({self.type_of(n)}) on a through route, "
                                      f"{2 * self.clearance_m(n):.1f} m wide") for n in nodes]

    def _intersection(self) -> list[Candidate]:
        typed = [Candidate(n, evidence=f"type '{self.type_of(n)}'") for n in self.typed("intersection")
                 if self.graph.degree[n] >= 3]
        geo = [Candidate(n, evidence=f"{self.graph.degree[n]} branches meet at {n} ({self.type_of(n)})")
               for n in sorted(self.graph.nodes, key=lambda n: (-self.graph.degree[n], n)) if self.graph.degree[n] >= 3]
        return typed + geo

    def _blind_corner(self) -> list[Candidate]:
        blind = [Candidate(n, evidence=f"type '{self.type_of(n)}'") for n in self.typed("blind_corner")
                 if self.graph.degree[n] >= 2]
        corner = [Candidate(n, evidence=f"type '{self.type_of(n)}'") for n in self.typed("corner")
                  if self.graph.degree[n] >= 2]
        geo = []
        for n in sorted(self.graph.nodes):
            nbrs = sorted(self.graph.neighbors(n))
            if len(nbrs) == 2 and self.turn_deg(nbrs[0], n, nbrs[1]) >= CORNER_TURN_DEG \
                    and not self.sees(nbrs[0], nbrs[1]):
                geo.append(Candidate(n, evidence=f"{n} is a turn whose neighbours {nbrs[0]} and {nbrs[1]} "
                                                 "cannot see each other"))
        return blind + corner + geo

    def _open_area(self) -> list[Candidate]:
        def roominess(n: str) -> tuple:
            return (-min(self.graph.degree[n], 4), -round(self.clearance_m(n), 1), n)
        typed = [Candidate(n, evidence=f"type '{self.type_of(n)}'")
                 for n in sorted(self.typed("open_area"), key=roominess)]
        geo = [Candidate(n, evidence=f"{self.clearance_m(n):.1f} m of free space around {n} ({self.type_of(n)})")
               for n in sorted(self.graph.nodes, key=roominess) if self.clearance_m(n) >= OPEN_CLEARANCE_M]
        return typed + geo

    def _narrow_passage(self) -> list[Candidate]:
        typed, geo = [], []
        for u, v, data in sorted(self.graph.edges(data=True)):
            if type_matches(str(data.get("type", "")), "narrow_edge"):
                typed += [Candidate(u, v, f"edge {u}-{v} of type '{data.get('type')}'"),
                          Candidate(v, u, f"edge {v}-{u} of type '{data.get('type')}'")]
            else:
                width = self.edge_clearance_m(u, v)
                if 0 < width < NARROW_CLEARANCE_M:
                    ev = f"edge {u}-{v} is only {2 * width:.1f} m wide"
                    geo += [Candidate(u, v, ev), Candidate(v, u, ev)]
        return typed + geo

    def _doorway(self) -> list[Candidate]:
        typed = [Candidate(n, evidence=f"type '{self.type_of(n)}'") for n in self.typed("doorway")
                 if self.graph.degree[n] >= 2]
        geo = [Candidate(n, evidence=f"{n} is a {2 * self.clearance_m(n):.1f} m wide pinch between two nodes")
               for n in sorted(self.graph.nodes)
               if self.graph.degree[n] == 2 and 0 < self.clearance_m(n) < DOOR_CLEARANCE_M]
        return typed + geo

    def _entry(self, family: str) -> list[Candidate]:
        """(P, T): T typed `family`, P a neighbour of T from which the route can continue outward."""
        doors: list[Candidate] = []
        others: list[Candidate] = []
        for target in self.typed(family):
            for p in sorted(self.graph.neighbors(target)):
                if type_matches(self.type_of(p), family) or self.graph.degree[p] < 2:
                    continue
                c = Candidate(p, target, f"{p} ({self.type_of(p)}) leads into {target} ({self.type_of(target)})")
                (doors if type_matches(self.type_of(p), "doorway") else others).append(c)
        return doors + others

    def _room_entry(self) -> list[Candidate]:
        return self._entry("room")

    def _elevator_entry(self) -> list[Candidate]:
        return self._entry("elevator")

    # -- explanations ------------------------------------------------------------------------
    def why_missing(self, feature: str) -> str:
        """Plain words for a feature with no candidate at all."""
        types = sorted(self.location.schema.node_types)

        def family_text(family: str, label: str) -> str:
            in_schema = [t for t in types if type_matches(t, family)]
            if not in_schema:
                return (f"needs a node of type {label} ({', '.join(KEYWORDS[family])}); the schema has none "
                        f"(node types: {', '.join(types)})")
            return f"the schema has {', '.join(in_schema)} but no usable node of that type is in the scene graph"

        if feature == "elevator_entry":
            return family_text("elevator", "ELEVATOR")
        if feature == "room_entry":
            return family_text("room", "ROOM")
        if feature == "intersection":
            return "needs an intersection: no node joins three or more edges"
        if feature == "blind_corner":
            return ("needs a BLIND CORNER: no node type names one (blind, corner) and no node is a turn whose "
                    "neighbours cannot see each other")
        if feature == "open_area":
            return (f"needs an OPEN AREA: no node type names one ({', '.join(KEYWORDS['open_area'])}) and no node "
                    f"has {OPEN_CLEARANCE_M:g} m of free space around it")
        if feature == "narrow_passage":
            return (f"needs a NARROW passage: no edge type says so ({', '.join(KEYWORDS['narrow_edge'])}) and no edge "
                    f"is narrower than {2 * NARROW_CLEARANCE_M:g} m")
        if feature == "doorway":
            return (f"needs a DOORWAY: no node type names one ({', '.join(KEYWORDS['doorway'])}) and no node is a "
                    f"pinch narrower than {2 * DOOR_CLEARANCE_M:g} m")
        return "needs a node with at least two edges (a route through it)"
