"""`socnavgen verify` on a run simulated with a robot policy of the user's (`simulate --robot module:Class`):
when the scenario verifies with the default robot under the same settings, the failures are the policy's
(as in campaigns: verify.runner.blame_the_policy); when it does not, the blame stays on the scenario."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from socnavgen.cards.generate import write_card_run
from socnavgen.cli import app

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "examples" / "locations" / "warehouse"
RUDE = f"{ROOT / 'tests' / 'campaign' / 'policies.py'}:StraightThrough"


def _simulate_and_verify(run: Path, timeout: float) -> tuple[dict, str]:
    runner = CliRunner()
    sim = runner.invoke(app, ["simulate", str(run), "--robot", RUDE, "--timeout", str(timeout), "--no-plot"])
    assert sim.exit_code == 0, sim.output
    shown = runner.invoke(app, ["verify", str(run)])
    assert shown.exit_code != 0  # the rude robot fails the scenario's criteria
    return json.loads((run / "sim" / "verify.json").read_text()), shown.output


def test_a_user_policy_is_blamed_when_the_default_robot_verifies(tmp_path: Path) -> None:
    # frontal-approach: the default robot passes the person; crowd-navigation's people touch each other whatever
    # the robot does (people_apart, tests/cards KNOWN_FAILING), so the scenario itself fails there
    run = write_card_run("frontal-approach", WAREHOUSE, tmp_path / "run").root
    report, shown = _simulate_and_verify(run, 60.0)
    failed = [f for f in report["findings"] if f["required"] and not f["passed"]]
    assert failed and all(f["blame"] == "policy" and f["blame_human"] is None for f in failed)
    assert all("StraightThrough" in f["blame_reason"] and "default robot (scripted)" in f["blame_reason"]
               for f in failed)
    assert "fix: policy" in shown
    # the trace judged is still the policy's (verify re-simulated the default robot without saving it)
    assert "StraightThrough" in json.loads((run / "sim" / "outputs.json").read_text())["made"]["robot"]


def test_the_scenario_keeps_the_blame_when_the_default_robot_fails_too(tmp_path: Path) -> None:
    run = write_card_run("crowd-navigation", WAREHOUSE, tmp_path / "run").root
    report, _ = _simulate_and_verify(run, 5.0)  # 5 s: no robot reaches the goal, the default one neither
    failed = [f for f in report["findings"] if f["required"] and not f["passed"]]
    assert failed and all(f["blame"] != "policy" for f in failed)
