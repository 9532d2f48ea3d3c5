"""The `socnavgen location` commands through typer's runner and once as a real process."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from PIL import Image
from typer.testing import CliRunner

from socnavgen.cli import app
from tests.location.conftest import EXAMPLES, read_graph, write_graph

runner = CliRunner()


def test_check_ok_exit_0() -> None:
    result = runner.invoke(app, ["location", "check", str(EXAMPLES / "warehouse")])
    assert result.exit_code == 0, result.output
    assert "OK" in result.output and "19 nodes, 22 edges, 0 error(s), 0 warning(s)" in result.output


def test_check_errors_exit_1_with_table(location_copy) -> None:
    loc = location_copy("home")
    data = read_graph(loc)
    data["links"].append({"type": "HALLWAY", "source": "g9", "target": "g9"})
    write_graph(loc, data)
    result = runner.invoke(app, ["location", "check", str(loc)])
    assert result.exit_code == 1
    assert "FAILED" in result.output and "1 error(s)" in result.output
    assert "self" in result.output and "what to do" in result.output  # the rich table (cells wrap at 80 columns)


def test_check_warnings_only_exit_0(location_copy) -> None:
    loc = location_copy("home")
    (loc / "scene_graph.png").unlink()
    result = runner.invoke(app, ["location", "check", str(loc)])
    assert result.exit_code == 0
    assert "1 warning(s)" in result.output


def test_check_json(location_copy) -> None:
    loc = location_copy("hospital")
    data = read_graph(loc)
    data["nodes"][0]["type"] = "CAFETERIA"
    write_graph(loc, data)
    result = runner.invoke(app, ["location", "check", "--json", str(loc)])
    assert result.exit_code == 1
    payload = json.loads(result.output)
    assert payload["ok"] is False and payload["errors"] == 1
    (problem,) = payload["problems"]
    assert problem["level"] == "error" and problem["file"].endswith("scene_graph.json")
    assert problem["message"] == "node ef has type 'CAFETERIA', not in the schema"
    assert isinstance(problem["line"], int)


def test_malformed_json_file_line_no_traceback(location_copy) -> None:
    loc = location_copy("home")
    (loc / "scene_graph.json").write_text('{\n  "nodes": [\n    {"id": "ab" "type": "X"}\n  ]\n}\n')
    result = runner.invoke(app, ["location", "check", str(loc)])
    assert result.exit_code == 1
    assert "scene_graph.json:3" in result.output.replace("\n", "")
    assert "Traceback" not in result.output


def test_show_writes_readable_png(tmp_path: Path) -> None:
    out = tmp_path / "w.png"
    result = runner.invoke(app, ["location", "show", str(EXAMPLES / "warehouse"), "-o", str(out)])
    assert result.exit_code == 0, result.output
    with Image.open(out) as img:
        assert 1024 <= max(img.size) <= 1800


def _run_cli(*args: str) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).parent / "socnavgen"
    cmd = [str(exe)] if exe.is_file() else [sys.executable, "-c", "from socnavgen.cli import main; main()"]
    return subprocess.run([*cmd, *args], capture_output=True, text=True, timeout=60)


def test_subprocess_exit_codes_and_no_traceback(location_copy) -> None:
    good = _run_cli("location", "check", str(EXAMPLES / "home"))
    assert good.returncode == 0, good.stderr
    loc = location_copy("home")
    (loc / "location.yaml").write_text("name: home\ndescription: [unclosed\n")
    bad_check = _run_cli("location", "check", str(loc))
    assert bad_check.returncode == 1
    assert "location.yaml:" in bad_check.stdout.replace("\n", "") and "Traceback" not in bad_check.stdout
    # `show` cannot draw a broken folder: a user error, exit 2, one message on stderr, no traceback
    bad_show = _run_cli("location", "show", str(loc))
    assert bad_show.returncode == 2
    assert "location.yaml:3: malformed YAML" in bad_show.stderr.replace("\n", "")
    assert "Traceback" not in bad_show.stderr + bad_show.stdout


def test_show_defaults_to_scene_graph_png_in_folder(location_copy) -> None:
    loc = location_copy("home")
    (loc / "scene_graph.png").unlink()
    result = runner.invoke(app, ["location", "show", str(loc)])
    assert result.exit_code == 0, result.output
    assert (loc / "scene_graph.png").read_bytes() == (EXAMPLES / "home" / "scene_graph.png").read_bytes()


def test_check_missing_folder_is_a_user_error(tmp_path: Path) -> None:
    from socnavgen.errors import InputFileError

    result = runner.invoke(app, ["location", "check", "--json", str(tmp_path / "nowhere")])
    # main() turns this into one message and exit code 2 (1 is for problems found in a location)
    assert isinstance(result.exception, InputFileError)
    assert "no such location folder" in result.exception.render()
