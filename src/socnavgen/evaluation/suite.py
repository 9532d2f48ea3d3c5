"""The evaluation inputs (scenes, contexts, rough scenarios) as a YAML file users can copy and edit."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from pydantic import BaseModel, Field

from socnavgen.safeio import load_model_file

DEFAULT_SUITE = "paper.yaml"


class ProposalScene(BaseModel):
    name: str
    context: str
    task: str
    rough: str


class PathScene(BaseModel):
    name: str
    rough: str


class PaperCell(BaseModel):
    path_validity: float
    bt_validity: float


class EvalSuite(BaseModel):
    location: str
    proposal_scenes: list[ProposalScene] = Field(default_factory=list)
    path_context: str
    path_task: str
    path_scenes: list[PathScene] = Field(default_factory=list)
    paper_table3: dict[str, PaperCell] = Field(default_factory=dict)
    location_description_from_location: bool = True


def load_suite(path: Path | None = None) -> EvalSuite:
    """Load a suite file; without a path, the paper's own scenes bundled with the package."""
    if path is None:
        ref = resources.files("socnavgen.evaluation") / "data" / DEFAULT_SUITE
        with resources.as_file(ref) as real:
            return load_suite(Path(real))
    return load_model_file(path, EvalSuite, hint="compare with the bundled suite: socnavgen eval --show-suite")
