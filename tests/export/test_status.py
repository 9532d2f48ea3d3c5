"""`export` says whether the run passed verification, failed it, was never verified or changed since; and
`generate` says at once which export targets will refuse the trees it wrote."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest

from socnavgen.export import export_run, target_refusals
from socnavgen.run import RunFolder
from socnavgen.run.verification import verification_status

from .export_helpers import GIVE_WAY_TREE, REGULAR_TREE, TRANSLATABLE_TREE


def _report(run: Path, passed: bool, failing: tuple[str, ...] = ()) -> Path:
    path = run / "sim" / "verify.json"
    path.parent.mkdir(exist_ok=True)
    findings = [{"name": n, "passed": False, "required": True} for n in failing]
    findings.append({"name": "a warning only", "passed": False, "required": False})
    path.write_text(json.dumps({"run": str(run), "passed": passed, "findings": findings}))
    return path


def test_every_state_of_verification(make_run) -> None:  # noqa: ANN001
    run = make_run()
    folder = RunFolder(run)
    assert verification_status(folder).state == "never"
    _report(run, True)
    assert verification_status(folder).ok
    report = _report(run, False, ("robot meets human1 at ee", "no collision"))
    status = verification_status(folder)
    assert status.state == "failed" and "2 failing: robot meets human1 at ee; no collision" in status.message
    later = time.time() + 5
    os.utime(run / "paths.json", (later, later))  # paths edited after the verdict
    status = verification_status(folder)
    assert status.state == "stale" and "paths.json" in status.message
    report.write_text("{not json")
    os.utime(report, (later + 5, later + 5))
    assert verification_status(folder).state == "unreadable"


def test_export_says_it_in_its_result_its_readme_and_on_the_terminal(make_run, tmp_path: Path) -> None:  # noqa: ANN001
    from tests.export.test_cli import run_cli

    run = make_run()
    result = export_run(run, "socrates", tmp_path / "a")
    assert result.verification == "never" and "never verified" in (tmp_path / "a" / "README.md").read_text()
    _report(run, False, ("robot meets human1 at ee",))
    done = run_cli("export", str(run), "-o", str(tmp_path / "b"))
    assert done.returncode == 0 and "warning" in done.stderr and "FAILED verification" in done.stderr
    assert "FAILED verification" in (tmp_path / "b" / "README.md").read_text()
    _report(run, True)
    assert export_run(run, "socrates", tmp_path / "c").verification == "passed"


MOVED_TREE = GIVE_WAY_TREE.replace('<RobotSays agent_id="{id}" message="4"/>', '<RobotMoved agent_id="{id}"/>')


def test_the_targets_that_would_refuse_a_run(make_run) -> None:  # noqa: ANN001
    moved = make_run(trees={"human1": MOVED_TREE, "human2": REGULAR_TREE}, name="moved")
    refused = target_refusals(moved)
    assert set(refused) == {"hunav2", "hunav1"} and "RobotMoved" in refused["hunav2"]
    phrase = make_run(trees={"human1": GIVE_WAY_TREE, "human2": REGULAR_TREE}, name="phrase")
    assert set(target_refusals(phrase)) == {"hunav1"}  # RobotSays becomes the script's condition for 2.x
    plain = make_run(trees={"human1": TRANSLATABLE_TREE, "human2": REGULAR_TREE}, name="plain")
    assert "hunav2" not in target_refusals(plain)


@pytest.mark.parametrize("target, loud", [("hunav2", True), (None, False)])
def test_generate_warns_about_its_own_target(make_run, capsys, target, loud) -> None:  # noqa: ANN001
    from socnavgen.cli.generate_cmd import _export_check

    run = make_run(trees={"human1": MOVED_TREE, "human2": REGULAR_TREE})
    _export_check(RunFolder(run), target)
    out, err = capsys.readouterr()
    text = " ".join((out + err).split())
    assert "`export --format hunav2`" in text and "RobotMoved" in text
    assert ("warning" in err) is loud and "hunav1" not in text


def test_generate_says_what_hunav2_approximates(make_run, capsys) -> None:  # noqa: ANN001
    from socnavgen.cli.generate_cmd import _export_check

    run = make_run(trees={"human1": GIVE_WAY_TREE, "human2": REGULAR_TREE})
    _export_check(RunFolder(run), "hunav2")
    out, err = capsys.readouterr()
    text = " ".join((out + err).split())
    assert "warning" not in err and "approximates what the robot says" in text
    assert "human1.xml:6: RobotSays becomes:" in text and "never" in text  # no script says EXCUSE ME here
    _export_check(RunFolder(run), None)  # the note is for runs made for 2.x
    assert "approximates" not in " ".join(capsys.readouterr())


def test_a_recorded_simulation_is_judged_by_its_digests_not_file_times(tmp_path: Path) -> None:
    """The simulator records what a trace was made from; export's verdict goes stale when a judged file's
    content changes, even when its modification time is put back (a copy, a checkout, a clock)."""
    from socnavgen.cards.generate import write_card_run
    from socnavgen.verify import verify_run

    warehouse = Path(__file__).resolve().parents[2] / "examples" / "locations" / "warehouse"
    run = tmp_path / "run"
    write_card_run("narrow-doorway", warehouse, run)
    verify_run(run)  # simulates (writing sim/outputs.json) and writes sim/verify.json
    assert export_run(run, "socrates", tmp_path / "a").verification in ("passed", "failed")
    paths = run / "paths.json"
    before = paths.stat()
    paths.write_text(paths.read_text().replace("\n", " \n"))  # same plan, other bytes
    os.utime(paths, ns=(before.st_atime_ns, before.st_mtime_ns))
    result = export_run(run, "socrates", tmp_path / "b")
    assert result.verification == "stale" and "paths.json changed" in result.verification_message
