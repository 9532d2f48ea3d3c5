"""A location folder loaded as one object: config, transform, occupancy grid and scene graph."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from pydantic import ValidationError

from socnavgen.errors import InputFileError
from socnavgen.limits import MAX_COORDINATE
from socnavgen.location.models import LocationConfig, SceneGraph, Schema
from socnavgen.location.occupancy import OccupancyGrid, Thresholds, load_image_gray, occupancy_from_image
from socnavgen.location.scene_graph import read_scene_graph, to_networkx
from socnavgen.location.transform import Transform
from socnavgen.safeio import contained_path, load_yaml_file

if TYPE_CHECKING:
    import networkx as nx

    from socnavgen.location.inventory import PlaceInventory

LOCATION_FILE = "location.yaml"
SCENE_GRAPH_FILE = "scene_graph.json"
SCENE_GRAPH_IMAGE = "scene_graph.png"


@dataclass
class Nav2Map:
    image: str
    resolution: float
    origin: list[float]
    thresholds: Thresholds


def read_nav2_yaml(path: Path) -> Nav2Map:
    data = load_yaml_file(path)
    if not isinstance(data, dict):
        raise InputFileError("a nav2 map yaml must be a mapping", file=path)
    missing = [k for k in ("image", "resolution", "origin") if k not in data]
    if missing:
        raise InputFileError(f"missing key(s) {', '.join(missing)}", file=path,
                             hint="a ROS map_server yaml has image, resolution, origin [x, y, yaw]")
    origin = data["origin"]
    if not isinstance(origin, list) or len(origin) not in (2, 3):
        raise InputFileError("origin must be [x, y, yaw]", file=path)
    try:
        res = float(data["resolution"])
        numbers = [res, *(float(v) for v in origin)]
        if res <= 0 or not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in numbers):
            raise ValueError
        return Nav2Map(
            image=str(data["image"]), resolution=res, origin=[float(v) for v in origin] + [0.0] * (3 - len(origin)),
            thresholds=Thresholds(occupied=float(data.get("occupied_thresh", 0.65)),
                                  free=float(data.get("free_thresh", 0.196)), negate=bool(data.get("negate", 0))))
    except (TypeError, ValueError) as exc:
        raise InputFileError("resolution must be a positive number and origin finite numbers", file=path) from exc


@dataclass
class Location:
    root: Path
    config: LocationConfig

    @property
    def name(self) -> str:
        return self.config.name

    @property
    def schema(self) -> Schema:
        return self.config.schema_

    @cached_property
    def nav2(self) -> Nav2Map | None:
        if self.config.nav2_map is None:
            return None
        return read_nav2_yaml(contained_path(self.root, self.config.nav2_map))

    @property
    def map_path(self) -> Path:
        return contained_path(self.root, self.config.map)

    @cached_property
    def map_gray(self) -> np.ndarray:
        return load_image_gray(self.map_path)

    @property
    def image_size(self) -> tuple[int, int]:
        """(width, height) of the map image in pixels."""
        h, w = self.map_gray.shape
        return w, h

    @cached_property
    def transform(self) -> Transform:
        if self.config.pixel_to_world is not None:
            try:
                return Transform(self.config.pixel_to_world)
            except ValueError as exc:  # singular matrix: a user error, not a crash
                raise InputFileError(f"bad pixel_to_world: {exc}", file=self.root / LOCATION_FILE,
                                     hint="give an invertible 3x3 matrix (pixel -> world, homogeneous)") from exc
        if self.nav2 is None:
            raise InputFileError("no transform: set `nav2_map` or `pixel_to_world`", file=self.root / LOCATION_FILE)
        try:
            return Transform.from_nav2(self.nav2.resolution, self.nav2.origin, self.image_size[1])
        except ValueError as exc:
            raise InputFileError(f"bad nav2 map: {exc}", file=self.root / str(self.config.nav2_map)) from exc

    @cached_property
    def occupancy(self) -> OccupancyGrid:
        if self.config.occupancy_image:
            gray = load_image_gray(contained_path(self.root, self.config.occupancy_image))
        else:
            gray = self.map_gray
        thresholds = self.nav2.thresholds if self.nav2 else Thresholds()
        return occupancy_from_image(gray, thresholds)

    @cached_property
    def scene_graph(self) -> SceneGraph:
        return read_scene_graph(contained_path(self.root, SCENE_GRAPH_FILE))  # a symlink may not leave

    @cached_property
    def graph(self) -> nx.Graph:
        return to_networkx(self.scene_graph)

    @cached_property
    def inventory(self) -> PlaceInventory:
        """The place inventory (location/inventory.py), measured once per loaded location."""
        from socnavgen.location.inventory import place_inventory

        return place_inventory(self)

    def node_world(self, node_id: str) -> tuple[float, float]:
        """World position of a node: the only path from a node id to metres."""
        return self.transform.pixel_to_world(*self.scene_graph.node(node_id).pos)


def load_location(root: Path | str) -> Location:
    root = Path(root)
    cfg_path = root / LOCATION_FILE
    if not cfg_path.is_file():
        what = f"no {LOCATION_FILE} in {root}" if root.is_dir() else "no such location folder"
        raise InputFileError(what, file=root, hint=nearby_locations(root) or
                             "a location folder holds location.yaml, the map image and scene_graph.json")
    data = load_yaml_file(cfg_path)
    try:
        config = LocationConfig.model_validate(data)
    except ValidationError as exc:
        msgs = "; ".join(f"{'.'.join(str(p) for p in e['loc']) or '(top)'}: {e['msg']}" for e in exc.errors())
        raise InputFileError(f"invalid location config: {msgs}", file=cfg_path,
                             hint="see 'Location format' in the README") from exc
    if (config.nav2_map is None) == (config.pixel_to_world is None):
        raise InputFileError("give exactly one of `nav2_map` and `pixel_to_world`", file=cfg_path)
    return Location(root=root, config=config)


def nearby_locations(root: Path) -> str | None:
    """`did you mean examples/locations/warehouse?` for a typo of a location folder beside it."""
    from socnavgen.text import did_you_mean

    parent = root.parent
    try:
        names = [p.name for p in parent.iterdir() if (p / LOCATION_FILE).is_file()] if parent.is_dir() else []
    except OSError:
        return None
    guess = did_you_mean(root.name, sorted(names)[:1000])
    return guess.replace("did you mean ", f"did you mean {parent}/" if str(parent) != "." else "did you mean ") \
        if guess else None
