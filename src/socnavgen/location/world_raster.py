"""Slice a world's collision geometry between ankle and head height into an occupancy grid.

For each shape, the part of its surface inside the slab [floor + ankle, floor + head] is projected
onto the floor: horizontal and sloped faces as filled areas, vertical faces as lines. A closed solid
(a shelf, a wall) is also cut at the slab's bottom and top; the inside of those cuts is the solid's
interior. The grid then marks the projected surface as occupied (what a laser at any height of the
slab would hit) and the interior behind it as unknown, as a map_server map of a scanned room shows a
shelf: an occupied outline around unknown space. Floors and roofs lie outside the slab and never
count. The footprint of a shape is computed once per (geometry, tilt, height) and moved by each
instance's yaw and position, so 2,000 copies of a shelf cost one slice.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from socnavgen.bodies import PERSON_HEIGHT
from socnavgen.location.sdf import Shape
from socnavgen.location.world_mesh import MeshError, MeshLibrary, Triangles, extent

OPEN_MARGIN = 1.5  # m of ground kept round a world standing in open ground: people walk round its outer things
ENCLOSED = 0.7  # ... unless its outermost obstacles line this much of its outline (a building: walls, a door)
HEIGHT_CLASSES = (("low", 1.0), ("waist to head", 2.0), ("tall", math.inf))  # top of an obstacle, metres
MAX_OBJECT_M = 5_000.0  # one collision shape wider than 5 km is an absurd scale, not a building


@dataclass
class SliceOptions:
    resolution: float = 0.05  # metres per cell (nav2's usual)
    ankle: float = 0.1  # the slab starts here above the floor: a carpet, a door sill, a floor tile are not obstacles
    head: float = PERSON_HEIGHT  # and ends here: a door lintel, a ceiling lamp or a roof are not obstacles
    floor_z: float = 0.0
    margin: float = 0.3  # floor kept around the outermost obstacle: narrower than a person, so the ground
    # around a building never joins its walkable floor (OPEN_MARGIN round a world with no outer walls)
    bounds: tuple[float, float, float, float] | None = None  # (xmin, ymin, xmax, ymax) in metres, or automatic


@dataclass
class Footprint:
    """A shape's slab footprint in its own yaw-free frame (metres): polygons as rings with a polygon
    id each (filled even-odd per polygon), and segments stroked cell by cell."""

    surface_rings: list[np.ndarray]
    surface_ids: list[int]
    solid_rings: list[np.ndarray]
    solid_ids: list[int]
    lines: np.ndarray  # (m, 2, 2)
    top: float  # highest point of the shape (world z), for the overhead's colours


@dataclass
class Raster:
    """Occupancy on a grid whose row 0 is the BOTTOM row (world y grows with the row)."""

    origin: tuple[float, float]
    resolution: float
    occupied: np.ndarray  # surface cells
    interior: np.ndarray  # inside a solid, behind its surface
    height_class: np.ndarray  # int8: -1 free, else index into HEIGHT_CLASSES of the tallest obstacle there
    problems: list[tuple[str, str]] = field(default_factory=list)  # (shape path, what)
    footprints: int = 0


def _rings(geom: object) -> tuple[list[np.ndarray], list[int], list[np.ndarray]]:
    """Polygon rings (with polygon ids) and bare line strings of a shapely geometry."""
    import shapely

    rings, ids, lines = [], [], []
    for k, part in enumerate(shapely.get_parts(geom)):
        if part.geom_type == "Polygon" and not part.is_empty:
            rings.append(np.asarray(part.exterior.coords)[:, :2])
            ids.append(k)
            for hole in part.interiors:
                rings.append(np.asarray(hole.coords)[:, :2])
                ids.append(k)
        elif part.geom_type in ("LineString", "LinearRing"):
            lines.append(np.asarray(part.coords)[:, :2])
        elif part.geom_type.startswith("Multi") or part.geom_type == "GeometryCollection":
            r, i, li = _rings(part)
            rings += r
            ids += [k * 100_000 + j for j in i]
            lines += li
    return rings, ids, lines


def _even_odd_faces(segments: np.ndarray) -> list:
    """The faces of a closed section (segments (n, 2, 2)) that lie inside the solid (odd crossings)."""
    import shapely

    if len(segments) < 3:
        return []
    lines = shapely.set_precision(shapely.linestrings(segments), 1e-6)
    faces = list(shapely.get_parts(shapely.polygonize(lines)))
    inside = []
    a, b = segments[:, 0], segments[:, 1]
    for face in faces:
        if face.area < 1e-8:
            continue
        px, py = np.asarray(face.representative_point().coords)[0]
        crosses = (a[:, 1] > py) != (b[:, 1] > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = a[:, 0] + (py - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        if int(np.count_nonzero(crosses & (x > px))) % 2 == 1:
            inside.append(face)
    return inside


def footprint(tris: Triangles, tilt: np.ndarray, tz: float, z0: float, z1: float) -> Footprint | None:
    """Slab footprint of triangles rotated by `tilt` (3x3) and lifted by `tz`, slab [z0, z1]."""
    import shapely
    import trimesh

    V = tris.vertices @ tilt.T
    V[:, 2] += tz
    top = float(V[:, 2].max())
    zs = V[tris.faces][:, :, 2]
    keep = (zs.max(axis=1) >= z0) & (zs.min(axis=1) <= z1)
    if not keep.any():
        return None
    v, f, _ = trimesh.intersections.slice_faces_plane(V, tris.faces[keep], [0, 0, 1], [0, 0, z0])
    if len(f):
        v, f, _ = trimesh.intersections.slice_faces_plane(v, f, [0, 0, -1], [0, 0, z1])
    parts = []
    seg_list = []
    if len(f):
        P = v[f][:, :, :2]
        area2 = np.abs((P[:, 1, 0] - P[:, 0, 0]) * (P[:, 2, 1] - P[:, 0, 1]) -
                       (P[:, 1, 1] - P[:, 0, 1]) * (P[:, 2, 0] - P[:, 0, 0]))
        flat = area2 > 1e-8
        if flat.any():
            parts.append(shapely.union_all(shapely.polygons(P[flat]), grid_size=1e-5))
        edges = np.concatenate([P[~flat][:, [0, 1]], P[~flat][:, [1, 2]], P[~flat][:, [2, 0]]])
        edges = edges[np.linalg.norm(edges[:, 1] - edges[:, 0], axis=1) > 1e-6]
        if len(edges):
            swap = (edges[:, 0, 0] > edges[:, 1, 0]) | ((edges[:, 0, 0] == edges[:, 1, 0]) &
                                                        (edges[:, 0, 1] > edges[:, 1, 1]))
            edges[swap] = edges[swap][:, ::-1]
            seg_list.append(np.unique(np.round(edges.reshape(-1, 4), 6), axis=0).reshape(-1, 2, 2))
    solids = []
    mesh = trimesh.Trimesh(V, tris.faces, process=True)
    for z in (z0 + 1e-4, z1 - 1e-4):
        if V[:, 2].min() < z < V[:, 2].max():
            section = trimesh.intersections.mesh_plane(mesh, [0, 0, 1], [0, 0, z])
            if len(section):
                solids += _even_odd_faces(np.asarray(section)[:, :, :2])
    surface = shapely.union_all(parts) if parts else shapely.Polygon()
    solid = shapely.union_all(solids) if solids else shapely.Polygon()
    s_rings, s_ids, s_lines = _rings(surface)
    d_rings, d_ids, _ = _rings(solid)
    lines = [np.stack([ln[:-1], ln[1:]], axis=1) for ln in s_lines if len(ln) > 1] + seg_list
    return Footprint(s_rings, s_ids, d_rings, d_ids,
                     np.concatenate(lines) if lines else np.zeros((0, 2, 2)), top)


def split_yaw(pose: np.ndarray) -> tuple[float, np.ndarray]:
    """(yaw, tilt) with R = Rz(yaw) @ tilt: a shape turned about z only has tilt = identity."""
    R = pose[:3, :3]
    yaw = math.atan2(R[1, 0], R[0, 0]) if abs(R[2, 0]) < 0.999999 else math.atan2(-R[0, 1], R[1, 1])
    c, s = math.cos(-yaw), math.sin(-yaw)
    return yaw, np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ R


# ---------------------------------------------------------------- the grid
def fill_rings(shape: tuple[int, int], rings: list[np.ndarray], ids: np.ndarray) -> np.ndarray:
    """Cells whose centre is inside a polygon (even-odd within each polygon id; rings in cell units
    where cell (i, j) has its centre at (i, j))."""
    h, w = shape
    out = np.zeros(shape, dtype=bool)
    keep = [k for k, r in enumerate(rings) if len(r) >= 4]
    if not keep:
        return out
    rings, ids = [rings[k] for k in keep], np.asarray(ids)[keep]
    a = np.concatenate([r[:-1] for r in rings])
    b = np.concatenate([r[1:] for r in rings])
    g = np.repeat(ids, [len(r) - 1 for r in rings])
    lo = np.maximum(np.ceil(np.minimum(a[:, 1], b[:, 1])), 0).astype(np.int64)
    hi = np.minimum(np.ceil(np.maximum(a[:, 1], b[:, 1])) - 1, h - 1).astype(np.int64)
    n = np.maximum(hi - lo + 1, 0)
    if n.sum() == 0:
        return out
    seg = np.repeat(np.arange(len(a)), n)
    rows = lo[seg] + (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n))
    t = (rows - a[seg, 1]) / (b[seg, 1] - a[seg, 1])
    xs = a[seg, 0] + t * (b[seg, 0] - a[seg, 0])
    order = np.lexsort((xs, rows, g[seg]))
    xs, rows, groups = xs[order], rows[order], g[seg][order]
    key = groups.astype(np.int64) * (h + 1) + rows
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    lengths = np.diff(np.r_[starts, len(key)])
    if (lengths % 2).any():  # an unclosed ring (never from shapely): drop its rows rather than streak
        bad = np.repeat(lengths % 2 == 1, lengths)
        xs, rows = xs[~bad], rows[~bad]
    xa, xb, r = xs[0::2], xs[1::2], rows[0::2]
    ca = np.maximum(np.ceil(xa), 0).astype(np.int64)
    cb = np.minimum(np.floor(xb), w - 1).astype(np.int64)
    ok = ca <= cb
    diff = np.zeros((h, w + 1), dtype=np.int32)
    np.add.at(diff, (r[ok], ca[ok]), 1)
    np.add.at(diff, (r[ok], cb[ok] + 1), -1)
    return np.cumsum(diff[:, :w], axis=1) > 0


def stroke(shape: tuple[int, int], segments: np.ndarray) -> np.ndarray:
    """Cells a segment passes through (sampled every half cell; segments (m, 2, 2) in cell units)."""
    h, w = shape
    out = np.zeros(shape, dtype=bool)
    if len(segments) == 0:
        return out
    a, b = segments[:, 0], segments[:, 1]
    n = np.ceil(np.linalg.norm(b - a, axis=1) * 2).astype(np.int64) + 1
    seg = np.repeat(np.arange(len(a)), n)
    k = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    t = k / np.maximum(n[seg] - 1, 1)
    pts = np.rint(a[seg] + t[:, None] * (b[seg] - a[seg])).astype(np.int64)
    ok = (pts[:, 0] >= 0) & (pts[:, 0] < w) & (pts[:, 1] >= 0) & (pts[:, 1] < h)
    out[pts[ok, 1], pts[ok, 0]] = True
    return out


@dataclass
class Placed:
    """Footprints moved to the world, gathered per height class."""

    surface_rings: list[np.ndarray] = field(default_factory=list)
    surface_ids: list[int] = field(default_factory=list)
    solid_rings: list[np.ndarray] = field(default_factory=list)
    solid_ids: list[int] = field(default_factory=list)
    lines: list[np.ndarray] = field(default_factory=list)
    next_id: int = 0

    def add(self, fp: Footprint, yaw: float, tx: float, ty: float) -> None:
        c, s = math.cos(yaw), math.sin(yaw)
        R = np.array([[c, s], [-s, c]])  # row vectors: p @ R == Rz(yaw) p
        t = np.array([tx, ty])
        base = self.next_id
        self.surface_rings += [r @ R + t for r in fp.surface_rings]
        self.surface_ids += [base + i for i in fp.surface_ids]
        self.solid_rings += [r @ R + t for r in fp.solid_rings]
        self.solid_ids += [base + i for i in fp.solid_ids]
        if len(fp.lines):
            self.lines.append(fp.lines @ R + t)
        self.next_id = base + 1 + max([*fp.surface_ids, *fp.solid_ids, 0])

    def bounds(self) -> tuple[float, float, float, float] | None:
        pts = [r for r in self.surface_rings + self.solid_rings] + [ln.reshape(-1, 2) for ln in self.lines]
        if not pts:
            return None
        allp = np.concatenate(pts)
        return float(allp[:, 0].min()), float(allp[:, 1].min()), float(allp[:, 0].max()), float(allp[:, 1].max())


def slice_shapes(shapes: list[Shape], options: SliceOptions, library: MeshLibrary | None = None,
                 progress: Callable[[int, int], None] | None = None) -> tuple[list[Placed], list[tuple[str, str]], int]:
    """Footprints of every shape, placed in the world, per height class; problems; distinct footprints."""
    library = library or MeshLibrary()
    z0, z1 = options.floor_z + options.ankle, options.floor_z + options.head
    cache: dict[tuple, Footprint | None] = {}
    placed = [Placed() for _ in HEIGHT_CLASSES]
    problems: list[tuple[str, str]] = []
    for index, shape in enumerate(shapes):
        if progress is not None and index % 50 == 0:
            progress(index, len(shapes))
        try:
            tris = library.get(shape.geometry)
        except MeshError as exc:
            problems.append((shape.path, str(exc)))
            continue
        if extent(tris) > MAX_OBJECT_M:
            problems.append((shape.path, f"is {extent(tris):.3g} m across (absurd size or scale): skipped"))
            continue
        yaw, tilt = split_yaw(shape.pose)
        tz = float(shape.pose[2, 3])
        geom = shape.geometry
        key = (geom.kind, geom.size, str(geom.mesh), geom.submesh, geom.scale, geom.points,
               tuple(np.round(tilt, 5).ravel()), round(tz, 5))
        if key not in cache:
            try:
                cache[key] = footprint(tris, tilt, tz, z0, z1)
            except Exception as exc:  # geometry libraries raise many types on degenerate input
                problems.append((shape.path, f"cannot slice: {type(exc).__name__}: {str(exc)[:120]}"))
                cache[key] = None
        fp = cache[key]
        if fp is None:
            continue
        cls = next(i for i, (_, limit) in enumerate(HEIGHT_CLASSES) if fp.top - options.floor_z < limit)
        placed[cls].add(fp, yaw, float(shape.pose[0, 3]), float(shape.pose[1, 3]))
    if progress is not None:
        progress(len(shapes), len(shapes))
    return placed, problems, len(cache)


def rasterize(placed: list[Placed], options: SliceOptions, max_cells: int,
              grid: tuple[tuple[float, float], tuple[int, int]] | None = None) -> Raster:
    """The grid: origin on a multiple of the resolution, covering the obstacles plus the margin (or the
    `grid` given: origin and (height, width) of another raster, so two slabs share their cells)."""
    from socnavgen.errors import ValidationFailed

    res = options.resolution
    if grid is not None:
        (ox, oy), (h, w) = grid
        xmin, ymin, xmax, ymax = ox, oy, ox + w * res, oy + h * res
    elif options.bounds is not None:
        xmin, ymin, xmax, ymax = options.bounds
    else:
        boxes = [b for b in (p.bounds() for p in placed) if b is not None]
        if not boxes:
            raise ValidationFailed("nothing in the world stands between ankle and head height: no map to make",
                                   hint="check --ankle/--head/--floor-z, and that the models were found")
        xmin = min(b[0] for b in boxes) - options.margin
        ymin = min(b[1] for b in boxes) - options.margin
        xmax = max(b[2] for b in boxes) + options.margin
        ymax = max(b[3] for b in boxes) + options.margin
    if grid is None:
        ox, oy = round(math.floor(xmin / res) * res, 9), round(math.floor(ymin / res) * res, 9)
        w, h = math.ceil((xmax - ox) / res), math.ceil((ymax - oy) / res)
    if w <= 0 or h <= 0:
        raise ValidationFailed("the map bounds are empty", hint="give --bounds xmin ymin xmax ymax with xmin < xmax")
    if w * h > max_cells:
        raise ValidationFailed(f"the map would be {w} x {h} cells ({(xmax - xmin):.0f} m x {(ymax - ymin):.0f} m at "
                               f"{res} m), more than {max_cells} cells",
                               hint="use a coarser --resolution, or --bounds to map a part of the world")
    shape = (h, w)

    def cells(points: np.ndarray) -> np.ndarray:
        return (points - np.array([ox, oy])) / res - 0.5

    occupied = np.zeros(shape, dtype=bool)
    interior = np.zeros(shape, dtype=bool)
    height_class = np.full(shape, -1, dtype=np.int8)
    for cls, p in enumerate(placed):
        surf = fill_rings(shape, [cells(r) for r in p.surface_rings], np.asarray(p.surface_ids, dtype=np.int64))
        edges = [np.stack([cells(r[:-1]), cells(r[1:])], axis=1) for r in p.surface_rings + p.solid_rings]
        edges += [cells(ln.reshape(-1, 2)).reshape(-1, 2, 2) for ln in p.lines]
        surf |= stroke(shape, np.concatenate(edges) if edges else np.zeros((0, 2, 2)))
        solid = fill_rings(shape, [cells(r) for r in p.solid_rings], np.asarray(p.solid_ids, dtype=np.int64))
        occupied |= surf
        interior |= solid
        height_class[surf | solid] = cls  # classes go from low to tall: the tallest wins
    return Raster(origin=(ox, oy), resolution=res, occupied=occupied, interior=interior & ~occupied,
                  height_class=height_class)


def enclosed(raster: Raster, options: SliceOptions) -> bool:
    """Whether the world's outermost obstacles line most of the map's outline (a building's walls, broken
    by a door or two) rather than stand in open ground (rows of shelves, pillars): then the narrow
    margin keeps the ground outside from joining its floor; else people walk round the outer things."""
    band = max(1, round((options.margin + 0.3) / options.resolution))
    blocked = raster.occupied | raster.interior
    h, w = blocked.shape
    lined = sum(int(side.sum()) for side in (blocked[:band].any(axis=0), blocked[-band:].any(axis=0),
                                              blocked[:, :band].any(axis=1), blocked[:, -band:].any(axis=1)))
    return lined >= ENCLOSED * 2 * (h + w)


OCCUPIED, UNKNOWN, FREE = 0, 205, 254  # map_saver's trinary grey levels


def trinary(raster: Raster) -> np.ndarray:
    """The map image (row 0 = TOP, as a PGM is stored): occupied 0, unknown 205, free 254.

    As in a map made by scanning the world from its floor: when the building is closed, the ground
    outside it (free space touching the map's edge) is unknown, and a surface no free cell touches
    (the back of an outer wall, the inside of a pillar) is unknown rather than occupied."""
    from scipy import ndimage

    blocked = raster.occupied | raster.interior
    free = ~blocked
    labels, count = ndimage.label(free, structure=np.ones((3, 3)))
    if count:
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        edge = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
        edge = edge[edge > 0]
        inner = np.setdiff1d(np.arange(1, count + 1), edge)
        if len(inner) and (not len(edge) or sizes[inner].max() > sizes[edge].max()):
            free &= ~np.isin(labels, edge)
    seen = raster.occupied & ndimage.binary_dilation(free, structure=np.ones((3, 3)))
    image = np.full(free.shape, UNKNOWN, dtype=np.uint8)
    image[free] = FREE
    image[seen] = OCCUPIED
    return image[::-1]
