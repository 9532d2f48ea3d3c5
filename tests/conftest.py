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


@pytest.fixture(autouse=True)
def _isolated_llm_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every test gets an empty LLM cache: a reply cached by an earlier run must never answer a test."""
    monkeypatch.setenv("SOCNAVGEN_CACHE_DIR", str(tmp_path_factory.mktemp("llm_cache")))


def pytest_sessionstart(session: pytest.Session) -> None:
    """Compile the simulator (or load numba's cache) once, before pytest-xdist starts its workers: workers
    that compile the same cold cache at the same time can read each other's half-written entries ("no
    compiled object yet"), and each would spend the same minute compiling."""
    if hasattr(session.config, "workerinput"):  # an xdist worker: the controller has warmed the cache
        return
    from socnavgen.sim import warm_up

    warm_up()
