"""verify_run and the `verify` command on run folders with hand-built traces in RUN/sim/trace.npz."""

from __future__ import annotations

import json
import sys
import types
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socnavgen.errors import InputFileError
from socnavgen.verify import VerifyReport, verify_run

from .verify_builders import cli_app, crossing_trace


def save_trace(run: Path, **kwargs) -> None:
    crossing_trace(**kwargs).save(run / "sim" / "trace.npz")


def test_verify_run_passes_and_writes_report(give_way_run: Path) -> None:
    save_trace(give_way_run)
    report = verify_run(give_way_run, simulate_if_missing=False)
    assert report.passed, report.feedback()
    names = [f.name for f in report.findings]
    assert "robot meets human1 at b2" in names and "human1 gives way while the robot passes" in names
    saved = VerifyReport.model_validate_json((give_way_run / "sim" / "verify.json").read_text())
    assert saved.passed and len(saved.findings) == len(report.findings)
    assert saved.trace_steps == 21 and saved.trace_seconds == pytest.approx(10.0)


def test_broken_scenario_fails_with_the_reason(give_way_run: Path) -> None:
    # The robot never says EXCUSE ME: the give-way branch can never run, and only the robot's script can fix it.
    save_trace(give_way_run, say_excuse_me=False)
    report = verify_run(give_way_run, simulate_if_missing=False)
    assert not report.passed and not report.spec
    failing = {f.node for f in report.failures}
    assert failing == {"RobotSays", "GiveWaytoRobot"}
    assert all(f.blame == "robot_script" and f.stage is None for f in report.failures)
    assert report.blamed_on("behaviors") == [] and report.blamed_on("paths") == []
    assert list(report.blamed()) == ["robot_script"]
    assert "GiveWaytoRobot with the robot within 2.5 m never ran" in report.feedback("robot_script")
    assert "fix: the robot never made the gesture" in report.feedback()


def test_missing_trace_without_simulation_is_a_user_error(give_way_run: Path) -> None:
    with pytest.raises(InputFileError, match="no simulation trace"):
        verify_run(give_way_run, simulate_if_missing=False)


def test_thresholds_are_configurable(give_way_run: Path) -> None:
    save_trace(give_way_run)
    report = verify_run(give_way_run, simulate_if_missing=False, distance=0.9)
    meet = next(f for f in report.findings if f.kind == "meets")
    assert not meet.passed and report.settings.distance == 0.9
    assert meet.robustness == pytest.approx(-0.1)  # closest 1.0 m, needs <= 0.9 m
    assert meet.blame == "paths"
    # closer than the two bodies' radii (0.75 m) is no meeting but a collision: the criterion is wrong
    tight = verify_run(give_way_run, simulate_if_missing=False, distance=0.5)
    meet = next(f for f in tight.findings if f.kind == "meets")
    assert not meet.passed and meet.blame == "spec" and meet.robustness is None
    assert "that is a collision" in meet.evidence


def test_card_criteria_are_checked(give_way_run: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    request = json.loads((give_way_run / "request.json").read_text())
    request["card"] = "frontal-approach"
    (give_way_run / "request.json").write_text(json.dumps(request))
    fake = types.ModuleType("socnavgen.cards.library")
    seen = []

    def card_criteria(run_dir):
        seen.append(Path(run_dir))
        return [{"kind": "meets_human", "within": 0.5}, {"kind": "executes", "node": "GiveWaytoRobot"}]

    fake.card_criteria = card_criteria
    monkeypatch.setitem(sys.modules, "socnavgen.cards.library", fake)
    save_trace(give_way_run)
    report = verify_run(give_way_run, simulate_if_missing=False)
    assert seen == [give_way_run]
    cards = [f for f in report.findings if f.source == "card"]
    assert [f.passed for f in cards] == [False, True]  # a card asking to meet within 0.5 m asks for a collision
    assert cards[0].blame == "spec"
    assert not report.passed


def test_cli_exit_codes_and_json(give_way_run: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from socnavgen.cli import verify_cmd

    monkeypatch.setattr(verify_cmd.console, "width", 220)  # one table row per line
    runner = CliRunner()
    save_trace(give_way_run)
    ok = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate", "--json"])
    assert ok.exit_code == 0, ok.output
    assert json.loads(ok.stdout)["passed"] is True
    save_trace(give_way_run, robot_stops_at=1.5)
    bad = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate"])
    assert bad.exit_code == 1
    assert "FAILED (4 failing)" in bad.stdout
    row = next(line for line in bad.stdout.splitlines() if "robot meets human1 at b2" in line)
    assert "FAIL" in row and "closest 1.00 m" in row and "-1.81" in row and "paths" in row
    help_text = runner.invoke(cli_app(), ["verify", "--help"]).stdout
    assert "--distance" in help_text and "Example" in help_text


def test_real_card_criteria(give_way_run: Path) -> None:
    """The cards module's own criteria for pedestrian-obstruction: meet human1 within 2 m, human1 gives way
    while passing, robot reaches its goal; the crossing trace satisfies them all."""
    request = json.loads((give_way_run / "request.json").read_text())
    request["card"] = "pedestrian-obstruction"
    (give_way_run / "request.json").write_text(json.dumps(request))
    save_trace(give_way_run)
    report = verify_run(give_way_run, simulate_if_missing=False)
    cards = [f for f in report.findings if f.source == "card"]
    assert [f.kind for f in cards] == ["meets", "robot_reaches_goal", "gives_way_while_passing"]
    assert all(f.passed for f in cards), report.feedback()
    assert cards[0].time == pytest.approx(4.5) and cards[0].distance == pytest.approx(1.41)  # first within 2 m


def _give_way_spec(**criterion):  # noqa: ANN003, ANN202
    from socnavgen.run.spec import (
        Criterion,
        CueTrigger,
        Encounter,
        HumanPart,
        RobotCue,
        RobotScript,
        ScenarioSpec,
    )

    crit = {"id": "c1", "kind": "reacts_after_phrase", "human": "human1", "phrase": "EXCUSE ME",
            "reaction": "give_way", "seconds": 2.0, **criterion}
    return ScenarioSpec(
        script=RobotScript(cues=[RobotCue(trigger=CueTrigger(when="human_within", distance=3.5), say="EXCUSE ME")]),
        encounters=[Encounter(id="e1", place="CORRIDOR", node="b2", humans=[
            HumanPart(human="human1", trigger="robot_says", phrase="EXCUSE ME", reaction="give_way")])],
        criteria=[Criterion(**crit)])


def test_spec_decides_and_the_cli_shows_robustness_and_blame(give_way_run: Path) -> None:
    from socnavgen.run.folder import RunFolder

    RunFolder(give_way_run).write_spec(_give_way_spec())
    save_trace(give_way_run)
    runner = CliRunner()
    ok = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate", "--json"])
    assert ok.exit_code == 0, ok.output
    report = json.loads(ok.stdout)
    assert report["spec"] is True
    crit = next(f for f in report["findings"] if f["criterion"] == "c1")
    assert crit["passed"] and crit["robustness"] == pytest.approx(0.5)
    assert "EXCUSE ME" in crit["formula"] or "excuse_me" in crit["formula"]
    # implied by the encounter: the meeting at b2; by every run: the goal, no contact, no deadlock
    assert {f["criterion"] for f in report["findings"] if f["source"] == "implied"} == \
        {"meet_human1_e1", "goal", "no_collision", "no_deadlock"}
    save_trace(give_way_run, say_excuse_me=False)
    bad = runner.invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate", "--json"])
    assert bad.exit_code == 1
    failing = [f for f in json.loads(bad.stdout)["findings"] if not f["passed"] and f["required"]]
    assert [(f["criterion"], f["blame"]) for f in failing] == [("c1", "robot_script")]
    # the tree checks still run, as warnings: the spec decides
    assert any(f["node"] == "RobotSays" and not f["passed"] and not f["required"]
               for f in json.loads(bad.stdout)["findings"])


def test_a_bad_formula_is_a_spec_finding_not_a_crash(give_way_run: Path) -> None:
    from socnavgen.run.folder import RunFolder

    RunFolder(give_way_run).write_spec(_give_way_spec(kind="stl", formula="eventually (dist_human9 < 1)"))
    save_trace(give_way_run)
    report = verify_run(give_way_run, simulate_if_missing=False)
    crit = next(f for f in report.findings if f.criterion == "c1")
    assert not crit.passed and crit.blame == "spec" and "human9 is not in this run" in crit.evidence
    assert report.blamed_on("spec") == [crit]


def test_malformed_spec_is_a_user_error(give_way_run: Path) -> None:
    (give_way_run / "spec.json").write_text('{"criteria": [{"id": "c1", "kind": "dances"}]}')
    save_trace(give_way_run)
    result = CliRunner().invoke(cli_app(), ["verify", str(give_way_run), "--no-simulate"])
    assert isinstance(result.exception, InputFileError)  # the main CLI turns it into one message, exit 2
    with pytest.raises(InputFileError, match="spec.json"):
        verify_run(give_way_run, simulate_if_missing=False)
