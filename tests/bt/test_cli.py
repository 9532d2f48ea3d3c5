"""`socnavgen bt check` and `socnavgen bt library`: output and exit codes."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from socnavgen.bt.library import NODES
from socnavgen.cli import app
from socnavgen.cli.bt_cmd import library_markdown

GOOD = ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'>\n"
        "<RobotSays agent_id='{id}' message='4'/>\n</BehaviorTree>\n</root>\n")
BAD = ("<root main_tree_to_execute='T'>\n<BehaviorTree ID='T'>\n<Sequence>\n"
       "<HasRobotMoved agent_id='{id}'/>\n<MakeGesture agent_id='{id}' message='9'/>\n"
       "</Sequence>\n</BehaviorTree>\n</root>\n")

runner = CliRunner()


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_check_valid_file_exits_0(tmp_path: Path) -> None:
    good = write(tmp_path, "good.xml", GOOD)
    result = runner.invoke(app, ["bt", "check", str(good)])
    assert result.exit_code == 0, result.output
    assert "ok" in result.output


def test_check_lists_every_problem_of_every_file_and_exits_1(tmp_path: Path) -> None:
    good = write(tmp_path, "good.xml", GOOD)
    bad = write(tmp_path, "bad.xml", BAD)
    bad2 = write(tmp_path, "bad2.xml", BAD.replace("message='9'", "message='1'"))
    result = runner.invoke(app, ["bt", "check", str(good), str(bad), str(bad2)])
    assert result.exit_code == 1
    out = result.output
    assert f"{bad}:4: unknown node 'HasRobotMoved'" in out
    assert f"{bad}:5: MakeGesture message='9': code 9 is not allowed" in out
    assert f"{bad2}:4: unknown node 'HasRobotMoved'" in out
    assert f"{bad2}:5:" not in out
    assert "2 of 3 file(s) have problems" in out


def test_check_missing_file_is_a_user_error_not_a_crash(tmp_path: Path) -> None:
    good = write(tmp_path, "good.xml", GOOD)
    from socnavgen.errors import InputFileError

    result = runner.invoke(app, ["bt", "check", str(good), str(tmp_path / "nope.xml")])
    # a user error: main() prints it and exits 2, as the README promises (1 is for problems found in trees)
    assert isinstance(result.exception, InputFileError)
    assert "no such file" in result.exception.render() and "nope.xml" in result.exception.render()


def test_check_findings_go_to_stdout(tmp_path: Path) -> None:
    import subprocess
    import sys

    bad = write(tmp_path, "bad.xml", "<root><BehaviorTree ID='x'><Nope/></BehaviorTree></root>")
    done = subprocess.run([sys.executable, "-c", "from socnavgen.cli import main; main()", "bt", "check", str(bad)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 1
    assert "bad.xml" in done.stdout and "Nope" in done.stdout and done.stderr == ""


def test_check_target_and_humans(tmp_path: Path) -> None:
    good = write(tmp_path, "good.xml", GOOD)
    assert runner.invoke(app, ["bt", "check", "--target", "hunav2", str(good)]).exit_code == 0  # the script's condition
    moved = write(tmp_path, "moved.xml", GOOD.replace("<RobotSays agent_id='{id}' message='4'/>",
                                                      "<RobotMoved agent_id='{id}'/>"))
    result = runner.invoke(app, ["bt", "check", "--target", "hunav2", str(moved)])
    assert result.exit_code == 1
    assert "node 'RobotMoved' is not supported by target hunav2" in result.output
    follow = write(tmp_path, "follow.xml", GOOD.replace("<RobotSays agent_id='{id}' message='4'/>",
                                                        "<FollowHuman agent_id='{id}' target_id='3' time_step='{dt}'/>"))
    assert runner.invoke(app, ["bt", "check", str(follow)]).exit_code == 0
    result = runner.invoke(app, ["bt", "check", "--humans", "0,1", str(follow)])
    assert result.exit_code == 1 and "there is no human with id 3" in result.output
    assert runner.invoke(app, ["bt", "check", "--target", "ros", str(good)]).exit_code == 2
    assert runner.invoke(app, ["bt", "check", "--humans", "a,b", str(good)]).exit_code == 2


def test_check_reference_trees(reference_dir: Path) -> None:
    folder = reference_dir / "data" / "socrates-hunav" / "behavior_trees"
    ok = runner.invoke(app, ["bt", "check", str(folder / "LLMBT_1.xml"), str(folder / "BTCuriousNav.xml")])
    assert ok.exit_code == 0, ok.output
    stale = runner.invoke(app, ["bt", "check", str(folder / "BTScaredNav.xml")])
    assert stale.exit_code == 1 and "unknown node 'AvoidRobot'" in stale.output


def test_library_table_and_markdown() -> None:
    result = runner.invoke(app, ["bt", "library"])
    assert result.exit_code == 0
    for spec in NODES:
        assert spec.name in result.output
    md = runner.invoke(app, ["bt", "library", "--markdown"])
    assert md.exit_code == 0
    assert md.output == library_markdown()
    rows = [line for line in md.output.splitlines() if line.startswith("| `")]
    assert len(rows) == len(NODES)
    notes = [spec.sim_note for spec in NODES if spec.sim_note]
    assert notes and all(note in md.output for note in notes)
    hunav1 = runner.invoke(app, ["bt", "library", "--target", "hunav1"])
    assert "RobotSays" not in hunav1.output and "IsGoalReached" in hunav1.output


def test_docs_table_is_the_generated_one(repo_root: Path) -> None:
    """docs/behavior-trees.md holds `socnavgen bt library --markdown` verbatim (regenerate it if this fails)."""
    doc = (repo_root / "docs" / "behavior-trees.md").read_text()
    assert library_markdown() in doc


def test_docs_example_tree_is_valid(repo_root: Path) -> None:
    from socnavgen.bt.validate import validate_bt_text

    doc = (repo_root / "docs" / "behavior-trees.md").read_text()
    example = doc.split("```xml\n", 1)[1].split("```", 1)[0]
    assert validate_bt_text(example) == []
