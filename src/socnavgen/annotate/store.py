"""The annotator's view of one location folder: what the page shows, and a save that validates
everything first and only then replaces all its files in one transaction (keeping a .bak), so a
failed save leaves every file as it was."""

from __future__ import annotations

import io
import math
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from PIL import Image

from socnavgen.annotate.models import SavePayload
from socnavgen.atomic_files import write_files_atomically
from socnavgen.errors import InputFileError, SocnavgenError
from socnavgen.limits import MAX_IMAGE_PIXELS
from socnavgen.location.location import (
    LOCATION_FILE,
    SCENE_GRAPH_FILE,
    SCENE_GRAPH_IMAGE,
    Location,
    load_location,
)
from socnavgen.location.models import Edge, LocationConfig, Node, SceneGraph, Schema
from socnavgen.location.scene_graph import scene_graph_json
from socnavgen.safeio import MAX_IMAGE_BYTES, atomic_write_bytes, check_image_pixels, load_yaml_file

BACKUP_SUFFIX = ".bak"


@dataclass
class SaveRejected(Exception):
    """The posted graph breaks a rule; nothing was written. `problems` lists every broken rule."""

    problems: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        return "; ".join(self.problems)


class AnnotationStore:
    """Reads and writes one location folder on behalf of the page; one save at a time."""

    def __init__(self, root: Path | str) -> None:
        self.root = Path(root).resolve()
        self._lock = threading.Lock()
        self._map_png: bytes | None = None
        self.location = load_location(self.root)
        _ = self.location.image_size  # fail now, in the terminal, if the map cannot be read

    # ---- reading -------------------------------------------------------------------------
    def scene_graph(self) -> SceneGraph:
        path = self.root / SCENE_GRAPH_FILE
        return self.location.scene_graph if path.is_file() else SceneGraph()

    def state(self) -> dict[str, Any]:
        """Everything the page needs on load: name, image size, schema, graph and warnings."""
        width, height = self.location.image_size
        graph = self.scene_graph()
        return {
            "name": self.location.name,
            "image_size": [width, height],
            "meters_per_pixel": self._meters_per_pixel(),
            "schema": {"node_types": list(self.location.schema.node_types),
                       "edge_types": list(self.location.schema.edge_types)},
            "graph": _graph_dict(graph),
            "warnings": self.warnings(),
        }

    def map_png(self) -> bytes:
        """The location's map image (and only it) as PNG: browsers cannot show PGM."""
        if self._map_png is None:
            path = self.location.map_path
            if path.stat().st_size > MAX_IMAGE_BYTES:
                raise InputFileError("map image is too large", file=path)
            with Image.open(path) as img:
                check_image_pixels(*img.size, file=path)
                rgb = img.convert("RGB")
            buf = io.BytesIO()
            rgb.save(buf, format="PNG")
            self._map_png = buf.getvalue()
        return self._map_png

    def warnings(self, graph: SceneGraph | None = None, schema: Schema | None = None) -> list[dict[str, Any]]:
        """`location check` problems for the saved graph, or for an unsaved one posted by the page."""
        location = self.location if graph is None else _with_graph(self.location, graph, schema)
        if graph is None and not (self.root / SCENE_GRAPH_FILE).is_file():
            return []
        return check_problems(location)

    # ---- validating ----------------------------------------------------------------------
    def validate(self, payload: SavePayload) -> tuple[SceneGraph, Schema]:
        """Turn a posted graph into a SceneGraph, or raise SaveRejected listing every problem."""
        schema = Schema(node_types=payload.schema_.node_types, edge_types=payload.schema_.edge_types)
        width, height = self.location.image_size
        problems: list[str] = []
        seen: set[str] = set()
        for node in payload.nodes:
            if node.id in seen:
                problems.append(f"node id {node.id!r} is used twice")
            seen.add(node.id)
            if node.type not in schema.node_types:
                problems.append(f"node {node.id}: type {node.type!r} is not in the schema's node types")
            x, y = node.pos
            if not (0 <= x < width and 0 <= y < height):
                problems.append(f"node {node.id}: position ({x:.0f}, {y:.0f}) is outside the {width}x{height} map")
        pairs: set[frozenset[str]] = set()
        for edge in payload.links:
            name = f"edge {edge.source}-{edge.target}"
            for end in (edge.source, edge.target):
                if end not in seen:
                    problems.append(f"{name}: node {end!r} does not exist")
            if edge.source == edge.target:
                problems.append(f"{name}: an edge must join two different nodes")
            pair = frozenset((edge.source, edge.target))
            if pair in pairs:
                problems.append(f"{name}: these two nodes are already joined")
            pairs.add(pair)
            if edge.type not in schema.edge_types:
                problems.append(f"{name}: type {edge.type!r} is not in the schema's edge types")
        if problems:
            raise SaveRejected(problems)
        graph = SceneGraph(
            nodes=[Node(id=n.id, type=n.type, pos=(_pixel(n.pos[0]), _pixel(n.pos[1]))) for n in payload.nodes],
            links=[Edge(source=e.source, target=e.target, type=e.type) for e in payload.links])
        return graph, schema

    # ---- saving --------------------------------------------------------------------------
    def save(self, payload: SavePayload) -> dict[str, Any]:
        """Validate, render in memory, back up, then replace files one atomic rename each."""
        with self._lock:
            graph, schema = self.validate(payload)
            new_location = _with_graph(self.location, graph, schema)
            png = render_png(new_location)  # a render failure stops the save before any write
            json_text = scene_graph_json(graph)
            yaml_text = self._location_yaml_with(schema) if schema != self.location.schema else None

            files: dict[Path, bytes] = {}
            if yaml_text is not None:
                files.update(_with_backup(self.root / LOCATION_FILE, yaml_text.encode("utf-8")))
            files.update(_with_backup(self.root / SCENE_GRAPH_FILE, json_text.encode("utf-8")))
            files[self.root / SCENE_GRAPH_IMAGE] = png
            write_files_atomically(files)  # every file replaced, or none (then the old ones are all kept)
            self.location = load_location(self.root)
            return {"saved": [LOCATION_FILE] * (yaml_text is not None) + [SCENE_GRAPH_FILE, SCENE_GRAPH_IMAGE],
                    "nodes": len(graph.nodes), "links": len(graph.links), "warnings": self.warnings()}

    def replace_map(self, data: bytes) -> dict[str, Any]:
        """Replace the map image by an edited version of the SAME size (pixel positions, the nav2
        origin and the graph all refer to it); PNG or PGM only; the old file is kept as .bak."""
        with self._lock:
            image = decode_map_upload(data, expected_size=self.location.image_size)
            path = self.location.map_path
            buf = io.BytesIO()
            if path.suffix.lower() in (".pgm", ".pnm"):
                image.convert("L").save(buf, format="PPM")
            else:
                image.save(buf, format="PNG")
            _backup(path)
            atomic_write_bytes(path, buf.getvalue())
            self._map_png = None
            self.location = load_location(self.root)
            return {"replaced": path.name, "warnings": self.warnings()}

    def _location_yaml_with(self, schema: Schema) -> str:
        """location.yaml with only the schema replaced (other keys kept, in order)."""
        data = load_yaml_file(self.root / LOCATION_FILE)
        data["schema"] = {"node_types": list(schema.node_types), "edge_types": list(schema.edge_types)}
        LocationConfig.model_validate(data)  # never write a config that would not load back
        return yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=100)

    def _meters_per_pixel(self) -> float | None:
        try:
            return self.location.transform.meters_per_pixel
        except SocnavgenError:
            return None


MAX_UPLOAD_PIXELS = MAX_IMAGE_PIXELS


def decode_map_upload(data: bytes, expected_size: tuple[int, int]) -> Image.Image:
    """Decode an uploaded map, refusing anything but a PNG or PGM of the expected size."""
    if not (data.startswith(b"\x89PNG\r\n\x1a\n") or data[:2] in (b"P2", b"P5")):
        raise SaveRejected(["the map must be a PNG or a PGM image"])
    try:
        with Image.open(io.BytesIO(data)) as img:
            if img.format not in ("PNG", "PPM") or img.width * img.height > MAX_UPLOAD_PIXELS:
                raise SaveRejected([f"unsupported or oversized image ({img.format}, {img.width}x{img.height})"])
            if img.size != tuple(expected_size):
                raise SaveRejected([f"the new map is {img.width}x{img.height} px but the location's map is "
                                    f"{expected_size[0]}x{expected_size[1]}: node positions and the nav2 "
                                    "origin refer to it, so the size must not change"])
            img.load()
            return img.convert("L") if img.mode not in ("L", "RGB", "RGBA") else img.copy()
    except SaveRejected:
        raise
    except Exception as exc:  # Pillow raises many types for corrupt data
        raise SaveRejected([f"cannot decode the image: {exc}"]) from exc


def _pixel(value: float) -> int:
    """Scene graphs store integer pixels, as the SocRATES annotator does."""
    return int(math.floor(value + 0.5))


def _graph_dict(graph: SceneGraph) -> dict[str, Any]:
    return {"nodes": [{"id": n.id, "type": n.type, "pos": [n.pos[0], n.pos[1]]} for n in graph.nodes],
            "links": [{"source": e.source, "target": e.target, "type": e.type} for e in graph.links]}


def _with_graph(location: Location, graph: SceneGraph, schema: Schema | None) -> Location:
    """A copy of `location` that sees `graph` (and `schema`) instead of the files on disk."""
    config = location.config if schema is None else location.config.model_copy(update={"schema_": schema})
    copy = Location(root=location.root, config=config)
    for cached in ("nav2", "map_gray", "transform", "occupancy"):
        if cached in location.__dict__:
            copy.__dict__[cached] = location.__dict__[cached]
    copy.__dict__["scene_graph"] = graph
    return copy


def _with_backup(path: Path, data: bytes) -> dict[Path, bytes]:
    """`path` -> new bytes, and its .bak -> the current bytes (when it exists), for one transaction."""
    files = {path: data}
    if path.is_file():
        files[path.with_name(path.name + BACKUP_SUFFIX)] = path.read_bytes()
    return files


def _backup(path: Path) -> None:
    """Keep the previous version beside the file (written atomically too)."""
    if path.is_file():
        atomic_write_bytes(path.with_name(path.name + BACKUP_SUFFIX), path.read_bytes())


# ---- bridges to `location check` and the renderer ---------------------------------------------
def check_problems(location: Location) -> list[dict[str, Any]]:
    """Problems `location check` finds, as {message, nodes, edge} dicts the page can highlight."""
    from socnavgen.annotate.bridge import run_check

    return run_check(location)


def render_png(location: Location) -> bytes:
    from socnavgen.annotate.bridge import render_overlay

    return render_overlay(location)


__all__ = ["AnnotationStore", "SaveRejected", "check_problems", "render_png"]
