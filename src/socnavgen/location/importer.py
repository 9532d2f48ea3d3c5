"""Import a SocRATES annotator folder (map.pgm, map.yaml, scene_graph.json) as a location folder.

The scene graph is kept as is (same node-link format, same ids and pixel positions); the schema is
the annotator's config.yaml types when given, plus any type the graph uses that the config lacks
(the published small_warehouse uses PASSAGEWAY_END, which its config does not list).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import yaml

from socnavgen.errors import InputFileError
from socnavgen.location.location import (
    LOCATION_FILE,
    SCENE_GRAPH_FILE,
    SCENE_GRAPH_IMAGE,
    load_location,
    read_nav2_yaml,
)
from socnavgen.location.models import DESCRIBE_ME, LocationConfig, SceneGraph, Schema
from socnavgen.location.occupancy import load_image_gray
from socnavgen.location.render import write_location_png
from socnavgen.location.scene_graph import read_scene_graph, write_scene_graph
from socnavgen.safeio import (
    MAX_IMAGE_BYTES,
    atomic_write_bytes,
    atomic_write_text,
    contained_path,
    load_yaml_file,
)

NAV2_FILE = "map.yaml"


@dataclass
class ImportResult:
    folder: Path
    schema: Schema
    notes: list[str] = field(default_factory=list)


def _ordered_unique(values: list[str]) -> list[str]:
    return list(dict.fromkeys(values))


def schema_for(graph: SceneGraph, config: Path | None, notes: list[str]) -> Schema:
    node_used = _ordered_unique([n.type for n in graph.nodes])
    edge_used = _ordered_unique([e.type for e in graph.links])
    node_types: list[str] = []
    edge_types: list[str] = []
    if config is not None:
        data = load_yaml_file(config)
        if not isinstance(data, dict):
            raise InputFileError("annotator config must be a mapping", file=config)
        for key, target in (("node_types", node_types), ("edge_types", edge_types)):
            values = data.get(key)
            if not isinstance(values, list) or not all(isinstance(v, str) for v in values):
                raise InputFileError(f"`{key}` must be a list of names", file=config,
                                     hint="the SocRATES annotator config lists node_types and edge_types")
            target.extend(_ordered_unique([v.strip() for v in values if v.strip()]))
    for kind, declared, used in (("node", node_types, node_used), ("edge", edge_types, edge_used)):
        extra = [t for t in used if t not in declared]
        if config is not None and extra:
            notes.append(f"{kind} type(s) {', '.join(extra)} used in the scene graph but not in {config}: added")
        declared.extend(extra)
    if not node_types or not edge_types:
        raise InputFileError("cannot build a schema: the scene graph has no node or no edge types and no --config "
                             "was given", hint="pass the annotator's config.yaml with --config")
    return Schema(node_types=node_types, edge_types=edge_types)


def default_description(name: str, schema: Schema) -> str:
    return (f"The {name.replace('_', ' ')} location, imported from a SocRATES annotator folder. Node types: "
            f"{', '.join(schema.node_types)}. Edge types: {', '.join(schema.edge_types)}. "
            + DESCRIBE_ME)


def import_socrates(source: Path | str, output: Path | str, *, config: Path | None = None, name: str | None = None,
                    description: str | None = None, force: bool = False) -> ImportResult:
    source, output = Path(source), Path(output)
    if not source.is_dir():
        raise InputFileError("SocRATES folder not found", file=source,
                             hint="give the annotator's location folder (map.pgm, map.yaml, scene_graph.json)")
    if (output / LOCATION_FILE).exists() and not force:
        raise InputFileError("output folder already holds a location", file=output,
                             hint="choose another -o folder or pass --force to overwrite")
    nav2_path = source / NAV2_FILE
    nav2 = read_nav2_yaml(nav2_path)
    # The annotator writes the image name; some copies hold an absolute path from the author's machine.
    image_src = contained_path(source, Path(nav2.image).name)
    load_image_gray(image_src)  # fails early, with the file named, on a missing or unreadable image
    if image_src.stat().st_size > MAX_IMAGE_BYTES:
        raise InputFileError("map image is too large", file=image_src)
    graph = read_scene_graph(contained_path(source, SCENE_GRAPH_FILE))

    notes: list[str] = []
    schema = schema_for(graph, config, notes)
    loc_name = name or source.resolve().name
    # a map named like a file we generate (scene_graph.png ...) would be overwritten by it: rename the copy
    map_name = image_src.name
    if map_name in (SCENE_GRAPH_IMAGE, SCENE_GRAPH_FILE, LOCATION_FILE, NAV2_FILE):
        map_name = "map_image" + image_src.suffix
        notes.append(f"the map {image_src.name} is stored as {map_name} ({image_src.name} is generated)")
    cfg = LocationConfig(name=loc_name, description=description or default_description(loc_name, schema),
                         map=map_name, nav2_map=NAV2_FILE, schema=schema)

    output.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(output / map_name, image_src.read_bytes())
    nav2_data = load_yaml_file(nav2_path)
    nav2_data["image"] = map_name
    atomic_write_text(output / NAV2_FILE, yaml.safe_dump(nav2_data, sort_keys=False))
    atomic_write_text(output / LOCATION_FILE, yaml.safe_dump(cfg.model_dump(by_alias=True, exclude_none=True),
                                                             sort_keys=False, width=100, allow_unicode=True))
    write_scene_graph(graph, output / SCENE_GRAPH_FILE)
    write_location_png(load_location(output), output / SCENE_GRAPH_IMAGE)
    return ImportResult(folder=output, schema=schema, notes=notes)
