"""Doorways and passage mouths on the skeleton graph of `location extract`: where a person sees one
space end and another begin. Each becomes a node that bounds the rooms (location/rooms.py)."""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
from scipy import ndimage

from socnavgen.location.extract_types import Geometry


def insert_doorways(graph: nx.MultiGraph, coords: np.ndarray, clearance: np.ndarray,
                    geo: Geometry) -> tuple[set[int], set[int]]:
    """Add a node at each short bottleneck (clearance much smaller on both sides) and where a corridor
    opens into a hall with both its walls ending: doors; and at each mouth where a long narrow passage
    opens into wider space (or at its middle when it leaves a junction): passage ends. Both bound rooms."""
    doors: set[int] = set()
    mouths: set[int] = set()
    window = int(max(6, 2.0 / geo.mpp))
    for u, v, key, data in list(graph.edges(keys=True, data=True)):
        path = data["path"]
        c = clearance[coords[path, 0], coords[path, 1]]
        labels, count = ndimage.label(c <= geo.door_half)
        cuts, ends = [], []
        for run in range(1, count + 1):
            idx = np.nonzero(labels == run)[0]
            low = c[idx].min()
            core = idx[c[idx] <= 1.15 * low + 1.0]  # the narrowest stretch: the opening itself
            s, e = int(core[0]), int(core[-1])
            left, right = c[max(0, s - window):s], c[e + 1:e + 1 + window]
            if (e - s) * geo.mpp > 1.5:  # a passage: mark where it opens into wider space
                if low <= geo.narrow_half:
                    marks = [i for i, side in ((s, left), (e, right))
                             if 3 <= i <= len(path) - 4 and len(side) and side.max() >= 1.5 * low]
                    # a passage leading off a junction is named by its middle and its far mouth (the mouth
                    # at the junction is that node); an aisle between two cross-aisles keeps both its ends
                    near_end = [i for i in (s, e) if min(i, len(path) - 1 - i) < geo.merge]
                    if len(near_end) == 1 and (e - s) > 2 * geo.merge:
                        marks = [i for i in marks if i not in near_end] + [(s + e) // 2]
                    elif len(marks) == 2 and (e - s) <= 2 * geo.merge:  # a short passage: one node names it
                        marks = [(s + e) // 2]
                    ends += marks
                continue
            if s < 3 or e > len(path) - 4:
                continue  # too close to an end
            mid = int(core[len(core) // 2])
            if len(left) and len(right) and min(left.max(), right.max()) >= 1.5 * low:
                cuts.append(mid)
        corridor_runs, count = ndimage.label(c <= geo.corridor_half)
        for run in range(1, count + 1):  # a corridor whose both walls end opens through a doorway into a hall
            idx = np.nonzero(corridor_runs == run)[0]
            low = c[idx].min()
            if (idx[-1] - idx[0]) * geo.mpp <= 1.5 or low <= geo.narrow_half:
                continue
            for i, side, way in ((int(idx[0]), c[max(0, idx[0] - window):idx[0]], -1),
                                 (int(idx[-1]), c[idx[-1] + 1:idx[-1] + 1 + window], 1)):
                if 3 <= i <= len(path) - 4 and len(side) and side.max() >= 1.5 * low \
                        and _walls_end(coords[path], i, way, low, clearance, window) \
                        and all(abs(i - j) > window for j in cuts + ends):
                    cuts.append(i)
        if cuts or ends:
            graph.remove_edge(u, v, key)
            added = dict(zip(sorted(set(cuts + ends)), split_at(graph, data, cuts + ends), strict=True))
            doors.update(added[i] for i in cuts)
            mouths.update(added[i] for i in ends if i not in cuts)
    return doors, mouths


def _walls_end(pts: np.ndarray, i: int, way: int, half: float, clearance: np.ndarray, window: int) -> bool:
    """Whether, a little ahead of path point i along the corridor's own line (it comes from `-way`),
    neither of its walls goes on: both points a corridor's width to either side have room around them.
    An alcove or a side door opens one wall only (the skeleton may turn into it; the corridor does not)."""
    back = pts[min(len(pts) - 1, max(0, i - way * window // 2))]
    d = (pts[i] - back).astype(float)
    if not d.any():
        return False
    d /= math.hypot(*d)
    ahead = pts[i] + d * window / 2
    normal = np.array([-d[1], d[0]])
    h, w = clearance.shape
    for sign in (1, -1):
        r, c = np.round(ahead + sign * 2 * half * normal).astype(int)
        if not (0 <= r < h and 0 <= c < w) or clearance[r, c] < 0.5 * half:
            return False
    return True


def split_at(graph: nx.MultiGraph, data: dict, cuts: list[int]) -> list[int]:
    """Split an edge's path at path indices `cuts`, adding a node at each; returns the new nodes."""
    path, bounds, added = data["path"], [0, *sorted(set(cuts)), len(data["path"]) - 1], []
    for a, b in zip(bounds, bounds[1:], strict=False):
        graph.add_edge(path[a], path[b], path=path[a:b + 1], start=path[a])
    for i in sorted(set(cuts)):
        added.append(path[i])
    return added


def add_exits(graph: nx.MultiGraph, coords: np.ndarray, walk: np.ndarray, blocked: np.ndarray,
              clearance: np.ndarray, mpp: float, min_width_m: float = 0.6) -> tuple[np.ndarray, set[int]]:
    """Doorways out of the mapped building: where the walkable floor opens, at least `min_width_m` wide,
    onto free ground nobody can walk (the strip of ground left around a building reaching the map's edge:
    outside, where the map ends). Each gets a node in the opening, joined to the nearest node a person
    walks to from it, or the nearest node already there becomes it. Returns the coordinates
    (new nodes appended) and the exit nodes."""
    from socnavgen.location.traverse import edge_verdict, segment_walkable

    labels, count = ndimage.label(~blocked & ~walk, structure=np.ones((3, 3)))
    if not len(graph):
        return coords, set()
    edge = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    frame = np.zeros_like(walk)
    frame[[0, -1], :] = frame[:, [0, -1]] = True
    outside = np.isin(labels, edge[edge > 0]) | (walk & frame)  # where the map ends, or ground nobody walks to it
    # the walkable floor within 0.3 m of the outside, through open ground only (never through a wall)
    zone = walk & ndimage.binary_dilation(outside, iterations=int(0.3 / mpp) + 1, mask=~blocked)
    runs, count = ndimage.label(zone, structure=np.ones((3, 3)))
    points = [tuple(int(v) for v in p) for p in coords]
    nodes = sorted(graph.nodes)
    exits: set[int] = set()
    for label, box in enumerate(ndimage.find_objects(runs), start=1):
        if box is None:
            continue
        grown = tuple(slice(max(0, b.start - 1), b.stop + 1) for b in box)
        # the walkable floor touching the outside: across the opening, as wide as it (a gap nobody fits in
        # is not entered by the walkable floor, which only touches its inner end)
        touch = (runs[grown] == label) & ndimage.binary_dilation(outside[grown], structure=np.ones((3, 3)))
        rows, cols = np.nonzero(touch)
        if not len(rows) or math.hypot(np.ptp(rows) + 1, np.ptp(cols) + 1) * mpp < min_width_m:
            continue
        centre = np.array([(box[0].start + box[0].stop) / 2, (box[1].start + box[1].stop) / 2])
        reach = int(0.6 / mpp) + 1  # the node stands in the opening or just inside it
        r0, c0 = max(0, int(centre[0]) - reach), max(0, int(centre[1]) - reach)
        rows, cols = np.nonzero(walk[r0:int(centre[0]) + reach + 1, c0:int(centre[1]) + reach + 1])
        rows, cols = rows + r0, cols + c0
        near = np.hypot(rows - centre[0], cols - centre[1]) <= reach
        if not near.any():
            continue
        k = int(np.argmax(np.where(near, clearance[rows, cols], -1.0)))
        spot = (int(rows[k]), int(cols[k]))
        closest = min(nodes, key=lambda n: math.dist(points[n], spot))
        if math.dist(points[closest], spot) * mpp <= 1.0:
            exits.add(closest)
            continue
        by_distance = sorted(nodes, key=lambda n: math.dist(points[n], spot))
        # the nearest node a person walks to from it (straight, or past a chair: THE traversability rule)
        target = next((n for n in by_distance[:8] if segment_walkable(clearance, spot[::-1], points[n][::-1], mpp)
                       or edge_verdict(clearance, spot[::-1], points[n][::-1], mpp).level == "ok"), by_distance[0])
        points.append(spot)
        graph.add_edge(len(points) - 1, target, path=[len(points) - 1, target], start=len(points) - 1)
        exits.add(len(points) - 1)
    return np.array(points, dtype=coords.dtype).reshape(-1, 2), exits
