"""The `extract` command (as the lead wires it under `socnavgen location`) and `annotate --map`."""

from __future__ import annotations

import json
from pathlib import Path

import typer
from typer.testing import CliRunner

from socnavgen.cli import annotate_cmd
from socnavgen.cli.extract_cmd import register_extract
from tests.extract.synthetic_maps import plus_map

runner = CliRunner()


def location_app() -> typer.Typer:
    app = typer.Typer()
    register_extract(app)

    @app.command("noop")
    def noop() -> None:  # a second command keeps typer from collapsing the group
        """nothing"""

    return app


def test_extract_command_writes_a_location(map_factory, tmp_path: Path) -> None:
    out = tmp_path / "plus"
    result = runner.invoke(location_app(), ["extract", str(map_factory(plus_map(), "plus")), "-o", str(out),
                                            "--density", "2", "--seed", "5"])
    assert result.exit_code == 0, result.output
    assert "INTERSECTION" in result.output and "socnavgen annotate" in result.output
    assert "location check: 0 error(s), 0 warning(s)" in result.output
    first = json.loads((out / "scene_graph.json").read_text())
    again = runner.invoke(location_app(), ["extract", str(map_factory(plus_map(), "plus")), "-o", str(out)])
    assert again.exit_code != 0 and "already holds a location" in str(again.exception)
    forced = runner.invoke(location_app(), ["extract", str(map_factory(plus_map(), "plus")), "-o", str(out),
                                            "--force", "--density", "0.5", "--seed", "5"])
    assert forced.exit_code == 0, forced.output
    assert json.loads((out / "scene_graph.json.bak").read_text()) == first
    assert len(json.loads((out / "scene_graph.json").read_text())["nodes"]) < len(first["nodes"])


def test_extract_help_teaches() -> None:
    result = runner.invoke(location_app(), ["extract", "--help"])
    assert result.exit_code == 0
    for words in ("--detail", "--min-spur", "Example", "straight segment"):
        assert words in result.output


def test_annotate_map_starts_a_new_location(map_factory, tmp_path: Path, monkeypatch) -> None:
    served = {}

    class FakeServer:
        def run(self) -> None:
            served["ran"] = True

    def fake_make_server(app, port):
        served["port"] = port
        served["app"] = app
        return FakeServer()

    monkeypatch.setattr("socnavgen.annotate.server.make_server", fake_make_server)
    app = typer.Typer()
    annotate_cmd.register(app)

    @app.command("noop")
    def noop() -> None:
        """nothing"""

    out = tmp_path / "new_place"
    result = runner.invoke(app, ["annotate", str(out), "--map", str(map_factory(plus_map(), "plus")),
                                 "--port", "8811", "--no-browser"])
    assert result.exit_code == 0, result.output
    assert served == {"port": 8811, "app": served["app"], "ran": True}
    assert (out / "location.yaml").is_file() and (out / "plus.pgm").is_file() and (out / "map.yaml").is_file()
    assert "127.0.0.1:8811" in result.output
    state = served["app"].state.store.state()
    assert state["graph"] == {"nodes": [], "links": []} and state["image_size"] == [300, 300]
