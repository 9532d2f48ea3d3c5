"""Shared fixtures: repository paths and the read-only reference material in ../shared."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "locations"
REFERENCE = REPO.parent / "shared" / "reference"


@pytest.fixture
def repo_root() -> Path:
    return REPO


@pytest.fixture
def reference_dir() -> Path:
    if not REFERENCE.is_dir():
        pytest.skip(f"reference material not found at {REFERENCE} (it lives in ../shared beside the clone)")
    return REFERENCE


@pytest.fixture
def warehouse_dir() -> Path:
    return EXAMPLES / "warehouse"
