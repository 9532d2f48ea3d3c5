"""Read a Gazebo world (SDF 1.4-1.9, `.world` / `.sdf`) into the collision shapes it places.

Defensive by construction: defusedxml refuses DTDs and entities (XML bombs), and the parse itself
stops past a nesting depth and an element count. Models come inline or by `<include>` of a
`model://NAME` (searched in the given folders, then GAZEBO_MODEL_PATH / GZ_SIM_RESOURCE_PATH), poses
compose through nested models, links and collisions, honouring `relative_to` frames (SDF 1.7+) and
the older `frame` attribute. A model that cannot be found or read (missing, cyclic include, NaN pose,
absurd size) is listed by name and skipped; the caller decides whether that is fatal (--strict).
Actors (the simulated people) are not obstacles and are ignored.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from socnavgen.errors import InputFileError
from socnavgen.safeio import read_text_limited

MAX_WORLD_BYTES = 32 * 1024 * 1024  # a world or model file; real worlds are a few hundred kB
MAX_XML_DEPTH = 64  # SDF nests world > model > model ... > link > collision > geometry > mesh: ~12
MAX_XML_ELEMENTS = 2_000_000  # per file
MAX_INCLUDE_DEPTH = 16  # model including model including ...
MAX_SHAPES = 500_000  # collision shapes in one world
MAX_METRES = 1e5  # a pose or size beyond 100 km is a typo or an attack
MAX_SCALE = 1e4
ENV_MODEL_PATHS = ("GAZEBO_MODEL_PATH", "GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH")
GEOMETRY_KINDS = ("box", "cylinder", "sphere", "capsule", "ellipsoid", "plane", "mesh", "polyline")


class BrokenModel(Exception):
    """A model that cannot be used as written; caught per model and listed, never shown as a traceback."""


@dataclass(frozen=True)
class Geometry:
    """One collision geometry in its own frame. `size` by kind: box (x, y, z); cylinder and capsule
    (radius, length); sphere (radius,); ellipsoid (rx, ry, rz); plane (nx, ny, nz, width, length);
    polyline (height,) with `points`; mesh: `mesh` file, `scale`, optional `submesh` name."""

    kind: str
    size: tuple[float, ...] = ()
    mesh: Path | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    submesh: str | None = None
    points: tuple[tuple[float, float], ...] = ()


@dataclass
class Shape:
    model: str  # the top-level model it belongs to (as the world names it)
    path: str  # scoped name, model::link::collision
    pose: np.ndarray  # 4x4, world frame
    geometry: Geometry
    static: bool


@dataclass
class Problem:
    model: str
    what: str
    where: str  # file:line


@dataclass
class WorldModel:
    name: str
    uri: str  # model://... when included, "" when inline
    static: bool
    x: float
    y: float
    shapes: int = 0


@dataclass
class World:
    file: Path
    name: str
    version: str
    models: list[WorldModel] = field(default_factory=list)
    shapes: list[Shape] = field(default_factory=list)
    problems: list[Problem] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


# ---------------------------------------------------------------- XML with line numbers and limits
@dataclass
class XmlDoc:
    file: Path
    root: ET.Element
    lines: dict[int, int]

    def where(self, el: ET.Element) -> str:
        line = self.lines.get(id(el))
        return f"{self.file}:{line}" if line else str(self.file)


class _Builder:
    """TreeBuilder that records each element's line and stops deep or huge documents early."""

    def __init__(self, file: Path) -> None:
        self._tb = ET.TreeBuilder()
        self.lines: dict[int, int] = {}
        self.parser: Any = None  # the expat parser, for line numbers
        self.depth = 0
        self.count = 0
        self.file = file

    def start(self, tag: str, attrs: dict[str, str]) -> ET.Element:
        self.depth += 1
        self.count += 1
        line = self.parser.CurrentLineNumber if self.parser is not None else 0
        if self.depth > MAX_XML_DEPTH:
            raise InputFileError(f"XML nested more than {MAX_XML_DEPTH} levels deep", file=self.file, line=line,
                                 hint="an SDF world nests a dozen levels; is this the right file?")
        if self.count > MAX_XML_ELEMENTS:
            raise InputFileError(f"more than {MAX_XML_ELEMENTS} XML elements", file=self.file, line=line,
                                 hint="split the world or check that it is the right file")
        el = self._tb.start(tag, attrs)
        self.lines[id(el)] = line
        return el

    def end(self, tag: str) -> ET.Element:
        self.depth -= 1
        return self._tb.end(tag)

    def data(self, text: str) -> None:
        self._tb.data(text)

    def close(self) -> ET.Element:
        return self._tb.close()


def parse_xml(path: Path, limit: int = MAX_WORLD_BYTES) -> XmlDoc:
    """Parse an untrusted XML file: no DTD, no entities, bounded size, depth and element count."""
    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import DefusedXMLParser

    text = read_text_limited(path, limit)
    builder = _Builder(path)
    parser = DefusedXMLParser(target=builder, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    builder.parser = parser.parser
    try:
        parser.feed(text)
        root = parser.close()
    except DefusedXmlException as exc:
        raise InputFileError(f"refused: the XML declares a DTD or entities ({type(exc).__name__})", file=path,
                             hint="SDF needs neither; remove the <!DOCTYPE>/<!ENTITY> lines") from exc
    except ET.ParseError as exc:
        line = exc.position[0] if exc.position else None
        raise InputFileError(f"malformed XML: {exc}", file=path, line=line, hint="fix the XML at that line") from exc
    return XmlDoc(path, root, builder.lines)


# ---------------------------------------------------------------- numbers and poses
def _floats(text: str | None, n: int | tuple[int, ...], what: str, where: str) -> list[float]:
    counts = (n,) if isinstance(n, int) else n
    try:
        values = [float(v) for v in (text or "").split()]
    except ValueError as exc:
        raise BrokenModel(f"{what} {text!r} is not numbers ({where})") from exc
    if len(values) not in counts:
        raise BrokenModel(f"{what} {text!r} needs {' or '.join(map(str, counts))} numbers ({where})")
    if not all(math.isfinite(v) and abs(v) <= MAX_METRES for v in values):
        raise BrokenModel(f"{what} {text!r} holds NaN, infinite or absurd values ({where})")
    return values


def rotation_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """SDF's fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), \
        math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def pose_matrix(el: ET.Element | None, where: str) -> np.ndarray:
    """4x4 of a <pose>: `x y z roll pitch yaw` (radians, or degrees="true"), or `x y z qx qy qz qw`
    with rotation_format="quat_xyzw" (SDF 1.9)."""
    T = np.eye(4)
    if el is None or not (el.text or "").strip():
        return T
    quat = el.get("rotation_format", "euler_rpy") == "quat_xyzw"
    v = _floats(el.text, 7 if quat else 6, "pose", where)
    T[:3, 3] = v[:3]
    if quat:
        x, y, z, w = v[3:]
        norm = math.sqrt(x * x + y * y + z * z + w * w)
        if norm < 1e-9:
            raise BrokenModel(f"pose quaternion is zero ({where})")
        x, y, z, w = x / norm, y / norm, z / norm, w / norm
        T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    else:
        angles = [math.radians(a) for a in v[3:]] if el.get("degrees", "false").strip() == "true" else v[3:]
        T[:3, :3] = rotation_rpy(*angles)
    return T


def _pose_ref(pose_el: ET.Element | None) -> str:
    """The frame a <pose> is expressed in: `relative_to` (1.7+), else the old `frame` attribute."""
    if pose_el is None:
        return ""
    return (pose_el.get("relative_to") or pose_el.get("frame") or "").strip()


class Frames:
    """The named frames of one model (links, nested models, frames, joints) resolved to the model frame."""

    def __init__(self, where: str) -> None:
        self.entries: dict[str, tuple[np.ndarray, str]] = {}
        self.done: dict[str, np.ndarray] = {}
        self.where = where

    def add(self, name: str, pose: np.ndarray, relative_to: str) -> None:
        self.entries[name] = (pose, relative_to)

    def resolve(self, name: str, stack: tuple[str, ...] = ()) -> np.ndarray:
        if name in ("", "__model__", "world"):
            return np.eye(4)
        if name in self.done:
            return self.done[name]
        if name not in self.entries:
            raise BrokenModel(f"pose relative to unknown frame {name!r} ({self.where})")
        if name in stack:
            raise BrokenModel(f"frames {' -> '.join(stack + (name,))} form a cycle ({self.where})")
        pose, ref = self.entries[name]
        result = self.resolve(ref, stack + (name,)) @ pose
        self.done[name] = result
        return result


# ---------------------------------------------------------------- finding models and files
class ModelPaths:
    """Folders holding Gazebo models (NAME/model.config, NAME/model.sdf); files may not leave them."""

    def __init__(self, folders: list[Path], world_dir: Path, env: Mapping[str, str] | None = None) -> None:
        env = os.environ if env is None else env
        found = [Path(f) for f in folders]
        for var in ENV_MODEL_PATHS:
            found += [Path(p) for p in env.get(var, "").split(os.pathsep) if p.strip()]
        self.folders = [f.resolve() for f in dict.fromkeys(found) if f.is_dir()]
        self.world_dir = world_dir.resolve()

    def allowed(self, path: Path) -> bool:
        path = path.resolve()
        return any(path == root or root in path.parents for root in [*self.folders, self.world_dir])

    def model_dir(self, name: str) -> Path | None:
        if not name or name in (".", "..") or "/" in name or "\\" in name:
            return None
        for root in self.folders:
            candidate = root / name
            if candidate.is_dir() and self.allowed(candidate):
                return candidate.resolve()
        return None

    def resolve_uri(self, uri: str, base: Path) -> Path:
        """A file named by `model://NAME/rest`, `file://path` or a path relative to `base` (the
        folder of the file that names it)."""
        uri = uri.strip()
        if uri.startswith(("http://", "https://")):
            raise BrokenModel(f"{uri} is an online (Fuel) resource, which is not downloaded: fetch it and "
                              "pass its folder with --models")
        if uri.startswith("model://"):
            name, _, rest = uri[len("model://"):].partition("/")
            folder = self.model_dir(name)
            if folder is None:
                raise BrokenModel(f"model {name!r} not found in the model folders")
            path = (folder / rest) if rest else folder
        else:
            raw = uri[len("file://"):] if uri.startswith("file://") else uri
            path = Path(raw) if Path(raw).is_absolute() else base / raw
            if not Path(raw).is_absolute() and not path.exists():  # Gazebo also looks in its model paths
                head, _, rest = raw.partition("/")
                tries = [root / raw for root in self.folders] + [root / rest for root in self.folders if root.name == head]
                path = next((t for t in tries if t.exists()), path)
        if not self.allowed(path):
            raise BrokenModel(f"{uri} is outside the world's folder and the model folders (add its folder "
                              "with --models)")
        return path.resolve()


def model_sdf_file(folder: Path) -> Path:
    """The SDF file of a model folder: model.config's <sdf> entry (the highest version up to 1.9), else
    model.sdf."""
    config = folder / "model.config"
    if config.is_file():
        doc = parse_xml(config, 1024 * 1024)
        entries = [(e.get("version", "0"), (e.text or "").strip()) for e in doc.root.iter("sdf") if (e.text or "").strip()]

        def version(text: str) -> tuple[int, ...]:
            try:
                return tuple(int(p) for p in text.split("."))
            except ValueError:
                return (0,)
        usable = [e for e in entries if version(e[0]) <= (1, 9)] or entries
        if usable:
            name = max(usable, key=lambda e: version(e[0]))[1]
            target = (folder / name).resolve()
            if folder.resolve() in target.parents and target.is_file():
                return target
    if (folder / "model.sdf").is_file():
        return folder / "model.sdf"
    raise BrokenModel(f"no model.sdf (nor a usable model.config) in {folder}")
