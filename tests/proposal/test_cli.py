"""`socnavgen generate` end to end on the bundled warehouse with the committed replay scripts."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socnavgen.cli import app
from socnavgen.run import RunFolder

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "replay"
ARGS = ["--context", "Delivery robot in a small warehouse", "--task", "Transport a box",
        "--rough", "The robot turns at a blind corner and meets a worker who stops"]


@pytest.fixture
def warehouse(warehouse_dir: Path) -> Path:
    if not (warehouse_dir / "location.yaml").is_file():
        pytest.fail("examples/locations/warehouse is not there yet")
    return warehouse_dir


def test_generate_with_a_replay_script(tmp_path, warehouse):
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "up -> co -> 54 -> f7 -> 6r" in result.output
    folder = RunFolder(out)
    data = json.loads(folder.manifest_path.read_text())
    assert data["status"] == "done" and data["stages"]["paths"]["attempts"] == 2
    assert "there is no edge between co and f7" in folder.transcript_path.read_text()
    assert folder.read_paths().humans[0].interaction_point == "f7"
    assert '<IsRobotBlocking agent_id="{id}" distance="0.5"/>' in folder.read_behavior("human1")


def test_relative_paths_as_make_demo_uses_them(tmp_path, warehouse, monkeypatch):
    """`make demo` passes relative --location and --out: the summary must still list the files."""
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["generate", "--location", os.path.relpath(warehouse, tmp_path), *ARGS, "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", "out/run"])
    assert result.exit_code == 0, result.output
    assert "behaviors/human1.xml" in result.output and (tmp_path / "out" / "run" / "paths.json").is_file()


def test_naive_with_a_replay_script(tmp_path, warehouse):
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--naive", "--llm",
                                      f"replay:{FIXTURES / 'warehouse_naive.yaml'}", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert RunFolder(out).behaviors().keys() == {"human1"}


def test_failure_is_one_clear_message_and_exit_2(tmp_path, warehouse):
    script = tmp_path / "bad.yaml"
    script.write_text("stages:\n  scenario:\n" + "    - 'not json at all'\n" * 4)
    out = tmp_path / "run"
    proc = subprocess.run([sys.executable, "-c", "from socnavgen.cli import main; main()", "generate",
                           "--location", str(warehouse), *ARGS, "--llm", f"replay:{script}", "--out", str(out),
                           "--max-restarts", "0"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    text = " ".join(proc.stderr.split())  # rich wraps long lines
    assert "stage 'scenario' failed" in text and "Traceback" not in text
    assert "the reply" in text or "JSON" in text  # the last mistake is named
    assert json.loads((out / "manifest.json").read_text())["status"] == "failed"


def test_missing_inputs_and_bad_options(tmp_path, warehouse):
    runner = CliRunner()
    result = runner.invoke(app, ["generate", "--location", str(warehouse), "--llm", "local", "--out",
                                 str(tmp_path / "r")])
    assert result.exit_code != 0 and "missing --context, --task" in str(result.exception)
    result = runner.invoke(app, ["generate", "--redo", "paths", "--out", str(tmp_path / "r")])
    assert "--redo needs --from RUN" in str(result.exception)
    result = runner.invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--proposals", "1", "--pick", "2",
                                 "--out", str(tmp_path / "r")])
    assert "--pick 2 but only 1 proposal" in str(result.exception)


def test_from_and_redo_on_the_command_line(tmp_path, warehouse):
    first = tmp_path / "first"
    runner = CliRunner()
    script = FIXTURES / "warehouse_blind_corner.yaml"
    assert runner.invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--llm", f"replay:{script}",
                               "--out", str(first)]).exit_code == 0
    second = tmp_path / "second"
    redo = tmp_path / "redo.yaml"
    redo.write_text("stages:\n  behaviors:\n    human1:\n      - " + json.dumps(json.dumps({
        "reasoning": "wait", "tree": "<root main_tree_to_execute='W'><BehaviorTree ID='W'><Sequence>"
                                     "<IsRobotBlocking agent_id='{id}' distance='0.5'/>"
                                     "<MakeGesture agent_id='{id}' message='1'/></Sequence></BehaviorTree></root>"})) + "\n")
    result = runner.invoke(app, ["generate", "--from", str(first), "--redo", "behaviors", "--llm", f"replay:{redo}",
                                 "--out", str(second)])
    assert result.exit_code == 0, result.output
    assert 'message="1"' in RunFolder(second).read_behavior("human1")
    assert 'IsRobotBlocking' in RunFolder(first).read_behavior("human1")  # the source run is untouched
    assert RunFolder(second).scenario_path.read_text() == RunFolder(first).scenario_path.read_text()


def test_unknown_card_is_one_clear_message(tmp_path, warehouse):
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), "--card", "frontal-aproach",
                                      *ARGS[:4], "--out", str(tmp_path / "r")])
    assert "frontal-approach" in str(result.exception)  # the did-you-mean hint names the real card
    assert not (tmp_path / "r" / "request.json").exists()

def test_card_gives_the_rough_scenario(tmp_path, warehouse):
    import socnavgen.cards.library  # noqa: F401
    from socnavgen.cards.library import get_card
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), "--card", "blind-corner", "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(out)])
    assert result.exit_code == 0, result.output
    request = RunFolder(out).read_request()
    card = get_card("blind-corner")
    assert (request.card, request.rough, request.context, request.task) == ("blind-corner", card.rough, card.context,
                                                                           card.task)
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), "--card", "no-such-card", *ARGS[:4],
                                      "--out", str(tmp_path / "r2")])
    assert "no scenario card named 'no-such-card'" in str(result.exception)


def test_console_review_reads_accept_retry_and_edits(monkeypatch):
    from socnavgen.cli import generate_cmd
    answers = iter(["", "r", "Move the meeting to the open area"])
    monkeypatch.setattr(generate_cmd.Prompt, "ask", lambda *a, **k: next(answers))
    decisions = [generate_cmd.console_review("paths", None, '{"robot": ["up", "co"]}') for _ in range(3)]
    assert [d.action for d in decisions] == ["accept", "retry", "edit"]
    assert decisions[2].request == "Move the meeting to the open area"


def test_review_needs_a_terminal(tmp_path, warehouse):
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--review", "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(tmp_path)])
    assert "--review needs an interactive terminal" in str(result.exception)


def test_target_and_deadline_reach_the_request_and_the_model(tmp_path, warehouse, monkeypatch):
    import socnavgen.llm as llm_module

    seen = {}
    real = llm_module.make_llm

    def spy(spec, **kwargs):  # noqa: ANN001, ANN003, ANN202
        seen.update(kwargs)
        return real(spec, **kwargs)

    monkeypatch.setattr(llm_module, "make_llm", spy)
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(out),
                                      "--target", "hunav2", "--deadline", "1800", "--timeout", "900"])
    assert seen["deadline"] == 1800.0 and seen["timeout"] == 900.0  # a slow local server can be waited for
    assert RunFolder(out).read_request().target == "hunav2"
    # the fixture's worker reacts with IsRobotBlocking, which hunav2 runs as IsRobotVisible (an approximation
    # the node table documents): the run is made, and its export for its target is not refused
    assert result.exit_code == 0, result.output
    assert "will refuse it" not in result.output
    from socnavgen.export import target_refusals

    assert "hunav2" not in target_refusals(out)


def test_unknown_target_is_one_clear_message(tmp_path, warehouse):
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--out", str(tmp_path / "r"),
                                      "--target", "gazebo"])
    assert "unknown --target 'gazebo'" in str(result.exception)
    assert not (tmp_path / "r" / "request.json").exists()


def test_verify_that_gives_up_prints_the_failing_findings(tmp_path, warehouse, monkeypatch):
    """A user who ran `generate --verify` sees why it failed, not only "see sim/verify.json" (a round-4 player)."""
    from socnavgen.proposal import pipeline
    from socnavgen.verify.models import Finding, VerifyReport

    failing = Finding(name="c1 meets", kind="meets", passed=False, human="human1", blame=None,
                      evidence="human1 never came within 2 m of the robot (closest 6.37 m)")
    monkeypatch.setattr(pipeline, "default_verifier", lambda: lambda run_dir, location=None: VerifyReport(
        run=str(run_dir), passed=False, findings=[failing]))
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(out),
                                      "--verify", "--max-restarts", "0"])
    assert result.exit_code == 1, result.output
    assert "the verifier still finds problems" in result.output and "1 failing" in result.output
    assert "FAIL c1 meets (human1): human1 never came within 2 m of the robot (closest 6.37 m)" in result.output


def test_verify_that_passes_says_so(tmp_path, warehouse, monkeypatch):
    """A passing `generate --verify` ends with a line that says it verified (round-37 players read sim/verify.json
    to learn it), and a failing one does not print it."""
    from socnavgen.proposal import pipeline
    from socnavgen.verify.models import Finding, VerifyReport

    held = [Finding(name=f"c{i} meets", kind="meets", passed=True, human="human1", blame=None, evidence="ok")
            for i in (1, 2)]
    monkeypatch.setattr(pipeline, "default_verifier", lambda: lambda run_dir, location=None: VerifyReport(
        run=str(run_dir), passed=True, findings=held))
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["generate", "--location", str(warehouse), *ARGS, "--llm",
                                      f"replay:{FIXTURES / 'warehouse_blind_corner.yaml'}", "--out", str(out),
                                      "--verify", "--max-restarts", "0"])
    assert result.exit_code == 0, result.output
    assert "verified: every required criterion held (2 checked after 1 simulation(s)" in result.output
    assert "still finds problems" not in result.output
