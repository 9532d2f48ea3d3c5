"""The vocabulary and knobs of `location extract`, and how a node or edge gets its type from the
map's geometry (degree, clearance, turn angle, line of sight)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import networkx as nx
import numpy as np
from skimage.draw import line as raster_line

from socnavgen.bodies import ROBOT_PASSAGE_WIDTH
from socnavgen.location.models import Schema
from socnavgen.location.rooms import CORRIDOR_WIDTH_M

ROOM, INTERSECTION, CORNER, BLIND_CORNER = "ROOM", "INTERSECTION", "CORNER", "BLIND CORNER"
DEAD_END = "DEAD END"
OPEN_AREA, DOORWAY, NARROW_PASSAGE, SIMPLE_NODE = "OPEN AREA", "DOORWAY", "NARROW PASSAGE", "SIMPLE NODE"
PASSAGEWAY, NARROW_PASSAGEWAY = "PASSAGEWAY", "NARROW PASSAGEWAY"
EXTRACT_SCHEMA = Schema(
    node_types=[ROOM, DOORWAY, INTERSECTION, CORNER, BLIND_CORNER, DEAD_END, OPEN_AREA, NARROW_PASSAGE, SIMPLE_NODE],
    edge_types=[PASSAGEWAY, NARROW_PASSAGEWAY])
# a walled recess two people wide (an entrance, a bay) and this deep past its wall is a place of its own
RECESS_WIDTH_M, RECESS_DEPTH_M = 1.6, 0.5
SLOT_WIDTH_M = 0.6  # a dead-end branch whose outer half is narrower than shoulders is a gap, not a place


@dataclass
class ExtractOptions:
    """Knobs in metres so they mean the same on any map resolution."""

    detail: float = 1.0           # >1 = finer graph (shorter edges, less merging, more nodes per room), <1 = coarser
    min_spur_m: float = 1.0       # side branches shorter than this (or than the local width) are pruned
    narrow_width_m: float = 1.2   # passages narrower than this are NARROW (doorways, tight aisles)
    door_width_m: float = 2.0     # a short bottleneck up to this wide between wider space is a doorway
    open_width_m: float = 3.0     # a node with at least this much free width around it may be an OPEN AREA
    min_gap_m: float = 0.5        # gaps narrower than this are not walkable at all (a person does not fit)
    robot_width_m: float = ROBOT_PASSAGE_WIDTH  # no edge narrower than this (wall to wall) for the robot; 0 = keep all
    max_edge_m: float = 10.0      # at detail 1, straight corridor edges longer than this get intermediate nodes
    merge_m: float = 2.0          # at detail 1, nodes joined by a branch shorter than this are merged
    room_cover_m: float = 4.5     # at detail 1, every part of a room is within this of one of its nodes
    rooms: bool = True            # segment rooms (one ROOM node each); False = the bare skeleton graph
    keep_all_components: bool = False  # default: only the largest connected free area
    seed: int | None = None       # node ids are random; a seed makes them reproducible


class Geometry:
    """Per-map scalars in pixels, derived once from the options and the resolution."""

    def __init__(self, opts: ExtractOptions, mpp: float) -> None:
        density = max(opts.detail, 0.05)
        self.mpp = mpp
        self.gap_r = max(1.0, opts.min_gap_m / 2 / mpp)
        self.min_spur = opts.min_spur_m / min(density, 1.0) / mpp  # a coarser graph drops longer side branches
        self.merge = max(2.0, opts.merge_m / density / mpp)
        self.max_edge = max(4.0, opts.max_edge_m / density / mpp)
        self.narrow_half = round(opts.narrow_width_m / 2 / mpp, 6) + 1.0  # one pixel of rasterisation slack
        self.door_half = round(opts.door_width_m / 2 / mpp, 6) + 1.0
        self.recess_width = RECESS_WIDTH_M / mpp
        self.slot_half = SLOT_WIDTH_M / 2 / mpp
        self.recess_depth = RECESS_DEPTH_M / mpp
        self.corridor_half = round(CORRIDOR_WIDTH_M / 2 / mpp, 6) + 1.0
        self.open_half = round(opts.open_width_m / 2 / mpp, 6) - 1.0  # the same slack, the other way
        self.look = max(3.0, 1.5 / mpp)  # how far along each leg a corner's line-of-sight test looks
        self.room_cover_m = opts.room_cover_m / density
        self.wall_clearance: np.ndarray | None = None  # clearance from walls without specks, set per map


# ---------------------------------------------------------------- typing
def type_node(graph: nx.MultiGraph, n: int, coords: np.ndarray, walls: np.ndarray, clearance: np.ndarray,
              geo: Geometry, doors: set[int]) -> str:
    """Type from geometry; `walls` / `clearance` are the de-speckled obstacle map and its distances."""
    r, c = coords[n]
    here = clearance[r, c]
    deg = graph.degree(n)
    paths = [np.asarray(d["path"]) for _, _, d in graph.edges(n, data=True)]
    around = np.median(np.concatenate([clearance[coords[p, 0], coords[p, 1]] for p in paths])) if paths else 0
    if deg == 0 or (here >= geo.open_half and (deg == 1 or here >= 1.5 * around)):
        return OPEN_AREA
    if deg >= 3:
        return INTERSECTION
    if deg == 1:
        return DEAD_END
    if n in doors:
        return DOORWAY
    if here >= geo.open_half:  # a bend or a waypoint in a wide space: a person names the space, not the bend
        return OPEN_AREA
    (_, a, _), (_, b, _) = list(graph.edges(n, data=True))
    va, vb = coords[a] - coords[n], coords[b] - coords[n]
    cos = float(va @ vb) / max(1e-9, float(np.linalg.norm(va) * np.linalg.norm(vb)))
    turns = math.degrees(math.acos(max(-1.0, min(1.0, cos)))) <= 140  # legs turn by 40 degrees or more
    if turns:
        look = max(geo.look, 2 * here)
        pa = coords[n] + va * min(1.0, look / max(1e-9, np.linalg.norm(va)))
        pb = coords[n] + vb * min(1.0, look / max(1e-9, np.linalg.norm(vb)))
        rows, cols = raster_line(int(round(pa[0])), int(round(pa[1])), int(round(pb[0])), int(round(pb[1])))
        if walls[rows, cols].any():
            return BLIND_CORNER
    if turns:
        return CORNER
    if here < geo.narrow_half:
        return NARROW_PASSAGE
    # a waypoint beside an open space (a rack's end, a wide bay) stands in that space for a person
    k = int(max(2, 1.0 / geo.mpp))
    near = clearance[max(0, r - k):r + k + 1, max(0, c - k):c + k + 1]
    return OPEN_AREA if near.max() >= geo.open_half else SIMPLE_NODE


def type_edge(a: np.ndarray, b: np.ndarray, clearance: np.ndarray, geo: Geometry) -> str:
    rows, cols = raster_line(int(a[0]), int(a[1]), int(b[0]), int(b[1]))
    return NARROW_PASSAGEWAY if clearance[rows, cols].min() < geo.narrow_half else PASSAGEWAY
