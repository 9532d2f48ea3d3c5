"""How close an extracted scene graph is to the one a person drew on the same map.

A person's node is found when an extracted node of a compatible type stands within `radius_m`
(recall); an extracted node is right when a person's node of a compatible type stands within
`radius_m` of it (precision). Types are compared through a table of the extractor's vocabulary, so a
person's graph written with another schema (a home's BEDROOM, a hospital's CORRIDOR) names which
extracted types count for each of its types.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from socnavgen.location.models import SceneGraph

# For each extracted type, the extracted types a person's node of that type may be matched by.
COMPATIBLE: dict[str, set[str]] = {
    "ROOM": {"ROOM", "OPEN AREA"},
    "OPEN AREA": {"ROOM", "OPEN AREA", "INTERSECTION"},
    "DOORWAY": {"DOORWAY", "NARROW PASSAGE"},
    "INTERSECTION": {"INTERSECTION", "OPEN AREA", "CORNER", "BLIND CORNER"},  # where corridor legs meet
    "CORNER": {"CORNER", "BLIND CORNER", "INTERSECTION"},
    "BLIND CORNER": {"BLIND CORNER", "CORNER", "INTERSECTION"},
    "DEAD END": {"DEAD END", "DOORWAY", "OPEN AREA"},
    "NARROW PASSAGE": {"NARROW PASSAGE", "DOORWAY", "SIMPLE NODE"},
    "SIMPLE NODE": {"SIMPLE NODE", "NARROW PASSAGE", "CORNER", "INTERSECTION"},
    "CORRIDOR": {"INTERSECTION", "CORNER", "BLIND CORNER", "SIMPLE NODE", "DEAD END", "NARROW PASSAGE",
                 "OPEN AREA"},
}


@dataclass
class Score:
    person_nodes: int
    extracted_nodes: int
    recall: float
    precision: float
    missed: list[str] = field(default_factory=list)  # "id TYPE (x, y): nearest compatible d m"

    @property
    def size_ratio(self) -> float:
        return self.extracted_nodes / max(1, self.person_nodes)


def compatible(person_type: str, extracted_type: str, aliases: dict[str, str] | None = None) -> bool:
    """Whether an extracted node of `extracted_type` may stand for a person's node of `person_type`
    (`aliases` maps a person's own type names onto the extractor's vocabulary first)."""
    canonical = (aliases or {}).get(person_type, person_type)
    return extracted_type in COMPATIBLE.get(canonical, {canonical})


def score(person: SceneGraph, extracted: SceneGraph, meters_per_pixel: float, *, radius_m: float = 2.0,
          aliases: dict[str, str] | None = None) -> Score:
    """Recall and precision of `extracted` against `person` within `radius_m`."""
    limit = radius_m / meters_per_pixel
    missed, found = [], 0
    for p in person.nodes:
        near = [math.dist(p.pos, e.pos) for e in extracted.nodes if compatible(p.type, e.type, aliases)]
        best = min(near, default=math.inf)
        if best <= limit:
            found += 1
        else:
            missed.append(f"{p.id} {p.type} ({p.pos[0]:g}, {p.pos[1]:g}): nearest compatible "
                          f"{best * meters_per_pixel:.1f} m")
    right = sum(1 for e in extracted.nodes
                if any(compatible(p.type, e.type, aliases) and math.dist(p.pos, e.pos) <= limit
                       for p in person.nodes))
    return Score(person_nodes=len(person.nodes), extracted_nodes=len(extracted.nodes),
                 recall=found / max(1, len(person.nodes)), precision=right / max(1, len(extracted.nodes)),
                 missed=missed)


def within_drawn_part(person: SceneGraph, extracted: SceneGraph, meters_per_pixel: float,
                      margin_m: float = 2.0) -> SceneGraph:
    """The extracted nodes within `margin_m` of what the person drew (their nodes and edges): a graph
    drawn over one lobby is compared with what was extracted there, not with the whole building."""
    from shapely.geometry import LineString, MultiPoint, Point
    from shapely.ops import unary_union

    pos = {n.id: tuple(n.pos) for n in person.nodes}
    shapes = [MultiPoint(list(pos.values()))] + [LineString([pos[e.source], pos[e.target]])
                                                 for e in person.links if e.source in pos and e.target in pos]
    drawn = unary_union(shapes).buffer(margin_m / meters_per_pixel)
    return SceneGraph(nodes=[n for n in extracted.nodes if drawn.covers(Point(tuple(n.pos)))])


def rooms_with_room_node(extracted: SceneGraph, rooms: list[tuple[float, float]], blocked: np.ndarray,
                         meters_per_pixel: float, room_type: str = "ROOM", door_m: float = 1.3) -> int:
    """How many of the rooms (one point inside each) have a ROOM node inside them. A room is the part
    of the floor around its point once every opening narrower than `door_m` is closed (a morphological opening of the free space), so a ROOM node seen through a door, or in
    a neighbouring room, does not count."""
    from scipy import ndimage

    free = ~blocked
    radius = door_m / 2 / meters_per_pixel
    core = ndimage.distance_transform_edt(free) > radius  # where a disc as wide as a door fits
    opened = ndimage.distance_transform_edt(~core) <= radius - 2  # the discs, a hair smaller: doors stay shut
    labels, _ = ndimage.label(opened & free)
    inside = {int(labels[int(n.pos[1]), int(n.pos[0])]) for n in extracted.nodes if n.type == room_type}
    inside.discard(0)
    return sum(1 for x, y in rooms if int(labels[int(y), int(x)]) in inside)
