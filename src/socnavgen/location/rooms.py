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

from socnavgen.location.room_nodes import contract_close, join_room, place_room_nodes

CLUTTER_SIDE_M = 3.5  # an obstacle free of the walls whose bounding box fits in this square is furniture ...
CLUTTER_AREA_M2 = 4.0  # ... when it also covers at most this area
CORRIDOR_WIDTH_M = 2.6  # pieces narrower than this ...
CORRIDOR_ASPECT = 2.5  # ... and at least this many times longer than wide are corridors ...
ROOM_FILL = 0.6  # ... unless their box is twice a corridor's width both ways and at least this full of floor
HALL_HOLES = 0.15  # a piece with blocks inside covering this much of it (or three blocks or more) is a hall
HALL_M2 = 200.0  # ... and so is any piece of at least this much floor ...
STORE_BLOCKS, STORE_BLOCK_M2 = 3, 3.0  # ... or one with this many pieces of furniture this big (shelves, pallets)
CLOSET_M2 = 6.0  # a dead-end piece behind one door this small is a room (an elevator) even when narrow ...
CLOSET_WIDER = 1.2  # ... unless it is no wider than this times its door and twice as long as wide: the end of
# the passage through that door (a dead-end aisle between racks), not a place of its own


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
    widest_m: float = 0.0  # the widest disc that fits in it
    long_side_m: float = 0.0  # the longer side of its bounding box
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


def big_blocks(furniture: np.ndarray, meters_per_pixel: float) -> np.ndarray:
    """The pieces of furniture of STORE_BLOCK_M2 or more (shelves, pallet stacks, a bed), labelled."""
    labels, count = ndimage.label(furniture, structure=np.ones((3, 3)))
    big = np.bincount(labels.ravel(), minlength=count + 1) * meters_per_pixel ** 2 >= STORE_BLOCK_M2
    big[0] = False
    return np.where(big[labels], labels, 0)


def classify_regions(labels: np.ndarray, count: int, structural: np.ndarray, clearance: np.ndarray,
                     meters_per_pixel: float, blocks: np.ndarray | None = None) -> dict[int, Region]:
    """Room or corridor for every labelled piece of free space (label 0 is not free); `blocks`: the big
    furniture (big_blocks)."""
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
        # a floor this large is not one place, nor one holding several shelves or pallet stacks (a room holds
        # a bed or a sofa): a person draws its lanes (a warehouse, a store, an open-plan hall)
        stored = 0 if blocks is None else int((np.unique(blocks[box][filled]) > 0).sum())
        hall = hall or area >= HALL_M2 or stored >= STORE_BLOCKS
        kind = "corridor" if hall or elongated else "room"
        regions[label] = Region(label=label, kind=kind, area_m2=area, width_m=width, hall=hall,
                                elongated=elongated, widest_m=2.0 * float(clearance[box][mask].max()) * meters_per_pixel,
                                long_side_m=max(box_h, box_w))
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
                  cover_m: float, blocks: np.ndarray | None = None) -> RoomGraph:
    """Cut the free space at the doorways, and replace the skeleton inside every room by room nodes
    joined to the room's doorways. `graph` (a networkx MultiGraph of skeleton pixel indices with a
    `path` per edge) is changed in place; new nodes get indices past the end of `coords`."""
    door_points = {d: (int(coords[d][0]), int(coords[d][1])) for d in doors if d in graph}
    for _ in range(8):  # cut, then forget the cuts that separate nothing (or only a room from its own nook)
        labels, count = ndimage.label(cut_at_doors(free, door_points, wall_clearance))
        around = pieces_around(door_points, labels, wall_clearance)
        false = {d for d, pieces in around.items() if len(pieces) < 2}
        if not false:  # the pieces are final unless a room's own side gap is among them
            regions = classify_regions(labels, count, walls, wall_clearance, meters_per_pixel, blocks)
            false = side_gaps(around, regions)
            if not false:
                break
        door_points = {d: p for d, p in door_points.items() if d not in false}
    else:  # out of rounds: the pieces of the doorways kept so far
        labels, count = ndimage.label(cut_at_doors(free, door_points, wall_clearance))
        regions = classify_regions(labels, count, walls, wall_clearance, meters_per_pixel, blocks)
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
        elif len(region.doors) == 1 and not region.hall:
            door_m = 2 * float(wall_clearance[door_points[region.doors[0]]]) * meters_per_pixel
            if region.widest_m < min(CORRIDOR_WIDTH_M, CLOSET_WIDER * door_m) \
                    and region.long_side_m >= 2 * region.widest_m:
                region.kind = "corridor"  # as narrow as its door and long: a passage's dead end (an aisle)
            elif not region.elongated or region.area_m2 <= CLOSET_M2:
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
    points_all = [(int(p[0]), int(p[1])) for p in coords]  # (row, col) pixels
    for label in sorted(rooms):
        region = regions[label]
        mask = labels == label
        points = place_room_nodes(mask, clearance, [door_points[d] for d in region.doors], meters_per_pixel, cover_m)
        ids = list(range(len(points_all), len(points_all) + len(points)))
        points_all.extend(points)
        result.room_nodes.add(ids[0])
        result.extra_nodes.update(ids[1:])
        graph.add_nodes_from(ids)
        waypoints = join_room(graph, ids, region.doors, points_all, clearance, meters_per_pixel, mask,
                               cover_m)
        result.extra_nodes.update(waypoints)
    contract_close(graph, points_all, clearance, meters_per_pixel, result.room_nodes, result.extra_nodes)
    result.coords = np.array(points_all, dtype=coords.dtype).reshape(-1, 2)
    return result
