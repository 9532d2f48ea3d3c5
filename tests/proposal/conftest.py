"""Fixtures of the generation-pipeline tests. The helpers module sits beside the tests (imported as
`gen_helpers`, a name no other test area uses)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from gen_helpers import make_mini_location  # noqa: E402


@pytest.fixture
def mini_location(tmp_path: Path) -> Path:
    return make_mini_location(tmp_path / "mini")
