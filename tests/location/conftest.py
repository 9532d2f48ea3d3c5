"""Broken copies of a bundled location, made in tmp_path so the examples stay untouched."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
BUNDLED = ("warehouse", "hospital", "home")


def read_graph(folder: Path) -> dict:
    return json.loads((folder / "scene_graph.json").read_text())


def write_graph(folder: Path, data: dict) -> None:
    (folder / "scene_graph.json").write_text(json.dumps(data, indent=4))


@pytest.fixture
def location_copy(tmp_path: Path) -> Callable[[str], Path]:
    def make(name: str = "warehouse") -> Path:
        target = tmp_path / name
        shutil.copytree(EXAMPLES / name, target)
        return target
    return make
