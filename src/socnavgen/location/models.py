"""Data models of a location folder (location.yaml and scene_graph.json)."""

from __future__ import annotations

import math
import re

from pydantic import BaseModel, ConfigDict, Field, field_validator

from socnavgen.limits import MAX_COORDINATE

NODE_ID_PATTERN = re.compile(r"^[a-z0-9]{2}$")  # use .fullmatch: Python's `$` also matches before a final \n
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")
# ends every description socnavgen writes for a new location: the user's text replaces it (the annotator refuses
# to save a description that still holds it: the prompts would tell the model nothing about the place)
DESCRIBE_ME = "Replace this text with what the place is, who moves around in it and what each node and edge type means."


def is_placeholder_description(text: str) -> bool:
    return DESCRIBE_ME in " ".join(text.split())


def _finite(values: list[float] | tuple[float, ...], what: str) -> None:
    if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in values):
        raise ValueError(f"{what} must be finite numbers within +-{MAX_COORDINATE:g} (no NaN or infinity)")


def _printable(value: str, what: str) -> str:
    if _CONTROL.search(value):
        raise ValueError(f"{what} {value!r} contains control characters (newline, tab, ...)")
    return value


class Schema(BaseModel):
    """Node and edge types allowed in the scene graph; the pipeline never depends on their words."""

    model_config = ConfigDict(extra="forbid")
    node_types: list[str] = Field(min_length=1)
    edge_types: list[str] = Field(min_length=1)


class LocationConfig(BaseModel):
    """location.yaml. Exactly one of `nav2_map` and `pixel_to_world` gives the transform."""

    model_config = ConfigDict(extra="forbid")
    name: str
    description: str
    map: str = Field(description="map image file, relative to the location folder")
    nav2_map: str | None = Field(default=None, description="ROS map_server yaml (resolution, origin)")
    pixel_to_world: list[list[float]] | None = Field(default=None, description="3x3 homogeneous matrix")
    occupancy_image: str | None = Field(
        default=None, description="occupancy image if `map` is a picture; defaults to the nav2 image or `map`")
    schema_: Schema = Field(alias="schema")

    @field_validator("pixel_to_world")
    @classmethod
    def _is_3x3(cls, value: list[list[float]] | None) -> list[list[float]] | None:
        if value is not None and (len(value) != 3 or any(len(row) != 3 for row in value)):
            raise ValueError("pixel_to_world must be a 3x3 matrix (three rows of three numbers)")
        if value is not None:
            _finite([v for row in value for v in row], "pixel_to_world")
        return value


class Node(BaseModel):
    """A scene-graph node; `pos` is in image pixels (x right, y down)."""

    type: str
    pos: tuple[float, float]
    id: str

    @field_validator("pos")
    @classmethod
    def _finite_pos(cls, value: tuple[float, float]) -> tuple[float, float]:
        _finite(value, "a node position")
        return value

    @field_validator("id", "type")
    @classmethod
    def _no_control(cls, value: str) -> str:
        return _printable(value, "node id or type")


class Edge(BaseModel):
    type: str
    source: str
    target: str

    @field_validator("type", "source", "target")
    @classmethod
    def _no_control(cls, value: str) -> str:
        return _printable(value, "edge field")


class SceneGraph(BaseModel):
    """networkx node-link JSON exactly as the SocRATES annotator writes it."""

    directed: bool = False
    multigraph: bool = False
    graph: dict = Field(default_factory=dict)
    nodes: list[Node] = Field(default_factory=list)
    links: list[Edge] = Field(default_factory=list)

    def node(self, node_id: str) -> Node:
        for node in self.nodes:
            if node.id == node_id:
                return node
        raise KeyError(node_id)

    def node_ids(self) -> list[str]:
        return [n.id for n in self.nodes]

    def __contains__(self, node_id: object) -> bool:  # what path_mistakes asks, without building networkx's view
        return any(n.id == node_id for n in self.nodes)

    def has_edge(self, a: str, b: str) -> bool:
        return any({e.source, e.target} == {a, b} for e in self.links)
