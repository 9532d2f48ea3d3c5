"""`socnavgen export` from the command line: success lists files, user errors exit 2 without traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from .export_helpers import GIVE_WAY_TREE


def run_cli(*args: str) -> subprocess.CompletedProcess:
    code = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=60)


def test_export_command(make_run, tmp_path: Path) -> None:
    run = make_run()
    out = tmp_path / "out"
    done = run_cli("export", str(run), "--format", "socrates", "-o", str(out))
    assert done.returncode == 0, done.stderr
    assert "LLMBT_0.xml" in done.stdout
    assert (out / "hunav_agent_manager/behavior_trees/LLMBT_1.xml").is_file()


def test_export_error_exit_code(make_run, tmp_path: Path) -> None:
    moved = GIVE_WAY_TREE.replace('<RobotSays agent_id="{id}" message="4"/>', '<RobotMoved agent_id="{id}"/>')
    run = make_run(trees={"human1": moved, "human2": GIVE_WAY_TREE})
    done = run_cli("export", str(run), "--format", "hunav2", "-o", str(tmp_path / "o"))
    assert done.returncode == 2  # no 2.x condition reads the robot's velocity
    assert "RobotMoved" in done.stderr and "Traceback" not in done.stderr
    done = run_cli("export", str(run), "--format", "gazebo", "-o", str(tmp_path / "o"))
    assert done.returncode == 2 and "unknown --format" in done.stderr
