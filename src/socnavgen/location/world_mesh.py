"""Triangles of a collision geometry: primitives built with trimesh, mesh files (COLLADA .dae, STL,
OBJ) read with trimesh (+ pycollada), defensively.

Before a mesh file is handed to the library it is checked: its size, the triangle count it claims
(a binary STL header, a COLLADA `count`), and for COLLADA a defusedxml parse (no DTD, no entities,
bounded depth). COLLADA's `<unit meter>` is applied as Gazebo does; its up axis is not (Gazebo
ignores it too). Results are cached per file, so a mesh placed 500 times is read once.
"""

from __future__ import annotations

import io
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numpy as np

from socnavgen.location.sdf import MAX_METRES, Geometry, parse_xml

MAX_MESH_BYTES = 64 * 1024 * 1024
MAX_MESH_TRIANGLES = 2_000_000  # one mesh; collision meshes are usually hundreds
MAX_TOTAL_TRIANGLES = 20_000_000  # all distinct meshes of a world
MESH_SUFFIXES = (".dae", ".stl", ".obj")
ROUND_SEGMENTS = 32  # facets of a cylinder or sphere: 1 cm off on a 1 m radius


class MeshError(Exception):
    """A mesh that cannot be used (missing, too large, malformed); listed by the caller."""


@dataclass
class Triangles:
    vertices: np.ndarray  # (V, 3) metres, in the geometry's frame
    faces: np.ndarray  # (F, 3) int

    def __len__(self) -> int:
        return len(self.faces)


def _claimed_dae_triangles(path: Path) -> int:
    """Triangles a COLLADA file says it holds (count attributes of its primitives), after a defused parse."""
    from socnavgen.errors import InputFileError

    try:
        doc = parse_xml(path, MAX_MESH_BYTES)
    except InputFileError as exc:
        raise MeshError(exc.message) from exc
    total = 0
    for el in doc.root.iter():
        tag = el.tag.rsplit("}", 1)[-1]
        if tag in ("triangles", "polylist", "polygons", "trifans", "tristrips"):
            try:
                count = int(el.get("count", "0"))
            except ValueError as exc:
                raise MeshError(f"<{tag} count={el.get('count')!r}> is not a number") from exc
            total += max(0, count) * (1 if tag == "triangles" else 4)  # a polygon fans into several triangles
    return total


def _claimed_stl_triangles(data: bytes) -> int:
    if data[:5].lower() == b"solid" and b"facet" in data[:1024]:  # ASCII STL: ~250 bytes a facet
        return data.count(b"facet") // 2
    if len(data) < 84:
        raise MeshError("binary STL shorter than its 84-byte header")
    (count,) = struct.unpack("<I", data[80:84])
    if 84 + 50 * count != len(data):
        raise MeshError(f"binary STL header claims {count} triangles but the file holds "
                        f"{(len(data) - 84) // 50}")
    return count


def load_mesh_file(path: Path, submesh: str | None = None) -> Triangles:
    import trimesh

    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshError(f"mesh format {suffix or '(none)'} is not read (use {', '.join(MESH_SUFFIXES)})")
    if not path.is_file():
        raise MeshError(f"mesh file {path} not found")
    size = path.stat().st_size
    if size > MAX_MESH_BYTES:
        raise MeshError(f"mesh file is {size} bytes, more than {MAX_MESH_BYTES}")
    data = path.read_bytes()
    claimed = _claimed_dae_triangles(path) if suffix == ".dae" else \
        _claimed_stl_triangles(data) if suffix == ".stl" else data.count(b"\nf ")
    if claimed > MAX_MESH_TRIANGLES:
        raise MeshError(f"claims {claimed} triangles, more than the {MAX_MESH_TRIANGLES} allowed in one mesh")
    try:
        loaded = cast(trimesh.Scene, trimesh.load(io.BytesIO(data), file_type=suffix[1:], force="scene",
                                                  process=False))
        if suffix == ".dae" and loaded.units not in (None, "meters", "meter", "m"):
            loaded = loaded.convert_units("meters", guess=False)
        if submesh:
            names = [n for n in loaded.graph.nodes_geometry if submesh in (n, loaded.graph[n][1])]
            if not names:
                raise MeshError(f"no submesh {submesh!r} in the mesh")
            loaded = loaded.subscene(names[0]) if hasattr(loaded, "subscene") else loaded
        mesh = loaded.to_geometry() if hasattr(loaded, "to_geometry") else loaded.dump(concatenate=True)
    except MeshError:
        raise
    except Exception as exc:  # the mesh libraries raise many types on a malformed file
        raise MeshError(f"cannot read the mesh: {type(exc).__name__}: {str(exc)[:200]}") from exc
    vertices = np.asarray(getattr(mesh, "vertices", np.zeros((0, 3))), dtype=float)
    faces = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), dtype=np.int64)
    if len(faces) == 0:
        raise MeshError("the mesh holds no triangles")
    if not np.isfinite(vertices).all() or np.abs(vertices).max() > MAX_METRES:
        raise MeshError("the mesh holds NaN, infinite or absurd coordinates")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError("the mesh's faces name vertices it does not have")
    return Triangles(vertices, faces)


def primitive(geom: Geometry) -> Triangles:
    """Triangles of a box, cylinder, sphere, capsule, ellipsoid, plane or polyline, as Gazebo places
    them (centred on the frame; a polyline extruded upward from z = 0)."""
    import trimesh

    kind, size = geom.kind, geom.size
    if kind == "box":
        mesh = trimesh.creation.box(extents=[max(s, 1e-6) for s in size])
    elif kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=size[0], height=size[1], sections=ROUND_SEGMENTS)
    elif kind == "capsule":  # SDF length is the cylinder between the two half spheres
        mesh = trimesh.creation.capsule(height=size[1], radius=size[0], count=[ROUND_SEGMENTS, ROUND_SEGMENTS])
        mesh.apply_translation(-mesh.bounds.mean(axis=0))
    elif kind in ("sphere", "ellipsoid"):
        mesh = trimesh.creation.uv_sphere(radius=1.0, count=[ROUND_SEGMENTS, ROUND_SEGMENTS])
        radii = (size[0],) * 3 if kind == "sphere" else size
        mesh.apply_scale(radii)
    elif kind == "plane":  # a rectangle of size (w, l) facing `normal`: a floor when horizontal, a wall when not
        normal = np.asarray(size[:3], dtype=float)
        n = normal / max(np.linalg.norm(normal), 1e-12)
        w, length = size[3] / 2, size[4] / 2
        corners = np.array([[-w, -length, 0], [w, -length, 0], [w, length, 0], [-w, length, 0]], dtype=float)
        R = trimesh.geometry.align_vectors([0, 0, 1], n)[:3, :3]
        return Triangles(corners @ R.T, np.array([[0, 1, 2], [0, 2, 3]]))
    elif kind == "polyline":
        return _prism(geom.points, max(size[0], 1e-6))
    else:
        raise MeshError(f"geometry {kind} is not supported")
    return Triangles(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64))


def _prism(points: tuple[tuple[float, float], ...], height: float) -> Triangles:
    """A polyline extruded from z = 0 to `height`: walls along its outline, caps triangulated inside it."""
    import shapely

    polygon = shapely.Polygon(points).buffer(0)
    if polygon.is_empty:
        raise MeshError("the polyline encloses no area")
    if polygon.geom_type != "Polygon":
        polygon = max(polygon.geoms, key=lambda p: p.area)
    ring = np.asarray(polygon.exterior.coords)[:-1]
    n = len(ring)
    caps = [np.asarray(t.exterior.coords)[:3] for t in shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))]
    vertices = [np.c_[ring, np.zeros(n)], np.c_[ring, np.full(n, height)]]
    faces = [[i, (i + 1) % n, n + i] for i in range(n)] + [[(i + 1) % n, n + (i + 1) % n, n + i] for i in range(n)]
    base = 2 * n
    for tri in caps:
        vertices += [np.c_[tri, np.zeros(3)], np.c_[tri, np.full(3, height)]]
        faces += [[base, base + 2, base + 1], [base + 3, base + 4, base + 5]]
        base += 6
    return Triangles(np.concatenate(vertices), np.asarray(faces, dtype=np.int64))


class MeshLibrary:
    """Triangles per geometry, each mesh file read once; counts what was read."""

    def __init__(self) -> None:
        self.files: dict[tuple[Path, str | None], Triangles | MeshError] = {}
        self.triangles = 0

    def get(self, geom: Geometry) -> Triangles:
        if geom.kind != "mesh":
            return primitive(geom)
        assert geom.mesh is not None, "a mesh geometry names its file"
        key = (geom.mesh, geom.submesh)
        if key not in self.files:
            try:
                tris = load_mesh_file(geom.mesh, geom.submesh)
                if self.triangles + len(tris) > MAX_TOTAL_TRIANGLES:
                    raise MeshError(f"the world's meshes hold more than {MAX_TOTAL_TRIANGLES} triangles")
                self.triangles += len(tris)
                self.files[key] = tris
            except MeshError as exc:
                self.files[key] = exc
        found = self.files[key]
        if isinstance(found, MeshError):
            raise found
        scale = np.asarray(geom.scale, dtype=float)
        if np.allclose(scale, 1.0):
            return found
        faces = found.faces if np.prod(np.sign(scale)) > 0 else found.faces[:, ::-1]  # a mirror flips winding
        return Triangles(found.vertices * scale, faces)


def extent(tris: Triangles) -> float:
    return float(np.ptp(tris.vertices, axis=0).max()) if len(tris.vertices) else 0.0
