"""Where the nodes of one room go, and how they join its doorways (used by location/rooms.py).

A room's node stands at the open spot nearest its middle; more nodes name the parts of a big room a
person walks to (the far end of a long room, the gym and the dining area of an open-plan house, the
corners of a hall), each where an existing node walks to it; the room's nodes are joined by a shortest
tree over the pairs that see each other and to every doorway, with waypoints where no straight
walkable line exists.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from socnavgen.bodies import PERSON_RADIUS
from socnavgen.location.traverse import edge_verdict, first_tight_pixel, segment_walkable

OPEN_SPOT_M = 0.75  # a room's node stands where two people pass (a 1.5 m disc fits), if there is such a spot
SIGHT_WIDTHS = 1.35  # a spot of a room in sight of one of its nodes is named by it up to this many room widths away ...
SIGHT_COVERS = 1.6  # ... and at most this many coverage radii (a long room has parts, a wide one is one place) ...
SIGHT_SOLIDITY = 0.9  # ... when it is one space seen at a glance: its floor fills this much of its convex hull
MAX_ROOM_NODES = 12  # nodes standing for one room at most
MAX_FAR_TRIES = 40  # far parts of a room tried for a node (those no node walks to are skipped)
DOOR_FRONT_DOORS = 3  # in a room with this many doorways, one farther than ...
DOOR_FRONT_FAR = 0.6  # ... this many coverage radii from the room's nodes ...
DOOR_FRONT_M = 1.5  # ... gets a node this far inside the room, on the way to the nearest one


def place_room_nodes(mask: np.ndarray, clearance: np.ndarray, door_points: list[tuple[int, int]],
                     meters_per_pixel: float, cover_m: float) -> list[tuple[int, int]]:
    """(row, col) of the nodes standing for one room: first the open spot nearest its middle (where a
    person writes the room's name: not squeezed between desks; seeing a doorway only breaks near-ties),
    then nodes for the parts of the room that node does not stand for (`_cover`): in a room seen at a
    glance, what lies beyond about its width from every node; in a room with parts round its corners,
    what lies beyond `cover_m`, each such node then moved to the middle of its part."""
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
    inner = mask & (clearance >= max(person, 0.6 / meters_per_pixel))
    # only the part of the room a person can walk to from the first node: furniture may wall off a nook
    reach, _ = ndimage.label(mask & (clearance >= min(person, float(clearance[best]))))
    inner &= reach == reach[best]
    if not inner.any():
        return nodes
    cover = cover_m / meters_per_pixel
    one_space, width = room_shape(mask)
    # a room seen at a glance is one place up to about its width past its node, however long its far side;
    # a room with parts round its corners (an open-plan house, a hall) has them named beyond `cover`
    sight = max(cover, min(SIGHT_COVERS * cover, SIGHT_WIDTHS * width)) if one_space else cover
    nodes = _cover(nodes, mask, inner, clearance, meters_per_pixel, cover, sight)
    return nodes if one_space else centre_parts(nodes, inner, clearance, meters_per_pixel)


def room_shape(mask: np.ndarray) -> tuple[bool, float]:
    """(whether the room is one space seen at a glance: its floor fills SIGHT_SOLIDITY of its convex hull,
    its widest free span in pixels)."""
    from skimage.morphology import convex_hull_image

    rows, cols = np.nonzero(mask)
    box = mask[rows.min():rows.max() + 1, cols.min():cols.max() + 1]
    width = 2 * float(ndimage.distance_transform_edt(np.pad(box, 1)).max())
    return bool(box.sum() >= SIGHT_SOLIDITY * convex_hull_image(box).sum()), width


def _cover(nodes: list[tuple[int, int]], mask: np.ndarray, inner: np.ndarray, clearance: np.ndarray, mpp: float,
           cover: float, sight: float) -> list[tuple[int, int]]:
    """Add nodes while some walkable spot of the room (`inner`) is neither within `cover` pixels of a node
    nor in sight of one (across the room, over its furniture) within `sight` pixels: near the
    farthest such spot, onto more clearance, where an existing node walks to it. A part no node walks to
    yet is skipped and tried again once another node is added."""
    ir, ic = np.nonzero(inner)
    seen = np.zeros(len(ir), bool)  # in sight of a node within `sight`
    skipped = np.zeros(len(ir), bool)
    nodes = list(nodes)
    for r, c in nodes:
        seen |= in_sight(mask, (r, c), sight)[ir, ic]
    tries = 0
    while len(nodes) < MAX_ROOM_NODES and tries < MAX_FAR_TRIES:
        d = np.min([np.hypot(ir - r, ic - c) for r, c in nodes], axis=0)
        d[seen | skipped] = 0.0
        far = int(np.argmax(d))
        if d[far] <= cover:
            break
        tries += 1
        # step from the far spot a little toward the room's middle, onto more clearance
        near = np.nonzero(np.hypot(ir - ir[far], ic - ic[far]) <= 0.5 * cover)[0]
        ranked = near[np.argsort(-clearance[ir[near], ic[near]])][:: max(1, len(near) // 40)]
        walk = [k for k in ranked if any(segment_walkable(clearance, (ic[k], ir[k]), (c, r), mpp) for r, c in nodes)]
        if not walk:  # else the best few a person walks to past a chair (THE traversability rule)
            walk = [k for k in ranked[:6] if any(edge_verdict(clearance, (ic[k], ir[k]), (c, r), mpp).level == "ok"
                                                 for r, c in nodes)]
        if not walk:  # behind furniture from every node so far: try the next far part of the room
            skipped[near] = True
            continue
        k = walk[0]  # one that an existing node walks to, so the room's edges are walkable
        nodes.append((int(ir[k]), int(ic[k])))
        seen |= in_sight(mask, nodes[-1], sight)[ir, ic]
        skipped[:] = False
    return nodes


def centre_parts(nodes: list[tuple[int, int]], inner: np.ndarray, clearance: np.ndarray, mpp: float,
                 rounds: int = 4) -> list[tuple[int, int]]:
    """Move every node but the room's own to the middle of the part of the room it stands for (the walkable
    spots nearer to it than to any other node): a person names the middle of the gym or the dining area,
    not its far corner. A node moves only to a spot from which a person walks straight to another node."""
    ir, ic = np.nonzero(inner)
    step = max(1, len(ir) // 4000)
    pts = np.stack([ir[::step], ic[::step]], axis=1)
    nodes = list(nodes)
    for _ in range(rounds):
        owner = np.argmin([np.hypot(pts[:, 0] - r, pts[:, 1] - c) for r, c in nodes], axis=0)
        moved = False
        for j in range(1, len(nodes)):
            mine = np.nonzero(owner == j)[0]
            if not len(mine):
                continue
            centre = pts[mine].mean(axis=0)
            order = mine[np.argsort(np.hypot(*(pts[mine] - centre).T))]
            for k in order[:: max(1, len(order) // 30)][:10]:  # the spots nearest the middle first
                spot = (int(pts[k, 0]), int(pts[k, 1]))
                if math.dist(spot, nodes[j]) < 2:
                    break
                if any(segment_walkable(clearance, (spot[1], spot[0]), (c, r), mpp)
                       for i, (r, c) in enumerate(nodes) if i != j):
                    nodes[j], moved = spot, True
                    break
        if not moved:
            break
    return nodes


def in_sight(mask: np.ndarray, origin: tuple[int, int], radius: float) -> np.ndarray:
    """Pixels of `mask` seen from `origin` (row, col) within `radius` pixels along straight lines that stay
    in `mask`: rays cast every half pixel of arc at the radius."""
    rays = max(64, int(4 * math.pi * radius))
    angles = np.linspace(0.0, 2 * math.pi, rays, endpoint=False)
    steps = np.arange(0.0, radius, 0.5)
    rows = np.rint(origin[0] + np.outer(np.sin(angles), steps)).astype(np.int64)
    cols = np.rint(origin[1] + np.outer(np.cos(angles), steps)).astype(np.int64)
    h, w = mask.shape
    inside = (rows >= 0) & (rows < h) & (cols >= 0) & (cols < w)
    rows, cols = np.clip(rows, 0, h - 1), np.clip(cols, 0, w - 1)
    clear = np.cumprod(inside & mask[rows, cols], axis=1).astype(bool)  # up to the first pixel off the room
    out = np.zeros_like(mask)
    out[rows[clear], cols[clear]] = True
    return out


def contract_close(graph, points: list[tuple[int, int]], clearance: np.ndarray, mpp: float, rooms: set[int],
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


def join_room(graph, ids: list[int], doors: list[int], points: list[tuple[int, int]], clearance: np.ndarray,
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

    vias: list[tuple[int, int]] = []
    i = 0
    while True:
        j = len(path) - 1
        while j > i + 1 and not straight_ok(path[i], path[j]):
            j -= 1
        if j == len(path) - 1:
            return vias
        vias.append(path[j])
        i = j
