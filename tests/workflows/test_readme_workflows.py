"""The README's workflows typed as a user types them: the real `socnavgen` command in a subprocess, its
output piped (not a terminal) and at 80 columns. Machine output (YAML, JSON) must survive a pipe byte for
byte; tables must fit; messages must never be broken inside a word or a path."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[2]
WAREHOUSE = REPO / "examples" / "locations" / "warehouse"


def socnavgen(*args: str, cwd: Path | None = None, columns: int = 80) -> subprocess.CompletedProcess:
    """Run the installed `socnavgen` script (falls back to the module when the script is not on PATH)."""
    script = Path(sys.executable).with_name("socnavgen")
    command = [str(script)] if script.is_file() else [sys.executable, "-c", "from socnavgen.cli import main; main()"]
    env = {**os.environ, "COLUMNS": str(columns), "TERM": "dumb"}
    return subprocess.run([*command, *args], capture_output=True, text=True, timeout=180, cwd=cwd, env=env)


def test_show_suite_through_a_pipe_is_the_suite_file(tmp_path: Path) -> None:
    from importlib import resources

    from socnavgen.evaluation.suite import DEFAULT_SUITE, load_suite

    done = socnavgen("eval", "--show-suite")
    assert done.returncode == 0, done.stderr
    bundled = (resources.files("socnavgen.evaluation") / "data" / DEFAULT_SUITE).read_text()
    assert done.stdout == bundled  # not re-wrapped at 80 columns, not styled
    mine = tmp_path / "my.yaml"
    mine.write_text(done.stdout)
    assert load_suite(mine).path_scenes  # `eval --suite my.yaml` reads it back


def test_cards_list_fits_80_columns_and_keeps_names_whole() -> None:
    from socnavgen.cards.library import all_cards

    done = socnavgen("cards", "list")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert max(len(line) for line in lines) <= 80
    for card in all_cards():
        assert any(card.name in line for line in lines), card.name
    summary_at = next(line for line in lines if "summary" in line).index("summary")
    widest = max(len(line[summary_at:].rstrip()) for line in lines if len(line) > summary_at)
    assert widest >= 20  # summaries are readable, not folded to 11 characters


def test_cards_show_prints_words_not_python(tmp_path: Path) -> None:
    done = socnavgen("cards", "show", "pedestrian-obstruction")
    assert done.returncode == 0, done.stderr
    assert "{'" not in done.stdout and "'kind'" not in done.stdout


def test_json_outputs_survive_a_pipe(tmp_path: Path) -> None:
    checked = socnavgen("location", "check", str(WAREHOUSE), "--json")
    assert checked.returncode == 0, checked.stderr
    assert json.loads(checked.stdout)["ok"] is True
    run = tmp_path / "bc"
    assert socnavgen("cards", "generate", "blind-corner", "--location", str(WAREHOUSE), "-o", str(run)).returncode == 0
    verified = socnavgen("verify", str(run), "--json")
    assert verified.returncode in (0, 1), verified.stderr
    assert "findings" in json.loads(verified.stdout)


def test_long_paths_in_messages_are_never_broken(tmp_path: Path) -> None:
    deep = tmp_path / ("a-rather-long-folder-name-" * 3) / "another-long-folder-name" / "missing_location"
    done = socnavgen("location", "check", str(deep))
    assert done.returncode == 2
    assert str(deep) in done.stderr  # whole, on one line


def test_a_run_resolves_its_location_from_anywhere(tmp_path: Path) -> None:
    """Run folders store the location so that it resolves from any directory (relative to the run)."""
    project = tmp_path / "project"
    shutil.copytree(WAREHOUSE, project / "locations" / "warehouse")
    made = socnavgen("cards", "generate", "frontal-approach", "--location", "locations/warehouse", "-o", "runs/fa",
                     cwd=project)
    assert made.returncode == 0, made.stderr
    stored = json.loads((project / "runs" / "fa" / "request.json").read_text())["location"]
    assert not Path(stored).is_absolute() and stored == "../../locations/warehouse"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    simulated = socnavgen("simulate", str(project / "runs" / "fa"), "--timeout", "5", cwd=elsewhere)
    assert simulated.returncode == 0, simulated.stderr
    moved = tmp_path / "moved"
    shutil.move(project, moved)  # the run moves with its location: still found
    exported = socnavgen("export", str(moved / "runs" / "fa"), "--format", "socrates", "-o", str(tmp_path / "x"),
                         cwd=elsewhere)
    assert exported.returncode == 0, exported.stderr


@pytest.mark.parametrize("args, teaches", [(["--help"], "campaign"), (["simulate", "--help"], "Example"),
                                           (["cards", "generate", "--help"], "Example")])
def test_help_teaches(args: list[str], teaches: str) -> None:
    done = socnavgen(*args)
    assert done.returncode == 0, done.stderr
    assert "Usage" in done.stdout and teaches in done.stdout


def test_suite_yaml_is_plain_yaml() -> None:
    done = socnavgen("eval", "--show-suite")
    assert isinstance(yaml.safe_load(done.stdout), dict)


def _five_minute_commands() -> list[list[str]]:
    """The README's "Five minutes, offline" block, one command per line, comments dropped."""
    import shlex

    text = (REPO / "README.md").read_text()
    section = text.split("## Five minutes, offline", 1)[1]
    block = section.split("```bash", 1)[1].split("```", 1)[0]
    commands = []
    for line in block.strip().splitlines():
        words = shlex.split(line, comments=True)
        assert words[0] == "socnavgen", line
        commands.append(words[1:])
    return commands


def test_the_five_minute_path_runs_as_typed(tmp_path: Path) -> None:
    (tmp_path / "examples").symlink_to(REPO / "examples")  # the README's paths are relative to the repository
    commands = _five_minute_commands()
    assert [c[0] for c in commands] == ["cards", "cards", "simulate", "verify", "export"]
    for words in commands:
        done = socnavgen(*words, cwd=tmp_path)
        assert done.returncode == 0, f"socnavgen {' '.join(words)}\n{done.stdout}\n{done.stderr}"
    run = tmp_path / "runs" / "doorway"
    for made in ("trace.npz", "metrics.json", "trajectories.png", "animation.gif", "verify.json"):
        assert (run / "sim" / made).is_file(), made
    assert json.loads((run / "sim" / "verify.json").read_text())["passed"] is True
    exported = tmp_path / "exports" / "doorway"
    assert (exported / "README.md").is_file() and list(exported.rglob("*.xml"))
