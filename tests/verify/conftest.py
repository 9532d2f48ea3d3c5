"""Fixtures for verify and output tests (builders live in verify_builders.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from .verify_builders import make_give_way_run, make_location


@pytest.fixture
def tiny_location(tmp_path: Path) -> Path:
    return make_location(tmp_path / "corridor")


@pytest.fixture
def give_way_run(tmp_path: Path, tiny_location: Path) -> Path:
    return make_give_way_run(tmp_path / "run", tiny_location)
