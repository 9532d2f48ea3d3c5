"""Fixtures of the card tests: bundled locations and synthetic ones built in tmp_path."""

from __future__ import annotations

from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "locations"
BUNDLED = ("warehouse", "hospital", "home")


@pytest.fixture(params=BUNDLED)
def bundled_location(request: pytest.FixtureRequest) -> Path:
    path = EXAMPLES / request.param
    if not (path / "location.yaml").is_file():
        pytest.fail(f"bundled location {request.param} not present")
    return path


@pytest.fixture(autouse=True)
def no_fsync(monkeypatch: pytest.MonkeyPatch) -> None:
    """Card tests write hundreds of small files; flushing each to the platter is not what they test."""
    import socnavgen.safeio as safeio

    monkeypatch.setattr(safeio.os, "fsync", lambda fd: None)
