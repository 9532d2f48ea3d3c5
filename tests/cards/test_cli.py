"""`socnavgen cards list|show|generate` from the command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socnavgen.cli import app
from socnavgen.errors import SocnavgenError

runner = CliRunner()


def invoke(*args: str):  # noqa: ANN201 - click Result
    return runner.invoke(app, list(args), env={"COLUMNS": "200"})


def test_list_and_show() -> None:
    listed = invoke("cards", "list")
    assert listed.exit_code == 0, listed.output
    assert "blind-corner" in listed.output and "robot-crowding" in listed.output
    shown = invoke("cards", "show", "narrow-doorway")
    assert shown.exit_code == 0
    assert "rough scenario:" in shown.output and "expected robot behavior:" in shown.output


def test_unknown_card_is_a_clean_error() -> None:
    code = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"
    bad = subprocess.run([sys.executable, "-c", code, "cards", "show", "narow-doorway"], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and "did you mean narrow-doorway" in bad.stderr and "Traceback" not in bad.stderr


def test_generate_one_and_all(repo_root: Path, tmp_path: Path) -> None:
    loc = repo_root / "examples/locations/warehouse"
    if not loc.is_dir():
        pytest.fail("warehouse location not present")
    one = invoke("cards", "generate", "blind-corner", "--location", str(loc), "-o", str(tmp_path / "bc"))
    assert one.exit_code == 0, one.output
    assert (tmp_path / "bc" / "paths.json").is_file() and (tmp_path / "bc" / "behaviors" / "human1.xml").is_file()
    every = invoke("cards", "generate", "--all", "--location", str(loc), "-o", str(tmp_path / "all"))
    assert every.exit_code == 0, every.output
    assert (tmp_path / "all" / "frontal-approach" / "request.json").is_file()
    assert "entering-elevator" in every.output and "needs a node of type ELEVATOR" in every.output
    assert not (tmp_path / "all" / "entering-elevator").exists()
    nofit = invoke("cards", "generate", "exiting-room", "--location", str(loc), "-o", str(tmp_path / "x"))
    assert isinstance(nofit.exception, SocnavgenError) and "ROOM" in str(nofit.exception)
    both = invoke("cards", "generate", "blind-corner", "--all", "--location", str(loc), "-o", str(tmp_path / "y"))
    assert isinstance(both.exception, SocnavgenError)
