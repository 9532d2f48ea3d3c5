"""Fixtures of the hostile-input tests: a tiny location, a run folder on it, and the real CLI entry
point run in-process (so exit codes and the one-line messages are what a user sees)."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.export.export_helpers import GIVE_WAY_TREE, REGULAR_TREE, build_location, build_run, default_plan


@dataclass
class CliResult:
    code: int
    out: str
    err: str


@pytest.fixture
def cli(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]):  # noqa: ANN201 - factory fixture
    """Run `socnavgen ARGS` through main() and return (exit code, stdout, stderr)."""
    from socnavgen.cli import main

    def run(*args: str) -> CliResult:
        monkeypatch.setattr(sys, "argv", ["socnavgen", *map(str, args)])
        capsys.readouterr()
        try:
            main()
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        captured = capsys.readouterr()  # rich wraps long lines: compare with whitespace collapsed
        return CliResult(code, " ".join(captured.out.split()), " ".join(captured.err.split()))

    return run


@pytest.fixture
def location(tmp_path: Path) -> Path:
    return build_location(tmp_path / "loc")


@pytest.fixture
def run_dir(tmp_path: Path, location: Path) -> Path:
    return build_run(tmp_path / "run", location, default_plan(), {"human1": GIVE_WAY_TREE, "human2": REGULAR_TREE})


def no_traceback(text: str) -> bool:
    return "Traceback" not in text and 'File "' not in text
