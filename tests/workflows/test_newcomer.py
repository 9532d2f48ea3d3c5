"""What a newcomer meets first (issue 30): help that reads at 80 columns, `--version`, suggestions for typos,
no folder left by a command that could not start, an annotator that saves ordinary files and a real
description."""

from __future__ import annotations

import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import click
import pytest

from tests.campaign.test_resume import CLI, REPO

WAREHOUSE = REPO / "examples" / "locations" / "warehouse"


def _run(*args: str, cwd: Path = REPO, columns: int = 80) -> subprocess.CompletedProcess:
    env = {**os.environ, "COLUMNS": str(columns), "PYTHONPATH": str(REPO / "src") + os.pathsep
           + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-c", CLI, *args], env=env, cwd=cwd, capture_output=True, text=True,
                          timeout=120)


def test_bt_library_at_80_columns_breaks_no_word() -> None:
    """At 80 columns the six-column table broke words ("conditio n", "`distanc e`")."""
    from socnavgen.bt.library import NODES

    result = _run("bt", "library")
    assert result.returncode == 0
    lines = result.stdout.splitlines()
    assert max(len(line) for line in lines) <= 80
    words = set(result.stdout.split())
    for spec in NODES:
        assert spec.name in words and f"({spec.kind})" in words
        for word in spec.description.split():
            assert word in words, f"{spec.name}: {word!r} broken"


def _commands() -> list[tuple[str, ...]]:
    from socnavgen.cli import COMMANDS, _load

    found = []
    for name in COMMANDS:
        command = _load(name)
        if isinstance(command, click.Group):
            found += [(name, sub) for sub in command.commands]
        else:
            found.append((name,))
    return found


def test_every_help_shows_whole_option_names_and_no_bool_placeholder() -> None:
    """`location extract --help` cut `--detail, --density` to `--detail,--densi…`; flags read `<bool>`."""
    from typer.testing import CliRunner

    from socnavgen.cli import _load, app

    runner = CliRunner(env={"COLUMNS": "80", "TERM": "dumb"})
    for path in _commands():
        command = _load(path[0])
        if len(path) > 1:
            command = command.commands[path[1]]
        text = runner.invoke(app, [*path, "--help"]).output
        assert "Usage:" in text and "<bool>" not in text and "…" not in text, (path, text)
        assert "--install-completion" not in text, path
        for option in (p for p in command.params if isinstance(p, click.Option)):
            for name in option.opts + option.secondary_opts:
                if name.startswith("--"):
                    assert re.search(rf"(^|[\s,/]){re.escape(name)}([\s,/=]|$)", text, re.M), (path, name)
    assert "--detail, --density" in _run("location", "extract", "--help").stdout


def test_version_flag() -> None:
    from socnavgen import __version__

    result = _run("--version")
    assert result.returncode == 0 and result.stdout.strip() == f"socnavgen {__version__}"


@pytest.mark.parametrize("command", [("cards", "generate", "blind-corner", "-o", "OUT", "--location"),
                                     ("location", "check")])
def test_a_location_typo_gets_a_suggestion(tmp_path, command) -> None:  # noqa: ANN001
    args = [str(tmp_path / "out") if a == "OUT" else a for a in command]
    result = _run(*args, "examples/locations/warehose")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "no such location folder" in result.stderr and "did you mean examples/locations/warehouse?" in result.stderr
    assert not (tmp_path / "out").exists()


def test_an_unreachable_model_server_leaves_no_run_folder(tmp_path) -> None:  # noqa: ANN001
    """`generate --llm openai:m@http://127.0.0.1:9/v1` (nothing listens there) left a run folder behind."""
    result = _run("generate", "--location", str(WAREHOUSE), "--context", "c", "--task", "t",
                  "--llm", "openai:m@http://127.0.0.1:9/v1", "--timeout", "2", "--deadline", "4",
                  "--out", str(tmp_path / "run"))
    assert result.returncode == 2 and "cannot connect" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "run").exists()


def test_the_annotator_saves_ordinary_files_and_refuses_the_placeholder_description(room_location) -> None:  # noqa: ANN001
    """Saved files were 0600 (mkstemp's mode), and the placeholder description could be saved as is."""
    from starlette.testclient import TestClient

    from socnavgen.annotate.server import create_app
    from socnavgen.location.location import load_location
    from tests.annotate.test_server_api import BASE, body

    client = TestClient(create_app(room_location), base_url=BASE)
    old = os.umask(0o022)
    try:
        assert client.post("/api/save", json=body()).status_code == 200
    finally:
        os.umask(old)
    for name in ("scene_graph.json", "scene_graph.png"):
        assert stat.S_IMODE((room_location / name).stat().st_mode) == 0o644, name
    placeholder = load_location(room_location).config.description
    refused = client.post("/api/description", json={"description": placeholder})
    assert refused.status_code == 422 and "placeholder" in refused.text
    assert client.post("/api/description", json={"description": "A lab with two desks."}).status_code == 200


@pytest.fixture
def room_location(tmp_path: Path) -> Path:
    from socnavgen.location.extract import start_location_folder
    from tests.annotate.conftest import SCHEMA, draw_map

    return start_location_folder(draw_map(tmp_path / "src"), tmp_path / "room", name="room", schema=SCHEMA)
