"""Locations: a map image, its pixel->world transform, and a scene graph annotated on it."""

from socnavgen.location.location import Location, load_location
from socnavgen.location.models import Edge, LocationConfig, Node, SceneGraph, Schema
from socnavgen.location.transform import Transform

__all__ = ["Edge", "Location", "LocationConfig", "Node", "SceneGraph", "Schema", "Transform", "load_location"]
