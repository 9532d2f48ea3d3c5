"""Room segmentation of a map's free space, the way a person reads a floor plan.

Furniture and clutter (small obstacles standing free of the walls) are first filled in, so they
neither split rooms nor make nodes. The free space is then cut at the doorways (short bottlenecks
found on the skeleton); a cut that separates nothing, or only a room from a tight gap beside its own
table, is forgotten and the space cut again. Each piece is classified:
- ROOM: a compact piece with no structural obstacle inside, or a walled box much wider than a
  corridor whose beds or desks along the walls narrow its aisle (one ROOM node, plus OPEN AREA nodes
  when it is too large for one node to stand for all of it);
- corridor / hall: an elongated piece, or one with racks or walls inside (the skeleton graph is kept).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage
from skimage.morphology import skeletonize

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.location.traverse import edge_verdict, first_tight_pixel, segment_walkable

CLUTTER_SIDE_M = 3.5  # an obstacle free of the walls whose bounding box fits in this square is furniture ...
CLUTTER_AREA_M2 = 4.0  # ... when it also covers at most this area
CORRIDOR_WIDTH_M = 2.6  # pieces narrower than this ...
CORRIDOR_ASPECT = 2.5  # ... and at least this many times longer than wide are corridors ...
ROOM_FILL = 0.6  # ... unless their box is twice a corridor's width both ways and at least this full of floor
HALL_HOLES = 0.15  # a piece with blocks inside covering this much of it (or three blocks or more) is a hall
HALL_M2 = 200.0  # ... and so is any piece of at least this much floor
CLOSET_M2 = 6.0  # a dead-end piece behind one door this small is a room (an elevator) even when long
OPEN_SPOT_M = 0.75  # a room's node stands where two people pass (a 1.5 m disc fits), if there is such a spot
ROOM_M2_PER_COVER = 5.0  # a room gets one node per this many squared coverage radii of floor (~100 m2 at 4.5 m)
DOOR_FRONT_DOORS = 3  # in a room with this many doorways, one farther than ...
DOOR_FRONT_FAR = 0.6  # ... this many coverage radii from the room's nodes ...
DOOR_FRONT_M = 1.5  # ... gets a node this far inside the room, on the way to the nearest one


def furniture_mask(blocked: np.ndarray, meters_per_pixel: float) -> np.ndarray:
    """Blocked components that are furniture: not touching the image border, small in extent and area."""
    labels, count = ndimage.label(blocked, structure=np.ones((3, 3)))
    if count == 0:
        return np.zeros_like(blocked)
    keep = np.zeros(count + 1, bool)
    areas = np.bincount(labels.ravel(), minlength=count + 1)
    h, w = blocked.shape
    side, area = CLUTTER_SIDE_M / meters_per_pixel, CLUTTER_AREA_M2 / meters_per_pixel ** 2
    for label, box in enumerate(ndimage.find_objects(labels), start=1):
        if box is None:
            continue
        rows, cols = box
        on_border = rows.start == 0 or cols.start == 0 or rows.stop == h or cols.stop == w
        extent = max(rows.stop - rows.start, cols.stop - cols.start)
        keep[label] = not on_border and extent <= side and areas[label] <= area
    return keep[labels]


@dataclass
class Region:
    """One piece of the free space between doorways."""

    label: int
    kind: str  # "room" | "corridor"
    area_m2: float
    width_m: float
    hall: bool = False  # structural obstacles inside (racks, wall blocks)
    elongated: bool = False  # narrow and long: a corridor
    doors: list[int] = field(default_factory=list)  # skeleton node ids of the doorways on its boundary


def cut_at_doors(free: np.ndarray, door_points: dict[int, tuple[int, int]], clearance: np.ndarray) -> np.ndarray:
    """`free` with a disc removed at each doorway, just wide enough to close the opening."""
    cut = np.zeros_like(free)
    for r, c in door_points.values():
        radius = float(clearance[r, c]) + 2.0
        k = int(math.ceil(radius))
        r0, r1, c0, c1 = max(0, r - k), min(free.shape[0], r + k + 1), max(0, c - k), min(free.shape[1], c + k + 1)
        yy, xx = np.mgrid[r0:r1, c0:c1]
        cut[r0:r1, c0:c1] |= (yy - r) ** 2 + (xx - c) ** 2 <= radius ** 2
    return free & ~cut


def pieces_around(door_points: dict[int, tuple[int, int]], labels: np.ndarray,
                  clearance: np.ndarray) -> dict[int, set[int]]:
    """For every doorway, the labels of the pieces of free space just outside its cut."""
    around = {}
    h, w = labels.shape
    for d, (r, c) in door_points.items():
        inner = float(clearance[r, c]) + 2.0
        outer = inner + 3.0
        k = int(math.ceil(outer))
        r0, r1, c0, c1 = max(0, r - k), min(h, r + k + 1), max(0, c - k), min(w, c + k + 1)
        yy, xx = np.mgrid[r0:r1, c0:c1]
        dist2 = (yy - r) ** 2 + (xx - c) ** 2
        ring = labels[r0:r1, c0:c1][(dist2 > inner ** 2) & (dist2 <= outer ** 2)]
        around[d] = {int(v) for v in np.unique(ring[ring > 0])}
    return around


def side_gaps(around: dict[int, set[int]], regions: dict[int, Region]) -> set[int]:
    """Doorways of a passage piece open at two or more ends, all into one and the same room: the tight
    side of a table or a bed standing in that room, not a passage of its own. Returned to be dropped."""
    drop: set[int] = set()
    for label, region in regions.items():
        if region.kind != "corridor" or region.hall:
            continue
        doors = [d for d, labels in around.items() if label in labels]
        others = set().union(*(around[d] for d in doors)) - {label} if doors else set()
        if len(doors) >= 2 and len(others) == 1:  # open at both ends, into the same room
            (other,) = others
            if regions[other].kind == "room" and regions[other].area_m2 > region.area_m2:
                drop.update(doors)
    return drop


def classify_regions(labels: np.ndarray, count: int, structural: np.ndarray, clearance: np.ndarray,
                     meters_per_pixel: float) -> dict[int, Region]:
    """Room or corridor for every labelled piece of free space (label 0 is not free)."""
    regions: dict[int, Region] = {}
    boxes = ndimage.find_objects(labels)
    for label in range(1, count + 1):
        box = boxes[label - 1]
        if box is None:
            continue
        mask = labels[box] == label
        area = float(mask.sum()) * meters_per_pixel ** 2
        filled = ndimage.binary_fill_holes(mask)
        holes = filled & ~mask & structural[box]  # walls or racks inside: a hall, not a room
        spur = int(1.5 / meters_per_pixel)
        skel = _without_spurs(skeletonize(filled & ~holes), spur)
        widths = clearance[box][skel] if skel.any() else clearance[box][mask]
        width = 2.0 * float(np.median(widths)) * meters_per_pixel
        length = float(skel.sum()) * meters_per_pixel + 2 * spur * meters_per_pixel
        rows, cols = box
        box_h, box_w = (rows.stop - rows.start) * meters_per_pixel, (cols.stop - cols.start) * meters_per_pixel
        length = min(length, box_h + box_w - width)  # a spine fits in its box: a closet is not long
        # a walled box much wider than a corridor, mostly floor, is a room whose furniture narrows the aisles
        boxy = min(box_h, box_w) >= 2 * CORRIDOR_WIDTH_M and \
            float(filled.sum()) * meters_per_pixel ** 2 >= ROOM_FILL * box_h * box_w
        elongated = width <= CORRIDOR_WIDTH_M and length >= CORRIDOR_ASPECT * width and not boxy
        # racks or wall blocks standing inside make a hall; one table island in a room does not
        hall = bool(holes.any()) and (float(holes.sum()) >= HALL_HOLES * float(filled.sum())
                                      or ndimage.label(holes)[1] >= 3)
        # a floor this large is not one place: a person draws its lanes (a warehouse, an open-plan hall)
        hall = hall or area >= HALL_M2
        kind = "corridor" if hall or elongated else "room"
        regions[label] = Region(label=label, kind=kind, area_m2=area, width_m=width, hall=hall,
                                elongated=elongated)
    return regions


def _without_spurs(skeleton: np.ndarray, steps: int) -> np.ndarray:
    """The skeleton with its end pixels peeled `steps` times: branches into corners go, the spine stays."""
    skel = skeleton.copy()
    rows, cols = np.nonzero(skel)
    if not len(rows):
        return skel
    r0, c0 = rows.min(), cols.min()
    view = np.pad(skel[r0:rows.max() + 1, c0:cols.max() + 1], 1)  # work on the skeleton's box only
    kernel = np.ones((3, 3), np.uint8)
    for _ in range(steps):
        ends = view & (ndimage.convolve(view.astype(np.uint8), kernel, mode="constant") <= 2)
        if not ends.any() or ends.sum() == view.sum():
            break
        view &= ~ends
    skel[r0:rows.max() + 1, c0:cols.max() + 1] = view[1:-1, 1:-1]
    return skel


def place_room_nodes(mask: np.ndarray, clearance: np.ndarray, door_points: list[tuple[int, int]],
                     meters_per_pixel: float, cover_m: float) -> list[tuple[int, int]]:
    """(row, col) of the nodes standing for one room: first the open spot nearest its middle (where a
    person writes the room's name: not squeezed between desks; seeing a doorway only breaks near-ties),
    then, while some walkable part of the room is farther than `cover_m` from every node, the farthest
    such spot (people name the corners of a big room too)."""
    person = 0.4 / meters_per_pixel
    roomy = mask & (clearance >= OPEN_SPOT_M / meters_per_pixel)
    if not roomy.any():
        roomy = mask & (clearance >= person)
    if not roomy.any():
        roomy = mask & (clearance >= max(1.0, clearance[mask].max() * 0.8))
    rows, cols = np.nonzero(roomy)
    step = max(1, len(rows) // 400)
    order = np.arange(len(rows))[:: max(step, len(rows) // 150 or 1)]
    centre = np.argwhere(ndimage.binary_fill_holes(mask)).mean(axis=0)
    best, best_score = None, -math.inf
    for i in order:
        p = (int(rows[i]), int(cols[i]))
        seen = sum(segment_walkable(clearance, (p[1], p[0]), (d[1], d[0]), meters_per_pixel) for d in door_points)
        off_centre = math.dist(p, centre) * meters_per_pixel
        score = seen * 0.8 + 0.5 * min(clearance[p] * meters_per_pixel, 1.0) - off_centre
        if score > best_score:
            best, best_score = p, score
    assert best is not None
    nodes = [best]
    cover = cover_m / meters_per_pixel
    area_m2 = float(mask.sum()) * meters_per_pixel ** 2
    budget = max(3, round(area_m2 / (ROOM_M2_PER_COVER * cover_m ** 2)))  # a person names a big room's parts, not every spot
    inner = mask & (clearance >= max(person, 0.6 / meters_per_pixel))
    # only the part of the room a person can walk to from the first node: furniture may wall off a nook
    reach, _ = ndimage.label(mask & (clearance >= min(person, float(clearance[best]))))
    inner &= reach == reach[best]
    if not inner.any():
        return nodes
    ir, ic = np.nonzero(inner)
    while len(nodes) < min(budget, 12):
        d = np.min([np.hypot(ir - r, ic - c) for r, c in nodes], axis=0)
        far = int(np.argmax(d))
        if d[far] <= cover:
            break
        target = np.array([ir[far], ic[far]])
        # step from the far spot a little toward the room's middle, onto more clearance
        near = np.nonzero(np.hypot(ir - target[0], ic - target[1]) <= 0.5 * cover)[0]
        ranked = near[np.argsort(-clearance[ir[near], ic[near]])][:: max(1, len(near) // 40)]
        seen = [k for k in ranked if any(segment_walkable(clearance, (ic[k], ir[k]), (c, r), meters_per_pixel)
                                         for r, c in nodes)]
        if not seen:  # else the best few a person walks to past a chair (THE traversability rule)
            seen = [k for k in ranked[:6] if any(edge_verdict(clearance, (ic[k], ir[k]), (c, r),
                                                              meters_per_pixel).level == "ok" for r, c in nodes)]
        if not seen:  # the rest of the room is behind furniture from every node: a person stops naming parts
            break
        k = seen[0]  # one that an existing node sees, so the room's edges are walkable
        nodes.append((int(ir[k]), int(ic[k])))
    return nodes


@dataclass
class RoomGraph:
    """What the room step adds to the skeleton graph: room node ids (first of each room is its ROOM)."""

    coords: np.ndarray
    room_nodes: set[int] = field(default_factory=set)
    extra_nodes: set[int] = field(default_factory=set)
    regions: dict[int, Region] = field(default_factory=dict)
    false_doors: set[int] = field(default_factory=set)  # bottlenecks with the same piece on both sides


def _region_of_path(path: list[int], coords: np.ndarray, labels: np.ndarray) -> int:
    values = labels[coords[path, 0], coords[path, 1]]
    values = values[values > 0]
    return int(np.bincount(values).argmax()) if len(values) else 0


def replace_rooms(graph, coords: np.ndarray, doors: set[int], free: np.ndarray, walls: np.ndarray,
                  wall_clearance: np.ndarray, clearance: np.ndarray, meters_per_pixel: float,
                  cover_m: float) -> RoomGraph:
    """Cut the free space at the doorways, and replace the skeleton inside every room by room nodes
    joined to the room's doorways. `graph` (a networkx MultiGraph of skeleton pixel indices with a
    `path` per edge) is changed in place; new nodes get indices past the end of `coords`."""
    door_points = {d: (int(coords[d][0]), int(coords[d][1])) for d in doors if d in graph}
    for _ in range(8):  # cut, then forget the cuts that separate nothing (or only a room from its own nook)
        labels, count = ndimage.label(cut_at_doors(free, door_points, wall_clearance))
        around = pieces_around(door_points, labels, wall_clearance)
        false = {d for d, pieces in around.items() if len(pieces) < 2}
        if not false:  # the pieces are final unless a room's own side gap is among them
            regions = classify_regions(labels, count, walls, wall_clearance, meters_per_pixel)
            false = side_gaps(around, regions)
            if not false:
                break
        door_points = {d: p for d, p in door_points.items() if d not in false}
    else:  # out of rounds: the pieces of the doorways kept so far
        labels, count = ndimage.label(cut_at_doors(free, door_points, wall_clearance))
        regions = classify_regions(labels, count, walls, wall_clearance, meters_per_pixel)
    door_regions: dict[int, set[int]] = {d: set() for d in door_points}
    edge_regions = {}
    for u, v, key, data in graph.edges(keys=True, data=True):
        label = edge_regions[u, v, key] = _region_of_path(data["path"], coords, labels)
        for end in (u, v):
            if end in door_regions and label:
                door_regions[end].add(label)
    for label, region in regions.items():
        region.doors = sorted(d for d, regs in door_regions.items() if label in regs)
        if region.area_m2 < 2.0:  # a sliver between two cuts is a passage
            region.kind = "corridor"
        elif len(region.doors) == 1 and not region.hall and (not region.elongated or region.area_m2 <= CLOSET_M2):
            region.kind = "room"  # a dead-end space behind one door: closet, elevator, office
    rooms = {label for label, r in regions.items() if r.kind == "room"}
    for (u, v, key), label in edge_regions.items():
        if label in rooms:
            graph.remove_edge(u, v, key)
    for n in list(graph.nodes):
        r, c = coords[n]
        if n not in door_points and labels[r, c] in rooms:
            graph.remove_node(n)
    result = RoomGraph(coords=coords, regions=regions, false_doors={d for d in doors if d in graph} - set(door_points))
    points_all = [tuple(int(v) for v in p) for p in coords]
    for label in sorted(rooms):
        region = regions[label]
        mask = labels == label
        points = place_room_nodes(mask, clearance, [door_points[d] for d in region.doors], meters_per_pixel, cover_m)
        ids = list(range(len(points_all), len(points_all) + len(points)))
        points_all.extend(points)
        result.room_nodes.add(ids[0])
        result.extra_nodes.update(ids[1:])
        graph.add_nodes_from(ids)
        waypoints = _join_room(graph, ids, region.doors, points_all, clearance, meters_per_pixel, mask,
                               cover_m)
        result.extra_nodes.update(waypoints)
    _contract_close(graph, points_all, clearance, meters_per_pixel, result.room_nodes, result.extra_nodes)
    result.coords = np.array(points_all, dtype=coords.dtype).reshape(-1, 2)
    return result


def _contract_close(graph, points: list[tuple[int, int]], clearance: np.ndarray, mpp: float, rooms: set[int],
                    extras: set[int], limit_m: float = 1.0) -> None:
    """Fold an extra room node (coverage or waypoint) into a room-side neighbour closer than `limit_m`
    when the neighbour sees all its other neighbours: nodes ~2 m apart or more, as a person draws."""
    changed = True
    while changed:
        changed = False
        for v in sorted(extras):
            if v not in graph:
                continue
            for u in list(graph.neighbors(v)):
                if u not in rooms | extras or math.dist(points[u], points[v]) * mpp >= limit_m:
                    continue
                others = [w for w in graph.neighbors(v) if w != u]
                if all(_visible(points, clearance, u, w, mpp) for w in others):
                    graph.remove_node(v)
                    for w in others:
                        if not graph.has_edge(u, w):
                            graph.add_edge(u, w, path=[u, w], start=u)
                    extras.discard(v)
                    changed = True
                    break


def _visible(points: list[tuple[int, int]], clearance: np.ndarray, a: int, b: int, mpp: float) -> bool:
    """Whether a person walks straight from node a to b: the disc fits, or (THE traversability rule)
    only chairs or desks stand in the way with a short step round them, as a person draws across a room."""
    pa, pb = (points[a][1], points[a][0]), (points[b][1], points[b][0])
    return segment_walkable(clearance, pa, pb, mpp) or edge_verdict(clearance, pa, pb, mpp).level == "ok"


def _join_room(graph, ids: list[int], doors: list[int], points: list[tuple[int, int]], clearance: np.ndarray,
               mpp: float, mask: np.ndarray, cover_m: float) -> list[int]:
    """Room nodes joined by a shortest tree (pairs that see each other first), each doorway to the
    nearest room node it sees (through a node just inside the door when that room node is far); where
    two ends do not see each other a waypoint both see is added
    (returned), so every edge stays walkable."""
    import networkx as nx

    def dist(a: int, b: int) -> float:
        return math.dist(points[a], points[b])

    waypoints: list[int] = []
    rows, cols = np.nonzero(mask)
    margin = int(2.0 / mpp)  # the room and a doorway's approach
    ends = [points[n] for n in [*ids, *doors]]
    box = (slice(max(0, min(rows.min(), *(p[0] for p in ends)) - margin),
                 max(rows.max(), *(p[0] for p in ends)) + margin + 1),
           slice(max(0, min(cols.min(), *(p[1] for p in ends)) - margin),
                 max(cols.max(), *(p[1] for p in ends)) + margin + 1))
    spots = np.argwhere(mask & (clearance >= min(0.4 / mpp, clearance[mask].max())))
    spots = spots[:: max(1, len(spots) // 600)]

    def chain(a: int, vias: list[tuple[int, int]], b: int) -> None:
        waypoints.extend(add_chain(graph, points, a, vias, b))

    def add(a: int, b: int) -> None:
        if _visible(points, clearance, a, b, mpp) or not len(spots):
            chain(a, [], b)
            return
        ok = [tuple(p) for p in spots
              if segment_walkable(clearance, (p[1], p[0]), (points[a][1], points[a][0]), mpp)
              and segment_walkable(clearance, (p[1], p[0]), (points[b][1], points[b][0]), mpp)]
        if ok:
            chain(a, [min(ok, key=lambda p: math.dist(p, points[a]) + math.dist(p, points[b]))], b)
        else:
            chain(a, pulled_path(points[a], points[b], clearance, mpp, box), b)

    if len(ids) > 1:  # a shortest tree over the pairs that see each other, parts joined by walkable paths
        seen = nx.Graph()
        seen.add_nodes_from(ids)
        seen.add_weighted_edges_from((a, b, dist(a, b)) for i, a in enumerate(ids) for b in ids[i + 1:]
                                     if _visible(points, clearance, a, b, mpp))
        for a, b in nx.minimum_spanning_edges(seen, data=False):
            add(a, b)
        parts = [sorted(c) for c in nx.connected_components(seen)]
        joined = parts[0]
        for part in parts[1:]:
            a, b = min(((x, y) for x in joined for y in part), key=lambda pair: dist(*pair))
            add(a, b)
            joined = joined + part
    front_px = DOOR_FRONT_M / mpp
    for d in doors:
        seen = [n for n in ids if _visible(points, clearance, d, n, mpp)]
        n = min(seen or ids, key=lambda n: dist(d, n))
        # a big room people cross between several doors: they meet just inside each door
        front = None
        if seen and len(doors) >= DOOR_FRONT_DOORS and dist(d, n) * mpp > DOOR_FRONT_FAR * cover_m:
            front = _front_spot(points[d], points[n], front_px, clearance, mpp)
        if front is not None:
            chain(d, [front], n)
        else:
            add(d, n)
    return waypoints


def _front_spot(door: tuple[int, int], node: tuple[int, int], front_px: float, clearance: np.ndarray,
                mpp: float) -> tuple[int, int] | None:
    """The first spot at least `front_px` inside the room on the way from a doorway to a room node where
    a person stands clear of every obstacle (the way may pass a chair); None when there is none."""
    length = math.dist(door, node)
    for along in np.arange(front_px, length - front_px / 2, 2.0):
        t = along / length
        spot = (int(round(door[0] + t * (node[0] - door[0]))), int(round(door[1] + t * (node[1] - door[1]))))
        if clearance[spot] * mpp >= PERSON_RADIUS:
            return spot
    return None


def add_chain(graph, points: list[tuple[int, int]], a: int, vias: list[tuple[int, int]], b: int) -> list[int]:
    """Join nodes a and b through waypoints `vias` (row, col), appended to `points` as new nodes; the
    new node indices are returned."""
    added, previous = [], a
    for via in vias:
        points.append((int(via[0]), int(via[1])))
        added.append(len(points) - 1)
        graph.add_edge(previous, added[-1], path=[previous, added[-1]], start=previous)
        previous = added[-1]
    graph.add_edge(previous, b, path=[previous, b], start=previous)
    return added


def pulled_path(a: tuple[int, int], b: tuple[int, int], clearance: np.ndarray, mpp: float,
                window: tuple[slice, slice]) -> list[tuple[int, int]]:
    """Waypoints (row, col) of the shortest walkable way from a to b inside `window` (the room's box),
    pulled tight: each straight piece is one a person can walk, or, where only a tight gap leads there,
    one whose line is at least clear of obstacles (`location check` then warns that people squeeze).
    Empty when there is no such way (the edge is then left straight)."""
    from skimage.graph import MCP_Geometric

    need = max(1.0, min(0.4 / mpp, float(clearance[a]), float(clearance[b])))
    r0, c0 = max(0, window[0].start), max(0, window[1].start)
    view = clearance[window]
    la, lb = (a[0] - r0, a[1] - c0), (b[0] - r0, b[1] - c0)
    for threshold in dict.fromkeys((need, min(need, 2.0))):
        costs = np.where(view >= threshold, 1.0, np.inf)
        costs[la] = costs[lb] = 1.0
        mcp = MCP_Geometric(costs, fully_connected=True)
        cumulative, _ = mcp.find_costs([la], [lb])
        if math.isfinite(float(cumulative[lb])):
            break
    else:
        return []
    path = [(int(p[0]) + r0, int(p[1]) + c0) for p in mcp.traceback(lb)]

    def straight_ok(p: tuple[int, int], q: tuple[int, int]) -> bool:
        if threshold >= need:
            return segment_walkable(clearance, p[::-1], q[::-1], mpp)
        return first_tight_pixel(clearance, p[::-1], q[::-1], threshold) is None

    vias, i = [], 0
    while True:
        j = len(path) - 1
        while j > i + 1 and not straight_ok(path[i], path[j]):
            j -= 1
        if j == len(path) - 1:
            return vias
        vias.append(path[j])
        i = j
