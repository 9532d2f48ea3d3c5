"""Fixtures of the export tests: a tiny off-centre location and a run-folder factory on it."""

from __future__ import annotations

from pathlib import Path

import pytest

from socnavgen.run import PathPlan

from .export_helpers import GIVE_WAY_TREE, REGULAR_TREE, build_location, build_run, default_plan


@pytest.fixture
def tiny_location(tmp_path: Path) -> Path:
    return build_location(tmp_path / "tiny_location")


@pytest.fixture
def make_run(tmp_path: Path, tiny_location: Path):  # noqa: ANN201 - factory fixture
    def make(trees: dict[str, str] | None = None, plan: PathPlan | None = None, name: str = "run") -> Path:
        trees = trees or {"human1": GIVE_WAY_TREE, "human2": REGULAR_TREE}
        return build_run(tmp_path / name, tiny_location, plan or default_plan(), trees)
    return make


@pytest.fixture(scope="session")
def bundled_runs(tmp_path_factory) -> list[tuple[str, str, Path]]:  # noqa: ANN001
    """(kind, label, run folder) of every card on every bundled location and of every replay fixture (replayed
    through the real pipeline, its recorded --verify loop included), written once per session."""
    from socnavgen.evaluation.fixtures import fixture_paths, replay_fixture

    from .conformance_helpers import REPLAY, ROOT, card_scenes

    work = Path(tmp_path_factory.mktemp("bundled"))
    runs = [("cards", label, work / "cards" / label.replace("/", "__")) for label, _ in card_scenes(str(work / "cards"))]
    for path in fixture_paths(REPLAY[0].parent):
        replay_fixture(path, work / "fixtures" / path.stem, root=ROOT)
        runs.append(("fixtures", path.stem, work / "fixtures" / path.stem))
    return runs
