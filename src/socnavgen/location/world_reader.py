"""Walk a parsed SDF world (sdf.py) and collect every collision shape with its world pose.

Poses compose world <- model <- nested model ... <- link <- collision; each model keeps its own
frame table (links, nested models, frames, joints) so `relative_to` resolves as SDF 1.7+ says, and
the SDF 1.4-1.6 `frame` attribute is read the same way. `<include>` pulls a model file from the model
folders (each file parsed once); its `<name>`, `<pose>` and `<static>` override the model's own.
A saved world's `<state>` moves its models to the saved poses, as Gazebo does on load.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from socnavgen.errors import InputFileError
from socnavgen.location.sdf import (
    GEOMETRY_KINDS,
    MAX_INCLUDE_DEPTH,
    MAX_SCALE,
    MAX_SHAPES,
    BrokenModel,
    Frames,
    Geometry,
    ModelPaths,
    Problem,
    Shape,
    World,
    WorldModel,
    XmlDoc,
    _floats,
    _pose_ref,
    model_sdf_file,
    parse_xml,
    pose_matrix,
)


def _text(el: ET.Element | None, default: str = "") -> str:
    return (el.text or "").strip() if el is not None else default


def _bool(el: ET.Element | None, default: bool) -> bool:
    value = _text(el).lower()
    return default if not value else value in ("1", "true")


class WorldReader:
    def __init__(self, paths: ModelPaths) -> None:
        self.paths = paths
        self.docs: dict[Path, XmlDoc] = {}
        self.shapes: list[Shape] = []

    # ------------------------------------------------------------ files
    def _doc(self, path: Path) -> XmlDoc:
        if path not in self.docs:
            self.docs[path] = parse_xml(path)
        return self.docs[path]

    def _included_model(self, uri: str, base: Path, where: str) -> tuple[ET.Element, XmlDoc, Path]:
        target = self.paths.resolve_uri(uri, base)
        if target.is_dir():
            target = model_sdf_file(target)
        if not target.is_file():
            raise BrokenModel(f"{uri}: no such file {target}")
        try:
            doc = self._doc(target)
        except InputFileError as exc:  # a broken model file is this model's problem, not the world's
            raise BrokenModel(exc.render().replace("\n  -> ", "; ")) from exc
        model = doc.root if doc.root.tag == "model" else doc.root.find("model")
        if model is None:
            raise BrokenModel(f"{target} holds no <model> ({where})")
        return model, doc, target.parent

    # ------------------------------------------------------------ models
    def model(self, el: ET.Element, doc: XmlDoc, T: np.ndarray, *, top: str, scope: str, static: bool,
              folder: Path, depth: int, files: tuple[Path, ...]) -> None:
        """Add the shapes of <model> `el`, whose frame is at world pose `T`."""
        if depth > MAX_INCLUDE_DEPTH:
            raise BrokenModel(f"models nest more than {MAX_INCLUDE_DEPTH} deep ({doc.where(el)})")
        static = _bool(el.find("static"), static)
        frames = Frames(doc.where(el))
        links = el.findall("link")
        children: list[tuple[ET.Element, str]] = [(m, "model") for m in el.findall("model")]
        children += [(i, "include") for i in el.findall("include")]
        for link in links:
            p = link.find("pose")
            frames.add(link.get("name", ""), pose_matrix(p, doc.where(link)), _pose_ref(p))
        for fr in el.findall("frame"):
            p = fr.find("pose")
            frames.add(fr.get("name", ""), pose_matrix(p, doc.where(fr)), _pose_ref(p) or fr.get("attached_to", ""))
        for joint in el.findall("joint"):
            p = joint.find("pose")
            frames.add(joint.get("name", ""), pose_matrix(p, doc.where(joint)), _pose_ref(p) or _text(joint.find("child")))
        for child, kind in children:
            name = child.get("name", "") if kind == "model" else _text(child.find("name"))
            p = child.find("pose")
            if name and p is not None:
                frames.add(name, pose_matrix(p, doc.where(child)), _pose_ref(p))
        for link in links:
            self.link(link, doc, T @ frames.resolve(link.get("name", "")), frames, top=top,
                      scope=f"{scope}::{link.get('name', '')}", static=static, folder=folder)
        for child, kind in children:
            if kind == "model":
                p = child.find("pose")
                local = frames.resolve(child.get("name", "")) if p is not None and child.get("name") \
                    else pose_matrix(p, doc.where(child))
                self.model(child, doc, T @ local, top=top, scope=f"{scope}::{child.get('name', '')}", static=static,
                           folder=folder, depth=depth + 1, files=files)
            else:
                self.include(child, doc, T, frames, top=top, scope=scope, static=static, folder=folder,
                             depth=depth + 1, files=files)

    def include(self, inc: ET.Element, doc: XmlDoc, T: np.ndarray, frames: Frames | None, *, top: str, scope: str,
                static: bool, folder: Path, depth: int, files: tuple[Path, ...], pose: np.ndarray | None = None) -> str:
        uri = _text(inc.find("uri"))
        if not uri:
            raise BrokenModel(f"<include> without <uri> ({doc.where(inc)})")
        model_el, mdoc, mfolder = self._included_model(uri, folder, doc.where(inc))
        if mdoc.file in files:
            raise BrokenModel(f"{uri} includes itself ({' -> '.join(str(f) for f in files + (mdoc.file,))})")
        name = _text(inc.find("name")) or model_el.get("name", "") or uri
        p = inc.find("pose")
        if pose is not None:  # placed by the caller (a world-level pose or a saved <state>)
            local = pose
        elif p is not None:  # the include's pose replaces the model's own
            local = frames.resolve(name) if frames is not None and name in frames.entries \
                else pose_matrix(p, doc.where(inc))
        else:
            local = pose_matrix(model_el.find("pose"), mdoc.where(model_el))
        static = _bool(inc.find("static"), _bool(model_el.find("static"), static))
        self.model(model_el, mdoc, T @ local, top=top, scope=f"{scope}::{name}", static=static, folder=mfolder,
                   depth=depth, files=files + (mdoc.file,))
        return name

    def link(self, link: ET.Element, doc: XmlDoc, T: np.ndarray, frames: Frames, *, top: str, scope: str,
             static: bool, folder: Path) -> None:
        for col in link.findall("collision"):
            p = col.find("pose")
            ref = _pose_ref(p)
            local = pose_matrix(p, doc.where(col))
            world = (T @ np.linalg.inv(frames.resolve(link.get("name", ""))) @ frames.resolve(ref) @ local
                     if ref else T @ local)
            geom = self.geometry(col.find("geometry"), doc, folder)
            if geom is None:
                continue
            if len(self.shapes) >= MAX_SHAPES:
                raise InputFileError(f"more than {MAX_SHAPES} collision shapes", file=doc.file,
                                     hint="import a part of the world, or merge small objects")
            self.shapes.append(Shape(model=top, path=f"{scope}::{col.get('name', '')}", pose=world, geometry=geom,
                                     static=static))

    def geometry(self, g: ET.Element | None, doc: XmlDoc, folder: Path) -> Geometry | None:
        if g is None:
            raise BrokenModel(f"<collision> without <geometry> ({doc.where(g) if g is not None else doc.file})")
        kinds = [c for c in g if c.tag in GEOMETRY_KINDS]
        if not kinds:
            other = [c.tag for c in g if c.tag != "empty"]
            if other:
                raise BrokenModel(f"geometry <{other[0]}> is not supported ({doc.where(g)})")
            return None
        el = kinds[0]
        where = doc.where(el)

        def num(tag: str, default: float | None = None) -> float:
            child = el.find(tag)
            if child is None:
                if default is None:
                    raise BrokenModel(f"<{el.tag}> without <{tag}> ({where})")
                return default
            value = _floats(child.text, 1, f"{el.tag} {tag}", doc.where(child))[0]
            if value < 0:
                raise BrokenModel(f"{el.tag} {tag} is negative ({doc.where(child)})")
            return value

        if el.tag == "box":
            size = tuple(_floats(_text(el.find("size"), "1 1 1"), 3, "box size", where))
            if min(size) < 0:
                raise BrokenModel(f"box size is negative ({where})")
            return Geometry("box", size)
        if el.tag in ("cylinder", "capsule"):
            return Geometry(el.tag, (num("radius", 0.5), num("length", 1.0)))
        if el.tag == "sphere":
            return Geometry("sphere", (num("radius", 0.5),))
        if el.tag == "ellipsoid":
            return Geometry("ellipsoid", tuple(_floats(_text(el.find("radii"), "1 1 1"), 3, "ellipsoid radii", where)))
        if el.tag == "plane":
            normal = _floats(_text(el.find("normal"), "0 0 1"), 3, "plane normal", where)
            size = tuple(_floats(_text(el.find("size"), "1 1"), 2, "plane size", where))
            return Geometry("plane", (*normal, *size))
        if el.tag == "polyline":
            pts = tuple(tuple(_floats(p.text, 2, "polyline point", doc.where(p))) for p in el.findall("point"))
            if len(pts) < 3:
                raise BrokenModel(f"polyline with fewer than 3 points ({where})")
            return Geometry("polyline", (num("height", 1.0),), points=pts)  # type: ignore[arg-type]
        uri = _text(el.find("uri"))
        if not uri:
            raise BrokenModel(f"<mesh> without <uri> ({where})")
        scale = tuple(_floats(_text(el.find("scale"), "1 1 1"), 3, "mesh scale", where))
        if not all(1e-6 <= abs(s) <= MAX_SCALE for s in scale):
            raise BrokenModel(f"mesh scale {' '.join(f'{s:g}' for s in scale)} is absurd (|s| must be within "
                              f"1e-6..{MAX_SCALE:g}) ({where})")
        sub = el.find("submesh")
        return Geometry("mesh", mesh=self.paths.resolve_uri(uri, folder), scale=scale,  # type: ignore[arg-type]
                        submesh=_text(sub.find("name")) or None if sub is not None else None)


def read_world(path: Path | str, model_dirs: list[Path] | None = None, *, env: dict[str, str] | None = None) -> World:
    """The collision shapes of a world file; models that cannot be used are listed in `problems`."""
    path = Path(path)
    doc = parse_xml(path)
    root = doc.root
    world_el = root.find("world") if root.tag == "sdf" else (root if root.tag == "world" else None)
    bare_model = root.find("model") if root.tag == "sdf" else (root if root.tag == "model" else None)
    if world_el is None and bare_model is None:
        raise InputFileError("no <world> (nor a <model>) in this SDF file", file=path,
                             hint="give a Gazebo .world or .sdf file")
    paths = ModelPaths(list(model_dirs or []), path.parent, env)
    reader = WorldReader(paths)
    world = World(file=path, name=(world_el.get("name", "") if world_el is not None else "") or path.stem,
                  version=root.get("version", "?") if root.tag == "sdf" else "?")
    scope_el = world_el if world_el is not None else root
    state: dict[str, ET.Element] = {}
    for st in scope_el.findall("state"):
        for m in st.findall("model"):
            if m.find("pose") is not None:
                state[m.get("name", "")] = m.find("pose")  # type: ignore[assignment]
    frames = Frames(doc.where(scope_el))
    for fr in scope_el.findall("frame"):
        p = fr.find("pose")
        try:
            frames.add(fr.get("name", ""), pose_matrix(p, doc.where(fr)), _pose_ref(p) or fr.get("attached_to", ""))
        except BrokenModel as exc:
            world.problems.append(Problem(fr.get("name", "?"), str(exc), doc.where(fr)))
    items = [c for c in scope_el if c.tag in ("model", "include")]
    if not items:
        world.notes.append("the world places no model")
    for index, el in enumerate(items):
        before = len(reader.shapes)
        name = el.get("name", "") if el.tag == "model" else _text(el.find("name"))
        uri = _text(el.find("uri")) if el.tag == "include" else _text(el.find("include/uri"))
        label = name or uri.removeprefix("model://") or f"#{index + 1}"
        try:
            p = state[name] if name in state else el.find("pose")
            T = None if p is None else frames.resolve(_pose_ref(p)) @ pose_matrix(p, doc.where(p))
            if el.tag == "model":
                T = np.eye(4) if T is None else T
                reader.model(el, doc, T, top=label, scope=label, static=False, folder=path.parent, depth=0,
                             files=(path,))
            else:
                label = reader.include(el, doc, np.eye(4), None, top=label, scope="", static=False,
                                       folder=path.parent, depth=0, files=(path,), pose=T)
            placed = reader.shapes[before:]
            for s in placed:
                s.model = label
            xy = T[:2, 3] if T is not None else (placed[0].pose[:2, 3] if placed else np.zeros(2))
            world.models.append(WorldModel(label, uri, any(s.static for s in placed), float(xy[0]), float(xy[1]),
                                           len(placed)))
        except BrokenModel as exc:
            del reader.shapes[before:]
            world.problems.append(Problem(label, str(exc), doc.where(el)))
    world.shapes = reader.shapes
    return world
