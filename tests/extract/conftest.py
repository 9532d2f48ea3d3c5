"""Fixtures for the extract tests: synthetic maps written as nav2 map folders."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.extract.synthetic_maps import write_map


@pytest.fixture
def map_factory(tmp_path: Path):
    def make(img: np.ndarray, name: str = "m") -> Path:
        return write_map(tmp_path / f"src_{name}", img, name)
    return make
