"""What the annotator page may post: strict pydantic models with size limits, so a malformed or
oversized request is refused before anything touches the location folder."""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field, field_validator

from socnavgen.location.models import NODE_ID_PATTERN

MAX_NODES = 36 * 36  # every 2-character id in use
MAX_LINKS = 20_000
MAX_TYPES = 64
MAX_TYPE_CHARS = 64


class NodeIn(BaseModel):
    model_config = ConfigDict(extra="forbid")
    id: str = Field(pattern=NODE_ID_PATTERN.pattern, description="random 2-character lowercase token")
    type: str = Field(min_length=1, max_length=MAX_TYPE_CHARS)
    pos: tuple[float, float] = Field(description="image pixels, x right, y down")

    @field_validator("pos")
    @classmethod
    def _finite(cls, value: tuple[float, float]) -> tuple[float, float]:
        if not all(math.isfinite(v) for v in value):
            raise ValueError("position must be finite numbers")
        return value


class EdgeIn(BaseModel):
    model_config = ConfigDict(extra="forbid")
    source: str = Field(pattern=NODE_ID_PATTERN.pattern)
    target: str = Field(pattern=NODE_ID_PATTERN.pattern)
    type: str = Field(min_length=1, max_length=MAX_TYPE_CHARS)


class SchemaIn(BaseModel):
    model_config = ConfigDict(extra="forbid")
    node_types: list[str] = Field(min_length=1, max_length=MAX_TYPES)
    edge_types: list[str] = Field(min_length=1, max_length=MAX_TYPES)

    @field_validator("node_types", "edge_types")
    @classmethod
    def _clean_names(cls, values: list[str]) -> list[str]:
        cleaned = [v.strip() for v in values]
        for v in cleaned:
            if not v or len(v) > MAX_TYPE_CHARS or any(ord(ch) < 32 or ord(ch) == 127 for ch in v):
                raise ValueError(f"type name {v!r} must be 1-{MAX_TYPE_CHARS} printable characters")
        if len(set(cleaned)) != len(cleaned):
            raise ValueError("type names must be unique")
        return cleaned


class SavePayload(BaseModel):
    """One save: the whole graph and the schema it is typed against."""

    model_config = ConfigDict(extra="forbid", populate_by_name=True)
    nodes: list[NodeIn] = Field(default_factory=list, max_length=MAX_NODES)
    links: list[EdgeIn] = Field(default_factory=list, max_length=MAX_LINKS)
    schema_: SchemaIn = Field(alias="schema")
