"""`location from-world`: a Gazebo world file -> a ready location folder.

world (sdf.py, world_reader.py) -> collision shapes -> slab footprints -> occupancy grid
(world_raster.py) -> nav2 map.pgm + map.yaml, an overhead picture with the same transform, then the
scene graph from the existing extraction, and a location.yaml whose description drafts what the world
names (shelves, doors, beds ...). Everything is computed before the first file is written, so a
failed import leaves nothing behind.
"""

from __future__ import annotations

import io
import re
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import yaml

from socnavgen.bodies import PERSON_HEIGHT
from socnavgen.errors import InputFileError, ValidationFailed
from socnavgen.limits import MAX_IMAGE_PIXELS
from socnavgen.location.extract import (
    EXTRACT_SCHEMA,
    ExtractOptions,
    ExtractStats,
    describe,
    extract_scene_graph,
)
from socnavgen.location.location import LOCATION_FILE, SCENE_GRAPH_FILE, SCENE_GRAPH_IMAGE, load_location
from socnavgen.location.occupancy import occupancy_from_image
from socnavgen.location.scene_graph import write_scene_graph
from socnavgen.location.sdf import World
from socnavgen.location.world_mesh import MeshLibrary
from socnavgen.location.world_raster import (
    FREE,
    OCCUPIED,
    OPEN_MARGIN,
    UNKNOWN,
    Raster,
    SliceOptions,
    enclosed,
    rasterize,
    slice_shapes,
    trinary,
)
from socnavgen.location.world_reader import read_world
from socnavgen.safeio import atomic_write_bytes, atomic_write_text

MAP_IMAGE, MAP_YAML, OVERHEAD_IMAGE = "map.pgm", "map.yaml", "overhead.png"
FREE_THRESH, OCCUPIED_THRESH = 0.196, 0.65  # with these, 205 reads as unknown in map_server and nav2 alike

# What a model's name says it is: (singular, plural, pattern on the lower-cased name and uri).
THINGS: tuple[tuple[str, str, str], ...] = (
    ("shelf", "shelves", r"shel(f|ves)|rack|bookcase"),
    ("door", "doors", r"door"),
    ("elevator", "elevators", r"elevator|\blift\b"),
    ("staircase", "staircases", r"stair"),
    ("bed", "beds", r"(^|[^a-z])bed([^a-z]|$)|bed_"),
    ("table", "tables", r"table"),
    ("desk", "desks", r"desk(?!portrait)"),
    ("chair", "chairs", r"chair|stool|bench(?!top)"),
    ("sofa", "sofas", r"sofa|couch"),
    ("cabinet", "cabinets", r"cabinet|wardrobe|cupboard|drawer|nightstand|locker"),
    ("kitchen fitting", "kitchen fittings", r"kitchen|fridge|refrigerator|oven|sink|cookingbench|rangehood"),
    ("pallet jack", "pallet jacks", r"palletjack|pallet_jack|forklift"),
    ("pallet", "pallets", r"pallet(?!jack)"),
    ("box", "boxes", r"(^|[^a-z])box|carton|crate|cardboard|cluttering"),
    ("bin", "bins", r"bucket|trash|bin\b|barrel"),
    ("counter", "counters", r"counter|reception|bar_"),
    ("plant", "plants", r"plant|tree|flower|vase"),
    ("screen", "screens", r"(^|[^a-z])tv|monitor|screen"),
    ("machine", "machines", r"machine|conveyor|printer|fitness"),
)


@dataclass
class WorldImportOptions:
    slice: SliceOptions = field(default_factory=SliceOptions)
    extract: ExtractOptions = field(default_factory=ExtractOptions)
    strict: bool = False  # a missing model or unreadable mesh is an error instead of a listed warning
    name: str | None = None
    force: bool = False


@dataclass
class WorldImport:
    folder: Path
    world: World
    skipped: list[str]  # "name: why" of every model, mesh or shape left out
    stats: ExtractStats
    things: dict[str, int]
    size: tuple[int, int]  # map width, height in cells
    origin: tuple[float, float]
    footprints: int  # distinct slices computed (the rest were reused)
    seconds: dict[str, float] = field(default_factory=dict)


def things_in(world: World) -> dict[str, int]:
    """How many models of each kind the world names, by the registry THINGS (first match wins)."""
    counts: Counter[str] = Counter()
    for model in world.models:
        text = f"{model.name} {model.uri}".lower().replace("-", "_")
        spaced = re.sub(r"([a-z])([A-Z])", r"\1 \2", f"{model.name} {model.uri}").lower()
        for singular, _plural, pattern in THINGS:
            if re.search(pattern, text) or re.search(pattern, spaced):
                counts[singular] += 1
                break
    return dict(counts)


def draft_description(world: World, things: dict[str, int], stats: ExtractStats, width_m: float, height_m: float,
                      free_m2: float) -> str:
    plural = {s: p for s, p, _ in THINGS}
    named = ", ".join(f"{n} {plural[s] if n != 1 else s}" for s, n in sorted(things.items(), key=lambda kv: -kv[1]))
    holds = f" It holds {named} (read from the model names)." if named else ""
    return (f"Imported from the Gazebo world {world.file.name} ({len(world.models)} models).{holds} "
            + describe(stats, width_m, height_m, free_m2))


def overhead_picture(raster_image: np.ndarray, height_class: np.ndarray) -> np.ndarray:
    """An orthographic top view with the map's transform: free floor white, unknown grey, obstacles
    coloured by how tall they are (low furniture brown, waist-to-head blue, tall shelves and walls
    black), their surface dark and their inside light."""
    outline = np.array([[150, 80, 20], [20, 80, 160], [0, 0, 0]], dtype=np.uint8)
    inside = np.array([[235, 190, 140], [160, 200, 240], [120, 120, 120]], dtype=np.uint8)
    cls = height_class[::-1]
    rgb = np.empty((*raster_image.shape, 3), dtype=np.uint8)
    rgb[:] = UNKNOWN
    rgb[raster_image == FREE] = 255
    solid = (raster_image == UNKNOWN) & (cls >= 0)
    rgb[solid] = inside[cls[solid]]
    occ = raster_image == OCCUPIED
    rgb[occ] = outline[np.maximum(cls[occ], 0)]
    return rgb


def _png(array: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, format="PNG")
    return buffer.getvalue()


def _pgm(array: np.ndarray) -> bytes:
    h, w = array.shape
    return f"P5\n# socnavgen location from-world\n{w} {h}\n255\n".encode() + array.astype(np.uint8).tobytes()


def person_slab(world: World, options: SliceOptions, library: MeshLibrary, raster: Raster) -> np.ndarray:
    """The map image of the same cells sliced up to a person's height: a map cut lower (a laser's, with
    --head 0.5) shows a rack as its legs, but people do not walk under its shelves, so the scene graph
    (where people walk) comes from this one. Its obstacles include the lower slab's, so every edge
    drawn on it is walkable on the map too."""
    person = replace(options, head=PERSON_HEIGHT, bounds=None)
    placed, _, _ = slice_shapes(world.shapes, person, library)
    return trinary(rasterize(placed, person, MAX_IMAGE_PIXELS, grid=(raster.origin, raster.occupied.shape)))


def import_world(world_file: Path | str, out: Path | str, model_dirs: list[Path] | None = None,
                 options: WorldImportOptions | None = None, *,
                 progress: Callable[[str, int, int], None] | None = None) -> WorldImport:
    """Read, slice, rasterise and extract; then write the location folder."""
    world_file, out = Path(world_file), Path(out)
    opts = options or WorldImportOptions()
    if world_file.suffix.lower() not in (".world", ".sdf"):
        raise InputFileError("not a Gazebo world", file=world_file, hint="give a .world or .sdf file")
    if (out / LOCATION_FILE).exists() and not opts.force:
        raise InputFileError(f"{out} already holds a location", file=out / LOCATION_FILE,
                             hint="choose another -o folder, or pass --force to replace it")
    for d in model_dirs or []:
        if not Path(d).is_dir():
            raise InputFileError("no such model folder", file=d, hint="--models takes a folder of Gazebo models")
    seconds: dict[str, float] = {}
    t = time.perf_counter()
    world = read_world(world_file, model_dirs)
    seconds["read"] = time.perf_counter() - t
    skipped = [f"{p.model}: {p.what}" for p in world.problems]
    library = MeshLibrary()
    t = time.perf_counter()
    placed, shape_problems, footprints = slice_shapes(
        world.shapes, opts.slice, library, (lambda i, n: progress("slicing", i, n)) if progress else None)
    seconds["slice"] = time.perf_counter() - t
    skipped += [f"{path}: {what}" for path, what in shape_problems]
    if opts.strict and skipped:
        raise ValidationFailed(f"{len(skipped)} model(s) or mesh(es) could not be used: " + "; ".join(skipped[:20]),
                               file=world_file, hint="add their folders with --models, fix them, or drop --strict")
    t = time.perf_counter()
    raster = rasterize(placed, opts.slice, MAX_IMAGE_PIXELS)
    if opts.slice.bounds is None and not enclosed(raster, opts.slice):  # open ground: walked round its edges
        raster = rasterize(placed, replace(opts.slice, margin=max(opts.slice.margin, OPEN_MARGIN)), MAX_IMAGE_PIXELS)
    image = trinary(raster)
    walked = image if opts.slice.head >= PERSON_HEIGHT else person_slab(world, opts.slice, library, raster)
    seconds["raster"] = time.perf_counter() - t
    t = time.perf_counter()
    if progress:
        progress("extracting the scene graph", 0, 1)
    graph, stats = extract_scene_graph(occupancy_from_image(walked), opts.slice.resolution, opts.extract)
    seconds["extract"] = time.perf_counter() - t
    h, w = image.shape
    res = opts.slice.resolution
    things = things_in(world)
    free_m2 = float((image == FREE).sum()) * res * res
    name = opts.name or out.resolve().name
    nav2 = {"image": MAP_IMAGE, "mode": "trinary", "resolution": res,
            "origin": [round(raster.origin[0], 6), round(raster.origin[1], 6), 0.0], "negate": 0,
            "occupied_thresh": OCCUPIED_THRESH, "free_thresh": FREE_THRESH}
    config = {"name": name, "description": draft_description(world, things, stats, w * res, h * res, free_m2),
              "map": OVERHEAD_IMAGE, "nav2_map": MAP_YAML, "occupancy_image": MAP_IMAGE,
              "schema": {"node_types": list(EXTRACT_SCHEMA.node_types), "edge_types": list(EXTRACT_SCHEMA.edge_types)}}
    t = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(out / MAP_IMAGE, _pgm(image))
    atomic_write_text(out / MAP_YAML, yaml.safe_dump(nav2, sort_keys=False))
    atomic_write_bytes(out / OVERHEAD_IMAGE, _png(overhead_picture(image, raster.height_class)))
    atomic_write_text(out / LOCATION_FILE, yaml.safe_dump(config, sort_keys=False, allow_unicode=True, width=100))
    write_scene_graph(graph, out / SCENE_GRAPH_FILE)
    from socnavgen.location.render import write_location_png

    write_location_png(load_location(out), out / SCENE_GRAPH_IMAGE)
    seconds["write"] = time.perf_counter() - t
    return WorldImport(folder=out, world=world, skipped=skipped, stats=stats, things=things, size=(w, h),
                       origin=raster.origin, footprints=footprints, seconds=seconds)
